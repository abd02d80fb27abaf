// atan(t)/t as a function of t^2 by its alternating series, shared by the batched bond
// kernel and the scalar bond path so both evaluate the same expression. Internal linkage
// (unnamed namespace) on purpose: translation units compiled for different instruction sets
// include it, and no such copy may stand in for another's.
#pragma once

namespace plastivox {
namespace {

// Nine terms leave an error below 1e-19 for t^2 < 1e-2 (rotations under 11 degrees).
template <class T>
inline T atan_series(T t2) {
  return 1.0 -
         t2 * (1.0 / 3 -
               t2 * (1.0 / 5 -
                     t2 * (1.0 / 7 -
                           t2 * (1.0 / 9 -
                                 t2 * (1.0 / 11 -
                                       t2 * (1.0 / 13 - t2 * (1.0 / 15 - t2 * (1.0 / 17))))))));
}

}  // namespace
}  // namespace plastivox
