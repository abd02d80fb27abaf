// The developmental stimuli beyond the paper's two (physics_def.hpp, docs/plasticity.md):
// each against an analytic value, development in the right direction under each, and the
// same bits at every SIMD level.
#include "plastivox/demo_robots.hpp"
#include "plastivox/io/robot_file.hpp"
#include "plastivox/simd.hpp"
#include "test_support.hpp"

namespace plastivox {
namespace {

using testing::RelNear;

constexpr double kE0 = 2e8;   // Pa
constexpr double kL = 0.01;   // m
constexpr double kRho = 1e7;  // kg/m^3: 10 kg voxels

PhysicsDef measuring(Treatment t) {
  PhysicsDef d = testing::passive_physics();
  d.e_min = 1e5;  // development gate at 1e8 Pa
  d.e_max = 1e11;
  d.density = kRho;
  d.treatment = t;
  return d;
}

// A 1 x 1 chain of four voxels hanging from a clamped fifth (ids 0..3 from the bottom, 4 the
// clamp): the bond above voxel i carries the weight of voxels 0..i.
RobotDef hanging_chain(double alpha) {
  RobotDef r = testing::block(1, 1, 8, kE0, kL);
  for (int z = 0; z < 3; ++z) r.present[z] = 0;
  r.fixed_sites = {7};
  for (double& a : r.dev_rate) a = alpha;
  return r;
}

// At rest (1 s is many damped periods of these stiff bodies) the linear bond law makes the
// analytic values exact to rounding, so the tolerances below are tight.
State run(const RobotDef& r, const PhysicsDef& d, double t) {
  const Model m = compile(r, d);
  Simulator sim(m);
  testing::run_until(sim, t);
  EXPECT_EQ(sim.state().status, SimStatus::kRunning) << sim.state().failure;
  return sim.state();
}

// Axial stress of the bond above voxel i of the hanging chain at rest, Pa.
double chain_stress(int i) {
  const double weight = kRho * kL * kL * kL * 9.81;
  return (i + 1) * weight / (kL * kL);
}

TEST(Stimuli, StrainIsTheLargestBondStrainOfABarUnderKnownLoad) {
  const State s = run(hanging_chain(0.0), measuring(Treatment::kStrain), 1.0);
  for (int i = 0; i < 4; ++i)  // the bond above carries more than the one below
    EXPECT_TRUE(RelNear(s.stimulus[i], chain_stress(i) / kE0, 1e-6)) << "voxel " << i;
}

TEST(Stimuli, StrainEnergyIsSigmaSquaredOverTwoEOfTheVoxelsHalfBonds) {
  const State s = run(hanging_chain(0.0), measuring(Treatment::kStrainEnergy), 1.0);
  for (int i = 0; i < 4; ++i) {
    // Half of each bond's energy density sigma^2 / 2E: the bond above, and the one below.
    const double above = chain_stress(i), below = i > 0 ? chain_stress(i - 1) : 0.0;
    const double want = 0.5 * (above * above + below * below) / (2 * kE0);
    EXPECT_TRUE(RelNear(s.stimulus[i], want, 1e-6)) << "voxel " << i;
  }
}

TEST(Stimuli, ContactSpreadsTheWeightOfABlockOverItsBottomFaces) {
  // A 3 x 3 x 2 block at rest on the floor: the bottom faces carry the whole weight.
  PhysicsDef d = measuring(Treatment::kContact);
  d.settle_time = 0.5;
  const Model m = compile(testing::block(3, 3, 2, kE0, kL), d);
  Simulator sim(m);
  testing::run_until(sim, 1.0);
  const State& s = sim.state();
  ASSERT_EQ(s.status, SimStatus::kRunning) << s.failure;
  double carried = 0;
  for (int i = 0; i < m.n; ++i) {
    if (s.pos[i].z() > kL) {
      EXPECT_EQ(s.stimulus[i], 0.0) << "voxel " << i << " is off the floor";
    } else {
      EXPECT_GT(s.stimulus[i], 0.0) << "voxel " << i;
      carried += s.stimulus[i] * s.size[i] * s.size[i];
    }
  }
  EXPECT_TRUE(RelNear(carried, m.n * m.mass * 9.81, 1e-6));
}

TEST(Stimuli, ContactIsZeroForAFallingBody) {
  // Three empty layers below: the block starts 3 cm up and takes 78 ms to reach the floor.
  RobotDef r = testing::block(2, 2, 5, kE0, kL);
  for (int s = 0; s < 12; ++s) r.present[s] = 0;
  PhysicsDef d = measuring(Treatment::kContact);
  d.settle_time = 0;
  const State s = run(r, d, 0.05);
  for (double v : s.stimulus) EXPECT_EQ(v, 0.0);
}

TEST(Stimuli, KineticIsHalfRhoVSquaredInFreeFall) {
  PhysicsDef d = measuring(Treatment::kKinetic);
  d.floor = false;
  d.global_damping = 0;  // nothing but gravity acts
  d.settle_time = 0;
  const State s = run(testing::block(2, 2, 2, kE0, kL), d, 0.1);
  const double v = 9.81 * s.time;  // the momentum of the step that ended at s.time
  for (double k : s.stimulus) EXPECT_TRUE(RelNear(k, 0.5 * kRho * v * v, 1e-9));
}

// Development follows each stimulus: positive alpha stiffens where the stimulus is felt.
TEST(Stimuli, DevelopmentStiffensWhereEachStimulusIsFelt) {
  for (Treatment t : {Treatment::kStrain, Treatment::kStrainEnergy}) {
    const State s = run(hanging_chain(10.0), measuring(t), 0.5);
    for (int i = 0; i < 4; ++i) EXPECT_GT(s.stiffness[i], kE0) << to_string(t) << " " << i;
    const State soft = run(hanging_chain(-10.0), measuring(t), 0.5);
    for (int i = 0; i < 4; ++i) EXPECT_LT(soft.stiffness[i], kE0) << to_string(t) << " " << i;
  }
  {  // contact: the bottom layer stiffens, the top layer never touches the floor
    RobotDef r = testing::block(3, 3, 2, kE0, kL);
    for (double& a : r.dev_rate) a = 10.0;
    const Model m = compile(r, measuring(Treatment::kContact));
    Simulator sim(m);
    testing::run_until(sim, 0.5);
    const State& s = sim.state();
    for (int i = 0; i < m.n; ++i) {
      if (s.pos[i].z() > kL)
        EXPECT_EQ(s.stiffness[i], kE0) << "contact " << i;
      else
        EXPECT_GT(s.stiffness[i], kE0) << "contact " << i;
    }
  }
  {  // kinetic: a falling block stiffens
    RobotDef r = testing::block(2, 2, 2, kE0, kL);
    for (double& a : r.dev_rate) a = 10.0;
    PhysicsDef d = measuring(Treatment::kKinetic);
    d.floor = false;
    const State s = run(r, d, 0.3);
    for (double e : s.stiffness) EXPECT_GT(e, kE0);
  }
}

TEST(Stimuli, EveryStimulusGivesTheSameBitsAtEverySimdLevel) {
  const SimdLevel best = best_simd_level();
  for (Treatment t :
       {Treatment::kStrain, Treatment::kStrainEnergy, Treatment::kContact, Treatment::kKinetic}) {
    PhysicsDef d = PhysicsDef{};
    d.treatment = t;
    d.duration = 0.6;
    const Model m = compile(demo_walker(), d);
    set_simd_level(SimdLevel::kScalar);
    const SimResult reference = simulate(m);
    ASSERT_EQ(reference.status, SimStatus::kFinished) << to_string(t);
    for (int level = static_cast<int>(SimdLevel::kAvx2); level <= static_cast<int>(best); ++level) {
      set_simd_level(static_cast<SimdLevel>(level));
      const SimResult r = simulate(m);
      EXPECT_EQ(r.final_state_hash, reference.final_state_hash)
          << to_string(t) << " at " << to_string(simd_level());
    }
  }
  set_simd_level(best);
}

TEST(Stimuli, TreatmentObjectInPhysicsSetsStimulusAndLaw) {
  PhysicsDef d;
  apply_physics_json(R"({"treatment": {"stimulus": "contact", "law": "rate"}})", "over", d);
  EXPECT_EQ(d.treatment, Treatment::kContact);
  EXPECT_EQ(d.growth, GrowthModel::kRate);
  PhysicsDef e;
  apply_physics_json(R"({"treatment": {"stimulus": "strain"}, "growth": "rate"})", "over", e);
  EXPECT_EQ(e.treatment, Treatment::kStrain);
  EXPECT_EQ(e.growth, GrowthModel::kRate);
  auto error_of = [](const std::string& text) {
    PhysicsDef x;
    try {
      apply_physics_json(text, "over", x);
    } catch (const InputError& err) {
      return std::string(err.what());
    }
    return std::string("(accepted)");
  };
  EXPECT_EQ(
      error_of(R"({"treatment": {"stimulus": "contact", "law": "rate"}, "growth": "integral"})"),
      "over: physics.treatment.law: contradicts physics.growth (give the law once)");
  EXPECT_EQ(error_of(R"({"treatment": {"stimulus": "contact", "law": "fast"}})"),
            "over: physics.treatment.law: growth model 'fast' is unknown (use integral or rate)");
  EXPECT_EQ(error_of(R"({"treatment": {"law": "rate"}})"),
            "over: physics.treatment.stimulus: missing");
  EXPECT_EQ(
      error_of(R"({"treatment": ["contact"]})"),
      "over: physics.treatment: expected a stimulus name or {\"stimulus\": ..., \"law\": ...}");
}

TEST(Stimuli, NamesRoundTripAndUnknownNamesListTheKnownOnes) {
  for (Treatment t : all_treatments()) EXPECT_EQ(parse_treatment(to_string(t)), t);
  try {
    parse_treatment("heat");
    FAIL() << "accepted an unknown stimulus";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("strain_energy"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace plastivox
