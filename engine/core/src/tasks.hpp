// Each task's watch, one per file (engine/core/src/task_<name>.cpp); the table in task.cpp
// names them (plastivox/task.hpp).
#pragma once

#include <memory>

#include "plastivox/task.hpp"

namespace plastivox {

std::unique_ptr<TaskWatch> make_walk_watch(const Model& model);
std::unique_ptr<TaskWatch> make_jump_watch(const Model& model);
std::unique_ptr<TaskWatch> make_turn_watch(const Model& model);

}  // namespace plastivox
