// The schedule simulator: how long an experiment's evolution takes on N cores, and how busy
// those cores are, replaying the scheduling policy the code really uses.
//
// Why simulate rather than divide: the evolution stage is a chain of barriers. A run cannot
// make generation g + 1 before every candidate of generation g is back, a generation holds
// only P + 1 candidates, and their costs differ (voxels x time steps). Dividing total work
// by cores ignores all of that; replaying the policy on a list of per-candidate costs gives
// the makespan the policy would reach with those costs.
//
// Two policies, as implemented:
//   kRunByRun  today's MPI path (and the code before the evaluation pool): runs one after
//              another; each generation's candidates split over the ranks (largest voxel
//              count first, each to the rank with the fewest voxels so far;
//              mpi_cluster.cpp assign_to_ranks), then each rank's share claimed by its
//              threads in largest-voxels-first order (evolver.cpp simulate_on_threads).
//   kPool      the evaluation pool (evo/eval_pool.hpp): every unfinished run advances at
//              once; all candidates wait in one queue ordered by expected cost (voxels x
//              steps, longest first, ties by submission), any free core takes the head;
//              a run submits its next generation as soon as its own candidates are back.
// Costs and keys are inputs, so tests can give exact synthetic lists.
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

namespace plastivox::experiment {

// One candidate simulation.
struct Job {
  double seconds = 0;  // wall time on one core, s
  double voxels = 0;   // voxel count (kRunByRun's ordering key)
  double steps = 0;    // expected time steps of its life (kPool orders by voxels x steps)
};

enum class Policy { kRunByRun, kPool };

struct Workload {
  int runs = 0;
  int generations = 0;  // generations per run, generation 0 included
  // The candidates of (run, generation), in the order the evolver creates them.
  std::function<std::vector<Job>(int run, int generation)> jobs;
  // Serial work of one run between two generations (making, expressing, selecting,
  // checkpointing), s; it delays that run's next submission but holds no core.
  double seconds_between_generations = 0;
};

struct Layout {
  int ranks = 1;    // MPI ranks (1: one process)
  int threads = 1;  // threads per rank
  int cores() const { return ranks * threads; }
};

struct ScheduleResult {
  double wall_seconds = 0;  // makespan, s
  double busy_seconds = 0;  // sum of job seconds, core-s
  int64_t simulations = 0;  // jobs scheduled
  double utilization = 0;   // busy / (cores x wall), 0-1
};

// Replays `policy` on `workload` over `layout`. Deterministic. Up to `max_replayed`
// candidates are replayed whole; past that, the first generations are replayed and extended (every
// generation after the first few costs the same in expectation) and, when one generation of
// every run is itself too many, a share of the runs is replayed on the same share of the
// cores. The time taken is bounded (well under a second) at any size the configs allow.
ScheduleResult simulate_schedule(const Workload& workload, const Layout& layout, Policy policy,
                                 int64_t max_replayed = 200000);

}  // namespace plastivox::experiment
