// The gradient of a life (gradient.hpp; docs/gradients.md says why it is built this way).
//
// The replica below is one step of Simulator::step2 (engine/core/src/simulator.cpp), stage by
// stage, with the engine's own kernel templates (bond_body.hpp, voxel_body.hpp,
// develop_body.hpp) instantiated on the recording type Adj (adj.hpp). The few lines of the
// stages that are not kernels (the voxel gather, self-collision, stable_dt, the controller's
// call: the sine here, the networks in network.hpp; time and settling) are written in the
// engine's order of operations, so the replica computes the engine's bits; gradient() checks
// it at every snapshot. When recording for gradient(), the bond stage, the gather and the
// voxel update run on doubles with the engine's kernel set and are kept as blocks with their
// own reverses (bond_adjoint.hpp, voxel_adjoint.hpp); g_reference_tape records them operation
// by operation instead.
#include "plastivox/grad/gradient.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <memory>
#include <numbers>
#include <stdexcept>
#include <string>
#include <utility>

#include "adj.hpp"
#include "adj_elementary.hpp"
#include "bond_adjoint.hpp"
#include "bond_body.hpp"
#include "develop_body.hpp"
#include "lanes.hpp"
#include "network.hpp"
#include "plastivox/simulator.hpp"
#include "plastivox/state.hpp"
#include "plastivox/task.hpp"
#include "voxel_adjoint.hpp"
#include "voxel_body.hpp"
#include "workspace.hpp"

namespace plastivox::grad {
namespace {

// The stages kept for their own reverses instead of recorded (bond_adjoint.hpp,
// voxel_adjoint.hpp): a block's outputs are leaves of the tape from node `first`.
// A step's bond stage: its outputs are kBondOutputs leaves a bond, in bond order, from node
// `first`; its record (keep_bond_stage) starts at `at` in Blocks::bond_values and bond_ids.
struct BondBlock {
  int64_t first;
  size_t at;
  bool all_valid;  // else its bonds' damping flags are kept in Blocks::bond_valid
};
struct VoxelBlock {
  int64_t first;
  VoxelArgs args;
};
struct GatherBlock {
  int64_t first;
  GatherArgs args;
};
struct Blocks {
  std::vector<BondBlock> bonds;
  std::vector<double> bond_values;
  std::vector<int32_t> bond_ids;
  std::vector<uint8_t> bond_valid;  // nb a stage without all_valid, in order
  std::vector<VoxelBlock> voxels;
  std::vector<GatherBlock> gathers;
  // Every block in the order recorded (its kind and its index in that kind's list).
  enum Kind : uint8_t { kBond, kVoxel, kGather };
  std::vector<std::pair<Kind, uint32_t>> order;
  void clear() {
    bonds.clear(), bond_values.clear(), bond_ids.clear(), bond_valid.clear();
    voxels.clear(), gathers.clear(), order.clear();
  }
};

// FNV-1a, for the event signature.
struct Fnv {
  uint64_t h = 1469598103934665603ull;
  void add(uint64_t v) {
    for (int k = 0; k < 8; ++k) h = (h ^ ((v >> (8 * k)) & 0xff)) * 1099511628211ull;
  }
};

// The watches (the floor's deepest penetration, the task's running values) are not physics:
// the replica does not keep them, and they are not compared.
bool is_watch(const char* name) {
  return !std::strcmp(name, "floor_deepest") || !std::strcmp(name, "floor_deep_most") ||
         !std::strcmp(name, "task_values") || !std::strcmp(name, "task_layout");
}

// The stable time step (compile.cpp, stable_dt: the exact model's rule), in the engine's order
// of operations, on recorded stiffness.
// With events, the voxels and bonds within the rule's 1e-9 of the stiffest are events: at a tie
// for the stiffest the time step has no derivative.
Adj stable_dt_adj(const Model& m, const double* E, Fnv* events = nullptr) {
  const int32_t* ids = g_tape ? g_tape->ids_of(E) : nullptr;
  const auto at = [&](int i) { return Adj(E[i], ids ? ids[i] : -1); };
  Adj e_top = 0.0;
  for (int i = 0; i < m.n; ++i) e_top = E[i] > e_top.v ? at(i) : e_top;
  const double near_top = e_top.v * (1.0 - 1e-9);
  Adj k_max = e_top * m.size;
  for (int i = 0; i < m.n; ++i) {
    if (!(E[i] >= near_top)) continue;
    if (events) events->add(i);
    for (int axis = 0; axis < 3; ++axis) {
      const int b = m.voxel_bonds[i][2 * axis + 1];
      if (b < 0) continue;
      const Adj ea = at(i), eb = at(m.bond_b[b]);
      if (eb.v >= near_top) {
        if (events) events->add(~uint64_t(b));
        const Adj k = 2.0 * ea * eb / (ea + eb) * m.size;
        k_max = k_max < k ? k : k_max;  // std::max
      }
    }
  }
  return m.def.dt_frac / (2.0 * std::numbers::pi * root(k_max / m.mass));
}

// One life's replica: a State (its values) and the node of every value of its floating-point
// rows, with the scratch arrays of a step.
class Replica {
 public:
  explicit Replica(const Model& m)
      : m_(m), s_(make_initial_state(m)), w_(m), nb_(m.bond_count()), net_(m) {
    for (const StateField& f : kStateFields) {
      const StateFieldBytes b = f.bytes(s_);
      rows_.push_back(b);
      ids_.emplace_back(b.kind == 'f' && b.value_bytes == sizeof(double) ? b.count : 0, -1);
    }
    // The engine's own views of the State's and the Workspace's arrays (bind_views); the bond
    // stage writes each bond's next deformation to the Workspace (bond_prev_next), which the
    // commit copies, as Simulator::step1 and step2 do.
    bind_views(m, s_, w_);
  }

