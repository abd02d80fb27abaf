// Bond stage: the elastic and damping forces of every beam bond between face neighbours.
//
// Each bond is an Euler-Bernoulli beam of nominal length L and square section L x L
// joining two voxel centres. Forces are computed in a "bond axes": voxel a's body axes,
// cyclically permuted so the bond's lattice axis is +x, then (in the chord-aligned form)
// rotated so the chord from a to b lies on +x. In that frame the chord carries only the
// axial extension and the two voxels' rotation vectors carry shear, bending and torsion;
// this form stays accurate for large rotations.
//
// Restoring forces and moments on the two ends (p = position of b relative to its rest
// place, th1/th2 = rotation vectors of a and b, b1..b3 and a2 the beam constants):
//   F_a = ( sigma A, b1 p_y - b2 (th1z + th2z), b1 p_z + b2 (th1y + th2y) ),  F_b = -F_a
//   M_a = ( a2 (th2x - th1x), -b2 p_z - b3 (2 th1y + th2y),  b2 p_y - b3 (2 th1z + th2z) )
//   M_b = ( a2 (th1x - th2x), -b2 p_z - b3 (th1y + 2 th2y),  b2 p_y - b3 (th1z + 2 th2z) )
// with a2 = G J / L, b1 = 12 E I / L^3, b2 = 6 E I / L^2, b3 = 2 E I / L, I = L^4/12,
// J = L^4/6. Damping mirrors these with each stiffness k replaced by a critical
// coefficient 2 sqrt(k m) (2 sqrt(k I) for rotations) times the bond damping ratio, acting
// on the rate of the same deformations (finite difference of the bond-frame deformation,
// half of it attributed to each end), so rigid motion of the whole bond is never damped.
//
// The exact model's bonds run in the batched kernel (bond_body.hpp), most of a step's
// time; this file holds the stage that drives it and the scalar path (scalar_bond_body.hpp, a
// template the gradient's replica runs too), which serves the Voxelyze 0.9 model and the few
// bonds the kernel hands back.
#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstring>

#include "kernels.hpp"
#include "plastivox/energy.hpp"
#include "scalar_bond_body.hpp"
#include "workspace.hpp"

