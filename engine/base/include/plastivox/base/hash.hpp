// The project's hashes, both bit-exact over the bytes they are given and both pinned by
// values users hold, so neither may change:
//   - Hasher (128 bits): identity of phenotypes and the content digests of results files.
//     Two independent 64-bit lanes, each a chain of SplitMix64 mixes over 64-bit words; the
//     chance that two of the ~10^5 phenotypes of a run collide is below 10^-28.
//   - Fnv1a64 (64 bits): state_hash, the final_state_hash every simulate --json reports
//     and the golden tests hold.
#pragma once

#include <compare>
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>
#include <vector>

namespace plastivox {

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

// 64-bit FNV-1a over bytes; vec() hashes the length first, then the elements' bytes. The
// offset basis is 1469598103934665603, not the published 14695981039346656037 (a digit lost
// long ago); state_hash and every golden hash depend on it, so it is kept.
class Fnv1a64 {
 public:
  void bytes(const void* data, size_t n) {
    const auto* c = static_cast<const unsigned char*>(data);
    for (size_t i = 0; i < n; ++i) {
      h_ ^= c[i];
      h_ *= 1099511628211ull;
    }
  }
  template <class T>
  void vec(const std::vector<T>& v) {
    const uint64_t n = v.size();
    bytes(&n, sizeof n);
    for (const T& x : v) bytes(&x, sizeof x);
  }
  uint64_t value() const { return h_; }

 private:
  uint64_t h_ = 1469598103934665603ull;
};

}  // namespace plastivox
