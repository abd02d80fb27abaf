// The bond stage's and the voxel update's reverses (bond_reverse_body.hpp,
// voxel_reverse_body.hpp) on AVX2, four bonds or voxels per lane group, as the
// engine's kernels_avx2.cpp runs the forward. Compiled with -mavx2
// (engine/grad/CMakeLists.txt); used only at the engine's SIMD level avx2.
#include "lanes_avx2.hpp"
// After the lane type: the vocabulary, then the template written in it (lanes.hpp).
#include "lanes_simd.hpp"

namespace plastivox {
namespace {

// Component k of the four 4-double records r + 4 idx[0..3], one vector per component: the
// 128-bit halves of records 0 and 2 (and of 1 and 3) paired, then interleaved.
inline void load_records(const double* r, const int* idx, V* c) {
  const __m256d q0 = _mm256_loadu_pd(r + 4 * idx[0]), q1 = _mm256_loadu_pd(r + 4 * idx[1]);
  const __m256d q2 = _mm256_loadu_pd(r + 4 * idx[2]), q3 = _mm256_loadu_pd(r + 4 * idx[3]);
  const __m256d xy02 = _mm256_permute2f128_pd(q0, q2, 0x20),
                zw02 = _mm256_permute2f128_pd(q0, q2, 0x31);
  const __m256d xy13 = _mm256_permute2f128_pd(q1, q3, 0x20),
                zw13 = _mm256_permute2f128_pd(q1, q3, 0x31);
  c[0] = (V)_mm256_unpacklo_pd(xy02, xy13), c[1] = (V)_mm256_unpackhi_pd(xy02, xy13);
  c[2] = (V)_mm256_unpacklo_pd(zw02, zw13), c[3] = (V)_mm256_unpackhi_pd(zw02, zw13);
}

}  // namespace
}  // namespace plastivox

#include "bond_reverse_body.hpp"
#include "voxel_reverse_body.hpp"

plastivox::grad::BondReverseKernel plastivox::grad::bond_reverse_kernel_avx2() {
  return &run_bond_reverse<V>;
}
plastivox::grad::VoxelReverseKernel plastivox::grad::voxel_reverse_kernel_avx2() {
  return &run_voxel_reverse<V>;
}
