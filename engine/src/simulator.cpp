#include "plastivox/simulator.hpp"

#include <cassert>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>

#include "workspace.hpp"

namespace plastivox {

Simulator::Simulator(const Model& model)
    : model_(&model), state_(make_initial_state(model)), ws_(std::make_unique<Workspace>(model)) {}
Simulator::~Simulator() = default;
Simulator::Simulator(Simulator&&) noexcept = default;

// One step, as a list of stages. Order follows Voxelyze 0.9 so results can be compared:
// bonds see the sizes and stiffness left by the previous step; actuation for the next step
// is set from the time at the start of this one; development reads this step's strains.
void Simulator::step() {
  const Model& m = *model_;
  State& s = state_;
  Workspace& w = *ws_;
  if (s.status != SimStatus::kRunning) return;
  assert(s.pos.size() == static_cast<size_t>(m.n) && s.size.size() == s.pos.size() &&
         s.stiffness.size() == s.pos.size() &&
         s.bond_prev_valid.size() == static_cast<size_t>(m.bond_count()) &&
         "the State was not made for this Model: restore only a State saved from a Simulator "
         "of the same compiled model");

  compute_bond_forces(m, s, w);
  follow_stiffness(m, s);
  gather_voxel_forces(m, s, w);
  apply_self_collisions(m, s, w);
  integrate(m, s, w);
  actuate(m, s);
  develop(m, s, w);

  s.time += s.dt;
  s.steps += 1;
  if (!s.settled && s.time > m.def.settle_time) {
    s.com_settled = center_of_mass(s);
    s.settled = true;
  }
}

namespace {

void record_frame(const State& s, Recording& rec) {
  Frame f;
  f.time = s.time;
  f.pos = s.pos;
  f.orient = s.orient;
  f.size = s.size;
  f.stiffness = s.stiffness;
  f.stimulus = s.stimulus;
  rec.frames.push_back(std::move(f));
}

}  // namespace

// Derived from the state, not carried in a flag: after any step that may have developed
// (time past the settle time) dt is recomputed, and for unchanged stiffness stable_dt gives
// the same dt, bit for bit.
void follow_stiffness(const Model& m, State& s) {
  if (m.def.treatment != Treatment::kNone && s.time >= m.def.settle_time)
    s.dt = stable_dt(m, s.stiffness);
}

SimResult simulate(const Model& model) {
  const auto wall_start = std::chrono::steady_clock::now();
  const PhysicsDef& d = model.def;
  Simulator sim(model);
  const State& s = sim.state();
  SimResult r;
  r.voxels = model.n;
  r.dt_initial = s.dt;
  r.recording.fps = d.record_fps;
  double next_frame = 0;
  // Like Voxelyze, run until time first passes the duration.
  while (s.time <= d.duration && s.status == SimStatus::kRunning) {
    if (d.record_fps > 0 && s.time >= next_frame) {
      record_frame(s, r.recording);
      next_frame = static_cast<double>(r.recording.frames.size()) / d.record_fps;
    }
    sim.step();
  }
  if (d.record_fps > 0 && s.status == SimStatus::kRunning) record_frame(s, r.recording);

  r.status = s.status == SimStatus::kRunning ? SimStatus::kFinished : s.status;
  r.failure = s.failure;
  r.steps = s.steps;
  r.sim_time = s.time;
  r.dt_final = s.dt;
  r.com_final = center_of_mass(s);
  r.com_settled = s.settled ? s.com_settled : r.com_final;
  Vec3 disp = (r.com_final - r.com_settled) / model.size;
  if (d.fitness == FitnessMode::kXY) disp.z() = 0;
  r.displacement = disp;
  r.fitness = r.status == SimStatus::kFinished ? disp.norm() : 0.0;
  r.final_stiffness = s.stiffness;
  double sum = 0, sum_abs = 0, sum_sq = 0;
  for (int i = 0; i < model.n; ++i) {
    const double rel = (s.stiffness[i] - model.e0[i]) / model.e0[i];
    sum += rel;
    sum_abs += std::abs(rel);
    sum_sq += rel * rel;
  }
  const double n = std::max(1, model.n);
  r.stiffness_change_mean = sum / n;
  r.stiffness_change_abs_mean = sum_abs / n;
  r.stiffness_change_var =
      std::max(0.0, sum_sq / n - r.stiffness_change_mean * r.stiffness_change_mean);
  r.final_state_hash = state_hash(s);
  // Health: did the body end below the floor? (A report; the life itself is unchanged.)
  if (d.floor && r.status == SimStatus::kFinished) {
    double lowest_top = std::numeric_limits<double>::infinity();  // m
    for (int i = 0; i < model.n; ++i) {
      const double top = s.pos[i].z() + 0.5 * model.size;
      lowest_top = std::min(lowest_top, top);
      r.voxels_below_floor += top < 0 ? 1 : 0;
    }
    if (r.com_final.z() < 0 || r.voxels_below_floor > 0) {
      r.sank = true;
      char buf[256];
      std::snprintf(buf, sizeof buf,
                    "sank through the floor: %d of %d voxels end wholly below z = 0 (the lowest "
                    "top face at z = %.4g m, %.4g voxel lengths); centre of mass at z = %.4g m",
                    r.voxels_below_floor, model.n, lowest_top, lowest_top / model.size,
                    r.com_final.z());
      r.warnings.push_back(buf);
      if (d.sinking_invalid) {
        r.status = SimStatus::kUnstable;
        r.failure = std::string(buf) + " (physics.sinking_invalid)";
        r.fitness = 0;
      }
    }
  }
  r.wall_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  return r;
}

const char* to_string(SimStatus s) {
  switch (s) {
    case SimStatus::kRunning:
      return "running";
    case SimStatus::kFinished:
      return "finished";
    case SimStatus::kUnstable:
      return "unstable";
  }
  return "?";
}

}  // namespace plastivox
