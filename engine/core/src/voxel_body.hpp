// The voxel kernels (KernelSet::gather, update and actuate, kernels.hpp): the gather voxel by
// voxel on 4-double records, the update and actuation for any lane type (lanes.hpp).
//
// Each lane evaluates exactly the scalar operations, in the same order, whichever lane type
// runs it; branches of the scalar formulation become selects, and the rare rotations over
// ~0.5 degrees per step are evaluated lane by lane.
#pragma once

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstring>

#include "elementary.hpp"
#include "kernels.hpp"
#include "lanes.hpp"

namespace plastivox {
namespace {

// Four doubles as one vector (a record of bond_out: x, y, z, 0), whatever the instruction set
// (two SSE2 operations each on the baseline, one AVX operation where compiled for it).
typedef double Vec4 __attribute__((vector_size(32)));

// (By reference: returning a 32-byte vector by value has a different ABI with and without
// AVX, which GCC warns about.)
inline void load_vec4(const double* p, Vec4& v) {
  std::memcpy(&v, p, sizeof v);
}

// Voxel i: bond forces and moments in slot order, slow damping, weight, load. A bond's
// force or moment is one record, so the three components are summed together (each exactly
// as on its own). A slot without a bond reads the zero record past the last bond, so there
// is no branch (its only effect on the sum is that -0 + 0 is +0).
inline void gather_voxel(const VoxelKernelIo& io, int i, const ModelConstants& k, double coef) {
  Vec4 f = {0, 0, 0, 0}, mo = {0, 0, 0, 0};
  for (int slot = 0; slot < 6; ++slot) {
    const size_t b = 4 * static_cast<size_t>(io.slot_bond[slot][i]);
    // A bond towards +axis has this voxel as its a end: +F_a and M_a; else -F_a and M_b.
    const bool plus = slot & 1;
    Vec4 fa, m;
    load_vec4(io.bond_out[0] + b, fa);
    load_vec4(io.bond_out[plus ? 1 : 2] + b, m);
    f = plus ? f + fa : f - fa;
    mo = mo + m;
  }
  for (int c = 0; c < 3; ++c) {
    const double fc = f[c] - coef * io.lin_mom[3 * i + c];
    io.force[c][i] = (fc + k.weight[c]) + io.load[3 * i + c];
    io.moment[c][i] = mo[c];
  }
}

// Voxels [i, i + width): floor contact and Coulomb friction, semi-implicit Euler update of
// momenta and position, orientation advanced by omega dt. Folds the squared speed and the
// finiteness of the momenta of the free voxels into max_speed2 / bad.
// S: the type of dt, double here (engine/grad runs the same body with its recording type).
template <class T, class Mask, class S = double>
inline void update_lanes(const VoxelKernelIo& io, const VoxelStateOut& st, int i,
                         const ModelConstants& k, S dt, T& max_speed2, Mask& bad) {
  const T zero = splat(0.0, T{}), one = splat(1.0, T{});
  const Mask fixed = load_flag(io.fixed, i, T{});
  const T E = load(io.stiff, i, T{});
  const T se = load(io.sqrt_e, i, T{});
  T fx = load(io.force[0], i, T{}), fy = load(io.force[1], i, T{});
  T fz = load(io.force[2], i, T{});
  T p[3], x[3];
  load3(io.lin_mom, i, p);
  load3(io.pos, i, x);
  T px = p[0], py = p[1], pz = p[2];
  const T x0 = x[0], y0 = x[1], z0 = x[2];
  Mask held = and_not(fixed, fixed);  // all clear
  T floor_normal = zero;

  if (k.flat_floor) {
    // Penetration of the voxel's (actuated) half-size below the floor plane z = 0; the
    // voxel's tilt is ignored, as in Voxelyze.
    const T pen = 0.5 * load(io.size, i, T{}) - z0;
    const Mask contact = pen > 0.0;
    if (any(contact)) {
      const T normal = 2.0 * E * k.size * pen;
      const T vz = pz * k.inv_mass;
      const T c_col = k.c_col_unit * se;
      const T vx = px * k.inv_mass, vy = py * k.inv_mass;
      // At rest: stick unless the lateral load exceeds the static limit.
      const Mask at_rest = (vx == 0.0) & (vy == 0.0);
      const Mask sticks = root(fx * fx + fy * fy) < k.def.mu_static * normal;
      // Sliding: kinetic friction against the velocity, or a stop if it would reverse the
      // motion within this step.
      const T speed = root(vx * vx + vy * vy);
      const T fric = k.def.mu_kinetic * normal;
      const Mask moving = and_not(contact, at_rest);
      const Mask slides = moving & (fric * dt < k.mass * speed);
      const Mask stops = and_not(moving, slides);
      const T divisor = pick(slides, speed, one);  // no 0/0 in lanes that do not slide
      fx = pick(slides, fx - fric * vx / divisor, fx);
      fy = pick(slides, fy - fric * vy / divisor, fy);
      px = pick(stops, zero, px);
      py = pick(stops, zero, py);
      held = (contact & at_rest & sticks) | stops;
      fz = pick(contact, fz + (normal - c_col * vz), fz);
      floor_normal = pick(contact, normal, zero);
    }
  }
  if (io.floor_normal) store(io.floor_normal, i, floor_normal);
  fx = pick(held, zero, fx);
  fy = pick(held, zero, fy);

  px = px + fx * dt, py = py + fy * dt, pz = pz + fz * dt;
  const S step = dt * k.inv_mass;
  const T x1 = x0 + px * step, y1 = y0 + py * step, z1 = z0 + pz * step;

  // Rotation: moment, then slow rotational damping as a per-step decay of the angular
  // momentum, then the orientation advanced by the rotation vector omega * dt.
  T h[3];
  load3(io.ang_mom, i, h);
  T hx = h[0], hy = h[1], hz = h[2];
  hx = hx + load(io.moment[0], i, T{}) * dt;
  hy = hy + load(io.moment[1], i, T{}) * dt;
  hz = hz + load(io.moment[2], i, T{}) * dt;
  const T c_rot = k.c_rot_unit * se;
  const T decay = 1.0 - k.rot_damp * c_rot * k.inv_inertia * dt;
  hx = hx * decay, hy = hy * decay, hz = hz * decay;

  T q[4];
  load4(io.quat, i, q);
  const T bx = q[0], by = q[1], bz = q[2], bw = q[3];
  T qx, qy, qz, qw;
  if (k.def.bond_model == BondModel::kVoxelyze09) {
    // Voxelyze 0.9 (CVXS_Voxel::EulerStep, CQuat::NormalizeFast): q += dt (0, omega/2) q,
    // then q *= 1/|q|, and a q whose w is then 1 becomes exactly no turn. So a voxel turned
    // less than about 3e-8 rad from the lattice stays unturned while its angular momentum
    // grows; mixed-stiffness bodies feel it from their first steps.
    const T ax = 0.5 * (hx * k.inv_inertia), ay = 0.5 * (hy * k.inv_inertia);
    const T az = 0.5 * (hz * k.inv_inertia);
    qw = bw + (((zero - ax * bx) - ay * by) - az * bz) * dt;
    qx = bx + ((ax * bw + ay * bz) - az * by) * dt;
    qy = by + ((ay * bw - ax * bz) + az * bx) * dt;
    qz = bz + ((ax * by - ay * bx) + az * bw) * dt;
    const T len = root(((qx * qx + qy * qy) + qz * qz) + qw * qw);
    const Mask some = len > 0.0;
    const T inv = one / pick(some, len, one);
    qw = pick(some, qw * inv, qw), qx = pick(some, qx * inv, qx);
    qy = pick(some, qy * inv, qy), qz = pick(some, qz * inv, qz);
    const Mask none = mask_not(qw < 1.0);
    qx = pick(none, zero, qx), qy = pick(none, zero, qy), qz = pick(none, zero, qz);
    qw = pick(none, one, qw);
  } else {
    // Rotation by v = omega dt. Per step a voxel turns by far less than 1e-2 rad, so the
    // common case uses the series cos(h) = 1 - h^2/2 + h^4/24 - h^6/720 + h^8/40320,
    // sin(h)/h = 1 - h^2/6 + h^4/120 - h^6/5040 + h^8/362880 (truncation error below 1e-20
    // for h < 5e-3); larger turns take sin_cycles lane by lane.
    const S turn = dt * k.inv_inertia;
    const T vx = hx * turn, vy = hy * turn, vz = hz * turn;
    const T a2 = vx * vx + vy * vy + vz * vz;
    const T h2 = 0.25 * a2;  // (angle / 2)^2
    T rw = 1.0 - h2 * (0.5 - h2 * (1.0 / 24 - h2 * (1.0 / 720 - h2 * (1.0 / 40320))));
    const T sinc =
        1.0 - h2 * (1.0 / 6 - h2 * (1.0 / 120 - h2 * (1.0 / 5040 - h2 * (1.0 / 362880))));
    const T half_sinc = 0.5 * sinc;
    T rx = half_sinc * vx, ry = half_sinc * vy, rz = half_sinc * vz;
    for_each_lane(mask_not(h2 < 2.5e-5), [&](int j) {
      // (auto: a double here, the lane's own type in engine/grad's recording instantiation.)
      const auto angle = root(lane_get(a2, j));
      const auto ax = lane_get(vx, j) / angle, ay = lane_get(vy, j) / angle;
      const auto az = lane_get(vz, j) / angle;
      // sin and cos of the half angle by the engine's own sin(2 pi u) (elementary.hpp), so no
      // result depends on the C library.
      const auto u = (0.5 * angle) * (1.0 / (2.0 * M_PI));
      const auto sh = sin_cycles(u);
      lane_set(rw, j, sin_cycles(u + 0.25));
      lane_set(rx, j, ax * sh), lane_set(ry, j, ay * sh), lane_set(rz, j, az * sh);
    });
    // q <- r q (Eigen's SSE2 quaternion product, term for term), then normalised.
    qx = (rw * bx + ry * bz) - (rz * by - rx * bw);
    qy = (rw * by + ry * bw) + (rz * bx - rx * bz);
    qz = (rw * bz - ry * bx) + (rz * bw + rx * by);
    qw = (rw * bw - ry * by) - (rz * bz + rx * bx);
    const T n2 = (qx * qx + qz * qz) + (qy * qy + qw * qw);
    const Mask positive = n2 > 0.0;
    const T norm = root(pick(positive, n2, one));
    qx = pick(positive, qx / norm, qx), qy = pick(positive, qy / norm, qy);
    qz = pick(positive, qz / norm, qz), qw = pick(positive, qw / norm, qw);
  }

  // Clamped voxels are held in place; their reaction is not tracked.
  const T out[13] = {pick(fixed, x0, x1),   pick(fixed, y0, y1),   pick(fixed, z0, z1),
                     pick(fixed, zero, px), pick(fixed, zero, py), pick(fixed, zero, pz),
                     pick(fixed, zero, hx), pick(fixed, zero, hy), pick(fixed, zero, hz),
                     pick(fixed, bx, qx),   pick(fixed, by, qy),   pick(fixed, bz, qz),
                     pick(fixed, bw, qw)};
  store3(st.pos, i, out);
  store3(st.lin_mom, i, out + 3);
  store3(st.ang_mom, i, out + 6);
  store4(st.quat, i, out + 9);
  const Mask was_held = load_flag(io.static_friction, i, T{});
  store_flag(st.static_friction, i, and_not(held, fixed) | (fixed & was_held));

  const T v2 = (px * px + py * py + pz * pz) * k.inv_mass * k.inv_mass;
  const T w2 = hx * hx + hy * hy + hz * hz;
  max_speed2 = pick(and_not(v2 > max_speed2, fixed), v2, max_speed2);
  bad = bad | and_not(mask_not(v2 <= DBL_MAX) | mask_not(w2 <= DBL_MAX), fixed);
}

// Voxels [i, i + width): the sine controller's signal, sin(2 pi (cycles + phase_i)).
template <class T, class S = double>
inline void sine_lanes(const double* phase, double* signal, int i, S cycles) {
  store(signal, i, sin_cycles(cycles + load(phase, i, T{})));
}

template <class T>
inline void run_sine(const double* phase, double* signal, int n, double cycles) {
  over_lanes<T>(n, [&](auto lane, int i) { sine_lanes<decltype(lane)>(phase, signal, i, cycles); });
}

// Voxels [i, i + width): the actuated size from each voxel's signal (docs/method.md §4).
template <class T>
inline void actuate_lanes(const double* stiff, const double* signal, const double* gain,
                          double* size, int i, const ModelConstants& k) {
  // Stiff voxels barely move; xi follows the *current* E, so development changes actuation.
  // (A gain of 1 and xi_base 0 leave every bit as the plain formula gives it.)
  const T xi = (k.xi_e_max - load(stiff, i, T{})) * k.xi_inv_range + k.xi_base;
  const T u = load(signal, i, T{});
  const T wave = pick(u > k.act_wave_max, splat(k.act_wave_max, T{}), u);
  // The size factor never drops below min_factor (Voxelyze's MIN_TEMP_FACTOR).
  const T factor = 1.0 + k.act_amplitude_xi * xi * load(gain, i, T{}) * wave;
  const double least = k.def.act_min_factor;
  store(size, i, k.size * pick(factor < least, splat(least, T{}), factor));
}

template <class T>
inline void run_actuate(const double* stiff, const double* signal, const double* gain, double* size,
                        int n, const ModelConstants& k) {
  over_lanes<T>(
      n, [&](auto lane, int i) { actuate_lanes<decltype(lane)>(stiff, signal, gain, size, i, k); });
}

// Slow (global) damping: a small fraction of the critical damping of the voxel's own axial
// spring, against absolute velocity; its coefficient (and sqrt(E), kept for the update) for
// lanes of voxels at a time, as square roots and divisions are slow one by one.
template <class T>
inline T slow_damping_lanes(const VoxelKernelIo& io, int i, const ModelConstants& k) {
  const T se = root(load(io.stiff, i, T{}));
  store(io.sqrt_e, i, se);
  const T c_lin = k.c_lin_unit * se;
  return (k.def.global_damping * c_lin) / k.mass;
}

template <class T>
inline void run_gather(const VoxelKernelIo& io, int n, const ModelConstants& k) {
  over_lanes<T>(n, [&](auto lane, int i) {
    using L = decltype(lane);
    double coef[kLanes<L>];
    store(coef, 0, slow_damping_lanes<L>(io, i, k));
    for (int j = 0; j < kLanes<L>; ++j) gather_voxel(io, i + j, k, coef[j]);
  });
}

template <class T>
inline VoxelUpdateSummary run_update(const VoxelKernelIo& io, const VoxelStateOut& st, int n,
                                     const ModelConstants& k, double dt) {
  using Mask = decltype(T{} < T{});
  T max_speed2 = splat(0.0, T{});
  Mask bad = max_speed2 < max_speed2;  // all clear
  double max_speed2_tail = 0;
  bool bad_tail = false;
  over_lanes<T>(n, [&](auto lane, int i) {
    if constexpr (kLanes<decltype(lane)> == 1)
      update_lanes<double, bool>(io, st, i, k, dt, max_speed2_tail, bad_tail);
    else
      update_lanes<T, Mask>(io, st, i, k, dt, max_speed2, bad);
  });
  VoxelUpdateSummary summary;
  summary.max_speed2 = max_speed2_tail;
  for (int j = 0; j < kLanes<T>; ++j)
    summary.max_speed2 = std::max(summary.max_speed2, lane_get(max_speed2, j));
  summary.non_finite = bad_tail || any(bad);
  return summary;
}

}  // namespace
}  // namespace plastivox
