// The engine's own atan(t)/t and sin(2 pi u) (engine/core/src/elementary.hpp) against libm over
// their whole ranges: the engine uses them instead of libm so results do not depend on the
// C library, so they must be as accurate as libm's to a few units in the last place.
#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "elementary.hpp"

namespace plastivox {
namespace {

// Relative error in units of 2^-52.
double ulps(double got, double want) {
  return std::abs(got - want) / (std::abs(want) * 0x1p-52);
}

TEST(Elementary, AtanOverTMatchesLibmEverywhere) {
  double worst = 0;
  // t from 1e-4 to 1e4, geometric steps, across every branch (the series, the three reductions
  // about tan(k pi/8), -1/t).
  for (double t = 1e-4; t < 1e4; t *= 1.0007) {
    const double want = std::atan(t) / t;
    worst = std::max(worst, ulps(atan_over_t(t * t, false), want));
  }
  EXPECT_LT(worst, 4.0);
  EXPECT_EQ(atan_over_t(0.0, false), 1.0);
}

TEST(Elementary, AtanOverTIsContinuousAtItsBranchPoints) {
  for (double t : {0.198912367379658, 0.6681786379192989, 1.496605762665489, 5.027339492125848}) {
    const double below = atan_over_t(std::nextafter(t, 0.0) * std::nextafter(t, 0.0), false);
    const double above = atan_over_t(std::nextafter(t, 10.0) * std::nextafter(t, 10.0), false);
    EXPECT_LT(std::abs(above - below), 8e-16) << "t = " << t;
  }
}

TEST(Elementary, SinCyclesMatchesLibm) {
  double worst_abs = 0;
  // u as the actuation forms it: f t + phase, f = 5 Hz, t up to 10 s, phase in (-1, 1).
  for (double u = -1.0; u < 51.0; u += 0.000731) {
    const double want = std::sin(2.0 * std::numbers::pi * u);
    // libm sees 2 pi u rounded (an argument error up to ~1e-14 at u = 50); compare with the
    // exact-argument value through a long-double reduction instead.
    const long double r = static_cast<long double>(u) - std::nearbyint(static_cast<long double>(u));
    const double exact = static_cast<double>(std::sin(2.0L * std::numbers::pi_v<long double> * r));
    worst_abs = std::max(worst_abs, std::abs(sin_cycles(u) - exact));
    EXPECT_NEAR(sin_cycles(u), want, 2e-13);
  }
  EXPECT_LT(worst_abs, 4e-16);
  EXPECT_EQ(sin_cycles(0.0), 0.0);
  EXPECT_EQ(sin_cycles(0.25), 1.0);
  EXPECT_EQ(sin_cycles(-0.25), -1.0);
  EXPECT_EQ(sin_cycles(3.5), 0.0);
}

}  // namespace
}  // namespace plastivox
