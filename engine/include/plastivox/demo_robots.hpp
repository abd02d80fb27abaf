// Built-in robots: the canonical scenario shared by the demo, the determinism test, the
// benchmark and the renderer (one fixed robot, so a golden hash means something).
#pragma once

#include "plastivox/robot.hpp"

namespace plastivox {

// ~500-voxel four-legged walker on the 10x10x10 lattice: a slab on front and back legs,
// with a smooth log-stiffness field spanning 3e8..3e10 Pa (stiff enough to stand), development
// rates in [-10, 10] and a phase gradient front to back. Deterministic: no randomness.
RobotDef demo_walker();

// A full n*n*n cube of uniform stiffness E (n^3 voxels), phases in a gradient along x.
RobotDef demo_cube(int n, double E);

// An irregular body of roughly `target` voxels on a 10x10x10 lattice, mixed stiffness
// (1e5..1e11 Pa), development rates in [-10, 10]; same seed, same robot.
RobotDef demo_irregular(int target, unsigned seed);

}  // namespace plastivox