namespace plastivox {

double elastic_energy(const Model& m, const State& s) {
  const ModelConstants& k = m;
  double u = 0;
  for (int b = 0; b < m.bond_count(); ++b) {
    const int ia = m.bond_a[b], ib = m.bond_b[b];
    const Eigen::Matrix3d R = s.orient[ia].toRotationMatrix();
    const double dl[3] = {s.pos[ib].x() - s.pos[ia].x(), s.pos[ib].y() - s.pos[ia].y(),
                          s.pos[ib].z() - s.pos[ia].z()};
    const BondGeometry<double> g =
        bond_geometry(m.bond_axis[b], R.data(), dl, s.orient[ia].coeffs().data(),
                      s.orient[ib].coeffs().data(), s.size[ia], s.size[ib], false, false);
    const double ea = s.stiffness[ia], eb = s.stiffness[ib];
    const double e = 2.0 * ea * eb / (ea + eb);
    const double a1 = (k.axial_own ? ea : e) * k.kb1;
    const double a2 = e * k.ka2;
    const double b3 = e * k.kb3;
    const BondV3<double>& t1 = g.th1;
    const BondV3<double>& t2 = g.th2;
    u += 0.5 * a1 * g.p.x * g.p.x + 0.5 * a2 * (t2.x - t1.x) * (t2.x - t1.x) +
         b3 * (t1.y * t1.y + t1.y * t2.y + t2.y * t2.y) +
         b3 * (t1.z * t1.z + t1.z * t2.z + t2.z * t2.z);
  }
  return u;
}

void bind_bond_views(const Model& m, Workspace& w) {
  static_assert(sizeof(Vec3) == 3 * sizeof(double) && sizeof(Quat) == 4 * sizeof(double));
  BondKernelIo& io = w.views.bond;
  io.bond_a = m.bond_a.data();
  io.bond_b = m.bond_b.data();
  io.axis_wide = w.bond_axis_wide.data();
  io.centre_size = w.centre_size.data();
  // Each step sets whether every bond has a previous deformation and chooses where the next
  // ones go (compute_bond_forces).
  io.all_valid = false;
  for (int k = 0; k < 9; ++k) io.prev_next[k] = w.bond_prev_next[k].data();
  w.views.small_angle_next = w.bond_small_angle_next.data();
  for (int v = 0; v < 3; ++v) io.out[v] = w.bond_out[v].data();
  io.strain = w.bond_strain.data();
  io.stress = w.bond_stress.data();
  io.energy = w.bond_energy.empty() ? nullptr : w.bond_energy.data();
  io.redo = w.redo.data();
}

// Exact model: the batched kernel reads the voxels and writes every bond's results; the
// few bonds it cannot handle (degenerate chords, rotations near half a turn) are redone in
// scalar code. Voxelyze 0.9 model: the scalar path for every bond (its switch of axes).
// The State is read only: each bond's deformation (and frame) for the next step goes to the
// Workspace, and step2 commits it (commit_bond_deformation); or, with next_into_state, into
// the State's arrays, through the views (each bond's are read before they are written).
void compute_bond_forces(const Model& m, const State& s, Workspace& w, bool next_into_state) {
  KernelViews& v = w.views;
  w.bonds_next_in_state = next_into_state;
  for (int k = 0; k < 9; ++k)
    v.bond.prev_next[k] = next_into_state ? v.prev_in_state[k] : w.bond_prev_next[k].data();
  v.small_angle_next = next_into_state ? v.small_angle_in_state : w.bond_small_angle_next.data();
  // Centres and sizes as records of 4 doubles: the bond kernel's and the self-collision
  // test's inputs (positions and sizes do not change until the update stage; why a second
  // layout: Workspace::centre_size).
  for (int i = 0; i < m.n; ++i) {
    double* r = &w.centre_size[4 * static_cast<size_t>(i)];
    r[0] = s.pos[i].x(), r[1] = s.pos[i].y(), r[2] = s.pos[i].z(), r[3] = s.size[i];
  }
  const int nb = m.bond_count();
  assert(w.bond_out[0].size() == 4 * (static_cast<size_t>(nb) + 1) &&
         w.bond_stress.size() == static_cast<size_t>(nb) + 1 &&
         "the Workspace was built for another Model: build it from the model it runs");
  // (No bonds: no array to search, and memchr must not be given a null one.)
  v.bond.all_valid =
      nb == 0 || std::memchr(s.bond_prev_valid.data(), 0, s.bond_prev_valid.size()) == nullptr;
  // Damping multiplier 2 sqrt(m) zeta / dt: turns sqrt(k) * (deformation change) into a
  // critical-fraction damping force.
  run_bond_stage(m, v, m.bond_damp / s.dt);
}

int run_bond_stage(const Model& m, KernelViews& v, double damp) {
  BondKernelIo& io = v.bond;
  const int nb = m.bond_count();
  if (m.def.bond_model == BondModel::kVoxelyze09) {
    for (int b = 0; b < nb; ++b)
      scalar_bond_lanes<double>(io, v.small_angle_in_state, v.small_angle_next, b, m, damp);
    return 0;
  }
  if (nb == 0) return 0;
  const int redo = kernels().bond(io, nb, m, damp);
  // From the unchanged previous deformation.
  for (int r = 0; r < redo; ++r)
    scalar_bond_lanes<double>(io, v.small_angle_in_state, v.small_angle_next, io.redo[r], m, damp);
  return redo;
}

// Copies, not swaps: the State's arrays keep their storage for the whole life (the kernels'
// views and Python's numpy views point into them). Nothing to copy after step(): its bond
// stage wrote them in place.
void commit_bond_deformation(const Model& m, State& s, const Workspace& w) {
  const size_t nb = static_cast<size_t>(m.bond_count());
  if (nb == 0) return;
  if (!w.bonds_next_in_state) {
    for (int k = 0; k < 9; ++k)
      std::memcpy(s.bond_prev[k].data(), w.bond_prev_next[k].data(), nb * sizeof(double));
    if (m.def.bond_model == BondModel::kVoxelyze09)
      std::memcpy(s.bond_small_angle.data(), w.bond_small_angle_next.data(), nb);
  }
  std::memset(s.bond_prev_valid.data(), 1, nb);
}

}  // namespace plastivox
