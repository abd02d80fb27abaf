// The voxel update's adjoint (voxel_adjoint.hpp).
#include "voxel_adjoint.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "adj.hpp"
#include "adj_elementary.hpp"
#include "lanes.hpp"
// After the lane vocabularies: the kernel template finds them by argument-dependent lookup.
#include "plastivox/simd.hpp"
#include "voxel_body.hpp"
#include "voxel_reverse_body.hpp"

namespace plastivox::grad {

void keep_voxel_stage(const VoxelKernelIo& io, size_t n, double dt, int32_t dt_id, double* values,
                      int32_t* ids, uint8_t* flags, bool shared) {
  // Component c of records of `width` in `row` as input `slot`'s row.
  const auto keep = [&](int slot, const double* row, int width, int c) {
    const int32_t* row_ids = g_tape ? g_tape->ids_of(row) : nullptr;
    double* v = values + size_t(slot) * n;
    int32_t* id = ids + size_t(slot) * n;
    for (size_t i = 0; i < n; ++i) {
      v[i] = row[width * i + c];
      id[i] = row_ids ? row_ids[width * i + c] : -1;
    }
  };
  keep(kVSqrtE, io.sqrt_e, 1, 0);
  for (int c = 0; c < 3; ++c) {
    keep(kVForce + c, io.force[c], 1, 0);
    keep(kVLinMom + c, io.lin_mom, 3, c);
    keep(kVAngMom + c, io.ang_mom, 3, c);
    keep(kVMoment + c, io.moment[c], 1, 0);
  }
  if (!shared) {
    keep(kVE, io.stiff, 1, 0);
    for (int c = 0; c < 3; ++c) keep(kVPos + c, io.pos, 3, c);
    keep(kVSize, io.size, 1, 0);
    for (int c = 0; c < 4; ++c) keep(kVQuat + c, io.quat, 4, c);
  }
  std::fill(values + size_t(kVDt) * n, values + size_t(kVDt + 1) * n, dt);
  std::fill(ids + size_t(kVDt) * n, ids + size_t(kVDt + 1) * n, dt_id);
  std::copy(io.fixed, io.fixed + n, flags);
  std::copy(io.static_friction, io.static_friction + n, flags + n);
}

// One voxel as the update sees it, in arrays of its own (outputs apart from inputs): a
// VoxelTape's.
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
  // Every array as a shadow of `t` (once).
  void shadow(Tape& t) {
    t.add_shadow(&stiff, &stiff_id);
    t.add_shadow(&sqrt_e, &sqrt_e_id);
    for (int c = 0; c < 3; ++c) t.add_shadow(&force[c], &force_id[c]);
    for (int c = 0; c < 3; ++c) t.add_shadow(&moment[c], &moment_id[c]);
    t.add_shadow(lin_mom, lin_mom_id);
    t.add_shadow(pos, pos_id);
    t.add_shadow(&size, &size_id);
    t.add_shadow(ang_mom, ang_mom_id);
    t.add_shadow(quat, quat_id);
    t.add_shadow(out_pos, out_pos_id);
    t.add_shadow(out_lin_mom, out_lin_mom_id);
    t.add_shadow(out_ang_mom, out_ang_mom_id);
    t.add_shadow(out_quat, out_quat_id);
    t.add_shadow(&normal, &normal_id);
  }
  // The inputs as the leaves of `t`, in VoxelInput's order (nodes 0 to kVoxelInputs - 1), and
  // the outputs without nodes before the kernel writes them.
  void record_inputs(Tape& t, const VoxelArgs& a) {
    const auto in = [&](double* value, int32_t* id, int slot, int count) {
      for (int c = 0; c < count; ++c) value[c] = a.v[slot + c], id[c] = slot + c;
    };
    for (int j = 0; j < kVoxelInputs; ++j) t.leaf();
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
    for (int c = 0; c < 3; ++c) out_pos_id[c] = out_lin_mom_id[c] = out_ang_mom_id[c] = -1;
    for (int c = 0; c < 4; ++c) out_quat_id[c] = -1;
    normal_id = -1;
    fixed = a.fixed;
    was_held = a.was_held;
  }
};

