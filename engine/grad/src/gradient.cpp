// The gradient of a life (gradient.hpp; docs/gradients.md says why it is built this way).
//
// The replica below is one step of Simulator::step2 (engine/core/src/simulator.cpp), stage by
// stage, with the engine's own kernel templates (bond_body.hpp, voxel_body.hpp,
// develop_body.hpp) instantiated on the recording type Adj (adj.hpp). The few lines of the
// stages that are not kernels (the voxel gather, stable_dt, the controller's
// call: the sine here, the networks in network.hpp; time and settling) are written in the
// engine's order of operations, so the replica computes the engine's bits; gradient() checks
// it at every snapshot. When recording for gradient(), the bond stage, the gather and the
// voxel update run on doubles with the engine's kernel set and are kept as blocks with their
// own reverses (bond_adjoint.hpp, voxel_adjoint.hpp); g_reference_tape records them operation
// by operation instead.
#include "plastivox/grad/gradient.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <future>
#include <memory>
#include <numbers>
#include <stdexcept>
#include <string>
#include <utility>

#include "adj.hpp"
#include "adj_elementary.hpp"
#include "bond_adjoint.hpp"
#include "bond_body.hpp"
#include "collision_adjoint.hpp"
#include "develop_body.hpp"
#include "lanes.hpp"
#include "network.hpp"
#include "plastivox/base/parallel.hpp"
#include "plastivox/simulator.hpp"
#include "plastivox/state.hpp"
#include "plastivox/task.hpp"
#include "scalar_bond_adjoint.hpp"
#include "terrain_adjoint.hpp"
#include "voxel_adjoint.hpp"
#include "voxel_body.hpp"
#include "workspace.hpp"

