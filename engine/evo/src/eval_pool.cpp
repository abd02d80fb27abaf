#include "plastivox/evo/eval_pool.hpp"

#include <exception>
#include <tuple>

#include "plastivox/base/parallel.hpp"

namespace plastivox::evo {

// One caller's batch: where its results go and how many are still out.
struct EvaluationPool::Batch {
  const std::vector<const Phenotype*>* bodies;
  const PhysicsDef* physics;
  std::vector<Evaluation> results;
  std::vector<std::exception_ptr> errors;
  size_t remaining;
};

bool EvaluationPool::Job::operator<(const Job& o) const {
  return std::tie(cost, o.seq) < std::tie(o.cost, seq);
}

EvaluationPool::EvaluationPool(int threads) {
  const int n = threads > 0 ? threads : hardware_threads();
  workers_.reserve(static_cast<size_t>(n));
  for (int t = 0; t < n; ++t) workers_.emplace_back([this] { work(); });
}

EvaluationPool::~EvaluationPool() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stopping_ = true;
  }
  work_ready_.notify_all();
  for (std::thread& w : workers_) w.join();
}

void EvaluationPool::work() {
  std::unique_lock<std::mutex> lock(mutex_);
  for (;;) {
    work_ready_.wait(lock, [this] { return stopping_ || !queue_.empty(); });
    if (queue_.empty()) return;  // stopping, nothing left
    const Job job = queue_.top();
    queue_.pop();
    lock.unlock();
    Batch& b = *job.batch;
    Evaluation e;
    std::exception_ptr error;
    try {
      e = evaluate_phenotype(*(*b.bodies)[job.index], *b.physics);
    } catch (...) {
      error = std::current_exception();
    }
    lock.lock();
    b.results[job.index] = std::move(e);
    b.errors[job.index] = error;
    if (--b.remaining == 0) batch_done_.notify_all();
  }
}

bool EvaluationPool::try_claim(Claim& out) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (queue_.empty()) return false;
  const Job job = queue_.top();
  queue_.pop();
  out = {(*job.batch->bodies)[job.index], job.batch->physics, job.batch, job.index};
  return true;
}

void EvaluationPool::complete(const Claim& claim, Evaluation result) {
  std::lock_guard<std::mutex> lock(mutex_);
  Batch& b = *static_cast<Batch*>(claim.batch);
  b.results[claim.index] = std::move(result);
  if (--b.remaining == 0) batch_done_.notify_all();
}

std::vector<Evaluation> EvaluationPool::run(const std::vector<const Phenotype*>& batch,
                                            const PhysicsDef& physics, int /*threads*/) {
  Batch b{&batch, &physics, std::vector<Evaluation>(batch.size()),
          std::vector<std::exception_ptr>(batch.size()), batch.size()};
  if (batch.empty()) return {};
  {
    std::lock_guard<std::mutex> lock(mutex_);
    for (size_t i = 0; i < batch.size(); ++i)
      queue_.push({batch[i]->voxels * expected_steps(*batch[i], physics), next_seq_++, &b, i});
  }
  work_ready_.notify_all();
  {
    std::unique_lock<std::mutex> lock(mutex_);
    batch_done_.wait(lock, [&b] { return b.remaining == 0; });
  }
  for (const std::exception_ptr& e : b.errors)
    if (e) std::rethrow_exception(e);
  return std::move(b.results);
}

}  // namespace plastivox::evo
