// The analysis's only source of randomness: a pinned generator (xoshiro256**, seeded through
// SplitMix64) with our own integer and real draws, so a bootstrap or a robustness draw gives
// the same bits on every standard library and platform.
//
// Why not <random>: the standard pins its engines' output but not its distributions
// (std::uniform_int_distribution and friends differ between libstdc++, libc++ and MSVC),
// and a published p-value or robustness figure must be reproducible from its seed alone.
//
// Streams: work that may run on any thread (one robustness draw, one bootstrap trial) takes
// its own generator from stream(seed, purpose, index), never a shared one, so results do not
// depend on the number of threads or on scheduling.
#pragma once

#include <array>
#include <cstdint>

#include "plastivox/base/rng.hpp"

namespace plastivox::analysis {

// What a stream is for; part of its key so two purposes never share numbers.
enum class StreamPurpose : uint64_t {
  kBootstrapTest = 1,  // resampling for a two-sample hypothesis test
  kBootstrapCi = 2,    // resampling for a confidence interval
  kRobustness = 3,     // random stiffness fields for the robustness test
  kTest = 99,          // reserved for tests
};

// xoshiro256** (Blackman & Vigna): 256-bit state, period 2^256 - 1. Not thread-safe: one per
// task.
class Rng {
 public:
  // The state is filled from SplitMix64 started at seed (any seed is fine, including 0).
  explicit Rng(uint64_t seed);

  // The generator for item `index` of a purpose under a user seed; same key, same numbers.
  static Rng stream(uint64_t seed, StreamPurpose purpose, uint64_t index);

  uint64_t next_u64();                   // uniform over all 2^64 values
  uint64_t below(uint64_t n);            // uniform in [0, n), unbiased; n must be > 0
  double uniform();                      // uniform in [0, 1), 53 random bits
  double uniform(double lo, double hi);  // lo + (hi - lo) * uniform(); lo when lo == hi

 private:
  std::array<uint64_t, 4> s_;
};

// SplitMix64's mixer, the base layer's (also used to derive stream keys).
using plastivox::mix64;

}  // namespace plastivox::analysis
