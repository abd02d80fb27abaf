// The table of tasks (plastivox/task.hpp): names, units and formulas, and each one's watch.
#include "plastivox/task.hpp"

#include <algorithm>
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
      {Task::kCarry, "carry", "voxel lengths",
       "|p_xy(t_last) - p_xy(settle)| / L: the payload's horizontal displacement from the end of "
       "settling to the last step it was on the body (no payload voxel within a voxel length of "
       "the ground)",
       make_carry_watch},
      {Task::kPush, "push", "voxel lengths",
       "|b_xy(T) - b_xy(settle)| / L: the horizontal displacement of the box's centre from the "
       "end of settling to the end of the life",
       make_push_watch},
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

Vec3 object_center(const Model& m, const State& s, int k) {
  Vec3 c = Vec3::Zero();
  const int begin = m.object_begin[k], end = m.object_begin[k + 1];
  for (int i = begin; i < end; ++i) c += s.pos[i];
  return c / static_cast<double>(end - begin);
}

void lattice_bounds(const RobotDef& r, int lo[3], int hi[3]) {
  for (int a = 0; a < 3; ++a) lo[a] = 1 << 30, hi[a] = -1;
  for (int s = 0; s < r.sites(); ++s) {
    if (!r.present[s]) continue;
    const int c[3] = {s % r.nx, (s / r.nx) % r.ny, s / (r.nx * r.ny)};
    for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], c[a]), hi[a] = std::max(hi[a], c[a]);
  }
}

std::vector<ObjectDef> task_objects(Task task, const RobotDef& robot) {
  if (task == Task::kCarry) return carry_objects(robot);
  if (task == Task::kPush) return push_objects(robot);
  return {};
}

std::unique_ptr<TaskWatch> make_task_watch(const Model& model) {
  return task_info(model.def.task).watch(model);
}

}  // namespace plastivox
