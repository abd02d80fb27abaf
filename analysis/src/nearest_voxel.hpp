// Exact nearest-voxel distances to one voxel set: a CGAL kd-tree (the design's geometry
// library) answers the queries; a distance field caches the answers around the set.
//
// Why a field: the rotation-and-translation search of the Hausdorff distance asks for the
// distance from the same few thousand lattice points to a set again and again (every candidate
// shift moves the query points by whole voxels). The field stores, for every lattice point of
// the set's bounding box grown by `pad`, the kd-tree's answer; points outside the field go to
// the kd-tree directly. Both are exact: coordinates are small integers, so squared distances
// are integers held exactly in doubles, and the answers are identical either way.
//
// Thread-safety: constructed on one thread (it builds the tree and the field); afterwards all
// member functions are const and may be called from any number of threads.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "plastivox/analysis/voxel_set.hpp"

namespace plastivox::analysis::detail {

class NearestVoxel {
 public:
  // voxels must be non-empty. pad: margin of the cached field around the set's bounding box,
  // lattice units; pad < 0 builds no field (every query goes to the kd-tree).
  NearestVoxel(const std::vector<Voxel>& voxels, int pad);
  ~NearestVoxel();
  NearestVoxel(NearestVoxel&&) noexcept;
  NearestVoxel& operator=(NearestVoxel&&) noexcept;

  // Squared distance from p to the nearest voxel of the set, asked of the kd-tree.
  int64_t query2(const Voxel& p) const;
  // query2(p) (read from the field when p lies inside it) when that is < bound2; otherwise
  // some value >= bound2: outside the field, the bounding-box bound spares the kd-tree query
  // for far points when the caller only needs to know "not below bound2".
  int64_t dist2_below(const Voxel& p, int64_t bound2) const {
    const int x = p[0] - origin_[0], y = p[1] - origin_[1], z = p[2] - origin_[2];
    if (static_cast<unsigned>(x) < static_cast<unsigned>(dims_[0]) &&
        static_cast<unsigned>(y) < static_cast<unsigned>(dims_[1]) &&
        static_cast<unsigned>(z) < static_cast<unsigned>(dims_[2]))
      return field_[x + dims_[0] * (y + dims_[1] * z)];
    const int64_t box = box_dist2(p);
    return box >= bound2 ? box : query2(p);
  }
  // Squared distance from p to the set's bounding box: a lower bound of query2, in O(1).
  int64_t box_dist2(const Voxel& p) const {
    int64_t d2 = 0;
    for (int k = 0; k < 3; ++k) {
      const int64_t d = p[k] < lo_[k] ? lo_[k] - p[k] : (p[k] > hi_[k] ? p[k] - hi_[k] : 0);
      d2 += d * d;
    }
    return d2;
  }
  const Voxel& box_lo() const { return lo_; }  // bounding box of the set, inclusive
  const Voxel& box_hi() const { return hi_; }

  // The cached field, for callers that index it directly: lattice point p (inside it) is at
  // field()[linear(p)]. Empty when built with pad < 0.
  const Voxel& field_origin() const { return origin_; }
  const Voxel& field_dims() const { return dims_; }
  const int32_t* field() const { return field_.data(); }
  bool in_field(const Voxel& lo, const Voxel& hi) const {  // is the box lo..hi inside?
    for (int k = 0; k < 3; ++k)
      if (lo[k] < origin_[k] || hi[k] >= origin_[k] + dims_[k]) return false;
    return true;
  }
  // Offset of p in the field (p need not be inside: offsets are linear in p).
  int linear(const Voxel& p) const {
    return (p[0] - origin_[0]) + dims_[0] * ((p[1] - origin_[1]) + dims_[1] * (p[2] - origin_[2]));
  }

 private:
  struct Tree;  // CGAL types stay in nearest_voxel.cpp
  std::unique_ptr<Tree> tree_;
  Voxel lo_{}, hi_{};           // bounding box of the set
  Voxel origin_{}, dims_{};     // the field covers origin .. origin + dims - 1
  std::vector<int32_t> field_;  // squared distances, x fastest
};

}  // namespace plastivox::analysis::detail
