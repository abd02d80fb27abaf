// The engine's Limits as this program's user sets them: the defaults (plastivox/robot.hpp),
// each raised or lowered by an environment variable.
#pragma once

#include "plastivox/robot.hpp"

namespace plastivox {

// Limits with PLASTIVOX_MAX_LATTICE_SITES (sites), PLASTIVOX_MAX_STEPS (steps) and
// PLASTIVOX_MAX_RECORDING_MB (MB) applied where set. Throws UsageError (the CLI's exit 2, as
// for a bad option; ValueError in Python) "<NAME>: expected a positive whole number of <unit>,
// got '<text>'" for a malformed value.
Limits limits_from_environment();

}  // namespace plastivox
