// Parallel loops for evaluation. Work items are claimed dynamically, but every item writes
// only its own result slot, so results never depend on the number of threads or on timing.
#pragma once

#include <cstddef>
#include <functional>

namespace plastivox::evo {

// Number of hardware threads (at least 1).
int hardware_threads();

// Calls fn(i) for every i in [0, n) on up to `threads` threads (the caller's thread
// included; threads <= 1 runs serially in order). If calls throw, the exception of the
// lowest index is rethrown after all threads have stopped.
void parallel_for(size_t n, int threads, const std::function<void(size_t)>& fn);

}  // namespace plastivox::evo
