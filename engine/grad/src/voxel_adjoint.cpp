// The voxel update's adjoint (voxel_adjoint.hpp).
#include "voxel_adjoint.hpp"

#include <cmath>
#include <vector>

#include "adj.hpp"
#include "adj_elementary.hpp"
#include "lanes.hpp"
// After the lane vocabularies: the kernel template finds them by argument-dependent lookup.
#include "voxel_body.hpp"

namespace plastivox::grad {

VoxelReads voxel_reads(const VoxelKernelIo& io, double dt, int32_t dt_id) {
  VoxelReads r;
  if (g_tape) {
    r.stiff = g_tape->ids_of(io.stiff);
    r.sqrt_e = g_tape->ids_of(io.sqrt_e);
    r.lin_mom = g_tape->ids_of(io.lin_mom);
    r.pos = g_tape->ids_of(io.pos);
    r.size = g_tape->ids_of(io.size);
    r.ang_mom = g_tape->ids_of(io.ang_mom);
    r.quat = g_tape->ids_of(io.quat);
    for (int c = 0; c < 3; ++c)
      r.force[c] = g_tape->ids_of(io.force[c]), r.moment[c] = g_tape->ids_of(io.moment[c]);
  }
  r.dt = dt;
  r.dt_id = dt_id;
  return r;
}

VoxelArgs voxel_args(const VoxelKernelIo& io, int i, const VoxelReads& r) {
  VoxelArgs a;
  const size_t v = static_cast<size_t>(i);
  const auto take = [&](int slot, const double* values, const int32_t* ids, size_t k) {
    a.v[slot] = values[k];
    a.id[slot] = ids ? ids[k] : -1;
  };
  take(kVE, io.stiff, r.stiff, v);
  take(kVSqrtE, io.sqrt_e, r.sqrt_e, v);
  for (int c = 0; c < 3; ++c) {
    take(kVForce + c, io.force[c], r.force[c], v);
    take(kVLinMom + c, io.lin_mom, r.lin_mom, 3 * v + c);
    take(kVPos + c, io.pos, r.pos, 3 * v + c);
    take(kVAngMom + c, io.ang_mom, r.ang_mom, 3 * v + c);
    take(kVMoment + c, io.moment[c], r.moment[c], v);
  }
  take(kVSize, io.size, r.size, v);
  for (int c = 0; c < 4; ++c) take(kVQuat + c, io.quat, r.quat, 4 * v + c);
  a.v[kVDt] = r.dt;
  a.id[kVDt] = r.dt_id;
  a.fixed = io.fixed[i];
  a.was_held = io.static_friction[i];
  return a;
}

namespace {

// One voxel as the update sees it, in arrays of its own (outputs apart from inputs).
struct LocalVoxel {
  double stiff, sqrt_e, force[3], moment[3], lin_mom[3], pos[3], size, ang_mom[3], quat[4];
  double out_pos[3], out_lin_mom[3], out_ang_mom[3], out_quat[4], normal;
  uint8_t fixed = 0, was_held = 0, held = 0;
  int32_t stiff_id, sqrt_e_id, force_id[3], moment_id[3], lin_mom_id[3], pos_id[3], size_id,
      ang_mom_id[3], quat_id[4];
  int32_t out_pos_id[3], out_lin_mom_id[3], out_ang_mom_id[3], out_quat_id[4], normal_id;
  VoxelKernelIo io;
  VoxelStateOut st;

