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
// time; this file holds the stage that drives it and the scalar path, which serves the
// Voxelyze 0.9 model and the few bonds the kernel hands back.
#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstring>

#include "elementary.hpp"
#include "kernels.hpp"
#include "plastivox/energy.hpp"
#include "workspace.hpp"

namespace plastivox {
namespace {

struct V3 {
  double x, y, z;
};

// Cyclic permutation taking lattice axis d onto x; a proper rotation, so it applies to
// rotation vectors as well as positions.
inline V3 to_bond(int d, double x, double y, double z) {
  if (d == 0) return {x, y, z};
  if (d == 1) return {y, z, x};
  return {z, x, y};
}
inline V3 from_bond(int d, const V3& v) {
  if (d == 0) return v;
  if (d == 1) return {v.z, v.x, v.y};
  return {v.y, v.z, v.x};
}

// Rotation vector (axis * angle, rad) of a unit quaternion, taking the shorter arc.
inline V3 rotation_vector(double w, double x, double y, double z) {
  if (w < 0) w = -w, x = -x, y = -y, z = -z;
  const double s2 = x * x + y * y + z * z;
  if (s2 == 0) return {0, 0, 0};
  // angle = 2 atan(s / w); angle / s = 2 atan(t) / (t w) with t = s / w. Near half a turn
  // (w <= 1e-3, so s ~ 1): angle = 2 (pi/2 - atan(q)) with q = w / s <= ~1e-3.
  double k;
  if (w > 1e-3) {
    const double inv_w = 1.0 / w;
    k = 2.0 * atan_over_t(s2 * (inv_w * inv_w), false) * inv_w;
  } else {
    const double s = std::sqrt(s2), q = w / s;
    k = 2.0 * (1.5707963267948966 - q * atan_series(q * q)) / s;
  }
  return {x * k, y * k, z * k};
}

// Voxelyze 0.9's SMALL_ANGLE_RAD (Vec3D.h, PREC_MED): its small-angle limit for a bond's
// relative rotation and for the chord frame's first-order form, rad.
constexpr double kVoxelyzeSmallAngle = 1.732e-2;

// The same as Voxelyze 0.9's CQuat::ToRotationVector computes it (PREC_MED): from 1 - w^2
// rather than x^2 + y^2 + z^2, so a relative rotation whose w rounds to 1 (below about 2e-8
// rad) is no rotation at all, with acos(w) ~ sqrt(2 - 2w) below about 0.1 rad and no
// shorter-arc flip.
inline V3 voxelyze_rotation_vector(double w, double x, double y, double z) {
  constexpr double kWAcos2Sqrt = 0.9988;
  constexpr double kAcos2Sqrt = 1.0 - kWAcos2Sqrt * kWAcos2Sqrt;
  const double sl = 1.0 - w * w;
  if (sl <= 0) return {0, 0, 0};
  const double wc = w > 1 ? 1 : w;
  if (sl < kAcos2Sqrt) {
    const double k = std::sqrt((2 - 2 * wc) / sl);
    return {x * 2.0 * k, y * 2.0 * k, z * 2.0 * k};
  }
  const double a = std::acos(wc), r = std::sqrt(sl);
  return {x * 2.0 * a / r, y * 2.0 * a / r, z * 2.0 * a / r};
}

// The deformation of one bond in its bond axes. Two frames are used:
//  - chord-aligned ("large angle"): voxel a's permuted frame rotated by the quaternion
//    f = (fw, 0, fy, fz) so the chord lies on +x; then p = (extension, 0, 0);
//  - voxel-aligned ("small angle", Voxelyze 0.9 only): voxel a's permuted frame itself
//    (f = identity); th1 = 0 and p = r - (rest, 0, 0) keeps the transverse offset.
struct BondGeometry {
  int axis;
  double fw, fy, fz;  // frame rotation (a quaternion with zero x part; unit but for voxelyze09's
                      // first-order frame, within 1e-8 of it)
  V3 p;               // position of b relative to its rest place, m, bond axes
  V3 th1, th2;        // rotation vectors of a and b, rad, bond axes
  V3 r;               // chord from a to b in the permuted frame of a, m
  double rest;        // actuated rest length, m
  double q2w;         // scalar part of b's rotation relative to a
};

// The chord-aligned frame as Voxelyze 0.9's CQuat::FromAngleToPosX builds it, and th1 its
// rotation vector: within 0.01732 of the axis in both y/x and z/x, the first-order
// (w, 0, z/2x, -y/2x) with w = 1 - (y^2 + z^2)/2 (not normalised: tan for sin, an error
// below 1e-4); otherwise half the angle acos(x/|r|) about the normal; a chord within 1e-7
// rad of backwards turns half a turn about y.
inline void voxelyze_frame(const V3& r, BondGeometry& g) {
  constexpr double kDiscard = 1e-7, kPi = 3.14159265358979;
  g.fw = 1, g.fy = 0, g.fz = 0;
  if (r.x == 0 && r.y == 0 && r.z == 0) {
    g.th1 = {0, 0, 0};
    return;
  }
  const double yx = r.y / r.x, zx = r.z / r.x;
  if (yx < kVoxelyzeSmallAngle && yx > -kVoxelyzeSmallAngle && zx < kVoxelyzeSmallAngle &&
      zx > -kVoxelyzeSmallAngle) {
    g.fy = 0.5 * zx, g.fz = -0.5 * yx;
    g.fw = 1 + 0.5 * (-g.fy * g.fy - g.fz * g.fz);
  } else {
    const double l = std::sqrt(r.x * r.x + r.y * r.y + r.z * r.z), li = 1.0 / l;
    const double nx = r.x * li, ny = r.y * li, nz = r.z * li;
    const double theta = std::acos(nx);
    if (theta > kPi - kDiscard) {
      g.fw = 0, g.fy = 1, g.fz = 0;
    } else {
      const double inv = 1.0 / std::sqrt(nz * nz + ny * ny), a = 0.5 * theta;
      const double sa = std::sin(a);
      g.fw = std::cos(a), g.fy = nz * inv * sa, g.fz = -ny * inv * sa;
    }
  }
  g.th1 = voxelyze_rotation_vector(g.fw, 0, g.fy, g.fz);
}

// R: voxel a's orientation as a column-major rotation matrix (R[0..2] the first column).
inline BondGeometry bond_geometry(const Model& m, const State& s, const double* R, int b,
                                  bool small_angle, bool voxelyze) {
  const auto rotvec = voxelyze ? voxelyze_rotation_vector : rotation_vector;
  const int ia = m.bond_a[b], ib = m.bond_b[b], d = m.bond_axis[b];
  BondGeometry g;
  g.axis = d;
  // Chord in a's body axes: R_a^T (p_b - p_a), then permuted.
  const double dx = s.pos[ib].x() - s.pos[ia].x();
  const double dy = s.pos[ib].y() - s.pos[ia].y();
  const double dz = s.pos[ib].z() - s.pos[ia].z();
  g.r = to_bond(d, R[0] * dx + R[1] * dy + R[2] * dz, R[3] * dx + R[4] * dy + R[5] * dz,
                R[6] * dx + R[7] * dy + R[8] * dz);
  // Rotation of b relative to a: conj(q_a) q_b, vector part permuted.
  const Quat& qa = s.orient[ia];
  const Quat& qb = s.orient[ib];
  const double aw = qa.w(), ax = qa.x(), ay = qa.y(), az = qa.z();
  const double bw = qb.w(), bx = qb.x(), by = qb.y(), bz = qb.z();
  const double qw = aw * bw + ax * bx + ay * by + az * bz;
  const V3 qv =
      to_bond(d, aw * bx - ax * bw - ay * bz + az * by, aw * by + ax * bz - ay * bw - az * bx,
              aw * bz - ax * by + ay * bx - az * bw);
  g.q2w = qw;
  // Extension is measured from the actuated rest length (mean of the two current sizes).
  g.rest = 0.5 * (s.size[ia] + s.size[ib]);
  if (small_angle) {
    g.fw = 1, g.fy = 0, g.fz = 0;
    g.p = {g.r.x - g.rest, g.r.y, g.r.z};
    g.th1 = {0, 0, 0};
    g.th2 = rotvec(qw, qv.x, qv.y, qv.z);
    return g;
  }
  // f takes the chord onto +x: the half-way quaternion (len + r_x, 0, r_z, -r_y), whose
  // norm is sqrt(2 len (len + r_x)).
  const V3& r = g.r;
  const double len = std::sqrt(r.x * r.x + r.y * r.y + r.z * r.z);
  const double h = len + r.x;
  g.p = {len - g.rest, 0, 0};
  if (voxelyze) {
    voxelyze_frame(r, g);
  } else if (h > 1e-6 * len) {
    const double inv_n = 1.0 / std::sqrt(2.0 * len * h);
    g.fw = h * inv_n, g.fy = r.z * inv_n, g.fz = -r.y * inv_n;
    // th1 = rotation vector of f; the tangent of its half angle is |(r_y, r_z)| / h.
    const double inv_h = 1.0 / h;
    const double k1 = 2.0 * atan_over_t((r.y * r.y + r.z * r.z) * (inv_h * inv_h), false) * inv_h;
    g.th1 = {0, r.z * k1, -r.y * k1};
  } else {
    // The chord points (almost) backwards, or the centres coincide: a crushed or inverted
    // bond. Any rotation onto +x will do; half a turn about z keeps the numbers finite.
    g.fw = 0, g.fy = 0, g.fz = 1;
    g.th1 = {0, 0, M_PI};
  }
  // th2 = rotation vector of f * q2 (f has no x part).
  const double fw = g.fw, fy = g.fy, fz = g.fz;
  g.th2 = rotvec(fw * qw - fy * qv.y - fz * qv.z, fw * qv.x + fy * qv.z - fz * qv.y,
                 fw * qv.y + qw * fy + fz * qv.x, fw * qv.z + qw * fz - fy * qv.x);
  return g;
}

// Voxelyze 0.9's switch between the two frames, with hysteresis: small-angle while the
// relative rotation, the chord's turn and the extension all stay small.
// The turn is computed as the authors' evolution build computed it. Its source writes
// (abs(y) + abs(z)) / x, but that build's abs took an int: each offset, in metres, is
// truncated towards zero first (the two cvttsd2si of CVXS_BondInternal::CalcLinForce in the
// fork's shipped VXS_BondInternal.o). A bond's offsets are far below a metre, so the turn is
// 0 and never switches a bond; only the rotation and the extension do. Linking the fork's
// own library into a trace harness and rebuilding its source with the truncation both give
// the settling cube's published fall (docs/vxa.md); with a real |y| + |z| the cube falls the
// other way.
inline bool next_small_angle(const BondGeometry& g, bool small_now) {
  constexpr double kBendTurn = 0.05;  // (|y| + |z|) / x
  constexpr double kExtension = 1.3;  // x / rest
  constexpr double kHysteresis = 1.1;
  const double angle = 2.0 * std::acos(std::min(1.0, std::abs(g.q2w)));
  const double turn = (std::abs(std::trunc(g.r.y)) + std::abs(std::trunc(g.r.z))) / g.r.x;
  const double extend = g.r.x / g.rest;
  if (small_now) {
    return !(angle >= kHysteresis * kVoxelyzeSmallAngle || !(turn <= kHysteresis * kBendTurn) ||
             extend > kHysteresis * kExtension);
  }
  return angle < kVoxelyzeSmallAngle && turn >= 0 && turn < kBendTurn && extend < kExtension;
}

// v expressed in the bond axes -> world: undo the frame rotation f (apply f^T), undo the
// permutation, apply a's orientation.
inline Vec3 to_world(const BondGeometry& g, const double* R, const V3& v) {
  const double w = g.fw, y = g.fy, z = g.fz;
  const V3 u{(1 - 2 * (y * y + z * z)) * v.x + 2 * w * z * v.y - 2 * w * y * v.z,
             -2 * w * z * v.x + (1 - 2 * z * z) * v.y + 2 * y * z * v.z,
             2 * w * y * v.x + 2 * y * z * v.y + (1 - 2 * y * y) * v.z};
  const V3 o = from_bond(g.axis, u);
  return Vec3(R[0] * o.x + R[3] * o.y + R[6] * o.z, R[1] * o.x + R[4] * o.y + R[7] * o.z,
              R[2] * o.x + R[5] * o.y + R[8] * o.z);
}

}  // namespace

double elastic_energy(const Model& m, const State& s) {
  const ModelConstants& k = m;
  double u = 0;
  for (int b = 0; b < m.bond_count(); ++b) {
    const Eigen::Matrix3d R = s.orient[m.bond_a[b]].toRotationMatrix();
    const BondGeometry g = bond_geometry(m, s, R.data(), b, false, false);
    const double ea = s.stiffness[m.bond_a[b]], eb = s.stiffness[m.bond_b[b]];
    const double e = 2.0 * ea * eb / (ea + eb);
    const double a1 = (k.axial_own ? ea : e) * k.kb1;
    const double a2 = e * k.ka2;
    const double b3 = e * k.kb3;
    const V3& t1 = g.th1;
    const V3& t2 = g.th2;
    u += 0.5 * a1 * g.p.x * g.p.x + 0.5 * a2 * (t2.x - t1.x) * (t2.x - t1.x) +
         b3 * (t1.y * t1.y + t1.y * t2.y + t2.y * t2.y) +
         b3 * (t1.z * t1.z + t1.z * t2.z + t2.z * t2.z);
  }
  return u;
}

namespace {

// The scalar path: every bond under the Voxelyze 0.9 model, and under the exact model the
// few bonds the batched kernel flags (large rotations, degenerate chords). Reads the State;
// what the next step inherits (the deformation, the frame) goes to the Workspace.
void scalar_bond(const Model& m, const State& s, Workspace& w, int b) {
  const ModelConstants& mk = m;
  // Damping multiplier 2 sqrt(m) zeta / dt: turns sqrt(k) * (deformation change) into a
  // critical-fraction damping force.
  const double damp = mk.bond_damp / s.dt;
  const bool voxelyze = m.def.bond_model == BondModel::kVoxelyze09;
  const int ia = m.bond_a[b], ib = m.bond_b[b];
  bool small = s.bond_small_angle[b] != 0;
  bool damp_ok = s.bond_prev_valid[b] != 0;
  const Eigen::Matrix3d rot = s.orient[ia].toRotationMatrix();
  const double* R = rot.data();
  BondGeometry g = bond_geometry(m, s, R, b, small, voxelyze);
  if (voxelyze) {
    const bool next = next_small_angle(g, small);
    if (next != small) {
      // Switching frames: deformation rates are undefined this step (no damping, and the
      // previous deformation is not refreshed), as in Voxelyze 0.9.
      small = next;
      g = bond_geometry(m, s, R, b, small, voxelyze);
      damp_ok = false;
    }
    w.views.small_angle_next[b] = small ? 1 : 0;
  }
  const V3& p = g.p;
  const V3& t1 = g.th1;
  const V3& t2 = g.th2;
  // As in Voxelyze 0.9, strain is the extension over the nominal length L.
  const double strain = p.x * mk.inv_L;
  const double ea = s.stiffness[ia], eb = s.stiffness[ib];
  const double e = 2.0 * ea * eb / (ea + eb);  // harmonic mean: two springs in series
  const double stress = (mk.axial_own ? ea : e) * strain;
  w.bond_strain[b] = strain;
  w.bond_stress[b] = stress;
  if (!w.bond_energy.empty()) w.bond_energy[b] = stress * strain;

  const double a2 = e * mk.ka2, b1 = e * mk.kb1, b2 = e * mk.kb2, b3 = e * mk.kb3;
  // Shear force from end rotations. Voxelyze uses b2 = 3 b3 / L; the exact model uses
  // 3 b3 / chord, which makes the forces the gradient of the bending energy and the
  // bond's moments balance its forces (angular momentum is conserved) once bonds stretch
  // or actuate by several percent. The two agree at rest length. The chord is floored at
  // min_shear_chord (kMinShearChord L, compile.cpp): as a crushed bond's centres meet,
  // 1/chord (a transverse displacement turns a short chord by a large angle) would grow
  // without bound.
  const double b2c = voxelyze ? b2 : 3.0 * b3 / std::max(p.x + g.rest, mk.min_shear_chord);
  V3 f{stress * mk.area, b1 * p.y - b2c * (t1.z + t2.z), b1 * p.z + b2c * (t1.y + t2.y)};
  V3 ma{a2 * (t2.x - t1.x), -b2 * p.z - b3 * (2 * t1.y + t2.y), b2 * p.y - b3 * (2 * t1.z + t2.z)};
  V3 mb{a2 * (t1.x - t2.x), -b2 * p.z - b3 * (t1.y + 2 * t2.y), b2 * p.y - b3 * (t1.z + 2 * t2.z)};

  const auto& P = s.bond_prev;
  const Vec3 prev_p(P[0][b], P[1][b], P[2][b]);
  const Vec3 prev_1(P[3][b], P[4][b], P[5][b]);
  const Vec3 prev_2(P[6][b], P[7][b], P[8][b]);
  if (damp_ok) {
    // Half of the deformation change is attributed to each end.
    const V3 dp{0.5 * (p.x - prev_p.x()), 0.5 * (p.y - prev_p.y()), 0.5 * (p.z - prev_p.z())};
    const V3 d1{0.5 * (t1.x - prev_1.x()), 0.5 * (t1.y - prev_1.y()), 0.5 * (t1.z - prev_1.z())};
    const V3 d2{0.5 * (t2.x - prev_2.x()), 0.5 * (t2.y - prev_2.y()), 0.5 * (t2.z - prev_2.z())};
    // Every coefficient is sqrt(E) times a geometric constant (ModelConstants).
    const double se = std::sqrt(e) * damp;
    const double c_a1 = se * mk.damp_a1, c_b1 = c_a1, c_b2 = se * mk.damp_b2;
    const double c_a2 = 0.5 * se * mk.damp_a2, c_b3 = 0.5 * se * mk.damp_b3;
    const double c_b2h = 0.5 * c_b2;
    f.x += c_a1 * dp.x;
    f.y += c_b1 * dp.y - c_b2 * (d1.z + d2.z);
    f.z += c_b1 * dp.z + c_b2 * (d1.y + d2.y);
    ma.x += c_a2 * (d2.x - d1.x);
    ma.y += -c_b2h * dp.z - c_b3 * (2 * d1.y + d2.y);
    ma.z += c_b2h * dp.y - c_b3 * (2 * d1.z + d2.z);
    mb.x += c_a2 * (d1.x - d2.x);
    mb.y += -c_b2h * dp.z - c_b3 * (d1.y + 2 * d2.y);
    mb.z += c_b2h * dp.y - c_b3 * (d1.z + 2 * d2.z);
  }
  // The deformation the next step damps against: this one, unless the bond switched frames
  // with a deformation recorded (then the recorded one stays, as in Voxelyze 0.9). Every bond
  // has one recorded after the step (commit_bond_deformation).
  const double now[9] = {p.x, p.y, p.z, t1.x, t1.y, t1.z, t2.x, t2.y, t2.z};
  const bool refresh = damp_ok || !s.bond_prev_valid[b];
  double* const* next = w.views.bond.prev_next;  // may be P itself (compute_bond_forces)
  for (int k = 0; k < 9; ++k) next[k][b] = refresh ? now[k] : P[k][b];

  const Vec3 results[3] = {to_world(g, R, f), to_world(g, R, ma), to_world(g, R, mb)};
  for (int v = 0; v < 3; ++v)
    for (int k = 0; k < 3; ++k) w.bond_out[v][4 * static_cast<size_t>(b) + k] = results[v][k];
}

}  // namespace

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
  if (m.def.bond_model == BondModel::kVoxelyze09) {
    for (int b = 0; b < nb; ++b) scalar_bond(m, s, w, b);
    return;
  }
  if (nb == 0) return;
  BondKernelIo& io = w.views.bond;
  io.all_valid = std::memchr(s.bond_prev_valid.data(), 0, s.bond_prev_valid.size()) == nullptr;
  const int redo = kernels().bond(io, nb, m, m.bond_damp / s.dt);
  // From the unchanged previous deformation.
  for (int r = 0; r < redo; ++r) scalar_bond(m, s, w, w.redo[r]);
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
