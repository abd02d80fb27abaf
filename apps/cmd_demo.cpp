// plastivox demo: the built-in walker under each treatment, side by side.
#include <cstdio>
#include <thread>
#include <vector>

#include "cli.hpp"
#include "plastivox/demo_robots.hpp"
#include "plastivox/io/limits.hpp"
#include "plastivox/rules/life_rules.hpp"
#include "plastivox/simulator.hpp"

namespace plastivox::cli {

int cmd_demo(const Args& in) {
  Args args = in;
  reject_unknown_options(args);
  const RobotDef robot = demo_walker();
  const Treatment treatments[] = {Treatment::kNone, Treatment::kStress, Treatment::kPressure};
  std::vector<Model> models;
  for (Treatment t : treatments) {
    PhysicsDef d = preset_gecco2018_code();
    d.treatment = t;
    models.push_back(compile(robot, d, limits_from_environment()));
  }
  std::printf("plastivox demo: %s, %d voxels, %.1f s lives (gecco2018-code preset)\n",
              robot.name.c_str(), models[0].n, models[0].def.duration);
  // One thread per treatment: each simulation is single-threaded and deterministic.
  std::vector<SimResult> results(models.size());
  std::vector<std::thread> workers;
  for (size_t k = 0; k < models.size(); ++k)
    workers.emplace_back([&, k] {
      results[k] = simulate(models[k]);
      judge_life(models[k].def, results[k]);
    });
  for (auto& w : workers) w.join();
  std::printf("%-10s %10s %14s %16s %10s %8s\n", "treatment", "fitness", "dE/E0 mean %",
              "|dE/E0| mean %", "steps", "wall s");
  int status = 0;
  for (size_t k = 0; k < models.size(); ++k) {
    const SimResult& r = results[k];
    std::printf("%-10s %10.4f %14.3f %16.3f %10lld %8.2f  %s\n", to_string(treatments[k]),
                r.fitness, 100 * r.stiffness_change_mean, 100 * r.stiffness_change_abs_mean,
                static_cast<long long>(r.steps), r.wall_seconds, to_string(r.status));
    if (r.status != SimStatus::kFinished) {
      std::fprintf(stderr, "plastivox demo: %s run unstable: %s\n", to_string(treatments[k]),
                   r.failure.c_str());
      status = 3;
    }
  }
  return status;
}

}  // namespace plastivox::cli
