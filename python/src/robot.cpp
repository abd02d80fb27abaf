// Robots and physics for Python: load and save robot files, build a robot from flat lattice
// arrays (the Python layer reshapes them), resolve physics presets and overrides; a robot's
// pickle state, equality and hash.
#include <algorithm>
#include <cstring>

#include <pybind11/stl.h>

#include "bindings.hpp"
#include "plastivox/base/hash.hpp"
#include "plastivox/demo_robots.hpp"
#include "plastivox/io/robot_file.hpp"
#include "plastivox/io/robot_io.hpp"
#include "plastivox/render/files.hpp"

namespace plastivox::py {
namespace {

PyRobot load_robot(const std::string& path, const std::string& vxd) {
  PyRobot r;
  r.source = vxd.empty() ? path : path + " + " + vxd;
  // The command line reads any other name as JSON; a library call says what it expects.
  if (!path.ends_with(".vxa") && !path.ends_with(".json"))
    throw plastivox::InputError(path + ": expected a robot file ending in .json or .vxa");
  if (!vxd.empty() && !path.ends_with(".vxa"))
    throw plastivox::InputError(path + ": a .vxd goes with voxcraft-sim's base .vxa");
  LoadedRobot file = plastivox::load_robot(path, vxd);
  for (const std::string& w : file.warnings) warn(w);  // a reader's warnings name the file already
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

// Any file render reads, as the robot and physics it would simulate: a robot file, a results
// file's last champion under the run's physics, or a recorded life's robot and physics.
PyRobot load_source(const std::string& path) {
  render::LifeSource life = render::load_life_source(path);
  for (const std::string& w : life.warnings) warn(w);
  PyRobot r;
  r.def = std::move(life.robot);
  r.physics = life.physics;
  r.source = path;
  return r;
}

// --- pickle state, equality, hash ------------------------------------------------------
// The state is a tuple that names its format and version first, so a pickle from another
// build or a damaged one fails with a line saying so:
//   ("plastivox.Robot", 3, name, (nx, ny, nz), voxel_size, present, stiffness, dev_rate,
//    phase, fixed_sites, loads, physics, source, act_amplitude, act_scale, controller)
// The six arrays are the raw bytes of every lattice site (uint8 and float64 in the host's
// byte order: little-endian on every machine plastivox builds for), so values come back bit
// for bit, those at empty sites included; act_amplitude is empty for a robot without its own
// per-voxel amplitudes (all but voxcraft-sim robots), act_scale for one without per-voxel
// actuation scales (RobotDef::act_scale). fixed_sites is a tuple of sites, loads
// a tuple of (site, fx, fy, fz); physics a dict of every PhysicsDef field (physics_dict).
// controller is (kind, hidden, every, weights as raw float64 bytes), new in version 4.
// Versions 1 (13 fields, no act_amplitude) and 2 held the physics as JSON text: still read;
// before version 4 every robot ran the sine.

constexpr const char* kStateFormat = "plastivox.Robot";
constexpr int kStateVersion = 4;
constexpr size_t kPickleFields = 16;  // 13 in version 1, 14 in version 2, 15 in version 3

template <class T>
pyb::bytes raw_bytes(const std::vector<T>& v) {
  return pyb::bytes(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
}

pyb::tuple robot_state(const PyRobot& r) {
  pyb::tuple fixed(r.def.fixed_sites.size());
  for (size_t i = 0; i < r.def.fixed_sites.size(); ++i) fixed[i] = r.def.fixed_sites[i];
  pyb::tuple loads(r.def.loads.size());
  for (size_t i = 0; i < r.def.loads.size(); ++i) {
    const RobotDef::Load& l = r.def.loads[i];
    loads[i] = pyb::make_tuple(l.site, l.fx, l.fy, l.fz);
  }
  return pyb::make_tuple(
      kStateFormat, kStateVersion, r.def.name, pyb::make_tuple(r.def.nx, r.def.ny, r.def.nz),
      r.def.voxel_size, raw_bytes(r.def.present), raw_bytes(r.def.stiffness),
      raw_bytes(r.def.dev_rate), raw_bytes(r.def.phase), fixed, loads, physics_dict(r.physics),
      r.source, raw_bytes(r.def.act_amplitude), raw_bytes(r.def.act_scale),
      pyb::make_tuple(to_string(r.def.controller.kind), r.def.controller.hidden,
                      r.def.controller.every, raw_bytes(r.def.controller.weights)));
}

// Copies bytes holding one T per lattice site into out; throws InputError naming the field.
template <class T>
void sites_from_bytes(const pyb::handle& h, size_t sites, const char* field, std::vector<T>& out) {
  const std::string b = pyb::isinstance<pyb::bytes>(h) ? h.cast<std::string>() : std::string();
  if (b.size() != sites * sizeof(T))
    throw InputError(std::string("Robot pickle: ") + field + ": expected " +
                     std::to_string(sites * sizeof(T)) + " bytes, one value per lattice site");
  out.resize(sites);
  std::memcpy(out.data(), b.data(), b.size());
}

PyRobot robot_from_state(const pyb::tuple& t) {
  if (t.size() < kPickleFields - 3 || t.size() > kPickleFields ||
      !pyb::isinstance<pyb::str>(t[0]) || t[0].cast<std::string>() != kStateFormat)
    throw InputError("Robot pickle: not a plastivox robot state (expected a tuple of 13 to " +
                     std::to_string(kPickleFields) + " fields starting with '" + kStateFormat +
                     "')");
  const pyb::object version = t[1];
  int v = 0;  // the version, when it is one this build reads
  for (int known = 1; known <= kStateVersion; ++known)
    if (pyb::isinstance<pyb::int_>(version) && version.equal(pyb::int_(known))) v = known;
  if (v == 0 || t.size() != static_cast<size_t>(12 + v))
    throw InputError("Robot pickle: state version " + pyb::str(version).cast<std::string>() +
                     " with " + std::to_string(t.size()) +
                     " fields, this plastivox reads versions 1 (13 fields), 2 (14), 3 (15) and "
                     "4 (16)");
  PyRobot r;
  try {
    const auto [nx, ny, nz] = t[3].cast<std::tuple<int, int, int>>();
    r.def = make_empty_robot(nx, ny, nz, t[4].cast<double>());
    r.def.name = t[2].cast<std::string>();
    const size_t sites = r.def.sites();
    sites_from_bytes(t[5], sites, "present", r.def.present);
    sites_from_bytes(t[6], sites, "stiffness", r.def.stiffness);
    sites_from_bytes(t[7], sites, "dev_rate", r.def.dev_rate);
    sites_from_bytes(t[8], sites, "phase", r.def.phase);
    r.def.fixed_sites = t[9].cast<std::vector<int>>();
    for (const auto& [site, fx, fy, fz] :
         t[10].cast<std::vector<std::tuple<int, double, double, double>>>())
      r.def.loads.push_back({site, fx, fy, fz});
    for (int s : r.def.fixed_sites)
      if (s < 0 || s >= r.def.sites())
        throw InputError("Robot pickle: fixed_sites: site out of range");
    for (const RobotDef::Load& l : r.def.loads)
      if (l.site < 0 || l.site >= r.def.sites())
        throw InputError("Robot pickle: loads: site out of range");
    if (v < 3) {
      r.physics = PhysicsDef{};
      apply_physics_json(t[11].cast<std::string>(), "Robot pickle", r.physics);
    } else {
      r.physics = physics_from(t[11], "Robot pickle");
    }
    r.source = t[12].cast<std::string>();
    // Version 3 writes empty bytes for a robot without its own amplitudes or scales.
    if (v == 2 || (v >= 3 && pyb::len(t[13]) != 0))
      sites_from_bytes(t[13], sites, "act_amplitude", r.def.act_amplitude);
    if (v >= 3 && pyb::len(t[14]) != 0)
      sites_from_bytes(t[14], sites, "act_scale", r.def.act_scale);
    if (v >= 4) {
      const auto [kind, hidden, every, weights] =
          t[15].cast<std::tuple<std::string, int, int, pyb::bytes>>();
      ControllerDef& c = r.def.controller;
      c.kind = parse_controller_kind(kind);
      c.hidden = hidden;
      c.every = every;
      const std::string b = weights;
      if (b.size() % sizeof(double) != 0)
        throw InputError("Robot pickle: controller: weights are not whole float64 values");
      c.weights.resize(b.size() / sizeof(double));
      if (!b.empty()) std::memcpy(c.weights.data(), b.data(), b.size());
    }
  } catch (const pyb::cast_error&) {
    throw InputError("Robot pickle: a field has the wrong type (damaged state?)");
  } catch (const std::invalid_argument& e) {
    throw InputError(std::string("Robot pickle: ") + e.what());
  }
  try {
    validate(r.def);
    validate(r.physics);
  } catch (const std::invalid_argument& e) {
    throw InputError(std::string("Robot pickle: ") + e.what());
  }
  return r;
}

template <class T>
bool same_bits(const std::vector<T>& a, const std::vector<T>& b) {
  // memcmp of two empty vectors would pass null pointers (undefined, even for 0 bytes).
  return a.size() == b.size() &&
         (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

// Equal when everything a simulation or a saved file sees is equal bit for bit: name,
// lattice, voxel size, the four arrays, fixed voxels, loads and physics. Where the robot was
// read from (source) does not count.
bool same_robot(const PyRobot& a, const PyRobot& b) {
  const RobotDef &x = a.def, &y = b.def;
  bool same = x.name == y.name && x.nx == y.nx && x.ny == y.ny && x.nz == y.nz &&
              std::memcmp(&x.voxel_size, &y.voxel_size, sizeof(double)) == 0 &&
              same_bits(x.present, y.present) && same_bits(x.stiffness, y.stiffness) &&
              same_bits(x.dev_rate, y.dev_rate) && same_bits(x.phase, y.phase) &&
              same_bits(x.act_amplitude, y.act_amplitude) && same_bits(x.act_scale, y.act_scale) &&
              x.fixed_sites == y.fixed_sites && x.loads.size() == y.loads.size() &&
              x.controller.kind == y.controller.kind &&
              x.controller.hidden == y.controller.hidden &&
              x.controller.every == y.controller.every &&
              same_bits(x.controller.weights, y.controller.weights);
  for (size_t i = 0; same && i < x.loads.size(); ++i) {
    const RobotDef::Load &l = x.loads[i], &m = y.loads[i];
    same = l.site == m.site && std::memcmp(&l.fx, &m.fx, sizeof(double)) == 0 &&
           std::memcmp(&l.fy, &m.fy, sizeof(double)) == 0 &&
           std::memcmp(&l.fz, &m.fz, sizeof(double)) == 0;
  }
  return same && same_physics(a.physics, b.physics);
}

// A hash of what same_robot compares, the same in every process.
int64_t robot_hash(const PyRobot& r) {
  Hasher h;
  h.str(r.def.name);
  for (int n : {r.def.nx, r.def.ny, r.def.nz}) h.u64(static_cast<uint64_t>(n));
  h.f64(r.def.voxel_size);
  h.vec(r.def.present);
  h.vec(r.def.stiffness);
  h.vec(r.def.dev_rate);
  h.vec(r.def.phase);
  if (!r.def.act_amplitude.empty()) h.vec(r.def.act_amplitude);  // hashes made before stay
  if (!r.def.act_scale.empty()) h.vec(r.def.act_scale);
  if (!r.def.controller.is_default()) {  // likewise
    h.str(to_string(r.def.controller.kind));
    h.u64(static_cast<uint64_t>(r.def.controller.hidden));
    h.u64(static_cast<uint64_t>(r.def.controller.every));
    h.vec(r.def.controller.weights);
  }
  h.vec(r.def.fixed_sites);
  for (const RobotDef::Load& l : r.def.loads) {
    h.u64(static_cast<uint64_t>(l.site));
    for (double f : {l.fx, l.fy, l.fz}) h.f64(f);
  }
  hash_physics(r.physics, h);
  return static_cast<int64_t>(h.finish().lo);
}

// A controller handed over from Python (Robot.with_controller, which checks the arguments'
// types), validated: errors name the argument (kind, hidden, every, weights[k]) as ValueError,
// without validate()'s "controller." prefix. weights null: as many zeros as the kind takes
// (only to count them).
ControllerDef controller_argument(const std::string& kind, int hidden, int every,
                                  const std::vector<double>* weights) {
  ControllerDef c;
  try {
    c.kind = parse_controller_kind(kind);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(std::string("kind: ") + e.what());
  }
  if (c.kind == ControllerKind::kSine && hidden != 0)
    throw std::invalid_argument("hidden: the sine has no network, expected 0, got " +
                                std::to_string(hidden));
  c.hidden = hidden;
  c.every = every;
  if (weights)
    c.weights = *weights;
  else
    c.weights.resize(std::max(0, weight_count(c.kind, hidden)));
  try {
    validate(c);
  } catch (const std::invalid_argument& e) {
    const std::string what = e.what(), prefix = "controller.";
    throw std::invalid_argument(what.starts_with(prefix) ? what.substr(prefix.size()) : what);
  }
  return c;
}

PyRobot with_controller(
    const PyRobot& r, const std::string& kind, int hidden, int every,
    const pyb::array_t<double, pyb::array::c_style | pyb::array::forcecast>& w) {
  if (w.ndim() != 1) throw std::invalid_argument("weights: expected a flat list of numbers");
  const std::vector<double> weights(w.data(), w.data() + w.size());
  PyRobot out = r;
  out.def.controller = controller_argument(kind, hidden, every, &weights);
  return out;
}

pyb::dict controller_dict(const PyRobot& r) {
  const ControllerDef& c = r.def.controller;
  return pyb::dict(pyb::arg("kind") = to_string(c.kind), pyb::arg("hidden") = c.hidden,
                   pyb::arg("every") = c.every, pyb::arg("weights") = to_array(c.weights));
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
      .def_property_readonly("physics",
                             [](const PyRobot& r) {
                               return PyPhysics{{r.physics}, true, true};
                             })
      .def_property_readonly("present_flat", &present_array)
      .def_property_readonly("stiffness_flat",
                             [](const PyRobot& r) { return to_array(r.def.stiffness); })
      .def_property_readonly("dev_rate_flat",
                             [](const PyRobot& r) { return to_array(r.def.dev_rate); })
      .def_property_readonly("phase_flat", [](const PyRobot& r) { return to_array(r.def.phase); })
      .def_property_readonly("act_amplitude_flat",
                             [](const PyRobot& r) { return to_array(r.def.act_amplitude); })
      .def_property_readonly("act_scale_flat",
                             [](const PyRobot& r) { return to_array(r.def.act_scale); })
      .def(
          "with_physics",
          [](const PyRobot& r, const pyb::object& physics,
             const std::optional<std::string>& treatment, const std::optional<std::string>& task) {
            PyRobot out = r;
            out.physics = physics_of_call(r.physics, physics, treatment, task);
            return out;
          },
          pyb::arg("physics"), pyb::arg("treatment"), pyb::arg("task") = pyb::none())
      .def_property_readonly("controller", &controller_dict)
      .def("with_controller", &with_controller, pyb::arg("kind"), pyb::arg("hidden"),
           pyb::arg("every"), pyb::arg("weights"))
      .def("save", &save_robot, pyb::arg("path"))
      .def("__eq__", &same_robot, pyb::is_operator())
      .def("__hash__", &robot_hash)
      .def(pyb::pickle(&robot_state, &robot_from_state));
  m.def("load_robot", &load_robot, pyb::arg("path"), pyb::arg("vxd") = "");
  m.def("load_source", &load_source, pyb::arg("path"));
  // How many weights a controller of this kind and hidden size takes (docs/control.md).
  m.def(
      "controller_weight_count",
      [](const std::string& kind, int hidden) {
        return controller_argument(kind, hidden, 1, nullptr).weights.size();
      },
      pyb::arg("kind"), pyb::arg("hidden"));
  m.def("from_flat", &from_flat);
  // The lattice limit, checked on shapes alone before any array is converted or copied
  // (std::invalid_argument becomes ValueError).
  m.def("check_lattice_size", [](int nx, int ny, int nz) { check_lattice_size(nx, ny, nz); });
  m.def("demo_walker", [] {
    // What `plastivox simulate` runs without a robot file.
    PyRobot r;
    r.def = demo_walker();
    r.physics = preset_gecco2018_code();
    r.physics.treatment = Treatment::kStress;
    r.source = "built-in demo walker";
    return r;
  });
}

}  // namespace plastivox::py