  State& state() { return s_; }
  const BondKernelIo& bond_io() const { return w_.views.bond; }
  // Keep the bond stage (one block a step), the gather and the voxel update (one block a voxel
  // each) for their own reverses in `blocks`, or, given null, record them operation by
  // operation on the tape (the reference).
  void record_blocks_into(Blocks* blocks) { blocks_ = blocks; }
  const std::vector<StateFieldBytes>& rows() const { return rows_; }
  std::vector<std::vector<int32_t>>& ids() { return ids_; }

  // Every scratch array and State row as the tape's shadows (when recording).
  void register_arrays(Tape& t) {
    for (size_t r = 0; r < rows_.size(); ++r)
      if (!ids_[r].empty()) t.add_shadow(static_cast<const double*>(rows_[r].data), ids_[r].data());
    scratch_ids_.resize(kScratch);
    size_t k = 0;
    const auto add = [&](std::vector<double>& v) {
      std::vector<int32_t>& ids = scratch_ids_[k++];
      if (v.empty()) return;
      ids.assign(v.size(), -1);
      t.add_shadow(v.data(), ids.data());
    };
    Workspace& w = w_;
    add(w.centre_size);
    add(w.bond_strain);
    add(w.bond_stress);
    add(w.bond_energy);
    add(w.floor_normal);
    add(w.sqrt_e);
    for (int c = 0; c < 3; ++c) add(w.bond_out[c]), add(w.force[c]), add(w.moment[c]);
    for (int c = 0; c < 9; ++c) add(w.bond_prev_next[c]);
  }

  // The value and node of element k of a State row.
  Adj get(const double* row, size_t k = 0) const { return {row[k], node_at(row, k)}; }
  // Component k of voxel i's centre (the row's base address finds its shadow).
  Adj pos(int i, int k) const { return get(s_.pos.front().data(), 3 * size_t(i) + k); }

  // One step: Simulator::step2 with step1 before it. Returns false when the life went unstable.
  bool step(Fnv* events) {
    const Model& m = m_;
    State& s = s_;
    const Adj dt_old = get(&s.dt);
    // ---- step1: bonds, time step, gather, self-collision ----
    for (int i = 0; i < m.n; ++i) {
      const Adj r[4] = {pos(i, 0), pos(i, 1), pos(i, 2), get(s.size.data(), i)};
      store4(w_.centre_size.data(), i, r);
    }
    BondKernelIo& io = w_.views.bond;
    io.all_valid = std::memchr(s.bond_prev_valid.data(), 0, s.bond_prev_valid.size()) == nullptr;
    if (nb_ > 0) {
      const Adj damp = m.bond_damp / dt_old;
      int redo = 0;
      if (g_tape && blocks_)
        record_bonds(io, damp, redo);
      else
        for (int b = 0; b < nb_; ++b) bond_lanes<Adj, Adj>(io, b, m, damp, redo);
      if (redo > 0)
        throw std::domain_error("gradient: bond " + std::to_string(w_.redo[0]) + " at step " +
                                std::to_string(s.steps) +
                                " has a degenerate chord or a relative rotation near half a "
                                "turn (the scalar bond path), which is not differentiated yet");
    }
    const Adj dt_next = m.def.treatment != Treatment::kNone && s.time >= m.def.settle_time
                            ? stable_dt_adj(m, s.stiffness.data(), events)
                            : dt_old;
    if (g_tape && blocks_)
      record_gather();
    else
      gather();
    self_collisions(events);
    // ---- step2 ----
    put(&s.dt, 0, dt_next);
    for (int k = 0; k < 9; ++k)
      for (int b = 0; b < nb_; ++b)
        put(s.bond_prev[k].data(), b, load(w_.bond_prev_next[k].data(), b, Adj{}));
    std::memset(s.bond_prev_valid.data(), 1, s.bond_prev_valid.size());
    const Adj dt = dt_next;
    const Adj time = get(&s.time);
    if (s.steps % m.controller.every == 0 && m.controller.kind != ControllerKind::kSine) {
      g_branches = events ? &events->h : nullptr;  // the rate limit's clamps are events
      net_.act(s, w_, dt);                         // a network, from its sensors (network.hpp)
      g_branches = nullptr;
    } else if (s.steps % m.controller.every == 0 && !(s.time < m.def.settle_time)) {  // the sine
      if (m.def.act_frequency == 0) {
        for (int i = 0; i < m.robot_n; ++i) put(s.actuation.data(), i, Adj(0.0));
      } else {
        const Adj cycles = m.def.act_frequency * time;
        for (int i = 0; i < m.robot_n; ++i)
          sine_lanes<Adj, Adj>(m.phase.data(), s.actuation.data(), i, cycles);
      }
    }
    // integrate: floor, friction, Euler update
    if (events && m.flat_floor)
      for (int i = 0; i < m.n; ++i) events->add(0.5 * s.size[i] - s.pos[i].z() > 0.0 ? 1 : 0);
    double max_speed2 = 0.0;
    bool bad = false;
    if (g_tape && blocks_) {
      record_updates(dt, max_speed2, bad);
    } else {
      Adj top = 0.0;
      for (int i = 0; i < m.n; ++i)
        update_lanes<Adj, bool, Adj>(w_.views.voxel, w_.views.voxel_out, i, m, dt, top, bad);
      max_speed2 = top.v;
    }
    if (bad || max_speed2 > m.def.max_speed * m.def.max_speed) return false;
    if (events)
      for (int i = 0; i < m.n; ++i) events->add(s.static_friction[i]);
    // actuate (its clamps and development's gates, clamps and maxima are events)
    g_branches = events ? &events->h : nullptr;
    if (s.time < m.def.settle_time || m.act_amplitude_max == 0) {
      for (int i = 0; i < m.n; ++i) put(s.size.data(), i, Adj(m.size));
    } else {
      for (int i = 0; i < m.n; ++i)
        actuate_lanes<Adj>(s.stiffness.data(), s.actuation.data(), m.act_gain.data(), s.size.data(),
                           i, m);
    }
    // develop
    if (m.def.treatment != Treatment::kNone && !(s.time < m.def.settle_time)) {
      for (int i = 0; i < m.n; ++i)
        develop_lanes<Adj, Adj>(w_.views.develop, i, m, dt, !s.stim_ref_set);
      s.stim_ref_set = true;
    }
    g_branches = nullptr;
    put(&s.time, 0, time + dt);
    s.steps += 1;
    if (!s.settled && s.time > m.def.settle_time) {
      // center_of_mass(pos, robot_n): the sum in voxel order, then divided by the count
      Adj c[3] = {0.0, 0.0, 0.0};
      for (int i = 0; i < m.robot_n; ++i)
        for (int k = 0; k < 3; ++k) c[k] = c[k] + pos(i, k);
      for (int k = 0; k < 3; ++k)
        put(s.com_settled.data(), k, m.robot_n == 0 ? c[k] : c[k] / static_cast<double>(m.robot_n));
      s.settled = true;
      if (events) events->add(0x5e771ed00000000ull + s.steps);
    }
    if (s.time > m.def.duration) {
      s.status = SimStatus::kFinished;
      if (events) events->add(0xf1a1500000000000ull + s.steps);
    }
    return true;
  }

