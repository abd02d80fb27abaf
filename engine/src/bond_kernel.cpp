// See bond_kernel.hpp. The formulas are those of bond_forces.cpp (exact bond model,
// chord-aligned frame), written once as a template over the lane type (bond_lanes_body.hpp):
// `double` here and for the tails, 4-wide (AVX2) and 8-wide (AVX-512) GCC vectors of doubles
// in their own files. All evaluate the same IEEE operations in the same order (no FMA:
// -ffp-contract=off), so a bond's result does not depend on which lane type computed it.
// This file holds the scalar kernel and the choice of instruction set.
//
// The kernel and the scalar path (bond_forces.cpp) evaluate the same formulas: the rotation
// matrix of voxel a is Eigen's toRotationMatrix() formula with its columns cyclically permuted
// so the bond's axis comes first (a per-lane select), and rotations of any size take
// atan_over_t (elementary.hpp). Only degenerate chords and relative rotations near half a
// turn are left to the scalar path (listed in io.redo). Every lane type gives the same bits
// for a bond, so the results do not depend on the instruction set.
#include <atomic>

#include "bond_kernel.hpp"
#include "bond_lanes_body.hpp"
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
  switch (level) {
    case SimdLevel::kScalar:
      return "scalar";
    case SimdLevel::kAvx2:
      return "avx2";
    case SimdLevel::kAvx512:
      return "avx512";
  }
  return "?";
}

int bond_kernel_exact(const BondKernelIo& io, int n, const BondConstants& k) {
  switch (simd_level()) {
#if defined(PLASTIVOX_HAVE_AVX512)
    case SimdLevel::kAvx512:
      return bond_kernel_avx512(io, n, k);
#endif
#if defined(PLASTIVOX_HAVE_AVX2)
    case SimdLevel::kAvx2:
      return bond_kernel_avx2(io, n, k);
#endif
    default:
      break;
  }
  int redo_count = 0;
  for (int i = 0; i < n; ++i) bond_lanes<double>(io, i, k, redo_count);
  return redo_count;
}

}  // namespace plastivox
