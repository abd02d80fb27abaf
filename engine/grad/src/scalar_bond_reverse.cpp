// The reverse of a Voxelyze 0.9 bond by hand (scalar_bond_adjoint.hpp, voxelyze_bond_reverse):
// scalar_bond_body.hpp's scalar path recomputed on doubles, keeping what its reverse reads, then
// its adjoint, statement by statement backwards. The branches are the forward's, decided on the
// same values computed by the same operations (the frame's switch by the engine's own
// next_small_angle). Off its path (a chord of zero length, or one within 1e-7 rad of
// backwards) it returns false and the caller takes the scalar path recorded on a small tape.
#include <cmath>

#include "scalar_bond_adjoint.hpp"
#include "scalar_bond_body.hpp"

namespace plastivox::grad {
namespace {

using V3 = BondV3<double>;  // scalar_bond_body.hpp's, whose add_bond_damping this file calls

// to_bond and from_bond (scalar_bond_body.hpp) on V3: the cyclic permutation taking lattice
// axis d onto x, and its inverse. The adjoint of one is the other.
V3 to_axes(int d, const V3& v) {
  if (d == 0) return v;
  if (d == 1) return {v.y, v.z, v.x};
  return {v.z, v.x, v.y};
}
V3 from_axes(int d, const V3& v) {
  if (d == 0) return v;
  if (d == 1) return {v.z, v.x, v.y};
  return {v.y, v.z, v.x};
}

// voxelyze_rotation_vector (scalar_bond_body.hpp): its forward, keeping its branch and
// intermediates, and its reverse.
struct RotationVector {
  double w, x, y, z;
  int form = 0;  // 0: none (1 - w^2 <= 0), 1: the square root's form, 2: acos's
  double k = 0, a = 0, root_sl = 0;
  V3 out{0, 0, 0};

