// Environments (docs/environments.md): a ground given as a height field and static boxes,
// with the floor's contact and friction model (engine/core/src/terrain.cpp), checked against
// analytic answers; the floor health on a ground; and the "environment" object of physics
// sections (engine/io/src/environment_json.cpp): errors, and a robot file round trip.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "plastivox/demo_robots.hpp"
#include "plastivox/io/robot_file.hpp"
#include "plastivox/rules/life_rules.hpp"
#include "plastivox/simulator.hpp"
#include "test_support.hpp"

namespace plastivox {
namespace {

using testing::block;
using testing::error_of;
using testing::passive_physics;
using testing::run_until;
using testing::with_environment;

constexpr double kPi = 3.14159265358979323846;

// ---- The plain floor's bits ----

// A flat ground at height 0 (level, or a grid of zeros) takes the terrain path (scalar, voxel
// by voxel) and gives the floor kernel's bits: a walking, developing body, with the contact
// stimulus (which reads the normal forces), and with a box far away (a second contact loop that
// never touches).
TEST(Terrain, FlatGroundAtZeroGivesTheFloorsBits) {
  for (Treatment t : {Treatment::kStress, Treatment::kContact}) {
    PhysicsDef floor = preset_gecco2018_code();
    floor.treatment = t;
    floor.duration = 1.0;
    const SimResult plain = simulate(compile(demo_walker(), floor));
    for (const char* env :
         {R"({"ground": {"type": "flat"}})",
          R"({"ground": {"type": "heightfield", "cell": 0.5, "origin": [-0.5, -0.5],
                         "heights": [[0, 0, 0], [0, 0, 0], [0, 0, 0]]}})",
          R"({"ground": {"type": "flat"}, "obstacles": [{"min": [5, 5, 0], "max": [6, 6, 1]}]})"}) {
      const Model m = compile(demo_walker(), with_environment(floor, env));
      ASSERT_TRUE(m.terrain);
      const SimResult r = simulate(m);
      EXPECT_EQ(r.final_state_hash, plain.final_state_hash) << to_string(t) << " " << env;
      EXPECT_EQ(r.fitness, plain.fitness);
      EXPECT_EQ(r.floor_depth, plain.floor_depth);
    }
  }
}

// ---- Resting on a step and on a box ----

// A 2 x 2 x 1 block dropped 2 mm onto a ground or a box comes to rest with its bottom at the
// surface's height less the penetration that carries each voxel's weight, m g / (2 E L).
void expect_rests_at(const std::string& env, double surface) {
  PhysicsDef d = passive_physics();
  d.duration = 1.5;
  const double E = 1e8, L = 0.01;
  const Model m = compile(block(2, 2, 1, E), with_environment(d, env));
  Simulator sim(m);
  // Placed resting on the ground (compile), not on a box: dropped 2 mm onto the surface.
  const double placed = m.rest_pos[0].z() - 0.5 * L;
  for (Vec3& p : sim.mutable_state().pos) p.z() += surface - placed + 0.002;
  run_until(sim, d.duration);
  const State& s = sim.state();
  ASSERT_EQ(s.status, SimStatus::kFinished) << s.failure;
  const double pen = m.mass * -d.gravity / (2 * E * L);
  for (int i = 0; i < m.n; ++i) {
    EXPECT_NEAR(s.pos[i].z() - 0.5 * L, surface - pen, 1e-6) << env;  // bottom face
    EXPECT_LT(s.lin_mom[i].norm() / m.mass, 1e-4);                    // at rest
  }
}

TEST(Terrain, BlockRestsOnAStepAtTheStepsHeight) {
  expect_rests_at(R"({"ground": {"type": "step", "height": 0.03, "at": -0.1}})", 0.03);
  // A step down: the block rests below z = 0.
  expect_rests_at(R"({"ground": {"type": "step", "height": -0.02, "at": -0.1}})", -0.02);
  // Stairs: on the third tread.
  expect_rests_at(
      R"({"ground": {"type": "stairs", "rise": 0.01, "run": 0.05, "count": 5, "at": -0.13}})",
      0.03);
}

TEST(Terrain, BlockRestsOnABoxAtItsTop) {
  expect_rests_at(R"({"obstacles": [{"min": [-0.1, -0.1, -0.05], "max": [0.1, 0.1, 0.025]}]})",
                  0.025);
}

// ---- Ramps and static friction ----

