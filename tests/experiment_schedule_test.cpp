// The schedule simulator (apps/experiment/schedule.hpp) on cost lists whose makespan is known
// by hand, for both policies, and the estimate's JSON through the real binary.
#include <chrono>
#include <cstdint>
#include <fstream>
#include <iterator>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "experiment/cost_estimate.hpp"
#include "experiment/experiment_config.hpp"
#include "experiment/schedule.hpp"
#include "plastivox/evo/rng.hpp"  // mix64
#include "plastivox/io/atomic_file.hpp"
#include "test_support.hpp"

namespace plastivox::experiment {
namespace {

// Every generation of every run holds `jobs` (the same list each time).
Workload repeat(int runs, int generations, const std::vector<Job>& jobs) {
  Workload w;
  w.runs = runs;
  w.generations = generations;
  w.jobs = [jobs](int, int) { return jobs; };
  return w;
}

Job job(double seconds, double voxels = 1) {
  return Job{seconds, voxels, seconds / voxels};  // voxels x steps = seconds
}

TEST(Schedule, EqualCostsPackPerfectlyInThePoolButNotRunByRun) {
  // 4 runs x 3 generations x 3 candidates of 2 s on 4 cores. The pool keeps all 4 cores
  // busy (72 core-s / 4 = 18 s); run by run each generation takes 2 s on 3 of 4 cores.
  const Workload w = repeat(4, 3, {job(2), job(2), job(2)});
  const ScheduleResult pool = simulate_schedule(w, {1, 4}, Policy::kPool);
  EXPECT_DOUBLE_EQ(pool.wall_seconds, 18);
  EXPECT_DOUBLE_EQ(pool.utilization, 1);
  EXPECT_EQ(pool.simulations, 36);
  const ScheduleResult before = simulate_schedule(w, {1, 4}, Policy::kRunByRun);
  EXPECT_DOUBLE_EQ(before.wall_seconds, 24);
  EXPECT_DOUBLE_EQ(before.utilization, 0.75);
  EXPECT_DOUBLE_EQ(before.busy_seconds, 72);
}

TEST(Schedule, OneHugeCandidateBoundsItsGeneration) {
  // One 10 s body and two 1 s bodies per generation, 2 runs, 1 generation, 3 cores: each
  // run's generation lasts 10 s; the pool overlaps the two runs, run by run does not.
  const Workload w = repeat(2, 1, {job(1), job(10), job(1)});
  EXPECT_DOUBLE_EQ(simulate_schedule(w, {1, 3}, Policy::kPool).wall_seconds, 10);
  EXPECT_DOUBLE_EQ(simulate_schedule(w, {1, 3}, Policy::kRunByRun).wall_seconds, 20);
  // One run on 2 cores: largest first, the 1 s bodies share the other core.
  const Workload one = repeat(1, 1, {job(1), job(1), job(1), job(1), job(1), job(10, 5)});
  const ScheduleResult r = simulate_schedule(one, {1, 2}, Policy::kRunByRun);
  EXPECT_DOUBLE_EQ(r.wall_seconds, 10);
  EXPECT_DOUBLE_EQ(r.utilization, 15.0 / 20.0);
  EXPECT_DOUBLE_EQ(simulate_schedule(one, {1, 2}, Policy::kPool).wall_seconds, 10);
}

TEST(Schedule, MoreCoresThanCandidates) {
  // 5 candidates of 1 s per generation, 3 generations, 16 cores: a generation cannot take
  // less than 1 s. Two runs overlap in the pool (6 s of generations in 3 s).
  const Workload w = repeat(2, 3, std::vector<Job>(5, job(1)));
  const ScheduleResult pool = simulate_schedule(w, {1, 16}, Policy::kPool);
  EXPECT_DOUBLE_EQ(pool.wall_seconds, 3);
  EXPECT_DOUBLE_EQ(pool.utilization, 30.0 / 48.0);
  const ScheduleResult before = simulate_schedule(w, {4, 4}, Policy::kRunByRun);
  EXPECT_DOUBLE_EQ(before.wall_seconds, 6);
  EXPECT_DOUBLE_EQ(before.utilization, 30.0 / 96.0);
}

TEST(Schedule, RunByRunReplaysTheRankSplitByVoxels) {
  // Ranks get bodies by voxel count (assign_to_ranks), which here misjudges the cost: the
  // 10-voxel body is quick, the 1-voxel ones slow. 2 ranks x 1 thread: rank 0 takes the big
  // quick body alone, rank 1 both slow ones (10 s). 1 rank x 2 threads claims dynamically:
  // 1 s + 5 s on one thread, 5 s on the other (6 s). The pool orders by cost: also 6 s.
  const Workload w = repeat(1, 1, {Job{1, 10, 0.1}, Job{5, 1, 5}, Job{5, 1, 5}});
  EXPECT_DOUBLE_EQ(simulate_schedule(w, {2, 1}, Policy::kRunByRun).wall_seconds, 10);
  EXPECT_DOUBLE_EQ(simulate_schedule(w, {1, 2}, Policy::kRunByRun).wall_seconds, 6);
  EXPECT_DOUBLE_EQ(simulate_schedule(w, {1, 2}, Policy::kPool).wall_seconds, 6);
}

TEST(Schedule, SerialWorkBetweenGenerationsDelaysOnlyItsRun) {
  // 1 s of making and selecting before each generation of one 1 s candidate: 2 generations
  // take 4 s run by run; in the pool two runs' serial parts overlap too.
  Workload w = repeat(2, 2, {job(1)});
  w.seconds_between_generations = 1;
  EXPECT_DOUBLE_EQ(simulate_schedule(w, {1, 2}, Policy::kRunByRun).wall_seconds, 8);
  EXPECT_DOUBLE_EQ(simulate_schedule(w, {1, 2}, Policy::kPool).wall_seconds, 4);
}

// The rendering stage's estimate: with nothing drawn, the champions' simulations shared out
// over the threads; drawing on a machine twice as fast takes half the time; more video frames
// cost more, and a second thread draws them faster.
TEST(RenderingEstimate, ChampionsOverThreadsPlusDrawingAtTheMachinesSpeed) {
  ExperimentConfig c;  // 3 treatments x 2 seeds
  c.rendering.figures = c.rendering.galleries = c.rendering.video = false;
  EXPECT_DOUBLE_EQ(rendering_seconds(c, 0.5, 20e6, 1), 6 * 0.5);
  EXPECT_DOUBLE_EQ(rendering_seconds(c, 0.5, 20e6, 2), 6 * 0.5 / 2);
  c.rendering.figures = c.rendering.galleries = c.rendering.video = true;
  const double drawing = rendering_seconds(c, 0.5, 20e6, 1) - 3;
  EXPECT_GT(drawing, 0);
  EXPECT_NEAR(rendering_seconds(c, 0.5, 40e6, 1) - 3, drawing / 2, 1e-9);
  c.rendering.video_fps *= 2;
  EXPECT_GT(rendering_seconds(c, 0.5, 20e6, 1) - 3, drawing);
  EXPECT_LT(rendering_seconds(c, 0.5, 20e6, 2) - 1.5, rendering_seconds(c, 0.5, 20e6, 1) - 3);
}

// Candidates of pseudo-random cost (0.5..2.5 s, 1..100 voxels), the same on every call.
Workload random_costs(int runs, int generations, int per_generation) {
  Workload w;
  w.runs = runs;
  w.generations = generations;
  w.jobs = [per_generation](int run, int gen) {
    std::vector<Job> jobs;
    for (int k = 0; k < per_generation; ++k) {
      const uint64_t h = evo::mix64(evo::mix64(evo::mix64(run) ^ gen) ^ k);
      jobs.push_back(job(0.5 + 2.0 * (h % 1000) / 1000.0, 1 + (h >> 32) % 100));
    }
    return jobs;
  };
  w.seconds_between_generations = 0.05;
  return w;
}

// Past max_replayed candidates the replay is partial and extended; its answer agrees with
// the whole replay to 2 % (wall time) on every shape that scaling touches: many generations,
// many runs per core, few runs on many cores, and both policies.
TEST(Schedule, PartialReplayOfLargeExperimentsAgreesWithTheWholeReplay) {
  struct Case {
    int runs, generations, per_generation;
    Layout layout;
  };
  for (const Case& c :
       {Case{6, 2000, 21, {1, 2}}, Case{6, 2000, 21, {1, 64}}, Case{60, 300, 31, {1, 16}},
        Case{400, 40, 51, {2, 8}}, Case{3, 5000, 101, {1, 4}}})
    for (Policy policy : {Policy::kPool, Policy::kRunByRun}) {
      const Workload w = random_costs(c.runs, c.generations, c.per_generation);
      const ScheduleResult whole = simulate_schedule(w, c.layout, policy, int64_t{1} << 40);
      const ScheduleResult part = simulate_schedule(w, c.layout, policy, 20000);
      SCOPED_TRACE(::testing::Message()
                   << c.runs << " runs x " << c.generations << " x " << c.per_generation << " on "
                   << c.layout.ranks << "x" << c.layout.threads
                   << (policy == Policy::kPool ? " pool" : " run by run"));
      EXPECT_NEAR(part.wall_seconds, whole.wall_seconds, 0.02 * whole.wall_seconds);
      EXPECT_NEAR(part.busy_seconds, whole.busy_seconds, 0.02 * whole.busy_seconds);
      EXPECT_NEAR(part.utilization, whole.utilization, 0.02);
      EXPECT_NEAR(static_cast<double>(part.simulations), static_cast<double>(whole.simulations),
                  0.001 * whole.simulations);
    }
}

// The issue's cases: 10^7 generations took 28 s, population 1,000 x 10^5 generations 78.5 s,
// and the documented maxima about 90 days. Each is now answered at once.
class ScheduleCliHuge : public testing::ScratchDirTest {};

TEST_F(ScheduleCliHuge, EstimatesOfHugeExperimentsAreAnsweredAtOnce) {
  const auto estimate = [&](const std::string& sizes) {
    const std::string cfg = path("c.json");
    write_file_atomic(cfg, R"({"format": "plastivox-experiment-config", "version": 1,
      "name": "huge", "treatments": ["none", "stress", "pressure"], "seeds": [1, 2],
      "evolution": {)" + sizes +
                               R"(, "lattice": {"nx": 4, "ny": 4, "nz": 4, "voxel_size": 0.01},
                    "physics": {"preset": "gecco2018-code", "duration": 0.5}},
      "analysis": {"robustness_draws": 2}})");
    const auto t0 = std::chrono::steady_clock::now();
    const auto o = testing::shell(std::string(PLASTIVOX_CLI) + " experiment --config " + cfg +
                                  " --estimate-only --json 2>/dev/null");
    EXPECT_EQ(o.status, 0) << sizes;
    EXPECT_LT(std::chrono::steady_clock::now() - t0, std::chrono::seconds(10)) << sizes;
    return nlohmann::json::parse(o.out);
  };
  const auto a = estimate(R"("population": 3, "generations": 10000000)");
  EXPECT_NEAR(a.at("simulations").get<double>(), 6.0 * (3 + 1e7 * 4) + 6 * 3, 1e3);
  const auto b = estimate(R"("population": 1000, "generations": 100000)");
  EXPECT_NEAR(b.at("simulations").get<double>(), 6.0 * (1000 + 1e5 * 1001) + 6 * 3, 1e5);
  EXPECT_GT(b.at("wall_seconds").get<double>(), a.at("wall_seconds").get<double>());
  const auto c = estimate(R"("population": 100000, "generations": 100000000)");
  EXPECT_NEAR(c.at("simulations").get<double>() / (6.0 * 1e8 * 100001), 1, 1e-3);
}

