// Each task's watch, one per file (engine/core/src/task_<name>.cpp); the table in task.cpp
// names them (plastivox/task.hpp).
#pragma once

#include <array>
#include <cmath>
#include <functional>
#include <memory>
#include <vector>

#include "plastivox/task.hpp"

namespace plastivox {

// Each task's score and, where it has one, its watch and the names of its running values
// (TaskInfo).
double walk_score(const Model& model, const State& last, const SimResult& summary);
double jump_score(const Model& model, const State& last, const SimResult& summary);
void see_jump(const Model& model, State& state);
std::vector<const char*> jump_values();
double turn_score(const Model& model, const State& last, const SimResult& summary);
void see_turn(const Model& model, State& state);
std::vector<const char*> turn_values();
double carry_score(const Model& model, const State& last, const SimResult& summary);
void see_carry(const Model& model, State& state);
std::vector<const char*> carry_values();
double push_score(const Model& model, const State& last, const SimResult& summary);
void see_push(const Model& model, State& state);
std::vector<const char*> push_values();

// The free objects a task places when the environment gives none (compile() adds them):
// carry's payload and push's box, sized in voxels and placed from the robot's lattice; none
// for the other tasks.
std::vector<ObjectDef> carry_objects(const RobotDef& robot);
std::vector<ObjectDef> push_objects(const RobotDef& robot);
std::vector<ObjectDef> task_objects(Task task, const RobotDef& robot);

// Centre of free object k's voxels, m (model.object_begin; equal masses).
Vec3 object_center(const Model& model, const State& state, int k);

// How far a point moved horizontally (a free object's centre, the body's centre of mass),
// for carry and push, kept in four running values from `at`: the point's first place (x, y)
// and its last (x, y), m. travel_to() sets the last, and the first too when `first`.
void travel_to(TaskValues& values, int at, const Vec3& point, bool first);
// |last_xy - first_xy| / L, voxel lengths; 0 before any state.
double travel_voxel_lengths(const Model& model, const TaskValues& values, int at);

// The bounds of the robot's voxels on its lattice, in sites: lo[a] <= site coordinate <= hi[a].
void lattice_bounds(const RobotDef& robot, int lo[3], int hi[3]);
// A free object of `voxels` centred on those bounds in x and y, its bottom at z = 0, and the
// bounds (lo, hi), from which carry_objects and push_objects place it.
ObjectDef centred_object(const RobotDef& robot, std::array<int, 3> voxels, int lo[3], int hi[3]);

// The terrain tasks: each one's watch, parameters and default environment.
std::vector<TaskParam> rough_params();
Environment rough_environment(const PhysicsDef& def, const TaskSite& site);
double climb_score(const Model& model, const State& last, const SimResult& summary);
std::vector<TaskParam> climb_params();
Environment climb_environment(const PhysicsDef& def, const TaskSite& site);
bool climb_succeeds(const Model& model, const SimResult& summary);
double slope_score(const Model& model, const State& last, const SimResult& summary);
std::vector<TaskParam> slope_params();
Environment slope_environment(const PhysicsDef& def, const TaskSite& site);
std::vector<TaskParam> obstacles_params();
Environment obstacles_environment(const PhysicsDef& def, const TaskSite& site);

// Shared by the terrain tasks' fitnesses, from a life's summary (m):
// the horizontal displacement of the centre of mass since settling,
double horizontal_displacement(const SimResult& summary);
// and the rise of the ground under it (model.ground; 0 on the flat floor).
double ground_rise(const Model& model, const SimResult& summary);
// The fitness of rough and obstacles: the horizontal displacement in voxel lengths.
double horizontal_travel(const Model& model, const State& last, const SimResult& summary);

// A square height field of node spacing `cell` centred on (cx, cy), nodes out to at least
// `reach` from it along each axis, node heights h(d) of the Chebyshev distance d from the
// centre (m): the grounds of climb and slope, which rise away from the start every way.
GroundDef ground_around(const TaskSite& site, double reach, double cell,
                        const std::function<double(double d)>& h);

}  // namespace plastivox
