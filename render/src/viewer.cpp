// The 3-D viewer's data and page (plastivox/render/viewer.hpp). The page is plain HTML with
// three scripts inlined: three.js and its OrbitControls from Debian's libjs-three, and the
// viewer (assets/viewer/viewer.js). Each life travels as base64 of its packed bytes plus a
// small JSON of what to read out and how to colour, so one page holds everything it needs.
#include "plastivox/render/viewer.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <limits>
#include <optional>

#include <nlohmann/json.hpp>

#include "plastivox/atomic_file.hpp"
#include "plastivox/base/parallel.hpp"
#include "plastivox/render/assets.hpp"
#include "plastivox/render/color_scale.hpp"
#include "plastivox/render/life.hpp"
#include "plastivox/render/offscreen.hpp"  // RenderError
#include "plastivox/robot_file.hpp"        // InputError
#include "plastivox/simulator.hpp"
#include "plastivox/state.hpp"

namespace plastivox::render {
namespace {

constexpr const char* kThreeDir = "/usr/share/javascript/three";

void put_u8(std::string& out, uint8_t v) {
  out.push_back(static_cast<char>(v));
}
void put_u16(std::string& out, uint16_t v) {
  put_u8(out, v & 0xff);
  put_u8(out, v >> 8);
}
void put_u32(std::string& out, uint32_t v) {
  put_u16(out, v & 0xffff);
  put_u16(out, v >> 16);
}
void put_f32(std::string& out, double v) {
  const float f = static_cast<float>(v);
  uint32_t bits = 0;
  std::memcpy(&bits, &f, 4);
  put_u32(out, bits);
}

// v in [lo, hi] to 0..levels (0 when the range is empty).
uint32_t quantise(double v, double lo, double hi, uint32_t levels) {
  if (!(hi > lo)) return 0;
  const double t = std::clamp((v - lo) / (hi - lo), 0.0, 1.0);
  return static_cast<uint32_t>(std::lround(t * levels));
}

// Unit quaternion (w, x, y, z) as the index of its largest component (2 bits) and the other
// three, each in [-1/sqrt2, 1/sqrt2], as 10 bits (the sign makes the largest positive).
uint32_t pack_rotation(const Eigen::Quaterniond& q_in) {
  const Eigen::Quaterniond q = q_in.normalized();
  const double c[4] = {q.w(), q.x(), q.y(), q.z()};
  int big = 0;
  for (int k = 1; k < 4; ++k)
    if (std::abs(c[k]) > std::abs(c[big])) big = k;
  const double sign = c[big] < 0 ? -1 : 1;
  uint32_t out = static_cast<uint32_t>(big) << 30;
  int shift = 20;
  for (int k = 0; k < 4; ++k) {
    if (k == big) continue;
    out |= quantise(sign * c[k] * std::sqrt(2.0), -1, 1, 1023) << shift;
    shift -= 10;
  }
  return out;
}

nlohmann::json scale_json(const ColorScale& s) {
  nlohmann::json ticks = nlohmann::json::array();
  for (const Tick& t : s.ticks()) ticks.push_back({{"t", t.t}, {"label", t.label}});
  return {
      {"lo", s.lo}, {"hi", s.hi}, {"map", s.map().name()}, {"title", s.title}, {"ticks", ticks}};
}

double largest_stimulus(const Recording& rec) {
  double m = 0;
  for (const Frame& f : rec.frames)
    for (double s : f.stimulus)
      if (std::isfinite(s)) m = std::max(m, std::abs(s));
  return m;
}

std::string read_text(const std::string& path, const std::string& what) {
  try {
    return read_file_bytes(path);
  } catch (const InputError&) {
    throw RenderError(path + ": missing (" + what + ")");
  }
}

// Text safe inside <script>...</script>: no "</script" can close the element early (in
// JavaScript, "<\/script" inside a string or comment means the same).
std::string script_safe(std::string s) {
  for (size_t at = 0; (at = s.find("</", at)) != std::string::npos; at += 2) {
    std::string word = s.substr(at + 2, 6);
    std::transform(word.begin(), word.end(), word.begin(), [](char c) { return std::tolower(c); });
    if (word == "script") s.replace(at, 2, "<\\/");
  }
  return s;
}

// The renderer's colour maps as the viewer reads them: name -> flat RGB bytes.
std::string colormaps_json() {
  nlohmann::json maps;
  const std::pair<const char*, const Colormap*> all[] = {{"sequential", &Colormap::sequential()},
                                                         {"diverging", &Colormap::diverging()},
                                                         {"cyclic", &Colormap::cyclic_map()}};
  for (const auto& [name, map] : all) {
    std::vector<int> rgb;
    for (int k = 0; k < Colormap::kEntries; ++k)
      for (uint8_t c : map->at(k / static_cast<double>(Colormap::kEntries - 1))) rgb.push_back(c);
    maps[name] = rgb;
  }
  return maps.dump();
}

// three.js, its OrbitControls, the colour maps and the viewer, inlined; `lives_js` (already
// script-safe) fills PLASTIVOX_LIVES before the viewer's script runs.
std::string scripts_html(const std::string& lives_js) {
  const ViewerScripts js = viewer_scripts();
  std::string html;
  html += "<script>" + script_safe(js.three) + "</script>\n";
  html += "<script>" + script_safe(js.orbit) + "</script>\n";
  html += "<script>window.PLASTIVOX_COLORMAPS = " + colormaps_json() +
          ";\nwindow.PLASTIVOX_LIVES = [];\n" + lives_js + "</script>\n";
  html += "<script>" + script_safe(js.viewer) + "</script>\n";
  return html;
}

// A button per life (labels set by the script from each life's meta).
std::string buttons_html(size_t n) {
  std::string html = "<div class=\"pv-lives\">";
  for (size_t i = 0; i < n; ++i)
    html += "<button type=\"button\" data-pv-life=\"" + std::to_string(i) +
            "\" onclick=\"plastivoxViewer.load(" + std::to_string(i) + ")\"></button>";
  return html + "</div>\n";
}

// One life as the viewer reads it: {meta: <life_meta_json>, data: "<base64 of pack_life>"}.
std::string life_object_js(const ViewerLife& life) {
  return "{meta: " + life_meta_json(life) + ", data: \"" + base64(pack_life(life)) + "\"}";
}

const char* kStart =
    "<script>plastivoxViewer.start(document.getElementById(\"pv-viewer\"), 0);</script>\n";

}  // namespace

ViewerLife ShownLife::life() const {
  ViewerLife l = info;
  l.model = &model;
  l.recording = &recording;
  return l;
}

namespace {

// A life to show with its model compiled and its caption set; no frames yet.
ShownLife compiled_life(const LifeSource& source) {
  ShownLife out;
  out.info.label = source.label;
  out.info.treatment = to_string(source.physics.treatment);
  try {
    out.model = compile(source.robot, source.physics);
  } catch (const std::invalid_argument& e) {
    throw InputError(source.path + ": " + e.what());
  }
  return out;
}

}  // namespace

ReportLife simulate_report_life(const LifeSource& source, double fps,
                                const std::vector<double>& times) {
  const PhysicsDef& def = source.physics;
  ReportLife out;
  out.shown = compiled_life(source);
  ShownLife& shown = out.shown;
  // A life that sinks through the floor is drawn to its end: the fall is what a reader needs
  // to see. Its fitness stays what the rule in force gives it (0 where sunk lives are
  // invalid); the rule changes no state, only the verdict.
  shown.model.def.sinking_invalid = false;
  if (!(fps > 0)) throw RenderError("simulate_report_life: fps must be > 0");
  for (size_t k = 0; k < times.size(); ++k)
    if (!(times[k] >= 0 && times[k] <= def.duration) || (k > 0 && times[k] < times[k - 1]))
      throw RenderError(source.path + ": frame times must ascend within the life [0, " +
                        std::to_string(def.duration) + "] s");

  // One list of frame times for the engine: the viewer's (k / fps, then the first state past
  // the end, as the engine's own recording ends) and the caller's. Each wanted frame keeps
  // where it goes: >= 0 an index into `times`, -1 the viewer.
  std::vector<std::pair<double, int>> wanted;
  for (int64_t k = 0;; ++k) {
    const double t = static_cast<double>(k) / fps;
    if (t > def.duration) break;
    wanted.push_back({t, -1});
  }
  wanted.push_back({std::nextafter(def.duration, std::numeric_limits<double>::infinity()), -1});
  for (size_t k = 0; k < times.size(); ++k) wanted.push_back({times[k], static_cast<int>(k)});
  std::stable_sort(wanted.begin(), wanted.end(),
                   [](const auto& a, const auto& b) { return a.first < b.first; });

  SimOptions options;
  for (const auto& w : wanted) options.frame_times.push_back(w.first);
  shown.recording.fps = fps;
  out.frames.frames.resize(times.size());
  size_t taken = 0, extra = 0;
  int64_t last_viewer_step = -1;
  options.on_frame = [&](const State& s) {
    const int to = wanted[taken++].second;
    if (to >= 0) {
      out.frames.frames[to] = capture_frame(s);
      extra += 1;
    } else if (s.steps != last_viewer_step) {  // one frame per state, as the recording does
      shown.recording.frames.push_back(capture_frame(s));
      last_viewer_step = s.steps;
    }
    return true;
  };
  const SimResult r = simulate(shown.model, options);
  shown.info.settled = r.settled;
  shown.info.com_settled = r.com_settled;
  shown.info.fitness = r.sank && def.sinking_invalid ? 0.0 : r.fitness;
  if (r.status != SimStatus::kFinished) shown.failure = "simulation unstable: " + r.failure;
  out.frames.model = std::make_shared<const Model>(shown.model);
  out.frames.settled = r.settled;
  out.frames.com_settled = r.com_settled;
  if (extra < times.size()) {
    out.frames.frames.clear();
    out.frames_failure = source.path +
                         ": the simulation went unstable at t = " + std::to_string(r.sim_time) +
                         " s (" + r.failure + ")";
  }
  return out;
}

ShownLife show_life(const LifeSource& source, double fps) {
  if (source.recorded) {
    ShownLife out = compiled_life(source);
    out.recording = source.recorded->recording;
    out.info.settled = source.recorded->settled;
    out.info.com_settled = source.recorded->com_settled;
    out.info.fitness = source.recorded->fitness;
    return out;
  }
  return simulate_report_life(source, fps, {}).shown;
}

std::string pack_life(const ViewerLife& life) {
  const Model& m = *life.model;
  const std::vector<Frame>& frames = life.recording->frames;
  const int n = m.n;
  // Ranges over the whole life: bounding box of the centres, sizes, log10 E, |stimulus|.
  double lo[3], hi[3];
  for (int a = 0; a < 3; ++a) {
    lo[a] = std::numeric_limits<double>::infinity();
    hi[a] = -lo[a];
  }
  double size_lo = lo[0], size_hi = hi[0], e_lo = lo[0], e_hi = hi[0];
  for (const Frame& f : frames)
    for (int i = 0; i < n; ++i) {
      for (int a = 0; a < 3; ++a) {
        lo[a] = std::min(lo[a], f.pos[i][a]);
        hi[a] = std::max(hi[a], f.pos[i][a]);
      }
      size_lo = std::min(size_lo, f.size[i]);
      size_hi = std::max(size_hi, f.size[i]);
      e_lo = std::min(e_lo, std::log10(f.stiffness[i]));
      e_hi = std::max(e_hi, std::log10(f.stiffness[i]));
    }
  const double stim = largest_stimulus(*life.recording);

  std::string out = "PVL1";
  put_u32(out, static_cast<uint32_t>(n));
  put_u32(out, static_cast<uint32_t>(frames.size()));
  put_f32(out, m.size);
  for (int a = 0; a < 3; ++a) put_f32(out, lo[a]);
  for (int a = 0; a < 3; ++a) put_f32(out, hi[a]);
  put_f32(out, size_lo);
  put_f32(out, size_hi);
  put_f32(out, e_lo);
  put_f32(out, e_hi);
  put_f32(out, stim);
  for (int i = 0; i < n; ++i) put_f32(out, std::log10(m.e0[i]));
  for (int i = 0; i < n; ++i) put_f32(out, m.phase[i]);
  // Per frame: time, displacement (as the video overlay reads it) and centre of mass. The
  // f32 bounds read back (the same rounding) quantise the per-voxel values below.
  Life overlay;  // what displacement_so_far needs: the model (not owned) and settling
  overlay.model = std::shared_ptr<const Model>(std::shared_ptr<const Model>(), &m);
  overlay.settled = life.settled;
  overlay.com_settled = life.com_settled;
  for (const Frame& f : frames) {
    put_f32(out, f.time);
    put_f32(out, displacement_so_far(overlay, f));
    const Eigen::Vector3d com = center_of_mass(f.pos);
    for (int a = 0; a < 3; ++a) put_f32(out, com[a]);
  }
  auto f32 = [](double v) { return static_cast<double>(static_cast<float>(v)); };
  for (const Frame& f : frames)
    for (int i = 0; i < n; ++i) {
      for (int a = 0; a < 3; ++a)
        put_u16(out, static_cast<uint16_t>(quantise(f.pos[i][a], f32(lo[a]), f32(hi[a]), 65535)));
      put_u32(out, pack_rotation(f.orient[i]));
      put_u8(out, static_cast<uint8_t>(quantise(f.size[i], f32(size_lo), f32(size_hi), 255)));
      put_u8(out,
             static_cast<uint8_t>(quantise(std::log10(f.stiffness[i]), f32(e_lo), f32(e_hi), 255)));
      put_u8(out, static_cast<uint8_t>(quantise(f.stimulus[i], -f32(stim), f32(stim), 255)));
    }
  return out;
}

std::string base64(const std::string& bytes) {
  static const char* abc = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  for (size_t i = 0; i < bytes.size(); i += 3) {
    const size_t left = bytes.size() - i;
    uint32_t v = static_cast<uint8_t>(bytes[i]) << 16;
    if (left > 1) v |= static_cast<uint8_t>(bytes[i + 1]) << 8;
    if (left > 2) v |= static_cast<uint8_t>(bytes[i + 2]);
    out.push_back(abc[(v >> 18) & 63]);
    out.push_back(abc[(v >> 12) & 63]);
    out.push_back(left > 1 ? abc[(v >> 6) & 63] : '=');
    out.push_back(left > 2 ? abc[v & 63] : '=');
  }
  return out;
}

std::string life_meta_json(const ViewerLife& life) {
  const Model& m = *life.model;
  std::vector<const Frame*> frames;
  for (const Frame& f : life.recording->frames) frames.push_back(&f);
  nlohmann::json scales;
  for (const ColorMode mode : {ColorMode::kCongenital, ColorMode::kStiffness, ColorMode::kChange,
                               ColorMode::kPhase, ColorMode::kStimulus})
    scales[to_string(mode)] = scale_json(make_color_scale(mode, m, frames));
  return nlohmann::json{{"label", life.label},
                        {"treatment", life.treatment},
                        {"fitness", life.fitness},
                        {"settle_time", m.def.settle_time},
                        {"scales", scales}}
      .dump();
}

ViewerScripts viewer_scripts() {
  const std::string hint = "Debian package libjs-three: apt-get install -y libjs-three";
  ViewerScripts s;
  s.three = read_text(std::string(kThreeDir) + "/three.min.js", hint);
  s.orbit = read_text(std::string(kThreeDir) + "/examples/js/controls/OrbitControls.js", hint);
  s.viewer = read_asset("viewer/viewer.js");
  return s;
}

std::string viewer_page(const std::vector<ViewerLife>& lives, const std::string& title) {
  // Text from files (robot names, labels) reaches the page only as JSON, set by the script
  // as text: nothing in it is parsed as HTML.
  std::string html;
  html += "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n";
  html +=
      "<title>plastivox viewer</title>\n<meta name=\"viewport\" content=\"width=device-width\">\n";
  html += "<style>body { font-family: sans-serif; margin: 1em; color: #222; }</style>\n";
  html += read_asset("viewer/viewer.css.html");
  html += "</head>\n<body>\n<h1 class=\"pv-title\"></h1>\n";
  if (lives.size() > 1) html += buttons_html(lives.size());  // one viewer; these pick its life
  html += read_asset("viewer/viewer_panel.html");
  std::string list;
  for (const ViewerLife& life : lives)
    list += "PLASTIVOX_LIVES.push(" + script_safe(life_object_js(life)) + ");\n";
  html += scripts_html(list);
  html += "<script>document.title = document.querySelector(\".pv-title\").textContent = " +
          script_safe(nlohmann::json(title).dump()) + ";</script>\n";
  html += kStart;
  html += "</body>\n</html>\n";
  return html;
}

std::string life_script(const std::string& id, const ViewerLife& life) {
  return "plastivoxViewer.deliver(" + nlohmann::json(id).dump() + ", " + life_object_js(life) +
         ");\n";
}

std::string viewer_fragment(const std::vector<LifeLink>& lives, bool buttons) {
  if (lives.empty()) return "";
  std::string html = read_asset("viewer/viewer.css.html");
  if (buttons) html += buttons_html(lives.size());
  html += read_asset("viewer/viewer_panel.html");
  std::string list;
  for (const LifeLink& l : lives)
    list += "PLASTIVOX_LIVES.push({id: " + nlohmann::json(l.id).dump() +
            ", src: " + nlohmann::json(l.src).dump() +
            ", meta: {label: " + nlohmann::json(l.id).dump() + "}});\n";
  html += scripts_html(script_safe(list));
  html += kStart;
  return html;
}

LifeLink write_report_life(const std::string& dir, const std::string& id, const ViewerLife& life) {
  std::filesystem::create_directories(dir + "/lives");
  write_file_atomic(dir + "/lives/" + id + ".js", life_script(id, life));
  return LifeLink{id, "lives/" + id + ".js"};
}

void remove_other_lives(const std::string& dir, const std::vector<LifeLink>& keep) {
  namespace fs = std::filesystem;
  if (!fs::is_directory(dir + "/lives")) return;
  for (const auto& e : fs::directory_iterator(dir + "/lives")) {
    const std::string src = "lives/" + e.path().filename().string();
    const bool kept =
        std::any_of(keep.begin(), keep.end(), [&](const LifeLink& l) { return l.src == src; });
    if (!kept && e.path().extension() == ".js") fs::remove(e.path());
  }
}

}  // namespace plastivox::render