// A 2 x 2 x 1 block on a ramp of angle theta (mu_s 0.5, mu_k 0.3, no slow damping), placed
// with its bottom on the slope and pressed in by the penetration that carries its weight
// normal to the slope, at rest. Runs to each of `times` and returns the centre's velocity
// down the slope there (m/s).
std::vector<double> slide_on_ramp(double theta_deg, const std::vector<double>& times) {
  PhysicsDef d = passive_physics();
  d.mu_static = 0.5;
  d.mu_kinetic = 0.3;
  d.global_damping = 0;
  d.duration = times.back() + 1;
  const double E = 1e8, L = 0.01, theta = theta_deg * kPi / 180;
  const std::string env = R"({"ground": {"type": "ramp", "angle_deg": )" +
                          std::to_string(theta_deg) + R"(, "at": -0.5, "length": 1.0}})";
  const Model m = compile(block(2, 2, 1, E), with_environment(d, env));
  Simulator sim(m);
  State& s = sim.mutable_state();
  const Eigen::AngleAxisd turn(-theta, Vec3::UnitY());  // +x onto the slope's direction
  const double pen = m.mass * -d.gravity * std::cos(theta) / (2 * E * L);
  const Vec3 normal = turn * Vec3::UnitZ();
  const Vec3 foot(0, 0, 0.5 * std::tan(theta));  // the ramp's surface at x = 0
  for (int i = 0; i < m.n; ++i) {
    const Vec3 lattice = m.rest_pos[i] - Vec3(0, 0, m.rest_pos[0].z() - 0.5 * L);  // on z = 0
    s.pos[i] = foot + turn * lattice - pen * normal;
    s.orient[i] = Quat(turn);
  }
  const Vec3 down = turn * -Vec3::UnitX();
  std::vector<double> speeds;
  for (double t : times) {
    run_until(sim, t);
    EXPECT_EQ(sim.state().status, SimStatus::kRunning) << sim.state().failure;
    Vec3 p = Vec3::Zero();
    for (const Vec3& v : sim.state().lin_mom) p += v;
    speeds.push_back(p.dot(down) / (m.n * m.mass));
  }
  return speeds;
}

TEST(Terrain, BlockStaysOnARampWhenTanThetaIsBelowStaticFriction) {
  // tan 10 deg = 0.18, tan 24 deg = 0.45 < mu_s = 0.5 (24 deg is steeper than mu_k allows a
  // slide to stop, so only static friction holds it): never moves.
  for (double theta : {10.0, 24.0})
    for (double v : slide_on_ramp(theta, {0.01, 0.2, 0.5}))
      EXPECT_LT(std::abs(v), 1e-15) << theta;  // rounding of the normal projection
}

TEST(Terrain, BlockSlidesDownARampWhenTanThetaExceedsStaticFriction) {
  // tan 29 deg = 0.55 and tan 35 deg = 0.70 > mu_s: it slides with a = g (sin - mu_k cos).
  for (double theta : {29.0, 35.0}) {
    const double th = theta * kPi / 180;
    const double a = 9.81 * (std::sin(th) - 0.3 * std::cos(th));
    const std::vector<double> v = slide_on_ramp(theta, {0.1, 0.4});
    EXPECT_GT(v[0], 0.5 * a * 0.1) << theta;
    EXPECT_TRUE(testing::RelNear((v[1] - v[0]) / 0.3, a, 0.02)) << theta;
  }
}

// ---- Thin obstacles at the speed limit ----

