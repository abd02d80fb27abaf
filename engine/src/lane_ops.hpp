// Lane operations on the scalar lane type `double` (mask type `bool`): the vocabulary the
// lane-generic kernels (bond_lanes_body.hpp, voxel_lanes_body.hpp) are written in. The vector
// lane types get the same operations in lane_ops_simd.hpp. Each operation is element-wise
// IEEE arithmetic or a plain copy, so a lane computes the same bits whatever its width.
//
// Internal linkage throughout (unnamed namespace): these headers are compiled into files
// built for different instruction sets, and no copy of an inline function built for AVX-512
// may be picked by the linker for code that runs on a CPU without it.
#pragma once

#include <cmath>
#include <cstdint>

namespace plastivox {
namespace {

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
// Element idx[i] of p.
inline double load_indexed(const double* p, const int* idx, int i, double) {
  return p[idx[i]];
}
// The mask of idx[i] != value.
inline bool index_mask_ne(const int* idx, int i, int value, double) {
  return idx[i] != value;
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
