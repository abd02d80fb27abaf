// Plain Hausdorff distance, option helpers, and the single-pair entry point.
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "hausdorff_search.hpp"
#include "nearest_voxel.hpp"
#include "plastivox/analysis/hausdorff.hpp"
#include "plastivox/base/names.hpp"

namespace plastivox::analysis {

namespace {
constexpr Named<RotationSearch> kRotationSearchNames[] = {{RotationSearch::kNone, "none"},
                                                          {RotationSearch::kPaper, "paper"},
                                                          {RotationSearch::kAll, "all"}};
}  // namespace

const char* to_string(RotationSearch r) {
  return name_in(kRotationSearchNames, r);
}

const char* to_string(TranslationSearch t) {
  return t == TranslationSearch::kNone ? "none" : "integer";
}

RotationSearch parse_rotation_search(const std::string& s) {
  if (const auto r = value_in(kRotationSearchNames, s)) return *r;
  throw std::invalid_argument("unknown rotation search '" + s + "' (expected " +
                              choices_in(kRotationSearchNames) + ")");
}

HausdorffOptions paper_hausdorff() {
  HausdorffOptions o;
  o.rotations = RotationSearch::kPaper;
  return o;
}

HausdorffOptions aligned_hausdorff() {
  HausdorffOptions o;
  o.rotations = RotationSearch::kAll;
  o.translation = TranslationSearch::kInteger;
  return o;
}

const std::vector<Rotation>& rotation_set(RotationSearch r) {
  switch (r) {
    case RotationSearch::kNone:
      return identity_rotations();
    case RotationSearch::kPaper:
      return paper_rotations();
    case RotationSearch::kAll:
      return cube_rotations();
  }
  return identity_rotations();
}

namespace {
// max over p in from of the squared distance to the nearest point of `to`.
int64_t directed2(const std::vector<Voxel>& from, const detail::NearestVoxel& to) {
  int64_t worst = 0;
  for (const Voxel& p : from) worst = std::max(worst, to.query2(p));
  return worst;
}
}  // namespace

double hausdorff_distance(const std::vector<Voxel>& a, const std::vector<Voxel>& b) {
  if (a.empty() || b.empty()) throw std::invalid_argument("hausdorff_distance: empty voxel set");
  // Straight kd-tree queries, no cached field: this is the reference the search is tested
  // against, and the shortest path to CGAL's answer.
  const detail::NearestVoxel index_a(a, -1), index_b(b, -1);
  const int64_t d2 = std::max(directed2(a, index_b), directed2(b, index_a));
  return std::sqrt(static_cast<double>(d2));
}

HausdorffResult hausdorff(const VoxelSet& a, const VoxelSet& b, const HausdorffOptions& options) {
  if (a.voxels.empty() || b.voxels.empty())
    throw std::invalid_argument("hausdorff: empty voxel set");
  const detail::PreparedShape pa(a, options.field_pad), pb(b, options.field_pad);
  return detail::search_placements(pa, pb, options);
}

}  // namespace plastivox::analysis
