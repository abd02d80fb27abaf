// The AVX2 lane type (lanes_simd.hpp says what an instruction set's file defines before
// including it): V, four doubles; M, what comparing two V yields; the square root and the
// mask's bits by intrinsics. Included first by each file compiled with -mavx2
// (kernels_avx2.cpp, engine/grad's reverse_avx2.cpp).
#pragma once

#if !defined(__AVX2__)
#error "lanes_avx2.hpp must be compiled with -mavx2"
#endif

#include <immintrin.h>

namespace plastivox {
namespace {

typedef double V __attribute__((vector_size(32)));
typedef long M __attribute__((vector_size(32)));

inline V root(V v) {
  return (V)_mm256_sqrt_pd((__m256d)v);
}
inline int lane_bits(M c) {
  return _mm256_movemask_pd((__m256d)c);
}

}  // namespace
}  // namespace plastivox
