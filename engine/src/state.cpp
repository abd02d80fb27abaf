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

uint64_t state_hash(const State& s) {
  Fnv1a64 f;
  f.bytes(&s.time, sizeof s.time);
  f.bytes(&s.steps, sizeof s.steps);
  f.bytes(&s.dt, sizeof s.dt);
  for (const Vec3& v : s.pos) f.bytes(v.data(), 3 * sizeof(double));
  for (const Quat& q : s.orient) f.bytes(q.coeffs().data(), 4 * sizeof(double));
  for (const Vec3& v : s.lin_mom) f.bytes(v.data(), 3 * sizeof(double));
  for (const Vec3& v : s.ang_mom) f.bytes(v.data(), 3 * sizeof(double));
  f.vec(s.stiffness);
  f.vec(s.stimulus);
  f.vec(s.stim_integral);
  f.vec(s.stim_ref);
  f.vec(s.static_friction);
  for (const auto& component : s.bond_prev) f.vec(component);
  f.vec(s.bond_prev_valid);
  f.vec(s.bond_small_angle);
  return f.value();
}

Vec3 center_of_mass(const std::vector<Vec3>& pos) {
  Vec3 c = Vec3::Zero();
  for (const Vec3& p : pos) c += p;
  return pos.empty() ? c : Vec3(c / static_cast<double>(pos.size()));
}

}  // namespace plastivox
