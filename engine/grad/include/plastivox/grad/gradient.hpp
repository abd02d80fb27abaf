// Reverse-mode gradients of a life (docs/gradients.md): the derivative of a life's fitness
// with respect to each voxel's congenital stiffness, actuation phase, development rate and
// actuation gain, the global actuation amplitude, a neural controller's weights and the initial
// state, through the engine's own discrete life.
//
// The forward pass is the engine's Simulator, unchanged: the fitness and the final state hash
// are simulate()'s, bit for bit. It stores a snapshot of the State every `checkpoint_every`
// steps. The backward pass takes the segments last to first: it recomputes each from its
// snapshot with the engine's own kernel templates run on a recording number type (the
// "replica", which checks that it reaches the next snapshot bit for bit), then propagates the
// adjoint of the segment's last state back to its first. Memory: the snapshots plus one
// segment's tape (two on two threads); cost: the forward life, the recomputation and the
// reverse sweep. On two threads the recomputation of the segment before runs beside the sweep
// of each segment (a pipeline); every segment's arithmetic is the same, so are the bits.
//
// This library depends on the core; the core knows nothing of it.
#pragma once

#include <cstdint>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include "plastivox/model.hpp"
#include "plastivox/simulator.hpp"
#include "plastivox/state.hpp"

namespace plastivox::grad {

// A life refused for GradientOptions::memory_limit: before it runs (plan()), or as it runs
// (a body that stiffens past it).
struct MemoryLimitError : std::invalid_argument {
  using std::invalid_argument::invalid_argument;
};

struct GradientOptions {
  // Steps between stored states (the length of a recomputed segment). 0 chooses: the least
  // memory takes sqrt(steps x snapshot bytes / tape bytes per step), which balances the
  // snapshots' memory against the tape's (their sum is then 2 sqrt(steps x snapshot x tape
  // per step)); but shorter segments are faster (more of a segment's tape is still in the
  // cache when it is swept), so a spacing above 16 steps is cut to 16 while the estimate (on
  // two threads) stays within 1 GB, else to the shortest that does, at most the least-memory
  // one (docs/gradients.md). The spacing depends on the model and the life alone, never on
  // the threads or memory_limit.
  int checkpoint_every = 0;
  // Refuse a life whose estimated memory (Plan::estimated_bytes) exceeds this many bytes, with
  // one line saying so (MemoryLimitError); 0: no limit. The estimate counts the life's steps
  // from its initial time step; a body that stiffens takes more, and more snapshots: the
  // forward pass then takes one thread for the backward pass if that keeps within the limit,
  // else stops with MemoryLimitError as it passes it.
  double memory_limit = 0;
  // Threads for the backward pass (0: all cores, as elsewhere in the engine). It uses at most
  // two: one sweeps a segment in reverse while the other recomputes the segment before, which
  // costs a second segment's tape (plan() counts it, and takes one thread instead when only
  // the second tape would pass memory_limit). Every thread count gives the same bits.
  int threads = 0;
  // Judges the forward life's summary (Gradient::life) before the backward pass, as the
  // caller's rules judge simulate()'s (judge_life, plastivox/rules/life_rules.hpp). Given a
  // judge, a life that does not count (it went unstable, or the judge leaves it unfinished)
  // has no backward pass: gradient() returns it, its derivative arrays empty. Without one, a
  // life that goes unstable throws std::domain_error.
  std::function<void(SimResult&)> judge;
  // Stop the life after this many steps (a Simulator's life so far: Python's
  // Simulator.backward), or at its end if sooner; -1: the whole life. A life stopped so is
  // not judged, and Gradient::life is its summary so far (status running).
  int64_t steps = -1;
};

struct Gradient {
  // The life's fitness and final state hash: simulate()'s for the same model, bit for bit.
  double fitness = 0;
  uint64_t final_state_hash = 0;
  int64_t steps = 0;
  // d fitness / d parameter, one value per robot voxel in voxel order (Model::e0's order):
  std::vector<double> stiffness;  // per Pa of congenital stiffness E0 (Model::e0)
  std::vector<double> phase;      // per cycle of actuation phase (Model::phase)
  std::vector<double> dev_rate;   // per 1/s of development rate (Model::alpha; 0 without
                                  // development, whose rates compile() zeroes)
  // d fitness / d initial centre (per m) and velocity (per m/s) of each robot voxel: x, y, z
  // per voxel, voxel order (the life starts at rest at Model::rest_pos).
  std::vector<double> initial_position, initial_velocity;
  // d fitness / d initial orientation of each robot voxel, per unit of each quaternion
  // component in the State's order (x, y, z, w per voxel), projected onto the unit quaternions'
  // tangent space at the start (every voxel starts unturned, w = 1: its w component is 0, and
  // x, y, z are twice the derivative per rad of a small turn about the world's x, y, z); and
  // per rad/s of initial angular velocity (x, y, z per voxel, world axes; the life starts
  // without turning).
  std::vector<double> initial_orientation, initial_angular_velocity;
  // d fitness / d each weight of a neural controller (Model::controller.weights, in its order:
  // docs/control.md; biases are weights there); empty for the sine.
  std::vector<double> controller_weights;
  double amplitude = 0;  // per unit of physics.act_amplitude (0 when the robot gives its own
                         // amplitudes or actuation is off)
  // d fitness / d each robot voxel's actuation gain (Model::act_gain, voxel order): with the
  // robot's own amplitudes (Model::act_per_voxel) the gain is RobotDef::act_amplitude times
  // RobotDef::act_scale (1 without one), so d / d act_amplitude = act_gain x act_scale; under
  // the paper's rule the gain is the act_scale, so this is d / d act_scale. 0 everywhere while
  // actuation is off (no voxel with a gain above 0: the stage is skipped).
  std::vector<double> act_gain;
  // The forward life's summary: simulate()'s for the same model, bit for bit (no recording),
  // judged by GradientOptions::judge when one is given. A caller judges this life instead of
  // simulating it again: its fitness is the task's, `fitness` above the loss's.
  SimResult life;
  // What it cost.
  int checkpoint_every = 0;     // steps per segment
  size_t checkpoints = 0;       // snapshots stored
  size_t checkpoint_bytes = 0;  // their total size
  size_t peak_tape_nodes = 0;   // largest segment's tape (32 bytes a node with its adjoint)
  double estimated_bytes = 0;   // the memory estimate the spacing was chosen by
  int threads = 1;              // threads the backward pass ran on (1 or 2)
};

// How gradient() will store the life, before it runs: the snapshot spacing and the memory it
// expects (snapshots, and one segment's tape and a replica a thread). Throws what gradient() throws
// before the life runs (bad options, a tape too long: std::invalid_argument; memory_limit:
// MemoryLimitError).
struct Plan {
  double steps = 0;                // the life's steps, from the initial time step (an estimate
                                   // when development changes dt)
  double snapshot_bytes = 0;       // one snapshot of the State
  double tape_bytes_per_step = 0;  // nodes and adjoints of one step (the first, and a fifth)
  int checkpoint_every = 0;
  double segment_nodes = 0;    // the nodes a segment's tape is reserved for (a quarter more)
  double thread_bytes = 0;     // what each thread of the backward pass keeps
  int threads = 1;             // the backward pass's (GradientOptions::threads)
  double estimated_bytes = 0;  // the heap's peak: snapshots, and a segment and a replica a thread
  // The heap's peak with `snapshots` bytes of snapshots and the backward pass on `threads`
  // (estimated_bytes is bytes(the planned snapshots, threads)).
  double bytes(double snapshots, int threads) const;
};
Plan plan(const Model& model, const GradientOptions& options = {});

// A loss of the life's final state: returns its value and adds its derivative with respect to
// each floating-point row of kStateFields to d[row] (d has one entry per row of kStateFields,
// sized like the row for a floating-point row and empty for the others, zero on entry).
using FinalLoss = std::function<double(const State& final, std::vector<std::vector<double>>& d)>;

// A loss of the states the life passes through, any of them, not only the last: a user's
// scalar function of the trajectory, or a task's fitness (task_loss). Its derivative with
// respect to the state after step t is added to that state's adjoint when the backward pass
// reaches step t.
struct TrajectoryLoss {
  // Forward: called with the initial state (steps 0) and then the state after every step, in
  // order: the engine's own states (the watches task_values, task_layout included). The loss
  // keeps what it reads.
  std::function<void(const State& s)> see;
  // After the life: the loss's value (Gradient::fitness).
  std::function<double(const State& final)> value;
  // Backward: called once for every state of the life again (the initial one and the one
  // after every step; segments last to first, each one's steps in order), with the replica's
  // state, which has the engine's bits in every row but the watches (not kept). Returns false
  // when the loss does not read this state (d untouched); else adds d loss / d row to d[row],
  // as FinalLoss does (d zero on entry), and returns true.
  std::function<bool(const State& s, std::vector<std::vector<double>>& d)> adjoint;
  // Optional, for tests: a signature of the loss's own non-differentiable choices in the life
  // it saw (jump's highest step, carry's lesser travel, ...), which replicate_life adds to its
  // events.
  std::function<uint64_t()> branches;
};

// The model's task's fitness (docs/tasks.md) as a TrajectoryLoss: its value is simulate()'s
// fitness bit for bit, from the physics rows alone (engine/grad/src/task_losses.cpp;
// docs/gradients.md says which states each task reads and its derivative where it has none).
// A fresh loss for each life; it refers to `model`, which must outlive it.
TrajectoryLoss task_loss(const Model& model);

// The gradient of the life's fitness: any task (each has its loss, task_loss), either bond
// model, any environment, free objects and controller. Throws std::invalid_argument as plan()
// does, MemoryLimitError also while the life runs (GradientOptions::memory_limit), and
// std::domain_error when the life does not finish (unstable; see GradientOptions::judge).
Gradient gradient(const Model& model, const GradientOptions& options = {});

// The gradient of a loss of the final state instead of the task's fitness (any task): the
// returned fitness is the loss's value. Throws as gradient() does, but for the task, and
// std::invalid_argument when the loss sizes a derivative unlike its row.
Gradient gradient_of(const Model& model, const FinalLoss& loss,
                     const GradientOptions& options = {});

// The gradient of a loss of the life's states (any task): the returned fitness is the
// loss's value. Throws as gradient_of(FinalLoss) does.
Gradient gradient_of(const Model& model, const TrajectoryLoss& loss,
                     const GradientOptions& options = {});

// The replica's forward life alone, without recording (for tests): its fitness, which must
// equal simulate()'s bit for bit, and a signature of the life's non-differentiable events
// (the voxels that set the time step, each voxel's floor contact and static friction, the
// pairs in self-contact, every comparison of the actuation and development kernels (their
// clamps, gates and maxima) and of a network's call (the sign of each softsign input, the rate
// limit's clamps) at every step, every comparison of the scalar bond path and, under
// bond_model voxelyze09, each bond's frame and each voxel's reset of a small turn, the steps at
// which settling and the life end): two lives with one signature took the same branches.
struct ReplicaSummary {
  double fitness = 0;
  uint64_t events = 0;
  int64_t steps = 0;
};
ReplicaSummary replicate_life(const Model& model);

// d fitness / d one factor of each robot voxel's actuation gain (Gradient::act_gain), in voxel
// order: the gain is the robot's act_amplitude times its act_scale (compile()), so this is
// act_gain times the other factor, `other` (RobotDef::act_scale for d / d act_amplitude,
// RobotDef::act_amplitude for d / d act_scale, on the lattice's sites; empty: 1 everywhere).
std::vector<double> gain_factor_derivative(const Gradient& g, const Model& model,
                                           const std::vector<double>& other);

// The watches among the State's rows (kStateFields: the floor's deepest penetration, the
// task's running values) are not physics: the backward pass's replica does not keep them, so
// a loss's derivative of one would go nowhere.
bool is_watch(const char* name);

}  // namespace plastivox::grad
