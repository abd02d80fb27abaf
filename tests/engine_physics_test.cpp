// Mechanics checked against physics: beam theory, contact, friction, conservation.
#include <cmath>

#include "plastivox/demo_robots.hpp"
#include "plastivox/energy.hpp"
#include "plastivox/rules/life_rules.hpp"
#include "test_support.hpp"

namespace plastivox {
namespace {

using testing::RelNear;

TEST(FloorContact, DroppedVoxelRestsAtPenaltyEquilibrium) {
  RobotDef r = testing::block(1, 1, 1, 1e9);
  const Model m = compile(r, testing::passive_physics());
  Simulator sim(m);
  sim.mutable_state().pos[0].z() += 0.02;  // drop from two voxel lengths higher
  testing::run_until(sim, 0.5);
  ASSERT_EQ(sim.state().status, SimStatus::kRunning) << sim.state().failure;
  // Floor spring 2 E L holds the weight: penetration m g / (2 E L) below L/2.
  const double L = m.size, E = 1e9;
  const double expected = L / 2 - m.mass * 9.81 / (2 * E * L);
  EXPECT_NEAR(sim.state().pos[0].z(), expected, 1e-4 * L);
  EXPECT_LT(std::abs(sim.state().lin_mom[0].z() / m.mass), 1e-6);
}

// A voxel resting on the floor, pushed sideways with a constant force F.
double push(double F_over_weight, double seconds, double* mass_out) {
  RobotDef r = testing::block(1, 1, 1, 1e9);
  PhysicsDef d = testing::passive_physics();
  d.global_damping = 0;  // slow damping of a 1e9 Pa voxel would rival friction here
  const double weight = d.density * 1e-6 * 9.81;
  r.loads.push_back({0, F_over_weight * weight, 0, 0});
  const Model m = compile(r, d);
  Simulator sim(m);
  // Start at the contact equilibrium so the normal force is steady from the first step.
  sim.mutable_state().pos[0].z() = m.size / 2 - m.mass * 9.81 / (2 * 1e9 * m.size);
  testing::run_until(sim, seconds);
  EXPECT_EQ(sim.state().status, SimStatus::kRunning) << sim.state().failure;
  *mass_out = m.mass;
  return sim.state().pos[0].x() - m.rest_pos[0].x();
}

// Gravity is the acceleration along z: 0 (none) or downwards. Upwards lifted bodies off the
// floor and scored their climb as a walk; it is refused, naming the field and its sign.
TEST(Gravity, UpwardsIsRefused) {
  PhysicsDef d;
  for (const double g : {-9.81, -0.0, 0.0}) {
    d.gravity = g;
    EXPECT_NO_THROW(validate(d)) << g;
  }
  for (const double g : {9.81, 5e-324}) {
    d.gravity = g;
    EXPECT_EQ(testing::error_of([&] { validate(d); }),
              "physics.gravity: must be finite and <= 0 m/s^2 (the acceleration along z; -9.81 "
              "is Earth's)")
        << g;
  }
}

TEST(Friction, StaticFrictionHoldsBelowTheLimit) {
  double mass;
  // mu_static = 1: a push of 0.9 weight must not move the block.
  EXPECT_LT(std::abs(push(0.9, 0.2, &mass)), 1e-9);
}

TEST(Friction, KineticFrictionSetsSlidingAcceleration) {
  double mass;
  // Push 1.5 weight, kinetic friction 0.5 weight: a = g, x = g t^2 / 2.
  const double t = 0.2;
  EXPECT_TRUE(RelNear(push(1.5, t, &mass), 0.5 * 9.81 * t * t, 0.02));
}

// Free flight, no damping, no gravity: a deformed, spinning block.
Model free_block() {
  PhysicsDef d = testing::passive_physics();
  d.floor = false;
  d.gravity = 0;
  d.bond_damping = d.global_damping = d.collision_damping = 0;
  d.duration = 1e4;  // longer than any test here steps it: a finished life stops stepping
  return compile(testing::block(3, 2, 2, 1e7), d);
}

void perturb(const Model& m, State& s) {
  for (int i = 0; i < m.n; ++i) {
    const double k = i + 1.0;
    // ~1 % strains and a drift: vibration well inside the linear range
    s.pos[i] += m.size * 0.01 * Vec3(std::sin(k), std::cos(2 * k), std::sin(3 * k));
    s.lin_mom[i] = m.mass * Vec3(0.001 * std::cos(k), 0.02, -0.001 * std::sin(k));
  }
}

TEST(Conservation, EnergyDoesNotDriftWithoutDamping) {
  const Model m = free_block();
  Simulator sim(m);
  perturb(m, sim.mutable_state());
  // Leapfrog-style energy: the stored momentum is a half step ahead of the positions, so
  // average it over the step to compare energies at the same instant; then compare the
  // mean energy of the first and last 1000 steps (the signal oscillates with the modes).
  auto total = [&](const State& before, const State& after) {
    State mid = before;
    for (int i = 0; i < m.n; ++i) {
      mid.lin_mom[i] = 0.5 * (before.lin_mom[i] + after.lin_mom[i]);
      mid.ang_mom[i] = 0.5 * (before.ang_mom[i] + after.ang_mom[i]);
    }
    return kinetic_energy(m, mid) + elastic_energy(m, mid);
  };
  double first = 0, last = 0;
  const int steps = 10000, window = 1000;
  for (int k = 0; k < steps; ++k) {
    const State before = sim.state();
    sim.step();
    const double e = total(before, sim.state());
    if (k < window) first += e / window;
    if (k >= steps - window) last += e / window;
  }
  ASSERT_EQ(sim.state().status, SimStatus::kRunning) << "every step was taken";
  ASSERT_GT(first, 0);
  EXPECT_TRUE(RelNear(last, first, 0.01));
}

TEST(Conservation, AngularMomentumInFreeFlight) {
  // Bond moments balance bond forces exactly, so spin plus orbital momentum is conserved.
  const Model m = free_block();
  Simulator sim(m);
  perturb(m, sim.mutable_state());
  auto angular = [&] {
    const Vec3 c = center_of_mass(sim.state());
    Vec3 h = Vec3::Zero();
    for (int i = 0; i < m.n; ++i)
      h += (sim.state().pos[i] - c).cross(sim.state().lin_mom[i]) + sim.state().ang_mom[i];
    return h;
  };
  const Vec3 h0 = angular();
  for (int k = 0; k < 5000; ++k) sim.step();
  ASSERT_EQ(sim.state().status, SimStatus::kRunning) << "every step was taken";
  EXPECT_LT((angular() - h0).norm(), 1e-6 * (h0.norm() + m.mass * m.size * 0.01));
}

TEST(Conservation, LinearMomentumInFreeFlight) {
  const Model m = free_block();
  Simulator sim(m);
  perturb(m, sim.mutable_state());
  auto momentum = [&] {
    Vec3 p = Vec3::Zero();
    for (const Vec3& v : sim.state().lin_mom) p += v;
    return p;
  };
  const Vec3 p0 = momentum();
  for (int k = 0; k < 5000; ++k) sim.step();
  ASSERT_EQ(sim.state().status, SimStatus::kRunning) << "every step was taken";
  EXPECT_LT((momentum() - p0).norm(), 1e-9 * m.mass);
}

// The paper's "heavy materials": 1000 kg voxels crush a soft column, a stiff one stands.
double column_height_ratio(double E) {
  PhysicsDef d = testing::passive_physics();
  d.self_collision = true;
  const Model m = compile(testing::block(2, 2, 8, E), d);
  Simulator sim(m);
  testing::run_until(sim, 0.5);
  EXPECT_EQ(sim.state().status, SimStatus::kRunning) << sim.state().failure;
  return center_of_mass(sim.state()).z() / center_of_mass(make_initial_state(m)).z();
}

TEST(HeavyMaterials, SoftColumnIsCrushedStiffColumnStands) {
  EXPECT_GT(column_height_ratio(1e11), 0.99);
  EXPECT_LT(column_height_ratio(1e7), 0.6);
}

// Floor contact as a health (docs/engine.md, "Floor contact and sinking"): a 3x3x3 block
// resting on the floor for 1 s, graded from its deepest penetration over the life. Its
// bottom voxels carry three voxels' weight: 3 m g / (2 E L) below L/2 at rest.
PhysicsDef resting_physics(bool sinking_invalid = true) {
  PhysicsDef d = testing::passive_physics();
  d.duration = 1.0;
  d.sinking_invalid = sinking_invalid;
  return d;
}
SimResult resting_block(double E, bool sinking_invalid = true) {
  return simulate(compile(testing::block(3, 3, 3, E), resting_physics(sinking_invalid)));
}

TEST(FloorHealth, StiffBlockStandsOk) {
  const SimResult r = resting_block(1e10);  // 0.015 voxel lengths at rest
  EXPECT_EQ(r.status, SimStatus::kFinished) << r.failure;
  EXPECT_EQ(r.floor_health, FloorHealth::kOk);
  EXPECT_GT(r.floor_depth, 0.0);
  EXPECT_LT(r.floor_depth, kFloorPenetratingDepth);
  EXPECT_TRUE(r.warnings.empty());
}

TEST(FloorHealth, BlockWithItsFeetPressedALittleIntoTheFloorIsPenetrating) {
  const SimResult r = resting_block(2e8);  // 0.74 voxel lengths at rest
  EXPECT_EQ(r.status, SimStatus::kFinished) << r.failure;
  EXPECT_EQ(r.floor_health, FloorHealth::kPenetrating);
  EXPECT_GT(r.floor_depth, kFloorPenetratingDepth);
  EXPECT_LT(r.floor_depth, kFloorSankDepth);
  EXPECT_EQ(r.voxels_deep_max, 9);  // the bottom layer
  EXPECT_EQ(r.voxels_below_floor, 0);
  ASSERT_EQ(r.warnings.size(), 1u);
  EXPECT_EQ(r.warnings[0].rfind("pressed into the floor: ", 0), 0u) << r.warnings[0];
  EXPECT_NE(r.warnings[0].find("9 of 27 voxels at once deeper than 0.5"), std::string::npos)
      << r.warnings[0];
}

TEST(FloorHealth, SoftHeavyCubeSankAndIsInvalidByDefault) {
  const SimResult r = resting_block(1e5);
  EXPECT_EQ(r.floor_health, FloorHealth::kSank);
  EXPECT_TRUE(r.sank);
  EXPECT_GT(r.floor_depth, 100.0);
  EXPECT_EQ(r.voxels_below_floor, 27);
  EXPECT_GT(r.vertical_share, 0.99);
  // The core measures the life to its end; whether it counts is judge_life's.
  EXPECT_EQ(r.status, SimStatus::kFinished) << r.failure;
  EXPECT_GT(r.fitness, 100.0);
  SimResult judged = r;
  judge_life(resting_physics(), judged);
  EXPECT_EQ(judged.status, SimStatus::kUnstable);
  EXPECT_EQ(judged.fitness, 0.0);
  EXPECT_NE(judged.failure.find("sank through the floor"), std::string::npos) << judged.failure;
  // The authors' rule scores the same life; the rule changes nothing the core measures.
  SimResult authors = resting_block(1e5, false);
  judge_life(resting_physics(false), authors);
  EXPECT_EQ(authors.status, SimStatus::kFinished);
  EXPECT_EQ(authors.floor_health, FloorHealth::kSank);
  EXPECT_EQ(authors.fitness, r.fitness);
  EXPECT_EQ(authors.final_state_hash, r.final_state_hash);
  EXPECT_EQ(authors.floor_depth, r.floor_depth);
}

// Heavy voxels can crush a soft bond until its centres meet (the demo walker under pressure
// does). The shear coupling 3 b3 / chord must stay bounded there: with the chord floored at
// L / 10 the force is at most about (1 + 10 pi) E L^2, whereas 3 b3 / chord at a chord of
// 1e-4 L would give ~8000 E L^2 and a speed no time step survives.
TEST(Stability, CrushedBondWhoseCentresMeetHasBoundedForces) {
  const double E = 1e8;
  PhysicsDef d = testing::passive_physics();
  d.gravity = 0;
  const Model m = compile(testing::block(1, 1, 2, E), d);
  ASSERT_EQ(m.bond_count(), 1);
  for (const Vec3& offset :
       {Vec3(1e-4, 0, 0), Vec3(0, 1e-4, 1e-5), Vec3(1e-4, 1e-4, -1e-5), Vec3(1e-7, 0, -1e-4)}) {
    Simulator sim(m);
    State& s = sim.mutable_state();
    // b's centre next to a's, beside it rather than above it: the chord is tiny and turned
    // by about a right angle from the bond's axis (or pointing backwards: the scalar path).
    s.pos[1] = s.pos[0] + offset * m.size;
    const double dt = s.dt;
    sim.step();
    ASSERT_EQ(sim.state().status, SimStatus::kRunning) << sim.state().failure;
    for (int i = 0; i < 2; ++i) {
      const double force = sim.state().lin_mom[i].norm() / dt;
      EXPECT_LT(force, 40 * E * m.size * m.size) << "voxel " << i;
      EXPECT_GT(force, 0.1 * E * m.size * m.size) << "voxel " << i;  // the bond does push
    }
  }
}

// Irregular bodies of 1e5-1e11 Pa, 1000 kg voxels that went unstable (a crushed soft bond's
// centres meeting) before the shear chord was floored: 7 of 32 such lives did, none since.
// Each runs a little past the time it used to fail at.
TEST(Stability, HeavyIrregularBodiesThatCrushSoftBondsStayStable) {
  struct Case {
    int voxels;
    unsigned seed;
    Treatment treatment;
    double until;
  };
  for (const Case& c :
       {Case{1000, 7, Treatment::kPressure, 0.5}, Case{300, 5, Treatment::kStress, 1.3},
        Case{1000, 5, Treatment::kPressure, 1.4}}) {
    PhysicsDef d = preset_gecco2018_code();
    d.treatment = c.treatment;
    const Model m = compile(demo_irregular(c.voxels, c.seed), d);
    Simulator sim(m);
    testing::run_until(sim, c.until);
    EXPECT_EQ(sim.state().status, SimStatus::kRunning)
        << c.voxels << " voxels, seed " << c.seed << ": " << sim.state().failure;
  }
}

// A checkerboard of the softest and stiffest admissible neighbours, actuated, on the floor,
// for a full 5.2 s life: the code preset's 1e5/1e11 Pa and the paper's 1e4/1e10 Pa.
class MixedExtremeStiffness : public ::testing::TestWithParam<const char*> {};

TEST_P(MixedExtremeStiffness, RunsAFullLifeWithoutInstability) {
  PhysicsDef d = physics_preset(GetParam());
  d.treatment = Treatment::kStress;
  RobotDef r = testing::block(6, 6, 4, d.e_min);
  for (int s = 0; s < r.sites(); ++s) {
    const int x = s % 6, y = (s / 6) % 6, z = s / 36;
    if ((x + y + z) % 2) r.stiffness[s] = d.e_max;
    r.phase[s] = 0.1 * x;
    r.dev_rate[s] = (x % 3) - 1.0;
  }
  // The soft half cannot carry the heavy voxels: the block sinks through the floor, which is
  // not a numerical instability. Under the authors' rule the life is scored to its end.
  d.sinking_invalid = false;
  const SimResult res = simulate(compile(r, d));
  EXPECT_EQ(res.status, SimStatus::kFinished) << res.failure;
  EXPECT_EQ(res.floor_health, FloorHealth::kSank);
  EXPECT_TRUE(std::isfinite(res.fitness));
  EXPECT_GT(res.sim_time, d.duration);
}

INSTANTIATE_TEST_SUITE_P(Presets, MixedExtremeStiffness,
                         ::testing::Values("gecco2018-code", "gecco2018-paper"),
                         [](const auto& info) { return std::string(info.param).substr(10); });

TEST(Stability, RunawaySpeedIsReportedNotReturnedAsANumber) {
  PhysicsDef d = testing::passive_physics();
  d.dt_frac = 1.5;  // allowed, but far too large for these contact stiffnesses
  d.max_speed = 1.0;
  RobotDef r = testing::block(3, 3, 3, 1e9);
  const Model m = compile(r, d);
  Simulator sim(m);
  sim.mutable_state().lin_mom[0] = Vec3(0, 0, -50.0 * m.mass);
  testing::run_until(sim, 0.5);
  EXPECT_EQ(sim.state().status, SimStatus::kUnstable);
  EXPECT_FALSE(sim.state().failure.empty());
}

}  // namespace
}  // namespace plastivox
