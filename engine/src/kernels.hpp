// The batched kernels of a step, one set per instruction set: scalar (kernels.cpp), AVX2
// (kernels_avx2.cpp) and AVX-512 (kernels_avx512.cpp), each the same lane-generic templates
// compiled for it (kernel_set_body.hpp). kernels() is the one place that chooses by
// plastivox/simd.hpp's level; every set gives the same bits.
#pragma once

#include "bond_kernel.hpp"
#include "develop_kernel.hpp"
#include "voxel_kernel.hpp"

namespace plastivox {

struct KernelSet {
  // Bonds [0, n) (bond_kernel.hpp); returns how many bond indices it wrote to io.redo.
  int (*bond)(const BondKernelIo& io, int n, const BondConstants& k);
  // Voxels [0, n): force[i] = the sum of its bonds' forces in slot order - slow damping +
  // weight + load; moment[i] = the sum of its bonds' moments; sqrt_e[i] = sqrt(E_i).
  void (*gather)(const VoxelKernelIo& io, int n, const VoxelConstants& k);
  // Voxels [0, n): floor contact and friction on force[i], then momenta, position and
  // orientation.
  VoxelUpdateSummary (*update)(const VoxelKernelIo& io, const VoxelStateOut& st, int n,
                               const VoxelConstants& k);
  // Voxels [0, n): the actuated sizes.
  void (*actuate)(const double* stiff, const double* phase, double* size, int n,
                  const ActuationConstants& k);
  // Voxels [0, n): stimulus and stiffness update.
  void (*develop)(const DevelopIo& io, int n, const DevelopConstants& k);
  // Writes to out, increasing, every e in [begin, end) with
  // (px[e] - x)^2 + (py[e] - y)^2 + (pz[e] - z)^2 < r2 (a plain comparison of those rounded
  // sums); returns how many. out has room for end - begin entries. (Self-collision refresh.)
  int (*scan_within)(const double* px, const double* py, const double* pz, int begin, int end,
                     double x, double y, double z, double r2, int* out);
  // Writes to out, increasing, every p in [0, n) whose voxels pair_a[p], pair_b[p] (records of
  // centre and size, Workspace::centre_size) may touch: centre distance squared below
  // (half_d (size_a + size_b))^2 (1 + 1e-9); returns how many. (Self-collision, each step.)
  int (*touch_candidates)(const double* records, const int* pair_a, const int* pair_b, int n,
                          double half_d, int* out);
};

// The set for the level in use.
const KernelSet& kernels();

// The set of one instruction set, compiled for it: use only when the CPU has it.
const KernelSet& kernels_avx2();
const KernelSet& kernels_avx512();

}  // namespace plastivox