// The estimate through the binary: the promised JSON keys, and the simulation count of the
// tiny preset (6 runs x (3 + 2 x 4) evolution + 6 x (1 + 2) analysis simulations).
TEST(ScheduleCli, EstimateOnlyJson) {
  const auto o = testing::shell(std::string(PLASTIVOX_CLI) +
                                " experiment --preset tiny --estimate-only --cores 8 --json");
  ASSERT_EQ(o.status, 0) << o.out;
  const auto j = nlohmann::json::parse(o.out);
  EXPECT_EQ(j.at("cores"), 8);
  EXPECT_EQ(j.at("ranks"), 1);
  EXPECT_EQ(j.at("simulations"), 6 * (3 + 2 * 4) + 6 * 3);
  EXPECT_GT(j.at("utilization").get<double>(), 0);
  EXPECT_LE(j.at("utilization").get<double>(), 1);
  EXPECT_GT(j.at("wall_seconds").get<double>(), 0);
  EXPECT_GT(j.at("rendering_seconds").get<double>(), 0);
  EXPECT_NEAR(j.at("core_hours").get<double>(), 8 * j.at("wall_seconds").get<double>() / 3600,
              1e-12);
  // The spread of the speed probe's rounds (issue 54: three runs read 56.6, 64.0 and 85.7 h).
  const auto wall = j.at("wall_seconds_range"), hours = j.at("core_hours_range");
  EXPECT_LE(wall[0].get<double>(), j.at("wall_seconds").get<double>());
  EXPECT_GE(wall[1].get<double>(), j.at("wall_seconds").get<double>());
  EXPECT_LE(hours[0].get<double>(), j.at("core_hours").get<double>());
  EXPECT_GE(hours[1].get<double>(), j.at("core_hours").get<double>());
  const auto bad = testing::shell(std::string(PLASTIVOX_CLI) +
                                  " experiment --preset tiny --estimate-only --cores 6 "
                                  "--ranks 4 2>&1");
  EXPECT_EQ(bad.status, 2);
  EXPECT_NE(bad.out.find("--cores 6 must be a multiple of --ranks 4"), std::string::npos)
      << bad.out;
  EXPECT_EQ(testing::shell(std::string(PLASTIVOX_CLI) +
                           " experiment --preset tiny --cores 4 --out x 2>&1")
                .status,
            2);
}

