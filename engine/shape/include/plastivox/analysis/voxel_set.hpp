// A robot's geometry as the analysis sees it: the integer lattice indices of its filled voxels
// (no stiffness, no physics), and the 24 proper rotations of the cube that act on them.
//
// Distances between voxel sets are in lattice units (voxel edge lengths), whatever the
// robots' voxel_size: the paper compares "filled-voxel index sets".
#pragma once

#include <array>
#include <string>
#include <vector>

#include "plastivox/robot.hpp"

namespace plastivox::analysis {

using Voxel = std::array<int, 3>;  // lattice index (x, y, z)

struct VoxelSet {
  Voxel lattice = {10, 10, 10};  // extent nx, ny, nz (the box rotations keep a set inside)
  std::vector<Voxel> voxels;     // filled sites, in increasing site order (x fastest)
};

// The present voxels of a robot. Throws std::invalid_argument if `present` is not
// lattice-sized.
VoxelSet voxel_set(const RobotDef& robot);

// A proper rotation of the cube: a signed permutation matrix with determinant +1, acting on
// column vectors (p' = m p).
struct Rotation {
  std::array<std::array<int, 3>, 3> m = {{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
  std::string name;  // the image of (x,y,z), e.g. "(-y,x,z)" for +90 deg about z
};

inline Voxel rotate_voxel(const Rotation& r, const Voxel& p) {
  Voxel q{};
  for (int i = 0; i < 3; ++i) q[i] = r.m[i][0] * p[0] + r.m[i][1] * p[1] + r.m[i][2] * p[2];
  return q;
}
Rotation compose(const Rotation& outer, const Rotation& inner);  // outer after inner
Rotation inverse(const Rotation& r);                             // the transpose
bool operator==(const Rotation& a, const Rotation& b);           // same matrix

// {identity}: no rotation search.
const std::vector<Rotation>& identity_rotations();
// The paper's 8 orientations of B (docs/method.md §8): R = T^j * Z^k, k = 0..3, j = 0..1,
// index 2k + j; Z is +90 deg about z ((x,y) -> (-y,x), numpy.rot90(B, k, axes=(0,1))) and T
// one +90 deg turn in the yz plane ((y,z) -> (-z,y), numpy.rot90(B, 1, axes=(1,2))) applied
// after the z rotation. The paper's text does not say in which order or sense its two
// rotations were applied; this is our reading, and the set is not closed under inversion, so
// the paper's measure min_R d(A, R B) need not be symmetric in A and B.
const std::vector<Rotation>& paper_rotations();
// All 24 proper rotations of the cube, the identity first, then in lexicographic order of
// their matrices (a fixed, documented order: best-rotation ties resolve to the earliest).
const std::vector<Rotation>& cube_rotations();

// Rotates a set the way numpy.rot90 rotates an array: the lattice box is rotated and put
// back with its minimum corner at the origin (p' = R p + s, s = -min over box corners of R c),
// so the result stays inside the rotated lattice. The lattice extents are permuted.
VoxelSet rotate_in_lattice(const VoxelSet& set, const Rotation& r);
// The shift s that rotate_in_lattice adds after R.
Voxel lattice_shift(const Voxel& lattice, const Rotation& r);

}  // namespace plastivox::analysis