 private:
  // The bond stage on doubles (the engine's kernel set), its input arrays kept and its outputs
  // made leaves of the tape, which the sweep's block reverse gives their adjoints.
  void record_bonds(const BondKernelIo& io, Adj damp, int& redo) {
    Tape& t = *g_tape;
    const BondStageLayout L{size_t(m_.n), size_t(nb_)};
    const BondBlock stage{static_cast<int64_t>(t.nodes.size()), blocks_->bond_values.size(),
                          io.all_valid};
    blocks_->bond_values.resize(stage.at + L.size());
    blocks_->bond_ids.resize(stage.at + L.size());
    keep_bond_stage(io, L, damp.v, damp.id, blocks_->bond_values.data() + stage.at,
                    blocks_->bond_ids.data() + stage.at);
    if (!io.all_valid)
      blocks_->bond_valid.insert(blocks_->bond_valid.end(), io.prev_valid, io.prev_valid + nb_);
    blocks_->order.push_back({Blocks::kBond, uint32_t(blocks_->bonds.size())});
    blocks_->bonds.push_back(stage);
    t.nodes.resize(t.nodes.size() + size_t(kBondOutputs) * size_t(nb_), Node{-1, -1, 0.0, 0.0});
    int32_t* out_ids[3];
    int32_t* next_ids[9];
    for (int v = 0; v < 3; ++v) out_ids[v] = t.ids_of(io.out[v]);
    for (int j = 0; j < 9; ++j) next_ids[j] = t.ids_of(io.prev_next[j]);
    int32_t* strain_ids = t.ids_of(io.strain);
    int32_t* stress_ids = t.ids_of(io.stress);
    int32_t* energy_ids = io.energy ? t.ids_of(io.energy) : nullptr;
    // The engine's own kernel set: every lane width computes the same bits (bond_body.hpp).
    redo += kernels().bond(io, nb_, m_, damp.v);
    for (int b = 0; b < nb_; ++b) {
      const int32_t first = static_cast<int32_t>(stage.first + int64_t(kBondOutputs) * b);
      for (int v = 0; v < 3; ++v) {
        for (int c = 0; c < 3; ++c) out_ids[v][4 * size_t(b) + c] = first + kOut + 3 * v + c;
        out_ids[v][4 * size_t(b) + 3] = -1;
      }
      for (int j = 0; j < 9; ++j) next_ids[j][b] = first + kPrevNext + j;
      strain_ids[b] = first + kStrain;
      stress_ids[b] = first + kStress;
      if (energy_ids) energy_ids[b] = first + kEnergy;
    }
  }

  // The voxel update on doubles, as record_bonds does the bond stage.
  void record_updates(Adj dt, double& max_speed2, bool& bad) {
    Tape& t = *g_tape;
    const VoxelKernelIo& io = w_.views.voxel;
    const VoxelStateOut& st = w_.views.voxel_out;
    const VoxelReads reads = voxel_reads(io, dt.v, dt.id);
    int32_t* pos_ids = t.ids_of(st.pos);
    int32_t* lin_ids = t.ids_of(st.lin_mom);
    int32_t* ang_ids = t.ids_of(st.ang_mom);
    int32_t* quat_ids = t.ids_of(st.quat);
    int32_t* normal_ids = io.floor_normal ? t.ids_of(io.floor_normal) : nullptr;
    const size_t start = blocks_->voxels.size();
    for (int i = 0; i < m_.n; ++i) {
      blocks_->order.push_back({Blocks::kVoxel, uint32_t(blocks_->voxels.size())});
      blocks_->voxels.push_back({0, voxel_args(io, i, reads)});
    }
    // Updated in place by the engine's own kernel set, after every voxel's arguments are kept.
    const VoxelUpdateSummary summary = kernels().update(io, st, m_.n, m_, dt.v);
    max_speed2 = summary.max_speed2;
    bad = summary.non_finite;
    for (int i = 0; i < m_.n; ++i) {
      blocks_->voxels[start + size_t(i)].first = static_cast<int64_t>(t.nodes.size());
      const int32_t first = static_cast<int32_t>(t.nodes.size());
      t.nodes.resize(t.nodes.size() + kVoxelOutputs, Node{-1, -1, 0.0, 0.0});
      const size_t v = static_cast<size_t>(i);
      for (int c = 0; c < 3; ++c) {
        pos_ids[3 * v + c] = first + kVOutPos + c;
        lin_ids[3 * v + c] = first + kVOutLinMom + c;
        ang_ids[3 * v + c] = first + kVOutAngMom + c;
      }
      for (int c = 0; c < 4; ++c) quat_ids[4 * v + c] = first + kVOutQuat + c;
      if (normal_ids) normal_ids[v] = first + kVOutNormal;
    }
  }

