#include "plastivox/base/parallel.hpp"

#include <algorithm>
#include <atomic>
#include <exception>
#include <thread>
#include <vector>

namespace plastivox {

int hardware_threads() {
  return static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
}

void parallel_for(size_t n, int threads, const std::function<void(size_t)>& fn) {
  std::vector<std::exception_ptr> errors(n);
  std::atomic<size_t> next{0};
  std::atomic<size_t> first_error{n};  // lowest index that has thrown so far
  auto worker = [&] {
    for (size_t i = next.fetch_add(1); i < n; i = next.fetch_add(1)) {
      if (i > first_error.load()) continue;  // cannot be the lowest failure any more
      try {
        fn(i);
      } catch (...) {
        errors[i] = std::current_exception();
        size_t seen = first_error.load();
        while (i < seen && !first_error.compare_exchange_weak(seen, i)) {
        }
      }
    }
  };
  const int wanted = threads > 0 ? threads : hardware_threads();
  const size_t helpers = std::min<size_t>(static_cast<size_t>(wanted - 1), n > 0 ? n - 1 : 0);
  std::vector<std::thread> pool;
  pool.reserve(helpers);
  for (size_t t = 0; t < helpers; ++t) pool.emplace_back(worker);
  worker();
  for (std::thread& t : pool) t.join();
  if (first_error.load() < n) std::rethrow_exception(errors[first_error.load()]);
}

}  // namespace plastivox
