// The batched bond and voxel kernels on AVX2: four bonds or voxels per instruction. Compiled with
// -mavx2 (see engine/CMakeLists.txt); called only when the CPU has AVX2.
#if !defined(__AVX2__)
#error "kernels_avx2.cpp must be compiled with -mavx2"
#endif

#include <immintrin.h>

#include "bond_lanes.hpp"

namespace plastivox {
namespace {

typedef double V __attribute__((vector_size(32)));
typedef long M __attribute__((vector_size(32)));  // what comparing two V yields
constexpr int kWidth = 4;

inline V root(V v) {
  return (V)_mm256_sqrt_pd((__m256d)v);
}
inline int lane_bits(M c) {
  return _mm256_movemask_pd((__m256d)c);
}
// Four consecutive records of 3 or 4 doubles to one vector per component and back, by
// in-lane shuffles, blends and 128-bit permutes (the lane-by-lane form costs a load or store
// per double).
#define PLASTIVOX_LANES_HAVE_RECORDS 1
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
inline void transpose4x4(__m256d q0, __m256d q1, __m256d q2, __m256d q3,
                         __m256d* c);  // bond_lanes_simd.hpp
inline void load4(const double* p, int i, V* out) {
  __m256d c[4];
  transpose4x4(_mm256_loadu_pd(p + 4 * i), _mm256_loadu_pd(p + 4 * i + 4),
               _mm256_loadu_pd(p + 4 * i + 8), _mm256_loadu_pd(p + 4 * i + 12), c);
  for (int k = 0; k < 4; ++k) out[k] = (V)c[k];
}
inline void store4(double* p, int i, const V* in) {
  __m256d r[4];
  transpose4x4((__m256d)in[0], (__m256d)in[1], (__m256d)in[2], (__m256d)in[3], r);
  for (int k = 0; k < 4; ++k) _mm256_storeu_pd(p + 4 * i + 4 * k, r[k]);
}
inline void load_quats4(const double* q, const int* idx, __m256d* c);  // bond_lanes_simd.hpp
inline void load_quats(const double* q, const int* idx, V& x, V& y, V& z, V& w) {
  __m256d c[4];
  load_quats4(q, idx, c);
  x = (V)c[0], y = (V)c[1], z = (V)c[2], w = (V)c[3];
}

}  // namespace
}  // namespace plastivox

#include "bond_lanes_simd.hpp"
#include "kernel_set_body.hpp"

namespace plastivox {

const KernelSet& kernels_avx2() {
  static const KernelSet set = make_kernel_set<V, kWidth>();
  return set;
}

}  // namespace plastivox