namespace plastivox::grad {
namespace {

// The stages kept for their own reverses instead of recorded (bond_adjoint.hpp,
// voxel_adjoint.hpp): a block's outputs are leaves of the tape from node `first`.
// A step's bond stage: its next deformations are 9 leaves a bond, output by output (bond b's
// output o is node first + (o - kPrevNext) nb + b), then those of its strain, stress and energy
// something reads (bond_leaf_rows: output o's row r is nodes first + r nb on); its records'
// adjoints are those of the same step's gather's outputs, from node gather_first
// (bond_adjoint.hpp); its record (keep_bond_stage) starts at `at` in Blocks::bond_values and
// bond_ids. Its bonds that took the scalar path (every bond under Voxelyze 0.9, whose frame flags
// are kept from Blocks::bond_small[scalar_at]; under the exact model the scalar_count bonds listed
// from Blocks::bond_redo[scalar_at]) take that path's reverse (bond_adjoint.hpp, ScalarPathBonds).
// Which of a bond's strain, stress and energy a bond stage makes leaves of: what development
// reads (record_development's per_bond), or all three under a network, whose sensors read them.
BondLeafRows bond_leaf_rows(const Model& m) {
  BondLeafRows r;
  if (m.controller.kind != ControllerKind::kSine) {
    r.row[0] = 9, r.row[1] = 10, r.row[2] = 11;
    return r;
  }
  const bool split = m.def.axial_modulus == AxialModulus::kHarmonicMean;
  switch (m.def.treatment) {
    case Treatment::kStress:
      r.row[kStress - kStrain] = 9;
      break;
    case Treatment::kPressure:
      r.row[(split ? kStress : kStrain) - kStrain] = 9;
      break;
    case Treatment::kStrain:
      r.row[0] = 9;
      break;
    case Treatment::kStrainEnergy:
      r.row[kEnergy - kStrain] = 9;
      break;
    default:
      break;
  }
  return r;
}

struct BondBlock {
  int64_t first;
  size_t at;
  bool all_valid;  // else its bonds' damping flags are kept in Blocks::bond_valid
  size_t scalar_at = 0;
  int scalar_count = 0;
  int64_t gather_first = -1;
  // The previous step's stage's first leaf (its next deformations are this stage's previous
  // ones), or -1 at a segment's first step: then they are kept with their nodes.
  int64_t prev_first = -1;
};
// A step's voxel update: its outputs are kVoxelOutputs leaves a voxel, output by output (voxel
// i's output o is node first + o n + i); its record (keep_voxel_stage) starts at `at` in
// Blocks::voxel_values and voxel_ids, its flags at 2 n times its index in voxel_flags. With
// bond >= 0 it reads its moduli, centres, sizes and orientations from that bond block's record
// (the same step's) and keeps no rows of them (VoxelSharedInputs).
struct VoxelBlock {
  int64_t first;
  size_t at;
  int64_t bond = -1;
};
// A step's gather: its outputs are kGatherOutputs leaves a voxel, output by output; its record
// (keep_gather_stage) starts at `at` in Blocks::gather_values and `ids_at` in gather_ids.
struct GatherBlock {
  int64_t first;
  size_t at, ids_at;
};
// A step's development (Replica::record_development): its outputs are kDevelopOutputs leaves a
// voxel, output by output (kDevStimulus, kDevStiffness, kDevIntegral: voxel i's output o is
// node first + o n + i); its record starts at `at` in Blocks::develop_values and develop_ids,
// kDevelopRows rows of n each (DevelopRows). A bond-based stimulus read the per-bond row whose
// bond b is leaf bond_first + b (the same step's bond stage's); dt is the integral law's;
// e0_ids and alpha_ids are the parameters' leaves.
struct DevelopBlock {
  int64_t first;
  size_t at;
  int64_t bond_first = -1;
  Adj dt{};
  const int32_t* e0_ids = nullptr;
  const int32_t* alpha_ids = nullptr;
};
enum DevelopOutput : int {
  kDevStimulus = 0,
  kDevStiffness = 1,
  kDevIntegral = 2,
  kDevelopOutputs = 3
};
// A development block's record, row by row (V: double or const double, I: int32_t or const
// int32_t). Values: the law's value; the stimulus; the stimulus's partial derivative with
// respect to the modulus before the step (pressure's, under the voxel's own modulus); the
// factor of its bonds' values (1 or -1 for the one a stress or strain took, 0.25 for strain
// energy, pressure's -E / denominator). Ids: the modulus's node before the step; the law's other
// input (the reference's node under the rate law, the integral's before the step under the
// integral law); the stimulus's input (the bond a stress or strain took, or the node of a
// contact or kinetic stimulus; -1 for none); the rule's flags, kDevActive and kDevFree.
constexpr int kDevelopRows = 4;  // of each kind
template <class V, class I>
struct DevelopRows {
  V *law, *stim, *stim_de, *bond_factor;
  I *e_id, *law_in, *stim_in, *flags;
  DevelopRows(V* v, I* id, size_t n)
      : law(v),
        stim(v + n),
        stim_de(v + 2 * n),
        bond_factor(v + 3 * n),
        e_id(id),
        law_in(id + n),
        stim_in(id + 2 * n),
        flags(id + 3 * n) {}
};
constexpr int32_t kDevActive = 1;  // the gate let the voxel develop (its integral moved)
constexpr int32_t kDevFree = 2;    // its new modulus is the law's target, no clamp holding
// An allocator whose growth leaves the new elements unwritten (default-initialised, not
// zeroed): the blocks' records grow by a stage at a time and are written whole at once, and
// zeroing them first was a twentieth of a gradient's time.
template <class T>
struct Unwritten : std::allocator<T> {
  template <class U>
  struct rebind {
    using other = Unwritten<U>;
  };
  Unwritten() = default;
  template <class U>
  Unwritten(const Unwritten<U>&) {}  // NOLINT: as std::allocator's
  template <class U>
  void construct(U* p) {
    ::new (static_cast<void*>(p)) U;
  }
  template <class U, class... A>
  void construct(U* p, A&&... a) {
    ::new (static_cast<void*>(p)) U(std::forward<A>(a)...);
  }
};
template <class T>
using Record = std::vector<T, Unwritten<T>>;

struct Blocks {
  std::vector<BondBlock> bonds;
  Record<double> bond_values;
  Record<int32_t> bond_ids;
  std::vector<uint8_t> bond_valid;  // nb a stage without all_valid, in order
  Record<uint8_t> bond_small;       // Voxelyze 0.9: nb a stage, the frame flags it read
  std::vector<int32_t> bond_redo;   // the exact model: the bonds its kernel handed back
  std::vector<VoxelBlock> voxels;
  Record<double> voxel_values;
  Record<int32_t> voxel_ids;
  Record<uint8_t> voxel_flags;
  std::vector<GatherBlock> gathers;
  Record<double> gather_values;
  Record<int32_t> gather_ids;
  std::vector<DevelopBlock> develops;
  Record<double> develop_values;
  Record<int32_t> develop_ids;
  // Every block in the order recorded (its kind and its index in that kind's list).
  enum Kind : uint8_t { kBond, kVoxel, kGather, kDevelop };
  std::vector<std::pair<Kind, uint32_t>> order;
  void clear() {
    bonds.clear(), bond_values.clear(), bond_ids.clear(), bond_valid.clear();
    bond_small.clear(), bond_redo.clear();
    voxels.clear(), voxel_values.clear(), voxel_ids.clear(), voxel_flags.clear();
    gathers.clear(), gather_values.clear(), gather_ids.clear(), order.clear();
    develops.clear(), develop_values.clear(), develop_ids.clear();
  }
};

// FNV-1a, for the event signature.
struct Fnv {
  uint64_t h = 1469598103934665603ull;
  void add(uint64_t v) {
    for (int k = 0; k < 8; ++k) h = (h ^ ((v >> (8 * k)) & 0xff)) * 1099511628211ull;
  }
};

// The stable time step (compile.cpp, stable_dt: the exact model's rule), in the engine's order
// of operations, on recorded stiffness.
// With events, the voxels and bonds within the rule's 1e-9 of the stiffest are events: at a tie
// for the stiffest the time step has no derivative.
Adj stable_dt_adj(const Model& m, const double* E, Fnv* events = nullptr) {
  if (m.def.bond_model == BondModel::kVoxelyze09) {
    std::vector<int> near;
    const Adj dt = voxelyze_dt_adj(m, E, &near);
    if (events)
      for (int b : near) events->add(~uint64_t(b));
    return dt;
  }
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

// The most nodes Replica::record_development records a voxel: its block's kDevelopOutputs
// leaves, and a contact or kinetic stimulus's node of its inputs (at most 5: kinetic's six).
size_t develop_nodes(const Model& m) {
  if (m.def.treatment == Treatment::kNone) return 0;
  const bool node =
      m.def.treatment == Treatment::kContact || m.def.treatment == Treatment::kKinetic;
  return (kDevelopOutputs + (node ? 5 : 0)) * size_t(m.n);
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
  const DevelopIo& develop_io() const { return w_.views.develop; }
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
    copy_centres();
    BondKernelIo& io = w_.views.bond;
    io.all_valid = std::memchr(s.bond_prev_valid.data(), 0, s.bond_prev_valid.size()) == nullptr;
    const bool voxelyze = m.def.bond_model == BondModel::kVoxelyze09;
    if (nb_ > 0) {
      const Adj damp = m.bond_damp / dt_old;
      if (g_tape && blocks_) {
        // On doubles, kept as a block: the batched kernel and the scalar path, or the scalar
        // path alone under Voxelyze 0.9.
        record_bonds(io, damp);
      } else {
        bond_block_ = false;
        int redo = 0;
        if (!voxelyze)
          for (int b = 0; b < nb_; ++b) bond_lanes<Adj, Adj>(io, b, m, damp, redo);
        // Every bond under Voxelyze 0.9, else the bonds the kernel handed back, by the scalar
        // path recorded on the tape (their results replace the kernel's). Its branches are
        // events (Voxelyze 0.9's switch of frames, its first-order forms, its rotation vectors'
        // zero below about 2e-8 rad): scalar_bond_adjoint.hpp.
        g_branches = events ? &events->h : nullptr;
        scalar_bonds(m, w_.views, damp, voxelyze ? nullptr : w_.redo.data(), redo);
        g_branches = nullptr;
      }
      if (events && voxelyze)
        for (int b = 0; b < nb_; ++b) events->add(w_.bond_small_angle_next[b]);
    }
    const Adj dt_next = m.def.treatment != Treatment::kNone && s.time >= m.def.settle_time
                            ? stable_dt_adj(m, s.stiffness.data(), events)
                            : dt_old;
    // The gather's block takes its bonds' records as doubles: after a bond block only.
    if (g_tape && blocks_ && (bond_block_ || nb_ == 0))
      record_gather();
    else
      gather();
    collisions_.apply(m, s, w_, dt_next, events ? &events->h : nullptr);
    // ---- step2 ----
    put(&s.dt, 0, dt_next);
    if (nb_ > 0 && bond_block_ && g_tape && blocks_) {  // the next deformations are in the record
      const BondStageLayout L{size_t(m.n), size_t(nb_)};
      for (int k = 0; k < 9; ++k) {
        std::memcpy(s.bond_prev[k].data(), blocks_->bond_values.data() + next_at_ + L.prev(k),
                    size_t(nb_) * sizeof(double));
        std::memcpy(ids_of(s.bond_prev[k].data()), ids_of(w_.bond_prev_next[k].data()),
                    size_t(nb_) * sizeof(int32_t));
      }
    } else {
      for (int k = 0; k < 9; ++k) copy(s.bond_prev[k].data(), w_.bond_prev_next[k].data(), nb_);
    }
    if (m.def.bond_model == BondModel::kVoxelyze09)
      std::memcpy(s.bond_small_angle.data(), w_.bond_small_angle_next.data(), size_t(nb_));
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
        if (g_tape && blocks_)
          record_sine(cycles);
        else
          for (int i = 0; i < m.robot_n; ++i)
            sine_lanes<Adj, Adj>(m.phase.data(), s.actuation.data(), i, cycles);
      }
    }
    // integrate: floor, friction, Euler update
    if (events && m.flat_floor)
      for (int i = 0; i < m.n; ++i) events->add(0.5 * s.size[i] - s.pos[i].z() > 0.0 ? 1 : 0);
    // an environment's contacts before and after the update (terrain.cpp)
    if (m.terrain) terrain_.contacts(m, s, w_, dt, events ? &events->h : nullptr);
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
    if (m.terrain) terrain_.after_update(m, s, w_, events ? &events->h : nullptr);
    if (events && m.def.bond_model == BondModel::kVoxelyze09)  // its reset of small turns
      for (int i = 0; i < m.n; ++i) events->add(s.orient[i].vec().isZero(0.0) ? 1 : 0);
    if (bad || max_speed2 > m.def.max_speed * m.def.max_speed) return false;
    if (events)
      for (int i = 0; i < m.n; ++i) events->add(s.static_friction[i]);
    // actuate (its clamps and development's gates, clamps and maxima are events)
    g_branches = events ? &events->h : nullptr;
    if (s.time < m.def.settle_time || m.act_amplitude_max == 0) {
      for (int i = 0; i < m.n; ++i) put(s.size.data(), i, Adj(m.size));
    } else if (g_tape && blocks_) {
      record_actuation();
    } else {
      for (int i = 0; i < m.n; ++i)
        actuate_lanes<Adj>(s.stiffness.data(), s.actuation.data(), m.act_gain.data(), s.size.data(),
                           i, m);
    }
    // develop
    if (m.def.treatment != Treatment::kNone && !(s.time < m.def.settle_time)) {
      if (g_tape && blocks_)
        record_development(dt, !s.stim_ref_set);
      else
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
  // The nodes of an array (its shadow's), or none: when not recording, or a constant array.
  static int32_t* ids_of(const double* p) { return g_tape ? g_tape->ids_of(p) : nullptr; }
  // dst[k] = src[k] for k < count, values and nodes (as put(dst, k, load(src, k)), with each
  // shadow looked up once).
  static void copy(double* dst, const double* src, size_t count) {
    std::memcpy(dst, src, count * sizeof(double));
    const int32_t* from = ids_of(src);
    if (int32_t* to = ids_of(dst); to && from)
      std::memcpy(to, from, count * sizeof(int32_t));
    else if (to)
      std::fill(to, to + count, -1);
    else if (from && std::any_of(from, from + count, [](int32_t id) { return id >= 0; }))
      throw std::logic_error("gradient: a recorded value copied into an array without a shadow");
  }
  // Workspace::centre_size: each voxel's centre and actuated size as a record of 4.
  void copy_centres() {
    const double *centre = s_.pos.front().data(), *size = s_.size.data();
    double* cs = w_.centre_size.data();
    const int n = m_.n;  // locals: the stores could alias the members
    for (int i = 0; i < n; ++i) {
      for (int k = 0; k < 3; ++k) cs[4 * i + k] = centre[3 * i + k];
      cs[4 * i + 3] = size[i];
    }
    int32_t* to = ids_of(cs);
    if (!g_tape) return;
    if (!to) throw std::logic_error("gradient: the centres are recorded without a shadow");
    const int32_t *pos_ids = ids_of(centre), *size_ids = ids_of(size);
    for (int i = 0; i < n; ++i) {
      for (int k = 0; k < 3; ++k) to[4 * i + k] = pos_ids ? pos_ids[3 * i + k] : -1;
      to[4 * i + 3] = size_ids ? size_ids[i] : -1;
    }
  }

  // The bond stage on doubles (the engine's kernel set, and the scalar path for the bonds it
  // hands back; under Voxelyze 0.9 the scalar path for every bond), its input arrays kept and
  // its outputs made leaves of the tape, which the sweep's block reverse gives their adjoints.
  void record_bonds(const BondKernelIo& io, Adj damp) {
    Tape& t = *g_tape;
    const BondStageLayout L{size_t(m_.n), size_t(nb_)};
    // After the segment's first stage, this one's record starts where the last one's kernel
    // wrote its next deformations (next_at_, below).
    BondBlock stage{static_cast<int64_t>(t.nodes.size()),
                    blocks_->bonds.empty() ? blocks_->bond_values.size() : next_at_, io.all_valid};
    // The step's commit copied the previous stage's next deformations, leaves and all, into
    // bond_prev: this stage's reverse adds to them as rows (when the previous step's bond stage
    // was a block: else they are kept with their nodes).
    if (!blocks_->bonds.empty() && bond_block_) {
      stage.prev_first = blocks_->bonds.back().first;
      const int32_t* prev_ids = t.ids_of(io.prev[8]);
      if (!prev_ids || prev_ids[0] != stage.prev_first + 8 * nb_ ||
          prev_ids[nb_ - 1] != stage.prev_first + 9 * nb_ - 1)
        throw std::logic_error("gradient: a bond stage's previous deformations are not the last's");
    }
    // This stage's record and the next stage's previous deformations, which this stage's kernel
    // writes (the record's capacity is reserved for a segment: no pointer below moves).
    next_at_ = stage.at + L.size();
    blocks_->bond_values.resize(next_at_ + L.damp());
    blocks_->bond_ids.resize(next_at_ + L.damp());
    double* values = blocks_->bond_values.data();
    // When the previous step's stage was a block, its kernel wrote its next deformations, this
    // stage's previous ones, straight into this stage's record: they are not kept again.
    keep_bond_stage(io, L, damp.v, damp.id, stage.prev_first < 0, values + stage.at,
                    blocks_->bond_ids.data() + stage.at);
    if (!io.all_valid)
      blocks_->bond_valid.insert(blocks_->bond_valid.end(), io.prev_valid, io.prev_valid + nb_);
    const BondLeafRows rows = bond_leaf_rows(m_);
    t.unswept_leaves(size_t(rows.count()) * size_t(nb_));
    int32_t* next_ids[9];
    for (int j = 0; j < 9; ++j) next_ids[j] = t.ids_of(io.prev_next[j]);
    int32_t* strain_ids = t.ids_of(io.strain);
    int32_t* stress_ids = t.ids_of(io.stress);
    int32_t* energy_ids = io.energy ? t.ids_of(io.energy) : nullptr;
    // The kernel and the scalar path write the next deformations into the record (the commit
    // copies them to the State from there, their nodes from the Workspace's shadow).
    BondKernelIo& out = w_.views.bond;
    for (int j = 0; j < 9; ++j) out.prev_next[j] = values + next_at_ + L.prev(j);
    // The engine's own bond stage (run_bond_stage: every lane width computes the same bits),
    // and what its reverse needs to take the same branches: under Voxelyze 0.9 the frames the
    // stage reads (every bond takes the scalar path), else the bonds the batched kernel hands
    // back to the scalar path (rare: a degenerate chord, a relative rotation near half a turn).
    const bool voxelyze = m_.def.bond_model == BondModel::kVoxelyze09;
    if (voxelyze) {
      stage.scalar_at = blocks_->bond_small.size();
      const uint8_t* small = w_.views.small_angle_in_state;
      blocks_->bond_small.insert(blocks_->bond_small.end(), small, small + nb_);
    }
    const int redo = run_bond_stage(m_, w_.views, damp.v);
    if (!voxelyze) {
      stage.scalar_at = blocks_->bond_redo.size();
      stage.scalar_count = redo;
      blocks_->bond_redo.insert(blocks_->bond_redo.end(), io.redo, io.redo + redo);
    }
    for (int j = 0; j < 9; ++j) out.prev_next[j] = w_.bond_prev_next[j].data();
    // Output o of bond b is leaf first + (o - kPrevNext) nb + b: the reverse reads each output's
    // adjoints as a row, and the next step's reads of a deformation component are consecutive.
    // The records (io.out) have no nodes: the gather alone reads them, on doubles
    // (record_gather), and their adjoints are its outputs' (bond_adjoint.hpp).
    // (A local count: the stores of int32 ids could alias the member nb_, which kept these loops
    // scalar, reloading it each element.)
    const int nb = nb_;
    const int64_t first = stage.first;
    const auto leaf = [first, nb](int o, int b) {
      return static_cast<int32_t>(first + int64_t(o - kPrevNext) * nb + b);
    };
    // Strain, stress and energy: leaves where something reads them, else constants.
    int32_t* const stim_ids[3] = {strain_ids, stress_ids, energy_ids};
    for (int o = 0; o < 3; ++o) {
      if (!stim_ids[o]) continue;
      const int row = rows.row[o];
      for (int b = 0; b < nb; ++b) stim_ids[o][b] = row < 0 ? -1 : leaf(kPrevNext + row, b);
    }
    for (int j = 0; j < 9; ++j)
      for (int b = 0; b < nb; ++b) next_ids[j][b] = leaf(kPrevNext + j, b);
    blocks_->order.push_back({Blocks::kBond, uint32_t(blocks_->bonds.size())});
    blocks_->bonds.push_back(stage);
    bond_block_ = true;
  }

  // The sine controller's signals by the engine's kernel set (its bits at every lane width), each
  // recorded as one node on the cycles and the phase with the slope 2 pi cos(2 pi u), as
  // adj_elementary.hpp's sin_cycles, its cosine by the same kernel a quarter cycle on.
  void record_sine(Adj cycles) {
    const Model& m = m_;
    double* signal = s_.actuation.data();
    kernels().sine(m.phase.data(), signal, m.robot_n, cycles.v);
    slope_.resize(size_t(m.robot_n));
    kernels().sine(m.phase.data(), slope_.data(), m.robot_n, cycles.v + 0.25);
    int32_t* signal_ids = ids_of(signal);
    if (!signal_ids) throw std::logic_error("gradient: the signals are recorded without a shadow");
    const int32_t* phase_ids = ids_of(m.phase.data());
    for (int i = 0; i < m.robot_n; ++i) {
      const double d = 2.0 * std::numbers::pi * slope_[i];
      signal_ids[i] = record(cycles.id, d, phase_ids ? phase_ids[i] : -1, d);
    }
  }

  // Actuation by the engine's kernel set on doubles (its bits), each voxel's size recorded as two
  // nodes instead of the kernel's eight or so: size = L max(1 + ((A xi) g) w, least) with
  // xi = (xi_e_max - E) xi_inv_range + xi_base and w = min(u, wave_max), from E, the gain g and
  // the signal u (a clamp that holds gives a constant, as pick does on Adj).
  void record_actuation() {
    const Model& m = m_;
    State& s = s_;
    const double *E = s.stiffness.data(), *u = s.actuation.data(), *gain = m.act_gain.data();
    const int32_t *E_ids = ids_of(E), *u_ids = ids_of(u), *gain_ids = ids_of(gain);
    int32_t* size_ids = ids_of(s.size.data());
    if (!size_ids) throw std::logic_error("gradient: the sizes are recorded without a shadow");
    const auto id = [](const int32_t* ids, int i) { return ids ? ids[i] : -1; };
    kernels().actuate(E, u, gain, s.size.data(), m.n, m);  // the engine's sizes, lanes at a time
    for (int i = 0; i < m.n; ++i) {
      const double xi = (m.xi_e_max - E[i]) * m.xi_inv_range + m.xi_base;
      const bool clipped = u[i] > m.act_wave_max;
      const double w = clipped ? m.act_wave_max : u[i];
      const double a_xi = m.act_amplitude_xi * xi, a_xi_g = a_xi * gain[i];
      if (1.0 + a_xi_g * w < m.def.act_min_factor) {
        size_ids[i] = -1;
        continue;
      }
      const double d_xi = m.size * (m.act_amplitude_xi * (gain[i] * w));
      const int32_t eg =
          record(id(E_ids, i), -(d_xi * m.xi_inv_range), id(gain_ids, i), m.size * (a_xi * w));
      size_ids[i] = record(eg, 1.0, clipped ? -1 : id(u_ids, i), m.size * a_xi_g);
    }
  }

  // A node of sum_k d_k x_k over the inputs' nodes (-1: a constant, left out), made by record:
  // one node for two inputs, one more for each further input (a node takes two operands), so
  // at most count - 1, or 1 for a lone input. (record is called, not passed: an always_inline
  // function taken by pointer fails to compile at -O1.)
  static int32_t combine(const int32_t* id, const double* d, int count) {
    int32_t acc = -1, first = -1;
    double first_d = 0.0;
    for (int k = 0; k < count; ++k) {
      if (id[k] < 0) continue;
      if (first < 0) {
        first = id[k], first_d = d[k];
      } else {
        acc = acc < 0 ? record(first, first_d, id[k], d[k]) : record(acc, 1.0, id[k], d[k]);
      }
    }
    return acc >= 0 ? acc : first >= 0 ? record(first, first_d, -1, 0.0) : -1;
  }

  // Development (develop_lanes) by the engine's own kernel set on doubles, kept as a block
  // (DevelopBlock): each voxel's stimulus, integral and new modulus are leaves, and the block's
  // reverse (develop_stage_reverse) gives their inputs the partial derivatives of the rule. A
  // contact or kinetic stimulus, from the floor's force or the momenta, is recorded as a node of
  // its inputs first, and the block reads that node. The branches are the kernel's: the
  // stimulus's largest bond (stress, strain) is the one its comparisons kept, and a clamp that
  // holds, or a gated voxel, gives what pick gives on Adj (docs/gradients.md).
  void record_development(Adj dt, bool first) {
    const Model& m = m_;
    State& s = s_;
    const DevelopIo& io = w_.views.develop;
    const size_t n = size_t(m.n);
    // The moduli as they were (the kernel overwrites them; the integral and the reference it
    // writes are what the rule below reads).
    e_old_.assign(s.stiffness.begin(), s.stiffness.end());
    kernels().develop(io, m.n, m, dt.v, first);
    const auto need = [](int32_t* ids) {
      if (!ids) throw std::logic_error("gradient: a developing row is recorded without a shadow");
      return ids;
    };
    int32_t* stiff_ids = need(ids_of(s.stiffness.data()));
    int32_t* stimulus_ids = need(ids_of(s.stimulus.data()));
    int32_t* integral_ids = need(ids_of(s.stim_integral.data()));
    int32_t* ref_ids = need(ids_of(s.stim_ref.data()));
    Tape& t = *g_tape;
    const Treatment which = m.def.treatment;
    const bool split = m.def.axial_modulus == AxialModulus::kHarmonicMean;
    const double* per_bond = which == Treatment::kStress || (which == Treatment::kPressure && split)
                                 ? io.bond_stress
                             : which == Treatment::kStrainEnergy ? io.bond_energy
                                                                 : io.bond_strain;
    DevelopBlock stage{0, blocks_->develop_values.size()};
    stage.dt = dt;
    stage.e0_ids = ids_of(io.e0), stage.alpha_ids = ids_of(io.alpha);
    const bool by_bonds = which != Treatment::kContact && which != Treatment::kKinetic;
    if (by_bonds && nb_ > 0) {
      // The same step's bond stage's leaves, a run (record_bonds).
      const int32_t* bond_ids = ids_of(per_bond);
      if (!bond_ids || bond_ids[nb_ - 1] != bond_ids[0] + nb_ - 1)
        throw std::logic_error("gradient: development's stimulus is not its bond stage's");
      stage.bond_first = bond_ids[0];
    }
    blocks_->develop_values.resize(stage.at + kDevelopRows * n);
    blocks_->develop_ids.resize(stage.at + kDevelopRows * n);
    const auto [law_v, stim_v, de_v, factor_v, e_in, law_in, stim_in, flags] =
        DevelopRows<double, int32_t>(blocks_->develop_values.data() + stage.at,
                                     blocks_->develop_ids.data() + stage.at, n);
    // The stimulus's inputs (stimulus_lanes): a contact or kinetic stimulus's node goes on the
    // tape before the block's leaves.
    const int32_t *normal_ids = ids_of(io.floor_normal), *size_ids = ids_of(io.size);
    const int32_t *p_ids = ids_of(io.lin_mom), *h_ids = ids_of(io.ang_mom);
    const auto at = [](const int32_t* ids, size_t k) { return ids ? ids[k] : -1; };
    int32_t in[6];
    double d[6];
    for (size_t i = 0; i < n; ++i) {
      stim_v[i] = s.stimulus[i], e_in[i] = stiff_ids[i];
      de_v[i] = 0.0, factor_v[i] = 0.0, stim_in[i] = -1;
      if (which == Treatment::kStress || which == Treatment::kStrain) {
        double top = 0.0;  // the running maximum, a constant until a bond exceeds it
        for (int slot = 0; slot < 6; ++slot) {
          const int b = io.slot_bond[slot][i];
          const double x = per_bond[b];
          const double v = which == Treatment::kStrain && x < 0.0 ? -x : x;
          if (top < v) top = v, stim_in[i] = b, factor_v[i] = x < 0.0 ? -1.0 : 1.0;
        }
      } else if (which == Treatment::kStrainEnergy) {
        factor_v[i] = 0.25;
      } else if (which == Treatment::kPressure) {
        double sum = 0.0;
        for (int axis = 0; axis < 3; ++axis) {
          const int neg = io.slot_bond[2 * axis][i], pos = io.slot_bond[2 * axis + 1][i];
          const double a = per_bond[neg], b = per_bond[pos];
          sum = sum + (neg != io.no_bond && pos != io.no_bond ? 0.5 * (a + b) : a + b);
        }
        factor_v[i] = -(split ? 1.0 : e_old_[i]) / m.pressure_denominator;
        de_v[i] = split ? 0.0 : -sum / m.pressure_denominator;
      } else if (which == Treatment::kContact) {
        const double side = io.size[i], normal = io.floor_normal[i];
        in[0] = at(normal_ids, i), d[0] = 1.0 / (side * side);
        in[1] = at(size_ids, i), d[1] = -2.0 * normal / (side * side * side);
        stim_in[i] = combine(in, d, 2);
      } else {  // kinetic
        for (int c = 0; c < 3; ++c) {
          in[c] = at(p_ids, 3 * i + c), d[c] = m.inv_mass * io.lin_mom[3 * i + c] * m.inv_volume;
          in[3 + c] = at(h_ids, 3 * i + c);
          d[3 + c] = m.inv_inertia * io.ang_mom[3 * i + c] * m.inv_volume;
        }
        stim_in[i] = combine(in, d, 6);
      }
    }
    stage.first = t.unswept_leaves(kDevelopOutputs * n);
    const auto leaf = [&](int o, size_t i) {
      return static_cast<int32_t>(stage.first + int64_t(o * n + i));
    };
    // The rule (develop_lanes): the gate, the law's target, the two clamps. A gated voxel's rows
    // keep their nodes, as a held change keeps the modulus's.
    const bool integral = m.def.growth == GrowthModel::kIntegral;
    const double most = m.def.max_change_per_step;
    for (size_t i = 0; i < n; ++i) {
      stimulus_ids[i] = leaf(kDevStimulus, i);
      if (first) ref_ids[i] = stimulus_ids[i];
      law_in[i] = integral ? integral_ids[i] : ref_ids[i];
      flags[i] = 0;
      const double e = e_old_[i], alpha = io.alpha[i];
      if (!(e > m.gate) || alpha == 0.0) continue;
      flags[i] = kDevActive;
      // The integral the kernel wrote, old + stim dt, or the stimulus less its reference.
      const double law = integral ? s.stim_integral[i] : s.stimulus[i] - s.stim_ref[i];
      law_v[i] = law;
      if (integral) integral_ids[i] = leaf(kDevIntegral, i);
      const double change = io.e0[i] + alpha * law - e;
      const bool change_held = change < -most || most < change;
      const double next = e + (change < -most ? -most : most < change ? most : change);
      if (next < m.def.e_min || m.def.e_max < next) {
        stiff_ids[i] = -1;
      } else if (!change_held) {  // next = e + (target - e): its derivative is the target's
        stiff_ids[i] = leaf(kDevStiffness, i);
        flags[i] |= kDevFree;
      }
    }
    blocks_->order.push_back({Blocks::kDevelop, uint32_t(blocks_->develops.size())});
    blocks_->develops.push_back(stage);
  }

  // The voxel update on doubles, as record_bonds does the bond stage.
  void record_updates(Adj dt, double& max_speed2, bool& bad) {
    Tape& t = *g_tape;
    const VoxelKernelIo& io = w_.views.voxel;
    const VoxelStateOut& st = w_.views.voxel_out;
    const size_t n = size_t(m_.n);
    VoxelBlock stage{0, blocks_->voxel_values.size()};
    // After this step's bond block, the update reads the arrays it kept (the centres and sizes,
    // orientations and moduli): nothing between the two stages writes them.
    if (bond_block_ && nb_ > 0) {
      stage.bond = int64_t(blocks_->bonds.size()) - 1;
      const int32_t* kept = blocks_->bond_ids.data() + blocks_->bonds.back().at;
      const int32_t *pos_ids = t.ids_of(io.pos), *quat_ids = t.ids_of(io.quat);
      if (!pos_ids || !quat_ids || kept[0] != pos_ids[0] || kept[4 * n - 2] != pos_ids[3 * n - 1] ||
          kept[4 * n] != quat_ids[0] || kept[8 * n - 1] != quat_ids[4 * n - 1])
        throw std::logic_error("gradient: the update's centres are not its bond stage's");
    }
    blocks_->voxel_values.resize(stage.at + kVoxelInputs * n);
    blocks_->voxel_ids.resize(stage.at + kVoxelInputs * n);
    blocks_->voxel_flags.resize(blocks_->voxel_flags.size() + 2 * n);
    keep_voxel_stage(io, n, dt.v, dt.id, blocks_->voxel_values.data() + stage.at,
                     blocks_->voxel_ids.data() + stage.at,
                     blocks_->voxel_flags.data() + blocks_->voxel_flags.size() - 2 * n,
                     stage.bond >= 0);
    // Updated in place by the engine's own kernel set, after the inputs are kept.
    const VoxelUpdateSummary summary = kernels().update(io, st, m_.n, m_, dt.v);
    max_speed2 = summary.max_speed2;
    bad = summary.non_finite;
    stage.first = t.unswept_leaves(kVoxelOutputs * n);
    blocks_->order.push_back({Blocks::kVoxel, uint32_t(blocks_->voxels.size())});
    blocks_->voxels.push_back(stage);
    const auto leaf = [&](int o, size_t v) {
      return static_cast<int32_t>(stage.first + int64_t(o * n + v));
    };
    int32_t* pos_ids = t.ids_of(st.pos);
    int32_t* lin_ids = t.ids_of(st.lin_mom);
    int32_t* ang_ids = t.ids_of(st.ang_mom);
    int32_t* quat_ids = t.ids_of(st.quat);
    int32_t* normal_ids = io.floor_normal ? t.ids_of(io.floor_normal) : nullptr;
    for (size_t v = 0; v < n; ++v) {
      for (int c = 0; c < 3; ++c) {
        pos_ids[3 * v + c] = leaf(kVOutPos + c, v);
        lin_ids[3 * v + c] = leaf(kVOutLinMom + c, v);
        ang_ids[3 * v + c] = leaf(kVOutAngMom + c, v);
      }
      for (int c = 0; c < 4; ++c) quat_ids[4 * v + c] = leaf(kVOutQuat + c, v);
      if (normal_ids) normal_ids[v] = leaf(kVOutNormal, v);
    }
  }

  // The gather on doubles (the engine's kernel set), one block a step (voxel_adjoint.hpp).
  void record_gather() {
    Tape& t = *g_tape;
    const VoxelKernelIo& io = w_.views.voxel;
    const GatherStageLayout L{size_t(m_.n)};
    GatherBlock stage{0, blocks_->gather_values.size(), blocks_->gather_ids.size()};
    blocks_->gather_values.resize(stage.at + L.values());
    blocks_->gather_ids.resize(stage.ids_at + L.ids());
    keep_gather_stage(io, L, blocks_->gather_values.data() + stage.at,
                      blocks_->gather_ids.data() + stage.ids_at);
    kernels().gather(io, m_.n, m_);
    stage.first = t.unswept_leaves(kGatherOutputs * L.n);
    // The same step's bond stage takes its records' adjoints from this gather's outputs'.
    if (nb_ > 0) {
      if (blocks_->order.empty() || blocks_->order.back().first != Blocks::kBond)
        throw std::logic_error("gradient: a gather not after its step's bond stage");
      blocks_->bonds.back().gather_first = stage.first;
    }
    blocks_->order.push_back({Blocks::kGather, uint32_t(blocks_->gathers.size())});
    blocks_->gathers.push_back(stage);
    const auto leaf = [&](int o, size_t v) {
      return static_cast<int32_t>(stage.first + int64_t(o * L.n + v));
    };
    for (int c = 0; c < 3; ++c) {
      int32_t* force_ids = t.ids_of(io.force[c]);
      int32_t* moment_ids = t.ids_of(io.moment[c]);
      for (size_t v = 0; v < L.n; ++v)
        force_ids[v] = leaf(kGOutForce + c, v), moment_ids[v] = leaf(kGOutMoment + c, v);
    }
    int32_t* sqrt_ids = t.ids_of(io.sqrt_e);
    for (size_t v = 0; v < L.n; ++v) sqrt_ids[v] = leaf(kGOutSqrtE, v);
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

  static constexpr size_t kScratch = 6 + 3 * 3 + 9;  // the Workspace arrays with shadows
  const Model& m_;
  State s_;
  Workspace w_;
  int nb_;
  std::vector<StateFieldBytes> rows_;
  std::vector<std::vector<int32_t>> ids_;
  std::vector<std::vector<int32_t>> scratch_ids_;
  // Self-collision and the free objects' contacts (collision_adjoint.hpp).
  CollisionReplica collisions_;
  std::vector<double> slope_;  // record_sine's
  std::vector<double> e_old_;  // record_development's: the moduli before its kernel
  bool bond_block_ = false;    // the last step's bond stage was recorded as a block
  size_t next_at_ = 0;         // where in bond_values that stage wrote its next deformations
  Blocks* blocks_ = nullptr;
  NetworkReplica net_;      // the neural controller's call
  TerrainReplica terrain_;  // an environment's contacts
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

// Whether a state's physics (every row but the watches) is a snapshot's (save_state's bytes),
// read where it lies rather than restored.
bool physics_equal(const State& a, const std::vector<uint8_t>& snapshot) {
  const std::vector<fields::View> rows = fields::views(kStateFields, a);
  fields::Read read;
  try {
    read = fields::check(rows, snapshot);
  } catch (const std::invalid_argument&) {
    return false;  // another shape
  }
  for (size_t r = 0; r < rows.size(); ++r) {
    const StateFieldBytes& x = rows[r].bytes;
    if (!is_watch(rows[r].name) && x.count > 0 &&
        std::memcmp(x.data, read.from[r], x.count * x.value_bytes) != 0)
      return false;
  }
  return true;
}

// Makes each of `ids` a fresh leaf of t, left unwritten (Tape::unswept_leaves): a segment's
// first leaves, below every node the sweep reads (sweep's `begin`).
void number_leaves(Tape& t, std::vector<int32_t>& ids) {
  int32_t id = static_cast<int32_t>(t.unswept_leaves(ids.size()));
  for (int32_t& x : ids) x = id++;
}

// The parameters as leaves of a tape: one node per value of an array of the Model.
struct ParamLeaves {
  std::vector<int32_t> e0, phase, alpha, gain, weights;
  void make(Tape& t, const Model& m) {
    for (auto* v : {&e0, &phase, &alpha, &gain}) {
      v->resize(m.n);
      number_leaves(t, *v);
    }
    t.add_shadow(m.e0.data(), e0.data());
    t.add_shadow(m.phase.data(), phase.data());
    t.add_shadow(m.alpha.data(), alpha.data());
    t.add_shadow(m.act_gain.data(), gain.data());
    weights.resize(m.controller.weights.size());
    number_leaves(t, weights);
    if (!weights.empty()) t.add_shadow(m.controller.weights.data(), weights.data());
  }
};

// A development block's reverse (Replica::record_development): from its outputs' adjoints, its
// inputs'. Voxel by voxel: the new modulus's (where it is the law's target) to E0, the rate
// alpha and the law; the integral's to the integral before, the stimulus and dt; the law's,
// under the rate law, to the stimulus and its reference (nothing on the step that takes the
// reference: the law is then stim - stim); the stimulus's to its bonds' values (or its node)
// and, for pressure under the voxel's own modulus, to the modulus before the step.
void develop_stage_reverse(const DevelopBlock& stage, const double* value, const int32_t* id,
                           const DevelopIo& io, const Model& k, double* adj) {
  const size_t n = size_t(k.n);
  const auto [law_v, stim_v, de_v, factor_v, e_in, law_in, stim_in, flags] =
      DevelopRows<const double, const int32_t>(value, id, n);
  const double* g_out = adj + stage.first;
  const bool integral = k.def.growth == GrowthModel::kIntegral;
  const Treatment which = k.def.treatment;
  double* g_bond = stage.bond_first >= 0 ? adj + stage.bond_first : nullptr;
  double g_dt = 0.0;
  for (size_t i = 0; i < n; ++i) {
    double g_stim = g_out[kDevStimulus * n + i];
    if (flags[i] & kDevActive) {
      double g_law = 0.0;
      if (flags[i] & kDevFree) {
        const double g = g_out[kDevStiffness * n + i];
        if (stage.e0_ids) adj[stage.e0_ids[i]] += g;
        if (stage.alpha_ids) adj[stage.alpha_ids[i]] += g * law_v[i];
        g_law = g * io.alpha[i];
      }
      if (integral) {  // the integral, old + stim dt
        const double g = g_out[kDevIntegral * n + i] + g_law;
        if (law_in[i] >= 0) adj[law_in[i]] += g;
        g_stim += g * stage.dt.v;
        g_dt += g * stim_v[i];
      } else if (law_in[i] != int32_t(stage.first + int64_t(kDevStimulus * n + i))) {
        g_stim += g_law;  // stim - ref
        if (law_in[i] >= 0) adj[law_in[i]] -= g_law;
      }
    }
    if (g_stim == 0.0) continue;
    if (which == Treatment::kContact || which == Treatment::kKinetic) {
      if (stim_in[i] >= 0) adj[stim_in[i]] += g_stim;
      continue;
    }
    if (!g_bond) continue;
    if (which == Treatment::kStress || which == Treatment::kStrain) {
      if (stim_in[i] >= 0) g_bond[stim_in[i]] += factor_v[i] * g_stim;
      continue;
    }
    const double g = factor_v[i] * g_stim;
    for (int axis = 0; axis < 3; ++axis) {
      const int neg = io.slot_bond[2 * axis][i], pos = io.slot_bond[2 * axis + 1][i];
      // Pressure: each axis's mean over its two bonds, or its one bond's value.
      const double w =
          which == Treatment::kPressure && neg != io.no_bond && pos != io.no_bond ? 0.5 * g : g;
      if (neg != io.no_bond) g_bond[neg] += w;
      if (pos != io.no_bond) g_bond[pos] += w;
    }
    if (e_in[i] >= 0 && de_v[i] != 0.0) adj[e_in[i]] += de_v[i] * g_stim;
  }
  if (stage.dt.id >= 0) adj[stage.dt.id] += g_dt;
}

// The stages' reverses' scratch, kept from sweep to sweep (sized for a stage once).
struct SweepScratch {
  BondStageScratch bond;
  VoxelStageScratch voxel;
};

// The whole tape, with each block's reverse where its output leaves begin: by hand where the
// stage has one for the branch taken, else by the kernel recorded on a small tape. Nodes below
// `begin` are leaves, left unswept.
void sweep(const Tape& t, size_t begin, std::vector<double>& adj, const Blocks& blocks,
           const Model& k, const BondKernelIo& io, const DevelopIo& dev, SweepScratch& scratch) {
  const BondStageLayout L{size_t(k.n), size_t(k.bond_count())};
  const BondLeafRows leaf_rows = bond_leaf_rows(k);
  size_t valid_at = blocks.bond_valid.size();  // the flags are kept stage by stage, in order
  BondStageScratch& bond_scratch = scratch.bond;
  VoxelStageScratch& voxel_scratch = scratch.voxel;
  int64_t pending = -1;  // the bond block whose reverse takes voxel_scratch.in's shared rows
  size_t end = t.nodes.size();
  for (size_t j = blocks.order.size(); j-- > 0;) {
    const auto [kind, index] = blocks.order[j];
    size_t first = 0;
    int outputs = 0;
    if (kind == Blocks::kBond)
      first = size_t(blocks.bonds[index].first), outputs = leaf_rows.count() * k.bond_count();
    else if (kind == Blocks::kVoxel)
      first = size_t(blocks.voxels[index].first), outputs = kVoxelOutputs * k.n;
    else if (kind == Blocks::kGather)
      first = size_t(blocks.gathers[index].first), outputs = kGatherOutputs * k.n;
    else
      first = size_t(blocks.develops[index].first), outputs = kDevelopOutputs * k.n;
    sweep_nodes(t, adj, first + outputs, end);
    end = first;
    if (kind == Blocks::kBond) {
      const BondBlock& stage = blocks.bonds[index];
      static_assert(kGOutMoment == kGOutForce + 3, "bond_reverse reads force and moment rows");
      if (stage.gather_first < 0) throw std::logic_error("gradient: a bond stage without a gather");
      const uint8_t* valid = nullptr;
      if (!stage.all_valid) valid_at -= L.nb, valid = blocks.bond_valid.data() + valid_at;
      ScalarPathBonds scalar;
      if (k.def.bond_model == BondModel::kVoxelyze09)
        scalar.small = blocks.bond_small.data() + stage.scalar_at;
      else
        scalar.list = blocks.bond_redo.data() + stage.scalar_at, scalar.count = stage.scalar_count;
      bond_stage_reverse(io, L, blocks.bond_values.data() + stage.at,
                         blocks.bond_ids.data() + stage.at, valid, first, leaf_rows,
                         stage.prev_first, adj.data() + stage.gather_first + kGOutForce * k.n,
                         adj.data(), k, bond_scratch,
                         pending == int64_t(index) ? voxel_scratch.in.data() : nullptr, scalar);
      pending = -1;
    } else if (kind == Blocks::kVoxel) {
      const VoxelBlock& stage = blocks.voxels[index];
      VoxelSharedInputs shared;
      if (stage.bond >= 0) {
        const size_t at = blocks.bonds[size_t(stage.bond)].at;
        const double* v = blocks.bond_values.data() + at;
        const int32_t* id = blocks.bond_ids.data() + at;
        shared = {v, v + L.quat(), v + L.stiff(), id, id + L.quat(), id + L.stiff()};
      }
      if (pending >= 0) throw std::logic_error("gradient: an update's bond stage was not swept");
      voxel_stage_reverse(size_t(k.n), blocks.voxel_values.data() + stage.at,
                          blocks.voxel_ids.data() + stage.at,
                          blocks.voxel_flags.data() + 2 * index * k.n, first, adj.data(), k,
                          voxel_scratch, stage.bond >= 0 ? &shared : nullptr);
      pending = stage.bond;
    } else if (kind == Blocks::kDevelop) {
      const DevelopBlock& stage = blocks.develops[index];
      develop_stage_reverse(stage, blocks.develop_values.data() + stage.at,
                            blocks.develop_ids.data() + stage.at, dev, k, adj.data());
    } else {
      const GatherBlock& stage = blocks.gathers[index];
      gather_stage_reverse(GatherStageLayout{L.n}, blocks.gather_values.data() + stage.at,
                           blocks.gather_ids.data() + stage.ids_at, first, adj.data(), k);
    }
  }
  if (pending >= 0) throw std::logic_error("gradient: an update's bond stage was not swept");
  sweep_nodes(t, adj, begin, end);
}

// Bytes a tape node costs: the node and its adjoint.
constexpr double kNodeBytes = sizeof(Node) + sizeof(double);
// The snapshots' spacing for speed, and the memory it may take (plan()).
constexpr double kFastSegment = 16;
constexpr double kFastBudget = 1e9;

// Bytes the blocks of a step cost (the bond stage, the gather, the update and development: one
// each).
double block_bytes(const Model& m) {
  const BondStageLayout L{size_t(m.n), size_t(m.bond_count())};
  // The stage's record, its damping flags and (Voxelyze 0.9) its frame flags.
  const double bond_stage = (sizeof(double) + sizeof(int32_t)) * double(L.size()) +
                            double(L.nb) * (m.def.bond_model == BondModel::kVoxelyze09 ? 2 : 1);
  const double voxel_stage =
      (sizeof(double) + sizeof(int32_t)) * double(kVoxelInputs) * m.n + 2.0 * m.n;
  const GatherStageLayout G{L.n};
  const double gather_stage =
      sizeof(double) * double(G.values()) + sizeof(int32_t) * double(G.ids());
  const double develop_stage =
      m.def.treatment == Treatment::kNone
          ? 0.0
          : (sizeof(double) + sizeof(int32_t)) * double(kDevelopRows) * m.n + sizeof(DevelopBlock) +
                sizeof(Blocks::order[0]);
  return bond_stage + voxel_stage + gather_stage + develop_stage + sizeof(BondBlock) +
         sizeof(VoxelBlock) + sizeof(GatherBlock) + 3 * sizeof(Blocks::order[0]);
}

// The nodes one step records: the first step of the life, a fifth more for what the first step
// lacks (actuation starts after settling, damping after the first step), and development's
// most (Replica::record_development), which also starts after settling. Its bond blocks are
// one a bond.
size_t nodes_per_step(const Model& m) {
  Tape tape;
  Replica rep(m);
  Blocks blocks;
  rep.record_blocks_into(g_reference_tape ? nullptr : &blocks);
  g_tape = &tape;
  for (auto& row : rep.ids()) number_leaves(tape, row);
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
  return (tape.nodes.size() - leaves) * 6 / 5 + 1 + develop_nodes(m);
}

// One segment of the life recomputed for its reverse sweep: the replica that recorded it, its
// tape and blocks, the parameters' leaves, the nodes of its first state, the reverses' scratch
// and its nodes' adjoints (zeroed by the recording, so that on two threads the helper, not the
// sweep, pays for it). One thread reuses one for every segment (cleared, not freed, so that after
// the first, the longest but for rounding, no page is faulted in again); two alternate two. Not
// movable: the replica points at its blocks.
struct Segment {
  Segment(const Model& m, const Plan& p) : rep(m) {
    const int K = p.checkpoint_every;
    // The adjoints too: the last segment, recorded first, is the shortest, and an array grown
    // for a longer one would hold both for a moment.
    tape.nodes.reserve(static_cast<size_t>(p.segment_nodes));
    adj.reserve(static_cast<size_t>(p.segment_nodes));
    // K stages, and the next deformations the last one writes (record_bonds).
    const BondStageLayout L{size_t(m.n), size_t(m.bond_count())};
    blocks.bond_values.reserve(static_cast<size_t>(K) * L.size() + L.damp());
    blocks.bond_ids.reserve(blocks.bond_values.capacity());
    if (m.def.bond_model == BondModel::kVoxelyze09)
      blocks.bond_small.reserve(static_cast<size_t>(K) * size_t(m.bond_count()));
    blocks.voxels.reserve(static_cast<size_t>(K));
    blocks.voxel_values.reserve(static_cast<size_t>(K) * kVoxelInputs * m.n);
    blocks.voxel_ids.reserve(blocks.voxel_values.capacity());
    blocks.voxel_flags.reserve(static_cast<size_t>(K) * 2 * m.n);
    blocks.gathers.reserve(static_cast<size_t>(K));
    const GatherStageLayout G{size_t(m.n)};
    blocks.gather_values.reserve(static_cast<size_t>(K) * G.values());
    blocks.gather_ids.reserve(static_cast<size_t>(K) * G.ids());
    blocks.order.reserve(static_cast<size_t>(K) * 4);
    if (m.def.treatment != Treatment::kNone) {
      blocks.develops.reserve(static_cast<size_t>(K));
      blocks.develop_values.reserve(static_cast<size_t>(K) * kDevelopRows * m.n);
      blocks.develop_ids.reserve(blocks.develop_values.capacity());
    }
    rep.record_blocks_into(g_reference_tape ? nullptr : &blocks);
  }
  Segment(const Segment&) = delete;
  Segment& operator=(const Segment&) = delete;
  Replica rep;
  Tape tape;
  Blocks blocks;
  ParamLeaves params;
  std::vector<std::vector<int32_t>> start;
  // The first node the sweep reads: the first state's and parameters' are leaves below it.
  size_t swept_from = 0;
  SweepScratch scratch;
  std::vector<std::pair<int32_t, double>> seeds;  // the loss's derivatives at this segment's states
  std::vector<std::vector<double>> d_loss;        // the loss's scratch, zero between states
  std::vector<double> adj;
};

// Recomputes steps [first, end) from `snapshot` on the segment's tape, on the calling thread,
// and checks that the replica reaches `next` (the engine's state at `end`: the next snapshot,
// or the final state's) bit for bit.
void record_segment(Segment& sg, const Model& m, const TrajectoryLoss& loss,
                    const std::vector<uint8_t>& snapshot, const std::vector<uint8_t>& next,
                    int64_t first, int64_t end) {
  sg.tape.nodes.clear();
  sg.tape.clear_shadows();
  sg.blocks.clear();
  g_tape = &sg.tape;
  restore_state(sg.rep.state(), snapshot);
  std::vector<std::vector<int32_t>>& ids = sg.rep.ids();
  for (auto& row : ids) number_leaves(sg.tape, row);
  sg.start = ids;
  sg.params.make(sg.tape, m);
  sg.swept_from = sg.tape.nodes.size();
  sg.rep.register_arrays(sg.tape);
  sg.seeds.clear();
  // The loss's derivative at the replica's present state, kept as seeds of the nodes that hold
  // its values (injected when the segment's tape is swept, so the sweep carries them back from
  // that step on). A value without a node is a constant: its derivative goes nowhere.
  const auto take_loss_adjoint = [&] {
    if (sg.d_loss.empty()) sg.d_loss = zero_rows(sg.rep.state());
    if (!loss.adjoint(sg.rep.state(), sg.d_loss)) return;
    for (size_t r = 0; r < ids.size(); ++r) {
      if (sg.d_loss[r].size() != ids[r].size())
        throw std::invalid_argument(std::string("gradient: the loss's derivative of row '") +
                                    kStateFields[r].name + "' has " +
                                    std::to_string(sg.d_loss[r].size()) + " values, the row " +
                                    std::to_string(ids[r].size()));
      for (size_t k = 0; k < ids[r].size(); ++k) {
        if (sg.d_loss[r][k] == 0) continue;
        if (ids[r][k] >= 0) sg.seeds.emplace_back(ids[r][k], sg.d_loss[r][k]);
        sg.d_loss[r][k] = 0;
      }
    }
  };
  try {
    if (first == 0) take_loss_adjoint();  // the initial state's
    while (sg.rep.state().steps < end) {
      if (!sg.rep.step(nullptr)) throw std::domain_error("gradient: the replica went unstable");
      take_loss_adjoint();
    }
  } catch (...) {
    g_tape = nullptr;
    throw;
  }
  g_tape = nullptr;
  if (!physics_equal(sg.rep.state(), next))
    throw std::logic_error("gradient: the replica left the engine's life in steps " +
                           std::to_string(first) + ".." + std::to_string(end) +
                           " (a stage differs from the engine's; docs/gradients.md)");
  sg.adj.assign(sg.tape.nodes.size(), 0.0);
}

// What the reverse sweeps carry from segment to segment: the adjoint of the state between
// them (each row of kStateFields) and the parameters' sums, added segment by segment from
// the last to the first whatever the thread count.
struct Backward {
  std::vector<std::vector<double>> adj_state;
  std::vector<double> d_gain;
};

// The reverse sweep of a recorded segment: from the adjoint of its last state, that of its
// first and its parameters' share, added to g and b.
void sweep_segment(Segment& sg, const Model& m, Backward& b, Gradient& g) {
  const std::vector<std::vector<int32_t>>& ids = sg.rep.ids();
  std::vector<double>& adj = sg.adj;
  g.peak_tape_nodes = std::max(g.peak_tape_nodes, sg.tape.nodes.size());
  for (size_t r = 0; r < ids.size(); ++r)
    for (size_t k = 0; k < ids[r].size(); ++k)
      if (ids[r][k] >= 0) adj[ids[r][k]] += b.adj_state[r][k];
  for (const auto& [id, v] : sg.seeds) adj[id] += v;
  sweep(sg.tape, sg.swept_from, adj, sg.blocks, m, sg.rep.bond_io(), sg.rep.develop_io(),
        sg.scratch);
  for (size_t r = 0; r < ids.size(); ++r)
    for (size_t k = 0; k < ids[r].size(); ++k) b.adj_state[r][k] = adj[sg.start[r][k]];
  for (int i = 0; i < m.n; ++i) {
    g.stiffness[i] += adj[sg.params.e0[i]];
    g.phase[i] += adj[sg.params.phase[i]];
    g.dev_rate[i] += adj[sg.params.alpha[i]];
    b.d_gain[i] += adj[sg.params.gain[i]];
  }
  for (size_t k = 0; k < sg.params.weights.size(); ++k)
    g.controller_weights[k] += adj[sg.params.weights[k]];
}

}  // namespace

std::vector<double> gain_factor_derivative(const Gradient& g, const Model& m,
                                           const std::vector<double>& other) {
  std::vector<double> d = g.act_gain;
  if (!other.empty())
    for (size_t i = 0; i < d.size(); ++i) d[i] *= other[size_t(m.site[i])];
  return d;
}

bool is_watch(const char* name) {
  return !std::strcmp(name, "floor_deepest") || !std::strcmp(name, "floor_deep_most") ||
         !std::strcmp(name, "task_values") || !std::strcmp(name, "task_layout");
}

ReplicaSummary replicate_life(const Model& m) {
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

double Plan::bytes(double snapshots, int threads) const {
  return snapshots + threads * thread_bytes + 14 * snapshot_bytes;  // 14: plan() says why
}

Plan plan(const Model& m, const GradientOptions& options) {
  if (options.checkpoint_every < 0)
    throw std::invalid_argument("gradient: checkpoint_every must be >= 0");
  if (options.threads < 0) throw std::invalid_argument("gradient: threads must be >= 0");
  if (options.steps < -1 || options.steps == 0)
    throw std::invalid_argument("gradient: steps must be >= 1, or -1 for the whole life");
  Plan p;
  const State initial = make_initial_state(m);
  p.steps = std::ceil(m.def.duration / initial.dt) + 1;  // dt may change: an estimate
  if (options.steps > 0) p.steps = std::min(p.steps, static_cast<double>(options.steps));
  p.snapshot_bytes = static_cast<double>(save_state(initial).size());
  const double step_nodes = static_cast<double>(nodes_per_step(m));
  const double blocks = block_bytes(m);
  p.tape_bytes_per_step = kNodeBytes * step_nodes + blocks;
  // N/K snapshots of S bytes beside K steps of tape of T bytes: K = sqrt(N S / T) makes the
  // two equal and their sum, 2 sqrt(N S T), the least. Time asks for short segments: a
  // segment's tape and blocks are written as it is recomputed and read back as it is swept,
  // and the fewer its steps the more of them are still in the cache. So a longer life, whose
  // least-memory spacing is above kFastSegment steps, takes kFastSegment while its estimate
  // (on two threads, so that the spacing is the same on any) stays within kFastBudget bytes,
  // else the shortest spacing up to the least-memory one that does (docs/gradients.md, "The
  // snapshots' spacing").
  const double N = p.steps, S = p.snapshot_bytes, T = p.tape_bytes_per_step;
  // A thread keeps a segment (its tape's nodes and adjoints as reserved, a quarter above the
  // estimate, its blocks) and a replica (its workspace and its copies of the state: the rows'
  // node ids, the loss's scratch, the state it is checked against); beside them is the
  // engine's own life. Those copies were measured at 15 snapshots' bytes on one thread and 23
  // on two, on the walker and the 10^3 cube (tests/grad_memory_test.cpp); 14 + 10 a thread
  // are counted (Plan::bytes).
  const auto segment_nodes_of = [&](double k) { return std::floor(k * step_nodes * 1.25); };
  const auto thread_bytes_of = [&](double k) {
    return segment_nodes_of(k) * kNodeBytes + k * blocks + 10 * S;
  };
  int K = options.checkpoint_every;
  if (K <= 0) {
    const double least = std::clamp(std::round(std::sqrt(N * S / T)), 1.0, N);
    double k = std::min(least, kFastSegment);
    const auto two_threads = [&] {
      Plan at = p;
      at.thread_bytes = thread_bytes_of(k);
      return at.bytes(std::ceil(N / k) * S, 2);
    };
    while (k < least && two_threads() > kFastBudget) ++k;
    K = static_cast<int>(k);
  }
  // A segment's tape is reserved a quarter above the estimate (Segment), which a node names by
  // a 32-bit index: below 2^31 nodes.
  const double segment_nodes = segment_nodes_of(K);
  if (segment_nodes >= 2147483647.0)
    throw std::invalid_argument("gradient: a segment of " + std::to_string(K) +
                                " steps records about " +
                                std::to_string(static_cast<long long>(segment_nodes)) +
                                " nodes, more than a tape holds (2^31): take snapshots more often "
                                "(checkpoint_every)");
  p.checkpoint_every = K;
  p.segment_nodes = segment_nodes;
  // Two threads keep two segments' tapes (the sweep's and the recomputation's beside it); one
  // is taken instead when only the second tape would pass the limit. The spacing is the same
  // on any thread count, so are the bits.
  const double snapshots = std::ceil(N / K) * S;
  p.thread_bytes = thread_bytes_of(K);
  const bool within = !(options.memory_limit > 0) || p.bytes(snapshots, 2) <= options.memory_limit;
  p.threads =
      (options.threads > 0 ? options.threads : hardware_threads()) >= 2 && N > K && within ? 2 : 1;
  p.estimated_bytes = p.bytes(snapshots, p.threads);
  if (options.memory_limit > 0 && p.estimated_bytes > options.memory_limit)
    throw MemoryLimitError(
        "gradient: the life needs about " + std::to_string(p.estimated_bytes / 1e6) + " MB (" +
        std::to_string(static_cast<long long>(N)) + " steps, a snapshot every " +
        std::to_string(K) + "), more than memory_limit " +
        std::to_string(options.memory_limit / 1e6) +
        " MB: shorten the life or raise the limit (multi-level checkpointing is not built yet)");
  return p;
}

Gradient gradient(const Model& m, const GradientOptions& options) {
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
  const auto wall_start = std::chrono::steady_clock::now();
  Simulator sim(m);
  std::vector<std::vector<uint8_t>> snaps;
  loss.see(sim.state());
  const auto go_on = [&] {
    return sim.state().status == SimStatus::kRunning &&
           (options.steps < 0 || sim.state().steps < options.steps);
  };
  // The plan counts the steps from the initial time step; a body that stiffens as it develops
  // takes more, and so more snapshots. Under a memory limit, once they pass it, the backward
  // pass takes one thread (a segment's tape fewer) if that keeps within it, else the life stops
  // with one line: the limit is never passed silently.
  size_t snapshot_bytes = 0;
  int threads = p.threads;
  const auto over = [&](int t) {
    return options.memory_limit > 0 &&
           p.bytes(static_cast<double>(snapshot_bytes), t) > options.memory_limit;
  };
  while (go_on()) {
    if (sim.state().steps % K == 0) {
      snaps.push_back(sim.save_state());
      snapshot_bytes += snaps.back().size();
      if (over(threads)) threads = 1;
      if (over(threads))
        throw MemoryLimitError(
            "gradient: the life goes on past step " + std::to_string(sim.state().steps) +
            " (t = " + std::to_string(sim.state().time) + " s), beyond the " +
            std::to_string(static_cast<long long>(p.steps)) +
            " steps its initial time step gave (its time step shrank as it stiffened), and its "
            "snapshots pass memory_limit " +
            std::to_string(options.memory_limit / 1e6) +
            " MB: raise the limit or shorten the life");
    }
    sim.step();
    loss.see(sim.state());
  }
  const bool stopped = sim.state().status == SimStatus::kRunning;  // at options.steps
  // simulate()'s summary of the same life (it records no frames here), judged by the caller's
  // rules: a life that does not count has no backward pass.
  g.life = sim.result();
  g.life.wall_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  if (options.judge && !stopped) options.judge(g.life);
  g.final_state_hash = g.life.final_state_hash;
  g.steps = sim.state().steps;
  if (g.life.status != SimStatus::kFinished && !stopped) {
    if (!options.judge)
      throw std::domain_error("gradient: the life went unstable (" + sim.state().failure + ")");
    g.fitness = g.life.fitness;
    return g;
  }
  g.checkpoint_every = K;
  g.checkpoints = snaps.size();
  g.checkpoint_bytes = snapshot_bytes;

  // ---- Backward: segments last to first ----
  // On two threads, a helper recomputes segment k - 1 while this thread sweeps segment k; the
  // sweeps run in the same order on the same thread either way, so the sums are the same.
  g.threads = threads >= 2 && snaps.size() > 1 ? 2 : 1;
  Segment one(m, p);
  std::unique_ptr<Segment> two = g.threads == 2 ? std::make_unique<Segment>(m, p) : nullptr;
  const auto& rows = one.rep.rows();
  Backward b;
  b.adj_state.resize(rows.size());
  for (size_t r = 0; r < rows.size(); ++r) b.adj_state[r].assign(one.rep.ids()[r].size(), 0.0);
  g.fitness = loss.value(sim.state());
  g.stiffness.assign(m.n, 0.0);
  g.phase.assign(m.n, 0.0);
  g.dev_rate.assign(m.n, 0.0);
  g.controller_weights.assign(m.controller.weights.size(), 0.0);
  b.d_gain.assign(m.n, 0.0);
  const std::vector<uint8_t> final_state = sim.save_state();  // the last segment's check
  const auto record = [&](Segment& sg, size_t seg) {
    const bool last = seg + 1 == snaps.size();
    record_segment(sg, m, loss, snaps[seg], last ? final_state : snaps[seg + 1],
                   static_cast<int64_t>(seg) * K,
                   last ? g.steps : static_cast<int64_t>(seg + 1) * K);
  };
  Segment* now = &one;
  Segment* ahead = two.get();
  if (ahead) record(*now, snaps.size() - 1);
  for (size_t seg = snaps.size(); seg-- > 0;) {
    std::future<void> helper;  // waited for by its destructor, should the sweep throw
    if (!ahead)
      record(*now, seg);
    else if (seg > 0)
      helper = std::async(std::launch::async, [&, seg] { record(*ahead, seg - 1); });
    sweep_segment(*now, m, b, g);
    if (helper.valid()) helper.get();
    if (ahead) std::swap(now, ahead);
  }
  // ---- The initial state's dependence on the parameters: stiffness = E0, dt = stable_dt(E0)
  {
    const size_t stiff_row = &state_field("stiffness") - kStateFields.data();
    const size_t dt_row = &state_field("dt") - kStateFields.data();
    for (int i = 0; i < m.n; ++i) g.stiffness[i] += b.adj_state[stiff_row][i];
    Tape& tape = one.tape;
    tape.nodes.clear();
    tape.clear_shadows();
    g_tape = &tape;
    std::vector<int32_t> e0_ids(m.n);
    for (auto& id : e0_ids) id = tape.leaf();
    tape.add_shadow(m.e0.data(), e0_ids.data());
    const Adj dt0 = stable_dt_adj(m, m.e0.data());
    g_tape = nullptr;
    std::vector<double>& adj = one.adj;
    adj.assign(tape.nodes.size(), 0.0);
    if (dt0.id >= 0) adj[dt0.id] = b.adj_state[dt_row][0];
    sweep(tape, 0, adj, {}, m, one.rep.bond_io(), one.rep.develop_io(), one.scratch);
    for (int i = 0; i < m.n; ++i) g.stiffness[i] += adj[e0_ids[i]];
  }
  // The amplitude scales every gain alike: dF/dA = sum_i gain_i dF/dgain_i / A.
  if (!m.act_per_voxel && m.def.act_amplitude != 0) {
    for (int i = 0; i < m.n; ++i) g.amplitude += m.act_gain[i] * b.d_gain[i];
    g.amplitude /= m.def.act_amplitude;
  }
  // The initial state: positions (rest_pos) and momenta (zero), velocities being momenta / m.
  {
    const std::vector<double>& pos = b.adj_state[&state_field("pos") - kStateFields.data()];
    const std::vector<double>& mom = b.adj_state[&state_field("lin_mom") - kStateFields.data()];
    g.initial_position.assign(pos.begin(), pos.begin() + 3 * size_t(m.robot_n));
    g.initial_velocity.resize(3 * size_t(m.robot_n));
    for (size_t k = 0; k < g.initial_velocity.size(); ++k) g.initial_velocity[k] = mom[k] * m.mass;
    // Orientations (x, y, z, w), all the identity at the start: the unit quaternions' tangent
    // space there is x, y, z, so w's share (a change of length, which no turn makes) is
    // dropped. Angular velocities are angular momenta / the inertia.
    const std::vector<double>& q = b.adj_state[&state_field("orient") - kStateFields.data()];
    const std::vector<double>& ang = b.adj_state[&state_field("ang_mom") - kStateFields.data()];
    g.initial_orientation.assign(q.begin(), q.begin() + 4 * size_t(m.robot_n));
    for (int i = 0; i < m.robot_n; ++i) g.initial_orientation[4 * size_t(i) + 3] = 0.0;
    g.initial_angular_velocity.resize(3 * size_t(m.robot_n));
    for (size_t k = 0; k < g.initial_angular_velocity.size(); ++k)
      g.initial_angular_velocity[k] = ang[k] * m.inertia;
  }
  g.act_gain.assign(b.d_gain.begin(), b.d_gain.begin() + m.robot_n);
  g.stiffness.resize(m.robot_n);
  g.phase.resize(m.robot_n);
  g.dev_rate.resize(m.robot_n);
  return g;
}

}  // namespace plastivox::grad
