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
