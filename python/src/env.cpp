// The engine side of plastivox.VoxelEnv (python/plastivox/_env.py, docs/python.md): one life
// stepped by actions; the Simulator keeps the watches in its State as simulate() does, so the
// task's fitness so far is known after every step and the last one is simulate()'s, bit for
// bit. One call per environment step: the action checked and held, `every` engine steps
// taken, the observation assembled. A single Episode keeps the GIL (a step is short), so it
// is never stepped by two threads at once; a batch (plastivox.VoxelVecEnv) steps its
// environments on threads with the GIL released, through the same EpisodeCore.
#include <algorithm>
#include <atomic>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <pybind11/stl.h>

#include "bindings.hpp"
#include "plastivox/base/parallel.hpp"
#include "plastivox/control.hpp"
#include "plastivox/io/limits.hpp"
#include "plastivox/rules/life_rules.hpp"
#include "plastivox/simulator.hpp"
#include "plastivox/task.hpp"

namespace plastivox::py {
namespace {

// What ends an episode, as the batch reports it (VoxelVecEnv maps it to terminated and
// truncated); the single Episode names it as a string.
enum class EpisodeEnd : int8_t { kRunning = 0, kFinished = 1, kUnstable = 2, kSank = 3 };

const char* end_name(EpisodeEnd e) {
  switch (e) {
    case EpisodeEnd::kFinished:
      return "finished";
    case EpisodeEnd::kUnstable:
      return "unstable";
    case EpisodeEnd::kSank:
      return "sank";
    case EpisodeEnd::kRunning:
      break;
  }
  return "running";
}

// One life stepped by actions, touching no Python object, so that a batch can step many on
// threads with the GIL released. The single Episode and the batch both step through this
// class, so an environment in a batch takes the very steps it takes alone.
class EpisodeCore {
 public:
  EpisodeCore(std::shared_ptr<const Model> model, const std::vector<const SensorField*>& observed,
              int obs_size, int every)
      : model_(std::move(model)),
        sim_(*model_),
        every_(every),
        observed_(observed),
        obs_size_(obs_size) {
    sim_.set_controller(nullptr);  // the actions drive the robot
  }

  // Back to t = 0.
  void reset() {
    sim_.reset();
    fitness_ = 0;
    end_ = EpisodeEnd::kRunning;
  }

  // Holds the robot_n values at u for `every` steps (fewer when the life ends). The episode
  // must be running (the callers check, with the GIL held).
  void step(const double* u) {
    // The robot's voxels only: the free objects that follow (Model::robot_n) do not actuate.
    std::copy(u, u + model_->robot_n, sim_.actuation().begin());
    const State& s = sim_.state();
    const PhysicsDef& def = model_->def;
    for (int k = 0; k < every_ && s.status == SimStatus::kRunning; ++k) {
      sim_.step();
      if (ends_invalid(def, has_sunk(*model_, s))) break;  // judge_life would make this life 0
    }
    // A life that is over is judged as plastivox simulate and evolution judge it; one running
    // ends invalid (fitness 0) once it is certain to be judged sunk.
    SimResult life;
    if (s.status != SimStatus::kRunning) {
      life = sim_.result();
      judge_life(def, life);
    }
    const bool sank = ends_invalid(def, has_sunk(*model_, s)) ||
                      (s.status == SimStatus::kFinished && life.status != SimStatus::kFinished);
    fitness_ = sank                              ? 0.0
               : s.status == SimStatus::kRunning ? fitness_so_far(*model_, s)
                                                 : life.fitness;
    if (s.status == SimStatus::kUnstable)
      end_ = EpisodeEnd::kUnstable;
    else if (sank)
      end_ = EpisodeEnd::kSank;
    else if (s.status == SimStatus::kFinished)
      end_ = EpisodeEnd::kFinished;
  }

  // The observed sensors of the present step, one after another, each flat in voxel order,
  // written to out[0, obs_size).
  void observe(double* out) {
    const Sensors sensors = sim_.sensors();
    for (const SensorField* f : observed_) {
      const std::span<const double> v = sensors.read(f->id);
      out = std::copy(v.begin(), v.end(), out);
    }
  }

