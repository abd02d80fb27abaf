// Internal: run body(i) for i in [0, n) on up to `threads` std::threads (0 = hardware count).
// Items are handed out through an atomic counter, so which thread runs which item varies; the
// callers make results independent of that by writing item i's result to slot i only, and by
// never sharing mutable state between items. The first exception thrown by a body is
// rethrown on the calling thread after all threads have stopped.
#pragma once

#include <algorithm>
#include <atomic>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace plastivox::analysis::detail {

inline int resolve_threads(int threads) {
  if (threads > 0) return threads;
  const unsigned hw = std::thread::hardware_concurrency();
  return hw > 0 ? static_cast<int>(hw) : 1;
}

template <class Body>
void parallel_for(int n, int threads, Body&& body) {
  const int workers = std::min(resolve_threads(threads), std::max(n, 1));
  std::atomic<int> next{0};
  std::exception_ptr error;
  std::mutex error_mutex;
  auto work = [&] {
    for (int i = next.fetch_add(1); i < n; i = next.fetch_add(1)) {
      try {
        body(i);
      } catch (...) {
        std::lock_guard<std::mutex> lock(error_mutex);
        if (!error) error = std::current_exception();
        next.store(n);  // stop handing out work
      }
    }
  };
  if (workers <= 1) {
    work();
  } else {
    std::vector<std::thread> pool;
    for (int w = 0; w < workers - 1; ++w) pool.emplace_back(work);
    work();
    for (std::thread& t : pool) t.join();
  }
  if (error) std::rethrow_exception(error);
}

}  // namespace plastivox::analysis::detail
