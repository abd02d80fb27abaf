// The one parallel loop. Items are claimed dynamically, so which thread runs which item
// varies; callers keep results independent of that by writing item i's result to slot i only.
#pragma once

#include <cstddef>
#include <functional>

namespace plastivox {

// Number of hardware threads (at least 1).
int hardware_threads();

// Calls fn(i) for every i in [0, n) on up to `threads` threads, the caller's included
// (0: hardware_threads(); 1: serially, in order). If calls throw, the exception of the
// lowest index is rethrown once all threads have stopped: the same error on any thread
// count. Items above an index that has thrown are skipped; every item below it runs.
void parallel_for(size_t n, int threads, const std::function<void(size_t)>& fn);

}  // namespace plastivox
