#include "plastivox/state.hpp"

#include <cstring>

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
StateFieldBytes one(const T& v) {
  return {&v, 1, sizeof v};
}
template <class T>
StateFieldBytes per_value(const std::vector<T>& v) {
  return {v.data(), v.size(), sizeof(T)};
}
// Eigen's fixed-size vectors and quaternions are plain arrays of doubles, so a vector of
// them is one flat array of doubles.
template <class T, int kComponents>
StateFieldBytes components(const std::vector<T>& v) {
  static_assert(sizeof(T) == kComponents * sizeof(double));
  return {v.data(), v.size() * kComponents, sizeof(double)};
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
       return StateFieldBytes{s.com_settled.data(), 3, sizeof(double)};
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

Vec3 center_of_mass(const std::vector<Vec3>& pos) {
  Vec3 c = Vec3::Zero();
  for (const Vec3& p : pos) c += p;
  return pos.empty() ? c : Vec3(c / static_cast<double>(pos.size()));
}

}  // namespace plastivox
