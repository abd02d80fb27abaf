// Saving and restoring a life: a State copied into another Simulator carries everything the
// rest of the life depends on.
#include "plastivox/demo_robots.hpp"
#include "test_support.hpp"

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
