#include "plastivox/io/sim_summary.hpp"

#include <nlohmann/json.hpp>

namespace plastivox {

std::string sim_summary_json(const SimResult& r, const PhysicsDef& physics,
                             const std::string& source, const std::string& version,
                             const StageTimings* timings) {
  nlohmann::json j;
  j["source"] = source;
  j["status"] = to_string(r.status);
  if (!r.failure.empty()) j["failure"] = r.failure;
  j["warnings"] = r.warnings;
  j["treatment"] = to_string(physics.treatment);
  j["growth_model"] = to_string(physics.growth);
  j["fitness"] = r.fitness;
  j["dist_x"] = r.displacement.x();
  j["dist_y"] = r.displacement.y();
  j["dist_z"] = r.displacement.z();
  j["voxels"] = r.voxels;
  j["health"] = to_string(r.floor_health);
  j["floor_depth"] = r.floor_depth;
  j["voxels_deep_max"] = r.voxels_deep_max;
  j["voxels_below_floor"] = r.voxels_below_floor;
  j["vertical_share"] = r.vertical_share;
  j["sinking_invalid"] = physics.sinking_invalid;
  j["steps"] = r.steps;
  j["dt"] = r.dt_initial;
  j["dt_final"] = r.dt_final;
  j["sim_time"] = r.sim_time;
  j["wall_seconds"] = r.wall_seconds;
  j["voxel_steps_per_second"] = r.wall_seconds > 0 ? r.voxels * r.steps / r.wall_seconds : 0.0;
  j["stiffness_change_mean"] = r.stiffness_change_mean;
  j["stiffness_change_abs_mean"] = r.stiffness_change_abs_mean;
  j["stiffness_change_variance"] = r.stiffness_change_var;
  j["stiffness_change_mean_percent"] = 100.0 * r.stiffness_change_mean;
  j["final_stiffness"] = r.final_stiffness;
  j["final_state_hash"] = r.final_state_hash;
  j["version"] = version;
  if (timings)
    for (const StageName& s : kStageNames) j["stage_seconds"][s.name] = timings->*s.seconds;
  return j.dump(1);
}

}  // namespace plastivox