  double fitness() const { return fitness_; }
  EpisodeEnd end() const { return end_; }
  const Simulator& sim() const { return sim_; }
  const Model& model() const { return *model_; }
  const std::shared_ptr<const Model>& model_ptr() const { return model_; }

 private:
  std::shared_ptr<const Model> model_;
  Simulator sim_;
  int every_;
  std::vector<const SensorField*> observed_;
  int obs_size_;
  double fitness_ = 0;
  EpisodeEnd end_ = EpisodeEnd::kRunning;
};

// The compiled model and the observed sensors an Episode or a batch is built from.
struct EpisodeSpec {
  std::shared_ptr<const Model> model;
  std::vector<const SensorField*> observed;
  int obs_size = 0;
  int every = 1;
};

EpisodeSpec episode_spec(const PyRobot& robot, const pyb::object& physics,
                         const std::optional<std::string>& treatment,
                         const std::optional<std::string>& task,
                         const std::vector<std::string>& sensors, int every) {
  EpisodeSpec spec;
  spec.model = std::make_shared<const Model>(
      compile(robot.def, physics_of_call(robot.physics, physics, treatment, task),
              limits_from_environment()));
  if (every < 1) throw std::invalid_argument("every: must be a number of steps >= 1");
  if (sensors.empty()) throw std::invalid_argument("sensors: name at least one sensor");
  for (const std::string& name : sensors) {
    const SensorField& f = sensor_named(name, "sensors");
    spec.observed.push_back(&f);
    spec.obs_size += f.per_voxel ? spec.model->n * f.width : f.width;
  }
  spec.every = every;
  return spec;
}

class PyEpisode {
 public:
  explicit PyEpisode(const EpisodeSpec& spec)
      : core_(spec.model, spec.observed, spec.obs_size, spec.every), obs_size_(spec.obs_size) {}

  // Back to t = 0; the first observation.
  pyb::array_t<double> reset() {
    core_.reset();
    return observe();
  }

  // Holds `action` for `every` steps (fewer when the life ends). Returns
  // (observation, fitness so far, how the episode stands: "running", "finished",
  // "unstable" or "sank").
  pyb::tuple step(const pyb::handle& action) {
    if (core_.end() != EpisodeEnd::kRunning)
      throw std::runtime_error(std::string("step: the episode is over (") + end_name(core_.end()) +
                               "); call reset()");
    const std::vector<double> u = checked_actuation(action, core_.model().robot_n, "action");
    core_.step(u.data());
    return pyb::make_tuple(observe(), core_.fitness(), end_name(core_.end()));
  }

  // The present state as an (h, w, 3) uint8 picture (VoxelEnv.render).
  pyb::array_t<uint8_t> render(int width, int height) {
    return painter_.draw(core_.model_ptr(), core_.sim().state(), width, height);
  }

  int voxels() const { return core_.model().n; }              // every per-voxel sensor's rows
  int robot_voxels() const { return core_.model().robot_n; }  // the action's values
  int obs_size() const { return obs_size_; }
  double fitness() const { return core_.fitness(); }
  const Simulator& sim() const { return core_.sim(); }
  const Model& model() const { return core_.model(); }

 private:
  pyb::array_t<double> observe() {
    pyb::array_t<double> obs(obs_size_);
    core_.observe(obs.mutable_data());
    return obs;
  }

  EpisodeCore core_;
  int obs_size_;
  StatePainter painter_;
};

// N lives of one robot (one compiled Model, a Simulator each), stepped together: one call
// checks the (N, robot voxels) actions, then steps the environments on parallel_for's threads
// with the GIL released, each writing only its own row of the outputs, so the results are the
// same bits on any number of threads (plastivox.VoxelVecEnv, python/plastivox/_env.py).
class PyEpisodeBatch {
 public:
  PyEpisodeBatch(const EpisodeSpec& spec, int num_envs, int threads)
      : obs_size_(spec.obs_size), threads_(threads) {
    if (num_envs < 1)
      throw std::invalid_argument("num_envs: expected a number of environments >= 1, got " +
                                  std::to_string(num_envs));
    if (threads < 0) throw std::invalid_argument("threads: must be >= 0 (0: all cores)");
    envs_.reserve(static_cast<size_t>(num_envs));
    for (int i = 0; i < num_envs; ++i)
      envs_.push_back(
          std::make_unique<EpisodeCore>(spec.model, spec.observed, spec.obs_size, spec.every));
  }

