// The engine's own elementary functions, as lane-generic templates (lanes.hpp): atan(t)/t
// and sin(2 pi u). Written in plain IEEE arithmetic (series and exact range reductions), so
// they vectorise like the rest of a kernel and give the same bits on every machine and lane
// width, whichever C library is installed (libm's results are not specified to the bit).
// Internal linkage (see lanes.hpp).
#pragma once

#include "atan_series.hpp"
#include "lanes.hpp"

namespace plastivox {
namespace {

// atan(t)/t as a function of t^2 >= 0, for any t (relative error ~1e-16). Lanes set in
// `skip` may hold anything and get an unspecified (finite) value. With t = tan(phi):
//  - phi < pi/16 (t^2 < 0.0396; nearly every bond every step): the series (atan_series.hpp);
//  - otherwise atan(t) = atan(c) + atan(x), x = (t - c) / (1 + t c), with c = tan(k pi/8) the
//    nearest of tan(pi/8), 1, tan(3 pi/8), or x = -1/t and atan(c) = pi/2 beyond tan(7 pi/16);
//    |x| <= tan(pi/16), so the same series gives atan(x) / x.
// A lane's branch is decided by its own t^2 alone, so its value does not depend on the other
// lanes of its group (nor on the lane width).
template <class T, class Mask>
inline T atan_over_t(T t2, Mask skip) {
  const Mask wide = and_not(t2 >= 0.03956612989658004, skip);  // tan^2(pi / 16)
  if (!any(wide)) return atan_series(t2);
  const T one = splat(1.0, T{});
  const T t = root(pick(wide, t2, one));      // 1 in the other lanes: no division by zero below
  const Mask c2 = t2 >= 0.44646269217168955;  // tan^2(3 pi / 16)
  const Mask c3 = t2 >= 2.23982880884355;     // tan^2(5 pi / 16)
  const Mask big = t2 >= 25.27414236908818;   // tan^2(7 pi / 16)
  const T c =
      pick(c3, splat(2.414213562373095, T{}), pick(c2, one, splat(0.41421356237309503, T{})));
  const T x = pick(big, splat(-1.0, T{}), t - c) / pick(big, t, 1.0 + t * c);
  const T atan_c =
      pick(big, splat(1.5707963267948966, T{}),
           pick(c3, splat(1.1780972450961724, T{}),
                pick(c2, splat(0.78539816339744831, T{}), splat(0.39269908169872414, T{}))));
  const T inv_t = 1.0 / t;  // alongside x's division rather than at the end of the chain
  // One series for the group: in x^2 for the wide lanes, in t^2 (the same bits as above)
  // for the others.
  const T series = atan_series(pick(wide, x * x, t2));
  return pick(wide, (atan_c + x * series) * inv_t, series);
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
