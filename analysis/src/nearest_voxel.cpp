// The one translation unit that includes CGAL (it is header-heavy): spatial searching with
// CGAL::Orthogonal_k_neighbor_search over a CGAL::Kd_tree, exact (epsilon 0), k = 1.
#include "nearest_voxel.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <stdexcept>

#include <CGAL/Orthogonal_k_neighbor_search.h>
#include <CGAL/Search_traits_3.h>
#include <CGAL/Simple_cartesian.h>

namespace plastivox::analysis::detail {

namespace {
using Kernel = CGAL::Simple_cartesian<double>;
using Point = Kernel::Point_3;
using Traits = CGAL::Search_traits_3<Kernel>;
using Search = CGAL::Orthogonal_k_neighbor_search<Traits>;  // Euclidean, squared distances
}  // namespace

struct NearestVoxel::Tree {
  explicit Tree(const std::vector<Point>& points) : tree(points.begin(), points.end()) {}
  Search::Tree tree;
};

NearestVoxel::NearestVoxel(const std::vector<Voxel>& voxels, int pad) {
  if (voxels.empty()) throw std::invalid_argument("nearest-voxel index of an empty voxel set");
  std::vector<Point> points;
  points.reserve(voxels.size());
  lo_ = hi_ = voxels[0];
  for (const Voxel& v : voxels) {
    points.emplace_back(v[0], v[1], v[2]);
    for (int k = 0; k < 3; ++k) {
      lo_[k] = std::min(lo_[k], v[k]);
      hi_[k] = std::max(hi_[k], v[k]);
    }
  }
  tree_ = std::make_unique<Tree>(points);
  // Build now: CGAL builds lazily on the first query, which is not thread-safe.
  tree_->tree.build();

  if (pad < 0) return;  // no field: dims_ stay 0, dist2 always queries
  for (int k = 0; k < 3; ++k) {
    origin_[k] = lo_[k] - pad;
    dims_[k] = hi_[k] - lo_[k] + 1 + 2 * pad;
  }
  field_.resize(static_cast<size_t>(dims_[0]) * dims_[1] * dims_[2]);
  size_t i = 0;
  for (int z = 0; z < dims_[2]; ++z)
    for (int y = 0; y < dims_[1]; ++y)
      for (int x = 0; x < dims_[0]; ++x)
        field_[i++] =
            static_cast<int32_t>(query2({origin_[0] + x, origin_[1] + y, origin_[2] + z}));
}

NearestVoxel::~NearestVoxel() = default;
NearestVoxel::NearestVoxel(NearestVoxel&&) noexcept = default;
NearestVoxel& NearestVoxel::operator=(NearestVoxel&&) noexcept = default;

int64_t NearestVoxel::query2(const Voxel& p) const {
  const Search search(tree_->tree, Point(p[0], p[1], p[2]), 1);
  const double d2 = search.begin()->second;
  // Integer coordinates: the squared distance is an exact integer in double.
  assert(d2 == std::floor(d2) && "nearest-voxel distance not integral: coordinates too large?");
  return static_cast<int64_t>(d2);
}

}  // namespace plastivox::analysis::detail
