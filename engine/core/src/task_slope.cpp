// slope: walk uphill. The fitness is the rise of the ground under the centre of mass from
// the end of settling to the end of the life, in voxel lengths, never negative:
//   max(0, h(c_xy(T)) - h(c_xy(settle))) / L,
// h the ground's height (0 on the flat floor). Reading the ground, not the centre of mass's
// own height, a body scores by where it got to, not by rearing up or jumping at the end.
//
// Default environment: a pit. The ground is level (at 0) over the body's footprint and kSlopeFlat
// voxel lengths around it, then rises at `angle_deg` away from the start in every direction
// (four planar ramps meeting on the diagonals: the height is a function of the distance
// along the larger of x and y) for `length` voxel lengths, then is level again. Any way a
// body walks is uphill, so a body evolved to walk can climb whichever way it goes. With a
// given environment (say a `ramp`, docs/environments.md) the same fitness reads its ground.
#include <algorithm>
#include <cmath>

#include "plastivox/simulator.hpp"
#include "tasks.hpp"

namespace plastivox {
namespace {

constexpr double kSlopePi = 3.14159265358979323846;
constexpr double kSlopeFlat = 1;    // voxel lengths of level ground around the footprint
constexpr double kSlopeCell = 0.5;  // voxel lengths between nodes

}  // namespace

double slope_score(const Model& m, const State&, const SimResult& summary) {
  return std::max(0.0, ground_rise(m, summary)) / m.size;
}

std::vector<TaskParam> slope_params() {
  return {{"angle_deg", 10, 0, 45, "degrees"}, {"length", 20, 1, 100, "voxel lengths"}};
}

Environment slope_environment(const PhysicsDef& def, const TaskSite& site) {
  const double L = site.L, flat = site.half() + kSlopeFlat * L;
  const double length = task_param(def, "length") * L;
  const double grade = std::tan(task_param(def, "angle_deg") * kSlopePi / 180);
  Environment env;
  env.ground = ground_around(site, flat + length + 2 * L, kSlopeCell * L,
                             [&](double d) { return grade * std::clamp(d - flat, 0.0, length); });
  return env;
}

}  // namespace plastivox