// The speed probe measures rounds and reports their median and spread, not one short run.
TEST(ScheduleSpeed, ProbeReportsTheMedianOfItsRounds) {
  const ExperimentConfig c = preset_config("tiny");
  const SpeedSample s = measure_speed(c, 0.05, 3);
  EXPECT_EQ(s.rounds, 3);
  EXPECT_GT(s.voxel_steps_low, 0);
  EXPECT_LE(s.voxel_steps_low, s.voxel_steps_per_second);
  EXPECT_LE(s.voxel_steps_per_second, s.voxel_steps_high);
  // A repriced sample is the same bodies at another speed.
  const BodySample b = sample_bodies(c, s, 6);
  ASSERT_FALSE(b.bodies.empty());
  const BodySample slow = repriced(b, s.voxel_steps_per_second / 2);
  EXPECT_DOUBLE_EQ(slow.bodies[0].seconds, 2 * b.bodies[0].seconds);
  EXPECT_EQ(slow.bodies[0].voxels, b.bodies[0].voxels);
}

// Issue 54: the estimate of a 100^3 lattice took 314 s, silent for 120 s: 96 random genomes
// expressed over 10^6 sites on one thread, and a 500 000-voxel calibration body. Both are now
// made on a lattice of the same shape of at most kSampleSites sites and scaled up, so the work
// is bounded at any size a config allows (before: 96 x 10^6 sites at least).
class ScheduleLargeLattice : public testing::ScratchDirTest {};

