// The robustness battery (battery.hpp) with short lives: each perturbation changes what it says
// and nothing else; the `paper` battery reproduces R to the bit; a profile is the same on 1 and
// 2 threads; an unstable or sunk life is counted, not averaged in; bad batteries are refused in
// one line naming the file and field.
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "plastivox/analysis/battery.hpp"
#include "plastivox/analysis/robustness.hpp"
#include "plastivox/evo/config.hpp"
#include "plastivox/model.hpp"
#include "plastivox/simulator.hpp"
#include "test_support.hpp"

namespace plastivox::analysis {
namespace {

using K = PerturbationKind;

RobotDef walker(double E = 1e8) {
  RobotDef r = testing::block(4, 3, 2, E);
  for (int z = 0; z < 2; ++z)
    for (int y = 0; y < 3; ++y)
      for (int x = 0; x < 4; ++x) {
        r.phase[r.site(x, y, z)] = 0.25 * x - 0.4;
        r.dev_rate[r.site(x, y, z)] = 5.0;
        r.stiffness[r.site(x, y, z)] = E * (1 + 0.1 * x);
      }
  return r;
}

PhysicsDef short_life() {
  PhysicsDef p = preset_gecco2018_code();
  p.treatment = Treatment::kStress;
  p.duration = 0.5;
  return p;
}

bool same_bits(double a, double b) {
  return std::memcmp(&a, &b, sizeof a) == 0;
}

// Every field of the robot but `present`, bit for bit.
void expect_same_but_present(const RobotDef& a, const RobotDef& b) {
  EXPECT_EQ(a.stiffness, b.stiffness);
  EXPECT_EQ(a.dev_rate, b.dev_rate);
  EXPECT_EQ(a.phase, b.phase);
  EXPECT_EQ(a.act_amplitude, b.act_amplitude);
  EXPECT_EQ(a.act_scale, b.act_scale);
  EXPECT_EQ(a.nx, b.nx);
  EXPECT_EQ(a.voxel_size, b.voxel_size);
  EXPECT_EQ(a.loads.size(), b.loads.size());
  EXPECT_EQ(a.fixed_sites, b.fixed_sites);
}

void expect_same_robot(const RobotDef& a, const RobotDef& b) {
  expect_same_but_present(a, b);
  EXPECT_EQ(a.present, b.present);
}

void expect_same_physics(const PhysicsDef& a, const PhysicsDef& b) {
  EXPECT_EQ(evo::resolved_physics_json(a), evo::resolved_physics_json(b));
  EXPECT_TRUE(a.environment == b.environment);
}

bool connected(const RobotDef& r) {
  std::vector<int> seen(r.sites(), 0), stack;
  int total = 0, first = -1;
  for (int s = 0; s < r.sites(); ++s)
    if (r.present[s]) {
      ++total;
      if (first < 0) first = s;
    }
  stack.push_back(first);
  seen[first] = 1;
  int reached = 0;
  while (!stack.empty()) {
    const int v = stack.back();
    stack.pop_back();
    ++reached;
    const int x = v % r.nx, y = (v / r.nx) % r.ny, z = v / (r.nx * r.ny);
    const int d[6][3] = {{-1, 0, 0}, {1, 0, 0}, {0, -1, 0}, {0, 1, 0}, {0, 0, -1}, {0, 0, 1}};
    for (const auto& q : d) {
      const int a = x + q[0], b = y + q[1], c = z + q[2];
      if (a < 0 || b < 0 || c < 0 || a >= r.nx || b >= r.ny || c >= r.nz) continue;
      const int w = r.site(a, b, c);
      if (r.present[w] && !seen[w]) {
        seen[w] = 1;
        stack.push_back(w);
      }
    }
  }
  return reached == total;
}

TEST(Battery, VoxelLossRemovesVoxelsAndKeepsEverythingElse) {
  const RobotDef robot = walker();
  const PhysicsDef physics = short_life();
  for (uint64_t seed : {0u, 1u, 2u}) {
    const PerturbedLife life = perturb(robot, physics, K::kVoxelLoss, 0.1, seed, 7);
    expect_same_but_present(life.robot, robot);
    expect_same_physics(life.physics, physics);
    int removed = 0;
    for (int s = 0; s < robot.sites(); ++s) {
      EXPECT_LE(life.robot.present[s], robot.present[s]);  // only removed, never added
      removed += robot.present[s] - life.robot.present[s];
    }
    EXPECT_GE(removed, 2);  // round(0.1 * 24) = 2, more when a piece broke off
    EXPECT_TRUE(connected(life.robot));
  }
  EXPECT_NE(perturb(robot, physics, K::kVoxelLoss, 0.1, 0, 7).robot.present,
            perturb(robot, physics, K::kVoxelLoss, 0.1, 1, 7).robot.present);
  EXPECT_EQ(perturb(robot, physics, K::kVoxelLoss, 0.0, 0, 7).robot.present, robot.present);
}

TEST(Battery, LimbLossCutsOneEndOff) {
  const RobotDef robot = walker();
  const PhysicsDef physics = short_life();
  for (uint64_t seed = 0; seed < 6; ++seed) {
    const PerturbedLife life = perturb(robot, physics, K::kLimbLoss, 0.25, seed, 7);
    expect_same_but_present(life.robot, robot);
    expect_same_physics(life.physics, physics);
    // 4 x 3 x 2: a quarter of x's extent is one layer (6 voxels), of y's one layer (8 voxels).
    const int left = life.robot.voxel_count();
    EXPECT_TRUE(left == 18 || left == 16) << left;
    EXPECT_TRUE(connected(life.robot));
  }
}

TEST(Battery, PhaseNoiseMovesOnlyPhases) {
  const RobotDef robot = walker();
  const PhysicsDef physics = short_life();
  const PerturbedLife life = perturb(robot, physics, K::kPhaseNoise, 0.5, 3, 7);
  RobotDef same = life.robot;
  same.phase = robot.phase;
  expect_same_robot(same, robot);
  expect_same_physics(life.physics, physics);
  int moved = 0;
  for (int s = 0; s < robot.sites(); ++s) {
    double d = life.robot.phase[s] - robot.phase[s];
    d -= std::round(d);  // whole cycles are the same wave
    EXPECT_LE(std::abs(d), 0.25 + 1e-15);
    EXPECT_GT(life.robot.phase[s], -1.0);
    EXPECT_LT(life.robot.phase[s], 1.0);
    moved += d != 0;
  }
  EXPECT_EQ(moved, robot.voxel_count());
}

TEST(Battery, AmplitudeLossScalesActuationOnly) {
  const RobotDef robot = walker();
  const PhysicsDef physics = short_life();
  const PerturbedLife life = perturb(robot, physics, K::kAmplitudeLoss, 0.75, 0, 7);
  ASSERT_EQ(life.robot.act_scale.size(), static_cast<size_t>(robot.sites()));
  for (double x : life.robot.act_scale) EXPECT_EQ(x, 0.25);
  RobotDef same = life.robot;
  same.act_scale = robot.act_scale;
  expect_same_robot(same, robot);
  expect_same_physics(life.physics, physics);
}

TEST(Battery, PhysicsPerturbationsChangeOneThing) {
  const RobotDef robot = walker();
  const PhysicsDef physics = short_life();
  struct Case {
    K kind;
    double severity;
    std::function<void(PhysicsDef&)> expected;
  };
  const std::vector<Case> cases = {
      {K::kFriction, 0.1,
       [](PhysicsDef& p) {
         p.mu_static *= 0.1;
         p.mu_kinetic *= 0.1;
       }},
      {K::kGravity, 2.0, [](PhysicsDef& p) { p.gravity *= 2.0; }},
      {K::kBondModel, 1.0, [](PhysicsDef& p) { p.bond_model = BondModel::kVoxelyze09; }},
      {K::kTimeStep, 0.5, [](PhysicsDef& p) { p.dt_frac *= 0.5; }},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(to_string(c.kind));
    const PerturbedLife life = perturb(robot, physics, c.kind, c.severity, 0, 7);
    PhysicsDef expected = physics;
    c.expected(expected);
    expect_same_physics(life.physics, expected);
    expect_same_robot(life.robot, robot);
  }
}

TEST(Battery, RoughGroundAndPayload) {
  const RobotDef robot = walker();
  const PhysicsDef physics = short_life();
  const PerturbedLife rough = perturb(robot, physics, K::kRoughGround, 0.5, 0, 7);
  expect_same_robot(rough.robot, robot);
  EXPECT_EQ(rough.physics.environment.ground.kind, GroundKind::kRough);
  EXPECT_EQ(rough.physics.environment.ground.amplitude, 0.5 * robot.voxel_size);
  PhysicsDef flat = rough.physics;
  flat.environment = physics.environment;
  expect_same_physics(flat, physics);
  EXPECT_NE(rough.physics.environment.ground.seed,
            perturb(robot, physics, K::kRoughGround, 0.5, 1, 7).physics.environment.ground.seed);

  const PerturbedLife load = perturb(robot, physics, K::kPayload, 0.5, 0, 7);
  expect_same_physics(load.physics, physics);
  ASSERT_EQ(load.robot.loads.size(), 12u);  // the top layer of 4 x 3
  double total = 0;
  for (const RobotDef::Load& l : load.robot.loads) {
    EXPECT_EQ(l.site / (robot.nx * robot.ny), 1);
    EXPECT_EQ(l.fx, 0.0);
    total += l.fz;
  }
  const double weight = 24 * physics.density * 1e-6 * 9.81;
  EXPECT_NEAR(total, -0.5 * weight, 1e-9 * weight);
  RobotDef same = load.robot;
  same.loads.clear();
  expect_same_robot(same, robot);
}

TEST(Battery, PaperIsEquationTwo) {
  const RobotDef robot = walker();
  const PhysicsDef physics = short_life();
  RobustnessOptions o;
  o.seed = 7;
  const PerturbedLife life = perturb(robot, physics, K::kPaper, 1.0, 2, 7);
  EXPECT_EQ(life.robot.stiffness, robustness_draw(robot, physics, o, 2).stiffness);
  EXPECT_EQ(life.robot.dev_rate, std::vector<double>(robot.sites(), 0.0));
  expect_same_physics(life.physics, robustness_physics(physics));
  // A smaller spread draws from a narrower range about the range's geometric centre.
  const PerturbedLife narrow = perturb(robot, physics, K::kPaper, 0.25, 2, 7);
  for (int s = 0; s < robot.sites(); ++s) {
    EXPECT_GE(narrow.robot.stiffness[s], std::sqrt(1e5 * 1e11) * std::pow(1e-3, 0.25) * 0.999);
    EXPECT_LE(narrow.robot.stiffness[s], std::sqrt(1e5 * 1e11) * std::pow(1e3, 0.25) * 1.001);
  }
}

TEST(Battery, PaperBatteryReproducesRToTheBit) {
  const RobotDef robot = walker();
  const PhysicsDef physics = short_life();
  RobustnessOptions o;
  o.draws = 4;
  o.seed = 11;
  const RobustnessResult r = robustness(robot, physics, o);
  ProfileOptions po;
  po.seed = 11;
  const RobustnessProfile p = robustness_profile(robot, physics, builtin_battery("paper", 4), po);
  ASSERT_EQ(p.perturbations.size(), 1u);
  const SeverityLevel& l = p.perturbations[0].levels.at(0);
  EXPECT_TRUE(same_bits(p.perturbations[0].f_reference, r.f_train));
  ASSERT_EQ(l.lives.size(), 4u);
  for (int k = 0; k < 4; ++k) EXPECT_TRUE(same_bits(l.lives[k].kept, r.draws[k].r)) << k;
  ASSERT_TRUE(l.mean_kept);
  EXPECT_TRUE(same_bits(*l.mean_kept, r.mean_r));
  EXPECT_TRUE(same_bits(*p.perturbations[0].auc, r.mean_r));
  EXPECT_EQ(p.lives, 5);
}

Battery two_kinds() {
  Battery b;
  b.name = "test";
  b.perturbations = {{"damage", K::kVoxelLoss, {0.05, 0.1, 0.2}, {0, 1}},
                     {"ice", K::kFriction, {0.1, 0.5, 2.0}, {0}}};
  return b;
}

TEST(Battery, ProfileIsTheSameOnOneAndTwoThreads) {
  const RobotDef robot = walker();
  const PhysicsDef physics = short_life();
  ProfileOptions one, two;
  one.threads = 1;
  two.threads = 2;
  const RobustnessProfile a = robustness_profile(robot, physics, two_kinds(), one);
  const RobustnessProfile b = robustness_profile(robot, physics, two_kinds(), two);
  ASSERT_EQ(a.perturbations.size(), b.perturbations.size());
  EXPECT_EQ(a.lives, 1 + 3 * 2 + 3);
  for (size_t i = 0; i < a.perturbations.size(); ++i) {
    const PerturbationProfile &x = a.perturbations[i], &y = b.perturbations[i];
    ASSERT_TRUE(x.auc && y.auc);
    EXPECT_TRUE(same_bits(*x.auc, *y.auc));
    for (size_t l = 0; l < x.levels.size(); ++l)
      for (size_t k = 0; k < x.levels[l].lives.size(); ++k)
        EXPECT_TRUE(same_bits(x.levels[l].lives[k].fitness, y.levels[l].lives[k].fitness));
  }
  // The AUC is the trapezoid area of the mean curve over the severity span.
  const PerturbationProfile& ice = a.perturbations[1];
  const double m0 = *ice.levels[0].mean_kept, m1 = *ice.levels[1].mean_kept,
               m2 = *ice.levels[2].mean_kept;
  EXPECT_DOUBLE_EQ(*ice.auc, (0.4 * (m0 + m1) / 2 + 1.5 * (m1 + m2) / 2) / 1.9);
  // A reference life is the unperturbed champion, development and all.
  EXPECT_EQ(ice.f_reference, simulate(compile(robot, physics)).fitness);
}

TEST(Battery, UnstableLivesAreCountedNotAveraged) {
  // The block sinks through the floor (or blows up) under a payload of five times its weight,
  // not under a tenth of it.
  RobotDef robot = walker(1e8);
  PhysicsDef physics = short_life();
  physics.treatment = Treatment::kNone;
  Battery b;
  b.name = "load";
  b.perturbations = {{"payload", K::kPayload, {0.1, 5.0}, {0}}};
  const RobustnessProfile p = robustness_profile(robot, physics, b);
  const PerturbationProfile& pp = p.perturbations[0];
  ASSERT_TRUE(pp.reference_valid) << pp.reference_failure;
  const SeverityLevel &light = pp.levels[0], &heavy = pp.levels[1];
  EXPECT_EQ(light.valid, 1);
  ASSERT_EQ(heavy.valid, 0);
  EXPECT_EQ(heavy.unstable + heavy.sank, 1);
  EXPECT_EQ(p.unstable + p.sank, 1);
  EXPECT_NE(heavy.lives[0].status, "ok");
  EXPECT_FALSE(heavy.lives[0].valid);
  EXPECT_FALSE(heavy.mean_kept);  // not a zero averaged in
  EXPECT_FALSE(pp.auc);
}

std::string battery_error(const std::string& text) {
  const std::string path =
      (std::filesystem::temp_directory_path() / "plastivox-battery-test.json").string();
  std::ofstream(path) << text;
  return testing::error_of([&] { load_battery(path); });
}

TEST(Battery, BadBatteriesAreRefusedNamingFileAndField) {
  const std::string head = R"({"format": "plastivox-battery", "version": 1, "perturbations": )";
  const std::string e1 =
      battery_error(head + R"([{"kind": "earthquake", "severities": [1], "seeds": [0]}]})");
  EXPECT_NE(e1.find("plastivox-battery-test.json: perturbations[0].kind: unknown perturbation "
                    "'earthquake'"),
            std::string::npos)
      << e1;
  const std::string e2 =
      battery_error(head + R"([{"kind": "gravity", "severities": [1]}, {"kind": "friction"}]})");
  EXPECT_NE(e2.find("plastivox-battery-test.json: perturbations[0].seeds: missing"),
            std::string::npos)
      << e2;
  const std::string e3 =
      battery_error(head + R"([{"kind": "voxel-loss", "severities": [0.1, 0.95], "seeds": [0]}]})");
  EXPECT_NE(e3.find("plastivox-battery-test.json: perturbations[0].severities[1]: "),
            std::string::npos)
      << e3;
  EXPECT_NE(e3.find("outside [0, 0.9]"), std::string::npos) << e3;
  for (const std::string& e : {e1, e2, e3}) EXPECT_EQ(e.find('\n'), std::string::npos) << e;
  EXPECT_NE(battery_error("[]").find(": (top): expected an object"), std::string::npos);
  EXPECT_NE(testing::error_of([] {
              load_battery("no-such-battery.json");
            }).find("no-such-battery.json: cannot read"),
            std::string::npos);
  // The built-in batteries are valid and read back from their JSON.
  for (const char* name : {"default", "paper", "small"}) {
    const Battery b = builtin_battery(name);
    const std::string path =
        (std::filesystem::temp_directory_path() / "plastivox-battery-builtin.json").string();
    std::ofstream(path) << battery_json(b);
    EXPECT_EQ(battery_json(load_battery(path)), battery_json(b)) << name;
  }
  // A bad battery is refused by the profile before any life runs.
  Battery bad = two_kinds();
  bad.perturbations[1].seeds.clear();
  EXPECT_NE(testing::error_of([&] {
              robustness_profile(walker(), short_life(), bad);
            }).find("test: perturbations[1].seeds: at least one seed"),
            std::string::npos);
}

TEST(Battery, DefaultBatteryCoversEveryKindWithThreeSeverities) {
  const Battery b = builtin_battery("default");
  for (const char* kind :
       {"paper", "voxel-loss", "limb-loss", "phase-noise", "amplitude-loss", "friction",
        "rough-ground", "payload", "gravity", "bond-model", "time-step"}) {
    bool found = false;
    for (const Perturbation& p : b.perturbations)
      if (to_string(p.kind) == std::string(kind)) {
        found = true;
        if (p.kind != K::kBondModel) {
          EXPECT_GE(p.severities.size(), 3u) << kind;
        }
      }
    EXPECT_TRUE(found) << kind;
  }
}

}  // namespace
}  // namespace plastivox::analysis
