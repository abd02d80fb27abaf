// Shared pieces of the compiled part of the Python module (plastivox._core): the robot a
// Python Robot wraps, and how a call's physics is resolved. The pure-Python layer
// (python/plastivox/__init__.py) checks arguments and shapes; this layer converts and calls
// the C++ library, releasing the GIL around every long call.
#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include "plastivox/base/hash.hpp"
#include "plastivox/control.hpp"
#include "plastivox/physics_def.hpp"
#include "plastivox/robot.hpp"
#include "plastivox/simulator.hpp"

namespace plastivox::render {
class FrameRenderer;
}

namespace plastivox::py {

namespace pyb = pybind11;

// A robot and the physics it came with (a file's own physics section, or the default
// preset with the treatment given to from_arrays). Plain data; copied into each call.
struct PyRobot {
  RobotDef def;
  PhysicsDef physics;
  std::string source;  // file path, or the robot's name for robots built in Python
};

// plastivox.PhysicsDef: every physics field, and whether its treatment and its task were named
// (given to physics(), set, or replaced). One that names neither keeps the robot's treatment
// and task wherever it is passed, as a preset does and a dict without them does; they read
// None. robot.physics names the robot's.
struct PyPhysics : PhysicsDef {
  bool treatment_named = false;
  bool task_named = false;
};

// The physics of one call, by io's one rule (plastivox/io/resolve_physics.hpp): the robot's
// own (`base`); `physics`, a PhysicsDef (as a preset, with the treatment and task it names)
// or a dict of fields applied on top ("preset" first); then `treatment` and `task`, which
// win. Throws InputError / std::invalid_argument / pyb::type_error naming the field or
// argument.
PhysicsDef physics_of_call(const PhysicsDef& base, const pyb::object& physics,
                           const std::optional<std::string>& treatment,
                           const std::optional<std::string>& task);

// Every field of d as a dict, from kPhysicsFields; and back (a dict with every field, as
// physics_dict writes it; `what` names the source in errors).
pyb::dict physics_dict(const PhysicsDef& d);
PhysicsDef physics_from(const pyb::handle& fields, const std::string& what);

// Equal bit for bit in every field of kPhysicsFields; and a hash of the same.
bool same_physics(const PhysicsDef& a, const PhysicsDef& b);
void hash_physics(const PhysicsDef& d, Hasher& h);

// Hands a library warning to Python's warnings machinery (which may turn it into an error).
void warn(const std::string& message);

// A table of fields (kStateFields, kSensorFields) as a list of dicts: name, shape, unit,
// frame, meaning.
template <class Fields>
pyb::list describe_fields(const Fields& fields) {
  pyb::list out;
  for (const auto& f : fields)
    out.append(pyb::dict(pyb::arg("name") = f.name, pyb::arg("shape") = f.shape,
                         pyb::arg("unit") = f.unit, pyb::arg("axes") = f.axes,
                         pyb::arg("meaning") = f.meaning));
  return out;
}

// A 1-D float64 copy of values.
pyb::array_t<double> to_array(const std::vector<double>& values);

// Pictures of a life's present state (VoxelEnv.render; render.cpp), each drawn off-screen
// as `plastivox render` draws the frame of the life at that state (congenital colours, msaa,
// the same camera and overlay), as an (h, w, 3) uint8 array. The off-screen context is made
// on the first call and kept for the next ones of the same size. Releases the GIL while
// drawing.
class StatePainter {
 public:
  StatePainter();
  ~StatePainter();
  StatePainter(const StatePainter&) = delete;
  StatePainter& operator=(const StatePainter&) = delete;
  pyb::array_t<uint8_t> draw(const std::shared_ptr<const Model>& model, const State& state,
                             int width, int height);

 private:
  std::unique_ptr<render::FrameRenderer> drawer_;
};

void bind_physics(pyb::module_& m);   // physics.cpp
void bind_robot(pyb::module_& m);     // robot.cpp
void bind_simulate(pyb::module_& m);  // simulate.cpp
void bind_evo(pyb::module_& m);       // evo.cpp
void bind_render(pyb::module_& m);    // render.cpp
void bind_env(pyb::module_& m);       // env.cpp
void bind_analysis(pyb::module_& m);  // analysis.cpp
void bind_gradient(pyb::module_& m);  // gradient.cpp

// Runs f on the engine Simulator behind a Python Simulator object (self), refused with
// RuntimeError while another thread steps it (simulate.cpp).
using UseSimulator = void (*)(const pyb::handle& self, const std::function<void(Simulator&)>& f);
// An actuation signal a caller hands over (control.cpp), checked: a float array of shape (n,)
// with every value in [-1, 1]; errors (TypeError, ValueError) begin with `name`, the argument.
std::vector<double> checked_actuation(const pyb::handle& given, int n, const std::string& name);
// The actuation phase of the robot's voxels (Model::robot_n: the values an actuation signal
// takes; free objects do not actuate), cycles, as a numpy array (control.cpp).
pyb::array_t<double> robot_phase(const Model& model);
// The row of kSensorFields named `name`; else std::invalid_argument "<what>: no sensor named
// 'x' (sensors: touch, ...)" (control.cpp).
const SensorField& sensor_named(const std::string& name, const std::string& what);
// control.cpp: adds per-step control to the Simulator class (sensors, set_actuation,
// set_controller, reset) and plastivox._core.sin_cycles.
void bind_control(pyb::module_& m, const pyb::object& simulator_class, UseSimulator use);
// gradient.cpp: Simulator.backward, the backward pass for a loss of one's own over the states
// a Simulator's life passed through.
void bind_backward(const pyb::object& simulator_class, UseSimulator use);

}  // namespace plastivox::py