struct VoxelTape::Impl {
  LocalVoxel voxel;
  Tape tape;
  std::vector<double> adj;
  Impl() { voxel.shadow(tape); }
};

VoxelTape::VoxelTape() : impl_(std::make_unique<Impl>()) {}
VoxelTape::~VoxelTape() = default;

void voxel_reverse_tape(const VoxelArgs& a, const ModelConstants& k, const double* out_adj,
                        double* in_adj) {
  VoxelTape tape;
  tape.reverse(a, k, out_adj, in_adj);
}

void VoxelTape::reverse(const VoxelArgs& a, const ModelConstants& k, const double* out_adj,
                        double* in_adj) {
  LocalVoxel& L = impl_->voxel;
  Tape& tape = impl_->tape;
  tape.nodes.clear();
  L.record_inputs(tape, a);
  Tape* const outer = g_tape;
  g_tape = &tape;
  Adj max_speed2 = 0.0;
  bool bad = false;
  update_lanes<Adj, bool, Adj>(L.io, L.st, 0, k, Adj(a.v[kVDt], kVDt), max_speed2, bad);
  g_tape = outer;
  std::vector<double>& adj = impl_->adj;
  adj.assign(tape.nodes.size(), 0.0);
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
  for (int j = 0; j < kVoxelInputs; ++j) in_adj[j] += adj[size_t(j)];
}

namespace {

VoxelReverseKernel voxel_reverse_kernel() {
  switch (simd_level()) {
    case SimdLevel::kAvx512:
#if defined(PLASTIVOX_HAVE_AVX512)
      return voxel_reverse_kernel_avx512();
#endif
      [[fallthrough]];
    case SimdLevel::kAvx2:
#if defined(PLASTIVOX_HAVE_AVX2)
      return voxel_reverse_kernel_avx2();
#endif
      [[fallthrough]];
    default:
      return &run_voxel_reverse<double>;
  }
}

}  // namespace

bool voxel_reverse(const VoxelArgs& A, const ModelConstants& k, const double* out_adj,
                   double* in_adj) {
  // The voxel as an update of one: its arguments are the record's rows of one.
  double in[kVoxelInputs];
  uint8_t off = 0;
  VoxelReverseIo io;
  io.values = A.v;
  io.fixed = &A.fixed;
  io.n = 1;
  io.out_adj = out_adj;
  io.in_adj = in;
  io.off = &off;
  voxel_reverse_lanes<double>(io, 0, k);
  if (off) return false;
  for (int j = 0; j < kVoxelInputs; ++j) in_adj[j] += in[j];
  return true;
}

