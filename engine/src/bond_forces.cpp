// Bond stage: the elastic and damping forces of every beam bond between face neighbours.
//
// Each bond is an Euler-Bernoulli beam of nominal length L and square section L x L
// joining two voxel centres. Forces are computed in a "bond frame": voxel a's body frame,
// cyclically permuted so the bond's lattice axis is +x, then rotated (q1) so the chord
// from a to b lies on +x. In that frame the chord carries only the axial extension and
// the two voxels' rotation vectors carry shear, bending and torsion; this form stays
// accurate for large rotations, unlike small-angle beam formulas in the lattice frame.
//
// Restoring forces and moments on the two ends (x = chord, theta1/theta2 = rotation
// vectors of a and b, b1..b3 and a2 the beam constants):
//   F_a = ( sigma*A,  -b2 (th1z + th2z),  b2 (th1y + th2y) ),  F_b = -F_a
//   M_a = ( a2 (th2x - th1x), -b3 (2 th1y + th2y), -b3 (2 th1z + th2z) )
//   M_b = ( a2 (th1x - th2x), -b3 (th1y + 2 th2y), -b3 (th1z + 2 th2z) )
// with a2 = G J / L, b2 = 6 E I / L^2, b3 = 2 E I / L, I = L^4/12, J = L^4/6.
// Damping mirrors these with each stiffness k replaced by a critical coefficient
// 2 sqrt(k m) (2 sqrt(k I) for rotations) times the bond damping ratio, acting on the
// rate of the same deformations (finite difference of the bond-frame deformation, half
// of it attributed to each end), so rigid motion of the whole bond is never damped.
#include <cmath>

#include "plastivox/energy.hpp"
#include "workspace.hpp"

