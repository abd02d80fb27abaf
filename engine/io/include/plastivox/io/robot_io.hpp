// Robot files by their extension: `.vxa` is the authors' format (vxa.hpp), anything else the
// project's own JSON (robot_file.hpp). The one place that picks the reader or the writer.
#pragma once

#include <string>
#include <vector>

#include "plastivox/physics_def.hpp"
#include "plastivox/robot.hpp"
#include "plastivox/simulator.hpp"  // SimResult

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

// The authors' VXA files hold 1e9 kg/m^3 materials of 1e6-1e10 Pa, which their simulator lets
// sink. When `source` is such a file (.vxa), simulated at its own density `file_density`, and
// its body pressed into or sank through the floor, adds to r.warnings one naming the density
// as the cause and the fix (docs/vxa.md, "A VXA file at its own density"). `simulate` and
// Python's simulate call it, so both summaries hold it.
void warn_vxa_density(SimResult& r, const std::string& source, double file_density,
                      const PhysicsDef& physics, double voxel_size);

}  // namespace plastivox
