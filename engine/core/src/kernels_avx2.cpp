// The kernel set on AVX2: four doubles per lane group. Compiled with -mavx2
// (engine/CMakeLists.txt); used only when the CPU has it.
#include "lanes_avx2.hpp"

namespace plastivox {
namespace {

// Four records of 4 doubles (x, y, z, w) transposed: c[0] = the four x, ... c[3] = the four w.
// Its own inverse, so it also turns four component vectors back into records.
inline void transpose4x4(__m256d q0, __m256d q1, __m256d q2, __m256d q3, V* c) {
  const __m256d xz01 = _mm256_unpacklo_pd(q0, q1), yw01 = _mm256_unpackhi_pd(q0, q1);
  const __m256d xz23 = _mm256_unpacklo_pd(q2, q3), yw23 = _mm256_unpackhi_pd(q2, q3);
  c[0] = (V)_mm256_permute2f128_pd(xz01, xz23, 0x20);
  c[1] = (V)_mm256_permute2f128_pd(yw01, yw23, 0x20);
  c[2] = (V)_mm256_permute2f128_pd(xz01, xz23, 0x31);
  c[3] = (V)_mm256_permute2f128_pd(yw01, yw23, 0x31);
}
inline void load_records(const double* r, const int* idx, V* c) {
  transpose4x4(_mm256_loadu_pd(r + 4 * idx[0]), _mm256_loadu_pd(r + 4 * idx[1]),
               _mm256_loadu_pd(r + 4 * idx[2]), _mm256_loadu_pd(r + 4 * idx[3]), c);
}
// Four consecutive records of 3 or 4 doubles to one vector per component and back, by in-lane
// shuffles, blends and 128-bit permutes (lane by lane, whole lives were 5 % slower).
inline void load3(const double* p, int i, V* out) {
  const __m256d a = _mm256_loadu_pd(p + 3 * i);           // x0 y0 z0 x1
  const __m256d b = _mm256_loadu_pd(p + 3 * i + 4);       // y1 z1 x2 y2
  const __m256d c = _mm256_loadu_pd(p + 3 * i + 8);       // z2 x3 y3 z3
  const __m256d ab = _mm256_permute2f128_pd(a, b, 0x21);  // z0 x1 y1 z1
  const __m256d bc = _mm256_permute2f128_pd(b, c, 0x21);  // x2 y2 z2 x3
  const __m256d xy = _mm256_blend_pd(a, b, 0xC);          // x0 y0 x2 y2
  const __m256d zx = _mm256_blend_pd(ab, bc, 0xC);        // z0 x1 z2 x3
  const __m256d yz = _mm256_blend_pd(b, c, 0xC);          // y1 z1 y3 z3
  out[0] = (V)_mm256_shuffle_pd(xy, zx, 0xA);
  out[1] = (V)_mm256_shuffle_pd(xy, yz, 0x5);
  out[2] = (V)_mm256_shuffle_pd(zx, yz, 0xA);
}
inline void store3(double* p, int i, const V* in) {
  const __m256d x = (__m256d)in[0], y = (__m256d)in[1], z = (__m256d)in[2];
  const __m256d xy = _mm256_unpacklo_pd(x, y);      // x0 y0 x2 y2
  const __m256d zx = _mm256_shuffle_pd(z, x, 0xA);  // z0 x1 z2 x3
  const __m256d yz = _mm256_unpackhi_pd(y, z);      // y1 z1 y3 z3
  _mm256_storeu_pd(p + 3 * i, _mm256_permute2f128_pd(xy, zx, 0x20));
  _mm256_storeu_pd(p + 3 * i + 4, _mm256_permute2f128_pd(yz, xy, 0x30));
  _mm256_storeu_pd(p + 3 * i + 8, _mm256_permute2f128_pd(zx, yz, 0x31));
}
inline void load4(const double* p, int i, V* out) {
  transpose4x4(_mm256_loadu_pd(p + 4 * i), _mm256_loadu_pd(p + 4 * i + 4),
               _mm256_loadu_pd(p + 4 * i + 8), _mm256_loadu_pd(p + 4 * i + 12), out);
}
inline void store4(double* p, int i, const V* in) {
  V r[4];
  transpose4x4((__m256d)in[0], (__m256d)in[1], (__m256d)in[2], (__m256d)in[3], r);
  for (int k = 0; k < 4; ++k) _mm256_storeu_pd(p + 4 * i + 4 * k, (__m256d)r[k]);
}

}  // namespace
}  // namespace plastivox

// The vector vocabulary for V, then the kernels written in it (in this order: lanes.hpp).
#include "lanes_simd.hpp"

#include "kernels_body.hpp"

namespace plastivox {

KernelSet kernels_avx2() {
  return make_kernel_set<V>();
}

}  // namespace plastivox
