// The voxel update's hand-written reverse (voxel_adjoint.hpp) as a template over the lane type,
// as bond_reverse_body.hpp is the bond stage's: compiled at each SIMD level, element-wise IEEE
// arithmetic in one order, so a voxel's adjoints are the same bits at every level. The floor's
// branches (contact, sliding, stopping, held) are per-lane selections of the branch the life
// took; the turn is the exact model's (its half-angle series) or Voxelyze 0.9's (a first-order
// step, normalised), per model. Lanes off the hand path (a clamped voxel, an exact model's turn
// past the half-angle series' range) are flagged in io.off, their adjoints to be ignored: the
// caller takes them by voxel_reverse_tape.
//
// Internal linkage (unnamed namespace), as every lane template: see lanes.hpp.
#pragma once

#include <cstddef>
#include <utility>

#include "lanes.hpp"
#include "voxel_adjoint.hpp"

namespace plastivox {
namespace {

// Component c of records of 4 of voxels [i, i + kLanes<T>) (a bond stage's kept centres and
// sizes or orientations), element by element.
template <class T, size_t... J>
inline T record_lanes(const double* p, int i, std::index_sequence<J...>) {
  return T{p[4 * (size_t(i) + J)]...};
}

// Voxels [i, i + kLanes<T>) of a kept update: from their outputs' adjoints, their inputs'.
template <class T>
inline void voxel_reverse_lanes(const grad::VoxelReverseIo& io, int i, const ModelConstants& k) {
  using grad::kVAngMom, grad::kVDt, grad::kVE, grad::kVForce, grad::kVLinMom, grad::kVMoment,
      grad::kVOutAngMom, grad::kVOutLinMom, grad::kVOutNormal, grad::kVOutPos, grad::kVOutQuat,
      grad::kVPos, grad::kVQuat, grad::kVSize, grad::kVSqrtE;
  const size_t n = io.n;
  const T zero = splat(0.0, T{});
  const auto in = [&](int slot) { return load(io.values + size_t(slot) * n, i, T{}); };
  const auto out = [&](int o) { return load(io.out_adj + size_t(o) * n, i, T{}); };
  const auto put_in = [&](int slot, T v) { store(io.in_adj + size_t(slot) * n, i, v); };

  // ---- The forward again (update_lanes' operations in its order) ----
  // The modulus, centre, size and orientation from the rows or from a bond stage's record.
  const auto record = [&](const double* p, int c) {
    return record_lanes<T>(p + c, i, std::make_index_sequence<kLanes<T>>());
  };
  const bool kept = io.centre_size != nullptr;
  const T E = kept ? load(io.stiff, i, T{}) : in(kVE), se = in(kVSqrtE), dt = in(kVDt);
  T x0[3], b[4];  // b: x, y, z, w
  for (int c = 0; c < 3; ++c) x0[c] = kept ? record(io.centre_size, c) : in(kVPos + c);
  const T size = kept ? record(io.centre_size, 3) : in(kVSize);
  for (int c = 0; c < 4; ++c) b[c] = kept ? record(io.quat, c) : in(kVQuat + c);
  const T h0[3] = {in(kVAngMom), in(kVAngMom + 1), in(kVAngMom + 2)};
  const T mo[3] = {in(kVMoment), in(kVMoment + 1), in(kVMoment + 2)};
  T f[3] = {in(kVForce), in(kVForce + 1), in(kVForce + 2)};
  T p[3] = {in(kVLinMom), in(kVLinMom + 1), in(kVLinMom + 2)};
  // The floor's branches (all clear without one).
  const T pen = 0.5 * size - x0[2];
  const auto never = zero != zero;
  const auto contact = k.flat_floor ? pen > 0.0 : never;
  const T normal = 2.0 * E * k.size * pen;
  const T vel[3] = {p[0] * k.inv_mass, p[1] * k.inv_mass, p[2] * k.inv_mass};
  const T c_col = k.c_col_unit * se;
  const auto at_rest = (vel[0] == 0.0) & (vel[1] == 0.0);
  const auto sticks = root(f[0] * f[0] + f[1] * f[1]) < k.def.mu_static * normal;
  const T speed = root(vel[0] * vel[0] + vel[1] * vel[1]);
  const T fric = k.def.mu_kinetic * normal;
  const auto moving = and_not(contact, at_rest);
  const auto slides = moving & (fric * dt < k.mass * speed);
  const auto stops = and_not(moving, slides);
  const auto held = (contact & at_rest & sticks) | stops;
  // Stand-ins in lanes that do not take a branch or are off the hand path (1 for a divisor, 0
  // for the series' argument), so that no lane makes a NaN (the tests trap FE_INVALID).
  const T divisor = pick(slides, speed, splat(1.0, T{}));
  T slide_t[2];
  for (int c = 0; c < 2; ++c) {
    slide_t[c] = fric * vel[c] / divisor;
    f[c] = pick(slides, f[c] - slide_t[c], f[c]);
    p[c] = pick(stops, zero, p[c]);
  }
  f[2] = pick(contact, f[2] + (normal - c_col * vel[2]), f[2]);
  f[0] = pick(held, zero, f[0]), f[1] = pick(held, zero, f[1]);
  T pn[3];
  for (int c = 0; c < 3; ++c) pn[c] = p[c] + f[c] * dt;
  const T step = dt * k.inv_mass;
  T hm[3], hd[3];
  for (int c = 0; c < 3; ++c) hm[c] = h0[c] + mo[c] * dt;
  const T cc = k.rot_damp * (k.c_rot_unit * se) * k.inv_inertia;
  const T decay = 1.0 - cc * dt;
  for (int c = 0; c < 3; ++c) hd[c] = hm[c] * decay;
  const T turn = dt * k.inv_inertia;
  T q[4];  // x, y, z, w
  T norm;
  // The exact model's turn by the rotation vector v = omega dt (r = (r, rw), its half-angle
  // series), or Voxelyze 0.9's first-order step q + dt (0, omega / 2) q (half: omega / 2),
  // normalised, a q whose w is then 1 no turn at all (none).
  const bool voxelyze = k.def.bond_model == BondModel::kVoxelyze09;
  T v[3] = {zero, zero, zero}, h2 = zero, rw = zero, half_sinc = zero, r[3] = {zero, zero, zero};
  T half[3] = {zero, zero, zero};
  auto none = never;
  if (!voxelyze) {
    for (int c = 0; c < 3; ++c) v[c] = hd[c] * turn;
    const T a2 = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
    const auto in_series = 0.25 * a2 < 2.5e-5;
    h2 = pick(in_series, 0.25 * a2, zero);
    rw = 1.0 - h2 * (0.5 - h2 * (1.0 / 24 - h2 * (1.0 / 720 - h2 * (1.0 / 40320))));
    const T sinc =
        1.0 - h2 * (1.0 / 6 - h2 * (1.0 / 120 - h2 * (1.0 / 5040 - h2 * (1.0 / 362880))));
    half_sinc = 0.5 * sinc;
    for (int c = 0; c < 3; ++c) r[c] = half_sinc * v[c];
    q[0] = (rw * b[0] + r[1] * b[2]) - (r[2] * b[1] - r[0] * b[3]);
    q[1] = (rw * b[1] + r[1] * b[3]) + (r[2] * b[0] - r[0] * b[2]);
    q[2] = (rw * b[2] - r[1] * b[0]) + (r[2] * b[3] + r[0] * b[1]);
    q[3] = (rw * b[3] - r[1] * b[1]) - (r[2] * b[2] + r[0] * b[0]);
    const T n2 = (q[0] * q[0] + q[2] * q[2]) + (q[1] * q[1] + q[3] * q[3]);
    const auto oriented = n2 > 0.0;
    norm = root(pick(oriented, n2, splat(1.0, T{})));
    // Off the hand path: clamped, a turn past the series' range (sin_cycles), no orientation.
    store_flag(io.off, i, load_flag(io.fixed, i, T{}) | mask_not(in_series) | mask_not(oriented));
  } else {
    for (int c = 0; c < 3; ++c) half[c] = 0.5 * (hd[c] * k.inv_inertia);
    q[3] = b[3] + (((zero - half[0] * b[0]) - half[1] * b[1]) - half[2] * b[2]) * dt;
    q[0] = b[0] + ((half[0] * b[3] + half[1] * b[2]) - half[2] * b[1]) * dt;
    q[1] = b[1] + ((half[1] * b[3] - half[0] * b[2]) + half[2] * b[0]) * dt;
    q[2] = b[2] + ((half[0] * b[1] - half[1] * b[0]) + half[2] * b[3]) * dt;
    const T len = root(((q[0] * q[0] + q[1] * q[1]) + q[2] * q[2]) + q[3] * q[3]);
    const auto some = len > 0.0;
    norm = pick(some, len, splat(1.0, T{}));
    none = mask_not(q[3] * (1.0 / norm) < 1.0);
    // Off the hand path: clamped, no orientation.
    store_flag(io.off, i, load_flag(io.fixed, i, T{}) | mask_not(some));
  }

  // ---- The reverse: g_* is the adjoint of * ----
  // Normalisation (Voxelyze 0.9's none: a constant).
  T g_q[4], g_n2 = zero;
  for (int c = 0; c < 4; ++c) {
    const T g = pick(none, zero, out(kVOutQuat + c));
    g_q[c] = g / norm;
    g_n2 -= g * (q[c] / norm) / norm;
  }
  g_n2 *= 0.5 / norm;
  for (int c = 0; c < 4; ++c) g_q[c] += 2.0 * g_n2 * q[c];
  T g_dt = zero, g_turned[3];  // g_turned: the turn's share of hd's adjoint
  if (!voxelyze) {
    // q = r b (r = (r, rw)).
    const T g_rw = g_q[0] * b[0] + g_q[1] * b[1] + g_q[2] * b[2] + g_q[3] * b[3];
    const T g_r[3] = {g_q[0] * b[3] - g_q[1] * b[2] + g_q[2] * b[1] - g_q[3] * b[0],
                      g_q[0] * b[2] + g_q[1] * b[3] - g_q[2] * b[0] - g_q[3] * b[1],
                      -g_q[0] * b[1] + g_q[1] * b[0] + g_q[2] * b[3] - g_q[3] * b[2]};
    put_in(kVQuat, g_q[0] * rw + g_q[1] * r[2] - g_q[2] * r[1] - g_q[3] * r[0]);
    put_in(kVQuat + 1, -g_q[0] * r[2] + g_q[1] * rw + g_q[2] * r[0] - g_q[3] * r[1]);
    put_in(kVQuat + 2, g_q[0] * r[1] - g_q[1] * r[0] + g_q[2] * rw - g_q[3] * r[2]);
    put_in(kVQuat + 3, g_q[0] * r[0] + g_q[1] * r[1] + g_q[2] * r[2] + g_q[3] * rw);
    // The half-angle series.
    const T g_half_sinc = g_r[0] * v[0] + g_r[1] * v[1] + g_r[2] * v[2];
    const T rw_slope = -(0.5 - h2 * (2.0 / 24 - h2 * (3.0 / 720 - h2 * (4.0 / 40320))));
    const T sinc_slope = -(1.0 / 6 - h2 * (2.0 / 120 - h2 * (3.0 / 5040 - h2 * (4.0 / 362880))));
    const T g_h2 = g_rw * rw_slope + 0.5 * g_half_sinc * sinc_slope;
    const T g_a2 = 0.25 * g_h2;
    T g_v[3], g_turn = zero;
    for (int c = 0; c < 3; ++c) {
      g_v[c] = g_r[c] * half_sinc + 2.0 * g_a2 * v[c];
      g_turn += g_v[c] * hd[c];
    }
    g_dt = g_turn * k.inv_inertia;
    for (int c = 0; c < 3; ++c) g_turned[c] = g_v[c] * turn;
  } else {
    // q = b + dt (0, half) b, half = omega / 2 (x, y, z; w last).
    put_in(kVQuat, g_q[0] + (-half[0] * g_q[3] + half[2] * g_q[1] - half[1] * g_q[2]) * dt);
    put_in(kVQuat + 1, g_q[1] + (-half[1] * g_q[3] - half[2] * g_q[0] + half[0] * g_q[2]) * dt);
    put_in(kVQuat + 2, g_q[2] + (-half[2] * g_q[3] + half[1] * g_q[0] - half[0] * g_q[1]) * dt);
    put_in(kVQuat + 3, g_q[3] + (half[0] * g_q[0] + half[1] * g_q[1] + half[2] * g_q[2]) * dt);
    const T g_half[3] = {(-b[0] * g_q[3] + b[3] * g_q[0] - b[2] * g_q[1] + b[1] * g_q[2]) * dt,
                         (-b[1] * g_q[3] + b[2] * g_q[0] + b[3] * g_q[1] - b[0] * g_q[2]) * dt,
                         (-b[2] * g_q[3] - b[1] * g_q[0] + b[0] * g_q[1] + b[3] * g_q[2]) * dt};
    const T dq[4] = {(half[0] * b[3] + half[1] * b[2]) - half[2] * b[1],
                     (half[1] * b[3] - half[0] * b[2]) + half[2] * b[0],
                     (half[0] * b[1] - half[1] * b[0]) + half[2] * b[3],
                     ((zero - half[0] * b[0]) - half[1] * b[1]) - half[2] * b[2]};
    g_dt = g_q[0] * dq[0] + g_q[1] * dq[1] + g_q[2] * dq[2] + g_q[3] * dq[3];
    for (int c = 0; c < 3; ++c) g_turned[c] = 0.5 * k.inv_inertia * g_half[c];
  }
  // Rotational damping and the moment.
  T g_decay = zero;
  for (int c = 0; c < 3; ++c) {
    const T g_hd = out(kVOutAngMom + c) + g_turned[c];
    g_decay += g_hd * hm[c];
    const T g_hm = g_hd * decay;
    put_in(kVAngMom + c, g_hm);
    put_in(kVMoment + c, g_hm * dt);
    g_dt += g_hm * mo[c];
  }
  g_dt -= g_decay * cc;
  T g_se = -g_decay * dt * k.inv_inertia * k.rot_damp * k.c_rot_unit;
  // Position and momentum.
  T g_step = zero, g_f[3], g_p[3];
  for (int c = 0; c < 3; ++c) {
    const T g_x1 = out(kVOutPos + c);
    put_in(kVPos + c, g_x1);
    const T g_pn = out(kVOutLinMom + c) + g_x1 * step;
    g_step += g_x1 * pn[c];
    g_p[c] = g_pn;
    g_f[c] = g_pn * dt;
    g_dt += g_pn * f[c];
  }
  g_dt += g_step * k.inv_mass;
  g_f[0] = pick(held, zero, g_f[0]), g_f[1] = pick(held, zero, g_f[1]);
  // The floor, in contact.
  T g_normal = out(kVOutNormal) + g_f[2];
  const T g_vz = -g_f[2] * c_col;
  g_se = pick(contact, g_se + -g_f[2] * vel[2] * k.c_col_unit, g_se);
  T g_vel[2];
  {  // sliding
    T g_fric = zero, g_speed = zero;
    for (int c = 0; c < 2; ++c) {
      const T g_t = -g_f[c];
      g_speed -= g_t * slide_t[c] / divisor;
      g_fric += g_t / divisor * vel[c];
      g_vel[c] = g_t / divisor * fric;
    }
    g_normal = pick(slides, g_normal + g_fric * k.def.mu_kinetic, g_normal);
    for (int c = 0; c < 2; ++c)
      g_vel[c] = pick(slides, g_vel[c] + g_speed * (0.5 / divisor) * 2.0 * vel[c], zero);
  }
  for (int c = 0; c < 2; ++c)
    g_p[c] = pick(contact, pick(stops, zero, g_p[c]) + g_vel[c] * k.inv_mass, g_p[c]);
  g_p[2] = pick(contact, g_p[2] + g_vz * k.inv_mass, g_p[2]);
  const T g_E = pick(contact, g_normal * pen * 2.0 * k.size, zero);
  const T g_pen = pick(contact, g_normal * (2.0 * E * k.size), zero);
  for (int c = 0; c < 3; ++c) put_in(kVForce + c, g_f[c]), put_in(kVLinMom + c, g_p[c]);
  put_in(kVSize, 0.5 * g_pen);
  put_in(kVPos + 2, out(kVOutPos + 2) - g_pen);
  put_in(kVE, g_E);
  put_in(kVSqrtE, g_se);
  put_in(kVDt, g_dt);
}

// The whole lane groups of voxels from the first; returns how many voxels that is (the caller
// takes the rest one by one with its own `double` instance).
template <class T>
int run_voxel_reverse(const grad::VoxelReverseIo& io, const ModelConstants& k) {
  int i = 0;
  for (; i + kLanes<T> <= static_cast<int>(io.n); i += kLanes<T>) voxel_reverse_lanes<T>(io, i, k);
  return i;
}

}  // namespace
}  // namespace plastivox
