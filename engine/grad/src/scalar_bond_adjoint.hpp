// The bonds that take the engine's scalar path, in the gradient's replica: every bond under
// bond_model voxelyze09, and under the exact model the few the batched kernel hands back (a
// degenerate chord, a relative rotation near half a turn). The replica runs the engine's own
// template (engine/core/src/scalar_bond_body.hpp), so its forward is the engine's bits. When
// recording with the stage adjoints, the replica runs it on doubles and keeps the bond stage as a
// block (bond_adjoint.hpp), whose reverse takes each such bond by hand under Voxelyze 0.9
// (voxelyze_bond_reverse), else recorded on a small tape of its own and swept
// (scalar_bond_forward); given no blocks (the reference, or the replica's forward
// with its events), on the recording type, operation by operation on the tape. Either way the
// same bits at every SIMD level and on any number of threads. Also Voxelyze 0.9's time step on
// recorded stiffness.
#pragma once

#include <vector>

#include "adj.hpp"
#include "bond_adjoint.hpp"
#include "plastivox/model.hpp"
#include "workspace.hpp"

namespace plastivox::grad {

// Bonds bonds[0, count) by the scalar path, or every bond when bonds is null; damp: bond_damp
// / dt. Reads and writes the views' arrays as the engine's bond stage does (bond_forces.cpp,
// compute_bond_forces): the next deformation to io.prev_next, the next frame to
// small_angle_next.
void scalar_bonds(const Model& m, KernelViews& v, Adj damp, const int* bonds, int count);
// Bond 0 of io by the scalar path on the recording type, its frame flag small_in[0]: the
// forward a BondTape records for the reverse of a kept stage's scalar-path bonds.
void scalar_bond_forward(const BondKernelIo& io, const uint8_t* small_in, uint8_t* small_out,
                         const ModelConstants& k, Adj damp);
// The same bond's reverse under Voxelyze 0.9 by hand (scalar_bond_reverse.cpp), from the
// adjoints of its outputs (kBondOutputs) adding those of its inputs to in_adj (kBondInputs), its
// frame flag `small`; returns false, having done nothing, off its path (a chord of zero length
// or within 1e-7 rad of backwards: the constant frames), which the BondTape takes.
bool voxelyze_bond_reverse(const BondArgs& a, bool small, const ModelConstants& k,
                           const double* out_adj, double* in_adj);

// Voxelyze 0.9's time step (compile.cpp, voxelyze_dt) in its order of operations, on recorded
// stiffness E: its derivative is the stiffest bond's (the first of a tie, as std::max keeps).
// near, when given, gets the bonds within a relative 1e-9 of the stiffest, where the time step
// has no derivative (events).
Adj voxelyze_dt_adj(const Model& m, const double* E, std::vector<int>* near = nullptr);

}  // namespace plastivox::grad