// A voxel thrown at 99.9 % of max_speed at a 1 mm plate (a tenth of its size) stops at the
// plate whatever its time step (the softest and the stiffest modulus the physics allows),
// from either side and at a slant; it never ends inside or past the plate.
TEST(Terrain, VoxelCannotPassThroughAThinPlateAtTheSpeedLimit) {
  const double L = 0.01, plate = 0.05, thick = 0.001;
  PhysicsDef d = passive_physics();
  d.gravity = 0;
  d.floor = false;
  d.duration = 1e3;
  const std::string env = R"({"obstacles": [{"min": [0.05, -1, -1], "max": [0.051, 1, 1]}]})";
  const PhysicsDef def = with_environment(d, env);
  for (double E : {def.e_min, 1e9, def.e_max}) {
    const Model m = compile(block(1, 1, 1, E), def);
    for (double dir : {1.0, -1.0}) {
      for (double slant : {0.0, 0.5, 1.2}) {
        Simulator sim(m);
        State& s = sim.mutable_state();
        const double v = 0.999 * def.max_speed;
        const Vec3 heading(dir * std::cos(slant), std::sin(slant), 0);
        // Start one voxel from the face on the side the voxel comes from.
        s.pos[0].x() = dir > 0 ? plate - 1.5 * L : plate + thick + 1.5 * L;
        s.lin_mom[0] = m.mass * v * heading;
        // The plate grown by the voxel's half size: the centre may enter it (the penalty
        // contact) but never reach its middle, and is pushed back out.
        const double middle = plate + 0.5 * thick,
                     face = dir > 0 ? plate - 0.5 * L : plate + thick + 0.5 * L;
        for (int k = 0; k < 400 && sim.state().status == SimStatus::kRunning; ++k) {
          sim.step();
          const double x = sim.state().pos[0].x();
          ASSERT_LT(dir * (x - middle), 0)
              << "E " << E << " dir " << dir << " slant " << slant << " step " << k << " x " << x;
        }
        EXPECT_EQ(sim.state().status, SimStatus::kRunning) << sim.state().failure;
        EXPECT_LE(dir * (sim.state().pos[0].x() - face), 1e-12) << "E " << E << " slant " << slant;
      }
    }
  }
}

// At a walking speed a voxel meets a box as it meets the floor: the penalty contact turns it
// back (it bounces) without the stop of fast paths.
TEST(Terrain, SlowVoxelBouncesOffABox) {
  PhysicsDef d = passive_physics();
  d.gravity = 0;
  d.floor = false;
  d.duration = 1e3;
  const Model m =
      compile(block(1, 1, 1, 1e9), with_environment(d, R"({"obstacles": [{"min": [0.05, -1, -1],
                                                  "max": [0.06, 1, 1]}]})"));
  Simulator sim(m);
  sim.mutable_state().lin_mom[0] = m.mass * Vec3(0.5, 0, 0);
  run_until(sim, 0.2);
  EXPECT_LT(sim.state().lin_mom[0].x(), -0.01 * m.mass);  // on its way back, > 1 cm/s
  EXPECT_LT(sim.state().pos[0].x(), 0.045);
}

// ---- Floor health on a ground ----

// Health is measured from the ground under each voxel: a block resting at the bottom of a gap
// (below z = 0) is fine, a soft heavy block that falls through the ground there has sunk.
TEST(Terrain, HealthIsMeasuredFromTheGround) {
  const std::string gap =
      R"({"ground": {"type": "gap", "at": -0.05, "width": 0.1, "depth": 0.05}})";
  PhysicsDef d = passive_physics();
  d.duration = 1.0;
  const SimResult firm = simulate(compile(block(2, 2, 1, 1e10), with_environment(d, gap)));
  EXPECT_EQ(firm.status, SimStatus::kFinished) << firm.failure;
  EXPECT_EQ(firm.floor_health, FloorHealth::kOk);
  EXPECT_LT(firm.com_final.z(), 0);  // in the gap
  EXPECT_LT(firm.floor_depth, 0.1);

  SimResult soft = simulate(compile(block(2, 2, 2, 1e5), with_environment(d, gap)));
  judge_life(d, soft);
  EXPECT_TRUE(soft.sank);
  EXPECT_EQ(soft.status, SimStatus::kUnstable);  // sinking_invalid
  EXPECT_GT(soft.voxels_below_floor, 0);
}

// A rough ground is seeded: the same seed, the same heights; all in [-amplitude, 0].
TEST(Terrain, RoughGroundIsSeededAndBounded) {
  GroundDef g;
  g.kind = GroundKind::kRough;
  g.cell = 0.02, g.nx = 20, g.ny = 10, g.amplitude = 0.004, g.seed = 7;
  const HeightField a = make_height_field(g), b = make_height_field(g);
  EXPECT_EQ(a.h, b.h);
  for (double h : a.h) EXPECT_TRUE(h <= 0 && h >= -0.004);
  g.seed = 8;
  EXPECT_NE(make_height_field(g).h, a.h);
  // Bilinear between nodes, the edge continued past the grid.
  HeightField f;
  f.cell = 1, f.nx = 2, f.ny = 2, f.h = {0, 1, 2, 3};
  double gx, gy;
  EXPECT_DOUBLE_EQ(f.height(0.5, 0.5, &gx, &gy), 1.5);
  EXPECT_DOUBLE_EQ(gx, 1);
  EXPECT_DOUBLE_EQ(gy, 2);
  EXPECT_DOUBLE_EQ(f.height(-3, 5, &gx, &gy), 2);
  EXPECT_EQ(gx, 0);
  EXPECT_EQ(gy, 0);
}

