// Each task's watch, one per file (engine/core/src/task_<name>.cpp); the table in task.cpp
// names them (plastivox/task.hpp).
#pragma once

#include <cmath>
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

// How far free object k's centre moved horizontally, for carry and push: add() each state
// to count, the first one the start.
struct ObjectTravel {
  bool started = false;
  Vec3 from = Vec3::Zero(), to = Vec3::Zero();  // the object's centre, first and last, m
  void add(const Model& model, const State& state, int k) {
    to = object_center(model, state, k);
    if (!started) from = to, started = true;
  }
  // |to_xy - from_xy| / L, voxel lengths; 0 before any state.
  double voxel_lengths(const Model& model) const {
    return std::hypot(to.x() - from.x(), to.y() - from.y()) / model.size;
  }
};

// The bounds of the robot's voxels on its lattice, in sites: lo[a] <= site coordinate <= hi[a].
void lattice_bounds(const RobotDef& robot, int lo[3], int hi[3]);

}  // namespace plastivox
