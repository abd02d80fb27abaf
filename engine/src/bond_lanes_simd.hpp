// The batched bond kernel's vector lane operations, shared by the AVX2 and AVX-512 files.
// The includer first declares, in an unnamed namespace in plastivox: the vector type V, its
// comparison result M, the width kWidth, and root(V) (square root), lane_bits(M) (one bit
// per lane) and load_quats() (kWidth voxels' quaternions transposed into one vector per
// component), which need that instruction set's intrinsics. Internal linkage throughout
// (see bond_lanes.hpp).
#pragma once

#include <immintrin.h>

#include <cstring>
#include <utility>

#include "bond_lanes.hpp"
#include "lane_ops_simd.hpp"

namespace plastivox {
namespace {

inline void append_redo(M redo, int i, const BondKernelIo& io, int& count) {
  const int bits = lane_bits(redo);
  if (bits == 0) return;
  for (int j = 0; j < kWidth; ++j)
    if (bits & (1 << j)) io.redo[count++] = i + j;
}

// Per-lane choice by the bond's lattice axis: v0 if 0, v1 if 1, v2 if 2.
struct AxisV {
  M is1, is2;
  V operator()(V v0, V v1, V v2) const { return is2 ? v2 : (is1 ? v1 : v0); }
};

// Four records of 4 doubles (x, y, z, w) transposed: c[0] = the four x, ... c[3] = the four w.
// Its own inverse, so it also turns four component vectors back into records.
inline void transpose4x4(__m256d q0, __m256d q1, __m256d q2, __m256d q3, __m256d* c) {
  const __m256d t0 = _mm256_unpacklo_pd(q0, q1);  // x0 x1 z0 z1
  const __m256d t1 = _mm256_unpackhi_pd(q0, q1);  // y0 y1 w0 w1
  const __m256d t2 = _mm256_unpacklo_pd(q2, q3);  // x2 x3 z2 z3
  const __m256d t3 = _mm256_unpackhi_pd(q2, q3);  // y2 y3 w2 w3
  c[0] = _mm256_permute2f128_pd(t0, t2, 0x20);
  c[1] = _mm256_permute2f128_pd(t1, t3, 0x20);
  c[2] = _mm256_permute2f128_pd(t0, t2, 0x31);
  c[3] = _mm256_permute2f128_pd(t1, t3, 0x31);
}

// Four voxels' quaternions (x, y, z, w in memory) transposed: c[0] = the four x, ... c[3] = w.
inline void load_quats4(const double* q, const int* idx, __m256d* c) {
  transpose4x4(_mm256_loadu_pd(q + 4 * idx[0]), _mm256_loadu_pd(q + 4 * idx[1]),
               _mm256_loadu_pd(q + 4 * idx[2]), _mm256_loadu_pd(q + 4 * idx[3]), c);
}

inline void load_records(const double* records, const int* idx, V* c) {
  load_quats(records, idx, c[0], c[1], c[2], c[3]);
}

inline BondIn<V> gather(const BondKernelIo& io, int b, V) {
  const int* ia = io.bond_a + b;
  const int* ib = io.bond_b + b;
  BondIn<V> in;
  // Centres and sizes from the 4-double records (whole-record loads and a transpose, like
  // the quaternions) rather than one load per double.
  V xa, ya, za, xb, yb, zb;
  load_quats(io.centre_size, ia, xa, ya, za, in.size_a);
  load_quats(io.centre_size, ib, xb, yb, zb, in.size_b);
  in.dx = xb - xa, in.dy = yb - ya, in.dz = zb - za;
  load_quats(io.quat, ia, in.ax, in.ay, in.az, in.aw);
  load_quats(io.quat, ib, in.bx, in.by, in.bz, in.bw);
  in.ea = lanes(io.stiff, ia, 1, 0), in.eb = lanes(io.stiff, ib, 1, 0);
  if (io.all_valid) {
    in.valid = splat(1.0, V{});
  } else {
    const uint8_t* valid = io.prev_valid + b;
    for (int j = 0; j < kWidth; ++j) in.valid[j] = valid[j] ? 1.0 : 0.0;
  }
  return in;
}

inline AxisV axis_select(const BondKernelIo& io, int b, V) {
  M d;
  std::memcpy(&d, io.axis_wide + b, sizeof d);
  return AxisV{d == 1, d == 2};
}

}  // namespace
}  // namespace plastivox
