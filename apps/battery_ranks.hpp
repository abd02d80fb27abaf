// The robustness battery's lives over MPI ranks (analyze and robustness under mpirun).
#pragma once

#include <functional>
#include <vector>

#include "plastivox/analysis/battery.hpp"

namespace plastivox::evo {
class Cluster;
}

namespace plastivox::cli {

using BatteryLives =
    std::function<std::vector<analysis::BatteryRun>(const std::vector<analysis::PerturbedLife>&)>;

// Under mpirun with more than one rank, StudyOptions::battery_lives for this rank: every rank
// is handed the same lives in the same order (each runs the same study), simulates its share
// on `threads` threads (0: all cores) and receives every other rank's outcomes, so all ranks
// go on with the same profiles. Shares: the longest life first, each to the rank with the
// least work so far (voxel-steps; evo::assign_by_cost). Empty (this process's pool) without a
// cluster of two ranks.
BatteryLives battery_lives_over_ranks(evo::Cluster* cluster, int threads);

}  // namespace plastivox::cli
