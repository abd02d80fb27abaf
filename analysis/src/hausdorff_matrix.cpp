// The pairwise Hausdorff matrix of a set of champions, parallel over pairs.
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>

#include "hausdorff_search.hpp"
#include "plastivox/analysis/hausdorff.hpp"
#include "plastivox/base/parallel.hpp"

namespace plastivox::analysis {

HausdorffMatrix hausdorff_matrix(const std::vector<VoxelSet>& sets, const HausdorffOptions& options,
                                 int threads) {
  const int n = static_cast<int>(sets.size());
  for (int i = 0; i < n; ++i)
    if (sets[i].voxels.empty())
      throw std::invalid_argument("hausdorff_matrix: set " + std::to_string(i) + " is empty");

  // Each set's index is built once and then only read, by every pair that uses it.
  std::vector<std::unique_ptr<detail::PreparedShape>> prepared(n);
  parallel_for(static_cast<size_t>(n), threads, [&](size_t i_) {
    const int i = static_cast<int>(i_);
    prepared[i] = std::make_unique<detail::PreparedShape>(sets[i], options.field_pad);
  });

  std::vector<std::pair<int, int>> pair_index;
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; ++j) pair_index.push_back({i, j});

  HausdorffMatrix m;
  m.n = n;
  m.options = options;
  m.distance.assign(static_cast<size_t>(n) * n, 0.0);
  m.pairs.resize(pair_index.size());
  parallel_for(pair_index.size(), threads, [&](size_t k_) {
    const int k = static_cast<int>(k_);
    const auto [i, j] = pair_index[k];
    m.pairs[k] = detail::search_placements(*prepared[i], *prepared[j], options);
  });
  for (size_t k = 0; k < pair_index.size(); ++k) {
    const auto [i, j] = pair_index[k];
    m.distance[static_cast<size_t>(i) * n + j] = m.pairs[k].distance;
    m.distance[static_cast<size_t>(j) * n + i] = m.pairs[k].distance;
  }
  return m;
}

}  // namespace plastivox::analysis
