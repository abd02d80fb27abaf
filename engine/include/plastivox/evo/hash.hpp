// A 128-bit non-cryptographic hash for bit-exact identity of phenotypes and result content.
// Two independent 64-bit lanes, each a chain of SplitMix64 mixes over 64-bit words; the
// chance that two of the ~10^5 phenotypes of a run collide is below 10^-28.
#pragma once

#include <compare>
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>
#include <vector>

namespace plastivox::evo {

struct Hash128 {
  uint64_t hi = 0, lo = 0;
  auto operator<=>(const Hash128&) const = default;
  std::string hex() const;  // 32 lowercase hex digits, hi first
};

// Streaming hasher. Values are hashed by their bytes (doubles bit for bit: -0.0 != 0.0),
// each call also mixing in its length, so ("ab","c") and ("a","bc") differ.
class Hasher {
 public:
  Hasher();
  void bytes(const void* data, size_t n);
  void u64(uint64_t v);
  void f64(double v);
  void str(std::string_view s) { bytes(s.data(), s.size()); }
  template <class T>
  void vec(const std::vector<T>& v) {
    bytes(v.data(), v.size() * sizeof(T));
  }
  Hash128 finish() const;

 private:
  void word(uint64_t w);
  uint64_t a_, b_, n_ = 0;
};

}  // namespace plastivox::evo
