// The bonds that take the engine's scalar path, in the gradient's replica: every bond under
// bond_model voxelyze09, and under the exact model the few the batched kernel hands back (a
// degenerate chord, a relative rotation near half a turn). The replica runs the engine's own
// template (engine/core/src/scalar_bond_body.hpp) on the recording type, so its forward is the
// engine's bits and, when recording, the tape holds each such bond operation by operation: its
// reverse is the tape's sweep (no block of its own), the same bits at every SIMD level and on
// any number of threads, as the tape is. Also Voxelyze 0.9's time step on recorded stiffness.
#pragma once

#include <vector>

#include "adj.hpp"
#include "plastivox/model.hpp"
#include "workspace.hpp"

namespace plastivox::grad {

// Bonds bonds[0, count) by the scalar path, or every bond when bonds is null; damp: bond_damp
// / dt. Reads and writes the views' arrays as the engine's bond stage does (bond_forces.cpp,
// compute_bond_forces): the next deformation to io.prev_next, the next frame to
// small_angle_next.
void scalar_bonds(const Model& m, KernelViews& v, Adj damp, const int* bonds, int count);

// Voxelyze 0.9's time step (compile.cpp, voxelyze_dt) in its order of operations, on recorded
// stiffness E: its derivative is the stiffest bond's (the first of a tie, as std::max keeps).
// near, when given, gets the bonds within a relative 1e-9 of the stiffest, where the time step
// has no derivative (events).
Adj voxelyze_dt_adj(const Model& m, const double* E, std::vector<int>* near = nullptr);

}  // namespace plastivox::grad
