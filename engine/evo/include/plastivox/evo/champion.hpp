// Picking a run's champion: the individual every tool means by "the run's robot" (export,
// render, gallery, experiment).
#pragma once

#include <string>

#include "plastivox/evo/run_state.hpp"
#include "plastivox/robot.hpp"

namespace plastivox::evo {

// The champion at the end of `generation` (-1: the last generation done): the last new best
// recorded by then. `source` (the results file's path) names the file in errors. Throws
// InputError (plastivox/robot_file.hpp) when the run has no generation yet, the generation
// is beyond those done, or no champion was recorded by then.
const ChampionRecord& champion_at(const RunState& run, int generation, const std::string& source);

// The champion's robot (present voxels, E0, alpha, phase), named
// "champion-<id>-gen<generation>".
RobotDef champion_robot(const ChampionRecord& champion, int generation);

}  // namespace plastivox::evo
