#include "plastivox/io/limits.hpp"

#include <stdexcept>

#include "plastivox/base/env.hpp"
#include "plastivox/base/error.hpp"

namespace plastivox {

Limits limits_from_environment() {
  Limits l;
  try {
    l.lattice_sites = positive_env_limit("PLASTIVOX_MAX_LATTICE_SITES", l.lattice_sites, "sites");
    l.life_steps = positive_env_limit("PLASTIVOX_MAX_STEPS", l.life_steps, "steps");
    l.recording_mb = positive_env_limit("PLASTIVOX_MAX_RECORDING_MB", l.recording_mb, "MB");
  } catch (const std::invalid_argument& e) {
    throw UsageError(e.what());  // set by the user as an option is: exit 2, as a bad option
  }
  return l;
}

}  // namespace plastivox