  LocalVoxel() {
    io.fixed = &fixed;
    io.pos = pos, io.quat = quat, io.lin_mom = lin_mom, io.ang_mom = ang_mom;
    io.stiff = &stiff, io.static_friction = &was_held, io.size = &size;
    for (int c = 0; c < 3; ++c) io.force[c] = &force[c], io.moment[c] = &moment[c];
    io.sqrt_e = &sqrt_e;
    io.floor_normal = &normal;
    st.pos = out_pos, st.quat = out_quat, st.lin_mom = out_lin_mom, st.ang_mom = out_ang_mom;
    st.static_friction = &held;
  }
  // Every array as a shadow of `t`, and the inputs as its leaves in VoxelInput's order.
  void record_inputs(Tape& t, const VoxelArgs& a, int32_t* leaf) {
    const auto in = [&](double* value, int32_t* id, int slot, int count) {
      t.add_shadow(value, id);
      for (int c = 0; c < count; ++c) value[c] = a.v[slot + c], id[c] = leaf[slot + c];
    };
    for (int j = 0; j < kVoxelInputs; ++j) leaf[j] = t.leaf();
    in(&stiff, &stiff_id, kVE, 1);
    in(&sqrt_e, &sqrt_e_id, kVSqrtE, 1);
    for (int c = 0; c < 3; ++c) {
      in(&force[c], &force_id[c], kVForce + c, 1);
      in(&moment[c], &moment_id[c], kVMoment + c, 1);
    }
    in(lin_mom, lin_mom_id, kVLinMom, 3);
    in(pos, pos_id, kVPos, 3);
    in(&size, &size_id, kVSize, 1);
    in(ang_mom, ang_mom_id, kVAngMom, 3);
    in(quat, quat_id, kVQuat, 4);
    t.add_shadow(out_pos, out_pos_id);
    t.add_shadow(out_lin_mom, out_lin_mom_id);
    t.add_shadow(out_ang_mom, out_ang_mom_id);
    t.add_shadow(out_quat, out_quat_id);
    t.add_shadow(&normal, &normal_id);
    fixed = a.fixed;
    was_held = a.was_held;
  }
};

}  // namespace

void voxel_reverse_tape(const VoxelArgs& a, const ModelConstants& k, const double* out_adj,
                        double* in_adj) {
  LocalVoxel L;
  Tape tape;
  int32_t leaf[kVoxelInputs];
  L.record_inputs(tape, a, leaf);
  Tape* const outer = g_tape;
  g_tape = &tape;
  Adj max_speed2 = 0.0;
  bool bad = false;
  update_lanes<Adj, bool, Adj>(L.io, L.st, 0, k, Adj(a.v[kVDt], leaf[kVDt]), max_speed2, bad);
  g_tape = outer;
  std::vector<double> adj(tape.nodes.size(), 0.0);
  const auto seed = [&](int32_t id, double v) {
    if (id >= 0) adj[id] += v;
  };
  for (int c = 0; c < 3; ++c) {
    seed(L.out_pos_id[c], out_adj[kVOutPos + c]);
    seed(L.out_lin_mom_id[c], out_adj[kVOutLinMom + c]);
    seed(L.out_ang_mom_id[c], out_adj[kVOutAngMom + c]);
  }
  for (int c = 0; c < 4; ++c) seed(L.out_quat_id[c], out_adj[kVOutQuat + c]);
  seed(L.normal_id, out_adj[kVOutNormal]);
  sweep_nodes(tape, adj, 0, tape.nodes.size());
  for (int j = 0; j < kVoxelInputs; ++j) in_adj[j] += adj[leaf[j]];
}

bool voxel_reverse(const VoxelArgs& A, const ModelConstants& k, const double* out_adj,
                   double* in_adj) {
  if (A.fixed || k.def.bond_model != BondModel::kExact) return false;
  // ---- The forward again (update_lanes' operations in its order), keeping what the reverse
  // needs ----
  const double E = A.v[kVE], se = A.v[kVSqrtE], dt = A.v[kVDt];
  const double* x0 = A.v + kVPos;
  const double* h0 = A.v + kVAngMom;
  const double* mo = A.v + kVMoment;
  const double* b = A.v + kVQuat;  // x, y, z, w
  double f[3] = {A.v[kVForce], A.v[kVForce + 1], A.v[kVForce + 2]};
  double p[3] = {A.v[kVLinMom], A.v[kVLinMom + 1], A.v[kVLinMom + 2]};
  bool contact = false, slides = false, stops = false, held = false;
  double pen = 0, normal = 0, vel[3] = {0, 0, 0}, c_col = 0, speed = 0, fric = 0, slide_t[2];
  if (k.flat_floor) {
    pen = 0.5 * A.v[kVSize] - x0[2];
    contact = pen > 0.0;
    if (contact) {
      normal = 2.0 * E * k.size * pen;
      vel[2] = p[2] * k.inv_mass;
      c_col = k.c_col_unit * se;
      vel[0] = p[0] * k.inv_mass, vel[1] = p[1] * k.inv_mass;
      const bool at_rest = vel[0] == 0.0 && vel[1] == 0.0;
      const bool sticks = std::sqrt(f[0] * f[0] + f[1] * f[1]) < k.def.mu_static * normal;
      speed = std::sqrt(vel[0] * vel[0] + vel[1] * vel[1]);
      fric = k.def.mu_kinetic * normal;
      slides = !at_rest && fric * dt < k.mass * speed;
      stops = !at_rest && !slides;
      if (slides)
        for (int c = 0; c < 2; ++c) slide_t[c] = fric * vel[c] / speed, f[c] = f[c] - slide_t[c];
      if (stops) p[0] = 0.0, p[1] = 0.0;
      held = (at_rest && sticks) || stops;
      f[2] = f[2] + (normal - c_col * vel[2]);
    }
  }
  if (held) f[0] = 0.0, f[1] = 0.0;
  double pn[3];
  for (int c = 0; c < 3; ++c) pn[c] = p[c] + f[c] * dt;
  const double step = dt * k.inv_mass;
  double hm[3], hd[3];
  for (int c = 0; c < 3; ++c) hm[c] = h0[c] + mo[c] * dt;
  const double cc = k.rot_damp * (k.c_rot_unit * se) * k.inv_inertia;
  const double decay = 1.0 - cc * dt;
  for (int c = 0; c < 3; ++c) hd[c] = hm[c] * decay;
  const double turn = dt * k.inv_inertia;
  const double v[3] = {hd[0] * turn, hd[1] * turn, hd[2] * turn};
  const double a2 = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
  const double h2 = 0.25 * a2;
  if (!(h2 < 2.5e-5)) return false;  // a turn past the series' range: sin_cycles
  const double rw = 1.0 - h2 * (0.5 - h2 * (1.0 / 24 - h2 * (1.0 / 720 - h2 * (1.0 / 40320))));
  const double sinc =
      1.0 - h2 * (1.0 / 6 - h2 * (1.0 / 120 - h2 * (1.0 / 5040 - h2 * (1.0 / 362880))));
  const double half_sinc = 0.5 * sinc;
  const double r[3] = {half_sinc * v[0], half_sinc * v[1], half_sinc * v[2]};
  double q[4];  // x, y, z, w
  q[0] = (rw * b[0] + r[1] * b[2]) - (r[2] * b[1] - r[0] * b[3]);
  q[1] = (rw * b[1] + r[1] * b[3]) + (r[2] * b[0] - r[0] * b[2]);
  q[2] = (rw * b[2] - r[1] * b[0]) + (r[2] * b[3] + r[0] * b[1]);
  q[3] = (rw * b[3] - r[1] * b[1]) - (r[2] * b[2] + r[0] * b[0]);
  const double n2 = (q[0] * q[0] + q[2] * q[2]) + (q[1] * q[1] + q[3] * q[3]);
  if (!(n2 > 0.0)) return false;
  const double norm = std::sqrt(n2);

  // ---- The reverse: g_* is the adjoint of * ----
  // Normalisation.
  double g_q[4], g_n2 = 0;
  for (int c = 0; c < 4; ++c) {
    const double g = out_adj[kVOutQuat + c];
    g_q[c] = g / norm;
    g_n2 -= g * (q[c] / norm) / norm;
  }
  g_n2 *= 0.5 / norm;
  for (int c = 0; c < 4; ++c) g_q[c] += 2 * g_n2 * q[c];
  // q = r b (r = (r, rw)).
  const double g_rw = g_q[0] * b[0] + g_q[1] * b[1] + g_q[2] * b[2] + g_q[3] * b[3];
  const double g_r[3] = {g_q[0] * b[3] - g_q[1] * b[2] + g_q[2] * b[1] - g_q[3] * b[0],
                         g_q[0] * b[2] + g_q[1] * b[3] - g_q[2] * b[0] - g_q[3] * b[1],
                         -g_q[0] * b[1] + g_q[1] * b[0] + g_q[2] * b[3] - g_q[3] * b[2]};
  in_adj[kVQuat] += g_q[0] * rw + g_q[1] * r[2] - g_q[2] * r[1] - g_q[3] * r[0];
  in_adj[kVQuat + 1] += -g_q[0] * r[2] + g_q[1] * rw + g_q[2] * r[0] - g_q[3] * r[1];
  in_adj[kVQuat + 2] += g_q[0] * r[1] - g_q[1] * r[0] + g_q[2] * rw - g_q[3] * r[2];
  in_adj[kVQuat + 3] += g_q[0] * r[0] + g_q[1] * r[1] + g_q[2] * r[2] + g_q[3] * rw;
  // The half-angle series.
  const double g_half_sinc = g_r[0] * v[0] + g_r[1] * v[1] + g_r[2] * v[2];
  const double rw_slope = -(0.5 - h2 * (2.0 / 24 - h2 * (3.0 / 720 - h2 * (4.0 / 40320))));
  const double sinc_slope = -(1.0 / 6 - h2 * (2.0 / 120 - h2 * (3.0 / 5040 - h2 * (4.0 / 362880))));
  const double g_h2 = g_rw * rw_slope + 0.5 * g_half_sinc * sinc_slope;
  const double g_a2 = 0.25 * g_h2;
  double g_v[3], g_turn = 0;
  for (int c = 0; c < 3; ++c) {
    g_v[c] = g_r[c] * half_sinc + 2 * g_a2 * v[c];
    g_turn += g_v[c] * hd[c];
  }
  double g_dt = g_turn * k.inv_inertia;
  // Rotational damping and the moment.
  double g_decay = 0;
  for (int c = 0; c < 3; ++c) {
    const double g_hd = out_adj[kVOutAngMom + c] + g_v[c] * turn;
    g_decay += g_hd * hm[c];
    const double g_hm = g_hd * decay;
    in_adj[kVAngMom + c] += g_hm;
    in_adj[kVMoment + c] += g_hm * dt;
    g_dt += g_hm * mo[c];
  }
  g_dt -= g_decay * cc;
  double g_se = -g_decay * dt * k.inv_inertia * k.rot_damp * k.c_rot_unit;
  // Position and momentum.
  double g_step = 0, g_f[3], g_p[3];
  for (int c = 0; c < 3; ++c) {
    const double g_x1 = out_adj[kVOutPos + c];
    in_adj[kVPos + c] += g_x1;
    const double g_pn = out_adj[kVOutLinMom + c] + g_x1 * step;
    g_step += g_x1 * pn[c];
    g_p[c] = g_pn;
    g_f[c] = g_pn * dt;
    g_dt += g_pn * f[c];
  }
  g_dt += g_step * k.inv_mass;
  if (held) g_f[0] = 0.0, g_f[1] = 0.0;
  // The floor.
  double g_E = 0, g_pen = 0;
  if (contact) {
    double g_normal = out_adj[kVOutNormal] + g_f[2];
    const double g_vz = -g_f[2] * c_col;
    g_se += -g_f[2] * vel[2] * k.c_col_unit;
    double g_vel[2] = {0, 0};
    if (slides) {
      double g_fric = 0, g_speed = 0;
      for (int c = 0; c < 2; ++c) {
        const double g_t = -g_f[c];
        g_speed -= g_t * slide_t[c] / speed;
        g_fric += g_t / speed * vel[c];
        g_vel[c] += g_t / speed * fric;
      }
      g_normal += g_fric * k.def.mu_kinetic;
      for (int c = 0; c < 2; ++c) g_vel[c] += g_speed * (0.5 / speed) * 2 * vel[c];
    }
    if (stops) g_p[0] = 0.0, g_p[1] = 0.0;
    for (int c = 0; c < 2; ++c) g_p[c] += g_vel[c] * k.inv_mass;
    g_p[2] += g_vz * k.inv_mass;
    g_E += g_normal * pen * 2.0 * k.size;
    g_pen = g_normal * (2.0 * E * k.size);
  }
  for (int c = 0; c < 3; ++c) in_adj[kVForce + c] += g_f[c], in_adj[kVLinMom + c] += g_p[c];
  in_adj[kVSize] += 0.5 * g_pen;
  in_adj[kVPos + 2] -= g_pen;
  in_adj[kVE] += g_E;
  in_adj[kVSqrtE] += g_se;
  in_adj[kVDt] += g_dt;
  return true;
}

void gather_reverse(const GatherArgs& a, const ModelConstants& k, const double* out_adj,
                    double* in_adj) {
  // force = ((sum_s +-F_s - coef p) + weight) + load, moment = sum_s M_s,
  // coef = global_damping c_lin_unit sqrt(E) / mass.
  const double se = std::sqrt(a.e);
  const double coef = (k.def.global_damping * (k.c_lin_unit * se)) / k.mass;
  double g_coef = 0;
  for (int c = 0; c < 3; ++c) {
    const double g_f = out_adj[kGOutForce + c], g_m = out_adj[kGOutMoment + c];
    for (int slot = 0; slot < 6; ++slot) {
      in_adj[kGSlots + 6 * slot + c] += slot & 1 ? g_f : -g_f;
      in_adj[kGSlots + 6 * slot + 3 + c] += g_m;
    }
    in_adj[kGLinMom + c] -= g_f * coef;
    g_coef -= g_f * a.lin_mom[c];
  }
  const double g_se = out_adj[kGOutSqrtE] + g_coef * k.def.global_damping * k.c_lin_unit / k.mass;
  in_adj[kGE] += se > 0 ? g_se * (0.5 / se) : 0.0;
}

}  // namespace plastivox::grad
