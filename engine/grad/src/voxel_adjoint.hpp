// The voxel update's own adjoint (floor contact, Coulomb friction, the Euler update of
// momenta, position and orientation; voxel_body.hpp's update_lanes), as bond_adjoint.hpp is
// the bond stage's: the replica runs the update on doubles and keeps, per voxel, what it
// read; its outputs are leaves of the tape, and the sweep calls the voxel's reverse there.
//
// voxel_reverse_tape records the kernel template on a small tape (the reference, and the path
// of clamped voxels and of turns past the series' range); voxel_reverse is written by hand for
// the rest (tests/grad_bond_adjoint_test.cpp holds the two to 1e-12).
#pragma once

#include <cstdint>

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

// The tape nodes of the arrays the update reads (null: constants), looked up once a step.
struct VoxelReads {
  const int32_t *stiff = nullptr, *sqrt_e = nullptr, *force[3] = {}, *lin_mom = nullptr,
                *pos = nullptr, *size = nullptr, *ang_mom = nullptr, *moment[3] = {},
                *quat = nullptr;
  double dt = 0;
  int32_t dt_id = -1;
};
VoxelReads voxel_reads(const VoxelKernelIo& io, double dt, int32_t dt_id);
VoxelArgs voxel_args(const VoxelKernelIo& io, int i, const VoxelReads& r);

// From the adjoints of a voxel's outputs (kVoxelOutputs), adds those of its inputs to in_adj.
void voxel_reverse_tape(const VoxelArgs& a, const ModelConstants& k, const double* out_adj,
                        double* in_adj);
// The same by hand; returns false, having done nothing, off its path (a clamped voxel, a turn
// of more than 0.01 rad in the step, a bond model other than the exact one).
bool voxel_reverse(const VoxelArgs& a, const ModelConstants& k, const double* out_adj,
                   double* in_adj);

// The gather (voxel_body.hpp's gather_voxel and slow_damping_lanes) of voxel i, which is
// linear but for the slow damping: its inputs are the records its six slots read (force on a,
// and moment on a or on b, of each slot's bond: 3 each), its momentum and its modulus; its
// outputs the total force, the total moment and sqrt(E).
enum GatherIo : int {
  kGSlots = 0,  // slot s: force at 6 s, moment at 6 s + 3
  kGLinMom = 36,
  kGE = 39,
  kGatherInputs = 40,
  kGOutForce = 0,
  kGOutMoment = 3,
  kGOutSqrtE = 6,
  kGatherOutputs = 7
};
struct GatherArgs {
  int32_t id[kGatherInputs];  // tape nodes (-1: a constant)
  double lin_mom[3], e;       // the values its derivative needs
};
// From the adjoints of the gather's outputs (kGatherOutputs), adds those of its inputs.
void gather_reverse(const GatherArgs& a, const ModelConstants& k, const double* out_adj,
                    double* in_adj);

}  // namespace plastivox::grad
