// The kernel set on AVX2: four doubles per lane group. Compiled with -mavx2
// (engine/CMakeLists.txt); used only when the CPU has it.
#if !defined(__AVX2__)
#error "kernels_avx2.cpp must be compiled with -mavx2"
#endif

#include <immintrin.h>

namespace plastivox {
namespace {

typedef double V __attribute__((vector_size(32)));
typedef long M __attribute__((vector_size(32)));

inline V root(V v) {
  return (V)_mm256_sqrt_pd((__m256d)v);
}
inline int lane_bits(M c) {
  return _mm256_movemask_pd((__m256d)c);
}
// Four records of 4 doubles, one per lane, transposed into one vector per component.
inline void load_records(const double* r, const int* idx, V* c) {
  const __m256d q0 = _mm256_loadu_pd(r + 4 * idx[0]), q1 = _mm256_loadu_pd(r + 4 * idx[1]);
  const __m256d q2 = _mm256_loadu_pd(r + 4 * idx[2]), q3 = _mm256_loadu_pd(r + 4 * idx[3]);
  const __m256d xz01 = _mm256_unpacklo_pd(q0, q1), yw01 = _mm256_unpackhi_pd(q0, q1);
  const __m256d xz23 = _mm256_unpacklo_pd(q2, q3), yw23 = _mm256_unpackhi_pd(q2, q3);
  c[0] = (V)_mm256_permute2f128_pd(xz01, xz23, 0x20);
  c[1] = (V)_mm256_permute2f128_pd(yw01, yw23, 0x20);
  c[2] = (V)_mm256_permute2f128_pd(xz01, xz23, 0x31);
  c[3] = (V)_mm256_permute2f128_pd(yw01, yw23, 0x31);
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
