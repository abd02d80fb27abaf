// See voxel_kernel.hpp: the scalar voxel kernels and the choice of instruction set (the same
// as the bond kernel's, plastivox/simd.hpp).
#include "voxel_kernel.hpp"

#include "plastivox/simd.hpp"
#include "voxel_lanes_body.hpp"

namespace plastivox {

void voxel_gather(const VoxelKernelIo& io, int n, const VoxelConstants& k) {
#if defined(PLASTIVOX_HAVE_AVX2)
  if (simd_level() >= SimdLevel::kAvx2) return voxel_gather_avx2(io, n, k);
#endif
  run_gather(io, n, k);
}

VoxelUpdateSummary voxel_update(const VoxelKernelIo& io, int n, const VoxelConstants& k) {
  switch (simd_level()) {
#if defined(PLASTIVOX_HAVE_AVX512)
    case SimdLevel::kAvx512:
      return voxel_update_avx512(io, n, k);
#endif
#if defined(PLASTIVOX_HAVE_AVX2)
    case SimdLevel::kAvx2:
      return voxel_update_avx2(io, n, k);
#endif
    default:
      return run_update_lanes<double, 1>(io, n, k);
  }
}

void voxel_actuate(const double* stiff, const double* phase, double* size, int n,
                   const ActuationConstants& k) {
  switch (simd_level()) {
#if defined(PLASTIVOX_HAVE_AVX512)
    case SimdLevel::kAvx512:
      return voxel_actuate_avx512(stiff, phase, size, n, k);
#endif
#if defined(PLASTIVOX_HAVE_AVX2)
    case SimdLevel::kAvx2:
      return voxel_actuate_avx2(stiff, phase, size, n, k);
#endif
    default:
      return run_actuate_lanes<double, 1>(stiff, phase, size, n, k);
  }
}

}  // namespace plastivox
