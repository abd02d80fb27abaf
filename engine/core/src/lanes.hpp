// The lane vocabulary the kernels are written in (bond_body.hpp, voxel_body.hpp, ...). A kernel
// is a template over its lane type T: `double` (mask `bool`) here, or a GCC vector of doubles
// (lanes_simd.hpp) in the file compiled for an instruction set. Every operation is
// element-wise IEEE arithmetic or a plain copy, so a lane computes the same bits whatever the
// width of its group.
//
// How the files fit (the one rule): an instruction set's file (kernels_avx2.cpp,
// kernels_avx512.cpp) defines its vector type and the few operations that need its intrinsics,
// then includes lanes_simd.hpp and kernels_body.hpp. The vector operations must be declared
// before the kernel templates that use them, because a vector type has no namespace in which
// argument-dependent lookup could find them later.
//
// Internal linkage throughout (unnamed namespace): these headers are compiled into files built
// for different instruction sets, and no copy of an inline function built for AVX-512 may be
// picked by the linker for code that runs on a CPU without it. For the same reason the kernels
// call only compiler intrinsics and their own elementary functions (elementary.hpp).
#pragma once

#include <cmath>
#include <cstdint>

namespace plastivox {
namespace {

// Doubles in one lane group of type T.
template <class T>
constexpr int kLanes = sizeof(T) / sizeof(double);

// Calls f(T{}, i) for every group of lanes [i, i + kLanes<T>) in [0, n), then f(double{}, i)
// for each element of the tail.
template <class T, class F>
inline void over_lanes(int n, F&& f) {
  int i = 0;
  for (; i + kLanes<T> <= n; i += kLanes<T>) f(T{}, i);
  for (; i < n; ++i) f(double{}, i);
}

inline double splat(double v, double) {
  return v;
}
inline double load(const double* p, int i, double) {
  return p[i];
}
inline void store(double* p, int i, double v) {
  p[i] = v;
}
// Records of 3 (x, y, z) or 4 (x, y, z, w) doubles back to back: element i's components.
inline void load3(const double* p, int i, double* c) {
  for (int k = 0; k < 3; ++k) c[k] = p[3 * i + k];
}
inline void store3(double* p, int i, const double* c) {
  for (int k = 0; k < 3; ++k) p[3 * i + k] = c[k];
}
inline void load4(const double* p, int i, double* c) {
  for (int k = 0; k < 4; ++k) c[k] = p[4 * i + k];
}
inline void store4(double* p, int i, const double* c) {
  for (int k = 0; k < 4; ++k) p[4 * i + k] = c[k];
}
// The 4-double records of elements idx[0], idx[1], ... (one per lane): c[k] = component k.
inline void load_records(const double* records, const int* idx, double* c) {
  load4(records, idx[0], c);
}
// Element idx[i] of p.
inline double load_indexed(const double* p, const int* idx, int i, double) {
  return p[idx[i]];
}
// The masks of idx[i] != value and p[i] == value.
inline bool index_mask_ne(const int* idx, int i, int value, double) {
  return idx[i] != value;
}
inline bool mask_eq(const int64_t* p, int i, int64_t value, double) {
  return p[i] == value;
}
// A 0/1 flag array as a mask, and back.
inline bool load_flag(const uint8_t* p, int i, double) {
  return p[i] != 0;
}
inline void store_flag(uint8_t* p, int i, bool c) {
  p[i] = c ? 1 : 0;
}
inline double root(double v) {
  return std::sqrt(v);
}
inline double pick(bool c, double a, double b) {
  return c ? a : b;
}
// A number's value (the recording type's own overload is found by argument-dependent lookup).
inline double value_of(double v) {
  return v;
}
inline bool any(bool c) {
  return c;
}
inline bool and_not(bool a, bool b) {
  return a && !b;
}
inline bool mask_not(bool c) {
  return !c;
}
inline double lane_get(double v, int) {
  return v;
}
inline void lane_set(double& v, int, double x) {
  v = x;
}
// Calls f(j) for every lane j whose mask is set.
template <class F>
inline void for_each_lane(bool c, F&& f) {
  if (c) f(0);
}

}  // namespace
}  // namespace plastivox
