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

// The deformation of one bond in its bond frame. Two frames are used:
//  - chord-aligned ("large angle"): voxel a's permuted frame rotated by q1 so the chord lies
//    on +x; then p = (extension, 0, 0) and both voxels carry rotation vectors th1, th2;
//  - voxel-aligned ("small angle", Voxelyze 0.9 only): voxel a's permuted frame itself;
//    th1 = 0 and p = r - (rest, 0, 0) keeps the transverse offset.
struct BondGeometry {
  int axis;
  Quat frame;     // rotation from the permuted body frame of a to the bond frame
  Vec3 p;         // position of b relative to its rest place, m, bond frame
  Vec3 th1, th2;  // rotation vectors of a and b, rad, bond frame
  Vec3 r;         // chord from a to b in the permuted frame of a, m
  double rest;    // actuated rest length, m
  Quat q2;        // rotation of b relative to a, permuted frame
};

inline BondGeometry bond_geometry(const Model& m, const State& s, const std::vector<double>& size,
                                  int b, bool small_angle) {
  const int ia = m.bond_a[b], ib = m.bond_b[b], d = m.bond_axis[b];
  BondGeometry g;
  g.axis = d;
  const Quat qa_inv = s.orient[ia].conjugate();
  g.r = to_bond(d, qa_inv * (s.pos[ib] - s.pos[ia]));
  const Quat qrel = qa_inv * s.orient[ib];
  const Vec3 qrel_v = to_bond(d, qrel.vec());
  g.q2 = Quat(qrel.w(), qrel_v.x(), qrel_v.y(), qrel_v.z());
  // Extension is measured from the actuated rest length (mean of the two current sizes).
  g.rest = 0.5 * (size[ia] + size[ib]);
  if (small_angle) {
    g.frame = Quat::Identity();
    g.p = g.r - Vec3(g.rest, 0.0, 0.0);
    g.th1 = Vec3::Zero();
    g.th2 = rotation_vector(g.q2);
  } else {
    // Rotation that takes the chord r onto +x (half-way quaternion between them).
    const double len = g.r.norm();
    g.frame = Quat(len + g.r.x(), 0.0, g.r.z(), -g.r.y());
    g.frame.normalize();
    g.p = Vec3(len - g.rest, 0.0, 0.0);
    g.th1 = rotation_vector(g.frame);
    g.th2 = rotation_vector(g.frame * g.q2);
  }
  return g;
}

// Voxelyze 0.9's switch between the two frames, with hysteresis: small-angle while the
// relative rotation, the chord's turn and the extension all stay small.
inline bool next_small_angle(const BondGeometry& g, bool small_now) {
  constexpr double kSmallAngle = 0.01732;  // rad
  constexpr double kBendTurn = 0.05;       // (|y| + |z|) / x
  constexpr double kExtension = 1.3;       // x / rest
  constexpr double kHysteresis = 1.1;
  const double w = std::min(1.0, std::abs(g.q2.w()));
  const double angle = 2.0 * std::acos(w);
  const double turn = (std::abs(g.r.y()) + std::abs(g.r.z())) / g.r.x();
  const double extend = g.r.x() / g.rest;
  if (small_now) {
    return !(angle >= kHysteresis * kSmallAngle || !(turn <= kHysteresis * kBendTurn) ||
             extend > kHysteresis * kExtension);
  }
  return angle < kSmallAngle && turn >= 0 && turn < kBendTurn && extend < kExtension;
}

}  // namespace

