// Diversity analysis speed: the full pairwise Hausdorff matrix of 20 champions (190 pairs),
// the paper's 8 orientations and the 24-rotation search with integer translation.
#include <algorithm>
#include <vector>

#include <benchmark/benchmark.h>

#include "plastivox/analysis/hausdorff.hpp"
#include "plastivox/analysis/voxel_set.hpp"
#include "plastivox/demo_robots.hpp"

namespace plastivox::analysis {
namespace {

// 20 irregular bodies of 500 to 1000 voxels.
std::vector<VoxelSet> champions() {
  std::vector<VoxelSet> sets;
  for (int i = 0; i < 20; ++i)
    sets.push_back(voxel_set(demo_irregular(500 + 500 * i / 19, 100 + i)));
  return sets;
}

void BM_HausdorffMatrix20(benchmark::State& bs) {
  const std::vector<VoxelSet> sets = champions();
  const HausdorffOptions options = bs.range(0) ? aligned_hausdorff() : paper_hausdorff();
  for (auto _ : bs) benchmark::DoNotOptimize(hausdorff_matrix(sets, options, 0));
  bs.counters["pairs"] = 190;
}
BENCHMARK(BM_HausdorffMatrix20)
    ->Arg(0)
    ->Arg(1)
    ->ArgName("all_rotations")
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace
}  // namespace plastivox::analysis

BENCHMARK_MAIN();
