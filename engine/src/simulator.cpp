#include "plastivox/simulator.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstdio>
#include <limits>

#include "plastivox/base/clock.hpp"
#include "workspace.hpp"

namespace plastivox {

Simulator::Simulator(const Model& model)
    : model_(&model), state_(make_initial_state(model)), ws_(std::make_unique<Workspace>(model)) {}
Simulator::~Simulator() = default;
Simulator::Simulator(Simulator&&) noexcept = default;

namespace {

// Runs one stage, adding its wall time to *seconds when timing is on.
template <class Stage>
inline void run_stage(StageTimings* timings, double StageTimings::*seconds, Stage&& stage) {
  if (!timings) {
    stage();
    return;
  }
  const auto start = WallClock::now();
  stage();
  timings->*seconds += seconds_since(start);
}

}  // namespace

// One step, as a list of stages. Order follows Voxelyze 0.9 so results can be compared:
// bonds see the sizes and stiffness left by the previous step; actuation for the next step
// is set from the time at the start of this one; development reads this step's strains.
void Simulator::step(StageTimings* t) {
  const Model& m = *model_;
  State& s = state_;
  Workspace& w = *ws_;
  if (s.status != SimStatus::kRunning) return;
  assert(s.pos.size() == static_cast<size_t>(m.n) && s.size.size() == s.pos.size() &&
         s.stiffness.size() == s.pos.size() &&
         s.bond_prev_valid.size() == static_cast<size_t>(m.bond_count()) &&
         "the State was not made for this Model: restore only a State saved from a Simulator "
         "of the same compiled model");

  using T = StageTimings;
  run_stage(t, &T::bond_forces, [&] { compute_bond_forces(m, s, w); });
  run_stage(t, &T::time_step, [&] { follow_stiffness(m, s); });
  run_stage(t, &T::voxel_forces, [&] { gather_voxel_forces(m, s, w); });
  run_stage(t, &T::self_collisions, [&] { apply_self_collisions(m, s, w); });
  run_stage(t, &T::integrate, [&] { integrate(m, s, w); });
  run_stage(t, &T::actuate, [&] { actuate(m, s); });
  run_stage(t, &T::develop, [&] { develop(m, s, w); });
  if (t) t->steps += 1;

  s.time += s.dt;
  s.steps += 1;
  if (!s.settled && s.time > m.def.settle_time) {
    s.com_settled = center_of_mass(s);
    s.settled = true;
  }
}

Frame capture_frame(const State& s) {
  Frame f;
  f.time = s.time;
  f.pos = s.pos;
  f.orient = s.orient;
  f.size = s.size;
  f.stiffness = s.stiffness;
  f.stimulus = s.stimulus;
  return f;
}

Vec3 displacement_since_settling(const Model& model, const Vec3& com_settled, const Vec3& com) {
  Vec3 d = (com - com_settled) / model.size;
  if (model.def.fitness == FitnessMode::kXY) d.z() = 0;
  return d;
}

// Derived from the state, not carried in a flag: after any step that may have developed
// (time past the settle time) dt is recomputed, and for unchanged stiffness stable_dt gives
// the same dt, bit for bit.
void follow_stiffness(const Model& m, State& s) {
  if (m.def.treatment != Treatment::kNone && s.time >= m.def.settle_time)
    s.dt = stable_dt(m, s.stiffness);
}

SimResult simulate(const Model& model, const SimOptions& o) {
  const auto wall_start = WallClock::now();
  const PhysicsDef& d = model.def;
  Simulator sim(model);
  const State& s = sim.state();
  SimResult r;
  r.voxels = model.n;
  r.dt_initial = s.dt;

  // Frame k is due once time reaches frame_time(k).
  const bool at_times = !o.frame_times.empty();
  const bool at_fps = !at_times && o.record_fps > 0;
  if (at_fps) r.recording.fps = o.record_fps;
  const size_t last_frame = at_times ? o.frame_times.size() : std::numeric_limits<size_t>::max();
  auto frame_time = [&](size_t k) {
    return at_times ? o.frame_times[k] : static_cast<double>(k) / o.record_fps;
  };
  size_t frames = 0;
  bool stopped = false;          // on_frame asked to end the life
  int64_t last_frame_step = -1;  // the step count of the state last taken as a frame
  auto take_frame = [&] {
    frames += 1;
    last_frame_step = s.steps;
    if (o.on_frame)
      stopped = !o.on_frame(s);
    else
      r.recording.frames.push_back(capture_frame(s));
  };
  const double end = at_times ? o.frame_times.back() : d.duration;
  double next_progress = 0;

  // Like Voxelyze, run until time first passes the duration.
  while (s.time <= d.duration && s.status == SimStatus::kRunning) {
    // One frame per step at most under record_fps, as the recording always did.
    if (at_fps && s.time >= frame_time(frames)) take_frame();
    while (at_times && frames < last_frame && s.time >= frame_time(frames) && !stopped)
      take_frame();
    if (stopped || frames == last_frame) break;
    if (o.progress && s.time >= next_progress) {
      o.progress(end > 0 ? std::min(1.0, s.time / end) : 1.0);
      next_progress = s.time + end / 100;
    }
    sim.step(o.timings);
  }
  // The life ran to its end: frames due at the last state, and under record_fps the last
  // state itself, are still to take.
  const bool whole_life = s.status == SimStatus::kRunning && s.time > d.duration && !stopped;
  if (whole_life) {
    while (at_times && frames < last_frame && s.time >= frame_time(frames) && !stopped)
      take_frame();
    if (at_fps && last_frame_step != s.steps) take_frame();
  }
  if (o.progress && !stopped) o.progress(1.0);

  r.status = whole_life ? SimStatus::kFinished : s.status;
  r.failure = s.failure;
  r.steps = s.steps;
  r.sim_time = s.time;
  r.dt_final = s.dt;
  r.com_final = center_of_mass(s);
  r.settled = s.settled;
  r.com_settled = s.settled ? s.com_settled : r.com_final;
  r.displacement = displacement_since_settling(model, r.com_settled, r.com_final);
  r.fitness = r.status == SimStatus::kFinished ? r.displacement.norm() : 0.0;
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
  r.wall_seconds = seconds_since(wall_start);
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
