// Each task's watch, one per file (engine/core/src/task_<name>.cpp); the table in task.cpp
// names them (plastivox/task.hpp).
#pragma once

#include <cmath>
#include <functional>
#include <memory>
#include <vector>

#include "plastivox/task.hpp"

namespace plastivox {

std::unique_ptr<TaskWatch> make_walk_watch(const Model& model);
std::unique_ptr<TaskWatch> make_jump_watch(const Model& model);
std::unique_ptr<TaskWatch> make_turn_watch(const Model& model);
std::unique_ptr<TaskWatch> make_carry_watch(const Model& model);
std::unique_ptr<TaskWatch> make_push_watch(const Model& model);

// The free objects a task places when the environment gives none (compile() adds them):
// carry's payload and push's box, sized in voxels and placed from the robot's lattice; none
// for the other tasks.
std::vector<ObjectDef> carry_objects(const RobotDef& robot);
std::vector<ObjectDef> push_objects(const RobotDef& robot);
std::vector<ObjectDef> task_objects(Task task, const RobotDef& robot);

// Centre of free object k's voxels, m (model.object_begin; equal masses).
Vec3 object_center(const Model& model, const State& state, int k);

// How far a point moved horizontally (a free object's centre, the body's centre of mass),
// for carry and push: add() its place at each state to count, the first one the start.
struct Travel {
  bool started = false;
  Vec3 from = Vec3::Zero(), to = Vec3::Zero();  // the point, first and last, m
  void add(const Vec3& at) {
    to = at;
    if (!started) from = to, started = true;
  }
  // |to_xy - from_xy| / L, voxel lengths; 0 before any state.
  double voxel_lengths(const Model& model) const {
    return std::hypot(to.x() - from.x(), to.y() - from.y()) / model.size;
  }
};

// The bounds of the robot's voxels on its lattice, in sites: lo[a] <= site coordinate <= hi[a].
void lattice_bounds(const RobotDef& robot, int lo[3], int hi[3]);

// The terrain tasks: each one's watch, parameters and default environment.
std::unique_ptr<TaskWatch> make_rough_watch(const Model& model);
std::vector<TaskParam> rough_params();
Environment rough_environment(const PhysicsDef& def, const TaskSite& site);
std::unique_ptr<TaskWatch> make_climb_watch(const Model& model);
std::vector<TaskParam> climb_params();
Environment climb_environment(const PhysicsDef& def, const TaskSite& site);
std::unique_ptr<TaskWatch> make_slope_watch(const Model& model);
std::vector<TaskParam> slope_params();
Environment slope_environment(const PhysicsDef& def, const TaskSite& site);
std::unique_ptr<TaskWatch> make_obstacles_watch(const Model& model);
std::vector<TaskParam> obstacles_params();
Environment obstacles_environment(const PhysicsDef& def, const TaskSite& site);

// A watch that looks at nothing and scores a finished life from its summary with `score`
// (the tasks whose fitness needs only the start and end of the life).
std::unique_ptr<TaskWatch> watch_of_summary(double (*score)(const Model& model,
                                                            const SimResult& summary));

// Shared by the terrain tasks' fitnesses, from a life's summary (m):
// the horizontal displacement of the centre of mass since settling,
double horizontal_displacement(const SimResult& summary);
// and the rise of the ground under it (model.ground; 0 on the flat floor).
double ground_rise(const Model& model, const SimResult& summary);
// The fitness of rough and obstacles: the horizontal displacement in voxel lengths.
double horizontal_travel(const Model& model, const SimResult& summary);

// A square height field of node spacing `cell` centred on (cx, cy), nodes out to at least
// `reach` from it along each axis, node heights h(d) of the Chebyshev distance d from the
// centre (m): the grounds of climb and slope, which rise away from the start every way.
GroundDef ground_around(const TaskSite& site, double reach, double cell,
                        const std::function<double(double d)>& h);

}  // namespace plastivox
