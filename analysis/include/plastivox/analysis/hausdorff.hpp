// Geometric diversity (docs/method.md §8, Fig. 5 panel B): the Hausdorff distance between
// the filled-voxel index sets of two robots,
//
//   d_H(A, B) = max( max_a min_b |a - b|, max_b min_a |a - b| ),   Euclidean, lattice units,
//
// with the nearest-neighbour queries answered by CGAL's spatial searching (an exact kd-tree).
// Because d_H depends on how B is oriented, it is minimised over a set of placements of B:
//
//   RotationSearch::kNone   B as it is.
//   RotationSearch::kPaper  the paper's 8 orientations (voxel_set.hpp, paper_rotations()), each
//                           applied the way numpy.rot90 turns B's lattice array.
//   RotationSearch::kAll    all 24 proper rotations of the cube (beyond the paper).
//   TranslationSearch::kNone     no alignment (the paper): B rotated inside its lattice box.
//   TranslationSearch::kInteger  B also shifted by the integer vector t that minimises d_H,
//                                found exactly (beyond the paper; see hausdorff_search.cpp):
//                                every shift that could beat the best is examined, the rest are
//                                excluded by a proven lower bound. Shifts are whole voxels, so
//                                B stays on the lattice; a half-voxel shift might do better, and
//                                is not considered.
//
// Results are exact (squared distances are integers) and deterministic: ties between
// placements resolve to the first in the documented search order. Functions are thread-safe.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "plastivox/analysis/voxel_set.hpp"

namespace plastivox::analysis {

enum class RotationSearch { kNone, kPaper, kAll };
enum class TranslationSearch { kNone, kInteger };
const char* to_string(RotationSearch r);                     // "none", "paper", "all"
const char* to_string(TranslationSearch t);                  // "none", "integer"
RotationSearch parse_rotation_search(const std::string& s);  // throws std::invalid_argument

struct HausdorffOptions {
  RotationSearch rotations = RotationSearch::kNone;
  TranslationSearch translation = TranslationSearch::kNone;
  // Margin (lattice units) of the cached distance field around each set; affects speed only.
  int field_pad = 4;
};
HausdorffOptions paper_hausdorff();    // kPaper rotations, no translation: as published
HausdorffOptions aligned_hausdorff();  // kAll rotations, optimal integer translation

// The rotation set a search uses (identity_rotations, paper_rotations or cube_rotations).
const std::vector<Rotation>& rotation_set(RotationSearch r);

struct HausdorffResult {
  double distance = 0;    // minimised d_H, lattice units (voxel edge lengths)
  int64_t distance2 = 0;  // its square, an exact integer
  // The minimising placement of B: every voxel b goes to rotate_voxel(rotation, b) + translation.
  // Without translation search, translation is rotate_in_lattice's shift.
  int rotation_index = 0;  // into rotation_set(rotations)
  Rotation rotation;
  Voxel translation = {0, 0, 0};
  RotationSearch rotations = RotationSearch::kNone;
  TranslationSearch translation_search = TranslationSearch::kNone;
};

// d_H between two point sets exactly as given (no rotation, no shift), lattice units.
// Throws std::invalid_argument if either is empty.
double hausdorff_distance(const std::vector<Voxel>& a, const std::vector<Voxel>& b);

// d_H(A, B) minimised over the placements of B the options allow. Throws std::invalid_argument
// if either set is empty.
HausdorffResult hausdorff(const VoxelSet& a, const VoxelSet& b,
                          const HausdorffOptions& options = {});

// All pairs of a set of champions.
struct HausdorffMatrix {
  int n = 0;
  HausdorffOptions options;
  // n*n, row-major, zero diagonal. Entry (i, j) = entry (j, i) = hausdorff(sets[i], sets[j])
  // for i < j (B = the later set is the one rotated; see paper_rotations() on symmetry).
  std::vector<double> distance;
  std::vector<HausdorffResult> pairs;  // n(n-1)/2 results, pairs (0,1), (0,2), ..., (1,2), ...
  double at(int i, int j) const { return distance[static_cast<size_t>(i) * n + j]; }
};

// Pairs are spread over `threads` threads (0 = the hardware's count); every pair is computed
// on one thread by the same sequential code, so the matrix does not depend on the thread
// count. Throws std::invalid_argument if a set is empty.
HausdorffMatrix hausdorff_matrix(const std::vector<VoxelSet>& sets,
                                 const HausdorffOptions& options = {}, int threads = 0);

}  // namespace plastivox::analysis
