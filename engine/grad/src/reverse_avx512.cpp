// The bond stage's and the voxel update's reverses (bond_reverse_body.hpp,
// voxel_reverse_body.hpp) on AVX-512, eight bonds or voxels per lane group, as the
// engine's kernels_avx512.cpp runs the forward. Compiled with -mavx512f -mavx512vl -mavx512dq
// (engine/grad/CMakeLists.txt); used only at the engine's SIMD level avx512.
#include "lanes_avx512.hpp"
// After the lane type: the vocabulary, then the template written in it (lanes.hpp).
#include "lanes_simd.hpp"

namespace plastivox {
namespace {

// Component k of the eight 4-double records r + 4 idx[0..7], one vector per component. Records
// j and j + 4 share a register; per component, two permutes take lanes 0, 1, 4, 5 from a pair
// of registers and a third interleaves the two pairs. (Lane by lane, the bond reverse took 8 %
// longer.)
inline void load_records(const double* r, const int* idx, V* c) {
  __m512d q[4];
  for (int j = 0; j < 4; ++j)
    q[j] = _mm512_insertf64x4(_mm512_castpd256_pd512(_mm256_loadu_pd(r + 4 * idx[j])),
                              _mm256_loadu_pd(r + 4 * idx[j + 4]), 1);
  const __m512i pairs = _mm512_set_epi64(13, 12, 5, 4, 9, 8, 1, 0);
  for (long k = 0; k < 4; ++k) {
    const __m512i take = _mm512_set_epi64(0, 0, 12 + k, 4 + k, 0, 0, 8 + k, k);
    const __m512d lo = _mm512_permutex2var_pd(q[0], take, q[1]);
    const __m512d hi = _mm512_permutex2var_pd(q[2], take, q[3]);
    c[k] = (V)_mm512_permutex2var_pd(lo, pairs, hi);
  }
}

}  // namespace
}  // namespace plastivox

#include "bond_reverse_body.hpp"
#include "voxel_reverse_body.hpp"

plastivox::grad::BondReverseKernel plastivox::grad::bond_reverse_kernel_avx512() {
  return &run_bond_reverse<V>;
}
plastivox::grad::VoxelReverseKernel plastivox::grad::voxel_reverse_kernel_avx512() {
  return &run_voxel_reverse<V>;
}
