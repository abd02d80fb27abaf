#include "plastivox/simulator.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <functional>
#include <limits>
#include <stdexcept>
#include <utility>

#include "plastivox/base/clock.hpp"
#include "plastivox/base/names.hpp"
#include "plastivox/task.hpp"
#include "workspace.hpp"

namespace plastivox {

Simulator::Simulator(const Model& model)
    : model_(&model),
      state_(make_initial_state(model)),
      ws_(std::make_unique<Workspace>(model)),
      controller_(make_controller(model)),
      every_(model.controller.every),
      see_task_(task_info(model.def.task).see) {
  bind_views(model, state_, *ws_);
}
Simulator::~Simulator() = default;
Simulator::Simulator(Simulator&&) noexcept = default;

State& Simulator::mutable_state() {
  views_stale_ = true;  // the caller may replace the State's arrays
  // What step1 computed came from the State as it was: the next step runs step1 again.
  between_halves_ = false;
  sensor_cache_.invalidate();
  return state_;
}

// Between step1 and step2 too: step1 writes only the Workspace, so the State (with the signal
// and the controller's memory, which the controller sets in step2) is still the state before
// the step.
std::vector<uint8_t> Simulator::save_state() const {
  return plastivox::save_state(state_);
}

void Simulator::restore_state(const std::vector<uint8_t>& snapshot) {
  plastivox::restore_state(state_, snapshot);
  between_halves_ = false;
  sensor_cache_.invalidate();
  // The self-collision candidates are a cache of the positions at their last refresh: start
  // it afresh, as a new Simulator restored from the snapshot would.
  ws_->contacts_valid = false;
  ws_->contact_grid.pairs_stale = true;
  bind_views(*model_, state_, *ws_);
  views_stale_ = false;
}

void Simulator::reset() {
  // Copied into the State's own arrays, which keep their storage (Python's views read them).
  restore_state(plastivox::save_state(make_initial_state(*model_)));
  if (controller_) controller_->reset();
}

void Simulator::set_controller(std::unique_ptr<Controller> controller, int every) {
  if (every < 1)
    throw std::invalid_argument("every: the control rate must be >= 1 step, got " +
                                std::to_string(every));
  const size_t memory = controller ? controller->memory_size() : 0;
  if (memory != 0 && memory != state_.control_memory.size())
    throw std::invalid_argument("set_controller: the controller keeps " + std::to_string(memory) +
                                " values of memory, this model's State " +
                                std::to_string(state_.control_memory.size()) +
                                " (State::control_memory is sized by the model's own controller)");
  controller_ = std::move(controller);
  every_ = every;
}

Sensors Simulator::sensors() {
  if (!between_halves_) step1();
  return Sensors(*model_, state_, *ws_, sensor_cache_);
}

// The Model's and Workspace's arrays by each stage's own binding, the State's from the list's
// kernel views column (PLASTIVOX_STATE_FIELDS).
void bind_views(const Model& m, State& s, Workspace& w) {
  bind_bond_views(m, w);
  bind_voxel_views(m, w);
  bind_develop_views(m, w);
  KernelViews& views = w.views;
  PLASTIVOX_BIND_VIEWS(PLASTIVOX_STATE_FIELDS)
}

bool views_bound_to(const State& s, const Workspace& w) {
  const KernelViews& views = w.views;
  return PLASTIVOX_VIEWS_BOUND(PLASTIVOX_STATE_FIELDS);
}

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

// Watches the floor over a life (the State's rows floor_deepest and floor_deep_most): after
// every step, the deepest penetration of any voxel's
// bottom face below z = 0 (as the next step's floor contact sees it: half the actuated size
// below the centre, tilt ignored) and the most voxels at once deeper than
// kFloorPenetratingDepth. With an environment, the ground's height field replaces z = 0
// (HeightField::penetration, as its contact sees it). Reads the state only, so the life is
// unchanged. see_ground is the same over a height field. Out of line: its calls inside the floor
// loop's function made the compiler keep that loop's sums in memory, a store and a load per voxel
// (4 % of a life).
[[gnu::noinline]] void see_ground(const Model& m, const State& s, double limit,
                                  double& step_deepest, int& deep) {
  double most = 0;
  int count = 0;
  for (int i = 0; i < m.n; ++i) {
    const Vec3& x = s.pos[i];
    const double pen = m.ground.penetration(x.x(), x.y(), x.z(), 0.5 * s.size[i]);
    most = std::max(most, pen);
    count += pen > limit ? 1 : 0;
  }
  step_deepest = most;
  deep = count;
}

void see_floor(const Model& m, State& s) {
  if (!m.def.floor) return;
  const double limit = kFloorPenetratingDepth * m.size;
  double step_deepest = 0;
  int deep = 0;
  if (m.terrain)
    see_ground(m, s, limit, step_deepest, deep);
  else  // the floor z = 0: a plain loop with its sums in registers, which vectorises
    for (int i = 0; i < m.n; ++i) {
      const double pen = 0.5 * s.size[i] - s.pos[i].z();
      step_deepest = std::max(step_deepest, pen);
      deep += pen > limit ? 1 : 0;
    }
  s.floor_deepest = std::max(s.floor_deepest, step_deepest);
  s.floor_deep_most = std::max(s.floor_deep_most, deep);
}

// Fills the floor health of r (SimResult, "Health") from the deepest penetration seen and the
// most voxels at once deep (the State's watch rows), with a warning past
// kFloorPenetratingDepth. Whether a sunk life counts is judge_life's
// (plastivox/rules/life_rules.hpp), not the core's.
void grade_floor_contact(const Model& m, const State& s, SimResult& r) {
  const Vec3& d = r.displacement;
  const double d2 = d.squaredNorm();
  r.vertical_share = d2 > 0 ? d.z() * d.z() / d2 : 0.0;
  if (!m.def.floor) return;
  // The ground under a point: z = 0, or the environment's height field.
  const auto ground = [&m](const Vec3& x) {
    return m.terrain ? m.ground.height(x.x(), x.y()) : 0.0;
  };
  for (int i = 0; i < m.n; ++i)
    r.voxels_below_floor += s.pos[i].z() + 0.5 * m.size < ground(s.pos[i]) ? 1 : 0;
  r.floor_depth = s.floor_deepest / m.size;
  r.voxels_deep_max = s.floor_deep_most;
  // Only a life that ran to its end is graded: one that blew up is unstable, not sunk (its
  // voxels may fly anywhere, under the floor too), and says so.
  if (r.status != SimStatus::kFinished) return;
  if (r.floor_depth >= kFloorSankDepth || r.com_final.z() < ground(r.com_final))
    r.floor_health = FloorHealth::kSank;
  else if (r.floor_depth > kFloorPenetratingDepth)
    r.floor_health = FloorHealth::kPenetrating;
  r.sank = r.floor_health == FloorHealth::kSank;
  if (r.floor_health == FloorHealth::kOk) return;

  char buf[320];
  if (r.sank)
    std::snprintf(buf, sizeof buf,
                  "sank through the floor: %.4g voxel lengths deep at the deepest; %d of %d "
                  "voxels at once deeper than %g, %d end wholly below z = 0; centre of mass "
                  "ends at z = %.4g voxel lengths",
                  r.floor_depth, r.voxels_deep_max, m.n, kFloorPenetratingDepth,
                  r.voxels_below_floor, r.com_final.z() / m.size);
  else
    std::snprintf(buf, sizeof buf,
                  "pressed into the floor: %.3g voxel lengths deep at the deepest (more than "
                  "%g); %d of %d voxels at once deeper than %g",
                  r.floor_depth, kFloorPenetratingDepth, r.voxels_deep_max, m.n,
                  kFloorPenetratingDepth);
  r.warnings.push_back(buf);
}

}  // namespace

