// Wall-clock intervals for reports (never for results: nothing simulated depends on time).
#pragma once

#include <chrono>

namespace plastivox {

using WallClock = std::chrono::steady_clock;

// Seconds from t0 to now.
inline double seconds_since(WallClock::time_point t0) {
  return std::chrono::duration<double>(WallClock::now() - t0).count();
}

}  // namespace plastivox