// ---- JSON ----

std::string robot_with_environment(const std::string& env) {
  return R"({"format": "plastivox-robot", "version": 1, "lattice": {"nx": 1, "ny": 1, "nz": 1,
    "voxel_size": 0.01}, "voxels": [[0, 0, 0, 1e9, 0, 0]], "physics": {"environment": )" +
         env + "}}";
}

TEST(EnvironmentJson, RobotFileRoundTripsEveryGround) {
  for (const char* env :
       {R"({"ground": {"type": "flat", "height": 0.01}})",
        R"({"ground": {"type": "heightfield", "cell": 0.02, "origin": [-0.1, -0.2],
               "heights": [[0, 0.001, 0.002], [0.003, 0.004, 0.005]]},
               "obstacles": [{"min": [0.1, 0, 0], "max": [0.2, 0.1, 0.05]}]})",
        R"({"ground": {"type": "ramp", "angle_deg": 10, "length": 0.5, "at": 0.1}})",
        R"({"ground": {"type": "step", "height": 0.02, "at": 0.1, "edge": 0.002}})",
        R"({"ground": {"type": "stairs", "rise": 0.01, "run": 0.03, "count": 4}})",
        R"({"ground": {"type": "gap", "width": 0.05, "depth": 0.1, "at": 0.1}})",
        R"({"ground": {"type": "rough", "amplitude": 0.003, "cell": 0.02, "nodes": [30, 20],
               "origin": [-0.3, -0.2], "seed": 12345678901234}})",
        R"({"obstacles": [{"min": [0.1, 0, 0], "max": [0.2, 0.1, 0.05]}]})"}) {
    const RobotFile a = parse_robot_json(robot_with_environment(env), "a.json");
    ASSERT_TRUE(a.physics.environment.active()) << env;
    const std::string text = robot_to_json(a.robot, &a.physics);
    const RobotFile b = parse_robot_json(text, "b.json");
    EXPECT_EQ(robot_to_json(b.robot, &b.physics), text) << env;
    const Model ma = compile(a.robot, a.physics), mb = compile(b.robot, b.physics);
    EXPECT_EQ(ma.ground.h, mb.ground.h) << env;
    EXPECT_EQ(ma.ground.nx, mb.ground.nx);
    EXPECT_EQ(b.physics.environment.obstacles.size(), a.physics.environment.obstacles.size());
  }
  // physics_to_json (how MPI ranks send physics) reads back exactly, environment and all.
  PhysicsDef d = with_environment(preset_gecco2018_paper(),
                                  R"({"ground": {"type": "rough", "amplitude": 0.003, "cell": 0.02,
                                      "nodes": [3, 2]}, "obstacles": [{"min": [0, 0, 0],
                                      "max": [0.1, 0.1, 0.1]}]})");
  d.sinking_invalid = false, d.treatment = Treatment::kKinetic, d.mu_static = 0.1 + 1e-17;
  PhysicsDef back;
  apply_physics_json(physics_to_json(d), "message", back);
  EXPECT_EQ(physics_to_json(back), physics_to_json(d));
  EXPECT_EQ(back.mu_static, d.mu_static);
  EXPECT_EQ(make_height_field(back.environment.ground).h,
            make_height_field(d.environment.ground).h);
  // The plain floor writes no environment (files and evolution identities keep their bytes).
  const RobotFile plain = parse_robot_json(robot_with_environment("{}"), "c.json");
  EXPECT_EQ(robot_to_json(plain.robot, &plain.physics).find("environment"), std::string::npos);
}

