// rough: walk over a seeded random height field. The fitness is the horizontal displacement
// of the centre of mass from the end of settling to the end of the life, in voxel lengths,
//   |c_xy(T) - c_xy(settle)| / L,
// so the ground's ups and downs neither add nor take away (a body does not score by sinking
// into a hollow or climbing a bump, only by getting somewhere).
//
// Default environment: a `rough` ground (docs/environments.md) whose node heights are drawn
// uniformly in [-amplitude, 0] from `seed`, one node every `cell`, over a square reaching
// kRoughReach voxel lengths past the body's footprint on every side (beyond it, the edge heights
// continue). The grid is centred on the footprint, so every body meets the same ground
// around it. The body starts resting on the highest point under it (compile()).
#include <cmath>

#include "plastivox/simulator.hpp"
#include "tasks.hpp"

namespace plastivox {
namespace {

constexpr double kRoughReach = 40;  // voxel lengths of ground past the footprint

}  // namespace

std::vector<TaskParam> rough_params() {
  return {{"amplitude", 0.25, 0, 5, "voxel lengths"},
          {"cell", 1, 0.25, 10, "voxel lengths"},
          {"seed", 1, 0, 9007199254740992.0, "", true}};
}

Environment rough_environment(const PhysicsDef& def, const TaskSite& site) {
  const double L = site.L, cell = task_param(def, "cell") * L;
  const int half = static_cast<int>(std::ceil((site.half() + kRoughReach * L) / cell));
  Environment env;
  GroundDef& g = env.ground;
  g.kind = GroundKind::kRough;
  g.cell = cell;
  g.nx = g.ny = 2 * half + 1;
  g.origin = {site.cx - half * cell, site.cy - half * cell};
  g.amplitude = task_param(def, "amplitude") * L;
  g.seed = static_cast<uint64_t>(task_param(def, "seed"));
  return env;
}

}  // namespace plastivox