// One step, as a list of stages. Order follows Voxelyze 0.9 so results can be compared:
// bonds see the sizes and stiffness left by the previous step; actuation for the next step
// is set from the time at the start of this one; development reads this step's strains.
void Simulator::step(StageTimings* t) {
  step2(t);  // which runs step1 first, unless it already ran
}

void Simulator::step1(StageTimings* t) {
  first_half(t, false);
}

// step1, or with next_into_state (step2 running it: nothing can see the State between the
// halves) the same with the bonds' next deformations written into the State (Workspace).
void Simulator::first_half(StageTimings* t, bool next_into_state) {
  const Model& m = *model_;
  const State& s = state_;  // read only: what the next state takes goes to the Workspace
  Workspace& w = *ws_;
  if (s.status != SimStatus::kRunning) return;
  assert(s.pos.size() == static_cast<size_t>(m.n) && s.size.size() == s.pos.size() &&
         s.stiffness.size() == s.pos.size() &&
         s.bond_prev_valid.size() == static_cast<size_t>(m.bond_count()) &&
         "the State was not made for this Model: restore only a State saved from a Simulator "
         "of the same compiled model");
  if (views_stale_) {
    bind_views(m, state_, w);
    views_stale_ = false;
  }
  assert(views_bound_to(s, w) &&
         "the State's arrays moved since mutable_state() was last called: replace the State "
         "through mutable_state() or restore_state() before the step");
  sensor_cache_.invalidate();
  using T = StageTimings;
  run_stage(t, &T::bond_forces, [&] { compute_bond_forces(m, s, w, next_into_state); });
  run_stage(t, &T::time_step, [&] { follow_stiffness(m, s, w); });
  run_stage(t, &T::voxel_forces, [&] { gather_voxel_forces(m, s, w); });
  run_stage(t, &T::self_collisions, [&] { apply_self_collisions(m, s, w); });
  between_halves_ = true;
}

