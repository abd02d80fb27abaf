// One queue of simulations shared by several evolutions running at once.
//
// Why: a generation holds only P + 1 candidates and ends with a barrier (selection needs
// every result), so one run keeps at most P + 1 cores busy and idles them while its slowest
// candidate finishes. With every run of an experiment advancing at once and feeding one
// queue, a core freed by one run's barrier takes another run's candidate. Each run's
// evolver still calls Simulations::run() with its own generation's batch and blocks until
// that batch is back, so a run moves on as soon as its own candidates are done, never
// waits for another run, and holds at most one generation in flight.
//
// Order: the longest expected simulation first (voxels x expected_steps()), ties by
// submission order. Which worker simulates a body never changes its result
// (evaluate_phenotype is a pure function of body and physics), so every run is
// bit-identical to running it alone, on any number of threads.
#pragma once

#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <queue>
#include <thread>
#include <vector>

#include "plastivox/evo/evolver.hpp"

namespace plastivox::evo {

class EvaluationPool final : public Simulations {
 public:
  explicit EvaluationPool(int threads);  // starts `threads` workers (0 = all cores)
  ~EvaluationPool() override;            // waits for the workers; no run() may be in progress
  EvaluationPool(const EvaluationPool&) = delete;
  EvaluationPool& operator=(const EvaluationPool&) = delete;

  int threads() const { return static_cast<int>(workers_.size()); }

  // Thread-safe: many evolvers call it at once. Queues the batch, blocks until all of it is
  // simulated and returns the results in batch order (`threads` is ignored: the pool's
  // workers serve every caller). A simulation's exception is rethrown here, lowest index
  // first, after the whole batch is done.
  std::vector<Evaluation> run(const std::vector<const Phenotype*>& batch, const PhysicsDef& physics,
                              int threads) override;

  // For helpers outside the pool (other MPI ranks, served by rank 0's main thread): the head
  // of the queue, taken off it, to be simulated elsewhere and handed back with complete().
  struct Claim {
    const Phenotype* body = nullptr;
    const PhysicsDef* physics = nullptr;
    void* batch = nullptr;  // opaque: where complete() puts the result
    size_t index = 0;
  };
  bool try_claim(Claim& out);  // false when nothing waits
  void complete(const Claim& claim, Evaluation result);

 private:
  struct Batch;
  struct Job {
    double cost;   // voxels x expected steps
    uint64_t seq;  // submission order
    Batch* batch;
    size_t index;                        // in the batch
    bool operator<(const Job& o) const;  // priority_queue pops the longest, then the earliest
  };
  void work();

  std::mutex mutex_;
  std::condition_variable work_ready_, batch_done_;
  std::priority_queue<Job> queue_;
  uint64_t next_seq_ = 0;
  bool stopping_ = false;
  std::vector<std::thread> workers_;
};

}  // namespace plastivox::evo