  // The gather on doubles (the engine's kernel set), one block a voxel (voxel_adjoint.hpp).
  void record_gather() {
    Tape& t = *g_tape;
    const VoxelKernelIo& io = w_.views.voxel;
    kernels().gather(io, m_.n, m_);
    const int32_t* out_ids[3] = {t.ids_of(io.bond_out[0]), t.ids_of(io.bond_out[1]),
                                 t.ids_of(io.bond_out[2])};
    const int32_t* lin_ids = t.ids_of(io.lin_mom);
    const int32_t* stiff_ids = t.ids_of(io.stiff);
    int32_t* force_ids[3] = {t.ids_of(io.force[0]), t.ids_of(io.force[1]), t.ids_of(io.force[2])};
    int32_t* moment_ids[3] = {t.ids_of(io.moment[0]), t.ids_of(io.moment[1]),
                              t.ids_of(io.moment[2])};
    int32_t* sqrt_ids = t.ids_of(io.sqrt_e);
    const auto id = [](const int32_t* ids, size_t k) { return ids ? ids[k] : -1; };
    for (int i = 0; i < m_.n; ++i) {
      const size_t v = static_cast<size_t>(i);
      GatherArgs a;
      for (int slot = 0; slot < 6; ++slot) {
        const size_t b = 4 * static_cast<size_t>(io.slot_bond[slot][i]);
        for (int c = 0; c < 3; ++c) {
          a.id[kGSlots + 6 * slot + c] = id(out_ids[0], b + c);
          a.id[kGSlots + 6 * slot + 3 + c] = id(out_ids[slot & 1 ? 1 : 2], b + c);
        }
      }
      for (int c = 0; c < 3; ++c)
        a.lin_mom[c] = io.lin_mom[3 * v + c], a.id[kGLinMom + c] = id(lin_ids, 3 * v + c);
      a.e = io.stiff[v];
      a.id[kGE] = id(stiff_ids, v);
      const int32_t first = static_cast<int32_t>(t.nodes.size());
      blocks_->order.push_back({Blocks::kGather, uint32_t(blocks_->gathers.size())});
      blocks_->gathers.push_back({first, a});
      t.nodes.resize(t.nodes.size() + kGatherOutputs, Node{-1, -1, 0.0, 0.0});
      for (int c = 0; c < 3; ++c) {
        force_ids[c][v] = first + kGOutForce + c;
        moment_ids[c][v] = first + kGOutMoment + c;
      }
      sqrt_ids[v] = first + kGOutSqrtE;
    }
  }

  // gather_voxel (voxel_body.hpp) on Adj: bond forces and moments in slot order (the 4-double
  // records element by element, each as the vector sum computes it), slow damping, weight,
  // load; slow_damping_lanes itself is the kernel's.
  void gather() {
    const Model& m = m_;
    const VoxelKernelIo& io = w_.views.voxel;
    for (int i = 0; i < m.n; ++i) {
      const Adj coef = slow_damping_lanes<Adj>(io, i, m);
      Adj f[3] = {0.0, 0.0, 0.0}, mo[3] = {0.0, 0.0, 0.0};
      for (int slot = 0; slot < 6; ++slot) {
        const int b = 4 * io.slot_bond[slot][i];
        const bool plus = slot & 1;
        for (int c = 0; c < 3; ++c) {
          const Adj fa = load(io.bond_out[0], b + c, Adj{});
          const Adj mc = load(io.bond_out[plus ? 1 : 2], b + c, Adj{});
          f[c] = plus ? f[c] + fa : f[c] - fa;
          mo[c] = mo[c] + mc;
        }
      }
      for (int c = 0; c < 3; ++c) {
        const Adj fc = f[c] - coef * load(io.lin_mom, 3 * i + c, Adj{});
        put(io.force[c], i, (fc + m.weight[c]) + m.load[i][c]);
        put(io.moment[c], i, mo[c]);
      }
    }
  }

  // The pairs that can touch until the next refresh, in increasing order: those whose centres
  // were within reach when the list was made (anchor_ the centres then). A pair touching now is
  // closer than half_d (size_i + size_j) <= 2 half_d size_top_; while no voxel has moved more
  // than kDrift L from its anchor and no size has grown past size_top_, its centres were then
  // closer than that plus 2 kDrift L, which is reach. Otherwise the list is made again.
  void refresh_near_pairs(double half_d) {
    static constexpr double kDrift = 0.05;  // of a voxel's edge
    const Model& m = m_;
    const State& s = s_;
    const double drift = kDrift * m.size;
    double size_top = 0, moved2 = 0;
    for (int i = 0; i < m.n; ++i) size_top = std::max(size_top, s.size[i]);
    if (anchor_.size() == 3 * size_t(m.n))
      for (int i = 0; i < m.n && moved2 <= drift * drift; ++i) {
        const double* a = &anchor_[3 * size_t(i)];
        const double dx = s.pos[i].x() - a[0], dy = s.pos[i].y() - a[1], dz = s.pos[i].z() - a[2];
        moved2 = std::max(moved2, dx * dx + dy * dy + dz * dz);
      }
    if (anchor_.size() == 3 * size_t(m.n) && moved2 <= drift * drift && size_top <= size_top_)
      return;
    anchor_.resize(3 * size_t(m.n));
    for (int i = 0; i < m.n; ++i)
      for (int k = 0; k < 3; ++k) anchor_[3 * size_t(i) + k] = s.pos[i][k];
    size_top_ = size_top * (1 + 1e-3);
    const double reach = (2 * half_d * size_top_ + 2 * drift) * (1 + 1e-9);
    near_.clear();
    for (size_t p = 0; p < pair_a_.size(); ++p) {
      const Vec3 d = s.pos[pair_b_[p]] - s.pos[pair_a_[p]];
      if (d.squaredNorm() < reach * reach) near_.push_back(static_cast<int>(p));
    }
  }

