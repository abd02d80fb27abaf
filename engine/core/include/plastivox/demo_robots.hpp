// Built-in robots: the canonical scenario shared by the demo, the determinism test, the
// benchmark and the renderer (one fixed robot, so a golden hash means something).
#pragma once

#include <string>
#include <vector>

#include "plastivox/robot.hpp"

namespace plastivox {

// 512-voxel walker on the 10x10x10 lattice: a slab on front and back legs, with a smooth
// log-stiffness field spanning 7e9..1e10 Pa (stiff enough to stand under the presets' 1e9
// kg/m^3), development rates in [0, 6] 1/s (loaded voxels stiffen) and a phase gradient front
// to back. It stands and walks under every treatment (floor health ok). Deterministic.
RobotDef demo_walker();

// A full n*n*n cube of uniform stiffness E (n^3 voxels), phases in a gradient along x.
RobotDef demo_cube(int n, double E);

// An irregular body of roughly `target` voxels on a 10x10x10 lattice, mixed stiffness
// (1e5..1e11 Pa), development rates in [-10, 10]; same seed, same robot.
RobotDef demo_irregular(int target, unsigned seed);

// The example robots shipped in examples/ (`plastivox export --demo NAME` writes them):
// "walker" (demo_walker), "pi", "gamma" and "upsilon" (one body of each of the paper's body
// plans, analysis/include/plastivox/analysis/body_plan.hpp) and "mixture" (soft and stiff
// blocks). Deterministic; smooth development-rate and phase fields.
// Throws InputError for another name.
RobotDef demo_example(const std::string& name);
// The names demo_example knows, in the order above.
const std::vector<std::string>& demo_example_names();

}  // namespace plastivox
