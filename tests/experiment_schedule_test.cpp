// The schedule simulator (apps/experiment/schedule.hpp) on cost lists whose makespan is known
// by hand, for both policies, and the estimate's JSON through the real binary.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "experiment/cost_estimate.hpp"
#include "experiment/schedule.hpp"
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

}  // namespace
}  // namespace plastivox::experiment
