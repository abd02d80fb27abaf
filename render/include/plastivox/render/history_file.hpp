// A recorded life in the history format of voxcraft-viz (the desktop viewer of voxcraft-sim),
// so a plastivox life opens in the viewer that field's users already have. Text, one line
// per record; what is written and what voxcraft-viz shows of it: docs/results-format.md,
// "voxcraft-viz history". No GL here.
#pragma once

#include <string>

#include "plastivox/model.hpp"
#include "plastivox/recording.hpp"

namespace plastivox::render {

// Material ids the history uses for congenital stiffness classes: 1..kHistoryClasses.
constexpr int kHistoryClasses = 9;

// The history text of `recording` (frames of `model`'s voxels): setting lines (length
// rescale, voxel size, one colour per congenital stiffness class, from the congenital colour
// map over the robot's own range), then one line per frame with every voxel's pose, corners,
// class and stiffness change.
std::string history_text(const Model& model, const Recording& recording);

// Writes history_text() to `path` atomically. Throws InputError naming the file.
void write_history_file(const std::string& path, const Model& model, const Recording& recording);

}  // namespace plastivox::render