double elastic_energy(const Model& m, const State& s, const std::vector<double>& size) {
  const double L = m.size, nu = m.def.poisson;
  const bool axial_own = m.def.axial_modulus == AxialModulus::kNegativeVoxel;
  double u = 0;
  for (int b = 0; b < m.bond_count(); ++b) {
    const BondGeometry g = bond_geometry(m, s, size, b, false);
    const double ea = s.stiffness[m.bond_a[b]], eb = s.stiffness[m.bond_b[b]];
    const double e = 2.0 * ea * eb / (ea + eb);
    const double a1 = (axial_own ? ea : e) * L;
    const double a2 = e * L * L * L / (12.0 * (1.0 + nu));
    const double b3 = e * L * L * L / 6.0;
    const Vec3& t1 = g.th1;
    const Vec3& t2 = g.th2;
    u += 0.5 * a1 * g.p.x() * g.p.x() + 0.5 * a2 * (t2.x() - t1.x()) * (t2.x() - t1.x()) +
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
  const bool axial_own = m.def.axial_modulus == AxialModulus::kNegativeVoxel;
  const bool voxelyze = m.def.bond_model == BondModel::kVoxelyze09;

  for (int b = 0; b < m.bond_count(); ++b) {
    const int ia = m.bond_a[b], ib = m.bond_b[b];
    bool small = s.bond_small_angle[b] != 0;
    bool damp_ok = s.bond_prev_valid[b] != 0;
    BondGeometry g = bond_geometry(m, s, w.size, b, small);
    if (voxelyze) {
      const bool next = next_small_angle(g, small);
      if (next != small) {
        // Switching frames: deformation rates are undefined this step (no damping, and the
        // previous deformation is not refreshed), as in Voxelyze 0.9.
        small = next;
        s.bond_small_angle[b] = small ? 1 : 0;
        g = bond_geometry(m, s, w.size, b, small);
        damp_ok = false;
      }
    }
    const Vec3& p = g.p;
    const Vec3& th1 = g.th1;
    const Vec3& th2 = g.th2;
    // As in Voxelyze 0.9, strain is the extension over the nominal length L.
    const double strain = p.x() / L;
    const double ea = s.stiffness[ia], eb = s.stiffness[ib];
    const double e = 2.0 * ea * eb / (ea + eb);  // harmonic mean: two springs in series
    const double stress = (axial_own ? ea : e) * strain;
    w.bond_strain[b] = strain;
    w.bond_stress[b] = stress;

    const double a2 = e * L * L * L / (12.0 * (1.0 + nu));
    const double b1 = e * L;            // 12 E I / L^3
    const double b2 = e * L * L / 2.0;  // 6 E I / L^2
    const double b3 = e * L * L * L / 6.0;
    // Shear force from end rotations. Voxelyze uses b2 = 3 b3 / L; the exact model uses
    // 3 b3 / chord, which makes the forces the gradient of the bending energy and the
    // bond's moments balance its forces (angular momentum is conserved) once bonds stretch
    // or actuate by several percent. The two agree at rest length.
    const double b2c = voxelyze ? b2 : 3.0 * b3 / (p.x() + g.rest);
    Vec3 f(stress * area, b1 * p.y() - b2c * (th1.z() + th2.z()),
           b1 * p.z() + b2c * (th1.y() + th2.y()));
    Vec3 ma(a2 * (th2.x() - th1.x()), -b2 * p.z() - b3 * (2 * th1.y() + th2.y()),
            b2 * p.y() - b3 * (2 * th1.z() + th2.z()));
    Vec3 mb(a2 * (th1.x() - th2.x()), -b2 * p.z() - b3 * (th1.y() + 2 * th2.y()),
            b2 * p.y() - b3 * (th1.z() + 2 * th2.z()));

    if (damp_ok) {
      // Half of the deformation change is attributed to each end.
      const Vec3 dp = 0.5 * (p - s.bond_prev_pos[b]);
      const Vec3 d1 = 0.5 * (th1 - s.bond_prev_rot1[b]);
      const Vec3 d2 = 0.5 * (th2 - s.bond_prev_rot2[b]);
      const double sq_a1 = std::sqrt(e * L);
      const double sq_b1 = std::sqrt(b1);
      const double sq_b2 = std::sqrt(b2 * L / 2.0);
      const double sq_a2 = std::sqrt(a2 * L * L / 6.0);
      const double sq_b3 = std::sqrt(b3 * L * L / 6.0);
      f += damp * Vec3(sq_a1 * dp.x(), sq_b1 * dp.y() - sq_b2 * (d1.z() + d2.z()),
                       sq_b1 * dp.z() + sq_b2 * (d1.y() + d2.y()));
      const double half = 0.5 * damp;
      ma += half * Vec3(sq_a2 * (d2.x() - d1.x()), -sq_b2 * dp.z() - sq_b3 * (2 * d1.y() + d2.y()),
                        sq_b2 * dp.y() - sq_b3 * (2 * d1.z() + d2.z()));
      mb += half * Vec3(sq_a2 * (d1.x() - d2.x()), -sq_b2 * dp.z() - sq_b3 * (d1.y() + 2 * d2.y()),
                        sq_b2 * dp.y() - sq_b3 * (d1.z() + 2 * d2.z()));
    }
    if (damp_ok || !s.bond_prev_valid[b]) {
      s.bond_prev_pos[b] = p;
      s.bond_prev_rot1[b] = th1;
      s.bond_prev_rot2[b] = th2;
    }
    s.bond_prev_valid[b] = 1;

    // Back from the bond frame to world: undo the frame, undo the permutation, apply qa.
    const Quat frame_inv = g.frame.conjugate();
    const Quat& qa = s.orient[ia];
    const int d = g.axis;
    w.bond_force_a[b] = qa * from_bond(d, frame_inv * f);
    w.bond_moment_a[b] = qa * from_bond(d, frame_inv * ma);
    w.bond_moment_b[b] = qa * from_bond(d, frame_inv * mb);
  }
}

}  // namespace plastivox
