// Development (docs/method.md §5): each voxel's stiffness follows its interoceptive
// stimulus, scaled by its evolved rate alpha. Runs after settling, on the bond strains of
// this step; the new stiffness takes effect in the next step's bonds, actuation and dt.
#include "kernels.hpp"
#include "workspace.hpp"

namespace plastivox {

// The rule, per voxel (develop_body.hpp):
// - stimulus under stress: the largest tensile axial stress among its bonds (compression
//   counts as 0), Pa;
// - under pressure, positive in compression, Pa: -E_i (eps_x + eps_y + eps_z) / (3 (1 - 2 nu))
//   from the voxel's own strains along its axes (the mean over its two bonds on an axis, or
//   the one bond). A bond is two springs in series, so the voxel of modulus E_i joined to one
//   of E_j takes 2 E_j / (E_i + E_j) of the bond's strain (the softer voxel stretches more),
//   and E_i times that share is the bond's harmonic-mean axial stress: the pressure sums bond
//   stresses. This is how the authors' simulator (Voxelyze 0.9,
//   CVXS_BondInternal::UpdateBondStrain) sets the per-voxel strains its pressure reads, except
//   that it leaves the strain unsplit when the two moduli are within 0.05 % of each other (its
//   refinement loop does not run), a change of that bond's term by less than 2.5e-4 that is
//   not reproduced. Under AxialModulus::kNegativeVoxel (bonds the authors' simulator treats as
//   homogeneous: no split) the voxel's own E times the bond strain is used;
// - the other stimuli (strain, strain_energy, contact, kinetic) are defined where the enum
//   is (physics_def.hpp) and computed beside these two in develop_body.hpp;
// - then (integral model) E = E0 + alpha * integral of the stimulus, or (rate model)
//   E = E0 + alpha * (stimulus - stimulus at the end of settling); the change in one step is
//   capped, E is clamped to [e_min, e_max], and only voxels with E > gate (min_devo_factor
//   e_min) and alpha != 0 develop: soft voxels never do, and one softened to the gate stops.
void bind_develop_views(const Model& m, Workspace& w) {
  DevelopIo& io = w.views.develop;
  for (int slot = 0; slot < 6; ++slot) io.slot_bond[slot] = w.slot_bond[slot].data();
  io.no_bond = m.bond_count();
  io.bond_stress = w.bond_stress.data();
  io.bond_strain = w.bond_strain.data();
  io.bond_energy = w.bond_energy.data();
  io.floor_normal = w.floor_normal.data();
  io.e0 = m.e0.data();
  io.alpha = m.alpha.data();
}

void develop(const Model& m, State& s, Workspace& w) {
  if (m.def.treatment == Treatment::kNone || s.time < m.def.settle_time) return;
  kernels().develop(w.views.develop, m.n, m, s.dt, !s.stim_ref_set);
  s.stim_ref_set = true;
}

}  // namespace plastivox
