// The engine's own elementary functions, as lane-generic templates (lane_ops.hpp): atan(t)/t
// and sin(2 pi u). Written in plain IEEE arithmetic (series and exact range reductions), so
// they vectorise like the rest of a kernel and give the same bits on every machine and lane
// width, whichever C library is installed (libm's results are not specified to the bit).
// Included after the lane operations of every lane type used; internal linkage (see
// lane_ops.hpp).
#pragma once

#include "atan_series.hpp"
#include "lane_ops.hpp"

namespace plastivox {
namespace {

// atan(t)/t as a function of t^2 >= 0, for any t (relative error ~1e-16). Lanes set in
// `skip` may hold anything and get an unspecified (finite) value.
//  - t^2 < 1e-2 (rotations under 11 degrees, nearly every bond every step): nine terms of the
//    series (atan_series.hpp);
//  - otherwise atan(t) = y0 + atan(x), with x = t (t <= tan(pi/8)), x = (t - 1)/(t + 1) and
//    y0 = pi/4 (up to tan(3 pi/8)), or x = -1/t and y0 = pi/2 beyond; |x| <= tan(pi/8), so
//    twenty terms of the series leave an error below 2e-17.
// 1 / (2 k + 1), k = 0..19.
constexpr double kOddReciprocals[20] = {1.0,      1.0 / 3,  1.0 / 5,  1.0 / 7,  1.0 / 9,
                                        1.0 / 11, 1.0 / 13, 1.0 / 15, 1.0 / 17, 1.0 / 19,
                                        1.0 / 21, 1.0 / 23, 1.0 / 25, 1.0 / 27, 1.0 / 29,
                                        1.0 / 31, 1.0 / 33, 1.0 / 35, 1.0 / 37, 1.0 / 39};

template <class T, class Mask>
inline T atan_over_t(T t2, Mask skip) {
  const T small = atan_series(t2);
  const Mask wide = and_not(t2 >= 1e-2, skip);
  if (!any(wide)) return small;
  const T one = splat(1.0, T{});
  const T t = root(pick(wide, t2, one));   // 1 in the other lanes: no division by zero below
  const Mask big = t > 2.414213562373095;  // tan(3 pi / 8)
  const Mask mid = and_not(t > 0.41421356237309503, big);  // tan(pi / 8)
  const Mask reduced = big | mid;
  const T x = pick(big, -1.0 / t, pick(mid, (t - 1.0) / (t + 1.0), t));
  const T z = pick(reduced, x * x, pick(wide, t2, one));
  // 1 - z/3 + z^2/5 - ... - z^19/39 as two interleaved Horner chains in w = z^2 (even and
  // odd powers), so the multiplications overlap instead of waiting on each other.
  const T w = z * z;
  T even = splat(kOddReciprocals[18], T{}), odd = splat(kOddReciprocals[19], T{});
  for (int j = 8; j >= 0; --j) {
    even = kOddReciprocals[2 * j] + w * even;
    odd = kOddReciprocals[2 * j + 1] + w * odd;
  }
  const T series = even - z * odd;
  const T y0 = pick(big, splat(1.5707963267948966, T{}),
                    pick(mid, splat(0.78539816339744831, T{}), splat(0.0, T{})));
  const T wide_value = pick(reduced, (y0 + x * series) / t, series);
  return pick(wide, wide_value, small);
}

// sin(2 pi u) for |u| < 2^51. u is reduced exactly to r in [-1/4, 1/4] (sin(2 pi u) =
// sin(2 pi r)), then a = 2 pi r, |a| <= pi/2, and the Taylor series to a^23 (error < 2e-18).
template <class T>
inline T sin_cycles(T u) {
  const double shifter = 6755399441055744.0;  // 1.5 * 2^52: u + shifter rounds u to an integer
  const T n = (u + shifter) - shifter;
  T r = u - n;                                                // exact, in [-1/2, 1/2]
  r = pick(r > 0.25, 0.5 - r, pick(r < -0.25, -0.5 - r, r));  // exact
  const T a = 6.283185307179586 * r;
  const T a2 = a * a;
  // sin a = a (1 - a^2/(2 3) (1 - a^2/(4 5) (1 - a^2/(6 7) ...))).
  T s = 1.0 - a2 * (1.0 / (22 * 23));
  s = 1.0 - a2 * (1.0 / (20 * 21)) * s;
  s = 1.0 - a2 * (1.0 / (18 * 19)) * s;
  s = 1.0 - a2 * (1.0 / (16 * 17)) * s;
  s = 1.0 - a2 * (1.0 / (14 * 15)) * s;
  s = 1.0 - a2 * (1.0 / (12 * 13)) * s;
  s = 1.0 - a2 * (1.0 / (10 * 11)) * s;
  s = 1.0 - a2 * (1.0 / (8 * 9)) * s;
  s = 1.0 - a2 * (1.0 / (6 * 7)) * s;
  s = 1.0 - a2 * (1.0 / (4 * 5)) * s;
  s = 1.0 - a2 * (1.0 / (2 * 3)) * s;
  return a * s;
}

}  // namespace
}  // namespace plastivox
