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
// Adding a task: its value in `enum class Task` (physics_def.hpp), its file with a
// make_<name>_watch(), its row in kTasks (task.cpp), a test in tests/tasks_test.cpp and its
// section in docs/tasks.md.
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

struct TaskInfo {
  Task task;
  const char* name;     // in configs, on the command line (--task) and in results files
  const char* unit;     // of the fitness: "voxel lengths", "rad"
  const char* formula;  // one line, as docs/tasks.md states it
  std::unique_ptr<TaskWatch> (*watch)(const Model& model);
};

// Every task, in the enum's order.
const std::vector<TaskInfo>& all_tasks();
const TaskInfo& task_info(Task task);
const char* to_string(Task task);  // "walk", "jump", "turn", "carry", "push"
// Throws std::invalid_argument "unknown task 'x' (use walk, jump, turn, carry, push)".
Task parse_task(const std::string& name);
std::string task_names();  // "walk, jump, turn, carry, push"

// The watch of the model's task (model.def.task) for one life.
std::unique_ptr<TaskWatch> make_task_watch(const Model& model);

}  // namespace plastivox
