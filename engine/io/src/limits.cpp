#include "plastivox/io/limits.hpp"

#include <cerrno>
#include <cstdlib>
#include <string>

#include "plastivox/base/error.hpp"

namespace plastivox {
namespace {

// The value of the environment variable `name`, or `fallback` when it is unset. Set by the
// user as an option is, so a malformed value is a UsageError (exit 2, as a bad option):
// "<name>: expected a positive whole number of <unit>, got '<text>'".
int64_t positive_env_limit(const char* name, int64_t fallback, const char* unit) {
  const char* env = std::getenv(name);
  if (!env) return fallback;
  char* end = nullptr;
  errno = 0;
  const long long v = std::strtoll(env, &end, 10);
  if (errno != 0 || end == env || *end != '\0' || v < 1)
    throw UsageError(std::string(name) + ": expected a positive whole number of " + unit +
                     ", got '" + env + "'");
  return v;
}

}  // namespace

Limits limits_from_environment() {
  Limits l;
  l.lattice_sites = positive_env_limit("PLASTIVOX_MAX_LATTICE_SITES", l.lattice_sites, "sites");
  l.life_steps = positive_env_limit("PLASTIVOX_MAX_STEPS", l.life_steps, "steps");
  l.recording_mb = positive_env_limit("PLASTIVOX_MAX_RECORDING_MB", l.recording_mb, "MB");
  return l;
}

}  // namespace plastivox
