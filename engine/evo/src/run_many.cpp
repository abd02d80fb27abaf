// Several evolutions at once over one evaluation pool: a driver thread per run.
#include <chrono>
#include <condition_variable>
#include <exception>
#include <mutex>
#include <thread>

#include "plastivox/base/parallel.hpp"
#include "plastivox/evo/eval_pool.hpp"
#include "plastivox/evo/run.hpp"

namespace plastivox::evo {

std::vector<RunReport> run_evolutions(const std::vector<RunSpec>& runs, const ManyRunOptions& opt) {
  if (runs.empty()) return {};
  const int threads = opt.threads >= 0 ? opt.threads : runs.front().config.threads;
  if (opt.cluster && opt.cluster->rank() != 0) {
    opt.cluster->work(threads > 0 ? threads : hardware_threads());
    return {};
  }
  EvaluationPool pool(threads);
  std::vector<RunReport> reports(runs.size());
  std::vector<std::exception_ptr> errors(runs.size());
  std::atomic<bool> halt{false};  // every run stops after its generation in flight
  std::mutex talk;                // one callback at a time
  std::mutex finished_mutex;
  std::condition_variable finished_cv;
  size_t finished = 0;

  auto drive = [&](size_t r) {
    RunOptions ro;
    ro.threads = pool.threads();  // provenance; the pool does the simulating
    ro.simulations = &pool;
    ro.stop_requested = &halt;
    ro.on_generation = [&, r](const RunProgress& p) {
      std::lock_guard<std::mutex> lock(talk);
      if (opt.on_generation) opt.on_generation(r, p);
    };
    ro.on_message = [&, r](const std::string& m) {
      std::lock_guard<std::mutex> lock(talk);
      if (opt.on_message) opt.on_message(r, m);
    };
    try {
      reports[r] = run_evolution(runs[r].config, runs[r].out_path, ro);
    } catch (...) {
      errors[r] = std::current_exception();
      halt = true;
    }
    std::lock_guard<std::mutex> lock(finished_mutex);
    ++finished;
    finished_cv.notify_all();
  };
  std::vector<std::thread> drivers;
  drivers.reserve(runs.size());
  for (size_t r = 0; r < runs.size(); ++r) drivers.emplace_back(drive, r);

  // Forward a stop request (set by a signal handler, so polled) to every run; under MPI
  // serve the other ranks meanwhile.
  auto all_finished = [&] {
    if (opt.stop_requested && opt.stop_requested->load()) halt = true;
    std::lock_guard<std::mutex> lock(finished_mutex);
    return finished == runs.size();
  };
  if (opt.cluster && opt.cluster->size() > 1) {
    opt.cluster->serve(pool, all_finished);
  } else {
    std::unique_lock<std::mutex> lock(finished_mutex);
    while (finished < runs.size()) {
      finished_cv.wait_for(lock, std::chrono::milliseconds(50));
      if (opt.stop_requested && opt.stop_requested->load()) halt = true;
    }
  }
  for (std::thread& d : drivers) d.join();
  for (const std::exception_ptr& e : errors)
    if (e) std::rethrow_exception(e);
  return reports;
}

}  // namespace plastivox::evo
