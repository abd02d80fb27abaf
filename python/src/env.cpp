// The engine side of plastivox.VoxelEnv (python/plastivox/_env.py, docs/python.md): one life
// stepped by actions; the Simulator keeps the watches in its State as simulate() does, so the
// task's fitness so far is known after every step and the last one is simulate()'s, bit for
// bit. One call
// per environment step: the action checked and held, `every` engine steps taken, the
// observation assembled. The GIL stays held (a step is short), so one Episode is never
// stepped by two threads at once.
#include <algorithm>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <pybind11/stl.h>

#include "bindings.hpp"
#include "plastivox/control.hpp"
#include "plastivox/io/limits.hpp"
#include "plastivox/rules/life_rules.hpp"
#include "plastivox/simulator.hpp"
#include "plastivox/task.hpp"

namespace plastivox::py {
namespace {

class PyEpisode {
 public:
  PyEpisode(const PyRobot& robot, const pyb::object& physics,
            const std::optional<std::string>& treatment, const std::optional<std::string>& task,
            const std::vector<std::string>& sensors, int every)
      : model_(std::make_shared<const Model>(
            compile(robot.def, physics_of_call(robot.physics, physics, treatment, task),
                    limits_from_environment()))),
        sim_(*model_),
        every_(every) {
    if (every < 1) throw std::invalid_argument("every: must be a number of steps >= 1");
    if (sensors.empty()) throw std::invalid_argument("sensors: name at least one sensor");
    for (const std::string& name : sensors) {
      const SensorField& f = sensor_named(name, "sensors");
      observed_.push_back(&f);
      obs_size_ += f.per_voxel ? model_->n * f.width : f.width;
    }
    sim_.set_controller(nullptr);  // the actions drive the robot
  }

  // Back to t = 0; the first observation.
  pyb::array_t<double> reset() {
    sim_.reset();
    fitness_ = 0;
    end_ = "";
    return observe();
  }

  // Holds `action` for `every` steps (fewer when the life ends). Returns
  // (observation, fitness so far, how the episode stands: "running", "finished",
  // "unstable" or "sank").
  pyb::tuple step(const pyb::handle& action) {
    if (!end_.empty())
      throw std::runtime_error("step: the episode is over (" + end_ + "); call reset()");
    // The robot's voxels only: the free objects that follow (Model::robot_n) do not actuate.
    const std::vector<double> u = checked_actuation(action, model_->robot_n, "action");
    std::copy(u.begin(), u.end(), sim_.actuation().begin());
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
      end_ = "unstable";
    else if (sank)
      end_ = "sank";
    else if (s.status == SimStatus::kFinished)
      end_ = "finished";
    return pyb::make_tuple(observe(), fitness_, end_.empty() ? "running" : end_);
  }

  // The present state as an (h, w, 3) uint8 picture (VoxelEnv.render).
  pyb::array_t<uint8_t> render(int width, int height) {
    return painter_.draw(model_, sim_.state(), width, height);
  }

  int voxels() const { return model_->n; }              // every per-voxel sensor's rows
  int robot_voxels() const { return model_->robot_n; }  // the action's values
  int obs_size() const { return obs_size_; }
  double fitness() const { return fitness_; }
  const Simulator& sim() const { return sim_; }
  const Model& model() const { return *model_; }

 private:
  // The observed sensors of the present step, one after another, each flat in voxel order.
  pyb::array_t<double> observe() {
    pyb::array_t<double> obs(obs_size_);
    double* out = obs.mutable_data();
    const Sensors sensors = sim_.sensors();
    for (const SensorField* f : observed_) {
      const std::span<const double> v = sensors.read(f->id);
      out = std::copy(v.begin(), v.end(), out);
    }
    return obs;
  }

  std::shared_ptr<const Model> model_;
  Simulator sim_;
  int every_;
  std::vector<const SensorField*> observed_;
  int obs_size_ = 0;
  double fitness_ = 0;
  std::string end_;  // why the episode ended; empty while it runs
  StatePainter painter_;
};

}  // namespace

void bind_env(pyb::module_& m) {
  pyb::class_<PyEpisode>(m, "Episode")
      .def(pyb::init<const PyRobot&, const pyb::object&, const std::optional<std::string>&,
                     const std::optional<std::string>&, const std::vector<std::string>&, int>(),
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
}

}  // namespace plastivox::py
