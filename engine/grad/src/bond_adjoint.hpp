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
// branch); the other is written by hand for the path nearly every bond takes every step
// (tests/grad_bond_adjoint_test.cpp holds the two to 1e-12), as a lane template
// (bond_reverse_body.hpp) that bond_stage_reverse runs over a whole stage at the engine's SIMD
// level, as the forward kernel runs. The bonds that take the engine's scalar path (every bond
// under Voxelyze 0.9, and the few the batched kernel hands back) are kept in the same block, and
// their reverse is Voxelyze 0.9's by hand (scalar_bond_adjoint.hpp, voxelyze_bond_reverse), else
// that path recorded on a small tape of its own (BondTape, ScalarPathBonds).
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

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
// A kept stage's outputs that may be leaves of the tape: kPrevNext on. The records are read by
// the gather alone, so their adjoints are not leaves but computed from the gather's outputs' (a
// bond's force on a is + in voxel a's total force and - in b's, its moments in a's and b's).
// Strain, stress and their product are read by development (one of them: the body's stimulus)
// and a network's sensors: a stage makes leaves of the next deformations (9 rows) and of those
// of the three something reads (BondLeafRows); the others' adjoints are zero.
constexpr int kBondLeaves = kBondOutputs - kPrevNext;
// The row among a stage's leaves of its strain, stress and energy (-1: not a leaf).
struct BondLeafRows {
  int row[3] = {-1, -1, -1};
  int count() const { return 9 + (row[0] >= 0) + (row[1] >= 0) + (row[2] >= 0); }
};

struct BondArgs {
  double v[kBondInputs];
  int32_t id[kBondInputs];  // tape nodes (-1: a constant)
  int32_t axis;             // the bond's lattice axis
  uint8_t valid;            // its previous deformation is recorded (damping on)
};

// A step's bond stage as kept for its reverse: the arrays the kernel read, values and tape
// nodes side by side (copied whole, not bond by bond), at these offsets for n voxels and nb
// bonds: centres and sizes (4 a voxel), orientations (4 a voxel), moduli, the previous
// deformations (component by component, nb each), the damping factor.
struct BondStageLayout {
  size_t n, nb;
  size_t quat() const { return 4 * n; }
  size_t stiff() const { return 8 * n; }
  size_t prev(int j) const { return 9 * n + size_t(j) * nb; }
  size_t damp() const { return 9 * n + 9 * nb; }
  size_t size() const { return damp() + 1; }
};
// Writes the stage's record (L.size() values and nodes; the nodes through the tape's shadows,
// -1 for an array without one) before the kernel runs. Without prev the previous deformations
// are left unwritten: they are the previous step's stage's next ones, which its kernel wrote
// into this record, and their nodes its leaves, to which the reverse adds as rows
// (bond_stage_reverse's prev_first).
void keep_bond_stage(const BondKernelIo& io, const BondStageLayout& L, double damp, int32_t damp_id,
                     bool prev, double* values, int32_t* ids);
// Bond b's arguments from a kept stage (valid: its damping flag).
BondArgs bond_args(const BondKernelIo& io, const BondStageLayout& L, const double* values,
                   const int32_t* ids, int b, bool valid);

struct Adj;

