// atan(t)/t as a function of t^2 by its alternating series, shared by the batched bond
// kernel and the scalar bond path so both evaluate the same expression. Internal linkage
// (unnamed namespace) on purpose: translation units compiled for different instruction sets
// include it, and no such copy may stand in for another's.
#pragma once

namespace plastivox {
namespace {

// Eleven terms leave a relative error below 2e-17 for t^2 < tan^2(pi/16) = 0.0396 (rotations
// under 22.5 degrees: nearly every bond every step).
template <class T>
inline T atan_series(T t2) {
  // 1 - z/3 + z^2/5 - ... - z^10/21 (z = t^2) as two Horner chains in z^2 (even and odd
  // powers), so the multiplications of one overlap those of the other.
  const T w = t2 * t2;
  const T even =
      1.0 + w * (1.0 / 5 + w * (1.0 / 9 + w * (1.0 / 13 + w * (1.0 / 17 + w * (1.0 / 21)))));
  const T odd = 1.0 / 3 + w * (1.0 / 7 + w * (1.0 / 11 + w * (1.0 / 15 + w * (1.0 / 19))));
  return even - t2 * odd;
}

}  // namespace
}  // namespace plastivox
