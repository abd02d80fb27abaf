// Gradients of a life for Python (docs/gradients.md): plastivox.gradient. The C++ library
// engine/grad computes them; this binds one call, with the GIL released.
#include <string>
#include <vector>

#include <pybind11/stl.h>

#include "bindings.hpp"
#include "plastivox/grad/gradient.hpp"
#include "plastivox/io/limits.hpp"
#include "plastivox/rules/life_rules.hpp"
#include "plastivox/simulator.hpp"

namespace plastivox::py {
namespace {

// What `wrt` may name: the Robot's own arrays, the physics' global amplitude and the Robot's
// controller (its weights).
constexpr const char* kWrt[] = {"stiffness", "phase", "dev_rate", "amplitude", "controller"};

// The fitness of the robot's life (as simulate gives it, bit for bit) and, for each name in
// wrt, its derivative: a flat array over the lattice's sites (0 where no voxel is; the Python
// layer shapes it like the Robot's arrays), or a float for "amplitude".
pyb::tuple gradient_one(const PyRobot& robot, const pyb::object& physics_arg,
                        const std::optional<std::string>& treatment,
                        const std::vector<std::string>& wrt, int threads) {
  for (const std::string& name : wrt) {
    bool known = false;
    for (const char* k : kWrt) known = known || name == k;
    if (!known)
      throw std::invalid_argument("wrt: no parameter is called '" + name +
                                  "' (stiffness, phase, dev_rate, amplitude, controller)");
  }
  const PhysicsDef physics = physics_of_call(robot.physics, physics_arg, treatment, std::nullopt);
  for (const std::string& name : wrt)
    if (name == "controller" && robot.def.controller.weights.empty())
      throw std::invalid_argument(
          "wrt: 'controller': the robot's controller is the sine, which has no weights "
          "(Robot.with_controller gives it a network)");
  if (threads < 0)
    throw std::invalid_argument("threads: expected an integer >= 0 (0: all cores), got " +
                                std::to_string(threads));
  grad::Gradient g;
  Model model;
  {
    pyb::gil_scoped_release unlocked;
    model = compile(robot.def, physics, limits_from_environment());
    // The gradient's forward life, judged as simulate judges a life: one that does not count
    // (sank under sinking_invalid, or unstable) scores 0 whatever its parameters, and has no
    // gradient to give.
    grad::GradientOptions options;
    options.threads = threads;
    options.judge = [&physics](SimResult& r) { judge_life(physics, r); };
    g = grad::gradient(model, options);
    if (g.life.status != SimStatus::kFinished)
      throw std::invalid_argument(
          "gradient: the life does not count, so its fitness has no "
          "gradient: " +
          g.life.failure);
  }
  const auto on_sites = [&](const std::vector<double>& per_voxel) {
    std::vector<double> sites(robot.def.present.size(), 0.0);
    for (int i = 0; i < model.robot_n; ++i) sites[model.site[i]] = per_voxel[i];
    return to_array(sites);
  };
  pyb::dict out;
  for (const std::string& name : wrt) {
    if (name == "stiffness") out[name.c_str()] = on_sites(g.stiffness);
    if (name == "phase") out[name.c_str()] = on_sites(g.phase);
    if (name == "dev_rate") out[name.c_str()] = on_sites(g.dev_rate);
    if (name == "amplitude") out[name.c_str()] = g.amplitude;
    if (name == "controller") out[name.c_str()] = to_array(g.controller_weights);
  }
  return pyb::make_tuple(g.fitness, out);
}

}  // namespace

void bind_gradient(pyb::module_& m) {
  m.def("gradient", &gradient_one, pyb::arg("robot"), pyb::arg("physics"), pyb::arg("treatment"),
        pyb::arg("wrt"), pyb::arg("threads"));
}

}  // namespace plastivox::py
