// Pinned randomness: SplitMix64 and its mixer with our own distributions, so a seed gives
// the same numbers on every standard library and platform.
//
// Why not <random>: the standard fixes its engines' output but not its distributions
// (std::uniform_int_distribution, std::normal_distribution differ between libstdc++, libc++
// and MSVC). Here every draw is integer arithmetic, except normal(), whose only library
// call is std::log (glibc's log is correctly rounded in practice; see docs/evolution.md).
//
// Streams: a random decision draws from a stream keyed by what it is for, never from a
// shared generator, so results do not depend on threads or order, and a resumed run needs
// no saved generator state. The evolver keys by (seed, purpose, generation, id), the analysis
// by (seed, purpose, index, 0); the demo bodies seed one directly. It is the project's only
// generator: evolution digests and analysis results depend on its exact numbers.
#pragma once

#include <cstdint>

namespace plastivox {

// SplitMix64's output function: a bijective 64-bit mixer.
uint64_t mix64(uint64_t x);

// A SplitMix64 generator (state: one 64-bit word, period 2^64). Not thread-safe: one per task.
class Rng {
 public:
  explicit Rng(uint64_t state) : state_(state) {}

  // The stream keyed by (seed, purpose, a, b); same key, same numbers. `purpose` is an
  // enum (or integer) naming what the numbers are for, so two purposes never share them.
  template <class Purpose>
  static Rng stream(uint64_t seed, Purpose purpose, uint64_t a, uint64_t b) {
    return keyed(seed, static_cast<uint64_t>(purpose), a, b);
  }

  uint64_t next_u64();                   // uniform over all 2^64 values
  double uniform();                      // uniform in [0, 1), 53 random bits
  double uniform(double lo, double hi);  // uniform in [lo, hi)
  uint64_t below(uint64_t n);            // uniform in [0, n), unbiased; n must be > 0
  int index(int n);                      // uniform in [0, n); n must be > 0
  bool coin(double p);                   // true with probability p
  double normal();                       // standard normal (Marsaglia's polar method)

  uint64_t state() const { return state_; }

 private:
  static Rng keyed(uint64_t seed, uint64_t purpose, uint64_t a, uint64_t b);
  uint64_t state_;
};

}  // namespace plastivox
