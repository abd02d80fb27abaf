// Tasks: what a life is scored on (docs/tasks.md). A task is an environment plus a fitness
// with a stated formula and unit; PhysicsDef::task chooses one, and simulate() scores every
// life with it. Each task is one small file (engine/core/src/task_<name>.cpp) behind this
// interface: a score of the life from its state, and, for the tasks that need more than the
// last state, a watch that the Simulator calls after every step (at the end of step2) to
// keep the task's running values in the State (task_values, task_layout): jump keeps the
// highest centre of mass, turn the body's accumulated yaw, carry and push where the payload
// or box went. So a snapshot resumes the score, and any life stepped by any front end can be
// scored (Simulator::result).
//
// Every task scores 0 for a life that did not finish (unstable, or sunk through the floor
// under physics.sinking_invalid): simulate() applies that rule, not the tasks.
//
// A task may come with its own environment (rough, climb, slope, obstacles: the ground or
// blocks they are about) and parameters. The environment is the task's default: compile()
// lays it out around the body's starting footprint, in voxel lengths, when the physics gives
// none (physics.environment inactive); an environment given by the user is used as given.
//
// Adding a task: its value in `enum class Task` (physics_def.hpp), its file with its score
// and watch (and, when it has them, its parameters and default environment), its
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
  // What a life must achieve to succeed at the task, one line a reader can check, as
  // docs/tasks.md states it; `threshold` is the least fitness that meets it (in `unit`) unless
  // `succeeds` decides.
  const char* criterion;
  double threshold;
  // The fitness of the life ended at `last`, in the task's unit, from its running values and
  // the summary (displacement and centres of mass already filled in).
  double (*score)(const Model& model, const State& last, const SimResult& summary);
  // After every step (and not before the first): updates the running values from the state
  // the step left; nullptr for a task that needs only the last state.
  void (*see)(const Model& model, State& state);
  // What each of task_values holds under this task, in order (one line each; none unused).
  std::vector<const char*> values;
  std::vector<TaskParam> params = {};  // its parameters, in docs/tasks.md's order
  // Its default environment for a body at `site` with parameters `def.task_params`; nullptr:
  // the flat floor.
  Environment (*environment)(const PhysicsDef& def, const TaskSite& site) = nullptr;
  const char* environment_text = "flat floor with friction";  // one line, for reports
  // Whether the life summarised by `summary` (fitness filled in) meets the criterion, for a
  // criterion that is not a least fitness; nullptr: fitness >= threshold.
  bool (*succeeds)(const Model& model, const SimResult& summary) = nullptr;
};

// Every task, in the enum's order.
const std::vector<TaskInfo>& all_tasks();
const TaskInfo& task_info(Task task);
const char* to_string(Task task);  // "walk", "jump", "turn", ...
// Throws std::invalid_argument "unknown task 'x' (use walk, jump, turn, ...)".
Task parse_task(const std::string& name);
std::string task_names();  // "walk, jump, turn, carry, push"

// The model's task (model.def.task): its watch after a step (nothing for a task without
// one), and its score of the life ended at `last`.
void see_task(const Model& model, State& state);
double task_score(const Model& model, const State& last, const SimResult& summary);
// Whether the life summarised by `summary` (its fitness the task's score) meets the task's
// criterion. A measurement: simulate() claims it only for a finished life, and judge_life
// (plastivox/rules/life_rules.hpp) withdraws it from a life that does not count.
bool task_success(const Model& model, const SimResult& summary);

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