void Simulator::step2(StageTimings* t) {
  const Model& m = *model_;
  State& s = state_;
  Workspace& w = *ws_;
  if (!between_halves_) first_half(t, true);
  if (s.status != SimStatus::kRunning) return;
  using T = StageTimings;
  // What step1 computed for the next state: the State is mid-step from here on (the
  // controller sees this step's dt, as it always has).
  s.dt = w.dt_next;
  run_stage(t, &T::bond_forces, [&] { commit_bond_deformation(m, s, w); });
  if (controller_ && s.steps % every_ == 0)
    run_stage(t, &T::actuate, [&] {
      const double rate = controller_->max_rate();
      std::vector<double>& u = s.actuation;
      if (rate > 0) held_.assign(u.begin(), u.end());
      controller_->act(Sensors(m, s, w, sensor_cache_), u, s.control_memory);
      if (rate > 0) {  // no faster than the controller allows, from the signal held
        const double most = rate * every_ * s.dt;
        for (size_t i = 0; i < u.size(); ++i)
          u[i] = std::clamp(u[i], held_[i] - most, held_[i] + most);
      }
    });
  between_halves_ = false;
  run_stage(t, &T::integrate, [&] { integrate(m, s, w); });
  run_stage(t, &T::actuate, [&] { actuate(m, s, s.actuation.data()); });
  run_stage(t, &T::develop, [&] { develop(m, s, w); });
  if (t) t->steps += 1;

  s.time += s.dt;
  s.steps += 1;
  if (!s.settled && s.time > m.def.settle_time) {
    s.com_settled = body_center_of_mass(m, s);
    s.settled = true;
  }
  if (s.status == SimStatus::kRunning && s.time > m.def.duration) s.status = SimStatus::kFinished;
  see_floor(m, s);  // the watches, as the step left the state
  if (see_task_) see_task_(m, s);
}

Vec3 displacement_since_settling(const Model& model, const Vec3& com_settled, const Vec3& com) {
  Vec3 d = (com - com_settled) / model.size;
  if (model.def.fitness == FitnessMode::kXY) d.z() = 0;
  return d;
}

