#include "plastivox/state.hpp"

#include <cstring>
#include <stdexcept>
#include <type_traits>

#include "plastivox/base/hash.hpp"

namespace plastivox {

State make_initial_state(const Model& m) {
  State s;
  s.pos = m.rest_pos;
  s.orient.assign(m.n, Quat::Identity());
  s.lin_mom.assign(m.n, Vec3::Zero());
  s.ang_mom.assign(m.n, Vec3::Zero());
  s.stiffness = m.e0;
  s.size.assign(m.n, m.size);  // no actuation before the first step
  s.stimulus.assign(m.n, 0.0);
  s.stim_integral.assign(m.n, 0.0);
  s.stim_ref.assign(m.n, 0.0);
  s.static_friction.assign(m.n, 0);
  for (auto& component : s.bond_prev) component.assign(m.bond_count(), 0.0);
  s.bond_prev_valid.assign(m.bond_count(), 0);
  // Voxelyze 0.9 starts every bond in its small-angle frame.
  s.bond_small_angle.assign(m.bond_count(), m.def.bond_model == BondModel::kVoxelyze09 ? 1 : 0);
  s.dt = stable_dt(m, s.stiffness);
  return s;
}

namespace {

template <class T>
constexpr char kind_of() {
  if constexpr (std::is_same_v<T, bool>) return 'b';
  if constexpr (std::is_floating_point_v<T>) return 'f';
  if constexpr (std::is_enum_v<T> || std::is_signed_v<T>) return 'i';
  return 'u';
}

template <class T>
StateFieldBytes one(const T& v) {
  return {&v, 1, sizeof v, kind_of<T>(), 1};
}
template <class T>
StateFieldBytes per_value(const std::vector<T>& v) {
  return {v.data(), v.size(), sizeof(T), kind_of<T>(), 1};
}
// Eigen's fixed-size vectors and quaternions are plain arrays of doubles, so a vector of
// them is one flat array of doubles.
template <class T, int kComponents>
StateFieldBytes components(const std::vector<T>& v) {
  static_assert(sizeof(T) == kComponents * sizeof(double));
  return {v.data(), v.size() * kComponents, sizeof(double), 'f', kComponents};
}
StateFieldBytes bond_prev(const State& s, int k) {
  return per_value(s.bond_prev[static_cast<size_t>(k)]);
}

}  // namespace

const std::vector<StateField> kStateFields = {
    {"time", "1", "s", "-", "simulated time", [](const State& s) { return one(s.time); }},
    {"steps", "1", "1", "-", "steps taken", [](const State& s) { return one(s.steps); }},
    {"dt", "1", "s", "-", "the next step's length (follows stiffness)",
     [](const State& s) { return one(s.dt); }},
    {"status", "1", "-", "-", "running, finished or unstable (SimStatus)",
     [](const State& s) { return one(s.status); }},
    {"pos", "n x 3", "m", "world", "voxel centre",
     [](const State& s) { return components<Vec3, 3>(s.pos); }},
    {"orient", "n x 4", "1", "body to world", "voxel rotation (x, y, z, w)",
     [](const State& s) { return components<Quat, 4>(s.orient); }},
    {"lin_mom", "n x 3", "kg m/s", "world", "linear momentum",
     [](const State& s) { return components<Vec3, 3>(s.lin_mom); }},
    {"ang_mom", "n x 3", "kg m^2/s", "world", "angular momentum",
     [](const State& s) { return components<Vec3, 3>(s.ang_mom); }},
    {"stiffness", "n", "Pa", "-", "current Young's modulus",
     [](const State& s) { return per_value(s.stiffness); }},
    {"size", "n", "m", "-", "actuated edge length for the next step",
     [](const State& s) { return per_value(s.size); }},
    {"stimulus", "n", "Pa", "-", "the treatment's last stimulus",
     [](const State& s) { return per_value(s.stimulus); }},
    {"stim_integral", "n", "Pa s", "-", "integral of the stimulus since settling",
     [](const State& s) { return per_value(s.stim_integral); }},
    {"stim_ref", "n", "Pa", "-", "stimulus at the end of settling (rate model)",
     [](const State& s) { return per_value(s.stim_ref); }},
    {"stim_ref_set", "1", "-", "-", "stim_ref has been taken",
     [](const State& s) { return one(s.stim_ref_set); }},
    {"static_friction", "n", "-", "-", "1 while held by floor static friction",
     [](const State& s) { return per_value(s.static_friction); }},
    {"bond_prev_x", "bonds", "m", "bond", "previous deformation: b's offset, x",
     [](const State& s) { return bond_prev(s, 0); }},
    {"bond_prev_y", "bonds", "m", "bond", "previous deformation: b's offset, y",
     [](const State& s) { return bond_prev(s, 1); }},
    {"bond_prev_z", "bonds", "m", "bond", "previous deformation: b's offset, z",
     [](const State& s) { return bond_prev(s, 2); }},
    {"bond_prev_rot_a_x", "bonds", "rad", "bond", "previous rotation vector of a, x",
     [](const State& s) { return bond_prev(s, 3); }},
    {"bond_prev_rot_a_y", "bonds", "rad", "bond", "previous rotation vector of a, y",
     [](const State& s) { return bond_prev(s, 4); }},
    {"bond_prev_rot_a_z", "bonds", "rad", "bond", "previous rotation vector of a, z",
     [](const State& s) { return bond_prev(s, 5); }},
    {"bond_prev_rot_b_x", "bonds", "rad", "bond", "previous rotation vector of b, x",
     [](const State& s) { return bond_prev(s, 6); }},
    {"bond_prev_rot_b_y", "bonds", "rad", "bond", "previous rotation vector of b, y",
     [](const State& s) { return bond_prev(s, 7); }},
    {"bond_prev_rot_b_z", "bonds", "rad", "bond", "previous rotation vector of b, z",
     [](const State& s) { return bond_prev(s, 8); }},
    {"bond_prev_valid", "bonds", "-", "-", "1 once the previous deformation is recorded",
     [](const State& s) { return per_value(s.bond_prev_valid); }},
    {"bond_small_angle", "bonds", "-", "-", "1 while the bond uses the small-angle frame",
     [](const State& s) { return per_value(s.bond_small_angle); }},
    {"com_settled", "3", "m", "world", "centre of mass when settling ended",
     [](const State& s) {
       return StateFieldBytes{s.com_settled.data(), 3, sizeof(double), 'f', 3};
     }},
    {"settled", "1", "-", "-", "time has passed the settle time",
     [](const State& s) { return one(s.settled); }},
};

uint64_t state_hash(const State& s) {
  Fnv1a64 f;
  for (const StateField& field : kStateFields) {
    const StateFieldBytes b = field.bytes(s);
    const uint64_t count = b.count;
    f.bytes(&count, sizeof count);
    f.bytes(b.data, b.count * b.value_bytes);
  }
  return f.value();
}

namespace {

constexpr char kSnapshotMagic[8] = {'P', 'V', 'X', 'S', 'T', 'A', 'T', '1'};

void put(std::vector<uint8_t>& out, const void* data, size_t bytes) {
  // resize and copy, not insert: GCC 12 sees a false overflow in an inlined insert into the
  // empty vector (-Wstringop-overflow) when this file shares a unity batch.
  if (bytes == 0) return;
  const size_t at = out.size();
  out.resize(at + bytes);
  std::memcpy(out.data() + at, data, bytes);
}
void put_u64(std::vector<uint8_t>& out, uint64_t v) {
  put(out, &v, sizeof v);
}

// Reads a snapshot front to back; every read checks there are bytes left.
struct SnapshotReader {
  const std::vector<uint8_t>& in;
  size_t at = 0;

