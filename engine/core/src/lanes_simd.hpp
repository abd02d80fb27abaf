// The lane vocabulary (lanes.hpp) for a vector lane type. The includer, an instruction set's
// file, first defines in an unnamed namespace in plastivox: V, a GCC vector of doubles; M,
// what comparing two V yields; and the operations that are best written with the instruction
// set's intrinsics: root(V) (square root), lane_bits(M) (one bit per lane), and the record
// moves load_records, load3, store3, load4 and store4 (lanes.hpp says what each does; by
// permutes they are 5 % faster on AVX2 and 12 % on AVX-512 over whole lives than lane by lane).
#pragma once

#include <cstdint>
#include <cstring>
#include <utility>

#include "lanes.hpp"

namespace plastivox {
namespace {

constexpr int kWidth = kLanes<V>;

inline V splat(double v, V) {
  V r;
  for (int j = 0; j < kWidth; ++j) r[j] = v;
  return r;
}
inline V load(const double* p, int i, V) {
  V v;
  std::memcpy(&v, p + i, sizeof v);
  return v;
}
inline void store(double* p, int i, V v) {
  std::memcpy(p + i, &v, sizeof v);
}
// One value per lane: p[idx[i + j]]. (A braced list, which compiles to fewer instructions than
// assigning lane by lane.)
template <size_t... J>
inline V indexed(const double* p, const int* idx, std::index_sequence<J...>) {
  return V{p[idx[J]]...};
}
inline V load_indexed(const double* p, const int* idx, int i, V) {
  return indexed(p, idx + i, std::make_index_sequence<kWidth>());
}
typedef int IndexLanes __attribute__((vector_size(4 * kWidth)));
inline M index_mask_ne(const int* idx, int i, int value, V) {
  IndexLanes v;
  std::memcpy(&v, idx + i, sizeof v);
  return __builtin_convertvector(v, M) != value;
}
inline M mask_eq(const int64_t* p, int i, int64_t value, V) {
  M v;
  std::memcpy(&v, p + i, sizeof v);
  return v == value;
}
// kWidth flag bytes as one vector, widened to (or narrowed from) the mask's lanes in one
// conversion rather than byte by byte.
typedef uint8_t FlagBytes __attribute__((vector_size(kWidth)));
inline M load_flag(const uint8_t* p, int i, V) {
  FlagBytes b;
  std::memcpy(&b, p + i, sizeof b);
  return __builtin_convertvector(b, M) != 0;
}
inline void store_flag(uint8_t* p, int i, M c) {
  const FlagBytes b = __builtin_convertvector(c & 1, FlagBytes);  // lanes are 0 or -1
  std::memcpy(p + i, &b, sizeof b);
}
inline V pick(M c, V a, V b) {
  return c ? a : b;
}
inline bool any(M c) {
  return lane_bits(c) != 0;
}
inline M and_not(M a, M b) {
  return a & ~b;
}
inline M mask_not(M c) {
  return ~c;
}
inline double lane_get(V v, int j) {
  return v[j];
}
inline void lane_set(V& v, int j, double x) {
  v[j] = x;
}
template <class F>
inline void for_each_lane(M c, F&& f) {
  const int bits = lane_bits(c);
  if (bits == 0) return;
  for (int j = 0; j < kWidth; ++j)
    if (bits & (1 << j)) f(j);
}

}  // namespace
}  // namespace plastivox
