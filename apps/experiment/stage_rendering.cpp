// Stage 3: figure panels, champion galleries, the callus-growth video and the champions'
// lives for the report's 3-D viewer.
//
// Each output is redrawn only when what it depends on changed or its bytes are not what was
// written: .stamps/rendering.json (stamps.hpp) maps each output group to a key made of the
// study fingerprint (the champions' content and the analysis options) and the rendering
// settings that group uses, and to the digests of the group's files.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <mutex>
#include <optional>

#include <nlohmann/json.hpp>

#include "experiment_run.hpp"
#include "plastivox/analysis/study.hpp"
#include "plastivox/base/clock.hpp"
#include "plastivox/base/parallel.hpp"
#include "plastivox/io/atomic_file.hpp"
#include "plastivox/render/archive_files.hpp"
#include "plastivox/render/files.hpp"
#include "plastivox/render/gallery.hpp"
#include "plastivox/render/panels.hpp"
#include "plastivox/render/render_life.hpp"
#include "plastivox/render/viewer.hpp"
#include "stamps.hpp"

namespace plastivox::experiment {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

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
  if (!ctx.opt.force.count("rendering") &&
      up_to_date(stamps, ctx.progress, "rendering", "figures", key, files)) {
    ctx.progress.log("[rendering] figure panels up to date");
    return files;
  }
  render::FigureOptions fo;
  fo.width = r.figure_width;
  fo.height = r.figure_height;
  const auto written = render::write_figures(figure, ctx.dir + "/figures", fo);
  stamps.record("figures", key, files);
  ctx.progress.log("[rendering] figure panels A-F" +
                   std::string(figure.evolution ? " and evolution curves: " : ": ") +
                   std::to_string(written.size()) + " files");
  return files;
}

// The champions' galleries (one per treatment: its run champions after settling, coloured by
// congenital stiffness, the paper's Figs. 2-4; a JSON sidecar records the tiles) and their
// lives for the report's 3-D viewer (lives/<label>.js at render::kViewerFps frames per
// simulated second; docs/rendering.md, "The 3-D viewer"). Both show the same champions, so
// each champion out of date in either is simulated once, on the experiment's threads, and
// only the two frames a gallery tile needs are kept in memory.
struct ChampionOutputs {
  std::vector<std::string> galleries;  // figures/gallery_<t>.png and .json, per treatment
  std::vector<std::string> lives;      // lives/<label>.js
};