  // apply_self_collisions (contacts.cpp) for the robot's own voxels: every pair of surface
  // voxels i < j not near each other in the bond graph, in (i, j) order, as the engine adds
  // the pairs its candidate lists find (they miss no contact, and the exact test is this one).
  void self_collisions(Fnv* events) {
    const Model& m = m_;
    if (!m.def.self_collision) return;
    const State& s = s_;
    const double half_d = 0.5 * m.def.contact_diameter;
    if (!paired_) {  // every pair that may touch, once: (i, j), i < j, in increasing order
      for (int i = 0; i < m.n; ++i) {
        if (!m.surface[i]) continue;
        const std::vector<int>& near = m.near_voxels[i];
        for (int j = i + 1; j < m.n; ++j)
          if (m.surface[j] && !std::binary_search(near.begin(), near.end(), j))
            pair_a_.push_back(i), pair_b_.push_back(j);
      }
      paired_ = true;
    }
    refresh_near_pairs(half_d);
    for (size_t c = 0; c < near_.size(); ++c) {
      const int i = pair_a_[near_[c]], j = pair_b_[near_[c]];
      const double dx = s.pos[j].x() - s.pos[i].x(), dy = s.pos[j].y() - s.pos[i].y();
      const double dz = s.pos[j].z() - s.pos[i].z();
      const double contact = half_d * (s.size[i] + s.size[j]);
      const double dist2 = dx * dx + dy * dy + dz * dz;
      if (dist2 >= contact * contact || dist2 == 0) continue;
      if (events) events->add((uint64_t(i) << 32) + uint64_t(j));
      Adj d[3];
      for (int k = 0; k < 3; ++k) d[k] = pos(j, k) - pos(i, k);
      const Adj cont = half_d * (get(s.size.data(), i) + get(s.size.data(), j));
      const Adj dist = root(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
      const Adj ei = get(s.stiffness.data(), i), ej = get(s.stiffness.data(), j);
      const Adj k = 2.0 * ei * ej / (ei + ej) * m.size;
      const Adj scale = k * (cont - dist) / dist;
      for (int c = 0; c < 3; ++c) {
        const Adj f = d[c] * scale;
        put(w_.force[c].data(), j, load(w_.force[c].data(), j, Adj{}) + f);
        put(w_.force[c].data(), i, load(w_.force[c].data(), i, Adj{}) - f);
      }
    }
  }

  static constexpr size_t kScratch = 6 + 3 * 3 + 9;  // the Workspace arrays with shadows
  const Model& m_;
  State s_;
  Workspace w_;
  int nb_;
  std::vector<StateFieldBytes> rows_;
  std::vector<std::vector<int32_t>> ids_;
  std::vector<std::vector<int32_t>> scratch_ids_;
  // The surface pairs self-collision tests (built on the first step), and those that may touch.
  std::vector<int> pair_a_, pair_b_, near_;
  bool paired_ = false;
  std::vector<double> anchor_;  // refresh_near_pairs'
  double size_top_ = 0;
  Blocks* blocks_ = nullptr;
  NetworkReplica net_;  // the neural controller's call
};

// A derivative for each row of kStateFields, zero, sized like the row for a floating-point row
// (as the replica gives them nodes) and empty for the others: what a loss adds its derivative
// to.
std::vector<std::vector<double>> zero_rows(const State& s) {
  std::vector<std::vector<double>> d;
  for (const StateField& f : kStateFields) {
    const StateFieldBytes b = f.bytes(s);
    d.emplace_back(b.kind == 'f' && b.value_bytes == sizeof(double) ? b.count : 0, 0.0);
  }
  return d;
}

bool physics_equal(const State& a, const State& b) {
  for (const StateField& f : kStateFields) {
    if (is_watch(f.name)) continue;
    const StateFieldBytes x = f.bytes(a), y = f.bytes(b);
    if (x.count != y.count ||
        (x.count > 0 && std::memcmp(x.data, y.data, x.count * x.value_bytes) != 0))
      return false;
  }
  return true;
}

// The parameters as leaves of a tape: one node per value of an array of the Model.
struct ParamLeaves {
  std::vector<int32_t> e0, phase, alpha, gain, weights;
  void make(Tape& t, const Model& m) {
    for (auto* v : {&e0, &phase, &alpha, &gain}) {
      v->resize(m.n);
      for (auto& id : *v) id = t.leaf();
    }
    t.add_shadow(m.e0.data(), e0.data());
    t.add_shadow(m.phase.data(), phase.data());
    t.add_shadow(m.alpha.data(), alpha.data());
    t.add_shadow(m.act_gain.data(), gain.data());
    weights.resize(m.controller.weights.size());
    for (auto& id : weights) id = t.leaf();
    if (!weights.empty()) t.add_shadow(m.controller.weights.data(), weights.data());
  }
};

// One block's reverse: from the adjoints of its outputs (nodes first..), those of its inputs.
template <int kIn, int kOut, class Args, class Reverse>
void block_reverse(const Args& args, size_t first, std::vector<double>& adj,
                   const ModelConstants& k, Reverse reverse) {
  const double* out = adj.data() + first;
  bool any = false;
  for (int o = 0; o < kOut; ++o) any = any || out[o] != 0;
  if (!any) return;
  double in[kIn] = {};
  reverse(args, k, out, in);
  for (int i = 0; i < kIn; ++i)
    if (args.id[i] >= 0) adj[args.id[i]] += in[i];
}

// The whole tape, with each block's reverse where its output leaves begin: by hand where the
// stage has one for the branch taken, else by the kernel recorded on a small tape.
void sweep(const Tape& t, std::vector<double>& adj, const Blocks& blocks, const Model& k,
           const BondKernelIo& io) {
  const BondStageLayout L{size_t(k.n), size_t(k.bond_count())};
  size_t valid_at = blocks.bond_valid.size();  // the flags are kept stage by stage, in order
  size_t end = t.nodes.size();
  for (size_t j = blocks.order.size(); j-- > 0;) {
    const auto [kind, index] = blocks.order[j];
    size_t first = 0;
    int outputs = 0;
    if (kind == Blocks::kBond)
      first = size_t(blocks.bonds[index].first), outputs = kBondOutputs * k.bond_count();
    else if (kind == Blocks::kVoxel)
      first = size_t(blocks.voxels[index].first), outputs = kVoxelOutputs;
    else
      first = size_t(blocks.gathers[index].first), outputs = kGatherOutputs;
    sweep_nodes(t, adj, first + outputs, end);
    end = first;
    if (kind == Blocks::kBond) {
      const BondBlock& stage = blocks.bonds[index];
      const uint8_t* valid = nullptr;
      if (!stage.all_valid) valid_at -= L.nb, valid = blocks.bond_valid.data() + valid_at;
      for (size_t b = L.nb; b-- > 0;) {
        const BondArgs a =
            bond_args(io, L, blocks.bond_values.data() + stage.at,
                      blocks.bond_ids.data() + stage.at, int(b), stage.all_valid || valid[b]);
        block_reverse<kBondInputs, kBondOutputs>(a, first + kBondOutputs * b, adj, k,
                                                 [](auto& a, auto& c, auto* o, auto* in) {
                                                   if (!bond_reverse(a, c, o, in))
                                                     bond_reverse_tape(a, c, o, in);
                                                 });
      }
    } else if (kind == Blocks::kVoxel)
      block_reverse<kVoxelInputs, kVoxelOutputs>(blocks.voxels[index].args, first, adj, k,
                                                 [](auto& a, auto& c, auto* o, auto* in) {
                                                   if (!voxel_reverse(a, c, o, in))
                                                     voxel_reverse_tape(a, c, o, in);
                                                 });
    else
      block_reverse<kGatherInputs, kGatherOutputs>(blocks.gathers[index].args, first, adj, k,
                                                   gather_reverse);
  }
  sweep_nodes(t, adj, 0, end);
}

// Bytes a tape node costs: the node and its adjoint.
constexpr double kNodeBytes = sizeof(Node) + sizeof(double);

// Bytes the blocks of a step cost (one a bond and one a voxel).
double block_bytes(const Model& m) {
  const BondStageLayout L{size_t(m.n), size_t(m.bond_count())};
  const double bond_stage = (sizeof(double) + sizeof(int32_t)) * double(L.size()) + double(L.nb);
  const double order = sizeof(Blocks::order[0]) * double(1 + 2 * m.n);
  return bond_stage + (sizeof(VoxelBlock) + sizeof(GatherBlock)) * double(m.n) + order;
}

// The nodes one step records: the first step of the life, and a fifth more for what the first
// step lacks (actuation and development start after settling; damping after the first step).
// Its bond blocks are one a bond.
size_t nodes_per_step(const Model& m) {
  Tape tape;
  Replica rep(m);
  Blocks blocks;
  rep.record_blocks_into(g_reference_tape ? nullptr : &blocks);
  g_tape = &tape;
  for (auto& row : rep.ids())
    for (auto& id : row) id = tape.leaf();
  ParamLeaves params;
  params.make(tape, m);
  rep.register_arrays(tape);
  const size_t leaves = tape.nodes.size();
  try {
    rep.step(nullptr);
  } catch (...) {
    g_tape = nullptr;
    throw;
  }
  g_tape = nullptr;
  return (tape.nodes.size() - leaves) * 6 / 5 + 1;
}

}  // namespace

std::string unsupported(const Model& m) {
  const std::string why = unsupported_life(m);
  return why.empty() ? why : std::string("the ") + to_string(m.def.task) + " task's life: " + why;
}

std::string unsupported_life(const Model& m) {
  if (m.def.bond_model != BondModel::kExact)
    return "only the exact bond model is differentiated yet (physics.bond_model)";
  if (m.terrain) return "environments (ground, boxes) are not differentiated yet";
  if (m.robot_n != m.n) return "free objects are not differentiated yet";
  return "";
}

ReplicaSummary replicate_life(const Model& m) {
  const std::string why = unsupported(m);
  if (!why.empty()) throw std::invalid_argument("gradient: " + why);
  g_tape = nullptr;
  Replica r(m);
  Fnv events;
  stable_dt_adj(m, m.e0.data(), &events);  // the initial time step's (make_initial_state)
  const TrajectoryLoss loss = task_loss(m);
  loss.see(r.state());
  while (r.state().status == SimStatus::kRunning) {
    if (!r.step(&events)) throw std::domain_error("gradient: the life went unstable");
    loss.see(r.state());
  }
  ReplicaSummary out;
  out.fitness = loss.value(r.state());
  if (loss.branches) events.add(loss.branches());
  out.events = events.h;
  out.steps = r.state().steps;
  return out;
}

Plan plan(const Model& m, const GradientOptions& options) {
  const std::string why = unsupported_life(m);
  if (!why.empty()) throw std::invalid_argument("gradient: " + why);
  if (options.checkpoint_every < 0)
    throw std::invalid_argument("gradient: checkpoint_every must be >= 0");
  Plan p;
  const State initial = make_initial_state(m);
  p.steps = std::ceil(m.def.duration / initial.dt) + 1;  // dt may change: an estimate
  p.snapshot_bytes = static_cast<double>(save_state(initial).size());
  const double step_nodes = static_cast<double>(nodes_per_step(m));
  p.tape_bytes_per_step = kNodeBytes * step_nodes + block_bytes(m);
  // N/K snapshots of S bytes beside K steps of tape of T bytes: K = sqrt(N S / T) makes the
  // two equal and their sum, 2 sqrt(N S T), the least.
  const double N = p.steps, S = p.snapshot_bytes, T = p.tape_bytes_per_step;
  const int K = options.checkpoint_every > 0
                    ? options.checkpoint_every
                    : static_cast<int>(std::clamp(std::round(std::sqrt(N * S / T)), 1.0, N));
  // A node is named by a 32-bit index: one segment's tape must stay below 2^31 nodes.
  const double segment_nodes = K * step_nodes * 1.25;
  if (segment_nodes >= 2147483647.0)
    throw std::invalid_argument("gradient: a segment of " + std::to_string(K) +
                                " steps records about " +
                                std::to_string(static_cast<long long>(segment_nodes)) +
                                " nodes, more than a tape holds (2^31): take snapshots more often "
                                "(checkpoint_every)");
  p.checkpoint_every = K;
  p.estimated_bytes = std::ceil(N / K) * S + K * T;
  if (options.memory_limit > 0 && p.estimated_bytes > options.memory_limit)
    throw std::invalid_argument(
        "gradient: the life needs about " + std::to_string(p.estimated_bytes / 1e6) + " MB (" +
        std::to_string(static_cast<long long>(N)) + " steps, a snapshot every " +
        std::to_string(K) + "), more than memory_limit " +
        std::to_string(options.memory_limit / 1e6) +
        " MB: shorten the life or raise the limit (multi-level checkpointing is not built yet)");
  return p;
}

Gradient gradient(const Model& m, const GradientOptions& options) {
  const std::string why = unsupported(m);
  if (!why.empty()) throw std::invalid_argument("gradient: " + why);
  return gradient_of(m, task_loss(m), options);
}

Gradient gradient_of(const Model& m, const FinalLoss& loss, const GradientOptions& options) {
  // A loss of the final state reads the state after the life's last step (its count known
  // once the forward life is over).
  auto last = std::make_shared<int64_t>(-1);
  TrajectoryLoss at_end;
  at_end.see = [](const State&) {};
  at_end.value = [&loss, last](const State& final) {
    *last = final.steps;
    std::vector<std::vector<double>> d = zero_rows(final);
    return loss(final, d);
  };
  at_end.adjoint = [&loss, last](const State& s, std::vector<std::vector<double>>& d) {
    if (s.steps != *last) return false;
    loss(s, d);
    return true;
  };
  return gradient_of(m, at_end, options);
}

Gradient gradient_of(const Model& m, const TrajectoryLoss& loss, const GradientOptions& options) {
  Gradient g;
  // ---- Forward: the engine's own life, with a snapshot every K steps ----
  const Plan p = plan(m, options);
  const int K = p.checkpoint_every;
  g.estimated_bytes = p.estimated_bytes;
  Simulator sim(m);
  std::vector<std::vector<uint8_t>> snaps;
  loss.see(sim.state());
  while (sim.state().status == SimStatus::kRunning) {
    if (sim.state().steps % K == 0) snaps.push_back(sim.save_state());
    sim.step();
    loss.see(sim.state());
  }
  if (sim.state().status != SimStatus::kFinished)
    throw std::domain_error("gradient: the life went unstable (" + sim.state().failure + ")");
  const SimResult result = sim.result();
  g.final_state_hash = result.final_state_hash;
  g.steps = sim.state().steps;
  g.checkpoint_every = K;
  g.checkpoints = snaps.size();
  for (const auto& s : snaps) g.checkpoint_bytes += s.size();

  // ---- Backward: segments last to first ----
  Replica rep(m);
  const auto& rows = rep.rows();
  std::vector<std::vector<double>> adj_state(rows.size());
  for (size_t r = 0; r < rows.size(); ++r) adj_state[r].assign(rep.ids()[r].size(), 0.0);
  g.fitness = loss.value(sim.state());
  // The loss's derivative at the replica's present state, kept as seeds of the nodes that hold
  // its values (injected when the segment's tape is swept, so the sweep carries them back from
  // that step on). A value without a node is a constant: its derivative goes nowhere.
  std::vector<std::vector<double>> d_loss = adj_state;
  std::vector<std::pair<int32_t, double>> seeds;
  const auto take_loss_adjoint = [&] {
    if (!loss.adjoint(rep.state(), d_loss)) return;
    const std::vector<std::vector<int32_t>>& ids = rep.ids();
    for (size_t r = 0; r < ids.size(); ++r) {
      if (d_loss[r].size() != ids[r].size())
        throw std::invalid_argument(std::string("gradient: the loss's derivative of row '") +
                                    kStateFields[r].name + "' has " +
                                    std::to_string(d_loss[r].size()) + " values, the row " +
                                    std::to_string(ids[r].size()));
      for (size_t k = 0; k < ids[r].size(); ++k) {
        if (d_loss[r][k] == 0) continue;
        if (ids[r][k] >= 0) seeds.emplace_back(ids[r][k], d_loss[r][k]);
        d_loss[r][k] = 0;
      }
    }
  };
  g.stiffness.assign(m.n, 0.0);
  g.phase.assign(m.n, 0.0);
  g.dev_rate.assign(m.n, 0.0);
  g.controller_weights.assign(m.controller.weights.size(), 0.0);
  std::vector<double> d_gain(m.n, 0.0);
  State next_check = sim.state();
  // One tape and one adjoint array for every segment: cleared, not freed, so that after the
  // first (the last segment of the life, the longest but for rounding) no page is faulted in
  // again.
  Tape tape;
  tape.nodes.reserve(
      static_cast<size_t>(1.25 * K * (p.tape_bytes_per_step - block_bytes(m)) / kNodeBytes));
  Blocks blocks;
  blocks.bond_values.reserve(static_cast<size_t>(K) *
                             BondStageLayout{size_t(m.n), size_t(m.bond_count())}.size());
  blocks.bond_ids.reserve(blocks.bond_values.capacity());
  blocks.voxels.reserve(static_cast<size_t>(K) * m.n);
  blocks.gathers.reserve(static_cast<size_t>(K) * m.n);
  blocks.order.reserve(static_cast<size_t>(K) * (1 + 2 * m.n));
  rep.record_blocks_into(g_reference_tape ? nullptr : &blocks);
  std::vector<double> adj;
  for (size_t seg = snaps.size(); seg-- > 0;) {
    tape.nodes.clear();
    tape.clear_shadows();
    blocks.clear();
    g_tape = &tape;
    restore_state(rep.state(), snaps[seg]);
    std::vector<std::vector<int32_t>>& ids = rep.ids();
    for (auto& row : ids)
      for (auto& id : row) id = tape.leaf();
    const std::vector<std::vector<int32_t>> start = ids;
    ParamLeaves params;
    params.make(tape, m);
    rep.register_arrays(tape);
    const int64_t end = seg + 1 < snaps.size() ? static_cast<int64_t>(seg + 1) * K : g.steps;
    seeds.clear();
    try {
      if (seg == 0) take_loss_adjoint();  // the initial state's
      while (rep.state().steps < end) {
        if (!rep.step(nullptr)) throw std::domain_error("gradient: the replica went unstable");
        take_loss_adjoint();
      }
    } catch (...) {
      g_tape = nullptr;
      throw;
    }
    g_tape = nullptr;
    if (seg + 1 < snaps.size()) restore_state(next_check, snaps[seg + 1]);
    if (!physics_equal(rep.state(), next_check))
      throw std::logic_error("gradient: the replica left the engine's life in steps " +
                             std::to_string(seg * K) + ".." + std::to_string(end) +
                             " (a stage differs from the engine's; docs/gradients.md)");
    g.peak_tape_nodes = std::max(g.peak_tape_nodes, tape.nodes.size());
    adj.assign(tape.nodes.size(), 0.0);
    for (size_t r = 0; r < ids.size(); ++r)
      for (size_t k = 0; k < ids[r].size(); ++k)
        if (ids[r][k] >= 0) adj[ids[r][k]] += adj_state[r][k];
    for (const auto& [id, v] : seeds) adj[id] += v;
    sweep(tape, adj, blocks, m, rep.bond_io());
    for (size_t r = 0; r < ids.size(); ++r)
      for (size_t k = 0; k < ids[r].size(); ++k) adj_state[r][k] = adj[start[r][k]];
    for (int i = 0; i < m.n; ++i) {
      g.stiffness[i] += adj[params.e0[i]];
      g.phase[i] += adj[params.phase[i]];
      g.dev_rate[i] += adj[params.alpha[i]];
      d_gain[i] += adj[params.gain[i]];
    }
    for (size_t k = 0; k < params.weights.size(); ++k)
      g.controller_weights[k] += adj[params.weights[k]];
  }
  // ---- The initial state's dependence on the parameters: stiffness = E0, dt = stable_dt(E0)
  {
    const size_t stiff_row = &state_field("stiffness") - kStateFields.data();
    const size_t dt_row = &state_field("dt") - kStateFields.data();
    for (int i = 0; i < m.n; ++i) g.stiffness[i] += adj_state[stiff_row][i];
    tape.nodes.clear();
    tape.clear_shadows();
    g_tape = &tape;
    std::vector<int32_t> e0_ids(m.n);
    for (auto& id : e0_ids) id = tape.leaf();
    tape.add_shadow(m.e0.data(), e0_ids.data());
    const Adj dt0 = stable_dt_adj(m, m.e0.data());
    g_tape = nullptr;
    adj.assign(tape.nodes.size(), 0.0);
    if (dt0.id >= 0) adj[dt0.id] = adj_state[dt_row][0];
    sweep(tape, adj, {}, m, rep.bond_io());
    for (int i = 0; i < m.n; ++i) g.stiffness[i] += adj[e0_ids[i]];
  }
  // The amplitude scales every gain alike: dF/dA = sum_i gain_i dF/dgain_i / A.
  if (!m.act_per_voxel && m.def.act_amplitude != 0) {
    for (int i = 0; i < m.n; ++i) g.amplitude += m.act_gain[i] * d_gain[i];
    g.amplitude /= m.def.act_amplitude;
  }
  // The initial state: positions (rest_pos) and momenta (zero), velocities being momenta / m.
  {
    const std::vector<double>& pos = adj_state[&state_field("pos") - kStateFields.data()];
    const std::vector<double>& mom = adj_state[&state_field("lin_mom") - kStateFields.data()];
    g.initial_position.assign(pos.begin(), pos.begin() + 3 * size_t(m.robot_n));
    g.initial_velocity.resize(3 * size_t(m.robot_n));
    for (size_t k = 0; k < g.initial_velocity.size(); ++k) g.initial_velocity[k] = mom[k] * m.mass;
  }
  g.stiffness.resize(m.robot_n);
  g.phase.resize(m.robot_n);
  g.dev_rate.resize(m.robot_n);
  return g;
}

}  // namespace plastivox::grad
