// The bond stage's adjoint (bond_adjoint.hpp).
#include "bond_adjoint.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "adj.hpp"
#include "elementary.hpp"
#include "lanes.hpp"
// After the lane vocabularies: the kernel template finds them by argument-dependent lookup.
#include "bond_body.hpp"

namespace plastivox::grad {

void keep_bond_stage(const BondKernelIo& io, const BondStageLayout& L, double damp, int32_t damp_id,
                     double* values, int32_t* ids) {
  const auto keep = [&](size_t at, const double* row, size_t count) {
    std::memcpy(values + at, row, count * sizeof(double));
    const int32_t* row_ids = g_tape ? g_tape->ids_of(row) : nullptr;
    if (row_ids)
      std::memcpy(ids + at, row_ids, count * sizeof(int32_t));
    else
      std::fill(ids + at, ids + at + count, -1);
  };
  keep(0, io.centre_size, 4 * L.n);
  keep(L.quat(), io.quat, 4 * L.n);
  keep(L.stiff(), io.stiff, L.n);
  for (int j = 0; j < 9; ++j) keep(L.prev(j), io.prev[j], L.nb);
  values[L.damp()] = damp;
  ids[L.damp()] = damp_id;
}

BondArgs bond_args(const BondKernelIo& io, const BondStageLayout& L, const double* values,
                   const int32_t* ids, int b, bool valid) {
  BondArgs a;
  const size_t ia = static_cast<size_t>(io.bond_a[b]), ib = static_cast<size_t>(io.bond_b[b]);
  const auto take = [&](int slot, size_t at) {
    a.v[slot] = values[at];
    a.id[slot] = ids[at];
  };
  for (int c = 0; c < 4; ++c) {
    take(kCentreA + c, 4 * ia + c);
    take(kCentreB + c, 4 * ib + c);
    take(kQuatA + c, L.quat() + 4 * ia + c);
    take(kQuatB + c, L.quat() + 4 * ib + c);
  }
  take(kStiffA, L.stiff() + ia);
  take(kStiffB, L.stiff() + ib);
  for (int j = 0; j < 9; ++j) take(kPrev + j, L.prev(j) + static_cast<size_t>(b));
  take(kDamp, L.damp());
  a.axis = static_cast<int32_t>(io.axis_wide[b]);
  a.valid = valid ? 1 : 0;
  return a;
}

namespace {

// One bond as the kernel sees it: bond 0 from voxel 0 to voxel 1, in arrays of its own.
struct LocalBond {
  double centre[8], quat[8], stiff[2], prev[9], prev_next[9], out[3][4], strain, stress, energy;
  int a = 0, b = 1, redo = 0;
  int64_t axis = 0;
  uint8_t valid = 0;
  int32_t centre_id[8], quat_id[8], stiff_id[2], prev_id[9], prev_next_id[9], out_id[3][4],
      strain_id, stress_id, energy_id;
  BondKernelIo io;

