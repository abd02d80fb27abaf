// Determinism: a run is defined by its robot and parameters; same inputs, same bits out,
// whichever thread runs it and whatever runs beside it.
#include <thread>

#include "plastivox/demo_robots.hpp"
#include "plastivox/simd.hpp"
#include "test_support.hpp"

namespace plastivox {
namespace {

PhysicsDef short_life(Treatment t) {
  PhysicsDef d;
  d.treatment = t;
  d.duration = 0.5;  // settle 0.2 s, then 0.3 s of walking and development
  // The irregular body sinks through the floor: its life is scored (the authors' rule), so
  // fitness is compared too. The bits do not depend on the rule.
  d.sinking_invalid = false;
  return d;
}

TEST(Determinism, CanonicalWalkerTwiceGivesTheSameFinalState) {
  const Model m = compile(demo_walker(), short_life(Treatment::kStress));
  const SimResult a = simulate(m);
  const SimResult b = simulate(m);
  ASSERT_EQ(a.status, SimStatus::kFinished) << a.failure;
  EXPECT_EQ(a.final_state_hash, b.final_state_hash);
  EXPECT_EQ(a.fitness, b.fitness);
  EXPECT_EQ(a.final_stiffness, b.final_stiffness);
}

TEST(Determinism, SameResultOnConcurrentThreads) {
  const Model m = compile(demo_walker(), short_life(Treatment::kPressure));
  const SimResult serial = simulate(m);
  SimResult r1, r2;
  std::thread t1([&] { r1 = simulate(m); });
  std::thread t2([&] { r2 = simulate(m); });
  t1.join();
  t2.join();
  EXPECT_EQ(serial.final_state_hash, r1.final_state_hash);
  EXPECT_EQ(serial.final_state_hash, r2.final_state_hash);
}

// The bond kernel runs four (AVX2) or eight (AVX-512) bonds per instruction where the CPU
// has them: every instruction set must give the same bits. The irregular body has soft
// voxels that bend far, so its bonds also take the large-rotation lanes (the engine's own
// arctangent series, wide reduction) and the scalar redo path.
TEST(Determinism, SameBitsOnEveryInstructionSet) {
  const Model m = compile(demo_irregular(500, 7), short_life(Treatment::kStress));
  const SimdLevel best = best_simd_level();
  set_simd_level(SimdLevel::kScalar);
  ASSERT_EQ(simd_level(), SimdLevel::kScalar);
  const SimResult reference = simulate(m);
  ASSERT_EQ(reference.status, SimStatus::kFinished) << reference.failure;
  for (int level = static_cast<int>(SimdLevel::kAvx2); level <= static_cast<int>(best); ++level) {
    set_simd_level(static_cast<SimdLevel>(level));
    ASSERT_EQ(simd_level(), static_cast<SimdLevel>(level));
    const SimResult r = simulate(m);
    EXPECT_EQ(r.final_state_hash, reference.final_state_hash) << to_string(simd_level());
    EXPECT_EQ(r.fitness, reference.fitness) << to_string(simd_level());
  }
  set_simd_level(best);
  EXPECT_EQ(simd_level(), best);
}

TEST(Determinism, TreatmentsDiffer) {
  const SimResult none = simulate(compile(demo_walker(), short_life(Treatment::kNone)));
  const SimResult stress = simulate(compile(demo_walker(), short_life(Treatment::kStress)));
  EXPECT_NE(none.final_state_hash, stress.final_state_hash);
  EXPECT_EQ(none.stiffness_change_abs_mean, 0.0);
  EXPECT_GT(stress.stiffness_change_abs_mean, 0.0);
}

}  // namespace
}  // namespace plastivox
