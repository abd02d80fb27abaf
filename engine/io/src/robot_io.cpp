#include "plastivox/io/robot_io.hpp"

#include <sys/stat.h>

#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "plastivox/base/error.hpp"  // InputError
#include "plastivox/io/file_seal.hpp"
#include "plastivox/io/robot_file.hpp"
#include "plastivox/io/voxcraft.hpp"
#include "plastivox/io/vxa.hpp"

namespace plastivox {

namespace {

// A results file or recorded life given as a robot is named as such (a JSON or XML reader
// would call it malformed text). Anything but a readable regular file is left to the readers
// (opening a pipe would block).
void refuse_hdf5(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0 || !S_ISREG(st.st_mode)) return;
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) return;
  char head[64] = {};
  const size_t got = std::fread(head, 1, sizeof head, f);
  std::fclose(f);
  const std::string what = seal::describe_hdf5(std::string_view(head, got));
  if (!what.empty()) throw InputError(path + ": " + what + ", not a robot file (.json or .vxa)");
}

}  // namespace

LoadedRobot load_robot(const std::string& path, const std::string& vxd) {
  refuse_hdf5(path);
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

void warn_vxa_density(SimResult& r, const std::string& source, double file_density,
                      const PhysicsDef& physics, double voxel_size) {
  if (!source.ends_with(".vxa") || physics.density != file_density ||
      r.floor_health == FloorHealth::kOk)
    return;
  char buf[480];
  std::snprintf(buf, sizeof buf,
                "the body pressed into the floor at the VXA file's own density, %g kg/m^3 (a %g "
                "m voxel weighs %g kg, too heavy for its stiffness): authors'-style files are run "
                "lighter, e.g. --physics '{\"density\": 1e7}' (Python: physics={\"density\": "
                "1e7}; docs/vxa.md, \"A VXA file at its own density\")",
                physics.density, voxel_size, physics.density * std::pow(voxel_size, 3));
  r.warnings.push_back(buf);
}

}  // namespace plastivox