namespace plastivox {
namespace {

// Cyclic permutation taking lattice axis d onto x; a proper rotation, so it applies to
// rotation vectors as well as positions.
inline Vec3 to_bond(int d, const Vec3& v) {
  if (d == 0) return v;
  if (d == 1) return Vec3(v.y(), v.z(), v.x());
  return Vec3(v.z(), v.x(), v.y());
}
inline Vec3 from_bond(int d, const Vec3& v) {
  if (d == 0) return v;
  if (d == 1) return Vec3(v.z(), v.x(), v.y());
  return Vec3(v.y(), v.z(), v.x());
}

// Rotation vector (axis * angle, rad) of a unit quaternion, taking the shorter arc.
inline Vec3 rotation_vector(const Quat& q) {
  const double sign = q.w() < 0 ? -1.0 : 1.0;
  const Vec3 v = sign * q.vec();
  const double s = v.norm();
  if (s < 1e-12) return 2.0 * v;  // small-angle limit of 2 atan2(s, w) / s
  return v * (2.0 * std::atan2(s, sign * q.w()) / s);
}

// The deformation of one bond, in its aligned bond frame.
struct BondGeometry {
  int axis;
  Quat q1;        // rotation from the permuted body frame of a to the aligned frame
  Vec3 th1, th2;  // rotation vectors of a and b in the aligned frame, rad
  double ext;     // chord length minus actuated rest length, m
};

inline BondGeometry bond_geometry(const Model& m, const State& s, const std::vector<double>& size,
                                  int b) {
  const int ia = m.bond_a[b], ib = m.bond_b[b], d = m.bond_axis[b];
  const Quat qa_inv = s.orient[ia].conjugate();
  const Vec3 r = to_bond(d, qa_inv * (s.pos[ib] - s.pos[ia]));
  const Quat qrel = qa_inv * s.orient[ib];
  const Vec3 qrel_v = to_bond(d, qrel.vec());
  const Quat q2(qrel.w(), qrel_v.x(), qrel_v.y(), qrel_v.z());
  // Rotation q1 that takes the chord r onto +x (half-way quaternion between them).
  const double len = r.norm();
  Quat q1(len + r.x(), 0.0, r.z(), -r.y());
  q1.normalize();
  // Extension is measured from the actuated rest length (mean of the two current sizes).
  return {d, q1, rotation_vector(q1), rotation_vector(q1 * q2), len - 0.5 * (size[ia] + size[ib])};
}

}  // namespace

double elastic_energy(const Model& m, const State& s, const std::vector<double>& size) {
  const double L = m.size, nu = m.def.poisson;
  const bool axial_own = m.def.axial_modulus == AxialModulus::kNegativeVoxel;
  double u = 0;
  for (int b = 0; b < m.bond_count(); ++b) {
    const BondGeometry g = bond_geometry(m, s, size, b);
    const double ea = s.stiffness[m.bond_a[b]], eb = s.stiffness[m.bond_b[b]];
    const double e = 2.0 * ea * eb / (ea + eb);
    const double a1 = (axial_own ? ea : e) * L;
    const double a2 = e * L * L * L / (12.0 * (1.0 + nu));
    const double b3 = e * L * L * L / 6.0;
    const Vec3& t1 = g.th1;
    const Vec3& t2 = g.th2;
    u += 0.5 * a1 * g.ext * g.ext + 0.5 * a2 * (t2.x() - t1.x()) * (t2.x() - t1.x()) +
         b3 * (t1.y() * t1.y() + t1.y() * t2.y() + t2.y() * t2.y()) +
         b3 * (t1.z() * t1.z() + t1.z() * t2.z() + t2.z() * t2.z());
  }
  return u;
}

void compute_bond_forces(const Model& m, State& s, Workspace& w) {
  const double L = m.size;
  const double area = L * L;
  const double nu = m.def.poisson;
  // Damping multiplier 2 sqrt(m) zeta / dt: turns sqrt(k) * (deformation change) into a
  // critical-fraction damping force.
  const double damp = 2.0 * std::sqrt(m.mass) * m.def.bond_damping / s.dt;
  const bool have_prev = s.bond_prev_valid;
  const bool axial_own = m.def.axial_modulus == AxialModulus::kNegativeVoxel;

  for (int b = 0; b < m.bond_count(); ++b) {
    const int ia = m.bond_a[b], ib = m.bond_b[b];
    const BondGeometry g = bond_geometry(m, s, w.size, b);
    const int d = g.axis;
    const Quat& q1 = g.q1;
    const Vec3& th1 = g.th1;
    const Vec3& th2 = g.th2;
    const double ext = g.ext;
    // As in Voxelyze 0.9, strain is the extension over the nominal length L.
    const double strain = ext / L;
    const double ea = s.stiffness[ia], eb = s.stiffness[ib];
    const double e = 2.0 * ea * eb / (ea + eb);  // harmonic mean: two springs in series
    const double stress = (axial_own ? ea : e) * strain;
    w.bond_strain[b] = strain;
    w.bond_stress[b] = stress;

    const double a2 = e * L * L * L / (12.0 * (1.0 + nu));
    const double b2 = e * L * L / 2.0;  // 6 E I / L^2, for the damping coefficients
    const double b3 = e * L * L * L / 6.0;
    // Shear force from end rotations: 3 b3 / chord rather than Voxelyze's b2 = 3 b3 / L.
    // The two agree at rest length; this one makes the forces the exact gradient of the
    // bending energy and the bond's moments balance its forces (angular momentum is then
    // conserved), which matters once bonds stretch or actuate by several percent.
    const double b2c = 3.0 * b3 / (g.ext + 0.5 * (w.size[ia] + w.size[ib]));
    Vec3 f(stress * area, -b2c * (th1.z() + th2.z()), b2c * (th1.y() + th2.y()));
    Vec3 ma(a2 * (th2.x() - th1.x()), -b3 * (2 * th1.y() + th2.y()), -b3 * (2 * th1.z() + th2.z()));
    Vec3 mb(a2 * (th1.x() - th2.x()), -b3 * (th1.y() + 2 * th2.y()), -b3 * (th1.z() + 2 * th2.z()));

    if (have_prev) {
      const double dx = 0.5 * (ext - s.bond_prev_pos[b].x());
      const Vec3 d1 = 0.5 * (th1 - s.bond_prev_rot1[b]);
      const Vec3 d2 = 0.5 * (th2 - s.bond_prev_rot2[b]);
      const double sq_a1 = std::sqrt(e * L);
      const double sq_b2 = std::sqrt(b2 * L / 2.0);
      const double sq_a2 = std::sqrt(a2 * L * L / 6.0);
      const double sq_b3 = std::sqrt(b3 * L * L / 6.0);
      f += damp * Vec3(sq_a1 * dx, -sq_b2 * (d1.z() + d2.z()), sq_b2 * (d1.y() + d2.y()));
      const double half = 0.5 * damp;
      ma += half * Vec3(sq_a2 * (d2.x() - d1.x()), -sq_b3 * (2 * d1.y() + d2.y()),
                        -sq_b3 * (2 * d1.z() + d2.z()));
      mb += half * Vec3(sq_a2 * (d1.x() - d2.x()), -sq_b3 * (d1.y() + 2 * d2.y()),
                        -sq_b3 * (d1.z() + 2 * d2.z()));
    }
    s.bond_prev_pos[b] = Vec3(ext, 0.0, 0.0);
    s.bond_prev_rot1[b] = th1;
    s.bond_prev_rot2[b] = th2;

    // Back from the aligned bond frame to world: undo q1, undo the permutation, apply qa.
    const Quat q1_inv = q1.conjugate();
    const Quat& qa = s.orient[ia];
    w.bond_force_a[b] = qa * from_bond(d, q1_inv * f);
    w.bond_moment_a[b] = qa * from_bond(d, q1_inv * ma);
    w.bond_moment_b[b] = qa * from_bond(d, q1_inv * mb);
  }
  s.bond_prev_valid = true;
}

}  // namespace plastivox