  const uint8_t* take(size_t bytes, const std::string& what) {
    if (bytes > in.size() - at)
      throw std::invalid_argument("state snapshot: ends inside " + what + " (" +
                                  std::to_string(in.size()) + " bytes; truncated or damaged)");
    const uint8_t* p = in.data() + at;
    at += bytes;
    return p;
  }
  uint64_t u64(const std::string& what) {
    uint64_t v;
    std::memcpy(&v, take(sizeof v, what), sizeof v);
    return v;
  }
};

}  // namespace

std::vector<uint8_t> save_state(const State& s) {
  std::vector<uint8_t> out;
  put(out, kSnapshotMagic, sizeof kSnapshotMagic);
  put_u64(out, kStateFields.size());
  for (const StateField& field : kStateFields) {
    const StateFieldBytes b = field.bytes(s);
    put_u64(out, b.count);
    put_u64(out, b.value_bytes);
    put(out, b.data, b.count * b.value_bytes);
  }
  put_u64(out, s.failure.size());
  put(out, s.failure.data(), s.failure.size());
  return out;
}

void restore_state(State& s, const std::vector<uint8_t>& snapshot) {
  // Every check first, so a refused snapshot leaves the state as it was.
  SnapshotReader r{snapshot};
  if (std::memcmp(r.take(sizeof kSnapshotMagic, "the header"), kSnapshotMagic,
                  sizeof kSnapshotMagic) != 0)
    throw std::invalid_argument("state snapshot: not a plastivox state (header differs)");
  const uint64_t fields = r.u64("the header");
  if (fields != kStateFields.size())
    throw std::invalid_argument("state snapshot: holds " + std::to_string(fields) +
                                " fields, this build's state " +
                                std::to_string(kStateFields.size()));
  std::vector<const uint8_t*> from;
  for (const StateField& field : kStateFields) {
    const std::string name = std::string("field '") + field.name + "'";
    const StateFieldBytes b = field.bytes(s);
    const uint64_t count = r.u64(name), value_bytes = r.u64(name);
    if (count != b.count || value_bytes != b.value_bytes)
      throw std::invalid_argument("state snapshot: " + name + " holds " + std::to_string(count) +
                                  " values of " + std::to_string(value_bytes) +
                                  " bytes, this state " + std::to_string(b.count) + " of " +
                                  std::to_string(b.value_bytes) + " (saved from another model?)");
    const uint8_t* p = r.take(b.count * b.value_bytes, name);
    for (size_t k = 0; b.kind == 'b' && k < b.count; ++k)
      if (p[k] > 1) throw std::invalid_argument("state snapshot: " + name + " is not 0 or 1");
    from.push_back(p);
  }
  size_t status_field = 0;
  while (std::strcmp(kStateFields[status_field].name, "status") != 0) ++status_field;
  SimStatus status;
  std::memcpy(&status, from[status_field], sizeof status);
  static_assert(sizeof status == sizeof(int));
  if (status != SimStatus::kRunning && status != SimStatus::kFinished &&
      status != SimStatus::kUnstable)
    throw std::invalid_argument("state snapshot: field 'status' is not a status");
  const uint64_t failure_bytes = r.u64("the failure text");
  const uint8_t* failure = r.take(failure_bytes, "the failure text");
  if (r.at != snapshot.size())
    throw std::invalid_argument("state snapshot: " + std::to_string(snapshot.size() - r.at) +
                                " bytes past the end (damaged)");

  for (size_t f = 0; f < kStateFields.size(); ++f) {
    const StateFieldBytes b = kStateFields[f].bytes(s);
    // The table's view is read-only for hashing; s itself is not const.
    if (b.count > 0) std::memcpy(const_cast<void*>(b.data), from[f], b.count * b.value_bytes);
  }
  s.failure.assign(reinterpret_cast<const char*>(failure), failure_bytes);
}

Vec3 center_of_mass(const std::vector<Vec3>& pos) {
  return center_of_mass(pos, static_cast<int>(pos.size()));
}

Vec3 center_of_mass(const std::vector<Vec3>& pos, int count) {
  Vec3 c = Vec3::Zero();
  for (int i = 0; i < count; ++i) c += pos[i];
  return count == 0 ? c : Vec3(c / static_cast<double>(count));
}

const StateField& state_field(std::string_view name) {
  for (const StateField& f : kStateFields)
    if (name == f.name) return f;
  throw std::invalid_argument("no State field is called " + std::string(name));
}

}  // namespace plastivox