TEST(EnvironmentJson, BadDefinitionsNameTheFileAndField) {
  const std::string g = "f.json: physics.environment.ground.";
  const std::pair<const char*, std::string> cases[] = {
      {R"({"ground": {"type": "heightfield", "cell": "a", "heights": [[0]]}})",
       g + "cell: expected a number"},
      {R"({"ground": {"type": "heightfield", "cell": -0.01, "heights": [[0]]}})",
       g + "cell: must be in (0, 1e6] m"},
      {R"({"ground": {"type": "heightfield", "cell": 0.01, "heights": [[0, 1], [2]]}})",
       g + "heights[1]: expected 2 heights, as row 0 (rows must not be ragged)"},
      {R"({"ground": {"type": "heightfield", "cell": 0.01, "heights": [[0, "x"]]}})",
       g + "heights[0][1]: expected a number"},
      {R"({"ground": {"type": "heightfield", "cell": 0.01, "heights": [[0, 1e7]]}})",
       g + "heights: every height must be finite, |h| <= 1e6 m"},
      {R"({"ground": {"type": "heightfield", "cell": 0.01, "heights": []}})",
       g + "heights: expected rows of heights along x, one row per y: [[h, ...], ...]"},
      {R"({"ground": {"type": "rough", "amplitude": 0.01, "cell": 0.01, "nodes": [4096, 4096]}})",
       g + "nodes: more than 4194304 nodes"},
      {R"({"ground": {"type": "ramp", "angle_deg": 5, "length": 1000, "edge": 1e-6}})", ""},
      {R"({"ground": {"type": "ramp", "angle_deg": 95, "length": 1}})",
       g + "angle_deg: must be in (-80, 80) degrees"},
      {R"({"ground": {"type": "ramp", "angle_deg": 10}})", g + "length: missing"},
      {R"({"ground": {"type": "hill"}})", g + "type: ground type 'hill' is unknown (use flat, "
                                              "heightfield, ramp, step, stairs, gap or rough)"},
      {R"({"ground": {"type": "flat", "slope": 1}})", g + "slope: unknown field"},
      {R"({"obstacles": [{"min": [0, 0, 0], "max": [1, -1, 1]}]})",
       "f.json: physics.environment.obstacles[0]: min must be below max on every axis"},
      {R"({"obstacles": [{"min": [0, 0], "max": [1, 1, 1]}]})",
       "f.json: physics.environment.obstacles[0].min: expected an array of 3 numbers"},
      {R"({"terrain": 1})", "f.json: physics.environment.terrain: unknown field"},
  };
  for (const auto& [env, message] : cases) {
    const std::string e =
        error_of([&] { parse_robot_json(robot_with_environment(env), "f.json"); });
    if (*message.c_str())
      EXPECT_EQ(e, message) << env;
    else  // a ramp sampled finer than the node limit allows
      EXPECT_NE(e.find(g + "edge: samples the ground at more than"), std::string::npos) << e;
  }
  // A ground with the floor off is a contradiction.
  EXPECT_NE(error_of([] {
              parse_robot_json(R"({"format": "plastivox-robot", "version": 1, "lattice": {"nx": 1,
                "ny": 1, "nz": 1, "voxel_size": 0.01}, "voxels": [[0, 0, 0, 1e9, 0, 0]],
                "physics": {"floor": false, "environment": {"ground": {"type": "flat"}}}})",
                               "g.json");
            }).find("g.json: physics.environment.ground: a ground needs physics.floor true"),
            std::string::npos);
}

// JSON has no NaN or infinity (1e999 is refused as not valid JSON); a height field made in
// code is checked all the same.
TEST(EnvironmentJson, NonFiniteHeightsAreRefused) {
  Environment env;
  env.ground.kind = GroundKind::kHeights;
  env.ground.cell = 0.01, env.ground.nx = 2, env.ground.ny = 1;
  env.ground.heights = {0, std::nan("")};
  EXPECT_EQ(error_of([&] { validate(env); }),
            "physics.environment.ground.heights: every height must be finite, |h| <= 1e6 m");
  env.ground.heights = {0, 0};
  env.obstacles.push_back({{0, 0, 0}, {1, 1, std::nan("")}});
  EXPECT_EQ(error_of([&] { validate(env); }),
            "physics.environment.obstacles[0]: corners must be finite, within 1e6 m");
}

// The program prints the one line and exits non-zero.
TEST(EnvironmentJson, ProgramRefusesABadEnvironmentInOneLine) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "pv_terrain_test";
  std::filesystem::create_directories(dir);
  const std::string path = (dir / "bad.json").string();
  std::ofstream(path) << robot_with_environment(
      R"({"ground": {"type": "heightfield", "cell": 0.01, "heights": [[0, 1], [2]]}})");
  const testing::Output o =
      testing::shell(std::string(PLASTIVOX_CLI) + " simulate " + path + " 2>&1");
  EXPECT_NE(o.status, 0);
  EXPECT_NE(o.out.find(path + ": physics.environment.ground.heights[1]: expected 2 heights"),
            std::string::npos)
      << o.out;
  EXPECT_EQ(std::count(o.out.begin(), o.out.end(), '\n'), 1) << o.out;
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace plastivox
