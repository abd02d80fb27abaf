#include "plastivox/base/hash.hpp"

#include <cstdio>

#include "plastivox/base/rng.hpp"

namespace plastivox {

std::string Hash128::hex() const {
  char buf[33];
  std::snprintf(buf, sizeof buf, "%016llx%016llx", static_cast<unsigned long long>(hi),
                static_cast<unsigned long long>(lo));
  return buf;
}

Hasher::Hasher() : a_(0x243f6a8885a308d3ULL), b_(0x13198a2e03707344ULL) {}

void Hasher::word(uint64_t w) {
  a_ = mix64(a_ ^ w) + 0x9e3779b97f4a7c15ULL;
  b_ = mix64(b_ + (w ^ 0xa4093822299f31d0ULL)) ^ (b_ >> 23);
  ++n_;
}

void Hasher::bytes(const void* data, size_t n) {
  const auto* p = static_cast<const unsigned char*>(data);
  word(0x5bd1e995ULL ^ n);  // length first: separates consecutive fields
  size_t i = 0;
  for (; i + 8 <= n; i += 8) {
    uint64_t w;
    std::memcpy(&w, p + i, 8);
    word(w);
  }
  if (i < n) {
    uint64_t w = 0;
    std::memcpy(&w, p + i, n - i);
    word(w);
  }
}

void Hasher::u64(uint64_t v) {
  bytes(&v, sizeof v);
}

void Hasher::f64(double v) {
  bytes(&v, sizeof v);
}

Hash128 Hasher::finish() const {
  Hash128 h;
  h.hi = mix64(a_ ^ mix64(n_));
  h.lo = mix64(b_ + h.hi);
  return h;
}

}  // namespace plastivox
