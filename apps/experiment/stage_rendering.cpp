// Stage 3: figure panels, champion galleries, the callus-growth video and the champions'
// lives for the report's 3-D viewer.
//
// Each output is redrawn only when what it depends on changed: .stamps/rendering.json maps
// each output group to a key made of the study fingerprint (the champions' content and the
// analysis options) and the rendering settings that group uses.
#include <chrono>
#include <cstdio>
#include <filesystem>

#include <nlohmann/json.hpp>

#include "experiment_run.hpp"
#include "plastivox/analysis/study.hpp"
#include "plastivox/atomic_file.hpp"
#include "plastivox/base/clock.hpp"
#include "plastivox/render/gallery.hpp"
#include "plastivox/render/panels.hpp"
#include "plastivox/render/render_life.hpp"
#include "plastivox/render/viewer.hpp"

namespace plastivox::experiment {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

class Stamps {
 public:
  explicit Stamps(std::string path) : path_(std::move(path)) {
    try {
      if (fs::exists(path_)) stamps_ = json::parse(read_file_bytes(path_));
    } catch (const std::exception&) {
      stamps_ = json::object();  // unreadable: everything is redrawn
    }
    if (!stamps_.is_object()) stamps_ = json::object();
  }
  bool current(const std::string& item, const std::string& key,
               const std::vector<std::string>& files, const std::string& dir) const {
    if (!stamps_.contains(item) || stamps_[item] != key) return false;
    for (const auto& f : files)
      if (!fs::exists(dir + "/" + f)) return false;
    return true;
  }
  void record(const std::string& item, const std::string& key) {
    stamps_[item] = key;
    write_file_atomic(path_, stamps_.dump(1) + "\n");
  }

