// Running a simulation: one step at a time (Simulator) or a whole life (simulate()).
//
// A Simulator owns the mutable State and a scratch workspace; the Model it reads is shared
// and immutable, so many Simulators (one per thread) may run the same or different models
// at once. A single simulation runs on one thread, which keeps every reduction in a fixed
// order: results are bit-identical whatever the number of threads evaluating robots.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "plastivox/control.hpp"
#include "plastivox/model.hpp"
#include "plastivox/recording.hpp"
#include "plastivox/state.hpp"

namespace plastivox {

struct SimResult;
struct Workspace;  // per-step scratch arrays (engine/core/src/workspace.hpp)

// Wall time spent in each stage of Simulator::step, summed over the steps timed (as
// MuJoCo's timers do). Costs two clock reads per stage, so only on request.
struct StageTimings {
  double bond_forces = 0;      // s: strains and forces of every bond, and step2's commit of
                               // their deformation (and dt) into the State
  double time_step = 0;        // s: dt follows developed stiffness
  double voxel_forces = 0;     // s: bond forces gathered per voxel, slow damping, gravity
  double self_collisions = 0;  // s
  double integrate = 0;        // s: floor contact and friction, velocities and poses
  double actuate = 0;          // s: the controller, and sizes for the next step
  double develop = 0;          // s: stimulus and stiffness
  int64_t steps = 0;
  double total() const;
};

// The stages by name, in step order, for reports.
struct StageName {
  const char* name;
  double StageTimings::*seconds;
};
inline constexpr StageName kStageNames[] = {{"bond_forces", &StageTimings::bond_forces},
                                            {"time_step", &StageTimings::time_step},
                                            {"voxel_forces", &StageTimings::voxel_forces},
                                            {"self_collisions", &StageTimings::self_collisions},
                                            {"integrate", &StageTimings::integrate},
                                            {"actuate", &StageTimings::actuate},
                                            {"develop", &StageTimings::develop}};
inline double StageTimings::total() const {
  double sum = 0;
  for (const StageName& s : kStageNames) sum += this->*s.seconds;
  return sum;
}

class Simulator {
 public:
  explicit Simulator(const Model& model);  // model must outlive the simulator
  ~Simulator();
  Simulator(Simulator&&) noexcept;
  Simulator& operator=(Simulator&&) = delete;

  const Model& model() const { return *model_; }
  const State& state() const { return state_; }
  // The state may be changed, or replaced by one copied from another Simulator of the same
  // model: the life then continues bit-identically (State holds everything that carries
  // over: the physics, the actuation signal, the controller's memory and the watches the
  // score is made from). The kernels' views of the state's arrays are rebuilt at the next
  // step, so make the changes through this reference before stepping (do not keep it across
  // steps). Between step1 and step2 it drops what step1 computed: step2 runs step1 again
  // first.
  State& mutable_state();

  // The state as bytes, and back: plastivox::save_state/restore_state (state.hpp, every row
  // of kStateFields in order). restore_state() takes a snapshot saved from a Simulator of the
  // same model (at any step, by this one or another) and the life continues from it
  // bit-identically under the same controller, its score included (result()). A snapshot of
  // another model's state, or a damaged one, is refused with std::invalid_argument naming the
  // field, and the state is left as it was. Between step1 and step2 (or after sensors()) the
  // snapshot is the state before that step, as step1 writes only the workspace; restoring it
  // (here or in another Simulator) runs the step again from step1, bit-identically.
  std::vector<uint8_t> save_state() const;
  void restore_state(const std::vector<uint8_t>& snapshot);
  // Back to the state at t = 0, as a new Simulator of the model starts; the controller and
  // its rate stay (its reset() is called), the signal is 0.
  void reset();

  // ---- Control (plastivox/control.hpp, docs/control.md) ----
  // The controller, called between step1 and step2 when steps % every == 0 (every >= 1, else
  // std::invalid_argument naming `every`). The default is the model's (make_controller: the
  // sine every step, unless the robot names another). nullptr: no controller; the signal is what
  // the caller writes to actuation(), and holds until written again.
  void set_controller(std::unique_ptr<Controller> controller, int every = 1);
  Controller* controller() const { return controller_.get(); }
  int control_every() const { return every_; }
  // Each voxel's actuation signal, in [-1, 1], voxel order (n values): what the controller
  // last wrote, read by the actuation stage in step2. Write it between steps (or between the
  // halves of one) when no controller is set.
  // The State's row `actuation`.
  std::span<double> actuation() { return state_.actuation; }
  std::span<const double> actuation() const { return state_.actuation; }
  // The sensors of the present step, computed on first read: runs step1 first when it has
  // not run since the last step2 (step() or step2() then finishes that step). Changes no
  // State (step1 fills the workspace only). The handle is valid until the next step.
  Sensors sensors();

