// The voxel update's own adjoint (floor contact, Coulomb friction, the Euler update of
// momenta, position and orientation; voxel_body.hpp's update_lanes), as bond_adjoint.hpp is
// the bond stage's: the replica runs the update on doubles and keeps, per voxel, what it
// read; its outputs are leaves of the tape, and the sweep calls the voxel's reverse there.
//
// voxel_reverse_tape records the kernel template on a small tape (the reference, and the path
// of clamped voxels and of the exact model's turns past the series' range); the other is
// written by hand for the rest (tests/grad_bond_adjoint_test.cpp holds the two to 1e-12), as a
// lane template (voxel_reverse_body.hpp) that voxel_stage_reverse runs over a whole step's
// update at the engine's SIMD level.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "kernels.hpp"
#include "plastivox/model_constants.hpp"

namespace plastivox::grad {

// What the update reads: the modulus and its square root, the total force, momentum,
// centre, actuated size, angular momentum, total moment, orientation (x, y, z, w), and dt.
enum VoxelInput : int {
  kVE = 0,
  kVSqrtE = 1,
  kVForce = 2,
  kVLinMom = 5,
  kVPos = 8,
  kVSize = 11,
  kVAngMom = 12,
  kVMoment = 15,
  kVQuat = 18,
  kVDt = 22,
  kVoxelInputs = 23
};
// What it writes: the centre, momentum, angular momentum, orientation, and the floor's normal
// force.
enum VoxelOutput : int {
  kVOutPos = 0,
  kVOutLinMom = 3,
  kVOutAngMom = 6,
  kVOutQuat = 9,
  kVOutNormal = 13,
  kVoxelOutputs = 14
};

struct VoxelArgs {
  double v[kVoxelInputs];
  int32_t id[kVoxelInputs];  // tape nodes (-1: a constant)
  uint8_t fixed;             // clamped
  uint8_t was_held;          // static friction held it last step
};

// A step's update as kept for its reverse: the arrays it read, values and tape nodes side by
// side, input by input (input slot j of voxel i at j n + i; dt repeated), and the voxels' flags
// (2 n: clamped, then held by static friction the step before). Written before the kernel runs
// (it updates some in place).
// With `shared`, the rows of the inputs the same step's bond stage kept (kVE, kVPos, kVSize,
// kVQuat: VoxelSharedInputs) are left unwritten.
void keep_voxel_stage(const VoxelKernelIo& io, size_t n, double dt, int32_t dt_id, double* values,
                      int32_t* ids, uint8_t* flags, bool shared = false);

// The same step's bond stage's record of the centres and sizes, orientations (4 a voxel each)
// and moduli, values and nodes (bond_adjoint.hpp's BondStageLayout): the update reads the same
// arrays unchanged (nothing between the two stages writes them), so it does not keep them again.
struct VoxelSharedInputs {
  const double *centre_size = nullptr, *quat = nullptr, *stiff = nullptr;
  const int32_t *centre_size_ids = nullptr, *quat_ids = nullptr, *stiff_ids = nullptr;
};

// What the lane template (voxel_reverse_body.hpp) reads and writes for n voxels: a kept
// update's values and clamp flags, the outputs' adjoints and the inputs', each as
// kVoxelOutputs (kVoxelInputs) rows of n, and a flag a voxel off the hand path.
struct VoxelReverseIo {
  const double* values = nullptr;
  const uint8_t* fixed = nullptr;
  size_t n = 0;
  const double* out_adj = nullptr;
  double* in_adj = nullptr;
  uint8_t* off = nullptr;
  // When set, the moduli, centres, sizes and orientations are read from a bond stage's record
  // (VoxelSharedInputs) instead of the rows.
  const double *centre_size = nullptr, *quat = nullptr, *stiff = nullptr;
};
using VoxelReverseKernel = int (*)(const VoxelReverseIo&, const ModelConstants&);  // voxels done
VoxelReverseKernel voxel_reverse_kernel_avx2();  // reverse_avx2.cpp
VoxelReverseKernel voxel_reverse_kernel_avx512();

// One voxel's update recorded on a small tape of its own and swept (voxel_reverse_tape): its
// arrays, the tape's shadows and the adjoints' array are kept from voxel to voxel, so that an
// update whose every voxel takes it (under Voxelyze 0.9, whose rotation has no hand path)
// allocates nothing a voxel.
class VoxelTape {
 public:
  VoxelTape();
  ~VoxelTape();
  VoxelTape(const VoxelTape&) = delete;
  VoxelTape& operator=(const VoxelTape&) = delete;
  // From the adjoints of voxel a's outputs (kVoxelOutputs), adds those of its inputs to in_adj.
  void reverse(const VoxelArgs& a, const ModelConstants& k, const double* out_adj, double* in_adj);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// Scratch arrays of voxel_stage_reverse, kept from stage to stage.
struct VoxelStageScratch {
  std::vector<double> in;
  std::vector<uint8_t> off;
  VoxelTape tape;  // the voxels off the hand path
};
// A kept update's reverse (its record `values`, `ids` and `flags`): from the adjoints of its
// outputs, adj[first + o n + i] for voxel i's output o, adds those of its inputs to adj through
// ids, input by input in voxel order (the same bits at every SIMD level). Voxels off the hand path
// take voxel_reverse_tape. With `shared` (its record kept without those rows), the adjoints of
// the inputs read from the bond stage's record are left in s.in's rows (kVoxelInputs rows of n)
// for that stage's reverse to add with its own (bond_stage_reverse's voxel_in), not to the tape.
void voxel_stage_reverse(size_t n, const double* values, const int32_t* ids, const uint8_t* flags,
                         size_t first, double* adj, const ModelConstants& k, VoxelStageScratch& s,
                         const VoxelSharedInputs* shared = nullptr);

// From the adjoints of a voxel's outputs (kVoxelOutputs), adds those of its inputs to in_adj.
void voxel_reverse_tape(const VoxelArgs& a, const ModelConstants& k, const double* out_adj,
                        double* in_adj);
// The same by hand (one voxel of voxel_reverse_body.hpp); returns false, having done nothing,
// off its path (a clamped voxel, under the exact model a turn of more than 0.01 rad in the step).
bool voxel_reverse(const VoxelArgs& a, const ModelConstants& k, const double* out_adj,
                   double* in_adj);

// The gather (voxel_body.hpp's gather_voxel and slow_damping_lanes), which is linear but for
// the slow damping, as one block a step: its inputs are the records each voxel's six slots read
// (force on a, and moment on a or on b, of each slot's bond), each voxel's momentum and
// modulus; its outputs each voxel's total force, total moment and sqrt(E), output by output
// (voxel i's output o is node first + o n + i). The records are the same step's bond stage's
// outputs and read by nothing else: their adjoints are not passed through the tape, the bond
// stage's reverse reads them from the gather's outputs' (bond_stage_reverse).
enum GatherOutput : int { kGOutForce = 0, kGOutMoment = 3, kGOutSqrtE = 6, kGatherOutputs = 7 };
// The gather's record for n voxels: the moduli and momenta (values and nodes, as the arrays are
// laid out).
struct GatherStageLayout {
  size_t n;
  size_t lin_mom() const { return n; }
  size_t values() const { return 4 * n; }
  size_t ids() const { return 4 * n; }
};
void keep_gather_stage(const VoxelKernelIo& io, const GatherStageLayout& L, double* values,
                       int32_t* ids);
// From the adjoints of a kept gather's outputs, adds those of its momenta and moduli to adj,
// voxel by voxel (the records' are the bond stage's reverse's).
void gather_stage_reverse(const GatherStageLayout& L, const double* values, const int32_t* ids,
                          size_t first, double* adj, const ModelConstants& k);

}  // namespace plastivox::grad
