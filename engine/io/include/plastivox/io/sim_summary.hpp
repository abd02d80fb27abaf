// The summary of one simulated life as JSON: the object `plastivox simulate --json` prints
// and the Python module's Result carries (one code path for both).
#pragma once

#include <cstdint>
#include <string>
#include <variant>
#include <vector>

#include "plastivox/physics_def.hpp"
#include "plastivox/simulator.hpp"

namespace plastivox {

// One field of the summary: its name (the JSON key and the Python attribute) and its value.
using SummaryValue = std::variant<bool, int64_t, uint64_t, double, std::string, std::vector<double>,
                                  std::vector<std::string>>;
struct SummaryField {
  const char* name;
  SummaryValue value;
};

// The summary's fields, described once; the JSON below and the Python module's Result are
// made from them. Fields: source, status, failure (only when unstable), warnings, treatment,
// growth_model, fitness, dist_x/y/z, voxels, health, floor_depth, voxels_deep_max,
// voxels_below_floor, vertical_share, vertical_exploit (the vertical rule, simulator.hpp),
// sinking_invalid, steps, dt, dt_final, sim_time,
// wall_seconds, voxel_steps_per_second, stiffness_change_*, final_stiffness,
// final_state_hash, version. `physics` is what the life was simulated under; `source` names
// the robot.
std::vector<SummaryField> sim_summary_fields(const SimResult& r, const PhysicsDef& physics,
                                             const std::string& source, const std::string& version);

// sim_summary_fields() as a JSON object (keys in sorted order; doubles round-trip exactly).
// With `timings`, also stage_seconds: {bond_forces: s, ...} (kStageNames).
std::string sim_summary_json(const SimResult& r, const PhysicsDef& physics,
                             const std::string& source, const std::string& version,
                             const StageTimings* timings = nullptr);

}  // namespace plastivox