// One bond recorded on a small tape of its own and swept: the reference reverse
// (bond_reverse_tape) and the scalar path's (scalar_bond_adjoint.hpp). Its arrays, the tape's
// shadows and the adjoints' array are kept from bond to bond, so that a stage whose every bond
// takes it (Voxelyze 0.9) allocates nothing a bond, and its tape (a few hundred nodes) stays in
// the cache.
class BondTape {
 public:
  // A bond's forward on the recording type: bond 0 of io (from voxel 0 to voxel 1), its frame
  // flag small_in[0] (the scalar path's: small_out[0] gets the next).
  using Forward = void (*)(const BondKernelIo& io, const uint8_t* small_in, uint8_t* small_out,
                           const ModelConstants& k, Adj damp);
  BondTape();
  ~BondTape();
  BondTape(const BondTape&) = delete;
  BondTape& operator=(const BondTape&) = delete;
  // From the adjoints of bond a's outputs (kBondOutputs), adds those of its inputs to in_adj
  // (kBondInputs), its forward being `forward` with the frame flag `small`.
  void reverse(Forward forward, const BondArgs& a, bool small, const ModelConstants& k,
               const double* out_adj, double* in_adj);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// From the adjoints of a bond's outputs (kBondOutputs of them), adds those of its inputs to
// in_adj (kBondInputs).
void bond_reverse_tape(const BondArgs& a, const ModelConstants& k, const double* out_adj,
                       double* in_adj);
// The same by hand (one bond of bond_reverse_body.hpp); returns false, having done nothing,
// off its path (a degenerate chord, or a rotation whose arctangent takes the wide branch).
bool bond_reverse(const BondArgs& a, const ModelConstants& k, const double* out_adj,
                  double* in_adj);

// What the lane template reads and writes for a stage of nb bonds: the kept stage's arrays as
// the forward kernel's (bond_a, bond_b, axis_wide the model's; centre_size, quat, stiff, prev
// and prev_valid the record's), the damping factor, the adjoints of the records (records_adj,
// the 9 outputs from kOut, rows of nb) and of the outputs from kPrevNext on (out_adj[o -
// kPrevNext], a row of nb each), the inputs' adjoints (kBondInputs rows of nb), and a flag a
// bond off the hand path.
struct BondReverseIo {
  BondKernelIo bond;
  double damp = 0;
  size_t nb = 0;
  const double* records_adj = nullptr;
  const double* out_adj[kBondLeaves] = {};
  double* in_adj = nullptr;
  uint8_t* off = nullptr;
};
using BondReverseKernel = int (*)(const BondReverseIo&, const ModelConstants&);  // bonds done
BondReverseKernel bond_reverse_kernel_avx2();                                    // reverse_avx2.cpp
BondReverseKernel bond_reverse_kernel_avx512();

// Scratch arrays of bond_stage_reverse, kept from stage to stage.
struct BondStageScratch {
  std::vector<double> in, voxel, records, zero;  // zero: the rows of outputs without leaves
  std::vector<uint8_t> off;
  BondTape tape;  // the bonds off the hand path, and the scalar path's
  // Each voxel's bonds in bond order, built once for a stage's bonds: voxel i's are entries
  // [start[i], start[i + 1]), entry e bond b's offsets in the a end's rows of in (ends[2 e]: in
  // its centre's and orientation's, b or b + 4 nb; ends[2 e + 1]: in its modulus', b or b + nb).
  std::vector<int32_t> start, ends;
};
// The bonds of a kept stage that took the engine's scalar path (scalar_bond_body.hpp), whose
// reverse is Voxelyze 0.9's by hand or that path recorded on a BondTape: every bond under
// Voxelyze 0.9 (small: their frame flags as the stage read them, nb), or under the exact model
// the `count` bonds the batched kernel handed back (list), whose results replaced the kernel's.
struct ScalarPathBonds {
  const uint8_t* small = nullptr;
  const int32_t* list = nullptr;
  int count = 0;
};

// A kept stage's reverse (its record `values` and `ids`, the bonds' damping flags or null when
// all are set): from the adjoints of its outputs, adj[first + (o - kPrevNext) nb + b] for bond
// b's next deformation o and adj[first + rows.row[o - kStrain] nb + b] for its strain, stress and
// energy (zero for those without a row), and of the voxels' total forces and moments (voxel_adj:
// force x, y, z then moment x, y, z, rows of n; the gather's outputs), adds those of its inputs to
// adj through ids. A bond's records' adjoints follow from its voxels': the force on a is + in a's
// total force and - in b's, the moment on a (b) is in a's (b's) total moment. With prev_first
// >= 0 the previous deformations are the previous step's stage's next ones, whose adjoints are
// the rows adj[prev_first + j nb + b] (its leaves from kPrevNext): added there as rows, not
// through ids. Bonds off the hand path take bond_reverse_tape. The inputs' adjoints are summed in
// bond order, the same bits at every SIMD level. voxel_in, when set, holds the adjoints of the
// same step's voxel update's inputs it read from this stage's record (voxel_adjoint.hpp's
// VoxelSharedInputs; rows of n by VoxelInput): each voxel's sum starts from them. The bonds in
// `scalar` take the scalar path's reverse (on a BondTape) instead of the batched one.
void bond_stage_reverse(const BondKernelIo& io, const BondStageLayout& L, const double* values,
                        const int32_t* ids, const uint8_t* valid, size_t first,
                        const BondLeafRows& rows, int64_t prev_first, const double* voxel_adj,
                        double* adj, const ModelConstants& k, BondStageScratch& s,
                        const double* voxel_in = nullptr, const ScalarPathBonds& scalar = {});

}  // namespace plastivox::grad
