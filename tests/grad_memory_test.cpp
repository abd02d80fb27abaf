// Issue 52's bound, measured: the gradient of a 10^3 body over a whole 5.2 s life stays under
// 2 GB. A counting operator new (counting_new.hpp) records the peak of live heap bytes while
// grad::gradient runs, on the threads it would take (two on a 2-core machine, which keeps a
// second segment's tape), and the peak must stay within both the 2 GB and the plan
// grad::plan makes before anything runs (snapshots and tapes, which the memory_limit option
// refuses by). Labelled slow: about 8 s of CPU in the Release build.
#include <cstdio>

#include <gtest/gtest.h>

#include "counting_new.hpp"
#include "plastivox/demo_robots.hpp"
#include "plastivox/grad/gradient.hpp"
#include "plastivox/model.hpp"
#include "plastivox/physics_def.hpp"
#include "plastivox/simulator.hpp"

namespace plastivox {
namespace {

TEST(GradMemory, A10CubedBodyOverAWholeLifeStaysUnder2GB) {
  RobotDef r = demo_cube(10, 1e10);
  for (int s = 0; s < r.sites(); ++s) r.stiffness[s] *= 1.0 + 1e-3 * (s % 7);
  const Model m = compile(r, PhysicsDef{});
  ASSERT_EQ(m.n, 1000);
  ASSERT_EQ(m.def.duration, 5.2);
  const grad::Plan plan = grad::plan(m);

  const test::PeakScope scope;
  const grad::Gradient g = grad::gradient(m);
  const size_t peak = scope.peak();
  std::printf(
      "  10^3 body, %lld steps: heap peak %.1f MB, planned %.1f MB (%d thread(s), a "
      "snapshot every %d steps)\n",
      static_cast<long long>(g.steps), peak / 1e6, plan.estimated_bytes / 1e6, plan.threads,
      plan.checkpoint_every);

  EXPECT_GT(g.steps, 11000);  // the whole life
  EXPECT_EQ(g.stiffness.size(), 1000u);
  EXPECT_LT(static_cast<double>(peak), 2e9);
  // The plan is what memory_limit refuses by: the peak within it.
  EXPECT_LE(static_cast<double>(peak), plan.estimated_bytes);
  // ... and the counter sees the snapshots the run reports keeping.
  EXPECT_GE(peak, g.checkpoint_bytes);
}

}  // namespace
}  // namespace plastivox
