// Lane operations on a vector lane type (see lane_ops.hpp for the scalar ones and the rules).
// The includer first declares, in an unnamed namespace in plastivox: the vector type V of
// kWidth doubles, its comparison result M, root(V) (square root) and lane_bits(M) (one bit
// per lane), which need that instruction set's intrinsics (kernels_avx2.cpp, kernels_avx512.cpp).
#pragma once

#include <cfloat>
#include <cstdint>
#include <cstring>
#include <utility>

#include "lane_ops.hpp"

namespace plastivox {
namespace {

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
// One value per lane from a per-element array: p[stride * idx[j] + offset]. (A braced list,
// which compiles to fewer instructions than assigning lane by lane.)
template <size_t... J>
inline V lanes(const double* p, const int* idx, int stride, int offset, std::index_sequence<J...>) {
  return V{p[stride * idx[J] + offset]...};
}
inline V lanes(const double* p, const int* idx, int stride, int offset) {
  return lanes(p, idx, stride, offset, std::make_index_sequence<kWidth>());
}
inline V load_indexed(const double* p, const int* idx, int i, V) {
  return lanes(p, idx + i, 1, 0);
}
// load3/store3/load4/store4 for kWidth consecutive records, one vector per component. An
// instruction set with fast cross-lane permutes defines its own before including this file
// (and PLASTIVOX_LANES_HAVE_RECORDS); otherwise lane by lane.
#ifndef PLASTIVOX_LANES_HAVE_RECORDS
template <size_t... J>
inline V load_strided(const double* p, int i, int stride, int offset, std::index_sequence<J...>) {
  return V{p[stride * (i + static_cast<int>(J)) + offset]...};
}
inline V load_strided(const double* p, int i, int stride, int offset, V) {
  return load_strided(p, i, stride, offset, std::make_index_sequence<kWidth>());
}
inline void store_strided(double* p, int i, int stride, int offset, V v) {
  for (int j = 0; j < kWidth; ++j) p[stride * (i + j) + offset] = v[j];
}
inline void load3(const double* p, int i, V* c) {
  for (int k = 0; k < 3; ++k) c[k] = load_strided(p, i, 3, k, V{});
}
inline void store3(double* p, int i, const V* c) {
  for (int k = 0; k < 3; ++k) store_strided(p, i, 3, k, c[k]);
}
inline void load4(const double* p, int i, V* c) {
  for (int k = 0; k < 4; ++k) c[k] = load_strided(p, i, 4, k, V{});
}
inline void store4(double* p, int i, const V* c) {
  for (int k = 0; k < 4; ++k) store_strided(p, i, 4, k, c[k]);
}
#endif
typedef int IndexLanes __attribute__((vector_size(4 * kWidth)));
inline M index_mask_ne(const int* idx, int i, int value, V) {
  IndexLanes v;
  std::memcpy(&v, idx + i, sizeof v);
  return __builtin_convertvector(v, M) != value;
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
