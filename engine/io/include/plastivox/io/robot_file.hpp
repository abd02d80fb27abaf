// The project's own robot file: JSON, schema "plastivox-robot" version 1 (docs/robot-format.md).
//
//   { "format": "plastivox-robot", "version": 1, "name": "walker",
//     "lattice": { "nx": 10, "ny": 10, "nz": 10, "voxel_size": 0.01 },
//     "voxels": [ [x, y, z, E_Pa, alpha_per_s, phase_cycles], ... ],
//     "fixed":  [ [x, y, z], ... ],                              (optional)
//     "loads":  [ { "at": [x, y, z], "force": [fx, fy, fz] } ],   (optional, N)
//     "physics": { "preset": "gecco2018-code", "treatment": "stress", ... } }  (optional)
#pragma once

#include <stdexcept>
#include <string>

#include "plastivox/base/error.hpp"  // InputError
#include "plastivox/physics_def.hpp"
#include "plastivox/robot.hpp"

namespace plastivox {

struct RobotFile {
  RobotDef robot;
  PhysicsDef physics;  // the file's "physics" section applied to its preset (default code preset)
};

RobotFile read_robot_file(const std::string& path);  // throws InputError
RobotFile parse_robot_json(const std::string& text, const std::string& source);
std::string robot_to_json(const RobotDef& robot, const PhysicsDef* physics = nullptr);
// Writes to "<path>.tmp" and renames, so a reader never sees half a file.
void write_robot_file(const std::string& path, const RobotDef& robot,
                      const PhysicsDef* physics = nullptr);

// The physics as the object a robot file holds at "physics" (compact JSON): every field, and
// the environment when one is defined. apply_physics_json reads it back into a default
// PhysicsDef exactly (MPI ranks send physics this way).
std::string physics_to_json(const PhysicsDef& def);

// Applies a JSON object of physics fields (names as in PhysicsDef, plus "preset") to def.
// Unknown fields and wrong types are errors naming "<where>.<field>". Declared here so
// experiment configs reuse it; json_text must hold one JSON object.
void apply_physics_json(const std::string& json_text, const std::string& where, PhysicsDef& def);

}  // namespace plastivox
