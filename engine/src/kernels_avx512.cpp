// The batched bond and voxel kernels on AVX-512: eight per instruction (and 32 vector registers,
// so fewer spills than with AVX2). Compiled with -mavx512f -mavx512vl -mavx512dq (see
// engine/CMakeLists.txt); called only when the CPU has them.
#if !defined(__AVX512F__) || !defined(__AVX512VL__) || !defined(__AVX512DQ__)
#error "kernels_avx512.cpp must be compiled with -mavx512f -mavx512vl -mavx512dq"
#endif

// GCC 12 flags _mm512_undefined_pd() inside its own AVX-512 intrinsics as uninitialized
// (a known false positive of the header's self-initialisation idiom).
#pragma GCC diagnostic ignored "-Wuninitialized"
#include <immintrin.h>

#include "bond_lanes.hpp"

namespace plastivox {
namespace {

typedef double V __attribute__((vector_size(64)));
typedef long M __attribute__((vector_size(64)));  // what comparing two V yields
constexpr int kWidth = 8;

inline V root(V v) {
  return (V)_mm512_sqrt_pd((__m512d)v);
}
inline int lane_bits(M c) {
  return _mm512_movepi64_mask((__m512i)c);
}
inline void load_quats4(const double* q, const int* idx, __m256d* c);  // bond_lanes_simd.hpp
inline void load_quats(const double* q, const int* idx, V& x, V& y, V& z, V& w) {
  __m256d lo[4], hi[4];
  load_quats4(q, idx, lo);
  load_quats4(q, idx + 4, hi);
  V* out[4] = {&x, &y, &z, &w};
  for (int c = 0; c < 4; ++c)
    *out[c] = (V)_mm512_insertf64x4(_mm512_castpd256_pd512(lo[c]), hi[c], 1);
}

}  // namespace
}  // namespace plastivox

#include "bond_lanes_simd.hpp"
#include "voxel_lanes_body.hpp"

namespace plastivox {

int bond_kernel_avx512(const BondKernelIo& io, int n, const BondConstants& k) {
  return run_bond_lanes(io, n, k);
}

VoxelUpdateSummary voxel_update_avx512(const VoxelKernelIo& io, int n, const VoxelConstants& k) {
  return run_update_lanes<V, kWidth>(io, n, k);
}

void voxel_actuate_avx512(const double* stiff, const double* phase, double* size, int n,
                          const ActuationConstants& k) {
  run_actuate_lanes<V, kWidth>(stiff, phase, size, n, k);
}

}  // namespace plastivox