  // Resets the environments whose `which` entry is true (all when `which` is None) and
  // steps the others with their rows of `actions` (ignored for those reset). Returns
  // (observations (N, obs), fitness so far (N,), end codes (N,) int8: 0 running, 1 finished,
  // 2 unstable, 3 sank); a reset environment reads 0 and 0.
  pyb::tuple advance(const pyb::object& actions, const pyb::object& which) {
    // One call at a time: a second Python thread would step the same Simulators while this
    // call runs without the GIL. It gets a clear error instead (as a Simulator's does).
    if (busy_.exchange(true))
      throw std::runtime_error(
          "VoxelVecEnv: in use by another thread; give each thread its own VoxelVecEnv");
    struct Release {
      std::atomic<bool>& flag;
      ~Release() { flag = false; }
    } release{busy_};
    const size_t n = envs_.size();
    const int a = envs_[0]->model().robot_n;
    std::vector<uint8_t> reset(n, 1);
    if (!which.is_none()) {
      const auto w = pyb::array_t<bool, pyb::array::c_style | pyb::array::forcecast>(which);
      if (w.ndim() != 1 || static_cast<size_t>(w.shape(0)) != n)
        throw std::invalid_argument("reset mask: expected shape (" + std::to_string(n) + ",)");
      for (size_t i = 0; i < n; ++i) reset[i] = w.data()[i] ? 1 : 0;
    }
    std::vector<double> u;
    if (!actions.is_none()) u = checked_actions(actions, static_cast<int>(n), a);
    // Stepping an environment whose episode is over is the caller's error, found before any
    // environment moves.
    for (size_t i = 0; i < n; ++i)
      if (!reset[i] && envs_[i]->end() != EpisodeEnd::kRunning)
        throw std::runtime_error("step: environment " + std::to_string(i) + "'s episode is over (" +
                                 end_name(envs_[i]->end()) + "); reset it");
    pyb::array_t<double> obs({static_cast<pyb::ssize_t>(n), static_cast<pyb::ssize_t>(obs_size_)});
    pyb::array_t<double> fitness(static_cast<pyb::ssize_t>(n));
    pyb::array_t<int8_t> ends(static_cast<pyb::ssize_t>(n));
    double* o = obs.mutable_data();
    double* f = fitness.mutable_data();
    int8_t* e = ends.mutable_data();
    {
      pyb::gil_scoped_release unlocked;
      parallel_for(n, threads_ == 0 ? hardware_threads() : threads_, [&](size_t i) {
        EpisodeCore& env = *envs_[i];
        if (reset[i])
          env.reset();
        else
          env.step(u.data() + i * static_cast<size_t>(a));
        env.observe(o + i * static_cast<size_t>(obs_size_));
        f[i] = env.fitness();
        e[i] = static_cast<int8_t>(env.end());
      });
    }
    return pyb::make_tuple(obs, fitness, ends);
  }

  size_t size() const { return envs_.size(); }
  // Environment i, for reading its state; refused while a step runs on another thread.
  const EpisodeCore& env(size_t i) const {
    if (busy_)
      throw std::runtime_error(
          "VoxelVecEnv: in use by another thread; give each thread its own VoxelVecEnv");
    return *envs_.at(i);
  }

 private:
  // An (N, A) float array with every value in [-1, 1], as a flat row-major copy.
  static std::vector<double> checked_actions(const pyb::object& given, int n, int a) {
    const pyb::array arr = pyb::array::ensure(given);
    if (!arr)
      throw pyb::type_error("actions: expected a numpy array of floats, got " +
                            std::string(pyb::str(given.get_type().attr("__name__"))));
    if (arr.dtype().kind() != 'f')
      throw pyb::type_error("actions: expected a float array (float64 or float32), got dtype " +
                            std::string(pyb::str(arr.dtype())));
    if (arr.ndim() != 2 || arr.shape(0) != n || arr.shape(1) != a) {
      std::string shape = "(";
      for (pyb::ssize_t d = 0; d < arr.ndim(); ++d)
        shape += (d ? ", " : "") + std::to_string(arr.shape(d));
      shape += arr.ndim() == 1 ? ",)" : ")";
      throw std::invalid_argument(
          "actions: expected shape (" + std::to_string(n) + ", " + std::to_string(a) +
          "), one row per environment and one value per voxel, got " + shape);
    }
    // Each row checked as a single environment's action is (values in [-1, 1]).
    std::vector<double> out;
    out.reserve(static_cast<size_t>(n) * static_cast<size_t>(a));
    for (int i = 0; i < n; ++i) {
      const std::vector<double> row =
          checked_actuation(arr[pyb::int_(i)], a, "actions[" + std::to_string(i) + "]");
      out.insert(out.end(), row.begin(), row.end());
    }
    return out;
  }

