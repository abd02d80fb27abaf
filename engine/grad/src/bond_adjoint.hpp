// The bond stage's own adjoint (docs/gradients.md, "Cost"). Recording the bond kernel
// operation by operation was most of a gradient's time: about 400 tape nodes a bond a step,
// recorded in the recomputation and swept back through a tape too large for the cache. Instead
// the replica runs the kernel on doubles (the engine's own bits) and keeps, per bond, what the
// kernel read (its arguments below, values and tape nodes); its outputs are fresh leaves of
// the tape. The sweep, on reaching a bond's leaves, calls the bond's reverse, which recomputes
// the bond from its arguments and adds the adjoints of its inputs.
//
// Two reverses: bond_reverse_tape records the kernel template on a small tape of its own and
// sweeps it (the reference, and the path of rotations past pi/16, the arctangent's wide
// branch); bond_reverse is written by hand for the path nearly every bond takes every step
// (tests/grad_bond_adjoint_test.cpp holds the two to 1e-12).
#pragma once

#include <cstdint>

#include "kernels.hpp"
#include "plastivox/model_constants.hpp"

namespace plastivox::grad {

// What a bond reads, in this order: the centre and actuated size of a and of b, their
// orientations (x, y, z, w), their moduli, the previous deformation, the damping factor.
enum BondInput : int {
  kCentreA = 0,
  kCentreB = 4,
  kQuatA = 8,
  kQuatB = 12,
  kStiffA = 16,
  kStiffB = 17,
  kPrev = 18,
  kDamp = 27,
  kBondInputs = 28
};
// What it writes: the records out[0..2] (x, y, z of each), the next deformation, strain,
// stress, and stress x strain.
enum BondOutput : int {
  kOut = 0,
  kPrevNext = 9,
  kStrain = 18,
  kStress = 19,
  kEnergy = 20,
  kBondOutputs = 21
};

struct BondArgs {
  double v[kBondInputs];
  int32_t id[kBondInputs];  // tape nodes (-1: a constant)
  int32_t axis;             // the bond's lattice axis
  uint8_t valid;            // its previous deformation is recorded (damping on)
};

// The tape nodes of the arrays the bond kernel reads (null: constants), looked up once a step.
struct BondReads {
  const int32_t* centre = nullptr;
  const int32_t* quat = nullptr;
  const int32_t* stiff = nullptr;
  const int32_t* prev[9] = {};
  double damp = 0;
  int32_t damp_id = -1;
};
BondReads bond_reads(const BondKernelIo& io, double damp, int32_t damp_id);
BondArgs bond_args(const BondKernelIo& io, int b, const BondReads& r);

// From the adjoints of a bond's outputs (kBondOutputs of them), adds those of its inputs to
// in_adj (kBondInputs).
void bond_reverse_tape(const BondArgs& a, const ModelConstants& k, const double* out_adj,
                       double* in_adj);
// The same by hand; returns false, having done nothing, off its path (a degenerate chord, or a
// rotation whose arctangent takes the wide branch).
bool bond_reverse(const BondArgs& a, const ModelConstants& k, const double* out_adj,
                  double* in_adj);

}  // namespace plastivox::grad
