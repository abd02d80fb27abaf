#include "plastivox/base/rng.hpp"

#include <cassert>
#include <cmath>

namespace plastivox {

namespace {
constexpr uint64_t kGolden = 0x9e3779b97f4a7c15ULL;  // 2^64 / golden ratio, SplitMix64's step
}  // namespace

uint64_t mix64(uint64_t z) {
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

Rng Rng::keyed(uint64_t seed, uint64_t purpose, uint64_t a, uint64_t b) {
  // Chain the key words through the mixer; each step is a bijection of the running value,
  // so distinct keys give unrelated starting states.
  uint64_t s = mix64(seed + kGolden);
  s = mix64(s ^ (purpose + 2 * kGolden));
  s = mix64(s ^ (a + 3 * kGolden));
  s = mix64(s ^ (b + 4 * kGolden));
  return Rng(s);
}

uint64_t Rng::next_u64() {
  state_ += kGolden;
  return mix64(state_);
}

double Rng::uniform() {
  return static_cast<double>(next_u64() >> 11) * 0x1.0p-53;
}

double Rng::uniform(double lo, double hi) {
  return lo + (hi - lo) * uniform();
}

uint64_t Rng::below(uint64_t n) {
  assert(n > 0 && "Rng::below needs a non-empty range");
  // Reject the lowest (2^64 mod n) values so every residue is equally likely.
  const uint64_t threshold = (0 - n) % n;
  for (;;) {
    const uint64_t r = next_u64();
    if (r >= threshold) return r % n;
  }
}

int Rng::index(int n) {
  assert(n > 0 && "Rng::index needs n > 0");
  return static_cast<int>(below(static_cast<uint64_t>(n)));
}

bool Rng::coin(double p) {
  return uniform() < p;
}

double Rng::normal() {
  // Marsaglia's polar method; the second variate is discarded so the stream has no hidden
  // state beyond its one word.
  for (;;) {
    const double u = 2.0 * uniform() - 1.0;
    const double v = 2.0 * uniform() - 1.0;
    const double s = u * u + v * v;
    if (s > 0.0 && s < 1.0) return u * std::sqrt(-2.0 * std::log(s) / s);
  }
}

}  // namespace plastivox