  void forward(double w_, double x_, double y_, double z_) {
    constexpr double kWAcos2Sqrt = 0.9988;
    constexpr double kAcos2Sqrt = 1.0 - kWAcos2Sqrt * kWAcos2Sqrt;
    w = w_, x = x_, y = y_, z = z_;
    const double sl = 1.0 - w * w;
    if (sl <= 0.0) {
      form = 0, out = {0, 0, 0};
      return;
    }
    const double wc = w > 1.0 ? 1.0 : w;
    if (sl < kAcos2Sqrt) {
      form = 1;
      k = std::sqrt((2.0 - 2.0 * wc) / sl);
      out = {x * 2.0 * k, y * 2.0 * k, z * 2.0 * k};
    } else {
      form = 2;
      a = std::acos(wc), root_sl = std::sqrt(sl);
      out = {x * 2.0 * a / root_sl, y * 2.0 * a / root_sl, z * 2.0 * a / root_sl};
    }
  }
  // From the adjoint g of out, adds those of w, x, y, z.
  void reverse(const V3& g, double& gw, double& gx, double& gy, double& gz) const {
    if (form == 0) return;
    const double wc = w > 1.0 ? 1.0 : w;
    if (form == 1) {
      // k = sqrt(2 / (1 + w)) differentiated as that form (scalar_bond_body.hpp).
      gx += g.x * 2.0 * k, gy += g.y * 2.0 * k, gz += g.z * 2.0 * k;
      const double gk = 2.0 * (x * g.x + y * g.y + z * g.z);
      if (w <= 1.0) gw += gk * (-k / (2.0 * (1.0 + wc)));
      return;
    }
    const double c = 2.0 * a / root_sl;
    gx += g.x * c, gy += g.y * c, gz += g.z * c;
    const double ga = 2.0 * (x * g.x + y * g.y + z * g.z) / root_sl;
    const double g_root = -(g.x * out.x + g.y * out.y + g.z * out.z) / root_sl;
    const double s = 1.0 - wc * wc;
    double gwc = 0;
    if (s > 0) gwc = ga * (-1.0 / std::sqrt(s));
    if (w <= 1.0) gw += gwc;
    gw += g_root * (0.5 / root_sl) * (-2.0 * w);
  }
};

// to_world's matrix (the frame f = (w, 0, y, z) undone): u = M v.
void frame_matrix(double w, double y, double z, double M[3][3]) {
  M[0][0] = 1.0 - 2.0 * (y * y + z * z), M[0][1] = 2.0 * w * z, M[0][2] = -2.0 * w * y;
  M[1][0] = -2.0 * w * z, M[1][1] = 1.0 - 2.0 * z * z, M[1][2] = 2.0 * y * z;
  M[2][0] = 2.0 * w * y, M[2][1] = 2.0 * y * z, M[2][2] = 1.0 - 2.0 * y * y;
}

}  // namespace

bool voxelyze_bond_reverse(const BondArgs& A, bool small_in, const ModelConstants& mk,
                           const double* out_adj, double* in_adj) {
  const double* v = A.v;
  const int d = A.axis;
  const double *ca = v + kCentreA, *cb = v + kCentreB, *qa = v + kQuatA, *qb = v + kQuatB;
  // ---- Forward (scalar_bond_lanes's operations, in its order where a branch reads them) ----
  double R[9];
  rotation_matrix(qa, R);
  const double dl[3] = {cb[0] - ca[0], cb[1] - ca[1], cb[2] - ca[2]};
  const double dx = dl[0], dy = dl[1], dz = dl[2];
  const V3 r = to_axes(d, {R[0] * dx + R[1] * dy + R[2] * dz, R[3] * dx + R[4] * dy + R[5] * dz,
                           R[6] * dx + R[7] * dy + R[8] * dz});
  BondV3<double> q_rel;
  const double qw = relative_rotation(d, qa, qb, q_rel);
  const V3 qv{q_rel.x, q_rel.y, q_rel.z};
  const double rest = 0.5 * (ca[3] + cb[3]);
  // The frame, as the engine's switch decides it (on r, the relative rotation and rest).
  bool small = small_in, damp_ok = A.valid != 0;
  {
    BondGeometry<double> g{};
    g.r = {r.x, r.y, r.z};
    g.q2w = qw;
    g.rest = rest;
    const bool next = next_small_angle(g, small);
    if (next != small) small = next, damp_ok = false;
  }
  V3 p;
  double fw = 1.0, fy = 0.0, fz = 0.0;
  RotationVector th1, th2;
  // The chord frame's intermediates.
  double len = 0, yx = 0, zx = 0, l = 0, li = 0, theta = 0, inv = 0, half = 0, sa = 0;
  V3 n{0, 0, 0};
  bool first_order = false;
  if (small) {
    p = {r.x - rest, r.y, r.z};
    th2.forward(qw, qv.x, qv.y, qv.z);
  } else {
    len = std::sqrt(r.x * r.x + r.y * r.y + r.z * r.z);
    p = {len - rest, 0.0, 0.0};
    if (r.x == 0.0 && r.y == 0.0 && r.z == 0.0) return false;
    yx = r.y / r.x, zx = r.z / r.x;
    if (yx < kVoxelyzeSmallAngle && yx > -kVoxelyzeSmallAngle && zx < kVoxelyzeSmallAngle &&
        zx > -kVoxelyzeSmallAngle) {
      first_order = true;
      fy = 0.5 * zx, fz = -0.5 * yx;
      fw = 1.0 + 0.5 * (-fy * fy - fz * fz);
    } else {
      l = std::sqrt(r.x * r.x + r.y * r.y + r.z * r.z), li = 1.0 / l;
      n = {r.x * li, r.y * li, r.z * li};
      theta = std::acos(n.x);
      if (theta > 3.14159265358979 - 1e-7) return false;  // a constant frame: the tape's
      inv = 1.0 / std::sqrt(n.z * n.z + n.y * n.y), half = 0.5 * theta;
      sa = std::sin(half);
      fw = std::cos(half), fy = n.z * inv * sa, fz = -n.y * inv * sa;
    }
    th1.forward(fw, 0.0, fy, fz);
    th2.forward(fw * qw - fy * qv.y - fz * qv.z, fw * qv.x + fy * qv.z - fz * qv.y,
                fw * qv.y + qw * fy + fz * qv.x, fw * qv.z + qw * fz - fy * qv.x);
  }
  const V3 t1 = th1.out, t2 = th2.out;
  const double strain = p.x * mk.inv_L;
  const double ea = v[kStiffA], eb = v[kStiffB];
  const double e = 2.0 * ea * eb / (ea + eb);
  const double se_mod = mk.axial_own ? ea : e;
  const double stress = se_mod * strain;
  const double a2 = e * mk.ka2, b1 = e * mk.kb1, b2 = e * mk.kb2, b3 = e * mk.kb3;
  V3 f{stress * mk.area, b1 * p.y - b2 * (t1.z + t2.z), b1 * p.z + b2 * (t1.y + t2.y)};
  V3 ma{a2 * (t2.x - t1.x), -b2 * p.z - b3 * (2.0 * t1.y + t2.y),
        b2 * p.y - b3 * (2.0 * t1.z + t2.z)};
  V3 mb{a2 * (t1.x - t2.x), -b2 * p.z - b3 * (t1.y + 2.0 * t2.y),
        b2 * p.y - b3 * (t1.z + 2.0 * t2.z)};
  const double* old = v + kPrev;
  const double damp = v[kDamp];
  V3 dp{0, 0, 0}, d1{0, 0, 0}, d2{0, 0, 0};
  double root_e = 0, se = 0, c_a1 = 0, c_b2 = 0, c_a2 = 0, c_b3 = 0, c_b2h = 0;
  if (damp_ok) {
    dp = {0.5 * (p.x - old[0]), 0.5 * (p.y - old[1]), 0.5 * (p.z - old[2])};
    d1 = {0.5 * (t1.x - old[3]), 0.5 * (t1.y - old[4]), 0.5 * (t1.z - old[5])};
    d2 = {0.5 * (t2.x - old[6]), 0.5 * (t2.y - old[7]), 0.5 * (t2.z - old[8])};
    root_e = std::sqrt(e), se = root_e * damp;
    c_a1 = se * mk.damp_a1, c_b2 = se * mk.damp_b2;
    c_a2 = 0.5 * se * mk.damp_a2, c_b3 = 0.5 * se * mk.damp_b3;
    c_b2h = 0.5 * c_b2;
    add_bond_damping<double>(f, ma, mb, dp, d1, d2, c_a1, c_b2, c_a2, c_b3, c_b2h);
  }
  const bool refresh = damp_ok || !A.valid;

  // ---- Reverse ----
  double g_in[kBondInputs] = {};
  double* g_old = g_in + kPrev;
  V3 g_p{0, 0, 0}, g_t1{0, 0, 0}, g_t2{0, 0, 0};
  // The next deformation: this one's, or the previous one kept.
  const double* g_next = out_adj + kPrevNext;
  if (refresh) {
    g_p = {g_next[0], g_next[1], g_next[2]};
    g_t1 = {g_next[3], g_next[4], g_next[5]};
    g_t2 = {g_next[6], g_next[7], g_next[8]};
  } else {
    for (int j = 0; j < 9; ++j) g_old[j] += g_next[j];
  }
  // to_world of f, ma and mb: world = R from_axes(M v).
  double M[3][3];
  frame_matrix(fw, fy, fz, M);
  double gR[9] = {}, gM[3][3] = {};
  V3 g_vec[3];
  const V3 vecs[3] = {f, ma, mb};
  for (int k = 0; k < 3; ++k) {
    const V3& vk = vecs[k];
    const double vv[3] = {vk.x, vk.y, vk.z};
    const V3 u{M[0][0] * vk.x + M[0][1] * vk.y + M[0][2] * vk.z,
               M[1][0] * vk.x + M[1][1] * vk.y + M[1][2] * vk.z,
               M[2][0] * vk.x + M[2][1] * vk.y + M[2][2] * vk.z};
    const V3 o = from_axes(d, u);
    const double oo[3] = {o.x, o.y, o.z};
    const double* gw = out_adj + kOut + 3 * k;
    double go[3];
    for (int j = 0; j < 3; ++j) {
      go[j] = R[3 * j] * gw[0] + R[3 * j + 1] * gw[1] + R[3 * j + 2] * gw[2];
      for (int i = 0; i < 3; ++i) gR[3 * j + i] += gw[i] * oo[j];
    }
    const V3 gu = to_axes(d, {go[0], go[1], go[2]});
    const double guu[3] = {gu.x, gu.y, gu.z};
    g_vec[k] = {M[0][0] * gu.x + M[1][0] * gu.y + M[2][0] * gu.z,
                M[0][1] * gu.x + M[1][1] * gu.y + M[2][1] * gu.z,
                M[0][2] * gu.x + M[1][2] * gu.y + M[2][2] * gu.z};
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) gM[i][j] += guu[i] * vv[j];
  }
  const V3 &g_f = g_vec[0], &g_ma = g_vec[1], &g_mb = g_vec[2];
  double g_fw = 0, g_fy = 0, g_fz = 0;
  if (!small) {
    g_fw += 2.0 * fz * (gM[0][1] - gM[1][0]) + 2.0 * fy * (gM[2][0] - gM[0][2]);
    g_fy += -4.0 * fy * (gM[0][0] + gM[2][2]) + 2.0 * fw * (gM[2][0] - gM[0][2]) +
            2.0 * fz * (gM[1][2] + gM[2][1]);
    g_fz += -4.0 * fz * (gM[0][0] + gM[1][1]) + 2.0 * fw * (gM[0][1] - gM[1][0]) +
            2.0 * fy * (gM[1][2] + gM[2][1]);
  }
  // Damping.
  double g_e = 0;
  if (damp_ok) {
    const double c_b1 = c_a1;
    const double g_c_a1 = g_f.x * dp.x + g_f.y * dp.y + g_f.z * dp.z;
    double g_c_b2 = -g_f.y * (d1.z + d2.z) + g_f.z * (d1.y + d2.y);
    const double g_c_b2h = -g_ma.y * dp.z + g_ma.z * dp.y - g_mb.y * dp.z + g_mb.z * dp.y;
    const double g_c_a2 = (g_ma.x - g_mb.x) * (d2.x - d1.x);
    const double g_c_b3 = -g_ma.y * (2.0 * d1.y + d2.y) - g_ma.z * (2.0 * d1.z + d2.z) -
                          g_mb.y * (d1.y + 2.0 * d2.y) - g_mb.z * (d1.z + 2.0 * d2.z);
    g_c_b2 += 0.5 * g_c_b2h;
    const V3 g_dp{g_f.x * c_a1, g_f.y * c_b1 + (g_ma.z + g_mb.z) * c_b2h,
                  g_f.z * c_b1 - (g_ma.y + g_mb.y) * c_b2h};
    const V3 g_d1{c_a2 * (g_mb.x - g_ma.x), g_f.z * c_b2 - c_b3 * (2.0 * g_ma.y + g_mb.y),
                  -g_f.y * c_b2 - c_b3 * (2.0 * g_ma.z + g_mb.z)};
    const V3 g_d2{c_a2 * (g_ma.x - g_mb.x), g_f.z * c_b2 - c_b3 * (g_ma.y + 2.0 * g_mb.y),
                  -g_f.y * c_b2 - c_b3 * (g_ma.z + 2.0 * g_mb.z)};
    g_p.x += 0.5 * g_dp.x, g_p.y += 0.5 * g_dp.y, g_p.z += 0.5 * g_dp.z;
    g_t1.x += 0.5 * g_d1.x, g_t1.y += 0.5 * g_d1.y, g_t1.z += 0.5 * g_d1.z;
    g_t2.x += 0.5 * g_d2.x, g_t2.y += 0.5 * g_d2.y, g_t2.z += 0.5 * g_d2.z;
    g_old[0] -= 0.5 * g_dp.x, g_old[1] -= 0.5 * g_dp.y, g_old[2] -= 0.5 * g_dp.z;
    g_old[3] -= 0.5 * g_d1.x, g_old[4] -= 0.5 * g_d1.y, g_old[5] -= 0.5 * g_d1.z;
    g_old[6] -= 0.5 * g_d2.x, g_old[7] -= 0.5 * g_d2.y, g_old[8] -= 0.5 * g_d2.z;
    const double g_se = g_c_a1 * mk.damp_a1 + g_c_b2 * mk.damp_b2 +
                        0.5 * (g_c_a2 * mk.damp_a2 + g_c_b3 * mk.damp_b3);
    g_in[kDamp] += g_se * root_e;
    if (root_e > 0) g_e += g_se * damp * (0.5 / root_e);
  }
  // The elastic forces and moments.
  const double g_a2 = (g_ma.x - g_mb.x) * (t2.x - t1.x);
  const double g_b1 = g_f.y * p.y + g_f.z * p.z;
  const double g_b2 = -g_f.y * (t1.z + t2.z) + g_f.z * (t1.y + t2.y) - (g_ma.y + g_mb.y) * p.z +
                      (g_ma.z + g_mb.z) * p.y;
  const double g_b3 = -g_ma.y * (2.0 * t1.y + t2.y) - g_ma.z * (2.0 * t1.z + t2.z) -
                      g_mb.y * (t1.y + 2.0 * t2.y) - g_mb.z * (t1.z + 2.0 * t2.z);
  g_e += g_a2 * mk.ka2 + g_b1 * mk.kb1 + g_b2 * mk.kb2 + g_b3 * mk.kb3;
  g_p.y += g_f.y * b1 + (g_ma.z + g_mb.z) * b2;
  g_p.z += g_f.z * b1 - (g_ma.y + g_mb.y) * b2;
  g_t1.x += a2 * (g_mb.x - g_ma.x);
  g_t2.x += a2 * (g_ma.x - g_mb.x);
  g_t1.y += g_f.z * b2 - b3 * (2.0 * g_ma.y + g_mb.y);
  g_t2.y += g_f.z * b2 - b3 * (g_ma.y + 2.0 * g_mb.y);
  g_t1.z += -g_f.y * b2 - b3 * (2.0 * g_ma.z + g_mb.z);
  g_t2.z += -g_f.y * b2 - b3 * (g_ma.z + 2.0 * g_mb.z);
  // Strain, stress and energy (stress x strain).
  const double g_stress = out_adj[kStress] + out_adj[kEnergy] * strain + g_f.x * mk.area;
  const double g_strain = out_adj[kStrain] + out_adj[kEnergy] * stress + g_stress * se_mod;
  const double g_mod = g_stress * strain;
  if (mk.axial_own)
    g_in[kStiffA] += g_mod;
  else
    g_e += g_mod;
  g_p.x += g_strain * mk.inv_L;
  // The harmonic mean e = 2 ea eb / (ea + eb).
  const double sum = ea + eb;
  g_in[kStiffA] += g_e * (2.0 * eb - e) / sum;
  g_in[kStiffB] += g_e * (2.0 * ea - e) / sum;
  // The deformation: p, th1 and th2 from r, rest, the frame and the relative rotation.
  double g_rest = 0, g_qw = 0;
  V3 g_r{0, 0, 0}, g_qv{0, 0, 0};
  if (small) {
    g_r = g_p;
    g_rest -= g_p.x;
    th2.reverse(g_t2, g_qw, g_qv.x, g_qv.y, g_qv.z);
  } else {
    g_rest -= g_p.x;
    if (len > 0) g_r.x += g_p.x * r.x / len, g_r.y += g_p.x * r.y / len, g_r.z += g_p.x * r.z / len;
    double gW = 0, gX = 0, gY = 0, gZ = 0;
    th2.reverse(g_t2, gW, gX, gY, gZ);
    g_fw += gW * qw + gX * qv.x + gY * qv.y + gZ * qv.z;
    g_fy += -gW * qv.y + gX * qv.z + gY * qw - gZ * qv.x;
    g_fz += -gW * qv.z - gX * qv.y + gY * qv.x + gZ * qw;
    g_qw += gW * fw + gY * fy + gZ * fz;
    g_qv.x += gX * fw + gY * fz - gZ * fy;
    g_qv.y += -gW * fy - gX * fz + gY * fw;
    g_qv.z += -gW * fz + gX * fy + gZ * fw;
    double g_unused = 0;
    th1.reverse(g_t1, g_fw, g_unused, g_fy, g_fz);
    if (first_order) {
      g_fy -= g_fw * fy, g_fz -= g_fw * fz;
      const double g_zx = 0.5 * g_fy, g_yx = -0.5 * g_fz;
      g_r.y += g_yx / r.x, g_r.z += g_zx / r.x;
      g_r.x -= (g_yx * yx + g_zx * zx) / r.x;
    } else {
      const double ch = std::cos(half);
      const double g_half = -sa * g_fw + (n.z * inv * g_fy - n.y * inv * g_fz) * ch;
      V3 g_n{0, inv * sa * g_fz * -1.0, inv * sa * g_fy};
      const double g_inv = sa * (n.z * g_fy - n.y * g_fz);
      const double g_theta = 0.5 * g_half;
      const double s = 1.0 - n.x * n.x;
      if (s > 0) g_n.x += g_theta * (-1.0 / std::sqrt(s));
      const double g_S = g_inv * (-0.5 * inv * inv * inv);
      g_n.z += 2.0 * n.z * g_S, g_n.y += 2.0 * n.y * g_S;
      g_r.x += g_n.x * li, g_r.y += g_n.y * li, g_r.z += g_n.z * li;
      const double g_l = -(g_n.x * r.x + g_n.y * r.y + g_n.z * r.z) * li * li;
      g_r.x += g_l * r.x / l, g_r.y += g_l * r.y / l, g_r.z += g_l * r.z / l;
    }
  }
  g_in[kCentreA + 3] += 0.5 * g_rest;
  g_in[kCentreB + 3] += 0.5 * g_rest;
  // The relative rotation conj(qa) qb.
  const double aw = qa[3], ax = qa[0], ay = qa[1], az = qa[2];
  const double bw = qb[3], bx = qb[0], by = qb[1], bz = qb[2];
  const V3 gq = from_axes(d, g_qv);
  double* g_qa = g_in + kQuatA;  // x, y, z, w
  double* g_qb = g_in + kQuatB;
  g_qa[3] += g_qw * bw + gq.x * bx + gq.y * by + gq.z * bz;
  g_qa[0] += g_qw * bx - gq.x * bw + gq.y * bz - gq.z * by;
  g_qa[1] += g_qw * by - gq.x * bz - gq.y * bw + gq.z * bx;
  g_qa[2] += g_qw * bz + gq.x * by - gq.y * bx - gq.z * bw;
  g_qb[3] += g_qw * aw - gq.x * ax - gq.y * ay - gq.z * az;
  g_qb[0] += g_qw * ax + gq.x * aw - gq.y * az + gq.z * ay;
  g_qb[1] += g_qw * ay + gq.x * az + gq.y * aw - gq.z * ax;
  g_qb[2] += g_qw * az - gq.x * ay + gq.y * ax + gq.z * aw;
  // The chord in a's axes: r = to_axes(R^T dl).
  const V3 gu = from_axes(d, g_r);
  const double guu[3] = {gu.x, gu.y, gu.z};
  for (int i = 0; i < 3; ++i) {
    double g_dl = 0;
    for (int j = 0; j < 3; ++j) gR[3 * j + i] += guu[j] * dl[i], g_dl += R[3 * j + i] * guu[j];
    g_in[kCentreB + i] += g_dl, g_in[kCentreA + i] -= g_dl;
  }
  // a's rotation matrix from its quaternion (rotation_matrix).
  const double tx = 2.0 * qa[0], ty = 2.0 * qa[1], tz = 2.0 * qa[2];
  const double g_tyy = -gR[0] - gR[8], g_tzz = -gR[0] - gR[4], g_txx = -gR[4] - gR[8];
  const double g_txy = gR[3] + gR[1], g_twz = gR[1] - gR[3];
  const double g_txz = gR[6] + gR[2], g_twy = gR[6] - gR[2];
  const double g_tyz = gR[7] + gR[5], g_twx = gR[5] - gR[7];
  const double g_tx = g_twx * qa[3] + g_txx * qa[0];
  const double g_ty = g_twy * qa[3] + g_txy * qa[0] + g_tyy * qa[1];
  const double g_tz = g_twz * qa[3] + g_txz * qa[0] + g_tyz * qa[1] + g_tzz * qa[2];
  g_qa[3] += g_twx * tx + g_twy * ty + g_twz * tz;
  g_qa[0] += g_txx * tx + g_txy * ty + g_txz * tz + 2.0 * g_tx;
  g_qa[1] += g_tyy * ty + g_tyz * tz + 2.0 * g_ty;
  g_qa[2] += g_tzz * tz + 2.0 * g_tz;
  for (int j = 0; j < kBondInputs; ++j) in_adj[j] += g_in[j];
  return true;
}

}  // namespace plastivox::grad
