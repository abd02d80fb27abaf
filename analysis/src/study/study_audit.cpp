// The champions' audit: each champion's life simulated once more with its run's physics,
// graded for floor contact (docs/engine.md, "Floor contact and sinking"). A run evolved under
// the authors' rule may have crowned a body that fell through the floor; whatever the rule,
// that life is measured here, and a champion whose life is unstable or sank is left out of
// the statistics and figures unless StudyOptions::keep_artifacts. A finished life the
// vertical rule flags (walk scored in 3-D, too much of its fitness from rising or falling:
// vertical_exploit, plastivox/rules/life_rules.hpp) is left out the same way unless
// StudyOptions::keep_vertical: a stronger search climbs onto its own legs before it learns to
// walk further, and the 3-D distance pays for the climb as for a stride.
#include <algorithm>
#include <cstdio>

#include "plastivox/base/parallel.hpp"
#include "plastivox/evo/config.hpp"  // sinking_invalid_in
#include "plastivox/io/limits.hpp"
#include "plastivox/rules/life_rules.hpp"
#include "plastivox/simulator.hpp"
#include "plastivox/task.hpp"
#include "study_internal.hpp"

namespace plastivox::analysis::study {
namespace {

// "invalid" or "scored (the authors' rule)" for one run's resolved physics.
std::string rule_of(const StudyInput& in) {
  return evo::sinking_invalid_in(in.physics_json) ? "invalid" : "scored (the authors' rule)";
}

std::string direction_of(const PhysicsDef& d) {
  switch (d.task) {
    case Task::kJump:
      return "highest rise of the centre of mass above its settled height";
    case Task::kTurn:
      return "body's net rotation about the vertical axis since settling, either way round";
    case Task::kRough:
    case Task::kObstacles:
      return "horizontal displacement of the centre of mass";
    case Task::kClimb: {
      char w[32];
      std::snprintf(w, sizeof w, "%g", task_param(d, "height_weight"));
      return "horizontal displacement of the centre of mass plus " + std::string(w) +
             " times the rise of the ground under it";
    }
    case Task::kSlope:
      return "rise of the ground under the centre of mass";
    default:
      break;
  }
  return d.fitness == FitnessMode::k3D
             ? "3-D displacement of the centre of mass (as in the authors' code)"
             : "displacement of the centre of mass in the xy-plane (as in the paper's text)";
}

// The first of `values` and, when they differ, every distinct one: "a" or "mixed: a; b".
std::string one_or_mixed(const std::vector<std::string>& values) {
  std::vector<std::string> distinct;
  for (const std::string& v : values)
    if (std::find(distinct.begin(), distinct.end(), v) == distinct.end()) distinct.push_back(v);
  if (distinct.size() == 1) return distinct[0];
  std::string s = "mixed: ";
  for (size_t i = 0; i < distinct.size(); ++i) s += (i ? "; " : "") + distinct[i];
  return s;
}

}  // namespace

std::string controller_of(const std::vector<ChampionAnalysis>& champions) {
  std::vector<std::string> controllers;
  for (const ChampionAnalysis& c : champions)
    controllers.push_back(controller_text(c.robot.controller));
  return controllers.empty() ? std::string() : one_or_mixed(controllers);
}

void audit_champions(StudyResult& r, const StudyProgressFn& progress) {
  const int n = static_cast<int>(r.champions.size());
  const int threads = r.options.threads > 0 ? r.options.threads : hardware_threads();
  parallel_for(r.champions.size(), std::min(threads, std::max(1, n)), [&](size_t i) {
    ChampionAnalysis& c = r.champions[i];
    // Every champion is held to the sinking rule, whatever rule its run selected under.
    PhysicsDef physics = c.physics;
    physics.sinking_invalid = true;
    SimResult life = simulate(compile(c.robot, physics, limits_from_environment()));
    c.life_status = life.status == SimStatus::kFinished ? "finished" : "unstable";  // measured
    c.health = to_string(life.floor_health);
    c.floor_depth = life.floor_depth;
    c.vertical_share = life.vertical_share;
    judge_life(physics, life);
    char why[200] = "";
    if (life.status != SimStatus::kFinished && !life.sank)
      std::snprintf(why, sizeof why, "its life is unstable (%s)", life.failure.c_str());
    else if (life.sank)
      std::snprintf(why, sizeof why,
                    "it sank through the floor (%.3g voxel lengths deep; %.0f %% of its "
                    "fitness is vertical)",
                    life.floor_depth, 100 * life.vertical_share);
    bool keep = r.options.keep_artifacts;
    const char* code = life.sank ? "sank" : "unstable";
    if (why[0] == 0 && vertical_exploit(physics, life)) {
      c.vertical_exploit = true;
      keep = r.options.keep_vertical;
      code = "vertical";
      std::snprintf(why, sizeof why,
                    "its fitness owes too much to vertical motion (vertical share %.2f, above %.2g "
                    "under walk's 3-D fitness; dz %.3g voxel lengths)",
                    life.vertical_share, kVerticalShareLimit, life.displacement.z());
    }
    if (why[0] == 0) return;
    if (c.status == "ok") c.status = code;
    c.status_detail += (c.status_detail.empty() ? "" : "; ") + std::string("audit: ") + why;
    if (!keep) c.artifact = why;
  });

  std::vector<std::string> rules, directions, tasks, units, environments;
  for (const StudyInput& in : r.inputs) rules.push_back(rule_of(in));
  for (const ChampionAnalysis& c : r.champions) {
    directions.push_back(direction_of(c.physics));
    tasks.push_back(to_string(c.physics.task));
    units.push_back(task_info(c.physics.task).unit);
    environments.push_back(environment_text(c.physics));
  }
  r.sinking_rule = one_or_mixed(rules);
  r.fitness_direction = one_or_mixed(directions);
  if (!tasks.empty()) {
    r.task = one_or_mixed(tasks);
    r.fitness_unit = one_or_mixed(units);
    r.environment = one_or_mixed(environments);
  }
  r.controller = controller_of(r.champions);

  int excluded = 0, flagged = 0, vertical = 0;
  for (const ChampionAnalysis& c : r.champions) {
    excluded += c.artifact.empty() ? 0 : 1;
    flagged += c.status == "sank" || c.life_status == "unstable" ? 1 : 0;
    vertical += c.vertical_exploit ? 1 : 0;
  }
  if (progress)
    progress({"audit", n, n,
              "audit: " + std::to_string(n) + " champions re-simulated, " +
                  std::to_string(flagged) + " unstable or sunk, " + std::to_string(vertical) +
                  " too vertical, " + std::to_string(excluded) + " excluded"});
}

}  // namespace plastivox::analysis::study

namespace plastivox::analysis {

VerticalAudit vertical_audit(const StudyResult& r) {
  VerticalAudit v;
  // direction_of's words for walk in 3-D, alone or among mixed directions.
  v.applies = r.fitness_direction.find("3-D displacement") != std::string::npos;
  for (const ChampionAnalysis& c : r.champions) {
    v.flagged += c.vertical_exploit ? 1 : 0;
    v.excluded += c.vertical_exploit && !c.artifact.empty() ? 1 : 0;
  }
  return v;
}

}  // namespace plastivox::analysis
