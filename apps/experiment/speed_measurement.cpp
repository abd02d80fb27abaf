// What simulations cost on this machine: a short calibration simulation of a typical body,
// a sample of evolution's candidate bodies priced at that speed, and the core-hours the
// experiment's simulations add up to (cost_estimate.hpp).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <ctime>
#include <memory>
#include <string>

#include "cost_estimate.hpp"
#include "plastivox/evo/evolver.hpp"
#include "plastivox/evo/rng.hpp"
#include "plastivox/evo/variation.hpp"
#include "plastivox/io/limits.hpp"
#include "plastivox/model.hpp"
#include "plastivox/robot.hpp"
#include "plastivox/simulator.hpp"

namespace plastivox::experiment {
namespace {

// CPU time of the calling thread, s: what one core gives, however loaded the machine is.
double thread_cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

}  // namespace

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
  // The run's controller (a neural one costs as much as a good part of the physics,
  // docs/benchmarks.md), with weights of the same fixed pattern.
  robot.controller = e.controller;
  for (int k = 0; k < e.controller_genes.count; ++k)
    robot.controller.weights.push_back(2 * uniform() - 1);
  PhysicsDef physics = e.physics;
  physics.treatment = Treatment::kStress;
  const Model model = compile(robot, physics, limits_from_environment());
  auto sim = std::make_unique<Simulator>(model);

  // Only steps actually taken count: a body this mixed can go unstable (a stopped
  // simulation's step() does nothing), and then the calibration starts it over.
  const auto t0 = std::chrono::steady_clock::now();
  const double cpu0 = thread_cpu_seconds();
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
  const double cpu = thread_cpu_seconds() - cpu0;
  SpeedSample s;
  s.voxels_per_body = static_cast<double>(model.n);
  s.voxel_steps_per_second = s.voxels_per_body * static_cast<double>(steps) / std::max(cpu, 1e-9);
  s.steps_per_life = physics.duration / std::max(dt, 1e-12);
  s.seconds_per_evaluation = s.voxels_per_body * s.steps_per_life / s.voxel_steps_per_second;
  return s;
}

CostEstimate estimate_cost(const ExperimentConfig& config, const SpeedSample& speed) {
  CostEstimate c;
  c.speed = speed;
  const int64_t p = config.evolution.population, g = config.evolution.generations;
  c.evolution_evaluations = config.runs() * (p + g * (p + 1));
  c.analysis_evaluations =
      static_cast<int64_t>(config.runs()) * (1 + config.analysis.robustness_draws);
  const double evals = static_cast<double>(c.evolution_evaluations + c.analysis_evaluations);
  const double core_seconds = evals * speed.seconds_per_evaluation;
  c.core_hours = core_seconds / 3600.0;
  return c;
}

BodySample sample_bodies(const ExperimentConfig& config, const SpeedSample& speed, int count) {
  BodySample s;
  int64_t draws = 0;
  const double cpu0 = thread_cpu_seconds();
  for (int k = 0; k < count; ++k) {
    const Treatment t = config.treatments[static_cast<size_t>(k) % config.treatments.size()];
    const evo::EvolveConfig run = config.run_config(t, 1);
    const evo::Expresser expresser(run.expression());
    evo::Rng rng = evo::Rng::stream(1, evo::StreamPurpose::kNewcomer, 0, static_cast<uint64_t>(k));
    const evo::Offspring o = evo::random_individual(expresser, rng, run.max_mutation_tries);
    draws += o.tries;
    if (!o.phenotype.valid) continue;  // not simulated by evolution either
    Job j;
    j.voxels = o.phenotype.voxels;
    j.steps = evo::expected_steps(o.phenotype, run.physics);
    j.seconds = j.voxels * j.steps / std::max(speed.voxel_steps_per_second, 1e-9);
    s.bodies.push_back(j);
  }
  s.seconds_per_expression =
      (thread_cpu_seconds() - cpu0) / static_cast<double>(std::max<int64_t>(draws, 1));
  s.voxel_steps_per_second = speed.voxel_steps_per_second;
  return s;
}

std::string CostEstimate::summary() const {
  char buf[512];
  std::snprintf(buf, sizeof buf,
                "estimate: %lld evolution + %lld analysis simulations of ~%.0f voxels x %.0f "
                "steps; measured %.2f M voxel-steps/s per core = %.2f s per life\n"
                "estimate: %.3g core-hours of simulation at that body's cost",
                static_cast<long long>(evolution_evaluations),
                static_cast<long long>(analysis_evaluations), speed.voxels_per_body,
                speed.steps_per_life, speed.voxel_steps_per_second / 1e6,
                speed.seconds_per_evaluation, core_hours);
  return buf;
}

}  // namespace plastivox::experiment
