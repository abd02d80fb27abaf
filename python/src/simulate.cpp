// Simulation for Python: a whole life (simulate), many lives on C++ threads
// (simulate_many) and step-wise control (Simulator). Each life runs on one thread with the
// GIL released, so results are the bits `plastivox simulate` gives, whatever the threads.
#include <chrono>
#include <memory>
#include <mutex>
#include <string_view>

#include <pybind11/stl.h>

#include "bindings.hpp"
#include "plastivox/base/parallel.hpp"
#include "plastivox/io/limits.hpp"
#include "plastivox/io/robot_io.hpp"  // warn_vxa_density
#include "plastivox/io/sim_summary.hpp"
#include "plastivox/model_fields.hpp"
#include "plastivox/rules/life_rules.hpp"
#include "plastivox/simulator.hpp"
#include "plastivox_version.hpp"

namespace plastivox::py {
namespace {

// What a call records: frames at record_fps (0: none), with the control channels when
// asked; checked here and nowhere else.
SimOptions recording(double record_fps, bool record_control) {
  if (!(record_fps >= 0 && record_fps <= 1e6))
    throw std::invalid_argument("record_fps: must be in [0, 1e6] frames per second");
  if (record_control && !(record_fps > 0))
    throw std::invalid_argument("record_control: records frames' channels: give record_fps > 0");
  SimOptions o;
  o.record_fps = record_fps;
  o.record_control = record_control;
  return o;
}

// One simulated life as the Python layer receives it: the summary's fields (the keys of
// `simulate --json`, from sim_summary_fields; final_stiffness as an array) as a dict, and,
// when recorded, the trajectory arrays.
pyb::tuple life_to_python(const SimResult& r, const std::vector<SummaryField>& fields) {
  pyb::dict summary;
  for (const SummaryField& f : fields)
    std::visit(
        [&](const auto& v) {
          if constexpr (std::is_same_v<std::decay_t<decltype(v)>, std::vector<double>>)
            summary[f.name] = to_array(v);
          else
            summary[f.name] = pyb::cast(v);
        },
        f.value);
  if (r.recording.frames.empty()) return pyb::make_tuple(summary, pyb::none());
  const auto& frames = r.recording.frames;
  const pyb::ssize_t t_count = static_cast<pyb::ssize_t>(frames.size());
  const pyb::ssize_t n = static_cast<pyb::ssize_t>(frames[0].pos.size());
  pyb::array_t<double> times(t_count);
  for (pyb::ssize_t t = 0; t < t_count; ++t) times.mutable_at(t) = frames[t].time;
  pyb::dict traj;
  traj["times"] = times;
  for (const auto* table : {&kFrameFields, &kControlFrameFields}) {
    if (table == &kControlFrameFields && !r.recording.control) break;
    for (const FrameField& f : *table) {  // (T, n[, width]), as a life file holds them
      std::vector<pyb::ssize_t> shape = {t_count, n};
      if (f.width > 1) shape.push_back(f.width);
      pyb::array_t<double> a(shape);
      const std::vector<double> values = frame_channel(frames, f);
      std::copy(values.begin(), values.end(), a.mutable_data());
      traj[f.python] = a;
    }
  }
  return pyb::make_tuple(summary, traj);
}

// (summary, trajectory, seconds): seconds is the wall time of the work `plastivox simulate
// --json` does in C++ for this life (resolve the physics, compile, simulate, build the
// summary), so bench/python_bench.py can set the whole Python call against it.
pyb::tuple simulate_one(const PyRobot& robot, const pyb::object& physics_arg,
                        const std::optional<std::string>& treatment,
                        const std::optional<std::string>& task, double record_fps,
                        bool record_control) {
  const auto t0 = std::chrono::steady_clock::now();
  const PhysicsDef physics = physics_of_call(robot.physics, physics_arg, treatment, task);
  const SimOptions options = recording(record_fps, record_control);
  SimResult r;
  {
    pyb::gil_scoped_release unlocked;
    const Limits limits = limits_from_environment();
    const Model model = compile(robot.def, physics, limits);
    // Refused before the life is simulated, not when memory runs out: the frames and the
    // numpy arrays made from them are held at once.
    if (record_fps > 0)
      check_recording_size(
          2 * recording_bytes(model.n, physics.duration, record_fps, record_control), "record_fps",
          limits.recording_mb);
    r = simulate(model, options);
  }
  judge_life(physics, r);  // as plastivox simulate judges it
  warn_vxa_density(r, robot.source, robot.physics.density, physics, robot.def.voxel_size);
  const std::vector<SummaryField> summary =
      sim_summary_fields(r, physics, robot.source, PLASTIVOX_VERSION);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  pyb::tuple life = life_to_python(r, summary);
  return pyb::make_tuple(life[0], life[1], seconds);
}

pyb::list simulate_many(const std::vector<const PyRobot*>& robots, const pyb::object& physics_arg,
                        const std::optional<std::string>& treatment,
                        const std::optional<std::string>& task, double record_fps,
                        bool record_control, int threads) {
  if (threads < 0) throw std::invalid_argument("threads: must be >= 0 (0: all cores)");
  const SimOptions options = recording(record_fps, record_control);
  const Limits limits = limits_from_environment();
  std::vector<PhysicsDef> physics;
  physics.reserve(robots.size());
  double recorded = 0;  // every life's frames (and arrays) are held at once, until returned
  for (const PyRobot* r : robots) {
    physics.push_back(physics_of_call(r->physics, physics_arg, treatment, task));
    if (record_fps > 0)
      recorded +=
          2 * recording_bytes(r->def.voxel_count() + object_voxels(physics.back().environment),
                              physics.back().duration, record_fps, record_control);
  }
  check_recording_size(recorded, "record_fps", limits.recording_mb);
  std::vector<SimResult> results(robots.size());
  std::vector<std::vector<SummaryField>> summaries(robots.size());
  {
    // The summaries are built on the workers too: only making the Python objects needs the
    // GIL, and what stays serial bounds the speed-up (docs/benchmarks.md, "Python module").
    pyb::gil_scoped_release unlocked;
    parallel_for(robots.size(), threads == 0 ? hardware_threads() : threads, [&](size_t i) {
      results[i] = simulate(compile(robots[i]->def, physics[i], limits), options);
      judge_life(physics[i], results[i]);
      warn_vxa_density(results[i], robots[i]->source, robots[i]->physics.density, physics[i],
                       robots[i]->def.voxel_size);
      summaries[i] =
          sim_summary_fields(results[i], physics[i], robots[i]->source, PLASTIVOX_VERSION);
    });
  }
  pyb::list out;
  for (size_t i = 0; i < robots.size(); ++i) out.append(life_to_python(results[i], summaries[i]));
  return out;
}

// A field's numpy dtype: its kind and value size (StateFieldBytes).
pyb::dtype field_dtype(const StateFieldBytes& b) {
  if (b.kind == 'b') return pyb::dtype::of<bool>();
  return pyb::dtype(std::string(1, b.kind) + std::to_string(b.value_bytes));
}

// A field's numpy shape: () for one value, (count,) for a fixed vector or one value per
// voxel or bond, (entries, width) for a vector or quaternion per voxel.
template <class Row>
std::vector<pyb::ssize_t> field_shape(const Row& f, const StateFieldBytes& b) {
  const auto count = static_cast<pyb::ssize_t>(b.count);
  const auto width = static_cast<pyb::ssize_t>(b.width);
  if (std::string(f.shape) == "1") return {};
  if (std::string(f.shape).find(" x ") != std::string::npos) return {count / width, width};
  return {count};
}

// A field of s (a State, or a Model) as a numpy array: a view of s's memory that keeps `base`
// alive, or, with a null base, a copy.
template <class S>
pyb::array field_array(const FieldRow<S>& f, const S& s, const pyb::handle& base) {
  const StateFieldBytes b = f.bytes(s);
  return pyb::array(field_dtype(b), field_shape(f, b), {}, b.data, base);
}

// Step-wise control: the model is compiled once and owned here, the Simulator reads it.
class PySimulator {
 public:
  PySimulator(const PyRobot& robot, const pyb::object& physics_arg,
              const std::optional<std::string>& treatment)
      : model_(std::make_shared<const Model>(
            compile(robot.def, physics_of_call(robot.physics, physics_arg, treatment, {}),
                    limits_from_environment()))),
        sim_(std::make_unique<Simulator>(*model_)),
        source_(robot.source),
        file_density_(robot.physics.density),
        voxel_size_(robot.def.voxel_size) {}

