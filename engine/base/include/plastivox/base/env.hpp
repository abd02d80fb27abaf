// Limits an environment variable may raise (or lower): one parser, one message.
#pragma once

#include <cerrno>
#include <cstdint>
#include <cstdlib>
#include <stdexcept>
#include <string>

namespace plastivox {

// The value of the environment variable `name`, or `fallback` when it is unset. Throws
// std::invalid_argument "<name>: expected a positive whole number of <unit>, got '<text>'"
// when it is set to anything else.
inline int64_t positive_env_limit(const char* name, int64_t fallback, const char* unit) {
  const char* env = std::getenv(name);
  if (!env) return fallback;
  char* end = nullptr;
  errno = 0;
  const long long v = std::strtoll(env, &end, 10);
  if (errno != 0 || end == env || *end != '\0' || v < 1)
    throw std::invalid_argument(std::string(name) + ": expected a positive whole number of " +
                                unit + ", got '" + env + "'");
  return v;
}

}  // namespace plastivox
