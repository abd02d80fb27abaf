// Per-step control of a Simulator from Python (docs/control.md): the sensors as numpy arrays,
// the actuation signal in, the controller's choice and reset. The methods are added to the
// Simulator class simulate.cpp defines; `use` hands them its engine Simulator, one user at a
// time.
#include <algorithm>
#include <cmath>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <utility>

#include <pybind11/stl.h>

#include "bindings.hpp"
#include "plastivox/control.hpp"
#include "plastivox/simulator.hpp"

namespace plastivox::py {
namespace {

constexpr double kSignalSlack = 1e-15;  // 4.5 ulp of 1

// One sensor's values as a numpy copy: shape () or (3,) for the whole body, (n,) or (n, 3)
// per voxel.
pyb::array sensor_array(const SensorField& f, std::span<const double> v) {
  std::vector<pyb::ssize_t> shape;
  if (f.per_voxel) shape.push_back(static_cast<pyb::ssize_t>(v.size() / f.width));
  if (f.width > 1) shape.push_back(f.width);
  pyb::array_t<double> a(shape);
  std::copy(v.begin(), v.end(), a.mutable_data());
  return a;
}

}  // namespace

const SensorField& sensor_named(const std::string& name, const std::string& what) {
  for (const SensorField& f : kSensorFields)
    if (name == f.name) return f;
  std::string known;
  for (const SensorField& f : kSensorFields)
    known += std::string(known.empty() ? "" : ", ") + f.name;
  throw std::invalid_argument(what + ": no sensor named '" + name + "' (sensors: " + known + ")");
}

// Within kSignalSlack of [-1, 1]: the engine's own sine, which a Python controller replays,
// reaches -1 - 2.2e-16 at 0.75 cycles.
pyb::array_t<double> robot_phase(const Model& model) {
  return to_array(std::vector<double>(model.phase.begin(), model.phase.begin() + model.robot_n));
}

std::vector<double> checked_actuation(const pyb::handle& given, int n, const std::string& name) {
  const pyb::array a = pyb::array::ensure(given);
  if (!a)
    throw pyb::type_error(name + ": expected a numpy array of floats, got " +
                          std::string(pyb::str(given.get_type().attr("__name__"))));
  const char kind = a.dtype().kind();
  if (kind != 'f')
    throw pyb::type_error(name + ": expected a float array (float64 or float32), got dtype " +
                          std::string(pyb::str(a.dtype())));
  if (a.ndim() != 1 || a.shape(0) != n) {
    std::string shape = "(";
    for (pyb::ssize_t d = 0; d < a.ndim(); ++d)
      shape += (d ? ", " : "") + std::to_string(a.shape(d));
    shape += a.ndim() == 1 ? ",)" : ")";
    throw std::invalid_argument(name + ": expected shape (" + std::to_string(n) +
                                ",), one value per voxel, got " + shape);
  }
  const auto values = pyb::array_t<double, pyb::array::c_style | pyb::array::forcecast>(a);
  const double* p = values.data();
  for (int i = 0; i < n; ++i)
    if (!(std::abs(p[i]) <= 1.0 + kSignalSlack))
      throw std::invalid_argument(name + ": every value must be in [-1, 1]; " + name + "[" +
                                  std::to_string(i) + "] is " + std::to_string(p[i]));
  return std::vector<double>(p, p + n);
}

void bind_control(pyb::module_& m, const pyb::object& simulator_class, UseSimulator use) {
  const pyb::handle cls = simulator_class;
  const auto method = [&](const char* name, auto&& f, auto... extra) {
    cls.attr(name) =
        pyb::cpp_function(std::forward<decltype(f)>(f), pyb::name(name), pyb::is_method(cls),
                          pyb::sibling(pyb::getattr(cls, name, pyb::none())), extra...);
  };

  // {name: array} of the named sensors (all when names is None), of the present step.
  method(
      "sensors",
      [use](const pyb::handle& self, const std::optional<std::vector<std::string>>& names) {
        pyb::dict out;
        use(self, [&](Simulator& sim) {
          const Sensors s = sim.sensors();
          if (!names) {
            for (const SensorField& f : kSensorFields) out[f.name] = sensor_array(f, s.read(f.id));
            return;
          }
          for (const std::string& name : *names) {
            const SensorField& f = sensor_named(name, "sensor");
            out[f.name] = sensor_array(f, s.read(f.id));
          }
        });
        return out;
      },
      pyb::arg("names") = pyb::none());

  method(
      "set_actuation",
      [use](const pyb::handle& self, const pyb::handle& actuation) {
        use(self, [&](Simulator& sim) {
          // The robot's voxels (Model::robot_n): the free objects after them do not actuate.
          const std::vector<double> u =
              checked_actuation(actuation, sim.model().robot_n, "actuation");
          sim.set_controller(nullptr);  // the caller's signal from now on
          std::copy(u.begin(), u.end(), sim.actuation().begin());
        });
      },
      pyb::arg("actuation"));

  method("actuation", [use](const pyb::handle& self) {
    pyb::array_t<double> out;
    use(self, [&](Simulator& sim) {
      const std::span<const double> u =
          std::as_const(sim).actuation().first(static_cast<size_t>(sim.model().robot_n));
      out = pyb::array_t<double>(static_cast<pyb::ssize_t>(u.size()));
      std::copy(u.begin(), u.end(), out.mutable_data());
    });
    return out;
  });

  // "sine" (the built-in open loop), the robot's own neural controller by its kind's name
  // ("distributed" or "central", with the robot's weights), or None (set_actuation's signal,
  // held).
  method(
      "set_controller",
      [use](const pyb::handle& self, const std::optional<std::string>& name, int every) {
        use(self, [&](Simulator& sim) {
          const ControllerDef& own = sim.model().controller;
          const bool neural = own.kind != ControllerKind::kSine;
          if (name && *name != "sine" && !(neural && *name == to_string(own.kind)))
            throw std::invalid_argument(
                "controller: expected \"sine\"" +
                (neural ? std::string(", \"") + to_string(own.kind) + "\" (the robot's own)"
                        : std::string()) +
                " or None, got \"" + *name + "\"");
          std::unique_ptr<Controller> c;
          if (name)
            c = *name == "sine" ? std::make_unique<SineController>() : make_controller(sim.model());
          sim.set_controller(std::move(c), every);
        });
      },
      pyb::arg("controller"), pyb::arg("every") = 1);

  // The controller's name: "sine", the robot's neural kind, or None.
  method("controller", [use](const pyb::handle& self) {
    pyb::object out = pyb::none();
    use(self, [&](Simulator& sim) {
      if (dynamic_cast<SineController*>(sim.controller()))
        out = pyb::str("sine");
      else if (sim.controller())
        out = pyb::str(to_string(sim.model().controller.kind));
    });
    return out;
  });

  method("reset",
         [use](const pyb::handle& self) { use(self, [](Simulator& sim) { sim.reset(); }); });

  method("act_frequency", [use](const pyb::handle& self) {
    double f = 0;
    use(self, [&](Simulator& sim) { f = sim.model().def.act_frequency; });
    return f;
  });

  method("voxel_phase", [use](const pyb::handle& self) {
    pyb::array_t<double> out;
    use(self, [&](Simulator& sim) { out = robot_phase(sim.model()); });
    return out;
  });

  cls.attr("sensor_fields") =
      pyb::cpp_function([] { return describe_fields(kSensorFields); }, pyb::name("sensor_fields"));
  cls.attr("sensor_fields") = pyb::staticmethod(cls.attr("sensor_fields"));

  // The engine's sin(2 pi u), element by element: what the sine controller computes.
  m.def(
      "sin_cycles",
      [](const pyb::array_t<double, pyb::array::c_style | pyb::array::forcecast>& u) {
        pyb::array_t<double> out(u.request().shape);
        sin_cycles_of(std::span<const double>(u.data(), static_cast<size_t>(u.size())),
                      std::span<double>(out.mutable_data(), static_cast<size_t>(out.size())));
        return out;
      },
      pyb::arg("u"));
}

}  // namespace plastivox::py