// Derived from the state, not carried in a flag: after any step that may have developed
// (time past the settle time) dt is recomputed, and for unchanged stiffness stable_dt gives
// the same dt, bit for bit. Into the Workspace: step2 commits it.
void follow_stiffness(const Model& m, const State& s, Workspace& w) {
  w.dt_next = m.def.treatment != Treatment::kNone && s.time >= m.def.settle_time
                  ? stable_dt(m, s.stiffness)
                  : s.dt;
}

namespace {

// The frames a life records (SimOptions): frame k is due once time reaches its frame time,
// k / record_fps or frame_times[k]. Each goes to on_frame, or into the recording.
class FrameTaker {
 public:
  FrameTaker(const SimOptions& o, Simulator& sim)
      : o_(o),
        sim_(sim),
        s_(sim.state()),
        at_times_(!o.frame_times.empty()),
        at_fps_(!at_times_ && o.record_fps > 0),
        last_(at_times_ ? o.frame_times.size() : std::numeric_limits<size_t>::max()) {
    if (at_fps_) recording_.fps = o.record_fps;
    recording_.control = o.record_control;
  }

  // Takes the frames due at the present state, before the next step; false when the life
  // ends here (on_frame said so, or the last of frame_times is taken).
  bool take_due() {
    // One frame per step at most under record_fps, as the recording always did.
    if (at_fps_ && s_.time >= frame_time(taken_)) take();
    while (at_times_ && taken_ < last_ && s_.time >= frame_time(taken_) && !stopped_) take();
    return !stopped_ && taken_ != last_;
  }
  // The life ran to its end: frames due at the last state, and under record_fps the last
  // state itself.
  void take_last() {
    while (at_times_ && taken_ < last_ && s_.time >= frame_time(taken_) && !stopped_) take();
    if (at_fps_ && last_step_ != s_.steps) take();
  }
  bool stopped() const { return stopped_; }
  // Where progress runs to: the life's end, or the last frame time.
  double end(double duration) const { return at_times_ ? o_.frame_times.back() : duration; }
  Recording& recording() { return recording_; }

 private:
  double frame_time(size_t k) const {
    return at_times_ ? o_.frame_times[k] : static_cast<double>(k) / o_.record_fps;
  }
  void take() {
    taken_ += 1;
    last_step_ = s_.steps;
    Frame frame = capture_frame(s_);
    if (o_.record_control) capture_control(sim_, frame);
    if (o_.on_frame)
      stopped_ = !o_.on_frame(s_, std::move(frame));
    else
      recording_.frames.push_back(std::move(frame));
  }

  const SimOptions& o_;
  Simulator& sim_;
  const State& s_;
  const bool at_times_, at_fps_;
  const size_t last_;  // frames there are to take (all of frame_times, or no limit)
  size_t taken_ = 0;
  bool stopped_ = false;    // on_frame asked to end the life
  int64_t last_step_ = -1;  // the step count of the state last taken as a frame
  Recording recording_;
};

// Reports the fraction of the life simulated to SimOptions::progress, about every 1 %.
class ProgressReport {
 public:
  ProgressReport(const SimOptions& o, double end) : fn_(o.progress), end_(end) {}
  void at(double time) {
    if (!fn_ || time < next_) return;
    fn_(end_ > 0 ? std::min(1.0, time / end_) : 1.0);
    next_ = time + end_ / 100;
  }
  void done() {
    if (fn_) fn_(1.0);
  }

