// Robots and physics for Python: load and save robot files, build a robot from flat lattice
// arrays (the Python layer reshapes them), resolve physics presets and overrides.
#include <pybind11/stl.h>

#include <nlohmann/json.hpp>

#include "bindings.hpp"
#include "plastivox/demo_robots.hpp"
#include "plastivox/evo/config.hpp"
#include "plastivox/robot_file.hpp"
#include "plastivox/robot_io.hpp"

namespace plastivox::py {
namespace {

PyRobot load_robot(const std::string& path) {
  PyRobot r;
  r.source = path;
  // The command line reads any other name as JSON; a library call says what it expects.
  if (!path.ends_with(".vxa") && !path.ends_with(".json"))
    throw plastivox::InputError(path + ": expected a robot file ending in .json or .vxa");
  LoadedRobot file = plastivox::load_robot(path);
  for (const std::string& w : file.warnings) warn(path + ": " + w);
  r.def = std::move(file.robot);
  r.physics = file.physics;
  return r;
}

void save_robot(const PyRobot& r, const std::string& path) {
  if (!path.ends_with(".vxa") && !path.ends_with(".json"))
    throw std::invalid_argument("path: expected a file name ending in .json or .vxa, got '" + path +
                                "'");
  validate(r.def);
  std::vector<std::string> warnings;
  plastivox::save_robot(path, r.def, r.physics, &warnings);
  for (const std::string& w : warnings) warn(path + ": " + w);
}

// Copies a flat float64 array of one value per lattice site into out.
void copy_sites(const pyb::array_t<double, pyb::array::c_style | pyb::array::forcecast>& a,
                size_t sites, const char* name, std::vector<double>& out) {
  if (a.ndim() != 1 || static_cast<size_t>(a.size()) != sites)
    throw std::invalid_argument(std::string(name) + ": expected one value per lattice site");
  out.assign(a.data(), a.data() + sites);
}

PyRobot from_flat(
    int nx, int ny, int nz,
    const pyb::array_t<uint8_t, pyb::array::c_style | pyb::array::forcecast>& present,
    const pyb::array_t<double, pyb::array::c_style | pyb::array::forcecast>& stiffness,
    const pyb::array_t<double, pyb::array::c_style | pyb::array::forcecast>& dev_rate,
    const pyb::array_t<double, pyb::array::c_style | pyb::array::forcecast>& phase,
    double voxel_size, const std::string& treatment, const std::string& name) {
  if (nx < 1 || ny < 1 || nz < 1 || static_cast<int64_t>(nx) * ny * nz > (1 << 24))
    throw std::invalid_argument("geometry: lattice extent must be 1..2^24 sites");
  PyRobot r;
  r.def = make_empty_robot(nx, ny, nz, voxel_size);
  r.def.name = name;
  r.source = name;
  const size_t sites = r.def.sites();
  if (present.ndim() != 1 || static_cast<size_t>(present.size()) != sites)
    throw std::invalid_argument("geometry: expected one value per lattice site");
  r.def.present.assign(present.data(), present.data() + sites);
  copy_sites(stiffness, sites, "stiffness", r.def.stiffness);
  copy_sites(dev_rate, sites, "dev_rate", r.def.dev_rate);
  copy_sites(phase, sites, "phase", r.def.phase);
  // Only present voxels carry values: absent sites hold 0, as a robot file reads back.
  for (size_t s = 0; s < sites; ++s)
    if (!r.def.present[s]) r.def.stiffness[s] = r.def.dev_rate[s] = r.def.phase[s] = 0;
  validate(r.def);
  r.physics = preset_gecco2018_code();
  r.physics.treatment = parse_treatment(treatment);
  return r;
}

pyb::array_t<uint8_t> present_array(const PyRobot& r) {
  pyb::array_t<uint8_t> a(static_cast<pyb::ssize_t>(r.def.present.size()));
  std::copy(r.def.present.begin(), r.def.present.end(), a.mutable_data());
  return a;
}

}  // namespace

void warn(const std::string& message) {
  if (PyErr_WarnEx(PyExc_UserWarning, message.c_str(), 2) < 0) throw pyb::error_already_set();
}

PhysicsDef resolve_physics(const PhysicsDef& base, const std::optional<std::string>& physics_json,
                           const std::optional<std::string>& treatment) {
  PhysicsDef d = base;
  if (physics_json) apply_physics_json(*physics_json, "physics", d);
  if (treatment) d.treatment = parse_treatment(*treatment);
  validate(d);
  return d;
}

std::string physics_to_json(const PhysicsDef& def) {
  return evo::resolved_physics_json(def);
}

pyb::array_t<double> to_array(const std::vector<double>& values) {
  pyb::array_t<double> a(static_cast<pyb::ssize_t>(values.size()));
  std::copy(values.begin(), values.end(), a.mutable_data());
  return a;
}

void bind_robot(pyb::module_& m) {
  pyb::class_<PyRobot>(m, "Robot", "A robot and the physics it came with (see plastivox.Robot).")
      .def_property_readonly(
          "shape", [](const PyRobot& r) { return pyb::make_tuple(r.def.nx, r.def.ny, r.def.nz); })
      .def_property_readonly("voxel_size", [](const PyRobot& r) { return r.def.voxel_size; })
      .def_property_readonly("name", [](const PyRobot& r) { return r.def.name; })
      .def_property_readonly("source", [](const PyRobot& r) { return r.source; })
      .def_property_readonly("voxel_count", [](const PyRobot& r) { return r.def.voxel_count(); })
      .def_property_readonly("treatment",
                             [](const PyRobot& r) { return to_string(r.physics.treatment); })
      .def_property_readonly("physics_json",
                             [](const PyRobot& r) { return physics_to_json(r.physics); })
      .def_property_readonly("present_flat", &present_array)
      .def_property_readonly("stiffness_flat",
                             [](const PyRobot& r) { return to_array(r.def.stiffness); })
      .def_property_readonly("dev_rate_flat",
                             [](const PyRobot& r) { return to_array(r.def.dev_rate); })
      .def_property_readonly("phase_flat", [](const PyRobot& r) { return to_array(r.def.phase); })
      .def("with_physics",
           [](const PyRobot& r, const std::optional<std::string>& physics_json,
              const std::optional<std::string>& treatment) {
             PyRobot out = r;
             out.physics = resolve_physics(r.physics, physics_json, treatment);
             return out;
           })
      .def("save", &save_robot, pyb::arg("path"));
  m.def("load_robot", &load_robot, pyb::arg("path"));
  m.def("from_flat", &from_flat);
  m.def("demo_walker", [] {
    // What `plastivox simulate` runs without a robot file.
    PyRobot r;
    r.def = demo_walker();
    r.physics = preset_gecco2018_code();
    r.physics.treatment = Treatment::kStress;
    r.source = "built-in demo walker";
    return r;
  });
  m.def(
      "physics_json",
      [](const std::string& preset, const std::optional<std::string>& overrides) {
        PhysicsDef d;
        try {
          d = physics_preset(preset);
        } catch (const std::invalid_argument& e) {
          throw std::invalid_argument(std::string("preset: ") + e.what());
        }
        if (overrides) apply_physics_json(*overrides, "physics", d);
        return physics_to_json(d);
      },
      pyb::arg("preset"), pyb::arg("overrides") = pyb::none());
}

}  // namespace plastivox::py