  // Advances up to n steps, stopping when the life is over (time past the duration, as in
  // simulate()) or unstable. Returns the steps taken.
  int64_t step(int64_t n) {
    if (n < 0) throw std::invalid_argument("n: must be >= 0");
    const Busy busy(*this);
    pyb::gil_scoped_release unlocked;
    int64_t done = 0;
    const State& s = sim_->state();
    while (done < n && s.status == SimStatus::kRunning) {
      sim_->step();
      ++done;
    }
    return done;
  }

  // The halves of one step (Simulator::step1 and step2; both do nothing once the life is
  // over). step1 changes no State.
  void step1() {
    const Busy busy(*this);
    pyb::gil_scoped_release unlocked;
    sim_->step1();
  }
  void step2() {
    const Busy busy(*this);
    pyb::gil_scoped_release unlocked;
    sim_->step2();
  }

  // Every read of the state comes here: refused while another thread steps (the state is
  // being written without the GIL).
  const State& state() const {
    const Busy busy(*this);
    return sim_->state();
  }
  const Model& model() const { return *model_; }
  const char* status() const { return to_string(state().status); }

  // Every field of kStateFields as a read-only numpy array that reads the Simulator's own
  // memory (no copy), `self` (this object) its base: the arrays keep it alive, and they stay
  // valid for its whole life, since the State's arrays never move (restore_state copies into
  // them). They show the state as it is when read: stepping changes what they hold.
  pyb::dict state_views(const pyb::object& self) const {
    const State& s = state();
    pyb::dict views;
    for (const StateField& f : kStateFields) {
      pyb::array a = field_array(f, s, self);
      a.attr("setflags")(pyb::arg("write") = false);
      views[f.name] = a;
    }
    return views;
  }

