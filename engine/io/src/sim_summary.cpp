#include "plastivox/io/sim_summary.hpp"

#include <nlohmann/json.hpp>

#include "plastivox/rules/life_rules.hpp"
#include "plastivox/task.hpp"

namespace plastivox {

std::vector<SummaryField> sim_summary_fields(const SimResult& r, const PhysicsDef& physics,
                                             const std::string& source,
                                             const std::string& version) {
  std::vector<SummaryField> f = {
      {"source", source},
      {"status", std::string(to_string(r.status))},
      {"warnings", r.warnings},
      {"treatment", std::string(to_string(physics.treatment))},
      {"growth_model", std::string(to_string(physics.growth))},
      {"task", std::string(to_string(physics.task))},
      {"fitness", r.fitness},
      {"fitness_unit", std::string(task_info(physics.task).unit)},
      {"success", r.success},
      {"dist_x", r.displacement.x()},
      {"dist_y", r.displacement.y()},
      {"dist_z", r.displacement.z()},
      {"voxels", int64_t{r.voxels}},
      {"health", std::string(to_string(r.floor_health))},
      {"floor_depth", r.floor_depth},
      {"voxels_deep_max", int64_t{r.voxels_deep_max}},
      {"voxels_below_floor", int64_t{r.voxels_below_floor}},
      {"vertical_share", r.vertical_share},
      {"vertical_exploit", vertical_exploit(physics, r)},
      {"sinking_invalid", physics.sinking_invalid},
      {"steps", int64_t{r.steps}},
      {"dt", r.dt_initial},
      {"dt_final", r.dt_final},
      {"sim_time", r.sim_time},
      {"wall_seconds", r.wall_seconds},
      {"voxel_steps_per_second", r.wall_seconds > 0 ? r.voxels * r.steps / r.wall_seconds : 0.0},
      {"stiffness_change_mean", r.stiffness_change_mean},
      {"stiffness_change_abs_mean", r.stiffness_change_abs_mean},
      {"stiffness_change_variance", r.stiffness_change_var},
      {"stiffness_change_mean_percent", 100.0 * r.stiffness_change_mean},
      {"final_stiffness", r.final_stiffness},
      {"final_state_hash", uint64_t{r.final_state_hash}},
      {"version", version},
  };
  if (!r.failure.empty()) f.insert(f.begin() + 2, {"failure", r.failure});
  return f;
}

std::string sim_summary_json(const SimResult& r, const PhysicsDef& physics,
                             const std::string& source, const std::string& version,
                             const StageTimings* timings) {
  nlohmann::json j;
  for (const SummaryField& f : sim_summary_fields(r, physics, source, version))
    std::visit([&](const auto& v) { j[f.name] = v; }, f.value);
  if (timings)
    for (const StageName& s : kStageNames) j["stage_seconds"][s.name] = timings->*s.seconds;
  return j.dump(1);
}

}  // namespace plastivox
