// Tasks: what a life is scored on (docs/tasks.md). A task is an environment plus a fitness
// with a stated formula and unit; PhysicsDef::task chooses one, and simulate() scores every
// life with it. Each task is one small file (engine/core/src/task_<name>.cpp) behind this
// interface: a TaskWatch, made once per life, that sees the state after every step (only
// the tasks that need more than the last state look at it: jump keeps the highest centre of
// mass, turn the body's accumulated yaw) and scores the finished life.
//
// Every task scores 0 for a life that did not finish (unstable, or sunk through the floor
// under physics.sinking_invalid): simulate() applies that rule, not the tasks.
//
// A task may come with its own environment (rough, climb, slope, obstacles: the ground or
// blocks they are about) and parameters. The environment is the task's default: compile()
// lays it out around the body's starting footprint, in voxel lengths, when the physics gives
// none (physics.environment inactive); an environment given by the user is used as given.
//
// Adding a task: its value in `enum class Task` (physics_def.hpp), its file with a
// make_<name>_watch() (and, when it has them, its parameters and default environment), its
// row in all_tasks() (task.cpp), a test with known answers and its section in docs/tasks.md.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "plastivox/model.hpp"
#include "plastivox/physics_def.hpp"
#include "plastivox/state.hpp"

namespace plastivox {

struct SimResult;

// One life's view of its task. Not thread-safe; one per life.
class TaskWatch {
 public:
  virtual ~TaskWatch() = default;
  // After every step (and not before the first): the state as the step left it.
  virtual void see(const Model& model, const State& state) = 0;
  // The fitness of a life that ran to its end, in the task's unit, from what see() saw, the
  // last state and the summary (displacement and centres of mass already filled in).
  virtual double score(const Model& model, const State& last, const SimResult& summary) const = 0;
};

// One parameter of a task: a number in [lo, hi] (whole: an integer), `fallback` when not
// given. `ground`: it shapes the task's default environment only (so giving it together with
// physics.environment is an error).
struct TaskParam {
  const char* name;
  double fallback;
  double lo, hi;
  const char* unit;  // "voxel lengths", "degrees", "" (a count or seed)
  bool whole = false;
  bool ground = true;
};

// Where a body starts, seen from above (the box of its voxels, m) and its voxel size: what a
// task's default environment is laid out around.
struct TaskSite {
  double L = 0.01;                                   // voxel size, m
  double cx = 0, cy = 0;                             // centre of the footprint, m
  double hx = 0, hy = 0;                             // half extents of the footprint, m
  double half() const { return hx > hy ? hx : hy; }  // of the square that holds it, m
};

struct TaskInfo {
  Task task;
  const char* name;     // in configs, on the command line (--task) and in results files
  const char* unit;     // of the fitness: "voxel lengths", "rad"
  const char* formula;  // one line, as docs/tasks.md states it
  std::unique_ptr<TaskWatch> (*watch)(const Model& model);
  std::vector<TaskParam> params = {};  // its parameters, in docs/tasks.md's order
  // Its default environment for a body at `site` with parameters `def.task_params`; nullptr:
  // the flat floor.
  Environment (*environment)(const PhysicsDef& def, const TaskSite& site) = nullptr;
  const char* environment_text = "flat floor with friction";  // one line, for reports
};

// Every task, in the enum's order.
const std::vector<TaskInfo>& all_tasks();
const TaskInfo& task_info(Task task);
const char* to_string(Task task);  // "walk", "jump", "turn", ...
// Throws std::invalid_argument "unknown task 'x' (use walk, jump, turn, ...)".
Task parse_task(const std::string& name);
std::string task_names();  // "walk, jump, turn, carry, push"

// The watch of the model's task (model.def.task) for one life.
std::unique_ptr<TaskWatch> make_task_watch(const Model& model);

// The value of parameter `name` of def.task: given, else its default. Throws
// std::invalid_argument when the task has no such parameter (a programming error).
double task_param(const PhysicsDef& def, const std::string& name);
// Throws std::invalid_argument "unknown parameter of climb (use rise, run, ...)" or "must be
// in [0, 5] voxel lengths" for a bad parameter `name` = `value` of `task`.
void check_task_param(Task task, const std::string& name, double value);
// Checks every given parameter of def.task, and that none shapes a default environment that
// def.environment replaces; throws std::invalid_argument "physics.task.<name>: ...".
void validate_task(const PhysicsDef& def);

// The environment a life under `def` takes place in, for a body at `site`: def.environment
// when active, else the task's default (the floor for tasks without one).
Environment task_environment(const PhysicsDef& def, const TaskSite& site);
// One line naming the environment of `def` for reports: the task's default, or "given".
std::string environment_text(const PhysicsDef& def);

}  // namespace plastivox
