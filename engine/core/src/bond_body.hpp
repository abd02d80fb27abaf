// The batched bond kernel (KernelSet::bond, kernels.hpp) for any lane type (lanes.hpp).
//
// The model is that of bond_forces.cpp (exact bond model, chord-aligned frame), written once
// as a template over the lane type; all lane types evaluate the same IEEE operations in the
// same order (no FMA: -ffp-contract=off), so a bond's result does not depend on which lane
// type computed it. The rotation matrix of voxel a is Eigen's toRotationMatrix() formula with
// its columns cyclically permuted so the bond's axis comes first (a per-lane select), and
// rotations of any size take atan_over_t (elementary.hpp).
// The arithmetic is arranged for a short chain of dependent operations (the chord frame is
// not normalised, results go to the world axes through the frame's axes), so it matches
// the scalar path's to rounding, not to the bit; the scalar path only ever takes whole
// bonds, so no result mixes the two.
// Only degenerate chords and relative rotations near half a turn are left to the scalar path
// (listed in io.redo).
#pragma once

#include "elementary.hpp"
#include "kernels.hpp"
#include "lanes.hpp"

namespace plastivox {
namespace {

// Inputs of one group of bonds: what the kernel reads from their voxels.
template <class T>
struct BondIn {
  T dx, dy, dz;      // centre of b minus centre of a, m, world axes
  T ax, ay, az, aw;  // orientation of a
  T bx, by, bz, bw;  // orientation of b
  T size_a, size_b;  // actuated sizes, m
  T ea, eb;          // moduli, Pa
  T valid;           // 1 if the previous deformation is recorded, else 0
};

template <class T>
inline BondIn<T> gather(const BondKernelIo& io, int b) {
  const int* ia = io.bond_a + b;
  const int* ib = io.bond_b + b;
  BondIn<T> in;
  T ca[4], cb[4];
  load_records(io.centre_size, ia, ca);
  load_records(io.centre_size, ib, cb);
  in.dx = cb[0] - ca[0], in.dy = cb[1] - ca[1], in.dz = cb[2] - ca[2];
  in.size_a = ca[3], in.size_b = cb[3];
  T qa[4], qb[4];
  load_records(io.quat, ia, qa);
  load_records(io.quat, ib, qb);
  in.ax = qa[0], in.ay = qa[1], in.az = qa[2], in.aw = qa[3];
  in.bx = qb[0], in.by = qb[1], in.bz = qb[2], in.bw = qb[3];
  in.ea = load_indexed(io.stiff, ia, 0, T{}), in.eb = load_indexed(io.stiff, ib, 0, T{});
  const T one = splat(1.0, T{});
  in.valid = io.all_valid ? one : pick(load_flag(io.prev_valid, b, T{}), one, splat(0.0, T{}));
  return in;
}

// S: the type of the damping factor, double here; the gradient library (engine/grad) runs the
// same body with its recording number type for both T and S, so that dt is differentiated too.
template <class T, class S = double>
inline void bond_lanes(const BondKernelIo& io, int i, const ModelConstants& k, S damp,
                       int& redo_count) {
  const T one = splat(1.0, T{}), zero = splat(0.0, T{});
  const BondIn<T> in = gather<T>(io, i);
  // Per-lane choice by the bond's lattice axis: v0 if 0, v1 if 1, v2 if 2.
  const auto is1 = mask_eq(io.axis_wide, i, 1, T{}), is2 = mask_eq(io.axis_wide, i, 2, T{});
  const auto sel = [&](T v0, T v1, T v2) { return pick(is2, v2, pick(is1, v1, v0)); };

  // Rotation matrix of a (column-major, Eigen's toRotationMatrix), and its columns
  // permuted so the bond's axis comes first: c[0..2] = column d, c[3..5] = column d + 1, ...
  T R[9];
  {
    // Doubling by addition, here and below: one multiplication fewer each, and x + x is 2 x
    // exactly.
    const T tx = in.ax + in.ax, ty = in.ay + in.ay, tz = in.az + in.az;
    const T twx = tx * in.aw, twy = ty * in.aw, twz = tz * in.aw;
    const T txx = tx * in.ax, txy = ty * in.ax, txz = tz * in.ax;
    const T tyy = ty * in.ay, tyz = tz * in.ay, tzz = tz * in.az;
    R[0] = 1.0 - (tyy + tzz), R[3] = txy - twz, R[6] = txz + twy;
    R[1] = txy + twz, R[4] = 1.0 - (txx + tzz), R[7] = tyz - twx;
    R[2] = txz - twy, R[5] = tyz + twx, R[8] = 1.0 - (txx + tyy);
  }
  T m[9];
  for (int r = 0; r < 3; ++r) {
    m[r] = sel(R[r], R[3 + r], R[6 + r]);
    m[3 + r] = sel(R[3 + r], R[6 + r], R[r]);
    m[6 + r] = sel(R[6 + r], R[r], R[3 + r]);
  }
  // Chord a->b in a's permuted body axes.
  const T x = m[0] * in.dx + m[1] * in.dy + m[2] * in.dz;
  const T y = m[3] * in.dx + m[4] * in.dy + m[5] * in.dz;
  const T z = m[6] * in.dx + m[7] * in.dy + m[8] * in.dz;
  // Rotation of b relative to a: conj(q_a) q_b, vector part permuted.
  const T aw = in.aw, ax = in.ax, ay = in.ay, az = in.az;
  const T bw_ = in.bw, bx_ = in.bx, by_ = in.by, bz_ = in.bz;
  const T v0 = aw * bx_ - ax * bw_ - ay * bz_ + az * by_;
  const T v1 = aw * by_ + ax * bz_ - ay * bw_ - az * bx_;
  const T v2 = aw * bz_ - ax * by_ + ay * bx_ - az * bw_;
  const T a = aw * bw_ + ax * bx_ + ay * by_ + az * bz_;
  const T bx = sel(v0, v1, v2), by = sel(v1, v2, v0), bz = sel(v2, v0, v1);

  // Chord-aligned frame f taking r onto +x: the half-way quaternion (h, 0, z, -y), h = len + x,
  // left unnormalised (its norm is sqrt(2 len h)): th2 below is a ratio of f * q2's parts, so
  // the scale cancels, and skipping the square root and division shortens the chain of
  // dependent operations, which is what bounds this kernel.
  const T len = root(x * x + y * y + z * z);
  const T h0 = len + x;
  const auto degenerate = h0 <= 1e-6 * len;
  const T h = pick(degenerate, one, h0);
  const T ln = pick(degenerate, one, len);
  const T inv_h = 1.0 / h;
  const T t1sq = (y * y + z * z) * (inv_h * inv_h);
  const T ratio1 = atan_over_t(t1sq, degenerate);  // atan(t1) / t1
  const T k1 = (ratio1 + ratio1) * inv_h;
  const T t1x = zero, t1y = z * k1, t1z = -y * k1;
  // th2: rotation vector of f * q2 (times the norm of f), shorter arc: the sign of its scalar
  // part goes into the factor k2. Half a turn away (scalar part at most 1e-3 of the norm)
  // is left to the scalar path.
  const T w2 = h * a - z * by + y * bz;
  const T x2 = h * bx + z * bz + y * by;
  const T y2 = h * by + a * z - y * bx;
  const T z2 = h * bz - a * y - z * bx;
  const T sgn = pick(w2 < 0.0, splat(-1.0, T{}), one);
  const T aw2 = w2 * sgn;
  const auto redo = degenerate | (w2 * w2 <= 2e-6 * (ln * h));
  const T ww = pick(redo, one, aw2);
  const T inv_ww = 1.0 / ww;
  const T t2sq = (x2 * x2 + y2 * y2 + z2 * z2) * (inv_ww * inv_ww);
  const T ratio2 = atan_over_t(t2sq, redo);
  const T k2 = (ratio2 + ratio2) * inv_ww * sgn;
  const T t2x = x2 * k2, t2y = y2 * k2, t2z = z2 * k2;
  for_each_lane(redo, [&](int j) { io.redo[redo_count++] = i + j; });

  // Axial strain over the nominal length; harmonic-mean modulus.
  const T rest = 0.5 * (in.size_a + in.size_b);
  const T px = len - rest;
  const T strain = px * k.inv_L;
  const T ea = in.ea, eb = in.eb;
  const T e = (ea + ea) * eb / (ea + eb);
  const T stress = (k.axial_own ? ea : e) * strain;
  store(io.strain, i, strain);
  store(io.stress, i, stress);
  if (io.energy) store(io.energy, i, stress * strain);

  const T a2 = e * k.ka2, b3 = e * k.kb3;
  // The chord floored at min_shear_chord, as in the scalar path (bond_forces.cpp).
  const T chord = px + rest;
  const T b2c = 3.0 * b3 / pick(chord < k.min_shear_chord, splat(k.min_shear_chord, T{}), chord);
  T fx = stress * k.area, fyv = -b2c * (t1z + t2z), fzv = b2c * (t1y + t2y);
  T max = a2 * (t2x - t1x), may = -b3 * (t1y + t1y + t2y), maz = -b3 * (t1z + t1z + t2z);
  T mbx = a2 * (t1x - t2x), mby = -b3 * (t1y + (t2y + t2y)), mbz = -b3 * (t1z + (t2z + t2z));

  // Damping on half the change of the deformation since the previous step (off until a
  // previous deformation exists: valid = 0). The halves are taken in the coefficients
  // (h_*: c (g / 2) = (c / 2) g exactly, as scaling by a power of two is), so the changes g
  // are used whole.
  T old[9];
  for (int j = 0; j < 9; ++j) old[j] = load(io.prev[j], i, T{});
  const T gpx = px - old[0], gpy = zero - old[1], gpz = zero - old[2];
  const T g1x = t1x - old[3], g1y = t1y - old[4], g1z = t1z - old[5];
  const T g2x = t2x - old[6], g2y = t2y - old[7], g2z = t2z - old[8];
  const T se = root(e) * damp * in.valid;
  const T h_a1 = se * (0.5 * k.damp_a1), h_b1 = h_a1, h_b2 = se * (0.5 * k.damp_b2);
  const T h_a2 = se * (0.25 * k.damp_a2), h_b3 = se * (0.25 * k.damp_b3);
  const T h_b2h = se * (0.25 * k.damp_b2);
  fx = fx + h_a1 * gpx;
  fyv = fyv + (h_b1 * gpy - h_b2 * (g1z + g2z));
  fzv = fzv + (h_b1 * gpz + h_b2 * (g1y + g2y));
  max = max + h_a2 * (g2x - g1x);
  may = may + (-h_b2h * gpz - h_b3 * (g1y + g1y + g2y));
  maz = maz + (h_b2h * gpy - h_b3 * (g1z + g1z + g2z));
  mbx = mbx + h_a2 * (g1x - g2x);
  mby = mby + (-h_b2h * gpz - h_b3 * (g1y + (g2y + g2y)));
  mbz = mbz + (h_b2h * gpy - h_b3 * (g1z + (g2z + g2z)));

  // Flagged lanes keep their previous deformation: the scalar path redoes them from it.
  const T now[9] = {px, zero, zero, t1x, t1y, t1z, t2x, t2y, t2z};
  for (int j = 0; j < 9; ++j) store(io.prev_next[j], i, pick(redo, old[j], now[j]));

  // World axes. The chord-aligned frame's axes, in world coordinates, are the chord
  // direction u and a's permuted y and z axes turned by the smallest rotation taking a's
  // permuted x axis (c0) onto u; for an axis c orthogonal to c0 that rotation gives
  // c - (c0 + u) (u . c) / (1 + c0 . u), and u . c / (1 + c0 . u) is y / h (or z / h) in a's
  // frame. About half the work of applying f^T and then a's orientation to each vector.
  const T inv_len = 1.0 / ln;
  const T ux = in.dx * inv_len, uy = in.dy * inv_len, uz = in.dz * inv_len;
  const T sx = m[0] + ux, sy = m[1] + uy, sz = m[2] + uz;
  const T ky = y * inv_h, kz = z * inv_h;
  const T e1[3] = {m[3] - sx * ky, m[4] - sy * ky, m[5] - sz * ky};
  const T e2[3] = {m[6] - sx * kz, m[7] - sy * kz, m[8] - sz * kz};
  const T e0[3] = {ux, uy, uz};
  const T vx[3] = {fx, max, mbx}, vy[3] = {fyv, may, mby}, vz[3] = {fzv, maz, mbz};
  for (int v = 0; v < 3; ++v) {
    T o[4];
    for (int c = 0; c < 3; ++c) o[c] = e0[c] * vx[v] + e1[c] * vy[v] + e2[c] * vz[v];
    o[3] = zero;
    store4(io.out[v], i, o);
  }
}

template <class T>
inline int run_bonds(const BondKernelIo& io, int n, const ModelConstants& k, double damp) {
  int redo_count = 0;
  over_lanes<T>(n,
                [&](auto lane, int i) { bond_lanes<decltype(lane)>(io, i, k, damp, redo_count); });
  return redo_count;
}

}  // namespace
}  // namespace plastivox