  // Advances one time step: step1() (unless it already ran: sensors(), or a call of step1())
  // then step2(). Sets status to kUnstable (with a reason)
  // instead of producing non-finite numbers, and to kFinished once time passes the life's
  // duration (as Voxelyze runs until time first passes it); further calls then do nothing.
  // Adds each stage's wall time to `timings` when given.
  void step(StageTimings* timings = nullptr);

  // The two halves of a step, as MuJoCo splits mj_step into mj_step1 and mj_step2, so a
  // controller can read and act between them. The stage order is step()'s either way.
  //   step1: what the present configuration implies: every bond's strain, stress and forces
  //          (the development stimuli come from them), the time step, each voxel's forces
  //          with gravity, and self-contacts (workspace()). It reads the State and writes
  //          only the workspace, including what the next state takes from this step (the
  //          time step, each bond's deformation, Voxelyze 0.9's bond axes): between the
  //          halves the State is the state before the step, save_state() takes it, and
  //          step1 called again leaves the same workspace. (step() has nothing between the
  //          halves, so there the bond stage writes the bonds' next deformations into the
  //          State directly: the same bits without step2's copy.)
  //   step2: acts on them: commits what step1 computed for the next state, calls the
  //          controller (every k steps), integrates (with floor contact and friction),
  //          sets each voxel's actuated size for the next step from its signal, develops
  //          stiffness, advances time, ends the life once time passes the duration, and
  //          updates the watches in the State (the floor's deepest penetration, the task's
  //          running values), so any life stepped by any front end can be scored (result()).
  //          It runs step1 first when step1 was not called since the last step2.
  void step1(StageTimings* timings = nullptr);
  void step2(StageTimings* timings = nullptr);

  // The scratch of the current step, as step1 leaves it (engine/core/src/workspace.hpp: bond
  // strains and stresses, forces, contact candidates); for tests and controllers.
  const Workspace& workspace() const { return *ws_; }

  // The life's SimResult at this point (result_of, with dt_initial): so far for a running
  // life, final for a finished one, and bit for bit what simulate() returns for the same life
  // (without its recording and wall time).
  SimResult result() const;

 private:
  // step1; step2 has it write the bonds' next deformations into the State (simulator.cpp).
  void first_half(StageTimings* t, bool next_into_state);