ChampionOutputs render_champions(StageContext& ctx, Stamps& stamps) {
  const auto& r = ctx.config.rendering;
  const analysis::StudyResult& study = *ctx.study;
  const bool force = ctx.opt.force.count("rendering") > 0;
  ChampionOutputs out;
  render::GalleryStyle style;
  style.width = r.gallery_width;
  style.height = r.gallery_height;
  // One colour scale for every treatment's gallery: the congenital stiffness of all the
  // study's champions (as compiled: clamped into the physics' range), rounded outward as one
  // gallery's own range would be.
  double lo = 1e300, hi = -1e300;
  for (const auto& c : study.champions)
    for (size_t s = 0; s < c.robot.present.size(); ++s)
      if (c.robot.present[s] && c.robot.stiffness[s] > 0) {
        const double e = std::clamp(c.robot.stiffness[s], c.physics.e_min, c.physics.e_max);
        lo = std::min(lo, std::log10(e));
        hi = std::max(hi, std::log10(e));
      }
  if (lo <= hi) {
    const auto scale = render::stiffness_data_scale(render::ColorMode::kCongenital, lo, hi);
    // 1-2-5 values: 5e9, not the 4999999999.999999 that 10^log10(5e9) comes back as.
    const auto value = [](double log10_pa) {
      char text[32];
      std::snprintf(text, sizeof text, "%.12g", std::pow(10.0, log10_pa));
      return std::strtod(text, nullptr);
    };
    style.e0_lo = value(scale.lo);
    style.e0_hi = value(scale.hi);
  }

  // What is out of date. Study champion k is the champion of run file k (stage_analysis).
  struct Gallery {
    Treatment treatment;
    std::string name, file, sidecar, key;
    std::vector<size_t> champions;
  };
  std::vector<Gallery> galleries;
  if (r.galleries) {
    fs::create_directories(ctx.dir + "/figures");
    for (auto t : ctx.config.treatments) {
      Gallery g;
      g.treatment = t;
      g.name = std::string("gallery_") + to_string(t);
      g.file = "figures/" + g.name + ".png";
      g.sidecar = "figures/" + g.name + ".json";
      for (size_t i = 0; i < study.champions.size(); ++i)
        if (study.champions[i].treatment == t) g.champions.push_back(i);
      // "study range, fitness labels": galleries drawn before one colour range was shared
      // by all treatments, or before the tiles showed fitness, are redrawn.
      g.key = study.fingerprint + " " + g.name + " study range, fitness labels " +
              std::to_string(r.gallery_width) + "x" + std::to_string(r.gallery_height);
      if (g.champions.empty()) continue;  // a treatment with no run here (--run)
      out.galleries.push_back(g.file);
      out.galleries.push_back(g.sidecar);
      if (!force &&
          up_to_date(stamps, ctx.progress, "rendering", g.name, g.key, {g.file, g.sidecar})) {
        ctx.progress.log("[rendering] " + g.file + " up to date");
        continue;
      }
      galleries.push_back(std::move(g));
    }
  }
  const std::string lives_key = study.fingerprint + " lives " + std::to_string(render::kViewerFps);
  std::vector<std::string> life_files;
  for (const auto& c : study.champions) life_files.push_back("lives/" + c.label + ".js");
  bool lives = false;
  if (ctx.opt.viewer) {
    lives = force || !up_to_date(stamps, ctx.progress, "rendering", "lives", lives_key, life_files);
    if (!lives) {
      ctx.progress.log("[rendering] lives for the 3-D viewer up to date");
      out.lives = life_files;
    }
  }
  std::vector<char> framed(study.champions.size(), 0);
  for (const Gallery& g : galleries)
    for (size_t i : g.champions) framed[i] = 1;
  std::vector<size_t> todo;
  for (size_t i = 0; i < study.champions.size(); ++i)
    if (lives || framed[i]) todo.push_back(i);
  if (todo.empty()) return out;

  // One simulation per champion: the viewer's life written at once, a gallery's two frames kept.
  const auto t0 = WallClock::now();
  const int threads = ctx.opt.threads >= 0 ? ctx.opt.threads : ctx.config.threads;
  std::vector<render::GalleryEntry> entries(study.champions.size());
  std::vector<std::string> frame_failures(study.champions.size()), life_failures(todo.size());
  std::vector<std::optional<render::ViewerLink>> links(todo.size());
  int done = 0;  // champions simulated, and life_seconds below: under status_mutex
  std::mutex status_mutex;
  double life_seconds = 0;  // writing the lives (packing, base64, files), summed over threads
  parallel_for(todo.size(), threads, [&](size_t j) {
    const auto& c = study.champions[todo[j]];
    render::GalleryEntry& e = entries[todo[j]];
    e.source = render::load_life_source(study.inputs[c.input].file, c.generation);
    // A champion the audit flagged says so under its tile (short: tiles can be narrow):
    // "· SANK" when it is left out of the statistics, "· SANK, kept" with --keep-artifacts;
    // "· VERTICAL" (", kept" with --keep-vertical) for a fitness mostly of rising.
    if (c.health == "sank" || c.life_status == "unstable" || c.vertical_exploit)
      e.source.label += std::string(c.life_status == "unstable" ? " · UNSTABLE"
                                    : c.vertical_exploit        ? " · VERTICAL"
                                                                : " · SANK") +
                        (c.artifact.empty() ? ", kept" : "");
    const auto times =
        framed[todo[j]] ? render::gallery_times(e.source.physics, style) : std::vector<double>{};
    if (lives) {
      render::ReportFrames life = render::report_life(e.source, render::kViewerFps, times);
      e.life = std::move(life.frames);
      frame_failures[todo[j]] = life.frames_failure;
      if (!life.shown.failure.empty()) {
        life_failures[j] = study.inputs[c.input].file + ": no 3-D replay, " + life.shown.failure;
      } else {
        const auto w0 = WallClock::now();
        links[j] = render::write_report_life(ctx.dir, c.label, life.shown.life());
        std::lock_guard<std::mutex> lock(status_mutex);
        life_seconds += seconds_since(w0);
      }
    } else {
      try {
        e.life = render::take_frame_set(e.source, times);
      } catch (const render::RenderError& err) {
        frame_failures[todo[j]] = err.what();
      }
    }
    std::lock_guard<std::mutex> lock(status_mutex);
    ctx.progress.status("[rendering] champions simulated: " + std::to_string(++done) + "/" +
                        std::to_string(todo.size()));
  });
  char buf[240];
  std::snprintf(buf, sizeof buf, "[rendering] %zu champions simulated for %s in %.1f s",
                todo.size(),
                lives && !galleries.empty() ? "the galleries and the 3-D viewer"
                : lives                     ? "the 3-D viewer"
                                            : "the galleries",
                seconds_since(t0));
  ctx.progress.log(buf);

  if (lives) {
    uintmax_t bytes = 0;
    std::vector<render::ViewerLink> kept;
    for (size_t j = 0; j < todo.size(); ++j) {
      if (!life_failures[j].empty()) ctx.progress.log("[rendering] " + life_failures[j]);
      if (!links[j]) continue;
      kept.push_back(*links[j]);
      out.lives.push_back(links[j]->src);
      bytes += fs::file_size(ctx.dir + "/" + links[j]->src);
    }
    render::remove_other_lives(ctx.dir, kept);
    if (out.lives.size() == life_files.size()) stamps.record("lives", lives_key, life_files);
    std::snprintf(buf, sizeof buf,
                  "[rendering] lives/: %zu of %zu champions, %.1f MB, written in %.1f s "
                  "(thread-seconds)",
                  out.lives.size(), life_files.size(), bytes / 1e6, life_seconds);
    ctx.progress.log(buf);
  }

  for (const Gallery& g : galleries) {
    std::vector<render::GalleryEntry> items;
    for (size_t i : g.champions) {
      if (!frame_failures[i].empty()) throw render::RenderError(frame_failures[i]);
      items.push_back(std::move(entries[i]));
    }
    const auto layout = render::render_gallery(items, style, ctx.dir + "/" + g.file);
    json tiles = json::array();
    for (size_t k = 0; k < layout.tiles.size(); ++k)
      tiles.push_back(
          {{"label", layout.labels[k]},
           {"fitness", layout.fitness[k]},
           {"file", fs::relative(study.inputs[study.champions[g.champions[k]].input].file, ctx.dir)
                        .string()},
           {"heading_deg", layout.heading_deg[k]},
           {"rect",
            {layout.tiles[k].x, layout.tiles[k].y, layout.tiles[k].width,
             layout.tiles[k].height}}});
    write_file_atomic(ctx.dir + "/" + g.sidecar, json{{"treatment", to_string(g.treatment)},
                                                      {"columns", layout.columns},
                                                      {"rows", layout.rows},
                                                      {"e0_range_pa", {layout.e0_lo, layout.e0_hi}},
                                                      {"tiles", tiles}}
                                                         .dump(1) +
                                                     "\n");
    stamps.record(g.name, g.key, {g.file, g.sidecar});
    ctx.progress.log("[rendering] " + g.file + ": " + std::to_string(layout.tiles.size()) +
                     (layout.tiles.size() == 1 ? " champion" : " champions"));
  }
  return out;
}

