// Development (docs/method.md §5): direction, gate, cap, clamps, treatments, models.
#include <algorithm>

#include "test_support.hpp"

namespace plastivox {
namespace {

using testing::RelNear;

// A chain of 4 voxels hanging from a clamped top voxel, well above the floor: its bonds
// are in tension (about 2 % strain at the top with E = 2e8 Pa and 10 kg voxels, see
// developing()). Voxel ids 0..3 hang, 4 is the clamp.
constexpr double kE0 = 2e8;
RobotDef hanging_chain(double E, double alpha) {
  RobotDef r = testing::block(1, 1, 8, E);
  for (int z = 0; z < 3; ++z) r.present[z] = 0;
  r.fixed_sites = {7};
  for (double& a : r.dev_rate) a = alpha;
  return r;
}

// A standing column on the floor: its bonds are in compression.
RobotDef standing_column(double E, double alpha) {
  RobotDef r = testing::block(1, 1, 5, E);
  for (double& a : r.dev_rate) a = alpha;
  return r;
}

PhysicsDef developing(Treatment t, GrowthModel g = GrowthModel::kIntegral) {
  PhysicsDef d = testing::passive_physics();
  d.e_min = 1e5;  // gate at 1000 * e_min = 1e8 Pa, as in the code preset
  d.e_max = 1e11;
  d.floor = true;
  d.density = 1e7;  // 10 kg voxels: strains of a few percent, no violent swinging
  d.treatment = t;
  d.growth = g;
  return d;
}

std::vector<double> run(const RobotDef& r, const PhysicsDef& d, double t) {
  const Model m = compile(r, d);
  Simulator sim(m);
  testing::run_until(sim, t);
  EXPECT_EQ(sim.state().status, SimStatus::kRunning) << sim.state().failure;
  return sim.state().stiffness;
}

TEST(Development, StressWithPositiveRateStiffensUnderTension) {
  const auto E = run(hanging_chain(kE0, 10.0), developing(Treatment::kStress), 0.5);
  for (int i = 1; i < 4; ++i) EXPECT_GT(E[i], 1.01 * kE0) << "voxel " << i;
}

TEST(Development, StressWithNegativeRateSoftensUnderTension) {
  const auto E = run(hanging_chain(kE0, -10.0), developing(Treatment::kStress), 0.5);
  for (int i = 1; i < 4; ++i) EXPECT_LT(E[i], 0.99 * kE0) << "voxel " << i;
}

TEST(Development, PressureWithPositiveRateStiffensUnderCompression) {
  PhysicsDef d = developing(Treatment::kPressure);
  d.density = 1e9;  // 1000 kg voxels load the column heavily
  const auto E = run(standing_column(1e9, 5.0), d, 0.4);
  EXPECT_GT(E[0], 1.01e9);  // bottom voxel carries the most weight
}

TEST(Development, PressureReadsEachVoxelsShareOfTheBondStrain) {
  // Two voxels in series (bottom four times stiffer): each takes the share of the bond's
  // strain a series spring takes, 2 E_other / (E_own + E_other), so both feel the bond's
  // harmonic-mean stress as pressure (the authors' simulator; the bond strain itself would
  // give the stiff voxel four times the pressure of the soft one).
  RobotDef r = standing_column(1e9, 0.0);
  r.present[2] = r.present[3] = r.present[4] = 0;
  r.stiffness[0] = 4e9;
  const Model m = compile(r, developing(Treatment::kPressure));
  Simulator sim(m);
  testing::run_until(sim, 0.3);
  const State& s = sim.state();
  ASSERT_EQ(s.status, SimStatus::kRunning) << s.failure;
  EXPECT_GT(s.stimulus[0], 0.0);  // compression
  EXPECT_TRUE(RelNear(s.stimulus[0], s.stimulus[1], 1e-12))
      << s.stimulus[0] << " vs " << s.stimulus[1];
}

TEST(Development, NothingHappensBeforeSettling) {
  PhysicsDef d = developing(Treatment::kStress);
  d.settle_time = 0.3;
  const auto E = run(hanging_chain(kE0, 10.0), d, 0.29);
  for (double e : E) EXPECT_EQ(e, kE0);
}

TEST(Development, SoftVoxelsBelowTheGateNeverDevelop) {
  // 1e8 Pa is exactly the gate (1000 * e_min): "E > gate" fails, nothing may change.
  const auto E = run(hanging_chain(1e8, 10.0), developing(Treatment::kStress), 0.4);
  for (double e : E) EXPECT_EQ(e, 1e8);
}

TEST(Development, NoneTreatmentChangesNothingWhateverAlpha) {
  const auto E = run(hanging_chain(kE0, 10.0), developing(Treatment::kNone), 0.4);
  for (double e : E) EXPECT_EQ(e, kE0);
}

TEST(Development, PerStepChangeIsCappedAndClamped) {
  PhysicsDef d = developing(Treatment::kStress);
  d.max_change_per_step = 1e3;  // alpha * stress * dt is ~1e4 Pa here: the cap binds
  const Model m = compile(hanging_chain(kE0, 10.0), d);
  Simulator sim(m);
  double largest = 0;
  while (sim.state().time < 0.5) {
    const std::vector<double> before = sim.state().stiffness;
    sim.step();
    for (int i = 0; i < m.n; ++i) {
      largest = std::max(largest, std::abs(sim.state().stiffness[i] - before[i]));
      EXPECT_GE(sim.state().stiffness[i], d.e_min);
      EXPECT_LE(sim.state().stiffness[i], d.e_max);
    }
  }
  EXPECT_GT(largest, 0.0);
  EXPECT_EQ(largest, 1e3);
}

TEST(Development, ClampHoldsAtEmax) {
  PhysicsDef d = developing(Treatment::kStress);
  d.e_max = 1.05 * kE0;  // rising stiffness must stop here
  const auto E = run(hanging_chain(kE0, 10.0), d, 0.6);
  EXPECT_EQ(*std::max_element(E.begin(), E.end()), 1.05 * kE0);
}

TEST(Development, RateModelFollowsStimulusChangeIntegralFollowsItsIntegral) {
  // The chain hangs still by the end of settling, so its stress is constant afterwards:
  // the integral model keeps stiffening, the rate model (dE/dt = alpha dS/dt) barely moves.
  const auto integral = run(hanging_chain(kE0, 10.0), developing(Treatment::kStress), 0.5);
  const auto rate =
      run(hanging_chain(kE0, 10.0), developing(Treatment::kStress, GrowthModel::kRate), 0.5);
  EXPECT_GT(integral[3] / kE0 - 1, 0.05);
  EXPECT_LT(std::abs(rate[3] / kE0 - 1), 0.01);
}

TEST(Development, TimeStepFollowsStiffness) {
  const Model m = compile(hanging_chain(kE0, 10.0), developing(Treatment::kStress));
  Simulator sim(m);
  const double dt0 = sim.state().dt;
  testing::run_until(sim, 0.6);
  const std::vector<double> E = sim.state().stiffness;
  ASSERT_GT(*std::max_element(E.begin(), E.end()), 1.05 * kE0);
  sim.step();  // takes its dt from the stiffness at its start
  EXPECT_LT(sim.state().dt, dt0);
  EXPECT_EQ(sim.state().dt, stable_dt(m, E));
}

}  // namespace
}  // namespace plastivox
