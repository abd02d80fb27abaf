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
// voxels that bend far, so its bonds also take the large-rotation lanes (the engine's own arctangent series, wide reduction)
// and the scalar redo path.
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

namespace plastivox {
namespace {

TEST(Recording, SixtyFramesPerSimulatedSecondOfEveryVoxel) {
  PhysicsDef d;
  d.treatment = Treatment::kStress;
  d.duration = 0.5;
  ASSERT_EQ(d.record_fps, 60.0);  // the default: a life can always be replayed
  const Model m = compile(demo_walker(), d);
  const SimResult r = simulate(m);
  ASSERT_EQ(r.status, SimStatus::kFinished);
  // Frames at 0, 1/60, ..., 29/60 s, then the final state (the first step past 0.5 s).
  ASSERT_EQ(r.recording.frames.size(), 31u);
  EXPECT_NEAR(r.recording.frames.back().time, 0.5, 0.001);
  for (size_t k = 0; k + 1 < r.recording.frames.size(); ++k) {
    const Frame& f = r.recording.frames[k];
    EXPECT_GE(f.time, k / 60.0);
    EXPECT_LT(f.time, k / 60.0 + 0.001);  // within one step of the frame time
    EXPECT_EQ(f.pos.size(), static_cast<size_t>(m.n));
    EXPECT_EQ(f.orient.size(), static_cast<size_t>(m.n));
    EXPECT_EQ(f.size.size(), static_cast<size_t>(m.n));
    EXPECT_EQ(f.stiffness.size(), static_cast<size_t>(m.n));
    EXPECT_EQ(f.stimulus.size(), static_cast<size_t>(m.n));
  }
  // The last frame is the final state: its stiffness is the result's final stiffness, and
  // stimulus and stiffness histories move after settling.
  EXPECT_EQ(r.recording.frames.back().stiffness, r.final_stiffness);
  EXPECT_NE(r.recording.frames[20].stimulus, r.recording.frames[25].stimulus);
  EXPECT_NE(r.recording.frames[0].stiffness, r.recording.frames.back().stiffness);
}

TEST(Recording, OffWhenFpsIsZero) {
  PhysicsDef d;
  d.duration = 0.3;
  d.record_fps = 0;
  EXPECT_TRUE(simulate(compile(demo_walker(), d)).recording.frames.empty());
}

}  // namespace
}  // namespace plastivox

namespace plastivox {
namespace {

// State is the whole state: a life stopped 1 s in (developing, actuated, stiffness and dt
// changing every step), its State copied into a new Simulator and continued, ends at the
// same bits as the uninterrupted life.
TEST(Determinism, CopiedStateContinuesBitIdentically) {
  for (Treatment t : {Treatment::kStress, Treatment::kPressure}) {
    PhysicsDef d = preset_gecco2018_code();
    d.treatment = t;
    d.duration = 1.5;
    d.record_fps = 0;
    const Model m = compile(demo_walker(), d);
    const SimResult whole = simulate(m);
    ASSERT_EQ(whole.status, SimStatus::kFinished) << whole.failure;

    Simulator first(m);
    testing::run_until(first, 1.0);
    ASSERT_EQ(first.state().status, SimStatus::kRunning);
    Simulator second(m);
    second.mutable_state() = first.state();
    while (second.state().time <= d.duration && second.state().status == SimStatus::kRunning)
      second.step();
    EXPECT_EQ(state_hash(second.state()), whole.final_state_hash) << to_string(t);
    EXPECT_EQ(second.state().stiffness, whole.final_stiffness) << to_string(t);
  }
}

}  // namespace
}  // namespace plastivox
