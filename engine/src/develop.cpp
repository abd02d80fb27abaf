// Development (METHOD.md section 5): each voxel's stiffness follows its interoceptive
// stimulus, scaled by its evolved rate alpha. Runs after settling, on the bond strains of
// this step; the new stiffness takes effect in the next step's bonds, actuation and dt.
#include <algorithm>
#include <cmath>

#include "workspace.hpp"

namespace plastivox {
namespace {

// Largest tensile axial stress among the voxel's bonds (compression counts as 0), Pa.
double stress_stimulus(const Model& m, const Workspace& w, int i) {
  double sigma = 0;
  for (int b : m.voxel_bonds[i]) {
    if (b >= 0) sigma = std::max(sigma, w.bond_stress[b]);
  }
  return sigma;
}

// Pressure, positive in compression, Pa: -E_i (eps_x + eps_y + eps_z) / (3 (1 - 2 nu)) from
// the voxel's own strains along its axes (the mean over its two bonds on an axis, or the one
// bond). A bond is two springs in series, so the voxel of modulus E_i joined to one of E_j
// takes 2 E_j / (E_i + E_j) of the bond's strain (the softer voxel stretches more), and E_i
// times that share is the bond's harmonic-mean axial stress: the pressure sums bond stresses.
// This is how the authors' simulator (Voxelyze 0.9, CVXS_BondInternal::UpdateBondStrain) sets
// the per-voxel strains its pressure reads, except that it leaves the strain unsplit when the
// two moduli are within 0.05 % of each other (its refinement loop does not run), a change of
// that bond's term by less than 2.5e-4 that is not reproduced. Under
// AxialModulus::kNegativeVoxel (bonds the authors' simulator treats as homogeneous: no split)
// the voxel's own E times the bond strain is used.
double pressure_stimulus(const Model& m, const State& s, const Workspace& w, int i) {
  const bool split = m.def.axial_modulus == AxialModulus::kHarmonicMean;
  const std::vector<double>& per_bond = split ? w.bond_stress : w.bond_strain;
  double sum = 0;
  for (int axis = 0; axis < 3; ++axis) {
    const int neg = m.voxel_bonds[i][axis * 2], pos = m.voxel_bonds[i][axis * 2 + 1];
    if (neg >= 0 && pos >= 0) {
      sum += 0.5 * (per_bond[neg] + per_bond[pos]);
    } else if (neg >= 0 || pos >= 0) {
      sum += per_bond[neg >= 0 ? neg : pos];
    }
  }
  const double nu = m.def.poisson;
  const double stress_sum = split ? sum : s.stiffness[i] * sum;
  return -stress_sum / (3.0 * (1.0 - 2.0 * nu));
}

}  // namespace

void develop(const Model& m, State& s, Workspace& w) {
  const PhysicsDef& d = m.def;
  w.stiffness_changed = false;
  if (d.treatment == Treatment::kNone || s.time < d.settle_time) return;
  const bool stress = d.treatment == Treatment::kStress;
  const bool first = !s.stim_ref_set;
  const double gate = d.min_devo_factor * d.e_min;
  for (int i = 0; i < m.n; ++i) {
    const double stim = stress ? stress_stimulus(m, w, i) : pressure_stimulus(m, s, w, i);
    s.stimulus[i] = stim;
    if (first) s.stim_ref[i] = stim;
    const double e = s.stiffness[i];
    // Soft voxels never develop; a voxel softened to the gate stops for good.
    if (!(e > gate) || m.alpha[i] == 0) continue;
    double target;
    if (d.growth == GrowthModel::kIntegral) {
      s.stim_integral[i] += stim * s.dt;
      target = m.e0[i] + m.alpha[i] * s.stim_integral[i];
    } else {
      target = m.e0[i] + m.alpha[i] * (stim - s.stim_ref[i]);
    }
    const double change = std::clamp(target - e, -d.max_change_per_step, d.max_change_per_step);
    const double next = std::clamp(e + change, d.e_min, d.e_max);
    if (next != e) {
      s.stiffness[i] = next;
      w.stiffness_changed = true;
    }
  }
  s.stim_ref_set = true;
}

}  // namespace plastivox
