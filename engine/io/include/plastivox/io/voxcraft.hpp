// The input dialect of voxcraft-sim (the GPU Voxelyze of voxcraft/voxcraft-sim): a base.vxa
// with the settings and environment, plus one .vxd per robot whose top-level elements that
// carry replace="VXA.A.B" replace that whole subtree of the base before the VXA is read.
//
// Export turns a plastivox robot into such a pair: per-voxel stiffness becomes a palette of
// materials (quantise_stiffness), the stiffness-damped actuation of the paper becomes each
// material's CTE, and the protocol becomes voxcraft's tags (stop formula, EnableExpansion,
// TurnOnThermalExpansionAfterThisManySeconds for the settling phase). Import reads the pair
// back as a robot with per-voxel amplitudes (RobotDef::act_amplitude). What either side
// cannot express is refused with one line (export: unless lossy, then dropped with a line
// each). docs/vxa.md, "voxcraft-sim", tables every tag both ways.
#pragma once

#include <string>
#include <vector>

#include "plastivox/io/vxa.hpp"
#include "plastivox/physics_def.hpp"
#include "plastivox/robot.hpp"

namespace plastivox {

// Most materials an exported palette holds: an ASCII_READABLE layer stores material id k as
// the character 48 + k, and '~' (126) is the last printable ASCII character, so ids 1..78.
constexpr int kVoxcraftMaxMaterials = 78;

// At most max_levels stiffness levels for `values` (each > 0, Pa), chosen to make the largest
// relative error as small as the greedy cover in log space can: values are cut into runs of
// log-width 2d with d as small as allows max_levels runs, each run represented by the
// geometric mean of its ends. Distinct values that fit are kept exactly (error 0).
struct StiffnessPalette {
  std::vector<double> levels;  // increasing, Pa
  std::vector<int> level_of;   // per value: its index in levels
  double max_rel_error = 0;    // max over values of |level - value| / value
};
StiffnessPalette quantise_stiffness(const std::vector<double>& values, int max_levels);

struct VoxcraftFiles {
  std::string base_vxa;                // settings, environment, lattice
  std::string robot_vxd;               // palette and structure (replace="VXA.VXC.Palette", ...)
  int materials = 0;                   // palette size
  double max_stiffness_error = 0;      // StiffnessPalette::max_rel_error over the voxels
  std::vector<std::string> dropped;    // under lossy: what was not written, one line each
  std::vector<std::string> unchanged;  // settings voxcraft-sim fixes its own way (one line)
};

// The pair for (robot, physics). Throws VxaError, one line naming what voxcraft-sim cannot
// express, unless `lossy`: development (nonzero rates under a treatment), fixed voxels and
// loads, a size floor (act_min_factor) the wave reaches, more than kVoxcraftMaxMaterials
// (stiffness, amplitude) pairs. std::invalid_argument for an invalid robot or physics.
VoxcraftFiles write_voxcraft(const RobotDef& robot, const PhysicsDef& physics, bool lossy);
// Writes dir/base.vxa and dir/robot.vxd (creating dir). Throws VxaError on I/O failure.
VoxcraftFiles write_voxcraft_files(const std::string& dir, const RobotDef& robot,
                                   const PhysicsDef& physics, bool lossy);

// Reads base + vxd as voxcraft-sim does (merge, then the VXA) into a robot whose voxels carry
// their material's E and TempAmplitude * CTE as act_amplitude, and the physics voxcraft-sim
// would run (see docs/vxa.md). Throws VxaError, one line: "<file>: <tag path>: what", and for
// features plastivox does not model one line naming them all.
VxaRobot parse_voxcraft(const std::string& base_text, const std::string& base_name,
                        const std::string& vxd_text, const std::string& vxd_name);
VxaRobot read_voxcraft(const std::string& base_path, const std::string& vxd_path);

}  // namespace plastivox
