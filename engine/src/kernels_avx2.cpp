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
#include "contact_scan_body.hpp"
#include "develop_lanes_body.hpp"
#include "voxel_lanes_body.hpp"

namespace plastivox {

int bond_kernel_avx2(const BondKernelIo& io, int n, const BondConstants& k) {
  return run_bond_lanes(io, n, k);
}

void voxel_gather_avx2(const VoxelKernelIo& io, int n, const VoxelConstants& k) {
  run_gather(io, n, k);
}

VoxelUpdateSummary voxel_update_avx2(const VoxelKernelIo& io, int n, const VoxelConstants& k) {
  return run_update_lanes<V, kWidth>(io, n, k);
}

void voxel_actuate_avx2(const double* stiff, const double* phase, double* size, int n,
                        const ActuationConstants& k) {
  run_actuate_lanes<V, kWidth>(stiff, phase, size, n, k);
}

bool develop_voxels_avx2(const DevelopIo& io, int n, const DevelopConstants& k) {
  return run_develop_lanes<V, kWidth>(io, n, k);
}

int scan_within_avx2(const double* px, const double* py, const double* pz, int begin, int end,
                     double x, double y, double z, double r2, int* out) {
  return run_scan_within<V, kWidth>(px, py, pz, begin, end, x, y, z, r2, out);
}

}  // namespace plastivox
