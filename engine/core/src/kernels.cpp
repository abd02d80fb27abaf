// See kernels.hpp: the instruction set in use (plastivox/simd.hpp: detected from the CPU,
// lowered by set_simd_level()) and the scalar kernel set.
#include <atomic>

#include "kernels.hpp"

#include "kernels_body.hpp"
#include "plastivox/base/names.hpp"
#include "plastivox/simd.hpp"

namespace plastivox {
namespace {

SimdLevel detect_simd_level() {
#if defined(__x86_64__) || defined(__i386__)
  __builtin_cpu_init();
#if defined(PLASTIVOX_HAVE_AVX512)
  if (__builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl") &&
      __builtin_cpu_supports("avx512dq"))
    return SimdLevel::kAvx512;
#endif
#if defined(PLASTIVOX_HAVE_AVX2)
  if (__builtin_cpu_supports("avx2")) return SimdLevel::kAvx2;
#endif
#endif
  return SimdLevel::kScalar;
}

// -1 until the first use, then the level in use.
std::atomic<int> g_level{-1};

}  // namespace

SimdLevel best_simd_level() {
  static const SimdLevel best = detect_simd_level();
  return best;
}

SimdLevel simd_level() {
  const int level = g_level.load(std::memory_order_relaxed);
  return level < 0 ? best_simd_level() : static_cast<SimdLevel>(level);
}

void set_simd_level(SimdLevel level) {
  const SimdLevel best = best_simd_level();
  g_level.store(static_cast<int>(level > best ? best : level), std::memory_order_relaxed);
}

const char* to_string(SimdLevel level) {
  static constexpr Named<SimdLevel> kNames[] = {
      {SimdLevel::kScalar, "scalar"}, {SimdLevel::kAvx2, "avx2"}, {SimdLevel::kAvx512, "avx512"}};
  return name_in(kNames, level);
}

const KernelSet& kernels() {
  switch (simd_level()) {
#if defined(PLASTIVOX_HAVE_AVX512)
    case SimdLevel::kAvx512: {
      static const KernelSet avx512 = kernels_avx512();
      return avx512;
    }
#endif
#if defined(PLASTIVOX_HAVE_AVX2)
    case SimdLevel::kAvx2: {
      static const KernelSet avx2 = kernels_avx2();
      return avx2;
    }
#endif
    default: {
      static const KernelSet scalar = make_kernel_set<double>();
      return scalar;
    }
  }
}

}  // namespace plastivox
