// Import and export of robots in the VXA (Voxelyze/VoxCAD XML) dialect written by the
// GECCO-2018 authors' scripts (VXA 1.0 wrapping VXC 0.93; see tests/data/vxa/README.md).
//
// Reading follows the authors' simulator (their Voxelyze 0.9 fork, notes/authors-physics.md):
// palette materials are numbered by their position, per-voxel blocks list one value for every
// lattice site (only the values at present voxels are used by that simulator), missing tags take
// that simulator's defaults. Tags that would change the physics in a way this engine cannot
// reproduce are errors; tags that the authors' simulator reads but that do not matter here, or
// that it ignores although they look meaningful, become warnings. Nothing is dropped silently.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "plastivox/base/error.hpp"
#include "plastivox/physics_def.hpp"
#include "plastivox/robot.hpp"

namespace plastivox {

// The most attributes one element may carry: the dialect's elements have at most 2 (a VXA
// file can need no more). More is refused before the XML is parsed, whose attribute check is
// quadratic in their number (200 000 on one element took 81 s).
constexpr int kMaxVxaAttributes = 64;

// what() is one line: "<file>: <Tag>/<Path>: what is wrong".
class VxaError : public InputError {
 public:
  using InputError::InputError;
};

// One <Palette>/<Material> entry as read (the physics keeps only what PhysicsDef can hold).
struct VxaMaterial {
  int index = 0;      // 1-based position in the palette: what a <Data> character refers to
  std::string name;   // <Name>
  int mat_type = 0;   // <MatType>: 0 = single material
  int mat_model = 0;  // <Mechanical>/<MatModel>: 0 = linear
  double elastic_mod = 0, density = 0, poisson = 0, cte = 0, mu_static = 0, mu_kinetic = 0;
  int voxels = 0;  // robot voxels made of this material
};

struct VxaRobot {
  RobotDef robot;  // name = file stem; lattice-sized arrays hold the file's value at every site
  PhysicsDef physics;
  std::vector<std::string> warnings;  // one line each, naming the tag
  std::vector<VxaMaterial> palette;   // in file order (palette[i].index == i + 1)
  std::vector<uint8_t> material;      // per lattice site: palette index, 0 = empty
};

// Parses VXA text. source_name is used in error messages and (its stem) as robot.name.
// Throws VxaError.
VxaRobot parse_vxa(const std::string& xml_text, const std::string& source_name);
VxaRobot read_vxa_file(const std::string& path);

// Writes the authors' dialect: palette materials 1-3 with every voxel made of material 3
// ("Active_+"), per-voxel blocks as CDATA layers with every double written so that it reads
// back exactly. Validates both inputs first (std::invalid_argument). Throws VxaError for
// settings the format cannot express (GrowthModel::kRate, act_frequency 0). Settings the
// authors' simulator fixes (e.g. axial_modulus, contact_diameter, fitness mode) are not
// written; if they differ from what reading gives back, a line is added to *warnings.
// For any (robot, physics) obtained from parse_vxa, parse_vxa(write_vxa(...)) gives back the
// same robot arrays and physics fields.
std::string write_vxa(const RobotDef& robot, const PhysicsDef& physics,
                      std::vector<std::string>* warnings = nullptr);
// Writes to "<path>.tmp" and renames it over path. Throws VxaError on I/O failure.
void write_vxa_file(const std::string& path, const RobotDef& robot, const PhysicsDef& physics,
                    std::vector<std::string>* warnings = nullptr);

}  // namespace plastivox
