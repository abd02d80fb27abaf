// Whether a life counts: the rules a study or an evolution applies to the core's measurements
// of a life (SimResult: floor health, depth, vertical share), decided here and nowhere else
// (docs/engine.md, "Floor contact and sinking" and "Vertical motion"). The core reports how a
// life went; these functions say what that means for its score. Pure functions of the physics
// and the life's summary, so they apply wherever a summary exists: simulate's exit status and
// output, Python's simulate and VoxelEnv, evolution's evaluation and the study's audit.
#pragma once

#include "plastivox/physics_def.hpp"
#include "plastivox/simulator.hpp"

namespace plastivox {

// The vertical rule: walk's 3-D fitness pays for a rise or a fall of the centre of mass as
// for a stride, so a life whose vertical_share exceeds kVerticalShareLimit owes its score too
// much to moving up or down rather than walking, provided it rose or fell at least
// kVerticalRiseMin voxel lengths (the share of a tiny displacement is noise: the demo
// walker's first 0.2 s of walking has a share of 0.32 on dz = 0.05). Set from measured lives:
// every walker measured stays at or below 0.06, the champions an optimiser crowns before they
// walk (crouching or rising) reach 0.17 and more.
inline constexpr double kVerticalShareLimit = 0.1;
inline constexpr double kVerticalRiseMin = 0.25;  // voxel lengths

// The vertical rule's flag: true when `def` scores walk in 3-D (the only fitness a vertical
// motion enters; xy fitness zeroes it and the other tasks define their own direction) and the
// finished life `r`, not sunk (a fall through the floor is graded as such), has
// vertical_share above kVerticalShareLimit and |dz| of at least kVerticalRiseMin. The study's
// audit excludes such a champion (docs/analysis.md, "The audit").
bool vertical_exploit(const PhysicsDef& def, const SimResult& r);

// Applies the rules to `r`, the core's summary of a life under `def` (call once per summary):
//   - sinking: a finished life that sank (r.sank) is invalid under def.sinking_invalid: its
//     status becomes kUnstable, its fitness 0 and `failure` says what sank and which rule
//     decided (false, the authors' rule, scores it like any other life);
//   - vertical: a life vertical_exploit flags gets a warning saying so;
//   - success: a life that does not count (not finished, or made invalid here) has
//     success false, whatever the task's criterion said of its measurements.
void judge_life(const PhysicsDef& def, SimResult& r);

// A life still running (Python's VoxelEnv) ends invalid the moment it is certain to be
// judged sunk: `sunk` is has_sunk(model, state) (plastivox/simulator.hpp), under
// def.sinking_invalid. Its fitness is then 0.
bool ends_invalid(const PhysicsDef& def, bool sunk);

}  // namespace plastivox
