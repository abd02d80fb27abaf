#include "plastivox/io/robot_io.hpp"

#include <stdexcept>

#include "plastivox/io/robot_file.hpp"
#include "plastivox/io/voxcraft.hpp"
#include "plastivox/io/vxa.hpp"

namespace plastivox {

LoadedRobot load_robot(const std::string& path, const std::string& vxd) {
  LoadedRobot out;
  if (!vxd.empty() || path.ends_with(".vxa")) {
    VxaRobot v = vxd.empty() ? read_vxa_file(path) : read_voxcraft(path, vxd);
    out.robot = std::move(v.robot);
    out.physics = v.physics;
    out.warnings = std::move(v.warnings);
  } else {
    RobotFile f = read_robot_file(path);
    out.robot = std::move(f.robot);
    out.physics = f.physics;
  }
  return out;
}

void save_robot(const std::string& path, const RobotDef& robot, const PhysicsDef& physics,
                std::vector<std::string>* warnings) {
  if (path.ends_with(".vxa")) {
    write_vxa_file(path, robot, physics, warnings);
  } else if (path.ends_with(".json")) {
    write_robot_file(path, robot, &physics);
  } else {
    throw std::invalid_argument("expected a robot file name ending in .json or .vxa, got '" + path +
                                "'");
  }
}

}  // namespace plastivox
