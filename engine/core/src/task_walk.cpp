// walk, the paper's locomotion and the default task: how far the centre of mass moved from
// the end of settling to the end of the life, in voxel lengths (the summary's displacement,
// displacement_since_settling: horizontal only under physics.fitness = xy). Needs only the
// last state, so it keeps no running values.
#include "plastivox/simulator.hpp"
#include "tasks.hpp"

namespace plastivox {

double walk_score(const Model&, const State&, const SimResult& summary) {
  return summary.displacement.norm();
}

}  // namespace plastivox
