// plastivox against the authors' own simulator: the sample robots in tests/data/vxa were run
// by their Voxelyze 0.9 fork; *.expected.json holds what it reported. Full 5.2 s lives.
#include <cmath>
#include <fstream>

#include <nlohmann/json.hpp>

#include "plastivox/io/vxa.hpp"
#include "plastivox/simulator.hpp"
#include "test_support.hpp"

namespace plastivox {
namespace {

double expected_value(const std::string& name, const std::string& key) {
  std::ifstream in(testing::data_dir() + "/vxa/" + name + ".expected.json");
  const nlohmann::json j = nlohmann::json::parse(in);
  if (!j.contains(key)) ADD_FAILURE() << name << ": no key " << key;
  return j.value(key, 0.0);
}

// Compared with the authors' simulator, so under their rule: a sunk life is scored.
SimResult run(const std::string& name) {
  VxaRobot v = read_vxa_file(testing::data_dir() + "/vxa/" + name + ".vxa");
  v.physics.sinking_invalid = false;
  return simulate(compile(v.robot, v.physics));
}

struct Walker {
  const char* name;
  double change_tolerance;  // relative, on the mean stiffness change
};

class AuthorsWalker : public ::testing::TestWithParam<Walker> {};

TEST_P(AuthorsWalker, AgreesWithTheAuthorsSimulator) {
  const std::string name = GetParam().name;
  const SimResult r = run(name);
  ASSERT_EQ(r.status, SimStatus::kFinished) << r.failure;
  // The authors' walkers stand and walk: their feet stay near the floor's surface.
  EXPECT_EQ(r.floor_health, FloorHealth::kOk) << r.floor_depth << " voxel lengths deep";
  EXPECT_EQ(r.voxels, expected_value(name, "voxels"));
  // Settling is near-deterministic mechanics: within 1 % of a voxel length.
  EXPECT_NEAR(r.displacement.z(), expected_value(name, "dist_z"), 0.01);
  // Walking amplifies small differences: fitness within 10 %.
  EXPECT_TRUE(testing::RelNear(r.fitness, expected_value(name, "fitness"), 0.10));
  const double change = expected_value(name, "stiffness_change_mean_percent");
  if (change != 0) {
    EXPECT_TRUE(
        testing::RelNear(100 * r.stiffness_change_mean, change, GetParam().change_tolerance));
  } else {
    EXPECT_EQ(r.stiffness_change_mean, 0.0);
  }
}

// The 10 % on the mean stiffness change holds for both developing walkers (pressure:
// -2.44 % vs the authors' -2.46 %, since the pressure reads each voxel's own share of its bond
// strains; docs/vxa.md).
INSTANTIATE_TEST_SUITE_P(SampleRobots, AuthorsWalker,
                         ::testing::Values(Walker{"walker-none", 0.10},
                                           Walker{"walker-stress", 0.10},
                                           Walker{"walker-pressure", 0.10}),
                         [](const auto& info) {
                           std::string n = info.param.name;
                           for (char& c : n) c = c == '-' ? '_' : c;
                           return n;
                         });

TEST(AuthorsSettleCube, CollapsesLikeTheAuthorsSimulator) {
  // A full cube of 1000 kg, 1e9 Pa voxels collapsing under its own weight for 1 s: bonds are
  // crushed past inversion and the body is still falling over at 1 s. Under the default
  // exact bond model the vertical drop agrees within 0.12 voxel lengths (-3.13 vs -3.24);
  // under the authors' own bond model (next test) within 0.01.
  const SimResult r = run("settle-cube-1e9");
  ASSERT_EQ(r.status, SimStatus::kFinished) << r.failure;
  EXPECT_NEAR(r.displacement.z(), expected_value("settle-cube-1e9", "dist_z"), 0.15);
}

TEST(AuthorsSettleCube, FallsTheAuthorsWayUnderTheirBondModel) {
  // Under bond_model voxelyze09 the cube falls over towards +x+y as far as the authors' does
  // (3.04 / 3.09 voxels against their 3.07 each way) and dist_z is -3.245 against -3.243:
  // the 0.01 voxel and 10 %. What it took (docs/vxa.md): the evolution build's
  // bending test (each bond offset truncated to whole metres), Voxelyze 0.9's first-order
  // turn with its reset of turns below ~3e-8 rad, its rotation vectors from 1 - w^2, its
  // chord frame and its time step (pi as 3.1415926, bonds only).
  VxaRobot v = read_vxa_file(testing::data_dir() + "/vxa/settle-cube-1e9.vxa");
  v.physics.bond_model = BondModel::kVoxelyze09;
  v.physics.sinking_invalid = false;  // the authors' rule
  const SimResult r = simulate(compile(v.robot, v.physics));
  ASSERT_EQ(r.status, SimStatus::kFinished) << r.failure;
  const double x = expected_value("settle-cube-1e9", "dist_x");
  const double y = expected_value("settle-cube-1e9", "dist_y");
  EXPECT_GT(r.displacement.x() * x, 0) << r.displacement.x();
  EXPECT_GT(r.displacement.y() * y, 0) << r.displacement.y();
  EXPECT_TRUE(testing::RelNear(r.displacement.x(), x, 0.10)) << r.displacement.x();
  EXPECT_TRUE(testing::RelNear(r.displacement.y(), y, 0.10)) << r.displacement.y();
  EXPECT_NEAR(r.displacement.z(), expected_value("settle-cube-1e9", "dist_z"), 0.01);
}

TEST(AuthorsSettleCube, FlipsItsFallWhereTheAuthorsDoes) {
  // The collapse amplifies rounding: scaling every E by 1 - 1e-5 turns the authors' fall from
  // +x+y (3.07) to -x-y (-2.57), and their own dist_z moves by 0.03 under 1e-4 (docs/vxa.md).
  // Under their bond model plastivox flips at the same factors; the authors' dist_x for each
  // factor was measured with the fork's library.
  const struct {
    double factor, authors_dist_x;
  } cases[] = {{0.99999, -2.56995}, {0.999997, 3.02893}, {1.00001, 3.0081}};
  for (const auto& c : cases) {
    VxaRobot v = read_vxa_file(testing::data_dir() + "/vxa/settle-cube-1e9.vxa");
    v.physics.bond_model = BondModel::kVoxelyze09;
    v.physics.sinking_invalid = false;  // the authors' rule
    for (double& e : v.robot.stiffness) e *= c.factor;
    const SimResult r = simulate(compile(v.robot, v.physics));
    ASSERT_EQ(r.status, SimStatus::kFinished) << r.failure;
    EXPECT_GT(r.displacement.x() * c.authors_dist_x, 0) << c.factor << ": " << r.displacement.x();
    EXPECT_TRUE(testing::RelNear(r.displacement.x(), c.authors_dist_x, 0.15))
        << c.factor << ": " << r.displacement.x();
  }
}

// Two of Voxelyze 0.9's own rules that bond_model voxelyze09 repeats (docs/vxa.md, "The
// mixture, step by step").
TEST(Voxelyze09, TimeStepIsCalcMaxDtOverBondsOnly) {
  // The stiffest voxel has only soft neighbours: CalcMaxDt takes the stiffest *bond*
  // (harmonic-mean E), with pi written 3.1415926; plastivox's own rule also counts the
  // voxel's own E L, a step 7x shorter here.
  RobotDef r = testing::block(3, 1, 1, 1e8);
  r.stiffness[1] = 1e10;
  PhysicsDef d = testing::passive_physics();
  d.bond_model = BondModel::kVoxelyze09;
  const Model m = compile(r, d);
  const double L = m.size, e = (1e8 * 1e10 / (1e8 + 1e10)) * 2, a1 = e * (L * L) / L;
  const double dt = Simulator(m).state().dt;
  EXPECT_EQ(dt, d.dt_frac * (1.0 / (std::sqrt(a1 / m.mass) * 2 * 3.1415926)));
  d.bond_model = BondModel::kExact;
  EXPECT_LT(Simulator(compile(r, d)).state().dt, 0.2 * dt);
}

TEST(Voxelyze09, TurnsBelowAbout3e8RadAreNoTurn) {
  // Three steps into the soft/stiff mixture's settle the blocks have begun to bend each
  // other. CQuat::NormalizeFast resets a w that rounds to 1, so voxels turned by less than
  // ~3e-8 rad stay exactly unturned while their angular momentum grows: the fork's own trace
  // has 32 turned voxels at step 3, which voxelyze09 repeats; the exact model turns them all.
  for (const BondModel model : {BondModel::kVoxelyze09, BondModel::kExact}) {
    VxaRobot v = read_vxa_file(std::string(PLASTIVOX_SOURCE_DIR) + "/examples/mixture.vxa");
    v.physics.bond_model = model;
    const Model m = compile(v.robot, v.physics);
    Simulator sim(m);
    for (int i = 0; i < 3; ++i) sim.step();
    const State& s = sim.state();
    int turned = 0, spinning_unturned = 0;
    for (size_t i = 0; i < s.orient.size(); ++i) {
      const bool turns = s.orient[i].vec().squaredNorm() > 0;
      turned += turns;
      spinning_unturned += !turns && s.ang_mom[i].squaredNorm() > 0;
    }
    if (model == BondModel::kVoxelyze09) {
      EXPECT_EQ(turned, 32);
      EXPECT_GT(spinning_unturned, 100);
    } else {
      EXPECT_GT(turned, 300);
      EXPECT_EQ(spinning_unturned, 0);
    }
  }
}

// The agreement set in tests/data/agreement (its README says what each robot is and how the
// authors' numbers were made), under the authors' bond model, held to the targets:
// every fitness within 3 % and their mean signed difference within +-0.5 %, the mean
// stiffness change within 2 %, the settled height (dist_z) within 0.01 voxel.
TEST(AgreementSet, VoxelyzeBondModelAgreesWithTheAuthorsSimulator) {
  const char* names[] = {"champion-10-none-s1",
                         "champion-10-stress-s1",
                         "champion-10-pressure-s1",
                         "champion-6-none-s1",
                         "champion-6-none-s2",
                         "champion-6-stress-s1",
                         "champion-6-stress-s2",
                         "champion-6-pressure-s1",
                         "gamma",
                         "pi",
                         "upsilon",
                         "mixture",
                         "walker-soft-1e7",
                         "walker-stiff-1e10",
                         "walker-long-settle"};
  const std::string source = PLASTIVOX_SOURCE_DIR;
  const std::string dir = source + "/tests/data/agreement/";
  double sum = 0;
  int n = 0;
  for (const char* name : names) {
    std::ifstream in(dir + name + ".expected.json");
    ASSERT_TRUE(in) << name;
    const nlohmann::json want = nlohmann::json::parse(in);
    // The paper's body plans and the mixture are examples/'s files themselves.
    std::ifstream here(dir + name + ".vxa");
    VxaRobot v = read_vxa_file((here ? dir : source + "/examples/") + name + ".vxa");
    v.physics.bond_model = BondModel::kVoxelyze09;
    v.physics.sinking_invalid = false;  // the authors' rule, as their simulator scores
    const SimResult r = simulate(compile(v.robot, v.physics));
    ASSERT_EQ(r.status, SimStatus::kFinished) << name << ": " << r.failure;
    // The walking robots (the evolved champions and the stiff walker) stand on the floor;
    // the soft walker falls through it (docs/engine.md, "Floor contact and sinking").
    const std::string robot = name;
    if (robot.starts_with("champion-") || robot == "walker-stiff-1e10") {
      EXPECT_EQ(r.floor_health, FloorHealth::kOk) << name << ": " << r.floor_depth;
    }
    if (robot == "walker-soft-1e7") {
      EXPECT_EQ(r.floor_health, FloorHealth::kSank) << name;
    }
    EXPECT_EQ(r.voxels, want["voxels"].get<int>()) << name;
    const double fitness = want["fitness"].get<double>();
    EXPECT_TRUE(testing::RelNear(r.fitness, fitness, 0.03)) << name;
    EXPECT_NEAR(r.displacement.z(), want["dist_z"].get<double>(), 0.01) << name;
    const double change = want["stiffness_change_mean_percent"].get<double>();
    if (change != 0)
      EXPECT_TRUE(testing::RelNear(100 * r.stiffness_change_mean, change, 0.02)) << name;
    else
      EXPECT_EQ(r.stiffness_change_mean, 0.0) << name;
    sum += r.fitness / fitness - 1;
    ++n;
  }
  EXPECT_LT(std::abs(sum / n), 0.005) << 100 * sum / n << " %";
}

}  // namespace
}  // namespace plastivox
