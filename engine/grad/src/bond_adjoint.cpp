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
#include "bond_reverse_body.hpp"
#include "plastivox/simd.hpp"
#include "scalar_bond_adjoint.hpp"
#include "voxel_adjoint.hpp"

namespace plastivox::grad {

void keep_bond_stage(const BondKernelIo& io, const BondStageLayout& L, double damp, int32_t damp_id,
                     bool prev, double* values, int32_t* ids) {
  const auto keep = [&](size_t at, const double* row, size_t count, bool with_ids = true) {
    std::memcpy(values + at, row, count * sizeof(double));
    if (!with_ids) return;
    const int32_t* row_ids = g_tape ? g_tape->ids_of(row) : nullptr;
    if (row_ids)
      std::memcpy(ids + at, row_ids, count * sizeof(int32_t));
    else
      std::fill(ids + at, ids + at + count, -1);
  };
  keep(0, io.centre_size, 4 * L.n);
  keep(L.quat(), io.quat, 4 * L.n);
  keep(L.stiff(), io.stiff, L.n);
  for (int j = 0; prev && j < 9; ++j) keep(L.prev(j), io.prev[j], L.nb);
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

// One bond as the kernel sees it: bond 0 from voxel 0 to voxel 1, in arrays of its own (a
// BondTape's).
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
  // The outputs' nodes as none, before the kernel writes them.
  void unwritten() {
    for (int j = 0; j < 9; ++j) prev_next_id[j] = -1;
    for (int v = 0; v < 3; ++v)
      for (int c = 0; c < 4; ++c) out_id[v][c] = -1;
    strain_id = stress_id = energy_id = -1;
  }
};

struct BondTape::Impl {
  LocalBond bond;
  Tape tape;
  std::vector<double> adj;
  uint8_t small = 0, small_next = 0;
  Impl() { bond.shadow(tape); }
};

BondTape::BondTape() : impl_(std::make_unique<Impl>()) {}
BondTape::~BondTape() = default;

void BondTape::reverse(Forward forward, const BondArgs& a, bool small, const ModelConstants& k,
                       const double* out_adj, double* in_adj) {
  LocalBond& L = impl_->bond;
  Tape& tape = impl_->tape;
  tape.nodes.clear();
  // Nodes 0 to kBondInputs - 1 are the inputs' leaves, in BondInput's order.
  for (int j = 0; j < kBondInputs; ++j) tape.leaf();
  for (int c = 0; c < 4; ++c) {
    L.centre[c] = a.v[kCentreA + c], L.centre_id[c] = kCentreA + c;
    L.centre[4 + c] = a.v[kCentreB + c], L.centre_id[4 + c] = kCentreB + c;
    L.quat[c] = a.v[kQuatA + c], L.quat_id[c] = kQuatA + c;
    L.quat[4 + c] = a.v[kQuatB + c], L.quat_id[4 + c] = kQuatB + c;
  }
  for (int j = 0; j < 2; ++j) L.stiff[j] = a.v[kStiffA + j], L.stiff_id[j] = kStiffA + j;
  for (int j = 0; j < 9; ++j) L.prev[j] = a.v[kPrev + j], L.prev_id[j] = kPrev + j;
  L.unwritten();
  L.axis = a.axis;
  L.valid = a.valid;
  L.redo = 0;
  impl_->small = small ? 1 : 0;
  Tape* const outer = g_tape;
  g_tape = &tape;
  forward(L.io, &impl_->small, &impl_->small_next, k, Adj(a.v[kDamp], kDamp));
  g_tape = outer;
  std::vector<double>& adj = impl_->adj;
  adj.assign(tape.nodes.size(), 0.0);
  const auto seed = [&](int32_t id, double v) {
    if (id >= 0) adj[size_t(id)] += v;
  };
  for (int v = 0; v < 3; ++v)
    for (int c = 0; c < 3; ++c) seed(L.out_id[v][c], out_adj[kOut + 3 * v + c]);
  for (int j = 0; j < 9; ++j) seed(L.prev_next_id[j], out_adj[kPrevNext + j]);
  seed(L.strain_id, out_adj[kStrain]);
  seed(L.stress_id, out_adj[kStress]);
  seed(L.energy_id, out_adj[kEnergy]);
  sweep_nodes(tape, adj, 0, tape.nodes.size());
  for (int j = 0; j < kBondInputs; ++j) in_adj[j] += adj[size_t(j)];
}

namespace {

// The exact model's batched kernel on one bond (BondTape's forward; it has no frame flags).
void exact_bond(const BondKernelIo& io, const uint8_t*, uint8_t*, const ModelConstants& k,
                Adj damp) {
  int redo = 0;
  bond_lanes<Adj, Adj>(io, 0, k, damp, redo);
}

}  // namespace

void bond_reverse_tape(const BondArgs& a, const ModelConstants& k, const double* out_adj,
                       double* in_adj) {
  BondTape tape;
  tape.reverse(&exact_bond, a, false, k, out_adj, in_adj);
}

namespace {

BondReverseKernel bond_reverse_kernel() {
  switch (simd_level()) {
    case SimdLevel::kAvx512:
#if defined(PLASTIVOX_HAVE_AVX512)
      return bond_reverse_kernel_avx512();
#endif
      [[fallthrough]];
    case SimdLevel::kAvx2:
#if defined(PLASTIVOX_HAVE_AVX2)
      return bond_reverse_kernel_avx2();
#endif
      [[fallthrough]];
    default:
      return &run_bond_reverse<double>;
  }
}

}  // namespace

bool bond_reverse(const BondArgs& A, const ModelConstants& k, const double* out_adj,
                  double* in_adj) {
  // The bond as a stage of one: bond 0 from voxel 0 to voxel 1 (its records back to back).
  double centre[8], quat[8], in[kBondInputs];
  for (int c = 0; c < 4; ++c) {
    centre[c] = A.v[kCentreA + c], centre[4 + c] = A.v[kCentreB + c];
    quat[c] = A.v[kQuatA + c], quat[4 + c] = A.v[kQuatB + c];
  }
  const int a = 0, b = 1;
  const int64_t axis = A.axis;
  uint8_t off = 0;
  BondReverseIo io;
  io.bond.bond_a = &a;
  io.bond.bond_b = &b;
  io.bond.axis_wide = &axis;
  io.bond.centre_size = centre;
  io.bond.quat = quat;
  io.bond.stiff = A.v + kStiffA;
  for (int j = 0; j < 9; ++j) io.bond.prev[j] = A.v + kPrev + j;
  io.bond.prev_valid = &A.valid;
  io.damp = A.v[kDamp];
  io.nb = 1;
  io.records_adj = out_adj + kOut;
  for (int o = kPrevNext; o < kBondOutputs; ++o) io.out_adj[o - kPrevNext] = out_adj + o;
  io.in_adj = in;
  io.off = &off;
  bond_reverse_lanes<double>(io, 0, k);
  if (off) return false;
  for (int j = 0; j < kBondInputs; ++j) in_adj[j] += in[j];
  return true;
}

void bond_stage_reverse(const BondKernelIo& io, const BondStageLayout& L, const double* values,
                        const int32_t* ids, const uint8_t* valid, size_t first,
                        const BondLeafRows& rows, int64_t prev_first, const double* voxel_adj,
                        double* adj, const ModelConstants& k, BondStageScratch& s,
                        const double* voxel_in, const ScalarPathBonds& scalar) {
  const size_t nb = L.nb;
  s.in.resize(kBondInputs * nb);
  s.off.resize(nb);
  BondReverseIo r;
  r.bond.bond_a = io.bond_a;
  r.bond.bond_b = io.bond_b;
  r.bond.axis_wide = io.axis_wide;
  r.bond.centre_size = values;
  r.bond.quat = values + L.quat();
  r.bond.stiff = values + L.stiff();
  for (int j = 0; j < 9; ++j) r.bond.prev[j] = values + L.prev(j);
  r.bond.prev_valid = valid;
  r.bond.all_valid = valid == nullptr;
  r.damp = values[L.damp()];
  r.nb = nb;
  // The records' adjoints from the voxels' (force on a: a's total force minus b's).
  s.records.resize(9 * nb);
  for (int c = 0; c < 3; ++c) {
    const double *force = voxel_adj + size_t(c) * L.n, *moment = voxel_adj + size_t(3 + c) * L.n;
    double* on_a = s.records.data() + size_t(c) * nb;
    double* moment_a = s.records.data() + size_t(3 + c) * nb;
    double* moment_b = s.records.data() + size_t(6 + c) * nb;
    for (size_t b = 0; b < nb; ++b) {
      const int ia = io.bond_a[b], ib = io.bond_b[b];
      on_a[b] = force[ia] - force[ib];
      moment_a[b] = moment[ia];
      moment_b[b] = moment[ib];
    }
  }
  r.records_adj = s.records.data();
  s.zero.resize(nb);  // zeros: written only here
  for (int o = kPrevNext; o < kBondOutputs; ++o) {
    const int row = o < kStrain ? o - kPrevNext : rows.row[o - kStrain];
    r.out_adj[o - kPrevNext] = row < 0 ? s.zero.data() : adj + first + size_t(row) * nb;
  }
  r.in_adj = s.in.data();
  r.off = s.off.data();
  // Bond b's reverse one at a time: Voxelyze 0.9's by hand where it can, else recorded on the
  // small tape, by the batched kernel or the scalar path.
  const auto one = [&](size_t b, BondTape::Forward forward, bool small, bool by_hand) {
    double out[kBondOutputs], in[kBondInputs] = {};
    for (int o = kOut; o < kPrevNext; ++o) out[o] = s.records[(o - kOut) * nb + b];
    for (int o = kPrevNext; o < kBondOutputs; ++o) out[o] = r.out_adj[o - kPrevNext][b];
    const BondArgs a = bond_args(io, L, values, ids, int(b), !valid || valid[b]);
    if (!by_hand || !voxelyze_bond_reverse(a, small, k, out, in))
      s.tape.reverse(forward, a, small, k, out, in);
    for (int j = 0; j < kBondInputs; ++j) s.in[j * nb + b] = in[j];
  };
  if (scalar.small) {
    // Voxelyze 0.9: every bond by the scalar path.
    for (size_t b = 0; b < nb; ++b) one(b, &scalar_bond_forward, scalar.small[b] != 0, true);
  } else {
    // Whole lane groups at the SIMD level, then the rest here: a file compiled for an
    // instruction set may fuse a double's multiply and add (GCC 12 turns alternating adds and
    // subtracts of products into fused multiply-add-subtracts even with -ffp-contract=off), so
    // every bond computed one at a time is computed by this file's code, the scalar level's.
    for (int b = bond_reverse_kernel()(r, k); b < int(nb); ++b) bond_reverse_lanes<double>(r, b, k);
    // The bonds the kernel handed back, by the scalar path (the exact model: no frame flags).
    for (int e = 0; e < scalar.count; ++e) {
      const size_t b = size_t(scalar.list[e]);
      s.off[b] = 0;
      one(b, &scalar_bond_forward, false, false);
    }
    // Bonds off the hand path, by the kernel recorded on a tape.
    for (size_t b = 0; b < nb; ++b)
      if (s.off[b]) one(b, &exact_bond, false, false);
  }
  // The voxels' inputs summed over their bonds in bond order, then added to their nodes. Summed
  // voxel by voxel from each voxel's list of bonds (the same additions in the same order as bond
  // by bond, without a read-modify-write of the sums per bond).
  if (s.start.size() != L.n + 1) {
    s.start.assign(L.n + 1, 0);
    for (size_t b = 0; b < nb; ++b)
      ++s.start[size_t(io.bond_a[b]) + 1], ++s.start[size_t(io.bond_b[b]) + 1];
    for (size_t i = 0; i < L.n; ++i) s.start[i + 1] += s.start[i];
    s.ends.resize(4 * nb);
    std::vector<int32_t> at(s.start.begin(), s.start.end() - 1);
    for (size_t b = 0; b < nb; ++b) {
      for (int end = 0; end < 2; ++end) {
        const size_t e = size_t(at[size_t(end ? io.bond_b[b] : io.bond_a[b])]++);
        s.ends[2 * e] = int32_t(b + size_t(4 * end) * nb);  // in the a end's centre, quat rows
        s.ends[2 * e + 1] = int32_t(b + size_t(end) * nb);  // in the a end's modulus row
      }
    }
  }
  s.voxel.resize(L.stiff() + L.n);
  double* g = s.voxel.data();
  const double* in = s.in.data();
  const auto row = [&](int slot) { return in + slot * nb; };
  static_assert(kCentreB == kCentreA + 4 && kQuatB == kQuatA + 4 && kStiffB == kStiffA + 1,
                "a bond's b end's inputs follow its a end's");
  const double* centre_rows[4] = {row(kCentreA), row(kCentreA + 1), row(kCentreA + 2),
                                  row(kCentreA + 3)};
  const double* quat_rows[4] = {row(kQuatA), row(kQuatA + 1), row(kQuatA + 2), row(kQuatA + 3)};
  const double* stiff_row = row(kStiffA);
  for (size_t i = 0; i < L.n; ++i) {
    double centre[4] = {0, 0, 0, 0}, quat[4] = {0, 0, 0, 0}, stiff = 0;
    if (voxel_in) {
      const auto update = [&](int slot) { return voxel_in[size_t(slot) * L.n + i]; };
      for (int c = 0; c < 4; ++c) centre[c] = update(kVPos + c), quat[c] = update(kVQuat + c);
      stiff = update(kVE);
    }
    for (int32_t e = s.start[i]; e < s.start[i + 1]; ++e) {
      const int32_t four = s.ends[2 * size_t(e)], one = s.ends[2 * size_t(e) + 1];
      for (int c = 0; c < 4; ++c) centre[c] += centre_rows[c][four], quat[c] += quat_rows[c][four];
      stiff += stiff_row[one];
    }
    for (int c = 0; c < 4; ++c) g[4 * i + c] = centre[c], g[L.quat() + 4 * i + c] = quat[c];
    g[L.stiff() + i] = stiff;
  }
  double g_damp = 0;
  for (size_t b = 0; b < nb; ++b) g_damp += row(kDamp)[b];
  for (size_t e = 0; e < L.stiff() + L.n; ++e)
    if (ids[e] >= 0) adj[ids[e]] += g[e];
  for (int j = 0; j < 9; ++j) {
    const double* g_prev = row(kPrev + j);
    if (prev_first >= 0) {
      double* to = adj + prev_first + int64_t(j) * int64_t(nb);
      for (size_t b = 0; b < nb; ++b) to[b] += g_prev[b];
      continue;
    }
    const int32_t* prev_ids = ids + L.prev(j);
    for (size_t b = 0; b < nb; ++b)
      if (prev_ids[b] >= 0) adj[prev_ids[b]] += g_prev[b];
  }
  if (ids[L.damp()] >= 0) adj[ids[L.damp()]] += g_damp;
}

}  // namespace plastivox::grad
