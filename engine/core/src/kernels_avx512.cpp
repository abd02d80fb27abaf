// The kernel set on AVX-512: eight doubles per lane group (and 32 vector registers, so fewer
// spills than with AVX2). Compiled with -mavx512f -mavx512vl -mavx512dq (engine/CMakeLists.txt);
// used only when the CPU has them.
#include "lanes_avx512.hpp"

namespace plastivox {
namespace {

// Lane indices of a two-source permute (0-7 the first source, 8-15 the second), lane 0 first.
inline __m512i idx8(long a, long b, long c, long d, long e, long f, long g, long h) {
  return _mm512_set_epi64(h, g, f, e, d, c, b, a);
}
// Eight records of 4 doubles, one per lane, transposed into one vector per component: records
// j and j + 4 share a register, whose 128-bit halves are then interleaved and gathered.
inline void load_records(const double* r, const int* idx, V* c) {
  __m512d q[4];
  for (int j = 0; j < 4; ++j)
    q[j] = _mm512_insertf64x4(_mm512_castpd256_pd512(_mm256_loadu_pd(r + 4 * idx[j])),
                              _mm256_loadu_pd(r + 4 * idx[j + 4]), 1);
  const __m512d xz01 = _mm512_unpacklo_pd(q[0], q[1]), yw01 = _mm512_unpackhi_pd(q[0], q[1]);
  const __m512d xz23 = _mm512_unpacklo_pd(q[2], q[3]), yw23 = _mm512_unpackhi_pd(q[2], q[3]);
  const __m512i first = idx8(0, 1, 8, 9, 4, 5, 12, 13), second = idx8(2, 3, 10, 11, 6, 7, 14, 15);
  c[0] = (V)_mm512_permutex2var_pd(xz01, first, xz23);
  c[1] = (V)_mm512_permutex2var_pd(yw01, first, yw23);
  c[2] = (V)_mm512_permutex2var_pd(xz01, second, xz23);
  c[3] = (V)_mm512_permutex2var_pd(yw01, second, yw23);
}
// Eight consecutive records of 3 or 4 doubles to one vector per component and back, by
// two-source permutes (lane by lane, whole lives were 12 % slower).
inline void load3(const double* p, int i, V* out) {
  const __m512d a = _mm512_loadu_pd(p + 3 * i), b = _mm512_loadu_pd(p + 3 * i + 8);
  const __m512d c = _mm512_loadu_pd(p + 3 * i + 16);
  // x: a0 a3 a6 b1 b4 b7 c2 c5; y: a1 a4 a7 b2 b5 c0 c3 c6; z: a2 a5 b0 b3 b6 c1 c4 c7.
  const __m512d tx = _mm512_permutex2var_pd(a, idx8(0, 3, 6, 9, 12, 15, 0, 0), b);
  const __m512d ty = _mm512_permutex2var_pd(a, idx8(1, 4, 7, 10, 13, 0, 0, 0), b);
  const __m512d tz = _mm512_permutex2var_pd(a, idx8(2, 5, 8, 11, 14, 0, 0, 0), b);
  out[0] = (V)_mm512_permutex2var_pd(tx, idx8(0, 1, 2, 3, 4, 5, 10, 13), c);
  out[1] = (V)_mm512_permutex2var_pd(ty, idx8(0, 1, 2, 3, 4, 8, 11, 14), c);
  out[2] = (V)_mm512_permutex2var_pd(tz, idx8(0, 1, 2, 3, 4, 9, 12, 15), c);
}
inline void store3(double* p, int i, const V* in) {
  const __m512d x = (__m512d)in[0], y = (__m512d)in[1], z = (__m512d)in[2];
  // a = x0 y0 z0 x1 y1 z1 x2 y2; b = z2 x3 y3 z3 x4 y4 z4 x5; c = y5 z5 x6 y6 z6 x7 y7 z7.
  const __m512d ta = _mm512_permutex2var_pd(x, idx8(0, 8, 0, 1, 9, 0, 2, 10), y);
  const __m512d tb = _mm512_permutex2var_pd(x, idx8(0, 3, 11, 0, 4, 12, 0, 5), y);
  const __m512d tc = _mm512_permutex2var_pd(x, idx8(13, 0, 6, 14, 0, 7, 15, 0), y);
  _mm512_storeu_pd(p + 3 * i, _mm512_permutex2var_pd(ta, idx8(0, 1, 8, 3, 4, 9, 6, 7), z));
  _mm512_storeu_pd(p + 3 * i + 8, _mm512_permutex2var_pd(tb, idx8(10, 1, 2, 11, 4, 5, 12, 7), z));
  _mm512_storeu_pd(p + 3 * i + 16, _mm512_permutex2var_pd(tc, idx8(0, 13, 2, 3, 14, 5, 6, 15), z));
}
inline void load4(const double* p, int i, V* out) {
  const __m512d q0 = _mm512_loadu_pd(p + 4 * i), q1 = _mm512_loadu_pd(p + 4 * i + 8);
  const __m512d q2 = _mm512_loadu_pd(p + 4 * i + 16), q3 = _mm512_loadu_pd(p + 4 * i + 24);
  const __m512i xy = idx8(0, 4, 8, 12, 1, 5, 9, 13), zw = idx8(2, 6, 10, 14, 3, 7, 11, 15);
  const __m512d xy01 = _mm512_permutex2var_pd(q0, xy, q1),
                xy23 = _mm512_permutex2var_pd(q2, xy, q3);
  const __m512d zw01 = _mm512_permutex2var_pd(q0, zw, q1),
                zw23 = _mm512_permutex2var_pd(q2, zw, q3);
  const __m512i lo = idx8(0, 1, 2, 3, 8, 9, 10, 11), hi = idx8(4, 5, 6, 7, 12, 13, 14, 15);
  out[0] = (V)_mm512_permutex2var_pd(xy01, lo, xy23);
  out[1] = (V)_mm512_permutex2var_pd(xy01, hi, xy23);
  out[2] = (V)_mm512_permutex2var_pd(zw01, lo, zw23);
  out[3] = (V)_mm512_permutex2var_pd(zw01, hi, zw23);
}
inline void store4(double* p, int i, const V* in) {
  const __m512d x = (__m512d)in[0], y = (__m512d)in[1], z = (__m512d)in[2], w = (__m512d)in[3];
  // xy = x0 y0 x1 y1 x2 y2 x3 y3 (and the upper four), zw alike, then records of (x y z w).
  const __m512i lo = idx8(0, 8, 1, 9, 2, 10, 3, 11), hi = idx8(4, 12, 5, 13, 6, 14, 7, 15);
  const __m512d xy_lo = _mm512_permutex2var_pd(x, lo, y), xy_hi = _mm512_permutex2var_pd(x, hi, y);
  const __m512d zw_lo = _mm512_permutex2var_pd(z, lo, w), zw_hi = _mm512_permutex2var_pd(z, hi, w);
  const __m512i r01 = idx8(0, 1, 8, 9, 2, 3, 10, 11), r23 = idx8(4, 5, 12, 13, 6, 7, 14, 15);
  _mm512_storeu_pd(p + 4 * i, _mm512_permutex2var_pd(xy_lo, r01, zw_lo));
  _mm512_storeu_pd(p + 4 * i + 8, _mm512_permutex2var_pd(xy_lo, r23, zw_lo));
  _mm512_storeu_pd(p + 4 * i + 16, _mm512_permutex2var_pd(xy_hi, r01, zw_hi));
  _mm512_storeu_pd(p + 4 * i + 24, _mm512_permutex2var_pd(xy_hi, r23, zw_hi));
}

}  // namespace
}  // namespace plastivox

// The vector vocabulary for V, then the kernels written in it (in this order: lanes.hpp).
#include "lanes_simd.hpp"

#include "kernels_body.hpp"

namespace plastivox {

KernelSet kernels_avx512() {
  return make_kernel_set<V>();
}

}  // namespace plastivox
