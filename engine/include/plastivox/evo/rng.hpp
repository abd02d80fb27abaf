// The evolver's only source of randomness: a pinned generator (SplitMix64) with our own
// distributions, so a run gives the same bits on every standard library and platform.
//
// Why not <random>: the standard fixes its engines' output but not its distributions
// (std::uniform_int_distribution, std::normal_distribution differ between libstdc++, libc++
// and MSVC). Here every draw is integer arithmetic, except normal(), whose only library
// call is std::log (glibc's log is correctly rounded in practice; see docs/evolution.md).
//
// Streams: every random decision of a run is drawn from a stream keyed by
// (run seed, purpose, generation, individual id), never from a shared generator. That makes
// the result independent of which thread does the work and in which order, and makes a
// resumed run identical to an uninterrupted one without saving generator state.
#pragma once

#include <cstdint>

namespace plastivox::evo {

// What a stream is for; part of its key so two purposes never share numbers.
enum class StreamPurpose : uint64_t {
  kNewcomer = 1,  // a random individual (initial population or the per-generation newcomer)
  kMutation = 2,  // the mutations that turn a parent into its child
  kTest = 99,     // reserved for tests
};

// SplitMix64's output function: a bijective 64-bit mixer.
uint64_t mix64(uint64_t x);

// A SplitMix64 generator (state: one 64-bit word, period 2^64). Not thread-safe: one per task.
class Rng {
 public:
  explicit Rng(uint64_t state) : state_(state) {}

  // The stream for one decision of a run; same key, same numbers.
  static Rng stream(uint64_t seed, StreamPurpose purpose, uint64_t generation, uint64_t id);

  uint64_t next_u64();                   // uniform over all 2^64 values
  double uniform();                      // uniform in [0, 1), 53 random bits
  double uniform(double lo, double hi);  // uniform in [lo, hi)
  uint64_t below(uint64_t n);            // uniform in [0, n), unbiased; n must be > 0
  int index(int n);                      // uniform in [0, n); n must be > 0
  bool coin(double p);                   // true with probability p
  double normal();                       // standard normal (Marsaglia's polar method)

  uint64_t state() const { return state_; }

 private:
  uint64_t state_;
};

}  // namespace plastivox::evo
