// The AVX-512 lane type (lanes_simd.hpp says what an instruction set's file defines before
// including it): V, eight doubles; M, what comparing two V yields; the square root and the
// mask's bits by intrinsics. Included first by each file compiled with -mavx512f -mavx512vl
// -mavx512dq (kernels_avx512.cpp, engine/grad's reverse_avx512.cpp).
#pragma once

#if !defined(__AVX512F__) || !defined(__AVX512VL__) || !defined(__AVX512DQ__)
#error "lanes_avx512.hpp must be compiled with -mavx512f -mavx512vl -mavx512dq"
#endif

// GCC 12 flags _mm512_undefined_pd() inside its own AVX-512 intrinsics as uninitialized
// (a known false positive of the header's self-initialisation idiom).
#pragma GCC diagnostic ignored "-Wuninitialized"
#include <immintrin.h>

namespace plastivox {
namespace {

typedef double V __attribute__((vector_size(64)));
typedef long M __attribute__((vector_size(64)));

inline V root(V v) {
  return (V)_mm512_sqrt_pd((__m512d)v);
}
inline int lane_bits(M c) {
  return _mm512_movepi64_mask((__m512i)c);
}

}  // namespace
}  // namespace plastivox
