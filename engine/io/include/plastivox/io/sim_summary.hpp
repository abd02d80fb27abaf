// The summary of one simulated life as JSON: the object `plastivox simulate --json` prints
// and the Python module's Result carries (one code path for both).
#pragma once

#include <string>

#include "plastivox/physics_def.hpp"
#include "plastivox/simulator.hpp"

namespace plastivox {

// Keys: source, status, failure (only when unstable), treatment, growth_model, fitness,
// dist_x/y/z, voxels, steps, dt, dt_final, sim_time, wall_seconds, voxel_steps_per_second,
// stiffness_change_*, final_stiffness, final_state_hash, version. `physics` is what the
// life was simulated under; `source` names the robot. Doubles round-trip exactly. With
// `timings`, also stage_seconds: {bond_forces: s, ...} (kStageNames).
std::string sim_summary_json(const SimResult& r, const PhysicsDef& physics,
                             const std::string& source, const std::string& version,
                             const StageTimings* timings = nullptr);

}  // namespace plastivox
