// The scalar bond path (bond_forces.cpp says what it computes: every bond under the Voxelyze 0.9
// model, and under the exact model the few bonds the batched kernel hands back) as a template
// over the number type T: `double` in the engine, and the gradient library's recording type
// (engine/grad/src/adj.hpp), so that the gradient's replica runs the engine's own arithmetic,
// operation for operation, and records it. One bond at a time: its branches (the two frames
// and their switch, the half-turn forms) are the bond's own.
//
// T's vocabulary: lanes.hpp's for double (load, store, root, value_of), with acos_of, sin_of,
// cos_of (libm's, which the Voxelyze 0.9 model takes for its frame and rotation vectors) and
// with_slope below; the recording type brings its own, found by
// argument-dependent lookup. Internal linkage, as every kernel template: see lanes.hpp.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>

#include "atan_series.hpp"
#include "elementary.hpp"
#include "kernels.hpp"
#include "lanes.hpp"
#include "plastivox/model_constants.hpp"

namespace plastivox {
namespace {

inline double acos_of(double x) {
  return std::acos(x);
}
inline double sin_of(double x) {
  return std::sin(x);
}
inline double cos_of(double x) {
  return std::cos(x);
}
// v, a function of x whose derivative is slope() (the recording type records it; a double is v,
// and slope() is never called).
template <class F>
inline double with_slope(double v, double, F&&) {
  return v;
}

// Record i of an array of 4-double records (centres and sizes, orientations) as T values: for
// double the record itself (copying it to the stack cost the engine 6 % of a voxelyze09 life:
// the copies' wide stores stalled the narrower loads after them), else loaded into scratch.
inline const double* record_of(const double* p, int i, double*) {
  return p + 4 * static_cast<size_t>(i);
}
template <class T>
inline const T* record_of(const double* p, int i, T* scratch) {
  for (int c = 0; c < 4; ++c) scratch[c] = load(p, 4 * i + c, T{});
  return scratch;
}

template <class T>
struct BondV3 {
  T x, y, z;
};

// Cyclic permutation taking lattice axis d onto x; a proper rotation, so it applies to
// rotation vectors as well as positions.
template <class T>
inline BondV3<T> to_bond(int d, T x, T y, T z) {
  if (d == 0) return {x, y, z};
  if (d == 1) return {y, z, x};
  return {z, x, y};
}
template <class T>
inline BondV3<T> from_bond(int d, const BondV3<T>& v) {
  if (d == 0) return v;
  if (d == 1) return {v.z, v.x, v.y};
  return {v.y, v.z, v.x};
}

// Rotation vector (axis * angle, rad) of a unit quaternion, taking the shorter arc.
template <class T>
inline BondV3<T> rotation_vector(T w, T x, T y, T z) {
  if (w < 0.0) w = -w, x = -x, y = -y, z = -z;
  const T s2 = x * x + y * y + z * z;
  if (s2 == 0.0) return {T(0.0), T(0.0), T(0.0)};
  // angle = 2 atan(s / w); angle / s = 2 atan(t) / (t w) with t = s / w. Near half a turn
  // (w <= 1e-3, so s ~ 1): angle = 2 (pi/2 - atan(q)) with q = w / s <= ~1e-3.
  T k;
  if (w > 1e-3) {
    const T inv_w = 1.0 / w;
    k = 2.0 * atan_over_t(s2 * (inv_w * inv_w), false) * inv_w;
  } else {
    const T s = root(s2), q = w / s;
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
template <class T>
inline BondV3<T> voxelyze_rotation_vector(T w, T x, T y, T z) {
  constexpr double kWAcos2Sqrt = 0.9988;
  constexpr double kAcos2Sqrt = 1.0 - kWAcos2Sqrt * kWAcos2Sqrt;
  const T sl = 1.0 - w * w;
  if (sl <= 0.0) return {T(0.0), T(0.0), T(0.0)};
  const T wc = w > 1.0 ? T(1.0) : w;
  if (sl < kAcos2Sqrt) {
    // k = sqrt((2 - 2w) / (1 - w^2)) = sqrt(2 / (1 + w)), computed as Voxelyze 0.9 does, from
    // two differences that cancel (so its value carries a relative error of about 1e-16 / (1 -
    // w)), and differentiated as the second form, -k / (2 (1 + w)): the derivative of the
    // first form's operations would carry that error over 1 - w again.
    const double wv = value_of(wc), kv = std::sqrt((2.0 - 2.0 * wv) / value_of(sl));
    const T k = with_slope(kv, wc, [&] { return -kv / (2.0 * (1.0 + wv)); });
    return {x * 2.0 * k, y * 2.0 * k, z * 2.0 * k};
  }
  const T a = acos_of(wc), r = root(sl);
  return {x * 2.0 * a / r, y * 2.0 * a / r, z * 2.0 * a / r};
}

// The deformation of one bond in its bond axes. Two frames are used:
//  - chord-aligned ("large angle"): voxel a's permuted frame rotated by the quaternion
//    f = (fw, 0, fy, fz) so the chord lies on +x; then p = (extension, 0, 0);
//  - voxel-aligned ("small angle", Voxelyze 0.9 only): voxel a's permuted frame itself
//    (f = identity); th1 = 0 and p = r - (rest, 0, 0) keeps the transverse offset.
template <class T>
struct BondGeometry {
  int axis;
  T fw, fy, fz;        // frame rotation (a quaternion with zero x part; unit but for voxelyze09's
                       // first-order frame, within 1e-8 of it)
  BondV3<T> p;         // position of b relative to its rest place, m, bond axes
  BondV3<T> th1, th2;  // rotation vectors of a and b, rad, bond axes
  BondV3<T> r;         // chord from a to b in the permuted frame of a, m
  T rest;              // actuated rest length, m
  T q2w;               // scalar part of b's rotation relative to a
};

// The chord-aligned frame as Voxelyze 0.9's CQuat::FromAngleToPosX builds it, and th1 its
// rotation vector: within 0.01732 of the axis in both y/x and z/x, the first-order
// (w, 0, z/2x, -y/2x) with w = 1 - (y^2 + z^2)/2 (not normalised: tan for sin, an error
// below 1e-4); otherwise half the angle acos(x/|r|) about the normal; a chord within 1e-7
// rad of backwards turns half a turn about y.
template <class T>
inline void voxelyze_frame(const BondV3<T>& r, BondGeometry<T>& g) {
  constexpr double kDiscard = 1e-7, kPi = 3.14159265358979;
  g.fw = 1.0, g.fy = 0.0, g.fz = 0.0;
  if (r.x == 0.0 && r.y == 0.0 && r.z == 0.0) {
    g.th1 = {T(0.0), T(0.0), T(0.0)};
    return;
  }
  const T yx = r.y / r.x, zx = r.z / r.x;
  if (yx < kVoxelyzeSmallAngle && yx > -kVoxelyzeSmallAngle && zx < kVoxelyzeSmallAngle &&
      zx > -kVoxelyzeSmallAngle) {
    g.fy = 0.5 * zx, g.fz = -0.5 * yx;
    g.fw = 1.0 + 0.5 * (-g.fy * g.fy - g.fz * g.fz);
  } else {
    const T l = root(r.x * r.x + r.y * r.y + r.z * r.z), li = 1.0 / l;
    const T nx = r.x * li, ny = r.y * li, nz = r.z * li;
    const T theta = acos_of(nx);
    if (theta > kPi - kDiscard) {
      g.fw = 0.0, g.fy = 1.0, g.fz = 0.0;
    } else {
      const T inv = 1.0 / root(nz * nz + ny * ny), a = 0.5 * theta;
      const T sa = sin_of(a);
      g.fw = cos_of(a), g.fy = nz * inv * sa, g.fz = -ny * inv * sa;
    }
  }
  g.th1 = voxelyze_rotation_vector(g.fw, T(0.0), g.fy, g.fz);
}

// The unit quaternion q (x, y, z, w) as a column-major rotation matrix (R[0..2] the first
// column), as Eigen's toRotationMatrix computes it.
template <class T>
inline void rotation_matrix(const T* q, T* R) {
  const T tx = 2.0 * q[0], ty = 2.0 * q[1], tz = 2.0 * q[2];
  const T twx = tx * q[3], twy = ty * q[3], twz = tz * q[3];
  const T txx = tx * q[0], txy = ty * q[0], txz = tz * q[0];
  const T tyy = ty * q[1], tyz = tz * q[1], tzz = tz * q[2];
  R[0] = 1.0 - (tyy + tzz), R[3] = txy - twz, R[6] = txz + twy;
  R[1] = txy + twz, R[4] = 1.0 - (txx + tzz), R[7] = tyz - twx;
  R[2] = txz - twy, R[5] = tyz + twx, R[8] = 1.0 - (txx + tyy);
}

// The rotation of b relative to a, conj(q_a) q_b: returns its scalar part, its vector part
// permuted to qv.
template <class T>
inline T relative_rotation(int d, const T* qa, const T* qb, BondV3<T>& qv) {
  const T aw = qa[3], ax = qa[0], ay = qa[1], az = qa[2];
  const T bw = qb[3], bx = qb[0], by = qb[1], bz = qb[2];
  const T qw = aw * bw + ax * bx + ay * by + az * bz;
  qv = to_bond<T>(d, aw * bx - ax * bw - ay * bz + az * by, aw * by + ax * bz - ay * bw - az * bx,
                  aw * bz - ax * by + ay * bx - az * bw);
  return qw;
}

// Damping's forces and moments added to a bond's elastic ones (f on b, ma on a, mb on b), from
// the halves of the changes in deformation dp, d1, d2 and the coefficients sqrt(E) times
// ModelConstants' geometric constants (c_b1 is c_a1, c_b2h half c_b2).
template <class T>
inline void add_bond_damping(BondV3<T>& f, BondV3<T>& ma, BondV3<T>& mb, const BondV3<T>& dp,
                             const BondV3<T>& d1, const BondV3<T>& d2, T c_a1, T c_b2, T c_a2,
                             T c_b3, T c_b2h) {
  const T c_b1 = c_a1;
  f.x = f.x + c_a1 * dp.x;
  f.y = f.y + (c_b1 * dp.y - c_b2 * (d1.z + d2.z));
  f.z = f.z + (c_b1 * dp.z + c_b2 * (d1.y + d2.y));
  ma.x = ma.x + c_a2 * (d2.x - d1.x);
  ma.y = ma.y + (-c_b2h * dp.z - c_b3 * (2.0 * d1.y + d2.y));
  ma.z = ma.z + (c_b2h * dp.y - c_b3 * (2.0 * d1.z + d2.z));
  mb.x = mb.x + c_a2 * (d1.x - d2.x);
  mb.y = mb.y + (-c_b2h * dp.z - c_b3 * (d1.y + 2.0 * d2.y));
  mb.z = mb.z + (c_b2h * dp.y - c_b3 * (d1.z + 2.0 * d2.z));
}

// d: the bond's lattice axis; R: voxel a's orientation as a column-major rotation matrix
// (R[0..2] the first column); dl: the chord b - a, world axes; qa, qb: the orientations of a
// and b (x, y, z, w); size_a, size_b: their actuated sizes.
template <class T>
inline BondGeometry<T> bond_geometry(int d, const T* R, const T* dl, const T* qa, const T* qb,
                                     T size_a, T size_b, bool small_angle, bool voxelyze) {
  BondGeometry<T> g;
  g.axis = d;
  // Chord in a's body axes: R_a^T (p_b - p_a), then permuted.
  const T dx = dl[0], dy = dl[1], dz = dl[2];
  g.r = to_bond<T>(d, R[0] * dx + R[1] * dy + R[2] * dz, R[3] * dx + R[4] * dy + R[5] * dz,
                   R[6] * dx + R[7] * dy + R[8] * dz);
  // Rotation of b relative to a: conj(q_a) q_b, vector part permuted.
  BondV3<T> qv;
  const T qw = relative_rotation(d, qa, qb, qv);
  g.q2w = qw;
  // Extension is measured from the actuated rest length (mean of the two current sizes).
  g.rest = 0.5 * (size_a + size_b);
  const auto rotvec = [voxelyze](T w, T x, T y, T z) {
    return voxelyze ? voxelyze_rotation_vector(w, x, y, z) : rotation_vector(w, x, y, z);
  };
  if (small_angle) {
    g.fw = 1.0, g.fy = 0.0, g.fz = 0.0;
    g.p = {g.r.x - g.rest, g.r.y, g.r.z};
    g.th1 = {T(0.0), T(0.0), T(0.0)};
    g.th2 = rotvec(qw, qv.x, qv.y, qv.z);
    return g;
  }
  // f takes the chord onto +x: the half-way quaternion (len + r_x, 0, r_z, -r_y), whose
  // norm is sqrt(2 len (len + r_x)).
  const BondV3<T>& r = g.r;
  const T len = root(r.x * r.x + r.y * r.y + r.z * r.z);
  const T h = len + r.x;
  g.p = {len - g.rest, T(0.0), T(0.0)};
  if (voxelyze) {
    voxelyze_frame(r, g);
  } else if (h > 1e-6 * len) {
    const T inv_n = 1.0 / root(2.0 * len * h);
    g.fw = h * inv_n, g.fy = r.z * inv_n, g.fz = -r.y * inv_n;
    // th1 = rotation vector of f; the tangent of its half angle is |(r_y, r_z)| / h.
    const T inv_h = 1.0 / h;
    const T k1 = 2.0 * atan_over_t((r.y * r.y + r.z * r.z) * (inv_h * inv_h), false) * inv_h;
    g.th1 = {T(0.0), r.z * k1, -r.y * k1};
  } else {
    // The chord points (almost) backwards, or the centres coincide: a crushed or inverted
    // bond. Any rotation onto +x will do; half a turn about z keeps the numbers finite.
    g.fw = 0.0, g.fy = 0.0, g.fz = 1.0;
    g.th1 = {T(0.0), T(0.0), T(M_PI)};
  }
  // th2 = rotation vector of f * q2 (f has no x part).
  const T fw = g.fw, fy = g.fy, fz = g.fz;
  g.th2 = rotvec(fw * qw - fy * qv.y - fz * qv.z, fw * qv.x + fy * qv.z - fz * qv.y,
                 fw * qv.y + qw * fy + fz * qv.x, fw * qv.z + qw * fz - fy * qv.x);
  return g;
}

// Voxelyze 0.9's switch between the two frames, with hysteresis: small-angle while the
// relative rotation, the chord's turn and the extension all stay small. A decision on values
// only (the gradient takes the branch the life took: docs/gradients.md).
// The turn is computed as the authors' evolution build computed it. Its source writes
// (abs(y) + abs(z)) / x, but that build's abs took an int: each offset, in metres, is
// truncated towards zero first (the two cvttsd2si of CVXS_BondInternal::CalcLinForce in the
// fork's shipped VXS_BondInternal.o). A bond's offsets are far below a metre, so the turn is
// 0 and never switches a bond; only the rotation and the extension do. Linking the fork's
// own library into a trace harness and rebuilding its source with the truncation both give
// the settling cube's published fall (docs/vxa.md); with a real |y| + |z| the cube falls the
// other way.
template <class T>
inline bool next_small_angle(const BondGeometry<T>& g, bool small_now) {
  constexpr double kBendTurn = 0.05;  // (|y| + |z|) / x
  constexpr double kExtension = 1.3;  // x / rest
  constexpr double kHysteresis = 1.1;
  const double rx = value_of(g.r.x), ry = value_of(g.r.y), rz = value_of(g.r.z);
  const double angle = 2.0 * std::acos(std::min(1.0, std::abs(value_of(g.q2w))));
  const double turn = (std::abs(std::trunc(ry)) + std::abs(std::trunc(rz))) / rx;
  const double extend = rx / value_of(g.rest);
  if (small_now) {
    return !(angle >= kHysteresis * kVoxelyzeSmallAngle || !(turn <= kHysteresis * kBendTurn) ||
             extend > kHysteresis * kExtension);
  }
  return angle < kVoxelyzeSmallAngle && turn >= 0 && turn < kBendTurn && extend < kExtension;
}

// v expressed in the bond axes -> world: undo the frame rotation f (apply f^T), undo the
// permutation, apply a's orientation.
template <class T>
inline BondV3<T> to_world(const BondGeometry<T>& g, const T* R, const BondV3<T>& v) {
  const T w = g.fw, y = g.fy, z = g.fz;
  const BondV3<T> u{(1.0 - 2.0 * (y * y + z * z)) * v.x + 2.0 * w * z * v.y - 2.0 * w * y * v.z,
                    -2.0 * w * z * v.x + (1.0 - 2.0 * z * z) * v.y + 2.0 * y * z * v.z,
                    2.0 * w * y * v.x + 2.0 * y * z * v.y + (1.0 - 2.0 * y * y) * v.z};
  const BondV3<T> o = from_bond(g.axis, u);
  return {R[0] * o.x + R[3] * o.y + R[6] * o.z, R[1] * o.x + R[4] * o.y + R[7] * o.z,
          R[2] * o.x + R[5] * o.y + R[8] * o.z};
}

// Bond b by the scalar path: reads what the batched kernel reads (io: centres and sizes,
// orientations, moduli, the previous deformation and its flag) and the bond's frame
// (small_in, Voxelyze 0.9 only); writes what it writes (io: the results, the next deformation)
// and the next frame (small_out). damp: bond_damp / dt (S: double, or the recording type, so
// that dt is differentiated too).
template <class T, class S>
inline void scalar_bond_lanes(const BondKernelIo& io, const uint8_t* small_in, uint8_t* small_out,
                              int b, const ModelConstants& mk, S damp) {
  const bool voxelyze = mk.def.bond_model == BondModel::kVoxelyze09;
  const int ia = io.bond_a[b], ib = io.bond_b[b], d = static_cast<int>(io.axis_wide[b]);
  bool small = small_in[b] != 0;
  bool damp_ok = io.prev_valid[b] != 0;
  T scratch[4][4];
  const T* ca = record_of(io.centre_size, ia, scratch[0]);
  const T* cb = record_of(io.centre_size, ib, scratch[1]);
  const T* qa = record_of(io.quat, ia, scratch[2]);
  const T* qb = record_of(io.quat, ib, scratch[3]);
  T R[9];
  rotation_matrix(qa, R);
  const T dl[3] = {cb[0] - ca[0], cb[1] - ca[1], cb[2] - ca[2]};
  BondGeometry<T> g = bond_geometry(d, R, dl, qa, qb, ca[3], cb[3], small, voxelyze);
  if (voxelyze) {
    const bool next = next_small_angle(g, small);
    if (next != small) {
      // Switching frames: deformation rates are undefined this step (no damping, and the
      // previous deformation is not refreshed), as in Voxelyze 0.9.
      small = next;
      g = bond_geometry(d, R, dl, qa, qb, ca[3], cb[3], small, voxelyze);
      damp_ok = false;
    }
    small_out[b] = small ? 1 : 0;
  }
  const BondV3<T>& p = g.p;
  const BondV3<T>& t1 = g.th1;
  const BondV3<T>& t2 = g.th2;
  // As in Voxelyze 0.9, strain is the extension over the nominal length L.
  const T strain = p.x * mk.inv_L;
  const T ea = load_indexed(io.stiff, io.bond_a, b, T{}),
          eb = load_indexed(io.stiff, io.bond_b, b, T{});
  const T e = 2.0 * ea * eb / (ea + eb);  // harmonic mean: two springs in series
  const T stress = (mk.axial_own ? ea : e) * strain;
  store(io.strain, b, strain);
  store(io.stress, b, stress);
  if (io.energy) store(io.energy, b, stress * strain);

  const T a2 = e * mk.ka2, b1 = e * mk.kb1, b2 = e * mk.kb2, b3 = e * mk.kb3;
  // Shear force from end rotations. Voxelyze uses b2 = 3 b3 / L; the exact model uses
  // 3 b3 / chord, which makes the forces the gradient of the bending energy and the
  // bond's moments balance its forces (angular momentum is conserved) once bonds stretch
  // or actuate by several percent. The two agree at rest length. The chord is floored at
  // min_shear_chord (kMinShearChord L, compile.cpp): as a crushed bond's centres meet,
  // 1/chord (a transverse displacement turns a short chord by a large angle) would grow
  // without bound. (std::max's choice: the floor only where the chord is below it.)
  const T chord = p.x + g.rest;
  const T b2c =
      voxelyze ? b2 : 3.0 * b3 / (chord < mk.min_shear_chord ? T(mk.min_shear_chord) : chord);
  BondV3<T> f{stress * mk.area, b1 * p.y - b2c * (t1.z + t2.z), b1 * p.z + b2c * (t1.y + t2.y)};
  BondV3<T> ma{a2 * (t2.x - t1.x), -b2 * p.z - b3 * (2.0 * t1.y + t2.y),
               b2 * p.y - b3 * (2.0 * t1.z + t2.z)};
  BondV3<T> mb{a2 * (t1.x - t2.x), -b2 * p.z - b3 * (t1.y + 2.0 * t2.y),
               b2 * p.y - b3 * (t1.z + 2.0 * t2.z)};

  T old[9];
  for (int k = 0; k < 9; ++k) old[k] = load(io.prev[k], b, T{});
  if (damp_ok) {
    // Half of the deformation change is attributed to each end.
    const BondV3<T> dp{0.5 * (p.x - old[0]), 0.5 * (p.y - old[1]), 0.5 * (p.z - old[2])};
    const BondV3<T> d1{0.5 * (t1.x - old[3]), 0.5 * (t1.y - old[4]), 0.5 * (t1.z - old[5])};
    const BondV3<T> d2{0.5 * (t2.x - old[6]), 0.5 * (t2.y - old[7]), 0.5 * (t2.z - old[8])};
    // Every coefficient is sqrt(E) times a geometric constant (ModelConstants).
    const T se = root(e) * damp;
    const T c_a1 = se * mk.damp_a1, c_b2 = se * mk.damp_b2;
    const T c_a2 = 0.5 * se * mk.damp_a2, c_b3 = 0.5 * se * mk.damp_b3;
    const T c_b2h = 0.5 * c_b2;
    add_bond_damping<T>(f, ma, mb, dp, d1, d2, c_a1, c_b2, c_a2, c_b3, c_b2h);
  }
  // The deformation the next step damps against: this one, unless the bond switched frames
  // with a deformation recorded (then the recorded one stays, as in Voxelyze 0.9). Every bond
  // has one recorded after the step (commit_bond_deformation).
  const T now[9] = {p.x, p.y, p.z, t1.x, t1.y, t1.z, t2.x, t2.y, t2.z};
  const bool refresh = damp_ok || !io.prev_valid[b];
  for (int k = 0; k < 9; ++k) store(io.prev_next[k], b, refresh ? now[k] : old[k]);

  const BondV3<T> results[3] = {to_world(g, R, f), to_world(g, R, ma), to_world(g, R, mb)};
  for (int v = 0; v < 3; ++v) {
    store(io.out[v], 4 * b, results[v].x);
    store(io.out[v], 4 * b + 1, results[v].y);
    store(io.out[v], 4 * b + 2, results[v].z);
  }
}

}  // namespace
}  // namespace plastivox
