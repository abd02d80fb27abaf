// The table of tasks (plastivox/task.hpp): names, units and formulas, and each one's watch.
#include "plastivox/task.hpp"

#include <stdexcept>

#include "tasks.hpp"

namespace plastivox {

const std::vector<TaskInfo>& all_tasks() {
  static const std::vector<TaskInfo> tasks = {
      {Task::kWalk, "walk", "voxel lengths",
       "|c(T) - c(settle)| / L: the centre of mass's displacement from the end of settling to "
       "the end of the life (horizontal only under physics.fitness = xy)",
       make_walk_watch},
      {Task::kJump, "jump", "voxel lengths",
       "max over t >= settle of (c_z(t) - c_z(settle)) / L: the highest rise of the centre of "
       "mass above its settled height",
       make_jump_watch},
      {Task::kTurn, "turn", "rad",
       "|theta(T)|: the body's net rotation about the vertical axis since settling, the "
       "least-squares turn of its voxel centres' horizontal layout, counted through whole turns",
       make_turn_watch},
  };
  return tasks;
}

const TaskInfo& task_info(Task task) {
  for (const TaskInfo& t : all_tasks())
    if (t.task == task) return t;
  throw std::invalid_argument("task out of range");
}

const char* to_string(Task task) {
  return task_info(task).name;
}

std::string task_names() {
  std::string out;
  for (const TaskInfo& t : all_tasks()) out += (out.empty() ? "" : ", ") + std::string(t.name);
  return out;
}

Task parse_task(const std::string& name) {
  for (const TaskInfo& t : all_tasks())
    if (name == t.name) return t.task;
  throw std::invalid_argument("unknown task '" + name + "' (use " + task_names() + ")");
}

std::unique_ptr<TaskWatch> make_task_watch(const Model& model) {
  return task_info(model.def.task).watch(model);
}

}  // namespace plastivox
