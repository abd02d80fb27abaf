// See bond_kernel.hpp. The formulas are those of bond_forces.cpp (exact bond model,
// chord-aligned frame), written once as a template over the lane type: `double` for the
// scalar tail and, where the build enables AVX2, a 4-wide GCC vector of doubles. Both
// evaluate the same IEEE operations in the same order (no FMA: -ffp-contract=off), so a
// bond's result does not depend on which lane type computed it.
//
// Bit-for-bit agreement with the scalar path (bond_forces.cpp) where the two overlap:
//  - the rotation matrix of voxel a is Eigen's toRotationMatrix() formula, its columns
//    cyclically permuted so the bond's axis comes first (a per-lane select);
//  - rotations beyond the series' range (over ~11 degrees) take std::atan lane by lane,
//    exactly as the scalar path does, and such a bond's forces go back to the world frame
//    in the scalar path's order of summation (unpermuted columns), so a bond gets the same
//    bits whichever path computes it;
//  - only degenerate chords and relative rotations near half a turn are left to the
//    scalar path (listed in io.redo).
#include "bond_kernel.hpp"

#include <cmath>

#if defined(__AVX2__)
#include <immintrin.h>
#endif

namespace plastivox {
namespace {

// ---- Lane operations: scalar -------------------------------------------------------------

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
inline bool any(bool c) {
  return c;
}
inline bool and_not(bool a, bool b) {
  return a && !b;
}
// atan(t)/t of t^2, as bond_forces.cpp's atan_over_t.
inline double atan_over_t(double t2, bool /*skip*/) {
  if (t2 < 1e-2) return atan_series(t2);
  const double t = std::sqrt(t2);
  return std::atan(t) / t;
}
inline void append_redo(bool redo, int i, const BondKernelIo& io, int& count) {
  if (redo) io.redo[count++] = i;
}

// Column/component selection by the bond's lattice axis d: v0 if d = 0, v1 if 1, v2 if 2.
struct Axis1 {
  int d;
  double operator()(double v0, double v1, double v2) const {
    return d == 0 ? v0 : d == 1 ? v1 : v2;
  }
};

// Inputs of one bond (or of a group of lanes): what the kernel reads from the voxels.
template <class T>
struct BondIn {
  T dx, dy, dz;      // centre of b minus centre of a, m, world frame
  T ax, ay, az, aw;  // orientation of a
  T bx, by, bz, bw;  // orientation of b
  T size_a, size_b;  // actuated sizes, m
  T ea, eb;          // moduli, Pa
  T valid;           // 1 if the previous deformation is recorded, else 0
};

inline BondIn<double> gather(const BondKernelIo& io, int b, double) {
  const int ia = io.bond_a[b], ib = io.bond_b[b];
  const double* pa = io.pos + 3 * ia;
  const double* pb = io.pos + 3 * ib;
  const double* qa = io.quat + 4 * ia;
  const double* qb = io.quat + 4 * ib;
  BondIn<double> in;
  in.dx = pb[0] - pa[0], in.dy = pb[1] - pa[1], in.dz = pb[2] - pa[2];
  in.ax = qa[0], in.ay = qa[1], in.az = qa[2], in.aw = qa[3];
  in.bx = qb[0], in.by = qb[1], in.bz = qb[2], in.bw = qb[3];
  in.size_a = io.size[ia], in.size_b = io.size[ib];
  in.ea = io.stiff[ia], in.eb = io.stiff[ib];
  in.valid = io.prev_valid[b] ? 1.0 : 0.0;
  return in;
}

inline Axis1 axis_select(const BondKernelIo& io, int b, double) {
  return Axis1{io.axis[b]};
}

// ---- Lane operations: four bonds (AVX2) --------------------------------------------------

#if defined(__AVX2__)
typedef double v4d __attribute__((vector_size(32)));
typedef long v4l __attribute__((vector_size(32)));  // what comparing two v4d yields
inline v4d splat(double v, v4d) {
  return v4d{v, v, v, v};
}
inline v4d load(const double* p, int i, v4d) {
  return (v4d)_mm256_loadu_pd(p + i);
}
inline void store(double* p, int i, v4d v) {
  _mm256_storeu_pd(p + i, (__m256d)v);
}
inline v4d root(v4d v) {
  return (v4d)_mm256_sqrt_pd((__m256d)v);
}
inline v4d pick(v4l c, v4d a, v4d b) {
  return c ? a : b;
}
inline int lane_bits(v4l c) {
  return _mm256_movemask_pd((__m256d)c);
}
inline bool any(v4l c) {
  return lane_bits(c) != 0;
}
inline v4l and_not(v4l a, v4l b) {
  return a & ~b;
}
// The series in every lane; lanes past its range (and not skipped) take std::atan.
inline v4d atan_over_t(v4d t2, v4l skip) {
  v4d r = atan_series(t2);
  const int big = lane_bits(and_not(t2 >= 1e-2, skip));
  if (big != 0) {
    for (int j = 0; j < 4; ++j) {
      if (!(big & (1 << j))) continue;
      const double t = std::sqrt(t2[j]);
      r[j] = std::atan(t) / t;
    }
  }
  return r;
}
inline void append_redo(v4l redo, int i, const BondKernelIo& io, int& count) {
  const int bits = lane_bits(redo);
  if (bits == 0) return;
  for (int j = 0; j < 4; ++j)
    if (bits & (1 << j)) io.redo[count++] = i + j;
}

struct Axis4 {
  v4l is1, is2;
  v4d operator()(v4d v0, v4d v1, v4d v2) const { return is2 ? v2 : (is1 ? v1 : v0); }
};

// Four voxels' quaternions (x, y, z, w in memory), transposed into one vector per component.
inline void load_quats(const double* q, const int* idx, v4d& x, v4d& y, v4d& z, v4d& w) {
  const __m256d q0 = _mm256_loadu_pd(q + 4 * idx[0]), q1 = _mm256_loadu_pd(q + 4 * idx[1]);
  const __m256d q2 = _mm256_loadu_pd(q + 4 * idx[2]), q3 = _mm256_loadu_pd(q + 4 * idx[3]);
  const __m256d t0 = _mm256_unpacklo_pd(q0, q1);  // x0 x1 z0 z1
  const __m256d t1 = _mm256_unpackhi_pd(q0, q1);  // y0 y1 w0 w1
  const __m256d t2 = _mm256_unpacklo_pd(q2, q3);  // x2 x3 z2 z3
  const __m256d t3 = _mm256_unpackhi_pd(q2, q3);  // y2 y3 w2 w3
  x = (v4d)_mm256_permute2f128_pd(t0, t2, 0x20);
  z = (v4d)_mm256_permute2f128_pd(t0, t2, 0x31);
  y = (v4d)_mm256_permute2f128_pd(t1, t3, 0x20);
  w = (v4d)_mm256_permute2f128_pd(t1, t3, 0x31);
}

inline v4d lanes(const double* p, const int* idx, int stride, int offset) {
  return v4d{p[stride * idx[0] + offset], p[stride * idx[1] + offset], p[stride * idx[2] + offset],
             p[stride * idx[3] + offset]};
}

inline BondIn<v4d> gather(const BondKernelIo& io, int b, v4d) {
  const int* ia = io.bond_a + b;
  const int* ib = io.bond_b + b;
  BondIn<v4d> in;
  in.dx = lanes(io.pos, ib, 3, 0) - lanes(io.pos, ia, 3, 0);
  in.dy = lanes(io.pos, ib, 3, 1) - lanes(io.pos, ia, 3, 1);
  in.dz = lanes(io.pos, ib, 3, 2) - lanes(io.pos, ia, 3, 2);
  load_quats(io.quat, ia, in.ax, in.ay, in.az, in.aw);
  load_quats(io.quat, ib, in.bx, in.by, in.bz, in.bw);
  in.size_a = lanes(io.size, ia, 1, 0), in.size_b = lanes(io.size, ib, 1, 0);
  in.ea = lanes(io.stiff, ia, 1, 0), in.eb = lanes(io.stiff, ib, 1, 0);
  const uint8_t* v = io.prev_valid + b;
  in.valid = v4d{v[0] ? 1.0 : 0.0, v[1] ? 1.0 : 0.0, v[2] ? 1.0 : 0.0, v[3] ? 1.0 : 0.0};
  return in;
}

inline Axis4 axis_select(const BondKernelIo& io, int b, v4d) {
  const uint8_t* a = io.axis + b;
  const v4l d{a[0], a[1], a[2], a[3]};
  return Axis4{d == 1, d == 2};
}
#endif

// ---- The bond, for any lane type ---------------------------------------------------------

template <class T>
inline void bond_lanes(const BondKernelIo& io, int i, const BondConstants& k, int& redo_count) {
  const T one = splat(1.0, T{}), zero = splat(0.0, T{});
  const BondIn<T> in = gather(io, i, T{});
  const auto sel = axis_select(io, i, T{});

  // Rotation matrix of a (column-major, Eigen's toRotationMatrix), and its columns
  // permuted so the bond's axis comes first: c[0..2] = column d, c[3..5] = column d + 1, ...
  T R[9];
  {
    const T tx = 2.0 * in.ax, ty = 2.0 * in.ay, tz = 2.0 * in.az;
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
  // Chord a->b in a's permuted body frame.
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

  // Chord-aligned frame f = (fw, 0, fy, fz) taking r onto +x.
  const T len = root(x * x + y * y + z * z);
  const T h0 = len + x;
  const auto degenerate = h0 <= 1e-6 * len;
  const T h = pick(degenerate, one, h0);
  const T ln = pick(degenerate, one, len);
  const T inv_n = 1.0 / root(2.0 * ln * h);
  const T fw = h * inv_n, fy = z * inv_n, fz = -y * inv_n;
  const T t1sq = (y * y + z * z) / (h * h);
  const T k1 = 2.0 * atan_over_t(t1sq, degenerate) / h;
  const T t1x = zero, t1y = z * k1, t1z = -y * k1;
  // th2: rotation vector of f * q2, shorter arc.
  T w2 = fw * a - fy * by - fz * bz;
  T x2 = fw * bx + fy * bz - fz * by;
  T y2 = fw * by + a * fy + fz * bx;
  T z2 = fw * bz + a * fz - fy * bx;
  const T sgn = pick(w2 < 0.0, splat(-1.0, T{}), one);
  w2 = w2 * sgn, x2 = x2 * sgn, y2 = y2 * sgn, z2 = z2 * sgn;
  const auto redo = degenerate | (w2 <= 1e-3);
  const T ww = pick(w2 > 1e-3, w2, one);
  const T t2sq = (x2 * x2 + y2 * y2 + z2 * z2) / (ww * ww);
  const T k2 = 2.0 * atan_over_t(t2sq, redo) / ww;
  const T t2x = x2 * k2, t2y = y2 * k2, t2z = z2 * k2;
  append_redo(redo, i, io, redo_count);
  // Bonds past the series' range: world-frame results in the scalar path's order.
  const auto large = and_not((t1sq >= 1e-2) | (t2sq >= 1e-2), redo);

  // Axial strain over the nominal length; harmonic-mean modulus.
  const T rest = 0.5 * (in.size_a + in.size_b);
  const T px = len - rest;
  const T strain = px * k.inv_L;
  const T ea = in.ea, eb = in.eb;
  const T e = 2.0 * ea * eb / (ea + eb);
  const T stress = (k.axial_own ? ea : e) * strain;
  store(io.strain, i, strain);
  store(io.stress, i, stress);

  const T a2 = e * k.ka2, b3 = e * k.kb3;
  const T b2c = 3.0 * b3 / (px + rest);
  T fx = stress * k.area, fyv = -b2c * (t1z + t2z), fzv = b2c * (t1y + t2y);
  T max = a2 * (t2x - t1x), may = -b3 * (2.0 * t1y + t2y), maz = -b3 * (2.0 * t1z + t2z);
  T mbx = a2 * (t1x - t2x), mby = -b3 * (t1y + 2.0 * t2y), mbz = -b3 * (t1z + 2.0 * t2z);

  // Damping on half the change of the deformation since the previous step (off until a
  // previous deformation exists: valid = 0).
  double* const* P = io.prev;
  T old[9];
  for (int j = 0; j < 9; ++j) old[j] = load(P[j], i, T{});
  const T dpx = 0.5 * (px - old[0]);
  const T dpy = 0.5 * (zero - old[1]), dpz = 0.5 * (zero - old[2]);
  const T d1x = 0.5 * (t1x - old[3]), d1y = 0.5 * (t1y - old[4]);
  const T d1z = 0.5 * (t1z - old[5]);
  const T d2x = 0.5 * (t2x - old[6]), d2y = 0.5 * (t2y - old[7]);
  const T d2z = 0.5 * (t2z - old[8]);
  const T se = root(e) * k.damp * in.valid;
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
  const T vx[3] = {fx, max, mbx}, vy[3] = {fyv, may, mby}, vz[3] = {fzv, maz, mbz};
  const bool any_large = any(large);
  for (int v = 0; v < 3; ++v) {
    const T ux = r00 * vx[v] + r01 * vy[v] + r02 * vz[v];
    const T uy = r10 * vx[v] + r11 * vy[v] + r12 * vz[v];
    const T uz = r20 * vx[v] + r21 * vy[v] + r22 * vz[v];
    T o[3];
    for (int c = 0; c < 3; ++c) o[c] = m[c] * ux + m[3 + c] * uy + m[6 + c] * uz;
    if (any_large) {
      // Undo the permutation first, then the unpermuted columns (bond_forces.cpp to_world).
      const T ox = sel(ux, uz, uy), oy = sel(uy, ux, uz), oz = sel(uz, uy, ux);
      for (int c = 0; c < 3; ++c)
        o[c] = pick(large, R[c] * ox + R[3 + c] * oy + R[6 + c] * oz, o[c]);
    }
    for (int c = 0; c < 3; ++c) store(io.out[3 * v + c], i, o[c]);
  }
}

}  // namespace

int bond_kernel_exact(const BondKernelIo& io, int n, const BondConstants& k) {
  int redo_count = 0;
  int i = 0;
#if defined(__AVX2__)
  for (; i + 4 <= n; i += 4) bond_lanes<v4d>(io, i, k, redo_count);
#endif
  for (; i < n; ++i) bond_lanes<double>(io, i, k, redo_count);
  return redo_count;
}

}  // namespace plastivox
