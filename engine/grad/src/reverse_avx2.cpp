// The bond stage's and the voxel update's reverses (bond_reverse_body.hpp,
// voxel_reverse_body.hpp) on AVX2, four bonds or voxels per lane group, as the
// engine's kernels_avx2.cpp runs the forward. Compiled with -mavx2
// (engine/grad/CMakeLists.txt); used only at the engine's SIMD level avx2.
#include "lanes_avx2.hpp"
// After the lane type: the vocabulary, then the template written in it (lanes.hpp).
#include "lanes_simd.hpp"

#include "bond_reverse_body.hpp"
#include "voxel_reverse_body.hpp"

plastivox::grad::BondReverseKernel plastivox::grad::bond_reverse_kernel_avx2() {
  return &run_bond_reverse<V>;
}
plastivox::grad::VoxelReverseKernel plastivox::grad::voxel_reverse_kernel_avx2() {
  return &run_voxel_reverse<V>;
}
