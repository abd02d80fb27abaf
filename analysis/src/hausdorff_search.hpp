// Internal: the minimisation of d_H over placements of B (see hausdorff_search.cpp), on shapes
// prepared once so that a matrix of pairs reuses each set's index.
#pragma once

#include <array>
#include <vector>

#include "nearest_voxel.hpp"
#include "plastivox/analysis/hausdorff.hpp"

namespace plastivox::analysis::detail {

// A voxel set with its nearest-voxel index and its projections on the three axes.
// Immutable after construction; shared read-only between threads.
struct PreparedShape {
  PreparedShape(const VoxelSet& s, int field_pad);

  VoxelSet set;
  NearestVoxel index;
  std::array<std::vector<int>, 3> projection;  // sorted distinct coordinates along x, y, z
};

HausdorffResult search_placements(const PreparedShape& a, const PreparedShape& b,
                                  const HausdorffOptions& options);

}  // namespace plastivox::analysis::detail
