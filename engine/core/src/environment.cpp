#include "plastivox/environment.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "plastivox/base/names.hpp"
#include "plastivox/base/rng.hpp"
#include "terrain_body.hpp"

namespace plastivox {
namespace {

constexpr double kPi = 3.14159265358979323846;
// The stream a rough ground draws its heights from (Rng::stream's purpose).
constexpr uint64_t kRoughGroundStream = 0x67726f756e64;  // "ground"

// Horizontal extent of a profile from `at`, m.
double profile_span(const GroundDef& g) {
  switch (g.kind) {
    case GroundKind::kRamp:
      return g.length;
    case GroundKind::kStep:
      return g.edge;
    case GroundKind::kStairs:
      return (g.count - 1) * g.run + g.edge;
    case GroundKind::kGap:
      return g.width;
    default:
      return 0;
  }
}

// A profile's height at distance u >= 0 from `at`, m.
double profile_height(const GroundDef& g, double u) {
  const auto ramp = [&](double from) { return std::clamp((u - from) / g.edge, 0.0, 1.0); };
  switch (g.kind) {
    case GroundKind::kRamp:
      return std::tan(g.angle_deg * kPi / 180) * std::min(u, g.length);
    case GroundKind::kStep:
      return g.height * ramp(0);
    case GroundKind::kStairs: {
      double h = 0;
      for (int k = 0; k < g.count; ++k) h += g.rise * ramp(k * g.run);
      return h;
    }
    case GroundKind::kGap:
      return -g.depth * std::clamp(std::min(u, g.width - u) / g.edge, 0.0, 1.0);
    default:
      return 0;
  }
}

}  // namespace

// The engine's and engine/grad's replica's own arithmetic (terrain_body.hpp).
double HeightField::height(double x, double y, double* gx, double* gy) const {
  return ground_height(*this, x, y, gx, gy);
}

double HeightField::penetration(double x, double y, double z, double r, double* normal) const {
  return ground_penetration(*this, x, y, z, r, normal);
}

int64_t ground_nodes(const GroundDef& g) {
  if (g.kind == GroundKind::kNone || g.kind == GroundKind::kFlat) return 1;
  if (g.kind == GroundKind::kHeights || g.kind == GroundKind::kRough)
    return g.nx >= 1 && g.ny >= 1 ? int64_t{g.nx} * g.ny : -1;
  const double nodes = std::floor(profile_span(g) / g.edge) + 2;
  if (!(g.edge > 0) || !(nodes >= 2)) return -1;
  return nodes > 1e15 ? std::numeric_limits<int64_t>::max() : static_cast<int64_t>(nodes);
}

HeightField make_height_field(const GroundDef& g) {
  HeightField f;
  switch (g.kind) {
    case GroundKind::kNone:
      break;
    case GroundKind::kFlat:
      f.h = {g.height};
      break;
    case GroundKind::kHeights:
    case GroundKind::kRough:
      f.x0 = g.origin[0], f.y0 = g.origin[1], f.cell = g.cell;
      f.nx = g.nx, f.ny = g.ny;
      if (g.kind == GroundKind::kHeights) {
        f.h = g.heights;
      } else {
        Rng rng = Rng::stream(g.seed, kRoughGroundStream, 0, 0);
        f.h.resize(static_cast<size_t>(g.nx) * g.ny);
        for (double& h : f.h) h = -g.amplitude * rng.uniform();
      }
      break;
    default: {  // a profile along +x, constant in y
      f.x0 = g.at, f.cell = g.edge;
      f.nx = static_cast<int>(ground_nodes(g));
      f.h.resize(f.nx);
      for (int i = 0; i < f.nx; ++i) f.h[i] = profile_height(g, i * g.edge);
    }
  }
  return f;
}

int64_t object_voxels(const Environment& env) {
  int64_t voxels = 0;
  for (const ObjectDef& o : env.objects) voxels += int64_t{o.voxels[0]} * o.voxels[1] * o.voxels[2];
  return voxels;
}

void validate(const Environment& env) {
  const auto need = [](bool ok, const std::string& field, const std::string& what) {
    if (!ok) throw std::invalid_argument("physics.environment." + field + ": " + what);
  };
  const auto fin = [](double v) { return std::isfinite(v); };
  const GroundDef& g = env.ground;
  const std::string gf = "ground.";
  const double big = 1e6;  // m: any coordinate or length of the world
  switch (g.kind) {
    case GroundKind::kNone:
      break;
    case GroundKind::kFlat:
      need(fin(g.height) && std::abs(g.height) <= big, gf + "height",
           "must be finite, |h| <= 1e6 m");
      break;
    case GroundKind::kHeights:
    case GroundKind::kRough:
      need(fin(g.cell) && g.cell > 0 && g.cell <= big, gf + "cell", "must be in (0, 1e6] m");
      need(fin(g.origin[0]) && fin(g.origin[1]) && std::abs(g.origin[0]) <= big &&
               std::abs(g.origin[1]) <= big,
           gf + "origin", "must be finite, within 1e6 m");
      need(g.nx >= 1 && g.ny >= 1, gf + (g.kind == GroundKind::kRough ? "nodes" : "heights"),
           "needs at least one node along x and y");
      need(int64_t{g.nx} * g.ny <= kMaxGroundNodes,
           gf + (g.kind == GroundKind::kRough ? "nodes" : "heights"),
           "more than " + std::to_string(kMaxGroundNodes) + " nodes");
      if (g.kind == GroundKind::kHeights) {
        need(g.heights.size() == static_cast<size_t>(g.nx) * g.ny, gf + "heights",
             "expected nx * ny heights");
        for (double h : g.heights)
          need(fin(h) && std::abs(h) <= big, gf + "heights",
               "every height must be finite, |h| <= 1e6 m");
      } else {
        need(fin(g.amplitude) && g.amplitude >= 0 && g.amplitude <= big, gf + "amplitude",
             "must be in [0, 1e6] m");
      }
      break;
    default:
      need(fin(g.at) && std::abs(g.at) <= big, gf + "at", "must be finite, within 1e6 m");
      need(fin(g.edge) && g.edge > 0 && g.edge <= big, gf + "edge", "must be in (0, 1e6] m");
      if (g.kind == GroundKind::kRamp) {
        need(fin(g.angle_deg) && std::abs(g.angle_deg) < 80, gf + "angle_deg",
             "must be in (-80, 80) degrees");
        need(fin(g.length) && g.length > 0 && g.length <= big, gf + "length",
             "must be in (0, 1e6] m");
      } else if (g.kind == GroundKind::kStep) {
        need(fin(g.height) && std::abs(g.height) <= big, gf + "height",
             "must be finite, |h| <= 1e6 m");
      } else if (g.kind == GroundKind::kStairs) {
        need(g.count >= 1 && g.count <= 100000, gf + "count", "must be in [1, 100000]");
        need(fin(g.rise) && std::abs(g.rise) <= big, gf + "rise",
             "must be finite, |rise| <= 1e6 m");
        need(fin(g.run) && g.run >= g.edge && g.run <= big, gf + "run",
             "must be >= edge and <= 1e6 m");
      } else if (g.kind == GroundKind::kGap) {
        need(fin(g.width) && g.width >= 2 * g.edge && g.width <= big, gf + "width",
             "must be >= 2 edge and <= 1e6 m");
        need(fin(g.depth) && g.depth >= 0 && g.depth <= big, gf + "depth", "must be in [0, 1e6] m");
      }
      need(ground_nodes(g) <= kMaxGroundNodes, gf + "edge",
           "samples the ground at more than " + std::to_string(kMaxGroundNodes) +
               " nodes (a longer edge, or a shorter ground)");
  }
  need(env.obstacles.size() <= static_cast<size_t>(kMaxObstacles), "obstacles",
       "more than " + std::to_string(kMaxObstacles) + " boxes");
  for (size_t b = 0; b < env.obstacles.size(); ++b) {
    const ObstacleBox& o = env.obstacles[b];
    const std::string field = "obstacles[" + std::to_string(b) + "]";
    for (int a = 0; a < 3; ++a) {
      need(fin(o.min[a]) && fin(o.max[a]) && std::abs(o.min[a]) <= big && std::abs(o.max[a]) <= big,
           field, "corners must be finite, within 1e6 m");
      need(o.min[a] < o.max[a], field, "min must be below max on every axis");
    }
  }
  need(env.objects.size() <= static_cast<size_t>(kMaxObjects), "objects",
       "more than " + std::to_string(kMaxObjects) + " objects");
  int64_t voxels = 0;
  for (size_t b = 0; b < env.objects.size(); ++b) {
    const ObjectDef& o = env.objects[b];
    const std::string field = "objects[" + std::to_string(b) + "].";
    for (int a = 0; a < 3; ++a)
      need(o.voxels[a] >= 1 && o.voxels[a] <= 1000, field + "voxels",
           "every extent must be in [1, 1000] voxels");
    voxels += int64_t{o.voxels[0]} * o.voxels[1] * o.voxels[2];
    need(voxels <= kMaxObjectVoxels, field + "voxels",
         "the objects hold more than " + std::to_string(kMaxObjectVoxels) + " voxels");
    for (int a = 0; a < 3; ++a)
      need(fin(o.at[a]) && std::abs(o.at[a]) <= big, field + "at", "must be finite, within 1e6 m");
    need(fin(o.stiffness) && o.stiffness >= 0 && o.stiffness <= 1e12, field + "stiffness",
         "must be in [0, 1e12] Pa (0: the robot's stiffest voxel's)");
  }
}

namespace {

// The ground types a file names, in docs/environments.md's order (kNone, the flat floor of
// PhysicsDef::floor, is named by no file).
constexpr Named<GroundKind> kGroundKindNames[] = {
    {GroundKind::kFlat, "flat"},     {GroundKind::kHeights, "heightfield"},
    {GroundKind::kRamp, "ramp"},     {GroundKind::kStep, "step"},
    {GroundKind::kStairs, "stairs"}, {GroundKind::kGap, "gap"},
    {GroundKind::kRough, "rough"},
};

}  // namespace

const char* to_string(GroundKind kind) {
  return kind == GroundKind::kNone ? "none" : name_in(kGroundKindNames, kind);
}

std::string ground_kind_names() {
  return choices_in(kGroundKindNames);
}

GroundKind parse_ground_kind(const std::string& name) {
  if (const auto kind = value_in(kGroundKindNames, name)) return *kind;
  throw std::invalid_argument("ground type '" + name + "' is unknown (use " + ground_kind_names() +
                              ")");
}

}  // namespace plastivox
