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
  // 1 - z/3 + z^2/5 - ... + z^10/21 (z = t^2) by Estrin's scheme: pairs of terms, then pairs
  // of pairs with z^2, z^4, z^8, so the chain of dependent operations is four multiply-adds
  // long instead of ten (the kernels that call this are bound by such chains).
  const T z = t2;
  const T z2 = z * z, z4 = z2 * z2, z8 = z4 * z4;
  const T p01 = 1.0 - z * (1.0 / 3), p23 = 1.0 / 5 - z * (1.0 / 7);
  const T p45 = 1.0 / 9 - z * (1.0 / 11), p67 = 1.0 / 13 - z * (1.0 / 15);
  const T p89 = 1.0 / 17 - z * (1.0 / 19);
  const T q0 = p01 + z2 * p23, q1 = p45 + z2 * p67, q2 = p89 + z2 * (1.0 / 21);
  return (q0 + z4 * q1) + z8 * q2;
}

}  // namespace
}  // namespace plastivox
