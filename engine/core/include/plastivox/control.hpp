// Closed-loop control (docs/control.md): each voxel's actuation is a signal in [-1, 1] that a
// controller writes between the two halves of a step, from sensors it reads then.
//
// The actuation stage turns voxel i's signal u_i into its rest size for the next step:
// size_i = L max(1 + A_i u_i, act_min_factor), A_i the voxel's amplitude (physics.act_amplitude
// times xi(E) times the robot's act_scale, or the robot's own amplitude; docs/method.md §4).
// Before settle_time every voxel keeps its nominal size, whatever the signal. The sine
// controller, u_i = sin(2 pi (f t + phase_i)), is the default and gives the bits the engine
// always gave.
//
// Sensors cost nothing unless read: each is computed on its first read after step1 (the
// Simulator's cache), from what step1 left (bond strains and stresses) and the state.
#pragma once

#include <array>
#include <cstddef>
#include <memory>
#include <span>
#include <vector>

#include "plastivox/model.hpp"
#include "plastivox/state.hpp"

namespace plastivox {

struct Workspace;  // engine/core/src/workspace.hpp

// The sensors, in kSensorFields order.
enum class Sensor {
  kTouch,        // per voxel
  kFloorForce,   // per voxel
  kStrain,       // per voxel
  kStress,       // per voxel
  kPressure,     // per voxel
  kVelocity,     // per voxel, xyz
  kUp,           // per voxel, xyz
  kComVelocity,  // whole body, xyz
  kTime,         // whole body
  kPhase,        // whole body
};
inline constexpr int kSensorCount = 10;

// One sensor, described once (as kStateFields describes the state): name, shape ("n" one
// value per voxel, "n x 3" a vector per voxel, "3" and "1" whole-body), unit, axes, meaning.
struct SensorField {
  Sensor id;
  const char* name;
  const char* shape;
  const char* unit;
  const char* axes;
  const char* meaning;
  bool per_voxel;  // n entries of `width` values; else `width` values in all
  int width;
};
extern const std::array<SensorField, kSensorCount> kSensorFields;

// Computed sensor values, kept until the next step1 (a Simulator holds one).
struct SensorCache {
  std::array<std::vector<double>, kSensorCount> values;
  std::array<bool, kSensorCount> fresh{};  // values[k] is of the present step
  void invalidate() { fresh.fill(false); }
};

// What a controller reads, between step1 and step2 of one step: the sensors (each computed
// on its first read this step, then kept), the model and the state. A handle into its
// Simulator, valid during the call that received it.
class Sensors {
 public:
  Sensors(const Model& model, const State& state, const Workspace& workspace, SensorCache& cache)
      : model_(model), state_(state), ws_(workspace), cache_(cache) {}

  // The sensor's values, flat in voxel order (x, y, z per voxel for "n x 3").
  std::span<const double> read(Sensor id) const;
  const Model& model() const { return model_; }
  const State& state() const { return state_; }

 private:
  const Model& model_;
  const State& state_;
  const Workspace& ws_;
  SensorCache& cache_;
};

// A controller: called between step1 and step2 every k steps (Simulator::set_controller), it
// writes each voxel's signal, in [-1, 1], in voxel order; the signal holds until its next
// call. It must be deterministic (the same sensors give the same signal, on any thread), so
// lives stay bit-identical. Values outside [-1, 1] are the controller's bug: the actuation
// stage reads what it is given.
//
// What it remembers from one call to the next lives in the State, not in the controller
// (State::control_memory, memory_size() values, 0 at t = 0): act() is handed it to read and
// write. So a snapshot, the state's hash and Python's state views hold it without the
// controller's help, a State copied into another Simulator carries it, and the controller is
// a function of what it is handed (which later work on gradients through a life needs).
class Controller {
 public:
  virtual ~Controller() = default;
  virtual void act(const Sensors& sensors, std::span<double> actuation,
                   std::span<double> memory) = 0;
  // How many values it keeps in State::control_memory: 0, or the State's (the model's
  // controller's, controller_memory_size); Simulator::set_controller refuses any other.
  virtual size_t memory_size() const { return 0; }
  // The life starts again (Simulator::reset): for a controller that counts or caches
  // something of its own (its memory in the State is reset with the State).
  virtual void reset() {}
  // The fastest its signal may change, per second (0: no limit): the Simulator moves each
  // voxel's signal at most max_rate * every * dt from the one it held, after act().
  virtual double max_rate() const { return 0; }
};

// Today's open loop, the default: u_i = sin(2 pi (f t + phase_i)) for each of the robot's
// voxels (a free object's signal stays 0), f = physics.act_frequency, t the time at the start
// of the step; 0 everywhere when f = 0. Reads no sensor. Before settle_time it writes nothing
// (the actuation stage ignores the signal then).
class SineController final : public Controller {
 public:
  void act(const Sensors& sensors, std::span<double> actuation, std::span<double>) override;
};

// The controller model.controller asks for (docs/control.md): the sine, or a distributed or
// central network with its weights. Simulator's constructor sets it, at its rate.
std::unique_ptr<Controller> make_controller(const Model& model);

// The engine's sin(2 pi u) (its own series, within 4 ulp of libm and the same bits on every
// machine and instruction set): what the sine controller computes, for a controller written
// elsewhere (Python) that must reproduce it bit for bit.
double sin_cycles_of(double u);
// The same for every u[i] into out[i] (out.size() >= u.size()), vectorised as the controller
// is; the one difference: u = -0 gives +0.
void sin_cycles_of(std::span<const double> u, std::span<double> out);

}  // namespace plastivox