void voxel_stage_reverse(size_t n, const double* values, const int32_t* ids, const uint8_t* flags,
                         size_t first, double* adj, const ModelConstants& k, VoxelStageScratch& s,
                         const VoxelSharedInputs* shared) {
  const uint8_t *fixed = flags, *held = flags + n;
  s.in.resize(kVoxelInputs * n);
  s.off.assign(n, 1);
  VoxelReverseIo r;
  r.values = values;
  r.fixed = fixed;
  r.n = n;
  r.out_adj = adj + first;
  r.in_adj = s.in.data();
  r.off = s.off.data();
  if (shared) r.centre_size = shared->centre_size, r.quat = shared->quat, r.stiff = shared->stiff;
  // Whole lane groups at the SIMD level, then the rest here (see bond_stage_reverse).
  for (int i = voxel_reverse_kernel()(r, k); i < int(n); ++i) voxel_reverse_lanes<double>(r, i, k);
  // Voxels off the hand path, by the kernel recorded on a tape.
  for (size_t i = 0; i < n; ++i) {
    if (!s.off[i]) continue;
    VoxelArgs a;
    double out[kVoxelOutputs], in[kVoxelInputs] = {};
    for (int j = 0; j < kVoxelInputs; ++j) a.v[j] = values[j * n + i], a.id[j] = ids[j * n + i];
    if (shared) {
      const auto take = [&](int slot, const double* v, const int32_t* id, size_t at) {
        a.v[slot] = v[at], a.id[slot] = id[at];
      };
      take(kVE, shared->stiff, shared->stiff_ids, i);
      for (int c = 0; c < 4; ++c) {
        take(kVPos + c, shared->centre_size, shared->centre_size_ids, 4 * i + c);  // kVSize: c 3
        take(kVQuat + c, shared->quat, shared->quat_ids, 4 * i + c);
      }
    }
    a.fixed = fixed[i];
    a.was_held = held[i];
    for (int o = 0; o < kVoxelOutputs; ++o) out[o] = r.out_adj[o * n + i];
    s.tape.reverse(a, k, out, in);
    for (int j = 0; j < kVoxelInputs; ++j) s.in[j * n + i] = in[j];
  }
  if (!shared) {
    for (size_t e = 0; e < kVoxelInputs * n; ++e)
      if (ids[e] >= 0) adj[ids[e]] += s.in[e];
    return;
  }
  static_assert(kVSize == kVPos + 3, "the shared rows are kVE, kVPos to kVSize and kVQuat on");
  for (int j = 0; j < kVoxelInputs; ++j) {
    if (j == kVE || (j >= kVPos && j <= kVSize) || (j >= kVQuat && j < kVQuat + 4)) continue;
    const int32_t* id = ids + size_t(j) * n;
    const double* g = s.in.data() + size_t(j) * n;
    for (size_t i = 0; i < n; ++i)
      if (id[i] >= 0) adj[id[i]] += g[i];
  }
}

void keep_gather_stage(const VoxelKernelIo& io, const GatherStageLayout& L, double* values,
                       int32_t* ids) {
  const auto keep = [&](const double* row, size_t count, double* v, int32_t* id) {
    std::copy(row, row + count, v);
    const int32_t* row_ids = g_tape ? g_tape->ids_of(row) : nullptr;
    if (row_ids)
      std::copy(row_ids, row_ids + count, id);
    else
      std::fill(id, id + count, -1);
  };
  keep(io.stiff, L.n, values, ids);
  keep(io.lin_mom, 3 * L.n, values + L.lin_mom(), ids + L.lin_mom());
}

void gather_stage_reverse(const GatherStageLayout& L, const double* values, const int32_t* ids,
                          size_t first, double* adj, const ModelConstants& k) {
  // force = ((sum_s +-F_s - coef p) + weight) + load, moment = sum_s M_s,
  // coef = global_damping c_lin_unit sqrt(E) / mass.
  const size_t n = L.n;
  const double* out = adj + first;
  const double* lin_mom = values + L.lin_mom();
  const int32_t* lin_ids = ids + L.lin_mom();
  const auto add = [&](int32_t id, double v) {
    if (id >= 0) adj[id] += v;
  };
  for (size_t i = 0; i < n; ++i) {
    const double se = std::sqrt(values[i]);
    const double coef = (k.def.global_damping * (k.c_lin_unit * se)) / k.mass;
    double g_coef = 0;
    for (int c = 0; c < 3; ++c) {
      const double g_f = out[(kGOutForce + c) * n + i];
      add(lin_ids[3 * i + c], -(g_f * coef));
      g_coef -= g_f * lin_mom[3 * i + c];
    }
    const double g_se =
        out[kGOutSqrtE * n + i] + g_coef * k.def.global_damping * k.c_lin_unit / k.mass;
    add(ids[i], se > 0 ? g_se * (0.5 / se) : 0.0);
  }
}

}  // namespace plastivox::grad
