// Robot files by their extension: `.vxa` is the authors' format (vxa.hpp), anything else the
// project's own JSON (robot_file.hpp). The one place that picks the reader or the writer.
#pragma once

#include <string>
#include <vector>

#include "plastivox/physics_def.hpp"
#include "plastivox/robot.hpp"

namespace plastivox {

struct LoadedRobot {
  RobotDef robot;
  PhysicsDef physics;                 // the file's physics (its preset and fields)
  std::vector<std::string> warnings;  // what a .vxa left to defaults or ignored, one line each
};

// Throws InputError (VxaError for .vxa), one line naming the file and the field. With a
// non-empty vxd, path is voxcraft-sim's base.vxa and vxd its robot (voxcraft.hpp).
LoadedRobot load_robot(const std::string& path, const std::string& vxd = "");

// Writes .vxa or .json (atomically); a .vxa writer's notes on what the format cannot hold go
// to *warnings. Throws std::invalid_argument for any other extension, InputError on failure.
void save_robot(const std::string& path, const RobotDef& robot, const PhysicsDef& physics,
                std::vector<std::string>* warnings);

}  // namespace plastivox
