#include "plastivox/analysis/rng.hpp"

#include <cassert>

namespace plastivox::analysis {

namespace {
constexpr uint64_t kGolden = 0x9e3779b97f4a7c15ULL;  // SplitMix64's increment
inline uint64_t rotl(uint64_t x, int k) {
  return (x << k) | (x >> (64 - k));
}
}  // namespace

Rng::Rng(uint64_t seed) {
  // SplitMix64 never yields four zero words in a row, so the state is never all zero
  // (the one state xoshiro cannot leave).
  for (uint64_t& w : s_) {
    seed += kGolden;
    w = mix64(seed);
  }
}

Rng Rng::stream(uint64_t seed, StreamPurpose purpose, uint64_t index) {
  // Chained mixing: every key component changes every bit of the result.
  uint64_t k = mix64(seed + kGolden);
  k = mix64(k ^ (static_cast<uint64_t>(purpose) * kGolden));
  k = mix64(k ^ (index + 1) * 0xd1342543de82ef95ULL);
  return Rng(k);
}

uint64_t Rng::next_u64() {
  const uint64_t result = rotl(s_[1] * 5, 7) * 9;
  const uint64_t t = s_[1] << 17;
  s_[2] ^= s_[0];
  s_[3] ^= s_[1];
  s_[1] ^= s_[2];
  s_[0] ^= s_[3];
  s_[2] ^= t;
  s_[3] = rotl(s_[3], 45);
  return result;
}

uint64_t Rng::below(uint64_t n) {
  assert(n > 0 && "Rng::below needs n > 0");
  // Lemire's multiply-and-reject: the high word of x*n is uniform in [0, n) once the low
  // word's biased zone (the first 2^64 mod n values) is rejected.
  unsigned __int128 m = static_cast<unsigned __int128>(next_u64()) * n;
  uint64_t low = static_cast<uint64_t>(m);
  if (low < n) {
    const uint64_t threshold = (0 - n) % n;  // 2^64 mod n
    while (low < threshold) {
      m = static_cast<unsigned __int128>(next_u64()) * n;
      low = static_cast<uint64_t>(m);
    }
  }
  return static_cast<uint64_t>(m >> 64);
}

double Rng::uniform() {
  return static_cast<double>(next_u64() >> 11) * 0x1.0p-53;
}

double Rng::uniform(double lo, double hi) {
  return lo == hi ? lo : lo + (hi - lo) * uniform();
}

}  // namespace plastivox::analysis
