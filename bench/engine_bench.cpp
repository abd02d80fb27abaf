// Engine throughput in voxel-steps per second (one voxel advanced by one time step).
//
// Every case first simulates past settling (0.25 s) outside the timed region, so the
// timed steps include actuation and, under a developing treatment, development and the
// per-step time-step update.
#include <memory>
#include <thread>
#include <vector>

#include <benchmark/benchmark.h>

#include "plastivox/demo_robots.hpp"
#include "plastivox/simd.hpp"
#include "plastivox/simulator.hpp"

namespace plastivox {
namespace {

constexpr int kStepsPerIteration = 200;

// Steps a settled simulation; a life that reaches 5.2 s (the evaluation's length) starts
// again, outside the timed region, so a long measurement times lives rather than whatever a
// body does long after its evaluation would have ended.
void run_steps(benchmark::State& bs, const Model& m) {
  auto settled = [&m] {
    auto sim = std::make_unique<Simulator>(m);
    while (sim->state().time < 0.25) sim->step();
    return sim;
  };
  std::unique_ptr<Simulator> sim = settled();
  for (auto _ : bs) {
    if (sim->state().time > 5.2) {
      bs.PauseTiming();
      sim = settled();
      bs.ResumeTiming();
    }
    for (int k = 0; k < kStepsPerIteration; ++k) sim->step();
    if (sim->state().status != SimStatus::kRunning) bs.SkipWithError(sim->state().failure.c_str());
  }
  bs.counters["voxels"] = m.n;
  bs.counters["voxel_steps/s"] = benchmark::Counter(static_cast<double>(m.n) * kStepsPerIteration,
                                                    benchmark::Counter::kIsIterationInvariantRate);
}

PhysicsDef physics(Treatment t) {
  PhysicsDef d = preset_gecco2018_code();
  d.treatment = t;
  d.duration = 1e4;  // never the limit here
  return d;
}

// The canonical scenario: the built-in 512-voxel walker (mixed stiffness 7e9..1e10 Pa), under
// every treatment in the enum's order: 0 none, 1 stress, 2 pressure (the paper's), 3 strain,
// 4 strain_energy, 5 contact, 6 kinetic (physics_def.hpp).
void BM_DemoWalker(benchmark::State& bs) {
  const Model m = compile(demo_walker(), physics(static_cast<Treatment>(bs.range(0))));
  run_steps(bs, m);
}
BENCHMARK(BM_DemoWalker)->DenseRange(0, 6)->ArgName("treatment")->Unit(benchmark::kMillisecond);

// A ~500-voxel irregular body, stiffness 1e5..1e11 Pa, stress development.
void BM_Irregular500Stress(benchmark::State& bs) {
  const Model m = compile(demo_irregular(500, 7), physics(Treatment::kStress));
  run_steps(bs, m);
}
BENCHMARK(BM_Irregular500Stress)->Unit(benchmark::kMillisecond);

// The demo walker (stress) with the bond kernel limited to one instruction set: 0 scalar,
// 1 AVX2, 2 AVX-512 (the other cases use the widest the CPU has; results are identical).
void BM_SimdLevel(benchmark::State& bs) {
  const auto level = static_cast<SimdLevel>(bs.range(0));
  const SimdLevel best = best_simd_level();
  if (level > best) {
    bs.SkipWithError("instruction set not available on this CPU or build");
    return;
  }
  set_simd_level(level);
  const Model m = compile(demo_walker(), physics(Treatment::kStress));
  run_steps(bs, m);
  set_simd_level(best);
}
BENCHMARK(BM_SimdLevel)->DenseRange(0, 2)->ArgName("simd")->Unit(benchmark::kMillisecond);

// Scaling with voxel count: full cubes of 5^3 = 125 up to 10^3 = 1000 voxels.
void BM_CubeScaling(benchmark::State& bs) {
  // 1e11 Pa: stiff enough that the cube stands, so only the voxel count changes.
  const Model m =
      compile(demo_cube(static_cast<int>(bs.range(0)), 1e11), physics(Treatment::kNone));
  run_steps(bs, m);
}
BENCHMARK(BM_CubeScaling)->DenseRange(5, 10)->ArgName("edge")->Unit(benchmark::kMillisecond);

// Thread scaling: N independent simulations of the demo walker on N threads (how the
// evolver uses cores). The rate counts the voxel-steps of all threads together.
void BM_ThreadScaling(benchmark::State& bs) {
  const int threads = static_cast<int>(bs.range(0));
  const Model m = compile(demo_walker(), physics(Treatment::kStress));
  std::vector<Simulator> sims;
  for (int t = 0; t < threads; ++t) {
    sims.emplace_back(m);
    while (sims.back().state().time < 0.25) sims.back().step();
  }
  for (auto _ : bs) {
    std::vector<std::thread> pool;
    for (int t = 0; t < threads; ++t)
      pool.emplace_back([&, t] {
        for (int k = 0; k < 4 * kStepsPerIteration; ++k) sims[t].step();
      });
    for (auto& th : pool) th.join();
  }
  bs.counters["voxel_steps/s"] =
      benchmark::Counter(static_cast<double>(m.n) * 4 * kStepsPerIteration * threads,
                         benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_ThreadScaling)
    ->Arg(1)
    ->Arg(2)
    ->ArgName("threads")
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);

// The development stage alone, per voxel-step, under each developing treatment (1..6 as in
// BM_DemoWalker): the stage timings of Simulator::step around it, so the stimulus's own cost
// shows apart from the rest of the step.
// Steps a settled simulation of m, timing each stage (StageTimings).
StageTimings run_timed_steps(benchmark::State& bs, const Model& m) {
  Simulator sim(m);
  while (sim.state().time < 0.25) sim.step();
  StageTimings t;
  for (auto _ : bs) {
    for (int k = 0; k < kStepsPerIteration; ++k) sim.step(&t);
    if (sim.state().status != SimStatus::kRunning) bs.SkipWithError(sim.state().failure.c_str());
  }
  return t;
}

void BM_DevelopStage(benchmark::State& bs) {
  const Model m = compile(demo_walker(), physics(static_cast<Treatment>(bs.range(0))));
  const StageTimings t = run_timed_steps(bs, m);
  bs.counters["develop_ns/voxel_step"] =
      1e9 * t.develop / (static_cast<double>(t.steps) * static_cast<double>(m.n));
  bs.counters["develop_share"] = t.develop / t.total();
}
BENCHMARK(BM_DevelopStage)->DenseRange(1, 6)->ArgName("treatment")->Unit(benchmark::kMillisecond);

// Cubes of 5^3 = 125 up to 20^3 = 8000 voxels (the bond arrays, about 200 bytes a bond,
// outgrow a 1 MiB L2 near a 12^3 cube), per stage: the bond stage per bond, the gather and
// update per voxel, so the cost of each unit of work shows apart from the bonds per voxel
// (2.4 to 2.85) and self-collision. The stage timers are wall clock; voxel_steps/s is CPU time.
void BM_CubeStages(benchmark::State& bs) {
  const Model m =
      compile(demo_cube(static_cast<int>(bs.range(0)), 1e11), physics(Treatment::kNone));
  const StageTimings t = run_timed_steps(bs, m);
  const double steps = static_cast<double>(t.steps);
  bs.counters["bonds"] = m.bond_count();
  bs.counters["bond_ns/bond"] = 1e9 * t.bond_forces / (steps * m.bond_count());
  bs.counters["gather_ns/voxel"] = 1e9 * t.voxel_forces / (steps * m.n);
  bs.counters["update_ns/voxel"] = 1e9 * t.integrate / (steps * m.n);
  bs.counters["step_ns/voxel"] = 1e9 * t.total() / (steps * m.n);
  bs.counters["voxel_steps/s"] = benchmark::Counter(static_cast<double>(m.n) * kStepsPerIteration,
                                                    benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_CubeStages)
    ->Arg(5)
    ->Arg(8)
    ->Arg(10)
    ->Arg(13)
    ->Arg(16)
    ->Arg(20)
    ->ArgName("edge")
    ->Unit(benchmark::kMillisecond);

// Contact with an environment (docs/environments.md), per voxel-step: the integrate stage
// (contacts, friction and the update) and the whole step of the demo walker (stress) on
// 0 the flat floor (the batched floor kernel), 1 a flat ground at 0 (the scalar terrain path,
// same bits), 2 a rough ground (5 mm, 1 cm cells, 64 x 64 nodes), 3 the flat ground with 16
// boxes of 1 cm (a 4 x 4 grid every 4 cm under and around the body; some touch it),
// 4 the rough ground with those boxes, 5 the rough ground with 256 boxes (16 x 16 every 2 cm).
void BM_TerrainContact(benchmark::State& bs) {
  PhysicsDef d = physics(Treatment::kStress);
  Environment& env = d.environment;
  const int which = static_cast<int>(bs.range(0));
  if (which >= 1) env.ground.kind = GroundKind::kFlat;
  if (which == 2 || which >= 4) {
    env.ground.kind = GroundKind::kRough;
    env.ground.amplitude = 0.005, env.ground.cell = 0.01, env.ground.nx = 64, env.ground.ny = 64;
    env.ground.origin = {-0.2, -0.2};
    env.ground.seed = 1;
  }
  const int grid = which == 5 ? 16 : which >= 3 ? 4 : 0;
  const double pitch = which == 5 ? 0.02 : 0.04;
  for (int i = 0; i < grid; ++i)
    for (int j = 0; j < grid; ++j) {
      const double x = -0.04 + i * pitch, y = -0.04 + j * pitch;
      env.obstacles.push_back({{x, y, -0.01}, {x + 0.01, y + 0.01, 0.002}});
    }
  const Model m = compile(demo_walker(), d);
  const StageTimings t = run_timed_steps(bs, m);
  const double voxel_steps = static_cast<double>(t.steps) * static_cast<double>(m.n);
  bs.counters["integrate_ns/voxel_step"] = 1e9 * t.integrate / voxel_steps;
  bs.counters["step_ns/voxel_step"] = 1e9 * t.total() / voxel_steps;
}
BENCHMARK(BM_TerrainContact)->DenseRange(0, 5)->ArgName("env")->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace plastivox

BENCHMARK_MAIN();