  const Model* model_;
  State state_;
  std::unique_ptr<Workspace> ws_;
  bool between_halves_ = false;  // step1 ran, step2 not yet
  bool views_stale_ = false;     // mutable_state() was called since the views were built
  std::unique_ptr<Controller> controller_;
  int every_ = 1;
  std::vector<double> held_;  // the signal before a rate-limited controller's call
  void (*see_task_)(const Model&, State&) = nullptr;  // the task's watch (TaskInfo::see)
  SensorCache sensor_cache_;                          // sensors read this step
};

// How a life met the floor, graded from its deepest penetration (SimResult::floor_depth).
enum class FloorHealth {
  kOk,           // no deeper than kFloorPenetratingDepth: a body that stands and walks
  kPenetrating,  // deeper, but not kFloorSankDepth: pressed into the floor
  kSank,         // kFloorSankDepth or deeper, or the centre of mass ended below z = 0
};
// Thresholds in voxel lengths, set from measured lives (docs/engine.md, "Floor contact and
// sinking"): every walker measured goes at most 0.42 deep, bodies pressed into the floor by
// their own weight 0.6 to 1.8, and bodies that fall through it 7.9 and more.
inline constexpr double kFloorPenetratingDepth = 0.5;  // a voxel's centre reaches the floor
inline constexpr double kFloorSankDepth = 2.0;

struct SimResult {
  SimStatus status = SimStatus::kRunning;
  std::string failure;  // why the run went unstable; empty when it finished
  // The task's score (def.task, plastivox/task.hpp) of the life: of a finished one its
  // fitness, of one ended early (still running) its score so far, 0 for an unstable one (a
  // sunk one keeps its score here: judge_life, plastivox/rules/life_rules.hpp, decides whether
  // it counts). Under walk, the default, the centre-of-mass displacement settle..end, voxel
  // lengths.
  double fitness = 0;
  // Whether a finished life met its task's criterion (TaskInfo::criterion, docs/tasks.md);
  // false for a life that did not finish, and judge_life clears it for one that does not count.
  bool success = false;
  Vec3 displacement = Vec3::Zero();  // centre of mass, settle..end, per axis, voxel lengths
  Vec3 com_settled = Vec3::Zero();   // m
  Vec3 com_final = Vec3::Zero();     // m
  int voxels = 0;                    // the robot's (Model::robot_n: free objects not counted)
  int64_t steps = 0;
  double dt_initial = 0;  // s
  double dt_final = 0;    // s
  double sim_time = 0;    // s reached
  double wall_seconds = 0;
  // Lifetime stiffness change, relative: (E_final - E0) / E0 per voxel.
  std::vector<double> final_stiffness;   // Pa, per robot voxel (the first robot_n)
  double stiffness_change_mean = 0;      // signed mean
  double stiffness_change_abs_mean = 0;  // mean of absolute values
  double stiffness_change_var = 0;       // variance of the signed values
  uint64_t final_state_hash = 0;
  Recording recording;  // frames, when SimOptions asked for them without an on_frame
  // Health: how the body met the floor over its whole life (docs/engine.md, "Floor
  // contact and sinking"). A voxel's penetration is how far its bottom face (half its
  // actuated size below its centre, tilt ignored, as the floor contact sees it) is below
  // z = 0; the deepest over every step is floor_depth. Heavy, soft bodies pass through the
  // floor: their time step is long enough to cross the contact in one step. Whether a sunk
  // life counts is not the core's to say: judge_life (plastivox/rules/life_rules.hpp) makes
  // it invalid under def.sinking_invalid. Only a life that ran to its end is graded (one that
  // blew up stays kOk and says why in `failure`); floor_depth and the counts are measured
  // either way.
  FloorHealth floor_health = FloorHealth::kOk;
  double floor_depth = 0;      // deepest penetration over the life, voxel lengths (>= 0)
  int voxels_deep_max = 0;     // most voxels at once deeper than kFloorPenetratingDepth
  int voxels_below_floor = 0;  // voxels whose top face ends below z = 0
  bool sank = false;           // floor_health == kSank
  // Share of the fitness from vertical displacement: dz^2 / |d|^2 of `displacement`, in
  // [0, 1] (0 without displacement, and always 0 under xy fitness, which ignores dz).
  double vertical_share = 0;
  bool settled = false;  // the life passed the settle time (else com_settled is com_final)
  std::vector<std::string> warnings;  // one line each, e.g. what sank and by how much
};

// What simulate() records and reports besides the summary. The default records nothing.
//
// Frames are taken at frame times, each the first state whose time is >= the frame time
// (several frame times inside one step get the same state):
//   - record_fps > 0: at k / record_fps over the whole life, plus the last state;
//   - frame_times (ascending, s): at those times only, and the life ends after the last one
//     (a still at t = 2.6 s does not simulate the rest); times past the end of the life are
//     not taken. frame_times wins over record_fps.
// Each frame goes to on_frame when it is set, else into SimResult::recording. With
// record_control each frame also carries the control channels (kControlFrameFields: the
// actuation signal and the per-voxel sensors, read as a controller reads them; the bits of
// the life are unchanged).
struct SimOptions {
  double record_fps = 0;            // frames per simulated second, 0 = none
  std::vector<double> frame_times;  // s, ascending
  bool record_control = false;      // frames carry the control channels
  // Called with the state at each frame time and its frame (capture_frame, and the control
  // channels when asked); returning false ends the life there.
  std::function<bool(const State&, Frame&&)> on_frame;
  // Called with the fraction of the life simulated, in [0, 1], about every 1 %, and with 1
  // when the life is over.
  std::function<void(double)> progress;
  StageTimings* timings = nullptr;  // per-stage wall time of every step, when set
};

// Simulates a life and summarises it: to def.duration (like Voxelyze, until time first
// passes it), or to the last of options.frame_times, or until on_frame returns false. A life
// ended early keeps status kRunning, and its summary describes the life so far.
SimResult simulate(const Model& model, const SimOptions& options = {});

// The frame simulate() records of a state: pose, size, stiffness and stimulus per voxel.
Frame capture_frame(const State& state);
// Adds the control channels of sim's present state to `frame` (kControlFrameFields): the
// actuation signal and the sensors as sim.sensors() gives them, so it runs the first half of
// the next step, which step() then finishes (the life's bits are unchanged). At the end of a
// life no step is left to begin: the strain, stress, pressure, touch and floor force are then
// those of the last step.
void capture_control(Simulator& sim, Frame& frame);

// A life's score, as functions of the model and the state (the watches step2 keeps up are
// rows of the State: floor_deepest, floor_deep_most, task_values, task_layout).
// The SimResult of the life so far (simulate()'s, without its recording, wall time and
// dt_initial): status, displacement, stiffness change, floor health and the task's fitness:
// of a finished life its score; of a running one the score as though it ended here (0 before
// settling); 0 for an unstable one. Measurements only: judge_life
// (plastivox/rules/life_rules.hpp) decides whether a sunk life counts.
SimResult result_of(const Model& model, const State& state);
// Its fitness alone, without the rest of the summary (cheaper, for every step of an episode).
double fitness_so_far(const Model& model, const State& state);
// The body has gone kFloorSankDepth or deeper into the floor: a finished life is graded sunk.
bool has_sunk(const Model& model, const State& state);

// Displacement of the centre of mass from com_settled to com in voxel lengths, z zeroed
// under the xy fitness mode: the vector whose norm is fitness.
Vec3 displacement_since_settling(const Model& model, const Vec3& com_settled, const Vec3& com);

const char* to_string(SimStatus s);
const char* to_string(FloorHealth h);  // "ok", "penetrating", "sank"

}  // namespace plastivox
