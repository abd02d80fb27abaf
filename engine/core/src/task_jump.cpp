// jump: the highest rise of the centre of mass above its settled height, in voxel lengths:
//   max over the steps after settling of (c_z(t) - c_z(settle)) / L,
// c the mean of the voxel centres (every voxel has one mass), L the voxel size. It is never
// negative: the first state seen after settling is the settled one. A body that sinks or
// topples scores what it rose before, not less.
#include <algorithm>

#include "plastivox/simulator.hpp"
#include "tasks.hpp"

namespace plastivox {
namespace {

constexpr int kJumpHighest = 0;  // task_values: m above the settled centre of mass, the most seen

}  // namespace

void see_jump(const Model& m, State& s) {
  double& highest = s.task_values[kJumpHighest];
  if (s.settled) highest = std::max(highest, body_center_of_mass(m, s).z() - s.com_settled.z());
}

double jump_score(const Model& m, const State& s, const SimResult&) {
  return s.task_values[kJumpHighest] / m.size;
}

std::vector<const char*> jump_values() {
  return {"the highest rise of the centre of mass above its settled height seen, m"};
}

}  // namespace plastivox
