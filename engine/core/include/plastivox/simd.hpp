// The SIMD instruction set of the batched bond kernel, chosen at run time from what the CPU
// has and what the build compiled in. Results are bit-identical on every level (element-wise
// IEEE arithmetic in the same order, no FMA contraction); only speed differs.
#pragma once

namespace plastivox {

enum class SimdLevel {
  kScalar = 0,  // one bond at a time
  kAvx2 = 1,    // four bonds per instruction
  kAvx512 = 2,  // eight bonds per instruction (AVX-512 F, VL and DQ)
};

// The widest level this build and this CPU support (under valgrind, which does not emulate
// AVX-512, at most kAvx2).
SimdLevel best_simd_level();

// The level in use: best_simd_level() unless lowered by set_simd_level().
SimdLevel simd_level();

// Sets the level for every bond-force evaluation from now on, in every thread (levels above
// best_simd_level() are clamped to it). For tests and benchmarks; not meant to be changed
// while simulations run, although doing so changes no result.
void set_simd_level(SimdLevel level);

const char* to_string(SimdLevel level);  // "scalar", "avx2", "avx512"

}  // namespace plastivox
