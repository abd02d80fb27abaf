// The bond stage's hand-written reverse (bond_adjoint.hpp) as a template over the lane type
// (engine/core/src/lanes.hpp), so that it runs on as many bonds at once as the forward kernel
// (bond_body.hpp): `double` in bond_adjoint.cpp, a vector of four or eight in
// reverse_avx2.cpp and reverse_avx512.cpp. Every operation is element-wise IEEE
// arithmetic in one fixed order (no FMA: -ffp-contract=off), so a bond's adjoints are the same
// bits whatever the lane width, as the forward kernels' results are.
//
// It computes the bond's forward again (bond_body.hpp's operations in its order, the
// small-angle path), then its reverse: g_* is the adjoint of *. Lanes off that path (a
// degenerate chord, a rotation whose arctangent takes its wide branch, the scalar path's half
// turn) are flagged in io.off and their adjoints are to be ignored: the caller takes them by
// bond_reverse_tape.
//
// Internal linkage (unnamed namespace), as every lane template: see lanes.hpp.
#pragma once

#include <cstddef>

#include "atan_series.hpp"
#include "bond_adjoint.hpp"
#include "lanes.hpp"

namespace plastivox {
namespace {

// d/dz of atan_series (atan_series.hpp): 1 - z/3 + z^2/5 - ... + z^10/21 differentiated term
// by term, -1/3 + 2 z/5 - ... + 10 z^9/21, by Estrin's scheme as the series itself (a chain of
// four multiply-adds, not nine).
template <class T>
inline T atan_series_slope(T z) {
  const T z2 = z * z, z4 = z2 * z2, z8 = z4 * z4;
  const T p12 = -1.0 / 3 + z * (2.0 / 5), p34 = -3.0 / 7 + z * (4.0 / 9);
  const T p56 = -5.0 / 11 + z * (6.0 / 13), p78 = -7.0 / 15 + z * (8.0 / 17);
  const T p910 = -9.0 / 19 + z * (10.0 / 21);
  return (p12 + z2 * p34) + z4 * (p56 + z2 * p78) + z8 * p910;
}

// Once a cache line of rows (eight bonds), the rows and voxel records of the bonds kAhead on:
// the reverse reads and writes some 60 rows at once, more streams than the hardware follows, and
// the kept stage was written when its segment was recorded, long out of the cache. (In a whole
// gradient of the 10^3 cube the kernel took 0.7 of its time with this than without.) Always
// inlined: a call would spill every live vector register around it.
__attribute__((always_inline)) inline void prefetch_bonds(const grad::BondReverseIo& io, int i) {
  constexpr int kAhead = 32;
  const size_t j = size_t(i) + kAhead;
  if (i % 8 != 0 || j + 8 > io.nb) return;
  for (int r = 0; r < 9; ++r) __builtin_prefetch(io.bond.prev[r] + j);
  for (int r = 0; r < grad::kBondLeaves; ++r) __builtin_prefetch(io.out_adj[r] + j);
  for (size_t b = j; b < j + 8; b += 2)
    for (const int v : {io.bond.bond_a[b], io.bond.bond_b[b]}) {
      __builtin_prefetch(io.bond.centre_size + 4 * v);
      __builtin_prefetch(io.bond.quat + 4 * v);
    }
}

// Bonds [i, i + kLanes<T>) of a kept stage: from their outputs' adjoints (io.records_adj and
// io.out_adj), their inputs' (io.in_adj), and io.off.
template <class T>
inline void bond_reverse_lanes(const grad::BondReverseIo& io, int i, const ModelConstants& k) {
  using grad::kCentreA, grad::kCentreB, grad::kQuatA, grad::kQuatB, grad::kStiffA, grad::kStiffB,
      grad::kPrev, grad::kDamp, grad::kPrevNext, grad::kStrain, grad::kStress, grad::kEnergy;
  const BondKernelIo& bi = io.bond;
  const size_t nb = io.nb;
  const T one = splat(1.0, T{}), zero = splat(0.0, T{});
  const int* ia = bi.bond_a + i;
  const int* ib = bi.bond_b + i;
  T ca[4], cb[4], qa[4], qb[4];
  load_records(bi.centre_size, ia, ca);
  load_records(bi.centre_size, ib, cb);
  load_records(bi.quat, ia, qa);
  load_records(bi.quat, ib, qb);
  prefetch_bonds(io, i);  // after this group's own loads
  const T ea = load_indexed(bi.stiff, ia, 0, T{}), eb = load_indexed(bi.stiff, ib, 0, T{});
  const T valid = bi.all_valid ? one : pick(load_flag(bi.prev_valid, i, T{}), one, zero);
  const auto is1 = mask_eq(bi.axis_wide, i, 1, T{}), is2 = mask_eq(bi.axis_wide, i, 2, T{});
  // Per-lane choice by the bond's lattice axis d: v0 if 0, v1 if 1, v2 if 2.
  const auto sel = [&](T v0, T v1, T v2) { return pick(is2, v2, pick(is1, v1, v0)); };
  const double damp = io.damp;

  // ---- The forward again ----
  const T ax = qa[0], ay = qa[1], az = qa[2], aw = qa[3];
  const T bx_ = qb[0], by_ = qb[1], bz_ = qb[2], bw_ = qb[3];
  const T dl[3] = {cb[0] - ca[0], cb[1] - ca[1], cb[2] - ca[2]};
  const T tx = ax + ax, ty = ay + ay, tz = az + az;
  const T twx = tx * aw, twy = ty * aw, twz = tz * aw;
  const T txx = tx * ax, txy = ty * ax, txz = tz * ax;
  const T tyy = ty * ay, tyz = tz * ay, tzz = tz * az;
  T R[9];
  R[0] = 1.0 - (tyy + tzz), R[3] = txy - twz, R[6] = txz + twy;
  R[1] = txy + twz, R[4] = 1.0 - (txx + tzz), R[7] = tyz - twx;
  R[2] = txz - twy, R[5] = tyz + twx, R[8] = 1.0 - (txx + tyy);
  T m[9];  // m[3 j + r] = R[3 ((j + d) % 3) + r]
  for (int r = 0; r < 3; ++r) {
    m[r] = sel(R[r], R[3 + r], R[6 + r]);
    m[3 + r] = sel(R[3 + r], R[6 + r], R[r]);
    m[6 + r] = sel(R[6 + r], R[r], R[3 + r]);
  }
  const T x = m[0] * dl[0] + m[1] * dl[1] + m[2] * dl[2];
  const T y = m[3] * dl[0] + m[4] * dl[1] + m[5] * dl[2];
  const T z = m[6] * dl[0] + m[7] * dl[1] + m[8] * dl[2];
  const T v0 = aw * bx_ - ax * bw_ - ay * bz_ + az * by_;
  const T v1 = aw * by_ + ax * bz_ - ay * bw_ - az * bx_;
  const T v2 = aw * bz_ - ax * by_ + ay * bx_ - az * bw_;
  const T a = aw * bw_ + ax * bx_ + ay * by_ + az * bz_;
  const T bx = sel(v0, v1, v2), by = sel(v1, v2, v0), bz = sel(v2, v0, v1);
  // Lanes off the hand path compute with stand-ins (1 for a divisor, 0 for a series' argument)
  // so that no lane makes an infinity or a NaN (the tests trap FE_INVALID); the stand-ins never
  // touch a lane on the path.
  const T len0 = root(x * x + y * y + z * z), h0 = len0 + x;
  const auto degenerate = h0 <= 1e-6 * len0;
  const T h = pick(degenerate, one, h0), len = pick(degenerate, one, len0);
  constexpr double kWide = 0.03956612989658004;  // atan_over_t's tan^2(pi / 16)
  const T inv_h = 1.0 / h;
  const T yz2 = y * y + z * z, ih2 = inv_h * inv_h;
  const auto wide1 = yz2 * ih2 >= kWide;
  const T t1sq = pick(wide1, zero, yz2 * ih2);
  const T ratio1 = atan_series(t1sq);
  const T k1 = (ratio1 + ratio1) * inv_h;
  const T t1y = z * k1, t1z = -y * k1;
  const T w2 = h * a - z * by + y * bz;
  const T x2 = h * bx + z * bz + y * by;
  const T y2 = h * by + a * z - y * bx;
  const T z2 = h * bz - a * y - z * bx;
  const T sgn = pick(w2 < 0.0, splat(-1.0, T{}), one);
  const auto redo = degenerate | (w2 * w2 <= 2e-6 * (len * h));  // the scalar path's
  const T ww = pick(redo, one, w2 * sgn);
  const T inv_ww = 1.0 / ww;
  const T n2 = x2 * x2 + y2 * y2 + z2 * z2, iw2 = inv_ww * inv_ww;
  const auto wide2 = n2 * iw2 >= kWide;
  const T t2sq = pick(wide2, zero, n2 * iw2);
  store_flag(io.off, i, redo | wide1 | wide2);
  const T ratio2 = atan_series(t2sq);
  const T k2 = (ratio2 + ratio2) * inv_ww * sgn;
  const T t2x = x2 * k2, t2y = y2 * k2, t2z = z2 * k2;
  const T rest = 0.5 * (ca[3] + cb[3]);
  const T px = len - rest;
  const T strain = px * k.inv_L;
  const T e_num = (ea + ea) * eb, e_den = ea + eb, e = e_num / e_den;
  const T coef = k.axial_own ? ea : e;
  const T stress = coef * strain;
  const T a2 = e * k.ka2, b3 = e * k.kb3;
  const T chord = px + rest;
  const auto floored = chord < k.min_shear_chord;
  const T cf = pick(floored, splat(k.min_shear_chord, T{}), chord);
  const T b2c = 3.0 * b3 / cf;
  T old[9];
  for (int j = 0; j < 9; ++j) old[j] = load(bi.prev[j], i, T{});
  const T gpx = px - old[0], gpy = zero - old[1], gpz = zero - old[2];
  const T g1x = zero - old[3], g1y = t1y - old[4], g1z = t1z - old[5];
  const T g2x = t2x - old[6], g2y = t2y - old[7], g2z = t2z - old[8];
  const T sqe = root(e);
  const T se = sqe * damp * valid;
  const T h_a1 = se * (0.5 * k.damp_a1), h_b1 = h_a1, h_b2 = se * (0.5 * k.damp_b2);
  const T h_a2 = se * (0.25 * k.damp_a2), h_b3 = se * (0.25 * k.damp_b3);
  const T h_b2h = se * (0.25 * k.damp_b2);
  const T fx = stress * k.area + h_a1 * gpx;
  const T fyv = -b2c * (t1z + t2z) + (h_b1 * gpy - h_b2 * (g1z + g2z));
  const T fzv = b2c * (t1y + t2y) + (h_b1 * gpz + h_b2 * (g1y + g2y));
  const T max = a2 * t2x + h_a2 * (g2x - g1x);
  const T may = -b3 * (t1y + t1y + t2y) + (-h_b2h * gpz - h_b3 * (g1y + g1y + g2y));
  const T maz = -b3 * (t1z + t1z + t2z) + (h_b2h * gpy - h_b3 * (g1z + g1z + g2z));
  const T mbx = a2 * (zero - t2x) + h_a2 * (g1x - g2x);
  const T mby = -b3 * (t1y + (t2y + t2y)) + (-h_b2h * gpz - h_b3 * (g1y + (g2y + g2y)));
  const T mbz = -b3 * (t1z + (t2z + t2z)) + (h_b2h * gpy - h_b3 * (g1z + (g2z + g2z)));
  const T inv_len = 1.0 / len;
  const T u[3] = {dl[0] * inv_len, dl[1] * inv_len, dl[2] * inv_len};
  const T s[3] = {m[0] + u[0], m[1] + u[1], m[2] + u[2]};
  const T ky = y * inv_h, kz = z * inv_h;
  T e1[3], e2[3];
  for (int c = 0; c < 3; ++c) e1[c] = m[3 + c] - s[c] * ky, e2[c] = m[6 + c] - s[c] * kz;
  const T vx[3] = {fx, max, mbx}, vy[3] = {fyv, may, mby}, vz[3] = {fzv, maz, mbz};

  // ---- The reverse ----
  // Outputs from kPrevNext on are rows of the stage's leaves, the records' rows of their own.
  const auto out = [&](int o) { return load(io.out_adj[o - kPrevNext], i, T{}); };
  const auto record_out = [&](int w, int c) {
    return load(io.records_adj + size_t(3 * w + c) * nb, i, T{});
  };
  const auto put_in = [&](int slot, T v) { store(io.in_adj + size_t(slot) * nb, i, v); };
  T g_u[3] = {zero, zero, zero}, g_e1[3] = {zero, zero, zero}, g_e2[3] = {zero, zero, zero};
  T g_vx[3] = {zero, zero, zero}, g_vy[3] = {zero, zero, zero}, g_vz[3] = {zero, zero, zero};
  for (int w = 0; w < 3; ++w)
    for (int c = 0; c < 3; ++c) {
      const T g = record_out(w, c);
      g_u[c] += g * vx[w], g_vx[w] += g * u[c];
      g_e1[c] += g * vy[w], g_vy[w] += g * e1[c];
      g_e2[c] += g * vz[w], g_vz[w] += g * e2[c];
    }
  T g_m[9];
  for (T& g : g_m) g = zero;
  T g_s[3] = {zero, zero, zero};
  T g_ky = zero, g_kz = zero;
  for (int c = 0; c < 3; ++c) {
    g_m[3 + c] += g_e1[c], g_s[c] -= g_e1[c] * ky, g_ky -= g_e1[c] * s[c];
    g_m[6 + c] += g_e2[c], g_s[c] -= g_e2[c] * kz, g_kz -= g_e2[c] * s[c];
    g_m[c] += g_s[c], g_u[c] += g_s[c];
  }
  T g_x = zero, g_y = g_ky * inv_h, g_z = g_kz * inv_h;
  T g_inv_h = g_ky * y + g_kz * z;
  T g_dl[3], g_inv_len = zero;
  for (int c = 0; c < 3; ++c) g_dl[c] = g_u[c] * inv_len, g_inv_len += g_u[c] * dl[c];
  T g_len = g_inv_len * -(inv_len * inv_len);
  // The next deformation.
  T g_px = out(kPrevNext), g_t1y = out(kPrevNext + 4), g_t1z = out(kPrevNext + 5);
  T g_t2x = out(kPrevNext + 6), g_t2y = out(kPrevNext + 7), g_t2z = out(kPrevNext + 8);
  const T g_fx = g_vx[0], g_max = g_vx[1], g_mbx = g_vx[2];
  const T g_fyv = g_vy[0], g_may = g_vy[1], g_mby = g_vy[2];
  const T g_fzv = g_vz[0], g_maz = g_vz[1], g_mbz = g_vz[2];
  // Damping.
  const T g_ha1 = g_fx * gpx + g_fyv * gpy + g_fzv * gpz;  // h_b1 is h_a1
  const T g_hb2 = -g_fyv * (g1z + g2z) + g_fzv * (g1y + g2y);
  const T g_ha2 = g_max * (g2x - g1x) + g_mbx * (g1x - g2x);
  const T g_hb2h = -g_may * gpz + g_maz * gpy - g_mby * gpz + g_mbz * gpy;
  const T g_hb3 = -g_may * (g1y + g1y + g2y) - g_maz * (g1z + g1z + g2z) -
                  g_mby * (g1y + (g2y + g2y)) - g_mbz * (g1z + (g2z + g2z));
  const T g_gpx = g_fx * h_a1;
  const T g_gpy = g_fyv * h_b1 + (g_maz + g_mbz) * h_b2h;
  const T g_gpz = g_fzv * h_b1 - (g_may + g_mby) * h_b2h;
  const T g_g1x = (g_mbx - g_max) * h_a2;
  const T g_g1y = g_fzv * h_b2 - (2.0 * g_may + g_mby) * h_b3;
  const T g_g1z = -g_fyv * h_b2 - (2.0 * g_maz + g_mbz) * h_b3;
  const T g_g2x = (g_max - g_mbx) * h_a2;
  const T g_g2y = g_fzv * h_b2 - (g_may + 2.0 * g_mby) * h_b3;
  const T g_g2z = -g_fyv * h_b2 - (g_maz + 2.0 * g_mbz) * h_b3;
  const T g_se = g_ha1 * (0.5 * k.damp_a1) + g_hb2 * (0.5 * k.damp_b2) +
                 g_ha2 * (0.25 * k.damp_a2) + g_hb3 * (0.25 * k.damp_b3) +
                 g_hb2h * (0.25 * k.damp_b2);
  T g_e = (g_se * valid * damp) * pick(sqe > 0.0, 0.5 / sqe, zero);
  put_in(kDamp, g_se * valid * sqe);
  g_px += g_gpx;
  g_t1y += g_g1y, g_t1z += g_g1z;
  g_t2x += g_g2x, g_t2y += g_g2y, g_t2z += g_g2z;
  const T g_old[9] = {-g_gpx, -g_gpy, -g_gpz, -g_g1x, -g_g1y, -g_g1z, -g_g2x, -g_g2y, -g_g2z};
  for (int j = 0; j < 9; ++j) put_in(kPrev + j, g_old[j]);
  // Elastic forces and moments.
  const T g_stress = g_fx * k.area + out(kStress) + out(kEnergy) * strain;
  T g_strain = out(kStrain) + out(kEnergy) * stress;
  const T g_b2c = -g_fyv * (t1z + t2z) + g_fzv * (t1y + t2y);
  g_t1z -= g_fyv * b2c, g_t2z -= g_fyv * b2c;
  g_t1y += g_fzv * b2c, g_t2y += g_fzv * b2c;
  const T g_a2 = g_max * t2x - g_mbx * t2x;
  g_t2x += (g_max - g_mbx) * a2;
  T g_b3 = -g_may * (t1y + t1y + t2y) - g_maz * (t1z + t1z + t2z) - g_mby * (t1y + (t2y + t2y)) -
           g_mbz * (t1z + (t2z + t2z));
  g_t1y -= (2.0 * g_may + g_mby) * b3, g_t2y -= (g_may + 2.0 * g_mby) * b3;
  g_t1z -= (2.0 * g_maz + g_mbz) * b3, g_t2z -= (g_maz + 2.0 * g_mbz) * b3;
  const T inv_cf = 1.0 / cf;
  g_b3 += g_b2c * 3.0 * inv_cf;
  const T g_chord = pick(floored, zero, -g_b2c * b2c * inv_cf);
  g_px += g_chord;
  T g_rest = g_chord;
  g_e += g_a2 * k.ka2 + g_b3 * k.kb3;
  g_strain += g_stress * coef;
  const T g_coef = g_stress * strain;
  T g_ea = k.axial_own ? g_coef : zero;
  if (!k.axial_own) g_e += g_coef;
  g_px += g_strain * k.inv_L;
  g_len += g_px, g_rest -= g_px;
  const T g_num = g_e * (1.0 / e_den), g_den = -g_num * e;
  g_ea += 2.0 * g_num * eb + g_den;
  put_in(kStiffB, g_num * (ea + ea) + g_den);
  put_in(kStiffA, g_ea);
  put_in(kCentreA + 3, 0.5 * g_rest);
  put_in(kCentreB + 3, 0.5 * g_rest);
  // The second rotation: t2 = (x2, y2, z2) k2.
  T g_x2 = g_t2x * k2, g_y2 = g_t2y * k2, g_z2 = g_t2z * k2;
  const T g_k2 = g_t2x * x2 + g_t2y * y2 + g_t2z * z2;
  const T g_ratio2 = 2.0 * g_k2 * sgn * inv_ww;
  T g_inv_ww = g_k2 * sgn * (ratio2 + ratio2);
  const T g_t2sq = g_ratio2 * atan_series_slope(t2sq);
  g_inv_ww += 2.0 * g_t2sq * n2 * inv_ww;
  g_x2 += 2.0 * g_t2sq * iw2 * x2, g_y2 += 2.0 * g_t2sq * iw2 * y2;
  g_z2 += 2.0 * g_t2sq * iw2 * z2;
  const T g_w2 = -g_inv_ww * iw2 * sgn;
  T g_h = g_w2 * a + g_x2 * bx + g_y2 * by + g_z2 * bz;
  const T g_a = g_w2 * h + g_y2 * z - g_z2 * y;
  const T g_bx = g_x2 * h - g_y2 * y - g_z2 * z;
  const T g_by = -g_w2 * z + g_x2 * y + g_y2 * h;
  const T g_bz = g_w2 * y + g_x2 * z + g_z2 * h;
  g_z += -g_w2 * by + g_x2 * bz + g_y2 * a - g_z2 * bx;
  g_y += g_w2 * bz + g_x2 * by - g_y2 * bx - g_z2 * a;
  // The first rotation: t1 = (0, z, -y) k1.
  const T g_k1 = g_t1y * z - g_t1z * y;
  g_z += g_t1y * k1, g_y -= g_t1z * k1;
  const T g_ratio1 = 2.0 * g_k1 * inv_h;
  g_inv_h += g_k1 * (ratio1 + ratio1);
  const T g_t1sq = g_ratio1 * atan_series_slope(t1sq);
  g_inv_h += 2.0 * g_t1sq * yz2 * inv_h;
  g_y += 2.0 * g_t1sq * ih2 * y, g_z += 2.0 * g_t1sq * ih2 * z;
  g_h -= g_inv_h * ih2;
  g_len += g_h, g_x += g_h;
  {
    const T c = pick(len0 > 0.0, g_len * (0.5 * inv_len), zero);
    g_x += 2.0 * c * x, g_y += 2.0 * c * y, g_z += 2.0 * c * z;
  }
  // The relative rotation conj(q_a) q_b: g_v[d] = g_bx, g_v[d + 1] = g_by, g_v[d + 2] = g_bz.
  const T g_v[3] = {sel(g_bx, g_bz, g_by), sel(g_by, g_bx, g_bz), sel(g_bz, g_by, g_bx)};
  T g_ax = -g_v[0] * bw_ + g_v[1] * bz_ - g_v[2] * by_ + g_a * bx_;
  T g_ay = -g_v[0] * bz_ - g_v[1] * bw_ + g_v[2] * bx_ + g_a * by_;
  T g_az = g_v[0] * by_ - g_v[1] * bx_ - g_v[2] * bw_ + g_a * bz_;
  T g_aw = g_v[0] * bx_ + g_v[1] * by_ + g_v[2] * bz_ + g_a * bw_;
  put_in(kQuatB, g_v[0] * aw - g_v[1] * az + g_v[2] * ay + g_a * ax);
  put_in(kQuatB + 1, g_v[0] * az + g_v[1] * aw - g_v[2] * ax + g_a * ay);
  put_in(kQuatB + 2, -g_v[0] * ay + g_v[1] * ax + g_v[2] * aw + g_a * az);
  put_in(kQuatB + 3, -g_v[0] * ax - g_v[1] * ay - g_v[2] * az + g_a * aw);
  // The chord in a's permuted axes.
  const T g_xyz[3] = {g_x, g_y, g_z};
  for (int j = 0; j < 3; ++j)
    for (int c = 0; c < 3; ++c)
      g_m[3 * j + c] += g_xyz[j] * dl[c], g_dl[c] += g_xyz[j] * m[3 * j + c];
  for (int c = 0; c < 3; ++c) put_in(kCentreB + c, g_dl[c]), put_in(kCentreA + c, -g_dl[c]);
  // a's rotation matrix: g_R[3 c + r] = g_m[3 ((c - d) % 3) + r].
  T g_R[9];
  for (int r = 0; r < 3; ++r) {
    g_R[r] = sel(g_m[r], g_m[6 + r], g_m[3 + r]);
    g_R[3 + r] = sel(g_m[3 + r], g_m[r], g_m[6 + r]);
    g_R[6 + r] = sel(g_m[6 + r], g_m[3 + r], g_m[r]);
  }
  const T g_tyy = -g_R[0] - g_R[8], g_tzz = -g_R[0] - g_R[4], g_txx = -g_R[4] - g_R[8];
  const T g_txy = g_R[3] + g_R[1], g_twz = -g_R[3] + g_R[1];
  const T g_txz = g_R[6] + g_R[2], g_twy = g_R[6] - g_R[2];
  const T g_tyz = g_R[7] + g_R[5], g_twx = -g_R[7] + g_R[5];
  const T g_tx = g_twx * aw + g_txx * ax;
  const T g_ty = g_twy * aw + g_txy * ax + g_tyy * ay;
  const T g_tz = g_twz * aw + g_txz * ax + g_tyz * ay + g_tzz * az;
  g_aw += g_twx * tx + g_twy * ty + g_twz * tz;
  g_ax += g_txx * tx + g_txy * ty + g_txz * tz + 2.0 * g_tx;
  g_ay += g_tyy * ty + g_tyz * tz + 2.0 * g_ty;
  g_az += g_tzz * tz + 2.0 * g_tz;
  put_in(kQuatA, g_ax), put_in(kQuatA + 1, g_ay), put_in(kQuatA + 2, g_az);
  put_in(kQuatA + 3, g_aw);
}

// The whole lane groups of bonds from the first; returns how many bonds that is (the caller
// takes the rest one by one with its own `double` instance).
template <class T>
int run_bond_reverse(const grad::BondReverseIo& io, const ModelConstants& k) {
  int i = 0;
  for (; i + kLanes<T> <= static_cast<int>(io.nb); i += kLanes<T>) bond_reverse_lanes<T>(io, i, k);
  return i;
}

}  // namespace
}  // namespace plastivox