 private:
  const std::function<void(double)>& fn_;
  double end_, next_ = 0;
};

// The robot's centres of mass (final: of s; free objects left out) and the displacement
// since settling (zero before).
void fill_displacement(const Model& model, const State& s, SimResult& r) {
  r.com_final = body_center_of_mass(model, s);
  r.settled = s.settled;
  r.com_settled = s.settled ? s.com_settled : r.com_final;
  r.displacement = displacement_since_settling(model, r.com_settled, r.com_final);
}

// The task's score of the life as though it ended at s: 0 for a life that went unstable. A
// measurement: whether a sunk life counts is judge_life's (plastivox/rules/life_rules.hpp).
double score_so_far(const Model& m, const State& s) {
  if (s.status == SimStatus::kUnstable) return 0.0;
  SimResult r;
  fill_displacement(m, s, r);
  return task_score(m, s, r);
}

// The summary of a life from its last state: status, fitness (the task's score so far, 0 for
// an unstable life), displacement and the lifetime stiffness change (SimResult).
void summarise(const Model& model, const State& s, SimResult& r) {
  r.voxels = model.robot_n;  // the free objects' voxels are not the robot's
  r.status = s.status;       // kRunning for a life ended early by on_frame or frame_times
  r.failure = s.failure;
  r.steps = s.steps;
  r.sim_time = s.time;
  r.dt_final = s.dt;
  fill_displacement(model, s, r);
  r.fitness = score_so_far(model, s);
  r.success = s.status == SimStatus::kFinished && task_success(model, r);
  r.final_stiffness.assign(s.stiffness.begin(), s.stiffness.begin() + model.robot_n);
  double sum = 0, sum_abs = 0, sum_sq = 0;
  for (int i = 0; i < model.robot_n; ++i) {
    const double rel = (s.stiffness[i] - model.e0[i]) / model.e0[i];
    sum += rel;
    sum_abs += std::abs(rel);
    sum_sq += rel * rel;
  }
  const double n = std::max(1, model.robot_n);
  r.stiffness_change_mean = sum / n;
  r.stiffness_change_abs_mean = sum_abs / n;
  r.stiffness_change_var =
      std::max(0.0, sum_sq / n - r.stiffness_change_mean * r.stiffness_change_mean);
  r.final_state_hash = state_hash(s);
}

}  // namespace

bool has_sunk(const Model& m, const State& s) {
  return s.floor_deepest >= kFloorSankDepth * m.size;
}

double fitness_so_far(const Model& m, const State& s) {
  return s.status == SimStatus::kRunning ? score_so_far(m, s) : result_of(m, s).fitness;
}

SimResult result_of(const Model& m, const State& s) {
  SimResult r;
  summarise(m, s, r);
  grade_floor_contact(m, s, r);
  return r;
}

SimResult Simulator::result() const {
  SimResult r = result_of(*model_, state_);
  r.dt_initial = stable_dt(*model_, model_->e0);  // make_initial_state's dt
  return r;
}

// A life, as a list: step until the Simulator says the life is over (like Voxelyze, until
// time first passes the duration) or the frames end it, taking frames, reporting progress
// (the Simulator watches the floor and the task as it steps); then the summary and the floor's
// grade.
SimResult simulate(const Model& model, const SimOptions& o) {
  const auto wall_start = WallClock::now();
  Simulator sim(model);
  const State& s = sim.state();
  const double dt_initial = s.dt;
  FrameTaker frames(o, sim);
  ProgressReport progress(o, frames.end(model.def.duration));
  while (s.status == SimStatus::kRunning && frames.take_due()) {
    progress.at(s.time);
    sim.step(o.timings);
  }
  if (s.status == SimStatus::kFinished) frames.take_last();
  if (!frames.stopped()) progress.done();

  SimResult r = sim.result();
  r.dt_initial = dt_initial;
  r.recording = std::move(frames.recording());
  r.wall_seconds = seconds_since(wall_start);
  return r;
}

const char* to_string(FloorHealth h) {
  static constexpr Named<FloorHealth> kNames[] = {{FloorHealth::kOk, "ok"},
                                                  {FloorHealth::kPenetrating, "penetrating"},
                                                  {FloorHealth::kSank, "sank"}};
  return name_in(kNames, h);
}

const char* to_string(SimStatus s) {
  static constexpr Named<SimStatus> kNames[] = {{SimStatus::kRunning, "running"},
                                                {SimStatus::kFinished, "finished"},
                                                {SimStatus::kUnstable, "unstable"}};
  return name_in(kNames, s);
}

}  // namespace plastivox
