// A life as the 3-D viewer reads it (plastivox/render/viewer.hpp): its frames packed into the
// compact binary form "PVL1" (layout in docs/rendering.md, "The 3-D viewer"), and the JSON
// beside them that says what the overlay reads out and how each colour mode scales.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "plastivox/render/color_scale.hpp"
#include "plastivox/render/life.hpp"
#include "plastivox/render/scene.hpp"  // ground_bends
#include "plastivox/render/viewer.hpp"
#include "plastivox/state.hpp"  // center_of_mass

namespace plastivox::render {
namespace {

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

double largest_stimulus(const Recording& rec) {
  double m = 0;
  for (const Frame& f : rec.frames)
    for (double s : f.stimulus)
      if (std::isfinite(s)) m = std::max(m, std::abs(s));
  return m;
}

nlohmann::json scale_json(const ColorScale& s) {
  nlohmann::json ticks = nlohmann::json::array();
  for (const Tick& t : s.ticks()) ticks.push_back({{"t", t.t}, {"label", t.label}});
  return {
      {"lo", s.lo}, {"hi", s.hi}, {"map", s.map().name()}, {"title", s.title}, {"ticks", ticks}};
}

// Metres to the micrometre, so the page's JSON stays short.
double micrometres(double v) {
  return std::round(v * 1e6) / 1e6;
}

// The environment as the viewer draws it (docs/rendering.md, "The 3-D viewer"), over the
// square the page's floor covers: the life's bounding box of centres, grown by 20 voxel
// lengths. The ground as heights h (x fastest) at the crossings of the lines x and y (its
// bends, as the renderer cuts it, and the square's edges); the obstacles in that square as
// [min x, min y, min z, max x, max y, max z]; zmin, the lowest of them (the page's camera
// stays above it).
nlohmann::json world_json(const Model& m, const std::vector<Frame>& frames) {
  Eigen::Vector2d lo = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  for (const Frame& f : frames)
    for (const Eigen::Vector3d& p : f.pos) {
      lo = lo.cwiseMin(p.head<2>());
      hi = hi.cwiseMax(p.head<2>());
    }
  if (frames.empty() || m.n == 0) lo = hi = Eigen::Vector2d::Zero();
  const Eigen::Vector2d centre = 0.5 * (lo + hi);
  const double half = 0.5 * (hi - lo).maxCoeff() + 20 * m.size;
  nlohmann::json world = nlohmann::json::object();
  double zmin = 0;
  const Environment& env = m.def.environment;
  if (env.ground.kind != GroundKind::kNone) {
    std::vector<double> lines[2];
    for (int a = 0; a < 2; ++a) {
      lines[a] = ground_bends(m.ground, a, centre[a] - half, centre[a] + half, kMaxGroundLines);
      lines[a].insert(lines[a].begin(), centre[a] - half);
      lines[a].push_back(centre[a] + half);
    }
    nlohmann::json h = nlohmann::json::array();
    zmin = std::numeric_limits<double>::infinity();
    for (double y : lines[1])
      for (double x : lines[0]) {
        const double z = m.ground.height(x, y);
        zmin = std::min(zmin, z);
        h.push_back(micrometres(z));
      }
    nlohmann::json xs = nlohmann::json::array(), ys = nlohmann::json::array();
    for (double x : lines[0]) xs.push_back(micrometres(x));
    for (double y : lines[1]) ys.push_back(micrometres(y));
    world["ground"] = {{"x", xs}, {"y", ys}, {"h", h}};
  }
  nlohmann::json boxes = nlohmann::json::array();
  for (const ObstacleBox& b : env.obstacles) {
    if (b.max[0] < centre.x() - half || b.min[0] > centre.x() + half ||
        b.max[1] < centre.y() - half || b.min[1] > centre.y() + half)
      continue;
    boxes.push_back({micrometres(b.min[0]), micrometres(b.min[1]), micrometres(b.min[2]),
                     micrometres(b.max[0]), micrometres(b.max[1]), micrometres(b.max[2])});
    zmin = std::min(zmin, b.min[2]);
  }
  world["obstacles"] = boxes;
  world["zmin"] = micrometres(zmin);
  return world;
}

}  // namespace

std::string pack_life(const ViewerItem& life) {
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
  FrameSet overlay;  // what displacement_so_far needs: the model (not owned) and settling
  overlay.model = std::shared_ptr<const Model>(std::shared_ptr<const Model>(), &m);
  overlay.settled = life.settled;
  overlay.com_settled = life.com_settled;
  for (const Frame& f : frames) {
    put_f32(out, f.time);
    put_f32(out, displacement_so_far(overlay, f));
    const Eigen::Vector3d com = center_of_mass(f.pos, m.robot_n);  // the robot's
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
  // The actuation signal, when recorded: per frame and voxel one u8 over [-1, 1].
  if (life.recording->control)
    for (const Frame& f : frames)
      for (int i = 0; i < n; ++i)
        put_u8(out, static_cast<uint8_t>(quantise(f.actuation[i], -1, 1, 255)));
  return out;
}

std::string life_meta_json(const ViewerItem& life) {
  const Model& m = *life.model;
  std::vector<const Frame*> frames;
  for (const Frame& f : life.recording->frames) frames.push_back(&f);
  nlohmann::json scales;
  for (const ColorMode mode : {ColorMode::kCongenital, ColorMode::kStiffness, ColorMode::kChange,
                               ColorMode::kPhase, ColorMode::kStimulus, ColorMode::kActuation})
    scales[to_string(mode)] = scale_json(make_color_scale(mode, m, frames));
  if (!life.recording->control) scales["actuation"]["title"] = "actuation signal (not recorded)";
  nlohmann::json meta{{"label", life.label},
                      {"treatment", life.treatment},
                      {"fitness", life.fitness},
                      {"settle_time", m.def.settle_time},
                      {"scales", scales}};
  // Only a life beyond the flat floor carries its world: the floor's pages stay as they were.
  if (m.terrain) meta["world"] = world_json(m, life.recording->frames);
  return meta.dump();
}

}  // namespace plastivox::render
