// Cost estimate: a short calibration simulation and the experiment's evaluation count.
#include "cost_estimate.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>

#include "plastivox/model.hpp"
#include "plastivox/robot.hpp"
#include "plastivox/simulator.hpp"

namespace plastivox::experiment {

SpeedSample measure_speed(const ExperimentConfig& config, double budget_seconds) {
  const auto& e = config.evolution;
  RobotDef robot = make_empty_robot(e.nx, e.ny, e.nz, e.voxel_size);
  // The lower half of the lattice, a fixed pseudo-random stiffness pattern: a body of the
  // size and stiffness spread evolution typically produces, the same on every call.
  uint64_t lcg = 12345;
  auto uniform = [&lcg] {
    lcg = lcg * 6364136223846793005ull + 1442695040888963407ull;
    return static_cast<double>(lcg >> 11) / 9007199254740992.0;
  };
  const int zmax = std::max(1, e.nz / 2);
  for (int z = 0; z < zmax; ++z)
    for (int y = 0; y < e.ny; ++y)
      for (int x = 0; x < e.nx; ++x) {
        const int i = x + e.nx * (y + e.ny * z);
        robot.present[i] = 1;
        robot.stiffness[i] =
            e.physics.e_min * std::pow(e.physics.e_max / e.physics.e_min, uniform());
        robot.dev_rate[i] = 2 * uniform() - 1;
        robot.phase[i] = 2 * uniform() - 1;
      }
  PhysicsDef physics = e.physics;
  physics.treatment = Treatment::kStress;
  const Model model = compile(robot, physics);
  auto sim = std::make_unique<Simulator>(model);

  // Only steps actually taken count: a body this mixed can go unstable (a stopped
  // simulation's step() does nothing), and then the calibration starts it over.
  const auto t0 = std::chrono::steady_clock::now();
  int64_t steps = 0;
  double elapsed = 0, dt = sim->state().dt;
  while (elapsed < budget_seconds) {
    if (sim->state().status != SimStatus::kRunning || sim->state().time >= physics.duration) {
      steps += sim->state().steps;
      sim = std::make_unique<Simulator>(model);
    }
    for (int k = 0; k < 50; ++k) sim->step();
    if (sim->state().status == SimStatus::kRunning) dt = sim->state().dt;
    elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }
  steps += sim->state().steps;
  SpeedSample s;
  s.voxels_per_body = static_cast<double>(model.n);
  s.voxel_steps_per_second =
      s.voxels_per_body * static_cast<double>(steps) / std::max(elapsed, 1e-9);
  s.steps_per_life = physics.duration / std::max(dt, 1e-12);
  s.seconds_per_evaluation = s.voxels_per_body * s.steps_per_life / s.voxel_steps_per_second;
  return s;
}

CostEstimate estimate_cost(const ExperimentConfig& config, const SpeedSample& speed, int threads) {
  CostEstimate c;
  c.speed = speed;
  c.threads = std::max(1, threads);
  const int64_t p = config.evolution.population, g = config.evolution.generations;
  c.evolution_evaluations = config.runs() * (p + g * (p + 1));
  c.analysis_evaluations =
      static_cast<int64_t>(config.runs()) * (1 + config.analysis.robustness_draws);
  const double evals = static_cast<double>(c.evolution_evaluations + c.analysis_evaluations);
  const double core_seconds = evals * speed.seconds_per_evaluation;
  c.core_hours = core_seconds / 3600.0;
  const double efficiency = c.threads > 1 ? 0.9 : 1.0;
  c.wall_seconds = core_seconds / (c.threads * efficiency);
  return c;
}

std::string human_duration(double s) {
  char buf[64];
  if (!std::isfinite(s) || s < 0) return "?";
  if (s < 90) {
    std::snprintf(buf, sizeof buf, "%.0f s", s);
  } else if (s < 5400) {
    std::snprintf(buf, sizeof buf, "%.0f min", s / 60);
  } else if (s < 3 * 86400) {
    std::snprintf(buf, sizeof buf, "%.0f h %02.0f min", std::floor(s / 3600),
                  std::floor(std::fmod(s, 3600) / 60));
  } else {
    std::snprintf(buf, sizeof buf, "%.1f days", s / 86400);
  }
  return buf;
}

std::string CostEstimate::summary() const {
  char buf[512];
  std::snprintf(buf, sizeof buf,
                "estimate: %lld evolution + %lld analysis simulations of ~%.0f voxels x %.0f "
                "steps; measured %.2f M voxel-steps/s per core = %.2f s per life\n"
                "estimate: %.3g core-hours; about %s on %d thread%s of this machine",
                static_cast<long long>(evolution_evaluations),
                static_cast<long long>(analysis_evaluations), speed.voxels_per_body,
                speed.steps_per_life, speed.voxel_steps_per_second / 1e6,
                speed.seconds_per_evaluation, core_hours, human_duration(wall_seconds).c_str(),
                threads, threads == 1 ? "" : "s");
  return buf;
}

}  // namespace plastivox::experiment
