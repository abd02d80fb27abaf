// Wall-clock intervals for reports (never for results: nothing simulated depends on time).
#pragma once

#include <chrono>
#include <ctime>
#include <string>

namespace plastivox {

using WallClock = std::chrono::steady_clock;

// Seconds from t0 to now.
inline double seconds_since(WallClock::time_point t0) {
  return std::chrono::duration<double>(WallClock::now() - t0).count();
}

// Now in UTC, ISO 8601 to the second ("2026-12-03T17:40:00Z"): provenance dates and logs.
inline std::string utc_timestamp() {
  const std::time_t t = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&t, &tm);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buf;
}

}  // namespace plastivox