  // Every row of kModelFields as a read-only numpy view of the compiled model, which never
  // changes and lives as long as this object.
  pyb::dict model_views(const pyb::object& self) const {
    pyb::dict views;
    for (const ModelField& f : kModelFields) {
      pyb::array a = field_array(f, *model_, self);
      a.attr("setflags")(pyb::arg("write") = false);
      views[f.name] = a;
    }
    return views;
  }

  // A copy of one field, made while no other thread steps.
  pyb::array state_copy(const std::string& name) const {
    const State& s = state();
    for (const StateField& f : kStateFields)
      if (name == f.name) return field_array(f, s, pyb::handle());
    throw std::invalid_argument("state field: no field named '" + name + "'");
  }

  // Runs f on the engine Simulator, one user at a time (control.cpp).
  void use(const std::function<void(Simulator&)>& f) {
    const Busy busy(*this);
    f(*sim_);
  }

  // The life's summary so far (Simulator::result: final once the life is over), judged as
  // simulate() judges it (judge_life), and handed over as simulate() hands its summary over:
  // the same fields, the same bits but the wall time.
  pyb::dict result() const {
    SimResult r;
    {
      const Busy busy(*this);
      r = sim_->result();
    }
    judge_life(model_->def, r);  // as simulate() and plastivox simulate judge a life
    warn_vxa_density(r, source_, file_density_, model_->def, voxel_size_);
    return life_to_python(r, sim_summary_fields(r, model_->def, source_, PLASTIVOX_VERSION))[0]
        .cast<pyb::dict>();
  }

  pyb::bytes save_state() const {
    const Busy busy(*this);
    const std::vector<uint8_t> bytes = sim_->save_state();  // the State (signal included)
    return pyb::bytes(reinterpret_cast<const char*>(bytes.data()), bytes.size());
  }

