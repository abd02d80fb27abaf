// See bond_kernel.hpp. The formulas are those of bond_forces.cpp (exact bond model,
// chord-aligned frame), written once as a template over the lane type: `double` for the
// scalar tail and, where the build enables AVX2, a 4-wide GCC vector of doubles. Both
// evaluate the same IEEE operations in the same order (no FMA: -ffp-contract=off), so a
// bond's result does not depend on which lane type computed it. Lanes whose rotations leave
// the range of the series for atan(t)/t, or whose chord is degenerate, are flagged and
// recomputed by the scalar path of bond_forces.cpp.
#include "bond_kernel.hpp"

#include <cmath>
#include <cstring>

#if defined(__AVX2__)
#include <immintrin.h>
#endif

namespace plastivox {

void BondBatch::resize(int n) {
  for (auto* v : {&rx, &ry, &rz, &qw, &qx, &qy, &qz, &rest, &ea, &eb, &valid, &redo})
    v->assign(n, 0.0);
  for (int i = 0; i < 9; ++i) c[i].assign(n, 0.0);
}

namespace {

// Scalar lane operations.
inline double splat(double v, double) {
  return v;
}
inline double load(const double* p, int i, double) {
  return p[i];
}
inline void store(double* p, int i, double v) {
  p[i] = v;
}
inline double root(double v) {
  return std::sqrt(v);
}
inline double pick(bool c, double a, double b) {
  return c ? a : b;
}

#if defined(__AVX2__)
typedef double v4d __attribute__((vector_size(32)));
typedef long v4l __attribute__((vector_size(32)));  // what comparing two v4d yields
inline v4d splat(double v, v4d) {
  return v4d{v, v, v, v};
}
inline v4d load(const double* p, int i, v4d) {
  v4d v;
  std::memcpy(&v, p + i, sizeof v);
  return v;
}
inline void store(double* p, int i, v4d v) {
  std::memcpy(p + i, &v, sizeof v);
}
inline v4d root(v4d v) {
  return (v4d)_mm256_sqrt_pd((__m256d)v);
}
inline v4d pick(v4l c, v4d a, v4d b) {
  return c ? a : b;
}
#endif

template <class T>
inline void bond_lanes(BondBatch& B, int i, const BondConstants& k) {
  const T one = splat(1.0, T{}), zero = splat(0.0, T{});
  // Chord-aligned frame f = (fw, 0, fy, fz) taking r onto +x.
  const T x = load(B.rx.data(), i, T{}), y = load(B.ry.data(), i, T{});
  const T z = load(B.rz.data(), i, T{});
  const T len = root(x * x + y * y + z * z);
  const T h0 = len + x;
  const auto degenerate = h0 <= 1e-6 * len;
  const T h = pick(degenerate, one, h0);
  const T ln = pick(degenerate, one, len);
  const T inv_n = 1.0 / root(2.0 * ln * h);
  const T fw = h * inv_n, fy = z * inv_n, fz = -y * inv_n;
  const T t1sq = (y * y + z * z) / (h * h);
  const T k1 = 2.0 * atan_series(t1sq) / h;
  const T t1x = zero, t1y = z * k1, t1z = -y * k1;
  // th2: rotation vector of f * q2, shorter arc.
  const T a = load(B.qw.data(), i, T{}), bx = load(B.qx.data(), i, T{});
  const T by = load(B.qy.data(), i, T{}), bz = load(B.qz.data(), i, T{});
  T w2 = fw * a - fy * by - fz * bz;
  T x2 = fw * bx + fy * bz - fz * by;
  T y2 = fw * by + a * fy + fz * bx;
  T z2 = fw * bz + a * fz - fy * bx;
  const T sgn = pick(w2 < 0.0, splat(-1.0, T{}), one);
  w2 = w2 * sgn, x2 = x2 * sgn, y2 = y2 * sgn, z2 = z2 * sgn;
  const T ww = pick(w2 > 1e-3, w2, one);
  const T t2sq = (x2 * x2 + y2 * y2 + z2 * z2) / (ww * ww);
  const T k2 = 2.0 * atan_series(t2sq) / ww;
  const T t2x = x2 * k2, t2y = y2 * k2, t2z = z2 * k2;
  const auto redo = degenerate | (t1sq >= 1e-2) | (t2sq >= 1e-2) | (w2 <= 1e-3);
  store(B.redo.data(), i, pick(redo, one, zero));

  // Axial strain over the nominal length; harmonic-mean modulus.
  const T rest = load(B.rest.data(), i, T{});
  const T px = len - rest;
  const T strain = px * k.inv_L;
  const T ea = load(B.ea.data(), i, T{}), eb = load(B.eb.data(), i, T{});
  const T e = 2.0 * ea * eb / (ea + eb);
  const T stress = (k.axial_own ? ea : e) * strain;
  store(B.strain, i, strain);
  store(B.stress, i, stress);

  const T a2 = e * k.ka2, b3 = e * k.kb3;
  const T b2c = 3.0 * b3 / (px + rest);
  T fx = stress * k.area, fyv = -b2c * (t1z + t2z), fzv = b2c * (t1y + t2y);
  T max = a2 * (t2x - t1x), may = -b3 * (2.0 * t1y + t2y), maz = -b3 * (2.0 * t1z + t2z);
  T mbx = a2 * (t1x - t2x), mby = -b3 * (t1y + 2.0 * t2y), mbz = -b3 * (t1z + 2.0 * t2z);

  // Damping on half the change of the deformation since the previous step (off until a
  // previous deformation exists: valid = 0).
  double* const* P = B.prev;
  T old[9];
  for (int j = 0; j < 9; ++j) old[j] = load(P[j], i, T{});
  const T dpx = 0.5 * (px - old[0]);
  const T dpy = 0.5 * (zero - old[1]), dpz = 0.5 * (zero - old[2]);
  const T d1x = 0.5 * (t1x - old[3]), d1y = 0.5 * (t1y - old[4]);
  const T d1z = 0.5 * (t1z - old[5]);
  const T d2x = 0.5 * (t2x - old[6]), d2y = 0.5 * (t2y - old[7]);
  const T d2z = 0.5 * (t2z - old[8]);
  const T se = root(e) * k.damp * load(B.valid.data(), i, T{});
  const T c_a1 = se * k.dk_a1, c_b1 = c_a1, c_b2 = se * k.dk_b2;
  const T c_a2 = 0.5 * se * k.dk_a2, c_b3 = 0.5 * se * k.dk_b3;
  const T c_b2h = 0.5 * c_b2;
  fx = fx + c_a1 * dpx;
  fyv = fyv + (c_b1 * dpy - c_b2 * (d1z + d2z));
  fzv = fzv + (c_b1 * dpz + c_b2 * (d1y + d2y));
  max = max + c_a2 * (d2x - d1x);
  may = may + (-c_b2h * dpz - c_b3 * (2.0 * d1y + d2y));
  maz = maz + (c_b2h * dpy - c_b3 * (2.0 * d1z + d2z));
  mbx = mbx + c_a2 * (d1x - d2x);
  mby = mby + (-c_b2h * dpz - c_b3 * (d1y + 2.0 * d2y));
  mbz = mbz + (c_b2h * dpy - c_b3 * (d1z + 2.0 * d2z));

  // Flagged lanes keep their previous deformation: the scalar path redoes them from it.
  const T now[9] = {px, zero, zero, t1x, t1y, t1z, t2x, t2y, t2z};
  for (int j = 0; j < 9; ++j) store(P[j], i, pick(redo, old[j], now[j]));

  // World frame: u = f^T v (f has no x part), then the permuted orientation of a.
  const T r00 = 1.0 - 2.0 * (fy * fy + fz * fz), r01 = 2.0 * fw * fz, r02 = -2.0 * fw * fy;
  const T r10 = -2.0 * fw * fz, r11 = 1.0 - 2.0 * fz * fz, r12 = 2.0 * fy * fz;
  const T r20 = 2.0 * fw * fy, r21 = 2.0 * fy * fz, r22 = 1.0 - 2.0 * fy * fy;
  T m[9];
  for (int j = 0; j < 9; ++j) m[j] = load(B.c[j].data(), i, T{});  // column-major
  const T vx[3] = {fx, max, mbx}, vy[3] = {fyv, may, mby}, vz[3] = {fzv, maz, mbz};
  for (int v = 0; v < 3; ++v) {
    const T ux = r00 * vx[v] + r01 * vy[v] + r02 * vz[v];
    const T uy = r10 * vx[v] + r11 * vy[v] + r12 * vz[v];
    const T uz = r20 * vx[v] + r21 * vy[v] + r22 * vz[v];
    store(B.out[3 * v], i, m[0] * ux + m[3] * uy + m[6] * uz);
    store(B.out[3 * v + 1], i, m[1] * ux + m[4] * uy + m[7] * uz);
    store(B.out[3 * v + 2], i, m[2] * ux + m[5] * uy + m[8] * uz);
  }
}

}  // namespace

void bond_kernel_exact(BondBatch& B, int n, const BondConstants& k) {
  int i = 0;
#if defined(__AVX2__)
  for (; i + 4 <= n; i += 4) bond_lanes<v4d>(B, i, k);
#endif
  for (; i < n; ++i) bond_lanes<double>(B, i, k);
}

}  // namespace plastivox
