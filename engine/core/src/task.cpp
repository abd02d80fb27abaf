// The table of tasks (plastivox/task.hpp): names, units and formulas, and each one's watch.
#include "plastivox/task.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "plastivox/simulator.hpp"
#include "tasks.hpp"

namespace plastivox {
namespace {

constexpr double kQuarterTurn = 1.5707963267948966;  // rad

}  // namespace

const std::vector<TaskInfo>& all_tasks() {
  static const std::vector<TaskInfo> tasks = {
      {Task::kWalk,
       "walk",
       "voxel lengths",
       "|c(T) - c(settle)| / L: the centre of mass's displacement from the end of settling to "
       "the end of the life (horizontal only under physics.fitness = xy)",
       "fitness >= 5: the centre of mass travels at least 5 voxel lengths",
       5,
       walk_score,
       nullptr,
       {}},
      {Task::kJump, "jump", "voxel lengths",
       "max over t >= settle of (c_z(t) - c_z(settle)) / L: the highest rise of the centre of "
       "mass above its settled height",
       "fitness >= 0.5: the centre of mass rises at least half a voxel length", 0.5, jump_score,
       see_jump, jump_values()},
      {Task::kTurn, "turn", "rad",
       "|theta(T)|: the body's net rotation about the vertical axis since settling, the "
       "least-squares turn of its voxel centres' horizontal layout, counted through whole turns",
       "fitness >= pi/2: the body turns at least a quarter turn", kQuarterTurn, turn_score,
       see_turn, turn_values()},
      {Task::kRough,
       "rough",
       "voxel lengths",
       "|c_xy(T) - c_xy(settle)| / L: the centre of mass's horizontal displacement over a "
       "seeded random height field",
       "fitness >= 5: the centre of mass travels at least 5 voxel lengths over the rough ground",
       5,
       horizontal_travel,
       nullptr,
       {},
       rough_params(),
       rough_environment,
       "rough ground: node heights uniform in [-amplitude, 0], one node every cell, seeded"},
      {Task::kClimb,
       "climb",
       "voxel lengths",
       "max(0, |c_xy(T) - c_xy(settle)| + w (h(c(T)) - h(c(settle)))) / L: horizontal "
       "displacement plus w times the rise of the ground under the centre of mass",
       "the ground under the centre of mass ends at least one step (rise) above the ground "
       "under it at settling: on the first terrace or higher",
       0,
       climb_score,
       nullptr,
       {},
       climb_params(),
       climb_environment,
       "terraces: count steps of height rise, one every run, rising away from the start every way",
       climb_succeeds},
      {Task::kSlope,
       "slope",
       "voxel lengths",
       "max(0, h(c(T)) - h(c(settle))) / L: the rise of the ground under the centre of mass",
       "fitness >= 1: the ground under the centre of mass rises at least one voxel length",
       1,
       slope_score,
       nullptr,
       {},
       slope_params(),
       slope_environment,
       "a pit: ramps at angle_deg rising away from the start every way for length"},
      {Task::kObstacles,
       "obstacles",
       "voxel lengths",
       "|c_xy(T) - c_xy(settle)| / L: the centre of mass's horizontal displacement through a "
       "field of static blocks",
       "fitness >= 5: the centre of mass travels at least 5 voxel lengths through the blocks",
       5,
       horizontal_travel,
       nullptr,
       {},
       obstacles_params(),
       obstacles_environment,
       "a field of static blocks, height by size by size, one at a seeded place in every square "
       "of side spacing"},
      {Task::kCarry,
       "carry",
       "voxel lengths",
       "min(|p_xy(t_last) - p_xy(settle)|, |c_xy(t_last) - c_xy(settle)|) / L: the lesser of the "
       "payload's and the body's horizontal displacements from the end of settling to the last "
       "step the payload was on the body (no payload voxel within a voxel length of the ground)",
       "fitness >= 2: the body carries the payload at least two voxel lengths",
       2,
       carry_score,
       see_carry,
       carry_values(),
       {},
       nullptr,
       "flat floor with friction; a free payload of 2 x 2 x 1 voxels centred on top of the body"},
      {Task::kPush,
       "push",
       "voxel lengths",
       "|b_xy(T) - b_xy(settle)| / L: the horizontal displacement of the box's centre from the "
       "end of settling to the end of the life",
       "fitness >= 2: the box moves at least two voxel lengths",
       2,
       push_score,
       see_push,
       push_values(),
       {},
       nullptr,
       "flat floor with friction; a free box of 2 x 2 x 2 voxels one voxel in front (+x) of the "
       "body"},
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

ObjectDef centred_object(const RobotDef& robot, std::array<int, 3> voxels, int lo[3], int hi[3]) {
  lattice_bounds(robot, lo, hi);
  const double L = robot.voxel_size;
  ObjectDef o;
  o.voxels = voxels;
  for (int a = 0; a < 2; ++a) o.at[a] = 0.5 * (lo[a] + hi[a] + 1) * L - 0.5 * voxels[a] * L;
  return o;
}

std::vector<ObjectDef> task_objects(Task task, const RobotDef& robot) {
  if (task == Task::kCarry) return carry_objects(robot);
  if (task == Task::kPush) return push_objects(robot);
  return {};
}

bool task_success(const Model& model, const SimResult& summary) {
  const TaskInfo& t = task_info(model.def.task);
  return t.succeeds ? t.succeeds(model, summary) : summary.fitness >= t.threshold;
}

void see_task(const Model& model, State& state) {
  if (const auto see = task_info(model.def.task).see) see(model, state);
}

double task_score(const Model& model, const State& last, const SimResult& summary) {
  return task_info(model.def.task).score(model, last, summary);
}

namespace {

const TaskParam* find_param(const TaskInfo& t, const std::string& name) {
  for (const TaskParam& p : t.params)
    if (name == p.name) return &p;
  return nullptr;
}

std::string number_text(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

}  // namespace

double task_param(const PhysicsDef& def, const std::string& name) {
  const TaskParam* p = find_param(task_info(def.task), name);
  if (!p)
    throw std::invalid_argument("task " + std::string(to_string(def.task)) + " has no parameter " +
                                name);
  const auto given = def.task_params.find(name);
  return given == def.task_params.end() ? p->fallback : given->second;
}

void check_task_param(Task task, const std::string& name, double value) {
  const TaskInfo& t = task_info(task);
  const TaskParam* p = find_param(t, name);
  if (!p) {
    std::string names;
    for (const TaskParam& q : t.params) names += (names.empty() ? "" : ", ") + std::string(q.name);
    throw std::invalid_argument("unknown parameter of " + std::string(t.name) +
                                (names.empty() ? " (it has none)" : " (use " + names + ")"));
  }
  const std::string unit = p->unit[0] ? std::string(" ") + p->unit : "";
  if (!(value >= p->lo && value <= p->hi))
    throw std::invalid_argument("must be in [" + number_text(p->lo) + ", " + number_text(p->hi) +
                                "]" + unit);
  if (p->whole && value != std::floor(value)) throw std::invalid_argument("must be a whole number");
}

void validate_task(const PhysicsDef& def) {
  const TaskInfo& t = task_info(def.task);
  for (const auto& [name, value] : def.task_params) {
    const std::string field = "physics.task." + name;
    try {
      check_task_param(def.task, name, value);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(field + ": " + e.what());
    }
    if (find_param(t, name)->ground && def.environment.terrain())
      throw std::invalid_argument(field +
                                  ": shapes the task's default environment, which "
                                  "physics.environment replaces (give one or the other)");
  }
  if (t.environment && !def.floor && !def.environment.terrain())
    throw std::invalid_argument(std::string("physics.floor: task ") + t.name +
                                " needs the floor (its ground lies on it)");
}

Environment task_environment(const PhysicsDef& def, const TaskSite& site) {
  const TaskInfo& t = task_info(def.task);
  if (def.environment.terrain() || !t.environment) return def.environment;
  Environment env = t.environment(def, site);
  env.objects = def.environment.objects;
  return env;
}

std::string environment_text(const PhysicsDef& def) {
  const TaskInfo& t = task_info(def.task);
  const size_t objects = def.environment.objects.size();
  const std::string free_objects =
      objects ? ", " + std::to_string(objects) + " free object" + (objects > 1 ? "s" : "") : "";
  if (def.environment.terrain()) {
    std::string s = std::string("given: ground ") + to_string(def.environment.ground.kind);
    if (!def.environment.obstacles.empty())
      s += ", " + std::to_string(def.environment.obstacles.size()) + " boxes";
    return s + free_objects;
  }
  if (objects) return std::string("given: ") + t.environment_text + free_objects;
  if (!t.environment) return t.environment_text;
  std::string s = "the default of " + std::string(t.name) + ": " + t.environment_text + " (";
  for (size_t i = 0; i < t.params.size(); ++i)
    if (t.params[i].ground)
      s += std::string(i ? ", " : "") + t.params[i].name + " " +
           number_text(task_param(def, t.params[i].name));
  return s + "; lengths in voxel lengths)";
}

}  // namespace plastivox

namespace plastivox {

void travel_to(TaskValues& v, int at, const Vec3& point, bool first) {
  v[at + 2] = point.x();
  v[at + 3] = point.y();
  if (first) v[at] = v[at + 2], v[at + 1] = v[at + 3];
}

double travel_voxel_lengths(const Model& model, const TaskValues& v, int at) {
  return std::hypot(v[at + 2] - v[at], v[at + 3] - v[at + 1]) / model.size;
}

double horizontal_displacement(const SimResult& r) {
  return (r.com_final - r.com_settled).head<2>().norm();
}

double horizontal_travel(const Model& m, const State&, const SimResult& r) {
  return horizontal_displacement(r) / m.size;
}

double ground_rise(const Model& m, const SimResult& r) {
  if (!m.terrain) return 0;
  return m.ground.height(r.com_final.x(), r.com_final.y()) -
         m.ground.height(r.com_settled.x(), r.com_settled.y());
}

GroundDef ground_around(const TaskSite& site, double reach, double cell,
                        const std::function<double(double d)>& h) {
  const int half = static_cast<int>(std::ceil(reach / cell));
  GroundDef g;
  g.kind = GroundKind::kHeights;
  g.cell = cell;
  g.nx = g.ny = 2 * half + 1;
  g.origin = {site.cx - half * cell, site.cy - half * cell};
  g.heights.resize(static_cast<size_t>(g.nx) * g.ny);
  for (int j = 0; j < g.ny; ++j)
    for (int i = 0; i < g.nx; ++i)
      g.heights[i + static_cast<size_t>(g.nx) * j] =
          h(cell * std::max(std::abs(i - half), std::abs(j - half)));
  return g;
}

}  // namespace plastivox
