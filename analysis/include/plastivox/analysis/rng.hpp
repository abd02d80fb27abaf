// The analysis's randomness: the base layer's pinned generator (plastivox/base/rng.hpp), the
// same one the evolver uses, keyed per task by (user seed, purpose, index, 0).
//
// Streams: work that may run on any thread (one robustness draw, one bootstrap trial) takes
// its own generator from Rng::stream(seed, purpose, index, 0), never a shared one, so results
// do not depend on the number of threads or on scheduling.
#pragma once

#include <cstdint>

#include "plastivox/base/rng.hpp"

namespace plastivox::analysis {

using plastivox::mix64;
using plastivox::Rng;

// What a stream is for; part of its key so two purposes never share numbers.
enum class StreamPurpose : uint64_t {
  kBootstrapTest = 1,  // resampling for a two-sample hypothesis test
  kBootstrapCi = 2,    // resampling for a confidence interval
  kRobustness = 3,     // random stiffness fields for the robustness test
  kBattery = 4,        // the robustness battery's perturbations (battery.hpp)
  kTest = 99,          // reserved for tests
};

}  // namespace plastivox::analysis