 private:
  std::string path_;
  json stamps_ = json::object();
};

std::vector<std::string> render_figures(StageContext& ctx, Stamps& stamps) {
  const auto& r = ctx.config.rendering;
  const std::string key = ctx.study->fingerprint + " figures " + std::to_string(r.figure_width) +
                          "x" + std::to_string(r.figure_height);
  const auto figure = render::read_stats_figure(ctx.dir + "/stats.json");
  // One fixed order, whether drawn now or found up to date (the report lists them so).
  std::vector<std::string> files;
  std::vector<std::string> stems;
  if (figure.evolution) stems.push_back("evolution");
  for (const char* id : {"A", "B", "C", "D", "E", "F"}) stems.push_back(std::string("panel_") + id);
  stems.push_back("figure_5");
  for (const auto& stem : stems)
    for (const char* ext : {".png", ".svg"}) files.push_back("figures/" + stem + ext);
  if (!ctx.opt.force.count("rendering") && stamps.current("figures", key, files, ctx.dir)) {
    ctx.progress.log("[rendering] figure panels up to date");
    return files;
  }
  render::FigureOptions fo;
  fo.width = r.figure_width;
  fo.height = r.figure_height;
  const auto written = render::write_figures(figure, ctx.dir + "/figures", fo);
  stamps.record("figures", key);
  ctx.progress.log("[rendering] figure panels A-F" +
                   std::string(figure.evolution ? " and evolution curves: " : ": ") +
                   std::to_string(written.size()) + " files");
  return files;
}

// One gallery per treatment: its run champions, after settling, coloured by congenital
// stiffness (the paper's Figs. 2-4). A JSON sidecar records the tiles (label, heading).
std::vector<std::string> render_galleries(StageContext& ctx, Stamps& stamps) {
  const auto& r = ctx.config.rendering;
  std::vector<std::string> out;
  fs::create_directories(ctx.dir + "/figures");
  for (auto t : ctx.config.treatments) {
    const std::string name = std::string("gallery_") + to_string(t);
    const std::string file = "figures/" + name + ".png", sidecar = "figures/" + name + ".json";
    std::vector<std::string> inputs;
    for (size_t i = 0; i < ctx.run_files.size(); ++i)
      if (ctx.run_labels[i].rfind(std::string(to_string(t)) + "-s", 0) == 0)
        inputs.push_back(ctx.dir + "/" + ctx.run_files[i]);
    // "data range": galleries drawn before the colour range was the data's are redrawn.
    const std::string key = ctx.study->fingerprint + " " + name + " data range " +
                            std::to_string(r.gallery_width) + "x" +
                            std::to_string(r.gallery_height);
    if (!ctx.opt.force.count("rendering") && stamps.current(name, key, {file, sidecar}, ctx.dir)) {
      ctx.progress.log("[rendering] " + file + " up to date");
    } else {
      render::GalleryStyle style;
      style.width = r.gallery_width;
      style.height = r.gallery_height;
      const auto layout = render::render_gallery_file(
          inputs, style, ctx.dir + "/" + file,
          [&](const std::string& m) { ctx.progress.status("[rendering] " + name + ": " + m); });
      json tiles = json::array();
      for (size_t i = 0; i < layout.tiles.size(); ++i)
        tiles.push_back({{"label", layout.labels[i]},
                         {"file", fs::relative(inputs[i], ctx.dir).string()},
                         {"heading_deg", layout.heading_deg[i]},
                         {"rect",
                          {layout.tiles[i].x, layout.tiles[i].y, layout.tiles[i].width,
                           layout.tiles[i].height}}});
      write_file_atomic(ctx.dir + "/" + sidecar, json{{"treatment", to_string(t)},
                                                      {"columns", layout.columns},
                                                      {"rows", layout.rows},
                                                      {"tiles", tiles}}
                                                         .dump(1) +
                                                     "\n");
      stamps.record(name, key);
      ctx.progress.log("[rendering] " + file + ": " + std::to_string(layout.tiles.size()) +
                       (layout.tiles.size() == 1 ? " champion" : " champions"));
    }
    out.push_back(file);
    out.push_back(sidecar);
  }
  return out;
}

// The callus-growth video: the fittest champion of a developing treatment (stress or
// pressure), its whole life coloured by E/E0.
std::vector<std::string> render_video(StageContext& ctx, Stamps& stamps) {
  const analysis::ChampionAnalysis* best = nullptr;
  for (const auto& c : ctx.study->champions) {
    if (c.treatment == Treatment::kNone || c.evaluation != "ok") continue;
    if (!best || c.fitness > best->fitness) best = &c;
  }
  if (!best) {
    ctx.progress.log("[rendering] no video: no developing champion lived a stable life");
    return {};
  }
  const auto& r = ctx.config.rendering;
  const std::string file = "videos/callus_" + best->label + ".mp4";
  // "life camera, data range": videos from before both are redrawn.
  const std::string key = ctx.study->fingerprint + " video life camera, data range " + best->label +
                          " " + std::to_string(r.video_width) + "x" +
                          std::to_string(r.video_height) + " " + std::to_string(r.video_fps) + " " +
                          r.video_color;
  if (!ctx.opt.force.count("rendering") && stamps.current("video", key, {file}, ctx.dir)) {
    ctx.progress.log("[rendering] video up to date");
    return {file};
  }
  fs::create_directories(ctx.dir + "/videos");
  // An earlier champion's video is stale once another one is the best.
  for (const auto& e : fs::directory_iterator(ctx.dir + "/videos"))
    if (e.path().extension() == ".mp4") fs::remove(e.path());
  render::FrameStyle style;
  style.width = r.video_width;
  style.height = r.video_height;
  style.color = render::parse_color_mode(r.video_color);
  render::VideoJob job;
  job.fps = r.video_fps;
  const std::string source = ctx.dir + "/runs/" + best->label + ".h5";
  const auto v = render::render_video_file(
      source, style, job, ctx.dir + "/" + file,
      [&](const std::string& m) { ctx.progress.status("[rendering] " + m); });
  stamps.record("video", key);
  char buf[256];
  std::snprintf(buf, sizeof buf,
                "[rendering] %s: %d frames, %.1f s of video (%s); simulated in %.1f s, drawn and "
                "encoded in %.1f s",
                file.c_str(), v.frames, v.duration_s, v.codec.c_str(), v.simulate_seconds,
                v.render_seconds);
  ctx.progress.log(buf);
  return {file};
}

// Every champion's life for the report's 3-D viewer: lives/<label>.js, recorded at
// render::kViewerFps frames per simulated second (docs/rendering.md, "The 3-D viewer").
std::vector<std::string> render_lives(StageContext& ctx, Stamps& stamps) {
  const std::string key = ctx.study->fingerprint + " lives " + std::to_string(render::kViewerFps);
  std::vector<render::ReportLifeSource> sources;
  std::vector<std::string> files;
  for (const auto& c : ctx.study->champions) {
    sources.push_back({c.label, ctx.study->inputs[c.input].file, c.generation});
    files.push_back("lives/" + c.label + ".js");
  }
  if (!ctx.opt.force.count("rendering") && stamps.current("lives", key, files, ctx.dir)) {
    ctx.progress.log("[rendering] lives for the 3-D viewer up to date");
    return files;
  }
  const auto t0 = WallClock::now();
  ctx.progress.status("[rendering] lives for the 3-D viewer: simulating " +
                      std::to_string(sources.size()) + " champions");
  const int threads = ctx.opt.threads >= 0 ? ctx.opt.threads : ctx.config.threads;
  const auto links = render::write_report_lives(
      sources, ctx.dir, render::kViewerFps, threads,
      [&](const std::string& m) { ctx.progress.log("[rendering] " + m); });
  std::vector<std::string> out;
  uintmax_t bytes = 0;
  for (const auto& l : links) {
    out.push_back(l.src);
    bytes += fs::file_size(ctx.dir + "/" + l.src);
  }
  if (out.size() == files.size()) stamps.record("lives", key);
  char buf[200];
  std::snprintf(buf, sizeof buf, "[rendering] lives/: %zu of %zu champions, %.1f MB, in %.1f s",
                links.size(), sources.size(), bytes / 1e6, seconds_since(t0));
  ctx.progress.log(buf);
  return out;
}

}  // namespace

std::vector<std::string> stage_rendering(StageContext& ctx) {
  fs::create_directories(ctx.dir + "/.stamps");
  Stamps stamps(ctx.dir + "/.stamps/rendering.json");
  std::vector<std::string> out;
  if (ctx.config.rendering.figures)
    for (const auto& f : render_figures(ctx, stamps)) out.push_back(f);
  if (ctx.config.rendering.galleries)
    for (const auto& f : render_galleries(ctx, stamps)) out.push_back(f);
  if (ctx.config.rendering.video)
    for (const auto& f : render_video(ctx, stamps)) out.push_back(f);
  if (ctx.opt.viewer)
    for (const auto& f : render_lives(ctx, stamps)) out.push_back(f);
  return out;
}

}  // namespace plastivox::experiment
