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
#include <vector>

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

SampleLattice sample_lattice(const ExperimentConfig& config) {
  const auto& e = config.evolution;
  SampleLattice l{e.nx, e.ny, e.nz, 1};
  const double sites = static_cast<double>(e.nx) * e.ny * e.nz;
  if (sites <= kSampleSites) return l;
  // The same shape, every extent shrunk by one factor (an extent of 1 or 2 stays: the CPPN's
  // coordinates span [-1, 1] whatever the extent, so a coarser lattice samples the same
  // body), then the factor lowered until the sites fit.
  for (double f = std::cbrt(kSampleSites / sites);; f *= 0.97) {
    const auto shrink = [f](int n) { return std::min(n, std::max(2, static_cast<int>(n * f))); };
    l = {shrink(e.nx), shrink(e.ny), shrink(e.nz), 1};
    if (l.sites() <= kSampleSites) break;
  }
  l.scale = sites / l.sites();
  return l;
}

SpeedSample measure_speed(const ExperimentConfig& config, double budget_seconds, int rounds) {
  const auto& e = config.evolution;
  const SampleLattice lattice = sample_lattice(config);
  RobotDef robot = make_empty_robot(lattice.nx, lattice.ny, lattice.nz, e.voxel_size);
  // The lower half of the lattice, a fixed pseudo-random stiffness pattern: a body of the
  // size and stiffness spread evolution typically produces, the same on every call.
  uint64_t lcg = 12345;
  auto uniform = [&lcg] {
    lcg = lcg * 6364136223846793005ull + 1442695040888963407ull;
    return static_cast<double>(lcg >> 11) / 9007199254740992.0;
  };
  const int zmax = std::max(1, lattice.nz / 2);
  for (int z = 0; z < zmax; ++z)
    for (int y = 0; y < lattice.ny; ++y)
      for (int x = 0; x < lattice.nx; ++x) {
        const int i = x + lattice.nx * (y + lattice.ny * z);
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

  // Rounds along one life (started over when it ends or goes unstable: only steps actually
  // taken count, a stopped simulation's step() does nothing). One round measured 10.0-13.0 M
  // voxel-steps/s in ten runs on a loaded machine: the median of several, with their spread,
  // is what the estimate says (docs/experiment.md, "How the estimate is made").
  rounds = std::max(rounds, 1);
  const double round_wall = budget_seconds / rounds;
  double dt = sim->state().dt;
  std::vector<double> speeds;
  for (int r = 0; r < rounds; ++r) {
    const auto t0 = std::chrono::steady_clock::now();
    const double cpu0 = thread_cpu_seconds();
    int64_t steps = 0;
    double elapsed = 0, cpu = 0;
    while (elapsed < round_wall || cpu < kMinRoundCpu) {
      if (sim->state().status != SimStatus::kRunning || sim->state().time >= physics.duration)
        sim = std::make_unique<Simulator>(model);
      const int64_t before = sim->state().steps;
      for (int k = 0; k < 50; ++k) sim->step();
      steps += sim->state().steps - before;
      if (sim->state().status == SimStatus::kRunning) dt = sim->state().dt;
      elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      cpu = thread_cpu_seconds() - cpu0;
    }
    speeds.push_back(static_cast<double>(model.n) * static_cast<double>(steps) /
                     std::max(cpu, 1e-9));
  }
  std::sort(speeds.begin(), speeds.end());
  SpeedSample s;
  s.rounds = rounds;
  s.voxel_steps_per_second = speeds[speeds.size() / 2];
  s.voxel_steps_low = speeds.front();
  s.voxel_steps_high = speeds.back();
  s.voxels_simulated = static_cast<double>(model.n);
  // The typical body of the whole lattice: its lower half.
  s.voxels_per_body = static_cast<double>(e.nx) * e.ny * std::max(1, e.nz / 2);
  s.steps_per_life = physics.duration / std::max(dt, 1e-12);
  s.seconds_per_evaluation = s.voxels_per_body * s.steps_per_life / s.voxel_steps_per_second;
  return s;
}

CostEstimate estimate_cost(const ExperimentConfig& config, const SpeedSample& speed) {
  CostEstimate c;
  c.speed = speed;
  c.evolution_evaluations = config.runs() * config.lives_per_run();
  c.analysis_evaluations =
      static_cast<int64_t>(config.runs()) * config.analysis.lives_per_champion();
  c.battery_evaluations = static_cast<int64_t>(config.runs()) * config.analysis.battery_lives;
  c.battery_core_seconds =
      static_cast<double>(c.battery_evaluations) * speed.seconds_per_evaluation;
  const double evals = static_cast<double>(c.evolution_evaluations + c.analysis_evaluations);
  const double core_seconds = evals * speed.seconds_per_evaluation;
  c.core_hours = core_seconds / 3600.0;
  return c;
}

BodySample sample_bodies(const ExperimentConfig& config, const SpeedSample& speed, int count) {
  BodySample s;
  const SampleLattice lattice = sample_lattice(config);
  int64_t draws = 0;
  const double cpu0 = thread_cpu_seconds();
  for (int k = 0; k < count; ++k) {
    const Treatment t = config.treatments[static_cast<size_t>(k) % config.treatments.size()];
    const evo::EvolveConfig run = config.run_config(t, 1);
    evo::ExpressionDef def = run.expression();
    def.nx = lattice.nx, def.ny = lattice.ny, def.nz = lattice.nz;
    const evo::Expresser expresser(def);
    evo::Rng rng = evo::Rng::stream(1, evo::StreamPurpose::kNewcomer, 0, static_cast<uint64_t>(k));
    const evo::Offspring o = evo::random_individual(expresser, rng, run.max_mutation_tries);
    draws += o.tries;
    if (!o.phenotype.valid) continue;  // not simulated by evolution either
    Job j;
    j.voxels = o.phenotype.voxels * lattice.scale;
    j.steps = evo::expected_steps(o.phenotype, run.physics);
    s.bodies.push_back(j);
  }
  s.sites_evaluated = draws * lattice.sites();
  s.seconds_per_expression = lattice.scale * (thread_cpu_seconds() - cpu0) /
                             static_cast<double>(std::max<int64_t>(draws, 1));
  return repriced(std::move(s), speed.voxel_steps_per_second);
}

BodySample repriced(BodySample sample, double voxel_steps_per_second) {
  for (Job& j : sample.bodies)
    j.seconds = j.voxels * j.steps / std::max(voxel_steps_per_second, 1e-9);
  sample.voxel_steps_per_second = voxel_steps_per_second;
  return sample;
}

std::string CostEstimate::summary() const {
  char buf[768];
  // The same count at the probe's slowest and fastest round: core-hours scale with 1 / speed.
  const double v = speed.voxel_steps_per_second;
  const double lo = speed.voxel_steps_high > 0 ? core_hours * v / speed.voxel_steps_high : 0;
  const double hi = speed.voxel_steps_low > 0 ? core_hours * v / speed.voxel_steps_low : 0;
  std::snprintf(buf, sizeof buf,
                "estimate: %lld evolution + %lld analysis simulations of ~%.0f voxels x %.0f "
                "steps; measured %.2f M voxel-steps/s per core (median of %d rounds, %.2f to "
                "%.2f) = %.2f s per life\n"
                "estimate: %.3g core-hours of simulation at that body's cost (%.3g to %.3g)",
                static_cast<long long>(evolution_evaluations),
                static_cast<long long>(analysis_evaluations), speed.voxels_per_body,
                speed.steps_per_life, v / 1e6, speed.rounds, speed.voxel_steps_low / 1e6,
                speed.voxel_steps_high / 1e6, speed.seconds_per_evaluation, core_hours, lo, hi);
  std::string out = buf;
  if (battery_evaluations > 0) {
    std::snprintf(buf, sizeof buf,
                  "\nestimate: of the analysis, the robustness battery: %lld lives, %.3g "
                  "core-seconds at that body's cost",
                  static_cast<long long>(battery_evaluations), battery_core_seconds);
    out += buf;
  }
  return out;
}

}  // namespace plastivox::experiment
