// Each task's watch, one per file (engine/core/src/task_<name>.cpp); the table in task.cpp
// names them (plastivox/task.hpp).
#pragma once

#include <functional>
#include <memory>
#include <vector>

#include "plastivox/task.hpp"

namespace plastivox {

std::unique_ptr<TaskWatch> make_walk_watch(const Model& model);
std::unique_ptr<TaskWatch> make_jump_watch(const Model& model);
std::unique_ptr<TaskWatch> make_turn_watch(const Model& model);

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

// A square height field of node spacing `cell` centred on (cx, cy), nodes out to at least
// `reach` from it along each axis, node heights h(d) of the Chebyshev distance d from the
// centre (m): the grounds of climb and slope, which rise away from the start every way.
GroundDef ground_around(const TaskSite& site, double reach, double cell,
                        const std::function<double(double d)>& h);

}  // namespace plastivox