// The callus-growth video: the fittest champion of a developing treatment (stress or
// pressure), its whole life coloured by E/E0.
std::vector<std::string> render_video(StageContext& ctx, Stamps& stamps) {
  const analysis::ChampionAnalysis* best = nullptr;
  for (const auto& c : ctx.study->champions) {
    if (c.treatment == Treatment::kNone || c.evaluation != "ok" || !c.artifact.empty()) continue;
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
  if (!ctx.opt.force.count("rendering") &&
      up_to_date(stamps, ctx.progress, "rendering", "video", key, {file})) {
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
  stamps.record("video", key, {file});
  char buf[256];
  std::snprintf(buf, sizeof buf,
                "[rendering] %s: %d frames, %.1f s of video (%s); simulated in %.1f s, drawn and "
                "encoded in %.1f s",
                file.c_str(), v.frames, v.duration_s, v.codec.c_str(), v.simulate_seconds,
                v.render_seconds);
  ctx.progress.log(buf);
  return {file};
}

// Each MAP-Elites run's archive in archives/<run>/, as plastivox archive draws it
// (render/archive_files.hpp): its map, its QD score and coverage over evaluations and its table
// with the figures, the gallery of its best kArchiveElites elites with the galleries. Redrawn
// when the run's content or the sizes change.
std::vector<std::string> render_archives(StageContext& ctx, Stamps& stamps) {
  const auto& r = ctx.config.rendering;
  std::vector<std::string> out;
  if (ctx.config.evolution.algorithm != evo::Algorithm::kMapElites || !r.figures) return out;
  const bool force = ctx.opt.force.count("rendering") > 0;
  for (const analysis::StudyInput& in : ctx.study->inputs) {
    const std::string label = ExperimentConfig::run_label(in.treatment, in.seed);
    const std::string dir = "archives/" + label;
    std::vector<std::string> files;
    for (const char* f : {"archive.svg", "archive.png", "qd.svg", "qd.png", "archive.csv"})
      files.push_back(dir + "/" + f);
    if (r.galleries) files.push_back(dir + "/elites.png");
    const std::string key =
        in.content_digest + " archive " + std::to_string(r.figure_width) + "x" +
        std::to_string(r.figure_height) +
        (r.galleries ? " elites " + std::to_string(kArchiveElites) + " " +
                           std::to_string(r.gallery_width) + "x" + std::to_string(r.gallery_height)
                     : std::string(" no elites"));
    const std::string item = "archive_" + label;
    if (!force && up_to_date(stamps, ctx.progress, "rendering", item, key, files)) {
      ctx.progress.log("[rendering] " + dir + " up to date");
      out.insert(out.end(), files.begin(), files.end());
      continue;
    }
    render::ArchiveRequest q;
    q.elites = r.galleries ? kArchiveElites : 0;
    q.style.width = r.gallery_width;
    q.style.height = r.gallery_height;
    q.figure.width = r.figure_width;
    q.figure.height = r.figure_height;
    const auto t0 = WallClock::now();
    const render::ArchiveFiles a = render::write_archive_files(in.file, ctx.dir + "/" + dir, q);
    files.clear();
    for (const std::string& w : a.written)
      files.push_back(fs::relative(w, ctx.dir).generic_string());
    stamps.record(item, key, files);
    out.insert(out.end(), files.begin(), files.end());
    char buf[240];
    std::snprintf(buf, sizeof buf,
                  "[rendering] %s: %lld of %lld cells, QD score %.4g, %zu elites drawn in %.1f s",
                  dir.c_str(), static_cast<long long>(a.filled), static_cast<long long>(a.cells),
                  a.qd_score, a.elites, seconds_since(t0));
    ctx.progress.log(buf);
  }
  return out;
}

}  // namespace

std::vector<std::string> stage_rendering(StageContext& ctx) {
  Stamps stamps(ctx.dir, "rendering");
  std::vector<std::string> out;
  if (ctx.config.rendering.figures)
    for (const auto& f : render_figures(ctx, stamps)) out.push_back(f);
  const ChampionOutputs champions = render_champions(ctx, stamps);
  for (const auto& f : champions.galleries) out.push_back(f);
  for (const auto& f : render_archives(ctx, stamps)) out.push_back(f);
  if (ctx.config.rendering.video)
    for (const auto& f : render_video(ctx, stamps)) out.push_back(f);
  for (const auto& f : champions.lives) out.push_back(f);
  return out;
}

}  // namespace plastivox::experiment