  LocalBond() {
    io.bond_a = &a;
    io.bond_b = &b;
    io.axis_wide = &axis;
    io.centre_size = centre;
    io.quat = quat;
    io.stiff = stiff;
    io.prev_valid = &valid;
    io.all_valid = false;
    for (int j = 0; j < 9; ++j) io.prev[j] = &prev[j], io.prev_next[j] = &prev_next[j];
    for (int v = 0; v < 3; ++v) io.out[v] = out[v];
    io.strain = &strain;
    io.stress = &stress;
    io.energy = &energy;
    io.redo = &redo;
  }
  void shadow(Tape& t) {
    t.add_shadow(centre, centre_id);
    t.add_shadow(quat, quat_id);
    t.add_shadow(stiff, stiff_id);
    for (int j = 0; j < 9; ++j)
      t.add_shadow(&prev[j], &prev_id[j]), t.add_shadow(&prev_next[j], &prev_next_id[j]);
    for (int v = 0; v < 3; ++v) t.add_shadow(out[v], out_id[v]);
    t.add_shadow(&strain, &strain_id);
    t.add_shadow(&stress, &stress_id);
    t.add_shadow(&energy, &energy_id);
  }
};

}  // namespace

void bond_reverse_tape(const BondArgs& a, const ModelConstants& k, const double* out_adj,
                       double* in_adj) {
  LocalBond L;
  Tape tape;
  L.shadow(tape);
  int32_t leaf[kBondInputs];
  for (int j = 0; j < kBondInputs; ++j) leaf[j] = tape.leaf();
  for (int c = 0; c < 4; ++c) {
    L.centre[c] = a.v[kCentreA + c], L.centre_id[c] = leaf[kCentreA + c];
    L.centre[4 + c] = a.v[kCentreB + c], L.centre_id[4 + c] = leaf[kCentreB + c];
    L.quat[c] = a.v[kQuatA + c], L.quat_id[c] = leaf[kQuatA + c];
    L.quat[4 + c] = a.v[kQuatB + c], L.quat_id[4 + c] = leaf[kQuatB + c];
  }
  for (int j = 0; j < 2; ++j) L.stiff[j] = a.v[kStiffA + j], L.stiff_id[j] = leaf[kStiffA + j];
  for (int j = 0; j < 9; ++j) L.prev[j] = a.v[kPrev + j], L.prev_id[j] = leaf[kPrev + j];
  L.axis = a.axis;
  L.valid = a.valid;
  Tape* const outer = g_tape;
  g_tape = &tape;
  bond_lanes<Adj, Adj>(L.io, 0, k, Adj(a.v[kDamp], leaf[kDamp]), L.redo);
  g_tape = outer;
  std::vector<double> adj(tape.nodes.size(), 0.0);
  const auto seed = [&](int32_t id, double v) {
    if (id >= 0) adj[id] += v;
  };
  for (int v = 0; v < 3; ++v)
    for (int c = 0; c < 3; ++c) seed(L.out_id[v][c], out_adj[kOut + 3 * v + c]);
  for (int j = 0; j < 9; ++j) seed(L.prev_next_id[j], out_adj[kPrevNext + j]);
  seed(L.strain_id, out_adj[kStrain]);
  seed(L.stress_id, out_adj[kStress]);
  seed(L.energy_id, out_adj[kEnergy]);
  sweep_nodes(tape, adj, 0, tape.nodes.size());
  for (int j = 0; j < kBondInputs; ++j) in_adj[j] += adj[leaf[j]];
}

namespace {

// d/dz of atan_series (atan_series.hpp): the series 1 - z/3 + z^2/5 - ... + z^10/21 term by
// term, by Horner's rule on the coefficients (-1)^j j / (2 j + 1).
double atan_series_slope(double z) {
  static constexpr double c[11] = {0,        -1.0 / 3,  2.0 / 5,  -3.0 / 7,  4.0 / 9,  -5.0 / 11,
                                   6.0 / 13, -7.0 / 15, 8.0 / 17, -9.0 / 19, 10.0 / 21};
  double s = 0;
  for (int j = 10; j >= 1; --j) s = s * z + c[j];
  return s;
}

}  // namespace

bool bond_reverse(const BondArgs& A, const ModelConstants& k, const double* out_adj,
                  double* in_adj) {
  // ---- The forward again, on doubles, keeping what the reverse needs (bond_body.hpp's
  // operations in its order, the small-angle path only) ----
  const double* pa = A.v + kCentreA;
  const double* pb = A.v + kCentreB;
  const double ax = A.v[kQuatA], ay = A.v[kQuatA + 1], az = A.v[kQuatA + 2], aw = A.v[kQuatA + 3];
  const double bx_ = A.v[kQuatB], by_ = A.v[kQuatB + 1], bz_ = A.v[kQuatB + 2],
               bw_ = A.v[kQuatB + 3];
  const double ea = A.v[kStiffA], eb = A.v[kStiffB], damp = A.v[kDamp];
  const double* old = A.v + kPrev;
  const int d = A.axis;
  const double dl[3] = {pb[0] - pa[0], pb[1] - pa[1], pb[2] - pa[2]};
  const double tx = ax + ax, ty = ay + ay, tz = az + az;
  const double twx = tx * aw, twy = ty * aw, twz = tz * aw;
  const double txx = tx * ax, txy = ty * ax, txz = tz * ax;
  const double tyy = ty * ay, tyz = tz * ay, tzz = tz * az;
  double R[9];
  R[0] = 1.0 - (tyy + tzz), R[3] = txy - twz, R[6] = txz + twy;
  R[1] = txy + twz, R[4] = 1.0 - (txx + tzz), R[7] = tyz - twx;
  R[2] = txz - twy, R[5] = tyz + twx, R[8] = 1.0 - (txx + tyy);
  double m[9];
  for (int j = 0; j < 3; ++j)
    for (int r = 0; r < 3; ++r) m[3 * j + r] = R[3 * ((j + d) % 3) + r];
  const double x = m[0] * dl[0] + m[1] * dl[1] + m[2] * dl[2];
  const double y = m[3] * dl[0] + m[4] * dl[1] + m[5] * dl[2];
  const double z = m[6] * dl[0] + m[7] * dl[1] + m[8] * dl[2];
  double v[3];
  v[0] = aw * bx_ - ax * bw_ - ay * bz_ + az * by_;
  v[1] = aw * by_ + ax * bz_ - ay * bw_ - az * bx_;
  v[2] = aw * bz_ - ax * by_ + ay * bx_ - az * bw_;
  const double a = aw * bw_ + ax * bx_ + ay * by_ + az * bz_;
  const double bx = v[d], by = v[(d + 1) % 3], bz = v[(d + 2) % 3];
  const double len = std::sqrt(x * x + y * y + z * z);
  const double h = len + x;
  if (h <= 1e-6 * len) return false;  // degenerate
  const double inv_h = 1.0 / h;
  const double yz2 = y * y + z * z, ih2 = inv_h * inv_h;
  const double t1sq = yz2 * ih2;
  constexpr double kWide = 0.03956612989658004;  // atan_over_t's tan^2(pi / 16)
  if (t1sq >= kWide) return false;
  const double ratio1 = atan_series(t1sq);
  const double k1 = (ratio1 + ratio1) * inv_h;
  const double t1y = z * k1, t1z = -y * k1;
  const double w2 = h * a - z * by + y * bz;
  const double x2 = h * bx + z * bz + y * by;
  const double y2 = h * by + a * z - y * bx;
  const double z2 = h * bz - a * y - z * bx;
  const double sgn = w2 < 0.0 ? -1.0 : 1.0;
  const double ww = w2 * sgn;
  if (w2 * w2 <= 2e-6 * (len * h)) return false;  // the scalar path's (redo)
  const double inv_ww = 1.0 / ww;
  const double n2 = x2 * x2 + y2 * y2 + z2 * z2, iw2 = inv_ww * inv_ww;
  const double t2sq = n2 * iw2;
  if (t2sq >= kWide) return false;
  const double ratio2 = atan_series(t2sq);
  const double k2 = (ratio2 + ratio2) * inv_ww * sgn;
  const double t2x = x2 * k2, t2y = y2 * k2, t2z = z2 * k2;
  const double rest = 0.5 * (A.v[kCentreA + 3] + A.v[kCentreB + 3]);
  const double px = len - rest;
  const double strain = px * k.inv_L;
  const double e_num = (ea + ea) * eb, e_den = ea + eb, e = e_num / e_den;
  const double coef = k.axial_own ? ea : e;
  const double stress = coef * strain;
  const double a2 = e * k.ka2, b3 = e * k.kb3;
  const double chord = px + rest;
  const bool floored = chord < k.min_shear_chord;
  const double cf = floored ? k.min_shear_chord : chord;
  const double b2c = 3.0 * b3 / cf;
  const double gpx = px - old[0], gpy = 0.0 - old[1], gpz = 0.0 - old[2];
  const double g1x = 0.0 - old[3], g1y = t1y - old[4], g1z = t1z - old[5];
  const double g2x = t2x - old[6], g2y = t2y - old[7], g2z = t2z - old[8];
  const double valid = A.valid ? 1.0 : 0.0;
  const double sqe = std::sqrt(e);
  const double se = sqe * damp * valid;
  const double h_a1 = se * (0.5 * k.damp_a1), h_b1 = h_a1, h_b2 = se * (0.5 * k.damp_b2);
  const double h_a2 = se * (0.25 * k.damp_a2), h_b3 = se * (0.25 * k.damp_b3);
  const double h_b2h = se * (0.25 * k.damp_b2);
  const double fx = stress * k.area + h_a1 * gpx;
  const double fyv = -b2c * (t1z + t2z) + (h_b1 * gpy - h_b2 * (g1z + g2z));
  const double fzv = b2c * (t1y + t2y) + (h_b1 * gpz + h_b2 * (g1y + g2y));
  const double max = a2 * t2x + h_a2 * (g2x - g1x);
  const double may = -b3 * (t1y + t1y + t2y) + (-h_b2h * gpz - h_b3 * (g1y + g1y + g2y));
  const double maz = -b3 * (t1z + t1z + t2z) + (h_b2h * gpy - h_b3 * (g1z + g1z + g2z));
  const double mbx = a2 * (0.0 - t2x) + h_a2 * (g1x - g2x);
  const double mby = -b3 * (t1y + (t2y + t2y)) + (-h_b2h * gpz - h_b3 * (g1y + (g2y + g2y)));
  const double mbz = -b3 * (t1z + (t2z + t2z)) + (h_b2h * gpy - h_b3 * (g1z + (g2z + g2z)));
  const double inv_len = 1.0 / len;
  const double u[3] = {dl[0] * inv_len, dl[1] * inv_len, dl[2] * inv_len};
  const double s[3] = {m[0] + u[0], m[1] + u[1], m[2] + u[2]};
  const double ky = y * inv_h, kz = z * inv_h;
  double e1[3], e2[3];
  for (int c = 0; c < 3; ++c) e1[c] = m[3 + c] - s[c] * ky, e2[c] = m[6 + c] - s[c] * kz;
  const double vx[3] = {fx, max, mbx}, vy[3] = {fyv, may, mby}, vz[3] = {fzv, maz, mbz};

  // ---- The reverse: g_* is the adjoint of * ----
  double g_u[3] = {0, 0, 0}, g_e1[3] = {0, 0, 0}, g_e2[3] = {0, 0, 0};
  double g_vx[3] = {0, 0, 0}, g_vy[3] = {0, 0, 0}, g_vz[3] = {0, 0, 0};
  for (int w = 0; w < 3; ++w)
    for (int c = 0; c < 3; ++c) {
      const double g = out_adj[kOut + 3 * w + c];
      g_u[c] += g * vx[w], g_vx[w] += g * u[c];
      g_e1[c] += g * vy[w], g_vy[w] += g * e1[c];
      g_e2[c] += g * vz[w], g_vz[w] += g * e2[c];
    }
  double g_m[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0}, g_s[3] = {0, 0, 0};
  double g_ky = 0, g_kz = 0;
  for (int c = 0; c < 3; ++c) {
    g_m[3 + c] += g_e1[c], g_s[c] -= g_e1[c] * ky, g_ky -= g_e1[c] * s[c];
    g_m[6 + c] += g_e2[c], g_s[c] -= g_e2[c] * kz, g_kz -= g_e2[c] * s[c];
    g_m[c] += g_s[c], g_u[c] += g_s[c];
  }
  double g_x = 0, g_y = g_ky * inv_h, g_z = g_kz * inv_h;
  double g_inv_h = g_ky * y + g_kz * z;
  double g_dl[3], g_inv_len = 0;
  for (int c = 0; c < 3; ++c) g_dl[c] = g_u[c] * inv_len, g_inv_len += g_u[c] * dl[c];
  double g_len = g_inv_len * (-inv_len / len);
  // The next deformation.
  const double* g_pn = out_adj + kPrevNext;
  double g_px = g_pn[0], g_t1y = g_pn[4], g_t1z = g_pn[5];
  double g_t2x = g_pn[6], g_t2y = g_pn[7], g_t2z = g_pn[8];
  const double g_fx = g_vx[0], g_max = g_vx[1], g_mbx = g_vx[2];
  const double g_fyv = g_vy[0], g_may = g_vy[1], g_mby = g_vy[2];
  const double g_fzv = g_vz[0], g_maz = g_vz[1], g_mbz = g_vz[2];
  // Damping.
  const double g_ha1 = g_fx * gpx + g_fyv * gpy + g_fzv * gpz;  // h_b1 is h_a1
  const double g_hb2 = -g_fyv * (g1z + g2z) + g_fzv * (g1y + g2y);
  const double g_ha2 = g_max * (g2x - g1x) + g_mbx * (g1x - g2x);
  const double g_hb2h = -g_may * gpz + g_maz * gpy - g_mby * gpz + g_mbz * gpy;
  const double g_hb3 = -g_may * (g1y + g1y + g2y) - g_maz * (g1z + g1z + g2z) -
                       g_mby * (g1y + (g2y + g2y)) - g_mbz * (g1z + (g2z + g2z));
  const double g_gpx = g_fx * h_a1;
  const double g_gpy = g_fyv * h_b1 + (g_maz + g_mbz) * h_b2h;
  const double g_gpz = g_fzv * h_b1 - (g_may + g_mby) * h_b2h;
  const double g_g1x = (g_mbx - g_max) * h_a2;
  const double g_g1y = g_fzv * h_b2 - (2 * g_may + g_mby) * h_b3;
  const double g_g1z = -g_fyv * h_b2 - (2 * g_maz + g_mbz) * h_b3;
  const double g_g2x = (g_max - g_mbx) * h_a2;
  const double g_g2y = g_fzv * h_b2 - (g_may + 2 * g_mby) * h_b3;
  const double g_g2z = -g_fyv * h_b2 - (g_maz + 2 * g_mbz) * h_b3;
  const double g_se = g_ha1 * (0.5 * k.damp_a1) + g_hb2 * (0.5 * k.damp_b2) +
                      g_ha2 * (0.25 * k.damp_a2) + g_hb3 * (0.25 * k.damp_b3) +
                      g_hb2h * (0.25 * k.damp_b2);
  double g_e = (g_se * valid * damp) * (sqe > 0 ? 0.5 / sqe : 0.0);
  const double g_damp = g_se * valid * sqe;
  double g_old[9];
  g_px += g_gpx, g_old[0] = -g_gpx, g_old[1] = -g_gpy, g_old[2] = -g_gpz;
  g_old[3] = -g_g1x, g_t1y += g_g1y, g_old[4] = -g_g1y, g_t1z += g_g1z, g_old[5] = -g_g1z;
  g_t2x += g_g2x, g_old[6] = -g_g2x, g_t2y += g_g2y, g_old[7] = -g_g2y;
  g_t2z += g_g2z, g_old[8] = -g_g2z;
  // Elastic forces and moments.
  double g_stress = g_fx * k.area + out_adj[kStress] + out_adj[kEnergy] * strain;
  double g_strain = out_adj[kStrain] + out_adj[kEnergy] * stress;
  const double g_b2c = -g_fyv * (t1z + t2z) + g_fzv * (t1y + t2y);
  g_t1z -= g_fyv * b2c, g_t2z -= g_fyv * b2c;
  g_t1y += g_fzv * b2c, g_t2y += g_fzv * b2c;
  const double g_a2 = g_max * t2x - g_mbx * t2x;
  g_t2x += (g_max - g_mbx) * a2;
  double g_b3 = -g_may * (t1y + t1y + t2y) - g_maz * (t1z + t1z + t2z) -
                g_mby * (t1y + (t2y + t2y)) - g_mbz * (t1z + (t2z + t2z));
  g_t1y -= (2 * g_may + g_mby) * b3, g_t2y -= (g_may + 2 * g_mby) * b3;
  g_t1z -= (2 * g_maz + g_mbz) * b3, g_t2z -= (g_maz + 2 * g_mbz) * b3;
  g_b3 += g_b2c * 3.0 / cf;
  const double g_chord = floored ? 0.0 : -g_b2c * b2c / cf;
  g_px += g_chord;
  double g_rest = g_chord;
  g_e += g_a2 * k.ka2 + g_b3 * k.kb3;
  g_strain += g_stress * coef;
  const double g_coef = g_stress * strain;
  double g_ea = k.axial_own ? g_coef : 0.0;
  if (!k.axial_own) g_e += g_coef;
  g_px += g_strain * k.inv_L;
  g_len += g_px, g_rest -= g_px;
  {
    const double g_num = g_e / e_den, g_den = -g_e * e / e_den;
    g_ea += 2 * g_num * eb + g_den;
    in_adj[kStiffB] += g_num * (ea + ea) + g_den;
  }
  in_adj[kStiffA] += g_ea;
  in_adj[kCentreA + 3] += 0.5 * g_rest;
  in_adj[kCentreB + 3] += 0.5 * g_rest;
  for (int j = 0; j < 9; ++j) in_adj[kPrev + j] += g_old[j];
  in_adj[kDamp] += g_damp;
  // The second rotation: t2 = (x2, y2, z2) k2.
  double g_x2 = g_t2x * k2, g_y2 = g_t2y * k2, g_z2 = g_t2z * k2;
  const double g_k2 = g_t2x * x2 + g_t2y * y2 + g_t2z * z2;
  const double g_ratio2 = 2 * g_k2 * sgn * inv_ww;
  double g_inv_ww = g_k2 * sgn * (ratio2 + ratio2);
  const double g_t2sq = g_ratio2 * atan_series_slope(t2sq);
  g_inv_ww += 2 * g_t2sq * n2 * inv_ww;
  g_x2 += 2 * g_t2sq * iw2 * x2, g_y2 += 2 * g_t2sq * iw2 * y2, g_z2 += 2 * g_t2sq * iw2 * z2;
  const double g_w2 = -g_inv_ww * inv_ww / ww * sgn;
  double g_h = g_w2 * a + g_x2 * bx + g_y2 * by + g_z2 * bz;
  const double g_a = g_w2 * h + g_y2 * z - g_z2 * y;
  const double g_bx = g_x2 * h - g_y2 * y - g_z2 * z;
  const double g_by = -g_w2 * z + g_x2 * y + g_y2 * h;
  const double g_bz = g_w2 * y + g_x2 * z + g_z2 * h;
  g_z += -g_w2 * by + g_x2 * bz + g_y2 * a - g_z2 * bx;
  g_y += g_w2 * bz + g_x2 * by - g_y2 * bx - g_z2 * a;
  // The first rotation: t1 = (0, z, -y) k1.
  const double g_k1 = g_t1y * z - g_t1z * y;
  g_z += g_t1y * k1, g_y -= g_t1z * k1;
  const double g_ratio1 = 2 * g_k1 * inv_h;
  g_inv_h += g_k1 * (ratio1 + ratio1);
  const double g_t1sq = g_ratio1 * atan_series_slope(t1sq);
  g_inv_h += 2 * g_t1sq * yz2 * inv_h;
  g_y += 2 * g_t1sq * ih2 * y, g_z += 2 * g_t1sq * ih2 * z;
  g_h -= g_inv_h * inv_h / h;
  g_len += g_h, g_x += g_h;
  if (len > 0) {
    const double c = g_len * (0.5 / len);
    g_x += 2 * c * x, g_y += 2 * c * y, g_z += 2 * c * z;
  }
  // The relative rotation conj(q_a) q_b.
  double g_v[3];
  g_v[d] = g_bx, g_v[(d + 1) % 3] = g_by, g_v[(d + 2) % 3] = g_bz;
  double g_ax = -g_v[0] * bw_ + g_v[1] * bz_ - g_v[2] * by_ + g_a * bx_;
  double g_ay = -g_v[0] * bz_ - g_v[1] * bw_ + g_v[2] * bx_ + g_a * by_;
  double g_az = g_v[0] * by_ - g_v[1] * bx_ - g_v[2] * bw_ + g_a * bz_;
  double g_aw = g_v[0] * bx_ + g_v[1] * by_ + g_v[2] * bz_ + g_a * bw_;
  in_adj[kQuatB] += g_v[0] * aw - g_v[1] * az + g_v[2] * ay + g_a * ax;
  in_adj[kQuatB + 1] += g_v[0] * az + g_v[1] * aw - g_v[2] * ax + g_a * ay;
  in_adj[kQuatB + 2] += -g_v[0] * ay + g_v[1] * ax + g_v[2] * aw + g_a * az;
  in_adj[kQuatB + 3] += -g_v[0] * ax - g_v[1] * ay - g_v[2] * az + g_a * aw;
  // The chord in a's permuted axes.
  const double g_xyz[3] = {g_x, g_y, g_z};
  for (int j = 0; j < 3; ++j)
    for (int c = 0; c < 3; ++c)
      g_m[3 * j + c] += g_xyz[j] * dl[c], g_dl[c] += g_xyz[j] * m[3 * j + c];
  for (int c = 0; c < 3; ++c) in_adj[kCentreB + c] += g_dl[c], in_adj[kCentreA + c] -= g_dl[c];
  // a's rotation matrix.
  double g_R[9];
  for (int j = 0; j < 3; ++j)
    for (int r = 0; r < 3; ++r) g_R[3 * ((j + d) % 3) + r] = g_m[3 * j + r];
  const double g_tyy = -g_R[0] - g_R[8], g_tzz = -g_R[0] - g_R[4], g_txx = -g_R[4] - g_R[8];
  const double g_txy = g_R[3] + g_R[1], g_twz = -g_R[3] + g_R[1];
  const double g_txz = g_R[6] + g_R[2], g_twy = g_R[6] - g_R[2];
  const double g_tyz = g_R[7] + g_R[5], g_twx = -g_R[7] + g_R[5];
  const double g_tx = g_twx * aw + g_txx * ax;
  const double g_ty = g_twy * aw + g_txy * ax + g_tyy * ay;
  const double g_tz = g_twz * aw + g_txz * ax + g_tyz * ay + g_tzz * az;
  g_aw += g_twx * tx + g_twy * ty + g_twz * tz;
  g_ax += g_txx * tx + g_txy * ty + g_txz * tz + 2 * g_tx;
  g_ay += g_tyy * ty + g_tyz * tz + 2 * g_ty;
  g_az += g_tzz * tz + 2 * g_tz;
  in_adj[kQuatA] += g_ax, in_adj[kQuatA + 1] += g_ay, in_adj[kQuatA + 2] += g_az;
  in_adj[kQuatA + 3] += g_aw;
  return true;
}

}  // namespace plastivox::grad
