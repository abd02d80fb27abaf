// PhysicsDef for Python, under its C++ name. One attribute per row of kPhysicsFields (the
// table the robot file's reader and writer use), readable as a mapping too, so a PhysicsDef
// and a dict of its fields serve alike wherever physics is taken. Dicts are applied through
// that table: no JSON text passes between Python and C++.
#include <cmath>
#include <cstring>
#include <string_view>

#include <pybind11/stl.h>
#include <nlohmann/json.hpp>

#include "bindings.hpp"
#include "plastivox/base/error.hpp"  // InputError
#include "plastivox/base/hash.hpp"
#include "plastivox/io/json_input.hpp"  // task_json
#include "plastivox/io/resolve_physics.hpp"
#include "plastivox/io/robot_file.hpp"  // the environment's JSON form
#include "plastivox/task.hpp"

namespace plastivox::py {
namespace {

const PhysicsField* find_field(const std::string& name) {
  for (const PhysicsField& f : kPhysicsFields)
    if (name == f.name) return &f;
  return nullptr;
}

// The task as files write it: its name alone, or {"name": ..., parameters} when it has any
// (docs/tasks.md), so every way a PhysicsDef is read gives what with_fields takes back.
pyb::object task_value(const PhysicsDef& d) {
  if (d.task_params.empty()) return pyb::str(to_string(d.task));
  pyb::dict out;
  out["name"] = to_string(d.task);
  for (const auto& [name, value] : d.task_params) out[pyb::str(name)] = value;
  return out;
}

// One field as to_dict() holds it (a task with its parameters).
pyb::object field_value(const PhysicsDef& d, const PhysicsField& f) {
  if (std::strcmp(f.name, "task") == 0) return task_value(d);
  switch (f.kind) {
    case PhysicsField::Kind::kNumber:
      return pyb::float_(d.*f.number);
    case PhysicsField::Kind::kFlag:
      return pyb::bool_(d.*f.flag);
    case PhysicsField::Kind::kWhole:
      return pyb::int_(d.*f.whole);
    case PhysicsField::Kind::kChoice:
      return pyb::str(f.get(d));
  }
  return pyb::none();
}

// The environment (ground and boxes, docs/environments.md) is nested arrays rather than a
// row of kPhysicsFields: Python sees it as the robot file's "environment" object, a dict (None
// for the flat floor), converted by the robot file's own reader and writer.
pyb::object environment_value(const PhysicsDef& d) {
  if (!d.environment.active()) return pyb::none();
  return pyb::module_::import("json").attr("loads")(physics_to_json(d))["environment"];
}

// A Python value as the JSON the robot file's reader takes: dicts (text keys), lists, tuples
// and numpy arrays, numbers (numpy scalars included), text, True/False and None. Numbers
// must be finite. Throws std::invalid_argument naming the field by `path`
// ("physics.environment.ground.height: must be finite").
nlohmann::json to_json(const pyb::handle& v, const std::string& path) {
  if (v.is_none()) return nullptr;
  const pyb::module_ np = pyb::module_::import("numpy");
  if (pyb::isinstance(v, np.attr("ndarray"))) return to_json(v.attr("tolist")(), path);
  if (pyb::isinstance(v, np.attr("generic"))) return to_json(v.attr("item")(), path);
  if (PyBool_Check(v.ptr())) return v.cast<bool>();
  if (PyLong_Check(v.ptr())) {
    int overflow = 0;
    const long long n = PyLong_AsLongLongAndOverflow(v.ptr(), &overflow);
    if (overflow != 0) throw std::invalid_argument(path + ": out of range");
    return n;
  }
  if (PyFloat_Check(v.ptr())) {
    const double x = PyFloat_AsDouble(v.ptr());
    if (!std::isfinite(x)) throw std::invalid_argument(path + ": must be finite");
    return x;
  }
  if (pyb::isinstance<pyb::str>(v)) return v.cast<std::string>();
  if (pyb::isinstance<pyb::dict>(v)) {
    nlohmann::json out = nlohmann::json::object();
    for (const auto& [key, value] : pyb::reinterpret_borrow<pyb::dict>(v)) {
      if (!pyb::isinstance<pyb::str>(key))
        throw std::invalid_argument(path + ": field names must be text, got " +
                                    pyb::repr(key).cast<std::string>());
      const std::string name = key.cast<std::string>();
      out[name] = to_json(value, path + "." + name);
    }
    return out;
  }
  if (pyb::isinstance<pyb::list>(v) || pyb::isinstance<pyb::tuple>(v)) {
    nlohmann::json out = nlohmann::json::array();
    size_t i = 0;
    for (const pyb::handle item : v)
      out.push_back(to_json(item, path + "[" + std::to_string(i++) + "]"));
    return out;
  }
  throw std::invalid_argument(path +
                              ": expected a number, text, True or False, a list or a dict, got " +
                              pyb::str(v.get_type().attr("__name__")).cast<std::string>());
}

// d with {key: value} applied by the robot file's reader (InputError
// "physics.<key>.<field>: ...", as every other field's error reads); the environment is left
// out of the check (validated with the whole, later).
PhysicsDef applied_as_file(const PhysicsDef& d, const char* key, const pyb::handle& value) {
  nlohmann::json fields = nlohmann::json::object();
  fields[key] = to_json(value, std::string("physics.") + key);
  PhysicsDef with = d;
  with.environment = Environment{};
  try {
    apply_physics_json(fields.dump(), "physics", with);
  } catch (const InputError& e) {
    // The reader names the source, then the field: "physics: physics.task.rise: ...".
    const std::string_view what = e.what(), source = "physics: ";
    if (what.starts_with(source)) throw InputError(std::string(what.substr(source.size())));
    throw;
  }
  return with;
}

void set_environment(PhysicsDef& d, const pyb::handle& v) {
  if (v.is_none()) {
    d.environment = Environment{};
    return;
  }
  if (!pyb::isinstance<pyb::dict>(v))
    throw std::invalid_argument(
        "physics.environment: expected a dict (docs/environments.md) or None");
  d.environment = applied_as_file(d, "environment", v).environment;
}

// A task with parameters ({"name": "climb", "rise": 1}, docs/tasks.md), read by the robot
// file's reader; a name alone goes through kPhysicsFields like any choice (and drops the
// parameters of another task).
void set_task_with_params(PhysicsDef& d, const pyb::handle& v) {
  const PhysicsDef with = applied_as_file(d, "task", v);
  d.task = with.task;
  d.task_params = with.task_params;
}

// Sets one field from a Python value of its kind (numpy scalars included). Throws
// std::invalid_argument (ValueError) naming "physics.<field>"; does not validate the whole.
void set_field(PhysicsDef& d, const PhysicsField& f, const pyb::handle& v) {
  const std::string field = std::string("physics.") + f.name;
  const bool is_bool = PyBool_Check(v.ptr()) != 0;
  switch (f.kind) {
    case PhysicsField::Kind::kNumber: {
      if (is_bool || !PyNumber_Check(v.ptr()) || pyb::isinstance<pyb::str>(v))
        throw std::invalid_argument(field + ": expected a number");
      const double x = pyb::float_(pyb::reinterpret_borrow<pyb::object>(v));
      if (!std::isfinite(x)) throw std::invalid_argument(field + ": must be finite");
      d.*f.number = x;
      return;
    }
    case PhysicsField::Kind::kFlag:
      if (!is_bool && !pyb::isinstance(v, pyb::module_::import("numpy").attr("bool_")))
        throw std::invalid_argument(field + ": expected True or False");
      d.*f.flag = v.cast<bool>();
      return;
    case PhysicsField::Kind::kWhole: {
      if (is_bool || !PyIndex_Check(v.ptr()))
        throw std::invalid_argument(field + ": expected a whole number");
      const long long n = pyb::int_(pyb::reinterpret_borrow<pyb::object>(v));
      if (n < INT32_MIN || n > INT32_MAX) throw std::invalid_argument(field + ": out of range");
      d.*f.whole = static_cast<int>(n);
      return;
    }
    case PhysicsField::Kind::kChoice:
      if (!pyb::isinstance<pyb::str>(v)) throw std::invalid_argument(field + ": expected text");
      try {
        f.set(d, v.cast<std::string>());
      } catch (const std::invalid_argument& e) {
        throw std::invalid_argument(field + ": " + e.what());
      }
      return;
  }
}

PhysicsDef preset(const std::string& name) {
  try {
    return physics_preset(name);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(std::string("physics.preset: ") + e.what());
  }
}

// A treatment given with its law, as in configs: {"stimulus": name, "law": "integral" |
// "rate"}; the law is physics.growth, so a growth field beside it must agree. Checked as
// configs and robot files check it: unknown fields first, then a missing stimulus.
void set_treatment_and_law(PhysicsDef& d, const pyb::dict& t, const pyb::dict& fields) {
  for (const auto& [key, value] : t) {
    const std::string name = pyb::str(key).cast<std::string>();
    if (name != "stimulus" && name != "law")
      throw std::invalid_argument("physics.treatment." + name +
                                  ": unknown field (a treatment has stimulus and law)");
  }
  if (!t.contains("stimulus")) throw std::invalid_argument("physics.treatment.stimulus: missing");
  for (const auto& [key, value] : t) {
    const std::string name = pyb::str(key).cast<std::string>();
    if (!pyb::isinstance<pyb::str>(value))
      throw std::invalid_argument("physics.treatment." + name + ": expected text");
    try {
      if (name == "stimulus") d.treatment = parse_treatment(value.cast<std::string>());
      if (name == "law") {
        const GrowthModel law = parse_growth(value.cast<std::string>());
        if (fields.contains("growth") && pyb::isinstance<pyb::str>(fields["growth"]) &&
            parse_growth(fields["growth"].cast<std::string>()) != law)
          throw std::invalid_argument("contradicts physics.growth (give the law once)");
        d.growth = law;
      }
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument("physics.treatment." + name + ": " + e.what());
    }
  }
}

// Whether `fields` names `key`, the treatment or the task (None names none: the robot's stays).
bool names(const pyb::dict& fields, const char* key) {
  return fields.contains(key) && !fields[key].is_none();
}

// d with the fields of `fields` applied ("preset" first, when given: with_preset, as
// resolve_physics applies it), validated.
PhysicsDef with_fields(PhysicsDef d, const pyb::dict& fields) {
  for (const auto& [key, value] : fields) {
    if (!pyb::isinstance<pyb::str>(key))
      throw pyb::type_error("physics: field names must be text, got " +
                            pyb::repr(key).cast<std::string>());
    if (key.cast<std::string>() != "preset") continue;
    if (!pyb::isinstance<pyb::str>(value))
      throw std::invalid_argument("physics.preset: expected a preset's name");
    try {
      d = with_preset(d, value.cast<std::string>());
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(std::string("physics.preset: ") + e.what());
    }
  }
  for (const auto& [key, value] : fields) {
    const std::string name = key.cast<std::string>();
    if (name == "preset" || ((name == "treatment" || name == "task") && value.is_none())) continue;
    if (name == "environment") {
      set_environment(d, value);
      continue;
    }
    if (name == "task" && pyb::isinstance<pyb::dict>(value)) {
      set_task_with_params(d, value);
      continue;
    }
    if (name == "treatment" && pyb::isinstance<pyb::dict>(value)) {
      set_treatment_and_law(d, value.cast<pyb::dict>(), fields);
      continue;
    }
    const PhysicsField* f = find_field(name);
    if (!f) throw InputError("physics." + name + ": unknown field");
    const Task before = d.task;
    set_field(d, *f, value);
    if (d.task != before) d.task_params.clear();  // they were the other task's
  }
  validate(d);
  return d;
}

pyb::dict to_dict(const PhysicsDef& d) {
  pyb::dict out;
  for (const PhysicsField& f : kPhysicsFields) out[f.name] = field_value(d, f);
  if (d.environment.active()) out["environment"] = environment_value(d);  // as files write it
  return out;
}

// A PhysicsDef's field as Python reads it: the treatment or task is None when it names none.
pyb::object py_field_value(const PyPhysics& d, const PhysicsField& f) {
  if (!d.treatment_named && std::strcmp(f.name, "treatment") == 0) return pyb::none();
  if (!d.task_named && std::strcmp(f.name, "task") == 0) return pyb::none();
  return field_value(d, f);
}

pyb::dict py_dict(const PyPhysics& d) {
  pyb::dict out = to_dict(d);
  // Applied as a dict, None keeps the robot's.
  if (!d.treatment_named) out["treatment"] = pyb::none();
  if (!d.task_named) out["task"] = pyb::none();
  return out;
}

// d with `fields` applied; the treatment (task) is named once a field names it, and unnamed
// again by "treatment" ("task"): None (back to the preset's, none (walk), until it is passed).
PyPhysics py_with_fields(const PyPhysics& d, const pyb::dict& fields) {
  PyPhysics out{{with_fields(d, fields)}, d.treatment_named, d.task_named};
  if (fields.contains("treatment")) out.treatment_named = names(fields, "treatment");
  if (fields.contains("task")) out.task_named = names(fields, "task");
  if (!out.treatment_named) out.treatment = Treatment::kNone;
  if (!out.task_named) {
    out.task = Task::kWalk;
    out.task_params.clear();
  }
  return out;
}

}  // namespace

bool same_physics(const PhysicsDef& a, const PhysicsDef& b) {
  if (!(a.environment == b.environment) || a.task_params != b.task_params) return false;
  for (const PhysicsField& f : kPhysicsFields) {
    switch (f.kind) {
      case PhysicsField::Kind::kNumber:
        if (std::memcmp(&(a.*f.number), &(b.*f.number), sizeof(double)) != 0) return false;
        break;
      case PhysicsField::Kind::kFlag:
        if (a.*f.flag != b.*f.flag) return false;
        break;
      case PhysicsField::Kind::kWhole:
        if (a.*f.whole != b.*f.whole) return false;
        break;
      case PhysicsField::Kind::kChoice:
        if (std::strcmp(f.get(a), f.get(b)) != 0) return false;
        break;
    }
  }
  return true;
}

void hash_physics(const PhysicsDef& d, Hasher& h) {
  // The flat floor and a task without parameters hash as before.
  if (d.environment.active() || !d.task_params.empty()) h.str(physics_to_json(d));
  for (const PhysicsField& f : kPhysicsFields) {
    h.str(f.name);
    switch (f.kind) {
      case PhysicsField::Kind::kNumber:
        h.f64(d.*f.number);
        break;
      case PhysicsField::Kind::kFlag:
        h.u64(d.*f.flag ? 1 : 0);
        break;
      case PhysicsField::Kind::kWhole:
        h.u64(static_cast<uint64_t>(d.*f.whole));
        break;
      case PhysicsField::Kind::kChoice:
        h.str(f.get(d));
        break;
    }
  }
}

PhysicsDef physics_from(const pyb::handle& fields, const std::string& what) {
  if (!pyb::isinstance<pyb::dict>(fields))
    throw InputError(what + ": physics: expected a dict of fields");
  try {
    return with_fields(PhysicsDef{}, fields.cast<pyb::dict>());
  } catch (const std::exception& e) {
    throw InputError(what + ": " + e.what());
  }
}

pyb::dict physics_dict(const PhysicsDef& d) {
  return to_dict(d);
}

PhysicsDef physics_of_call(const PhysicsDef& base, const pyb::object& physics,
                           const std::optional<std::string>& treatment,
                           const std::optional<std::string>& task) {
  PhysicsRequest request;  // io's one rule; Python only translates its arguments
  nlohmann::json fields = nlohmann::json::object();
  if (pyb::isinstance<PyPhysics>(physics)) {  // as a preset, with what it names
    const PyPhysics& given = physics.cast<const PyPhysics&>();
    request.whole = static_cast<const PhysicsDef&>(given);
    if (given.treatment_named) fields["treatment"] = to_string(given.treatment);
    if (given.task_named) fields["task"] = json_field::task_json(given.task, given.task_params);
  } else if (pyb::isinstance<pyb::dict>(physics)) {
    for (const auto& [key, value] : physics.cast<pyb::dict>()) {
      if (!pyb::isinstance<pyb::str>(key))
        throw pyb::type_error("physics: field names must be text, got " +
                              pyb::repr(key).cast<std::string>());
      const std::string name = key.cast<std::string>();
      if ((name == "treatment" || name == "task") && value.is_none()) continue;  // the robot's
      if (name == "environment" && value.is_none()) {  // the flat floor, an empty environment
        fields[name] = nlohmann::json::object();
        continue;
      }
      fields[name] = to_json(value, "physics." + name);
    }
  } else if (!physics.is_none()) {
    throw pyb::type_error("physics: expected a PhysicsDef or a dict of its fields, got " +
                          pyb::str(physics.get_type().attr("__name__")).cast<std::string>());
  }
  if (!fields.empty()) request.fields = fields.dump();
  if (treatment) request.treatment = parse_treatment(*treatment);
  try {
    if (task) request.task = parse_task(*task);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(std::string("physics.task: ") + e.what());
  }
  try {
    return resolve_physics(base, request);
  } catch (const InputError& e) {
    // "physics: physics.duration: ..." names the field twice; Python's errors name it once.
    const std::string_view what = e.what(), source = "physics: ";
    if (what.starts_with(source)) throw InputError(std::string(what.substr(source.size())));
    throw;
  }
}

void bind_physics(pyb::module_& m) {
  pyb::class_<PyPhysics> c(m, "PhysicsDef",
                           "Every physics field of a simulation (see plastivox.PhysicsDef).");
  c.def(pyb::init([](const std::string& name, const pyb::kwargs& fields) {
          return py_with_fields(PyPhysics{{preset(name)}, false, false}, fields);
        }),
        pyb::arg("preset") = "gecco2018-code");
  for (const PhysicsField& field : kPhysicsFields) {
    const PhysicsField* f = &field;  // the table outlives the module
    c.def_property(
        f->name, [f](const PyPhysics& d) { return py_field_value(d, *f); },
        [f](PyPhysics& d, const pyb::object& v) {
          // As with_physics({name: v}) applies it: a task or treatment object too.
          d = py_with_fields(d, pyb::dict(pyb::arg(f->name) = v));
        });
  }
  c.def_property(
      "environment", [](const PyPhysics& d) { return environment_value(d); },
      [](PyPhysics& d, const pyb::object& v) {
        PyPhysics changed = d;
        set_environment(changed, v);
        validate(changed);
        d = changed;
      });
  c.def("__getitem__",
        [](const PyPhysics& d, const std::string& name) {
          if (name == "environment") return environment_value(d);
          const PhysicsField* f = find_field(name);
          if (!f) throw pyb::key_error(name);
          return py_field_value(d, *f);
        })
      .def("__contains__",
           [](const PyPhysics&, const pyb::object& name) {
             return pyb::isinstance<pyb::str>(name) && (name.cast<std::string>() == "environment" ||
                                                        find_field(name.cast<std::string>()));
           })
      .def("__len__", [](const PyPhysics& d) { return pyb::len(py_dict(d)); })
      .def("keys", [](const PyPhysics& d) { return py_dict(d).attr("keys")(); })
      .def("__iter__", [](const PyPhysics& d) { return pyb::iter(py_dict(d)); })
      .def("items", [](const PyPhysics& d) { return py_dict(d).attr("items")(); })
      .def("to_dict", &py_dict)
      .def("replace",
           [](const PyPhysics& d, const pyb::kwargs& fields) { return py_with_fields(d, fields); })
      .def("__eq__",
           [](const PyPhysics& d, const pyb::object& other) -> pyb::object {
             if (pyb::isinstance<PyPhysics>(other)) {
               const PyPhysics& o = other.cast<const PyPhysics&>();
               return pyb::bool_(same_physics(d, o) && d.treatment_named == o.treatment_named &&
                                 d.task_named == o.task_named);
             }
             if (pyb::isinstance<pyb::dict>(other)) return py_dict(d).attr("__eq__")(other);
             return pyb::reinterpret_borrow<pyb::object>(Py_NotImplemented);
           })
      .def("__copy__", [](const PyPhysics& d) { return d; })
      .def("__deepcopy__", [](const PyPhysics& d, const pyb::object&) { return d; })
      .def("__repr__",
           [](const PyPhysics& d) {
             std::string s = "PhysicsDef(";
             for (const PhysicsField& f : kPhysicsFields)
               s += std::string(&f == &kPhysicsFields[0] ? "" : ", ") + f.name + "=" +
                    pyb::repr(py_field_value(d, f)).cast<std::string>();
             if (d.environment.active())
               s += ", environment=" + pyb::repr(environment_value(d)).cast<std::string>();
             return s + ")";
           })
      .def(pyb::pickle(&py_dict, [](const pyb::dict& fields) {
        return PyPhysics{{physics_from(fields, "PhysicsDef pickle")},
                         names(fields, "treatment"),
                         names(fields, "task")};
      }));
  c.attr("__hash__") = pyb::none();  // mutable
}

}  // namespace plastivox::py