  void restore_state(const pyb::bytes& snapshot) {
    const Busy busy(*this);
    const std::string_view view(snapshot);
    sim_->restore_state(std::vector<uint8_t>(view.begin(), view.end()));
  }

 private:
  // One user at a time. step() releases the GIL while it runs, so without this two Python
  // threads could step one Simulator at once (a crash, or a state no sequential run gives).
  // A second user gets a clear error instead of waiting: waiting here while holding the GIL
  // would deadlock with the stepping thread, which takes the GIL back before it is done.
  class Busy {
   public:
    explicit Busy(const PySimulator& s) : m_(s.in_use_) {
      if (!m_.try_lock())
        throw std::runtime_error(
            "Simulator: in use by another thread (step() is running); a Simulator must not be "
            "used from two threads at once: give each thread its own");
    }
    ~Busy() { m_.unlock(); }
    Busy(const Busy&) = delete;
    Busy& operator=(const Busy&) = delete;

   private:
    std::mutex& m_;
  };

  std::shared_ptr<const Model> model_;
  std::unique_ptr<Simulator> sim_;
  std::string source_;  // the robot's file or name, and its own density and voxel size: what
  double file_density_, voxel_size_;  // simulate()'s summary says of them
  mutable std::mutex in_use_;
};

pyb::list state_field_table() {
  return describe_fields(kStateFields);
}

pyb::list model_field_table() {
  return describe_fields(kModelFields);
}

}  // namespace

void bind_simulate(pyb::module_& m) {
  m.def("simulate", &simulate_one, pyb::arg("robot"), pyb::arg("physics"), pyb::arg("treatment"),
        pyb::arg("task"), pyb::arg("record_fps"), pyb::arg("record_control") = false);
  m.def("simulate_many", &simulate_many, pyb::arg("robots"), pyb::arg("physics"),
        pyb::arg("treatment"), pyb::arg("task"), pyb::arg("record_fps"), pyb::arg("record_control"),
        pyb::arg("threads"));
  auto simulator = pyb::class_<PySimulator>(m, "Simulator");
  simulator.def(pyb::init<const PyRobot&, const pyb::object&, const std::optional<std::string>&>())
      .def("step", &PySimulator::step, pyb::arg("n") = 1)
      .def("step1", &PySimulator::step1)
      .def("step2", &PySimulator::step2)
      .def_property_readonly("time", [](const PySimulator& s) { return s.state().time; })
      .def_property_readonly("steps", [](const PySimulator& s) { return s.state().steps; })
      .def_property_readonly("dt", [](const PySimulator& s) { return s.state().dt; })
      .def_property_readonly("duration",
                             [](const PySimulator& s) { return s.model().def.duration; })
      .def_property_readonly("status", &PySimulator::status)
      .def_property_readonly("failure", [](const PySimulator& s) { return s.state().failure; })
      .def_property_readonly("state_hash",
                             [](const PySimulator& s) { return state_hash(s.state()); })
      .def_property_readonly("voxel_mass", [](const PySimulator& s) { return s.model().mass; })
      .def_property_readonly("robot_voxels", [](const PySimulator& s) { return s.model().robot_n; })
      .def(
          "state_views",
          [](const pyb::object& self) { return self.cast<const PySimulator&>().state_views(self); })
      .def("state_copy", &PySimulator::state_copy, pyb::arg("name"))
      .def("result", &PySimulator::result)
      .def("save_state", &PySimulator::save_state)
      .def("restore_state", &PySimulator::restore_state, pyb::arg("snapshot"))
      .def_static("state_fields", &state_field_table)
      .def(
          "model_views",
          [](const pyb::object& self) { return self.cast<const PySimulator&>().model_views(self); })
      .def_static("model_fields", &model_field_table);
  const UseSimulator use = [](const pyb::handle& self, const std::function<void(Simulator&)>& f) {
    self.cast<PySimulator&>().use(f);
  };
  bind_control(m, simulator, use);
  bind_backward(simulator, use);
}

}  // namespace plastivox::py