  std::vector<std::unique_ptr<EpisodeCore>> envs_;
  int obs_size_;
  int threads_;
  std::atomic<bool> busy_{false};
};

}  // namespace

void bind_env(pyb::module_& m) {
  pyb::class_<PyEpisode>(m, "Episode")
      .def(pyb::init([](const PyRobot& robot, const pyb::object& physics,
                        const std::optional<std::string>& treatment,
                        const std::optional<std::string>& task,
                        const std::vector<std::string>& sensors, int every) {
             return std::make_unique<PyEpisode>(
                 episode_spec(robot, physics, treatment, task, sensors, every));
           }),
           pyb::arg("robot"), pyb::arg("physics"), pyb::arg("treatment"), pyb::arg("task"),
           pyb::arg("sensors"), pyb::arg("every"))
      .def("reset", &PyEpisode::reset)
      .def("step", &PyEpisode::step, pyb::arg("action"))
      .def("render", &PyEpisode::render, pyb::arg("width"), pyb::arg("height"))
      .def_property_readonly("voxels", &PyEpisode::voxels)
      .def_property_readonly("robot_voxels", &PyEpisode::robot_voxels)
      .def_property_readonly("obs_size", &PyEpisode::obs_size)
      .def_property_readonly("fitness", &PyEpisode::fitness)
      .def_property_readonly("time", [](const PyEpisode& e) { return e.sim().state().time; })
      .def_property_readonly("steps", [](const PyEpisode& e) { return e.sim().state().steps; })
      .def_property_readonly("failure", [](const PyEpisode& e) { return e.sim().state().failure; })
      .def_property_readonly("duration", [](const PyEpisode& e) { return e.model().def.duration; })
      .def_property_readonly("dt", [](const PyEpisode& e) { return e.sim().state().dt; })
      .def_property_readonly("act_frequency",
                             [](const PyEpisode& e) { return e.model().def.act_frequency; })
      .def_property_readonly("voxel_phase",
                             [](const PyEpisode& e) { return robot_phase(e.model()); })
      .def_property_readonly("task",
                             [](const PyEpisode& e) { return to_string(e.model().def.task); })
      .def_property_readonly("state_hash",
                             [](const PyEpisode& e) { return state_hash(e.sim().state()); });

  pyb::class_<PyEpisodeBatch>(m, "EpisodeBatch")
      .def(pyb::init([](const PyRobot& robot, const pyb::object& physics,
                        const std::optional<std::string>& treatment,
                        const std::optional<std::string>& task,
                        const std::vector<std::string>& sensors, int every, int num_envs,
                        int threads) {
             return std::make_unique<PyEpisodeBatch>(
                 episode_spec(robot, physics, treatment, task, sensors, every), num_envs, threads);
           }),
           pyb::arg("robot"), pyb::arg("physics"), pyb::arg("treatment"), pyb::arg("task"),
           pyb::arg("sensors"), pyb::arg("every"), pyb::arg("num_envs"), pyb::arg("threads"))
      .def("advance", &PyEpisodeBatch::advance, pyb::arg("actions"), pyb::arg("reset"))
      .def_property_readonly("num_envs", &PyEpisodeBatch::size)
      .def("time", [](const PyEpisodeBatch& b, size_t i) { return b.env(i).sim().state().time; })
      .def("steps", [](const PyEpisodeBatch& b, size_t i) { return b.env(i).sim().state().steps; })
      .def("failure",
           [](const PyEpisodeBatch& b, size_t i) { return b.env(i).sim().state().failure; })
      .def("state_hash",
           [](const PyEpisodeBatch& b, size_t i) { return state_hash(b.env(i).sim().state()); });
}

}  // namespace plastivox::py
