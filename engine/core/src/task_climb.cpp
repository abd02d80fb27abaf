// climb: ascend steps. The fitness adds the horizontal distance the centre of mass covered
// and the height of ground it gained, weighted by w (`height_weight`), in voxel lengths,
// never negative:
//   max(0, |c_xy(T) - c_xy(settle)| + w (h(c_xy(T)) - h(c_xy(settle)))) / L,
// h the ground's height (0 on the flat floor). Distance pays for reaching the steps; each
// voxel length climbed pays w more, and one descended costs w.
//
// Default environment: terraces. The ground is level (at 0) over the body's footprint and
// kClimbFlat voxel lengths around it; then `count` steps of `rise`, one every `run`, rise away
// from the start in every direction (square rings: the height is a function of the distance
// along the larger of x and y), each riser one node spacing (a quarter voxel) wide. Any way
// a body walks it meets a step. With a given environment (`step` or `stairs`,
// docs/environments.md) the same fitness reads its ground. The bounds on count and run
// keep the grid within kMaxGroundNodes around the largest lattice's footprint.
#include <algorithm>
#include <cmath>

#include "plastivox/simulator.hpp"
#include "tasks.hpp"

namespace plastivox {
namespace {

constexpr double kClimbFlat = 1;     // voxel lengths of level ground around the footprint
constexpr double kClimbCell = 0.25;  // voxel lengths between nodes: a riser's width

}  // namespace

double climb_score(const Model& m, const State&, const SimResult& summary) {
  const double w = task_param(m.def, "height_weight");
  return std::max(0.0, horizontal_displacement(summary) + w * ground_rise(m, summary)) / m.size;
}

// Success: the ground under the centre of mass rose at least one step, less a rounding's
// worth (the ground is interpolated between nodes, and a terrace is level at rise).
bool climb_succeeds(const Model& m, const SimResult& summary) {
  return ground_rise(m, summary) >= (task_param(m.def, "rise") - 1e-9) * m.size;
}

std::vector<TaskParam> climb_params() {
  return {{"rise", 0.25, 0.05, 5, "voxel lengths"},
          {"run", 3, 0.5, 10, "voxel lengths"},
          {"count", 8, 1, 20, "", true},
          {"height_weight", 4, 0, 100, "", false, false}};
}

Environment climb_environment(const PhysicsDef& def, const TaskSite& site) {
  const double L = site.L, flat = site.half() + kClimbFlat * L;
  const double rise = task_param(def, "rise") * L, run = task_param(def, "run") * L;
  const double count = task_param(def, "count");
  Environment env;
  env.ground = ground_around(site, flat + count * run + 2 * L, kClimbCell * L, [&](double d) {
    return d < flat ? 0.0 : rise * std::min(count, std::floor((d - flat) / run) + 1);
  });
  return env;
}

}  // namespace plastivox
