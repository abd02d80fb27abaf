// Determinism: a run is defined by its robot and parameters; same inputs, same bits out,
// whichever thread runs it and whatever runs beside it.
#include <thread>

#include "plastivox/demo_robots.hpp"
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

TEST(Determinism, TreatmentsDiffer) {
  const SimResult none = simulate(compile(demo_walker(), short_life(Treatment::kNone)));
  const SimResult stress = simulate(compile(demo_walker(), short_life(Treatment::kStress)));
  EXPECT_NE(none.final_state_hash, stress.final_state_hash);
  EXPECT_EQ(none.stiffness_change_abs_mean, 0.0);
  EXPECT_GT(stress.stiffness_change_abs_mean, 0.0);
}

}  // namespace
}  // namespace plastivox