TEST_F(ScheduleLargeLattice, EstimateOfTheLargestLatticeWorksOnASampleOfIt) {
  const auto config_text = [](int nx, int ny, int nz) {
    return R"({"format": "plastivox-experiment-config", "version": 1, "name": "large",
      "treatments": ["none", "stress"], "seeds": [1],
      "evolution": {"population": 4, "generations": 2,
                    "lattice": {"nx": )" +
           std::to_string(nx) + R"(, "ny": )" + std::to_string(ny) + R"(, "nz": )" +
           std::to_string(nz) + R"(, "voxel_size": 0.01},
                    "physics": {"preset": "gecco2018-code", "duration": 0.5}}})";
  };
  const ExperimentConfig big = parse_experiment_config(config_text(100, 100, 100), "big");
  const SampleLattice l = sample_lattice(big);
  EXPECT_EQ(l.nx, 10);
  EXPECT_EQ(l.ny, 10);
  EXPECT_EQ(l.nz, 10);
  EXPECT_DOUBLE_EQ(l.scale, 1000);
  const SpeedSample s = measure_speed(big, 0.05, 1);
  EXPECT_EQ(s.voxels_simulated, 500);    // the sample lattice's lower half
  EXPECT_EQ(s.voxels_per_body, 500000);  // the whole lattice's
  const BodySample b = sample_bodies(big, s, 12);
  EXPECT_GT(b.sites_evaluated, 0);
  EXPECT_LT(b.sites_evaluated, 1000000);  // less than one expression of the whole lattice
  ASSERT_FALSE(b.bodies.empty());
  for (const Job& j : b.bodies) {  // whole-lattice bodies: at least min_fill of 10^6 sites
    EXPECT_GE(j.voxels, 0.2 * 1e6);
    EXPECT_LE(j.voxels, 1e6);
  }
  // Flat and thin lattices keep their shape; extents of 1 and 2 stay.
  const SampleLattice flat = sample_lattice(parse_experiment_config(config_text(100, 100, 2), "f"));
  EXPECT_EQ(flat.nz, 2);
  EXPECT_LE(flat.sites(), kSampleSites);
  EXPECT_EQ(flat.nx, flat.ny);
  EXPECT_GE(flat.nx, 20);
  EXPECT_DOUBLE_EQ(flat.scale, 20000.0 / flat.sites());
  // The paper's lattice is not sampled: its estimate is as before.
  const SampleLattice paper = sample_lattice(preset_config("gecco2018"));
  EXPECT_EQ(paper.sites(), 1000);
  EXPECT_DOUBLE_EQ(paper.scale, 1);

  // Through the binary: it answers, says it sampled, and prints the estimate.
  const std::string cfg = path("big.json");
  write_file_atomic(cfg, config_text(100, 100, 100));
  const auto o = testing::shell(std::string(PLASTIVOX_CLI) + " experiment --config " + cfg +
                                " --estimate-only --json 2>" + path("err.txt"));
  ASSERT_EQ(o.status, 0) << o.out;
  EXPECT_EQ(nlohmann::json::parse(o.out).at("simulations"), 2 * (4 + 2 * 5) + 2 * (1 + 10));
  std::ifstream in(path("err.txt"));
  const std::string err((std::istreambuf_iterator<char>(in)), {});
  EXPECT_NE(err.find("estimate: bodies drawn and calibrated on a 10x10x10 lattice of the same "
                     "shape, voxels scaled up 1000x"),
            std::string::npos)
      << err;
  EXPECT_NE(err.find("core-hours of simulation"), std::string::npos) << err;
}

}  // namespace
}  // namespace plastivox::experiment
