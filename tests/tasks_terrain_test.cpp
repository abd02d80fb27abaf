// The terrain tasks (rough, climb, slope, obstacles; docs/tasks.md): each fitness on hand-made
// cases with known answers, each default environment (laid out around the body, in voxel
// lengths, seeded), a given environment used as given, the body placed resting on the ground
// under it, the task's parameters in configs and robot files, and bad definitions as one line.
#include <cmath>
#include <fstream>

#include <nlohmann/json.hpp>

#include "experiment/experiment_config.hpp"
#include "plastivox/evo/config.hpp"
#include "plastivox/evo/results_file.hpp"
#include "plastivox/io/robot_file.hpp"
#include "plastivox/simulator.hpp"
#include "plastivox/task.hpp"
#include "test_support.hpp"

namespace plastivox {
namespace {

using testing::cli;

using testing::block;
using testing::error_of;
using testing::Output;
using testing::passive_physics;

constexpr double kPi = 3.14159265358979323846;
constexpr double L = 0.01;  // the voxel size of every body here, m

PhysicsDef physics_of(Task task, const TaskParams& params = {}) {
  PhysicsDef d = passive_physics();
  d.task = task;
  d.task_params = params;
  return d;
}

// A 3 x 2 x 1 block (footprint centre (1.5 L, 1 L), half extents 1.5 L and 1 L) under `d`.
Model block_under(const PhysicsDef& d) {
  return compile(block(3, 2, 1, 1e6), d);
}

// The score of a life of model m whose centre of mass went from `from` to `to` (m).
double score_of(const Model& m, const Vec3& from, const Vec3& to) {
  SimResult summary;
  summary.com_settled = from;
  summary.com_final = to;
  summary.displacement = to - from;
  return task_score(m, State{}, summary);
}

// The centre of the 3 x 2 footprint at height z.
Vec3 centre(double z = 0.5 * L) {
  return {1.5 * L, 1.0 * L, z};
}

// ---- The table ----

TEST(TerrainTasks, EachHasAUnitAFormulaParametersAndADefaultEnvironment) {
  for (Task t : {Task::kRough, Task::kClimb, Task::kSlope, Task::kObstacles}) {
    const TaskInfo& info = task_info(t);
    EXPECT_STREQ(info.unit, "voxel lengths");
    EXPECT_GT(std::string(info.formula).size(), 20u);
    ASSERT_NE(info.environment, nullptr);
    EXPECT_FALSE(info.params.empty());
    for (const TaskParam& p : info.params) {
      EXPECT_NO_THROW(check_task_param(t, p.name, p.fallback)) << info.name << " " << p.name;
      EXPECT_EQ(task_param(physics_of(t), p.name), p.fallback);
    }
    EXPECT_EQ(parse_task(info.name), t);
  }
  // The tasks without an environment of their own live on the floor.
  for (Task t : {Task::kWalk, Task::kJump, Task::kTurn}) {
    EXPECT_EQ(task_info(t).environment, nullptr);
    EXPECT_FALSE(block_under(physics_of(t)).terrain);
  }
}

// ---- Fitness on hand-made cases ----

TEST(TerrainTasks, RoughAndObstaclesScoreTheHorizontalDisplacement) {
  for (Task t : {Task::kRough, Task::kObstacles}) {
    const Model m = block_under(physics_of(t));
    EXPECT_EQ(score_of(m, centre(), centre()), 0.0) << to_string(t);
    // 3 and 4 voxel lengths across, and up and down: 5, whatever the height.
    EXPECT_NEAR(score_of(m, centre(), centre() + Vec3(3 * L, -4 * L, 0.7 * L)), 5.0, 1e-12);
    EXPECT_NEAR(score_of(m, centre(), centre() + Vec3(-3 * L, 4 * L, -0.2 * L)), 5.0, 1e-12);
  }
}

TEST(TerrainTasks, SlopeScoresTheRiseOfTheGroundUnderTheCentreOfMass) {
  const Model m = block_under(physics_of(Task::kSlope));
  const double grade = std::tan(10 * kPi / 180);
  const double flat = 1.5 * L + 1 * L;  // level ground: the footprint's half extent and 1 L
  EXPECT_EQ(score_of(m, centre(), centre()), 0.0);
  // Across the level ground alone: nothing.
  EXPECT_EQ(score_of(m, centre(), centre() + Vec3(flat, 0, 0)), 0.0);
  // 4 voxel lengths up the slope, along +x or -y (every way is uphill): 4 tan 10 deg.
  EXPECT_NEAR(score_of(m, centre(), centre() + Vec3(flat + 4 * L, 0, 0)), 4 * grade, 1e-9);
  EXPECT_NEAR(score_of(m, centre(), centre() + Vec3(0, -flat - 4 * L, 0)), 4 * grade, 1e-9);
  // Rearing up scores nothing, and coming down from higher up scores 0, not less.
  EXPECT_EQ(score_of(m, centre(), centre() + Vec3(0, 0, 3 * L)), 0.0);
  EXPECT_EQ(score_of(m, centre() + Vec3(flat + 4 * L, 0, 0), centre()), 0.0);
  // Past the slope's length (20 L) the ground is level: 20 tan 10 deg at most.
  EXPECT_NEAR(score_of(m, centre(), centre() + Vec3(flat + 25 * L, 0, 0)), 20 * grade, 1e-9);
  // Another angle.
  const Model steep = block_under(physics_of(Task::kSlope, {{"angle_deg", 20}}));
  EXPECT_NEAR(score_of(steep, centre(), centre() + Vec3(flat + 2 * L, 0, 0)),
              2 * std::tan(20 * kPi / 180), 1e-9);
}

TEST(TerrainTasks, ClimbScoresDistancePlusWeightedHeightGained) {
  // Steps of 0.5 L (the default is 0.25 L) keep the sums round.
  const Model m = block_under(physics_of(Task::kClimb, {{"rise", 0.5}}));
  const double flat = 1.5 * L + 1 * L;
  EXPECT_EQ(score_of(m, centre(), centre()), 0.0);
  // On the level ground: the distance alone (2 L).
  EXPECT_NEAR(score_of(m, centre(), centre() + Vec3(0, 2 * L, 0)), 2.0, 1e-12);
  // Onto the second step (runs of 3 L, rises of 0.5 L): 7 L across, 1 L up, weighed 4 times.
  const Vec3 second = centre() + Vec3(flat + 4.5 * L, 0, 0);
  EXPECT_NEAR(m.ground.height(second.x(), second.y()), 1.0 * L, 1e-15);
  EXPECT_NEAR(score_of(m, centre(), second), 7.0 + 4 * 1.0, 1e-9);
  // Down again to the start: 7 L across less 4 x 1 L down.
  EXPECT_NEAR(score_of(m, second, centre()), 7.0 - 4.0, 1e-9);
  // Parameters: a weight of 0 is distance alone; steps of 1 L: onto the first, 2.5 + 4 x 1.
  const Model w0 = block_under(physics_of(Task::kClimb, {{"rise", 0.5}, {"height_weight", 0}}));
  EXPECT_NEAR(score_of(w0, centre(), second), 7.0, 1e-9);
  const Model tall = block_under(physics_of(Task::kClimb, {{"rise", 1}}));
  EXPECT_NEAR(score_of(tall, centre(), centre() + Vec3(-flat - 1.5 * L, 0, 0)), 4.0 + 4.0, 1e-9);
}

TEST(TerrainTasks, ClimbReadsAGivenStaircase) {
  // Stairs along +x from x = 5 L, 1 L high every 2 L: a body moved 6 L, from x = 1.5 L to
  // 7.5 L, is on the second tread, 2 L up: 6 + 4 x 2.
  PhysicsDef d = physics_of(Task::kClimb);
  apply_physics_json(
      R"({"environment": {"ground": {"type": "stairs", "rise": 0.01, "run": 0.02, "count": 5,
                                     "at": 0.05}}})",
      "test", d);
  const Model m = block_under(d);
  EXPECT_EQ(m.def.environment, d.environment);  // used as given
  EXPECT_NEAR(score_of(m, centre(), centre() + Vec3(6 * L, 0, 0)), 6.0 + 4 * 2.0, 1e-9);
}

TEST(TerrainTasks, AStillBodyScoresZeroOnItsDefaultGround) {
  for (Task t : {Task::kRough, Task::kClimb, Task::kSlope, Task::kObstacles}) {
    PhysicsDef d = physics_of(t);
    d.gravity = 0;  // nothing moves it
    d.duration = 0.4;
    d.settle_time = 0.1;
    const SimResult r = simulate(block_under(d));
    ASSERT_EQ(r.status, SimStatus::kFinished) << to_string(t);
    EXPECT_EQ(r.com_final, r.com_settled) << to_string(t);
    EXPECT_EQ(r.fitness, 0.0) << to_string(t);
  }
}

// ---- Default environments ----

TEST(TerrainTasks, RoughGroundIsSeededScaledAndAroundTheBody) {
  const Model a = block_under(physics_of(Task::kRough));
  const GroundDef& g = a.def.environment.ground;
  ASSERT_EQ(g.kind, GroundKind::kRough);
  EXPECT_EQ(g.amplitude, 0.25 * L);
  EXPECT_EQ(g.cell, 1 * L);
  EXPECT_EQ(g.seed, 1u);
  // Centred on the footprint, reaching at least 40 L past it.
  EXPECT_NEAR(g.origin[0] + 0.5 * (g.nx - 1) * g.cell, 1.5 * L, 1e-15);
  EXPECT_NEAR(g.origin[1] + 0.5 * (g.ny - 1) * g.cell, 1.0 * L, 1e-15);
  EXPECT_GE(0.5 * (g.nx - 1) * g.cell, 41.5 * L);
  // The same seed gives the same ground, another seed another.
  EXPECT_EQ(block_under(physics_of(Task::kRough)).ground.h, a.ground.h);
  EXPECT_NE(block_under(physics_of(Task::kRough, {{"seed", 2}})).ground.h, a.ground.h);
  // Scaled to the voxel size: the same ground, in voxel lengths, on a body of 2 cm voxels.
  const Model big = compile(block(3, 2, 1, 1e6, 2 * L), physics_of(Task::kRough));
  ASSERT_EQ(big.ground.h.size(), a.ground.h.size());
  for (size_t i = 0; i < a.ground.h.size(); ++i)
    ASSERT_NEAR(big.ground.h[i], 2 * a.ground.h[i], 1e-15);
}

TEST(TerrainTasks, ObstacleFieldLeavesTheStartOpenAndIsSeeded) {
  const Model m = block_under(physics_of(Task::kObstacles));
  const std::vector<ObstacleBox>& boxes = m.def.environment.obstacles;
  EXPECT_GT(boxes.size(), 100u);
  EXPECT_EQ(m.def.environment.ground.kind, GroundKind::kNone);  // on the floor
  for (const ObstacleBox& b : boxes) {
    EXPECT_NEAR(b.max[0] - b.min[0], 1 * L, 1e-15);  // size
    EXPECT_NEAR(b.max[2], 0.5 * L, 1e-15);           // height
    // At least 1 L clear of the footprint [0, 3 L] x [0, 2 L].
    const bool clear =
        b.max[0] <= -1 * L || b.min[0] >= 4 * L || b.max[1] <= -1 * L || b.min[1] >= 3 * L;
    EXPECT_TRUE(clear) << b.min[0] << " " << b.min[1];
  }
  EXPECT_EQ(block_under(physics_of(Task::kObstacles)).def.environment.obstacles, boxes);
  EXPECT_NE(block_under(physics_of(Task::kObstacles, {{"seed", 7}})).def.environment.obstacles,
            boxes);
  // The same field around a bigger body, less the blocks it needs cleared.
  const Model big = compile(block(6, 2, 1, 1e6), physics_of(Task::kObstacles));
  EXPECT_LT(big.def.environment.obstacles.size(), boxes.size());
}

// The parameters' bounds keep every default environment within the environment's own (height
// nodes, boxes) around the widest body a lattice holds (100 sites).
TEST(TerrainTasks, TheLargestDefaultEnvironmentsStayWithinBounds) {
  const RobotDef wide = block(100, 1, 1, 1e6);
  const std::pair<Task, TaskParams> extremes[] = {
      {Task::kRough, {{"cell", 0.25}}},
      {Task::kClimb, {{"count", 20}, {"run", 10}}},
      {Task::kSlope, {{"length", 100}}},
      {Task::kObstacles, {{"spacing", 1}, {"size", 0.25}}},
  };
  for (const auto& [task, params] : extremes)
    EXPECT_NO_THROW(compile(wide, physics_of(task, params))) << to_string(task);
}

TEST(TerrainTasks, AGivenEnvironmentIsUsedAsGiven) {
  for (Task t : {Task::kRough, Task::kClimb, Task::kSlope, Task::kObstacles}) {
    PhysicsDef d = physics_of(t);
    apply_physics_json(R"({"environment": {"ground": {"type": "flat"}}})", "test", d);
    const Model m = block_under(d);
    EXPECT_EQ(m.def.environment, d.environment) << to_string(t);
    EXPECT_EQ(environment_text(d), "given: ground flat");
  }
  EXPECT_EQ(environment_text(physics_of(Task::kWalk)), "flat floor with friction");
  EXPECT_NE(environment_text(physics_of(Task::kClimb, {{"rise", 2}})).find("rise 2"),
            std::string::npos);
}

// ---- Placement on uneven ground ----

// The largest penetration of model m's voxels into its ground at the start, m.
double deepest_start(const Model& m) {
  double deepest = -1;
  for (const Vec3& p : m.rest_pos)
    deepest = std::max(deepest, m.ground.penetration(p.x(), p.y(), p.z(), 0.5 * m.size));
  return deepest;
}

TEST(TerrainTasks, ABlockPlacedOverAStepStartsOnTheStepsHeightAndRestsThere) {
  PhysicsDef d = passive_physics();
  d.duration = 1.5;
  apply_physics_json(R"({"environment": {"ground": {"type": "step", "height": 0.03, "at": -0.1}}})",
                     "test", d);
  const Model m = compile(block(2, 2, 1, 1e8), d);
  for (const Vec3& p : m.rest_pos) EXPECT_NEAR(p.z() - 0.5 * L, 0.03, 1e-15);  // bottom face
  Simulator sim(m);
  testing::run_until(sim, d.duration);
  const double pen = m.mass * -d.gravity / (2 * 1e8 * L);  // what carries each voxel's weight
  for (const Vec3& p : sim.state().pos) EXPECT_NEAR(p.z() - 0.5 * L, 0.03 - pen, 1e-6);
}

TEST(TerrainTasks, ABodyStartsTouchingAnyGroundAndInsideNone) {
  // A step under half the body: it rests on the higher part (its other half hangs).
  const char* grounds[] = {
      R"({"ground": {"type": "step", "height": 0.013, "at": 0.015}})",
      R"({"ground": {"type": "step", "height": -0.02, "at": -0.1}})",
      R"({"ground": {"type": "ramp", "angle_deg": 15, "at": -0.5, "length": 1}})",
      R"({"ground": {"type": "rough", "amplitude": 0.005, "cell": 0.01, "nodes": [9, 9],
                     "origin": [-0.02, -0.02], "seed": 3}})"};
  for (const char* env : grounds) {
    PhysicsDef d = passive_physics();
    apply_physics_json(std::string(R"({"environment": )") + env + "}", "test", d);
    const Model m = compile(block(3, 2, 2, 1e6), d);
    EXPECT_NEAR(deepest_start(m), 0.0, 1e-15) << env;
  }
  // Every task's default ground, too.
  for (Task t : {Task::kRough, Task::kClimb, Task::kSlope, Task::kObstacles})
    EXPECT_NEAR(deepest_start(block_under(physics_of(t))), 0.0, 1e-15) << to_string(t);
  // The flat floor (no environment): the bottom layer on z = 0, as always.
  const Model floor = block_under(passive_physics());
  for (const Vec3& p : floor.rest_pos) EXPECT_EQ(p.z(), 0.5 * L);
}

// ---- Parameters in configs and robot files, and bad ones ----

TEST(TerrainTasks, ParametersReadFromConfigsAndRobotFiles) {
  const std::string head = R"({"format": "plastivox-evolve-config", "version": 1)";
  const evo::EvolveConfig c = evo::parse_config(
      head + R"(, "task": {"name": "climb", "rise": 1, "count": 3}})", "run.json");
  EXPECT_EQ(c.task, Task::kClimb);
  const TaskParams want = {{"count", 3}, {"rise", 1}};
  EXPECT_EQ(c.physics.task_params, want);
  EXPECT_EQ(evo::parse_config(c.canonical_json(), "again").physics.task_params, want);
  EXPECT_NE(c.identity_json().find(R"("task":{"count":3.0,"name":"climb","rise":1.0})"),
            std::string::npos)
      << c.identity_json();
  // The plain name: every default.
  EXPECT_TRUE(evo::parse_config(head + R"(, "task": "rough"})", "run.json").task_params.empty());
  // --task of another task drops the parameters; of the same task keeps them.
  evo::EvolveConfig other = c;
  evo::set_task(other, Task::kClimb);
  EXPECT_EQ(other.physics.task_params, want);
  evo::set_task(other, Task::kSlope);
  EXPECT_TRUE(other.physics.task_params.empty());
  // Robot files: the name alone without parameters, the object with them; both read back.
  const RobotDef r = block(2, 1, 1, 1e6);
  PhysicsDef d = physics_of(Task::kRough);
  EXPECT_NE(robot_to_json(r, &d).find("\"task\": \"rough\""), std::string::npos);
  d.task_params = {{"amplitude", 0.5}};
  const std::string text = robot_to_json(r, &d);
  const auto back = parse_robot_json(text, "r.json");
  EXPECT_EQ(back.physics.task, Task::kRough);
  EXPECT_EQ(back.physics.task_params, d.task_params);
  EXPECT_EQ(evo::resolved_physics_json(d).find("task") != std::string::npos, true);
}

TEST(TerrainTasks, BadTaskDefinitionsAreOneLineNamingTheFileAndField) {
  const std::string head = R"({"format": "plastivox-evolve-config", "version": 1, )";
  const struct {
    std::string body, error;
  } bad[] = {
      {R"("task": {"name": "climb", "height": 2})",
       "run.json: task.height: unknown parameter of climb (use rise, run, count, height_weight)"},
      {R"("task": {"name": "jump", "rise": 2})",
       "run.json: task.rise: unknown parameter of jump (it has none)"},
      {R"("task": {"name": "climb", "rise": -1})",
       "run.json: task.rise: must be in [0.05, 5] voxel lengths"},
      {R"("task": {"name": "slope", "angle_deg": 60})",
       "run.json: task.angle_deg: must be in [0, 45] degrees"},
      {R"("task": {"name": "climb", "count": 2.5})",
       "run.json: task.count: must be a whole number"},
      {R"("task": {"name": "rough", "seed": "x"})", "run.json: task.seed: expected a number"},
      {R"("task": {"name": "rough", "amplitude": 1}, "physics": {"environment": {"ground":
           {"type": "flat"}}})",
       "run.json: task.amplitude: shapes the task's default environment, which "
       "physics.environment replaces (give one or the other)"},
      {R"("task": "slope", "physics": {"floor": false})",
       "run.json: physics.floor: task slope needs the floor (its ground lies on it)"},
  };
  for (const auto& b : bad)
    EXPECT_EQ(error_of([&] { evo::parse_config(head + b.body + "}", "run.json"); }), b.error)
        << b.body;
  // A fitness parameter goes with a given environment.
  EXPECT_NO_THROW(evo::parse_config(
      head + R"("task": {"name": "climb", "height_weight": 2}, "physics": {"environment":
           {"ground": {"type": "step", "height": 0.01, "at": 0.05}}}})",
      "run.json"));
  // In a robot file the task is a physics field.
  PhysicsDef d = physics_of(Task::kObstacles);
  std::string text = robot_to_json(block(1, 1, 1, 1e6), &d);
  const std::string name = "\"task\": \"obstacles\"";
  ASSERT_NE(text.find(name), std::string::npos);
  text.replace(text.find(name), name.size(), R"("task": {"name": "obstacles", "spacing": 0})");
  EXPECT_EQ(error_of([&] { parse_robot_json(text, "r.json"); }),
            "r.json: physics.task.spacing: must be in [1, 20] voxel lengths");
}

// One experiment preset per task (assets/presets/experiment-<task>.json), on its default
// environment.
// The baselines of docs/tasks.md are these presets: one budget for every task.
TEST(TerrainTasks, EveryTaskHasAnExperimentPreset) {
  for (const TaskInfo& t : all_tasks()) {
    const experiment::ExperimentConfig c = experiment::preset_config(t.name);
    const evo::EvolveConfig run = c.run_config(Treatment::kStress, 1);
    EXPECT_EQ(run.physics.task, t.task) << t.name;
    EXPECT_FALSE(run.physics.environment.active()) << t.name;  // the task's own
    EXPECT_EQ(c.treatments.size(), 3u);
    EXPECT_EQ(c.seeds, (std::vector<std::uint64_t>{1, 2, 3})) << t.name;
    EXPECT_EQ(run.population, 12) << t.name;
    EXPECT_EQ(run.generations, 24) << t.name;
    EXPECT_EQ(run.controller.kind, ControllerKind::kSine) << t.name;
  }
  // The controller study (docs/control.md): the same runs with the distributed controller.
  for (const char* name : {"walk", "rough"}) {
    const experiment::ExperimentConfig sine = experiment::preset_config(name);
    const experiment::ExperimentConfig net =
        experiment::preset_config(std::string(name) + "-distributed");
    const evo::EvolveConfig a = sine.run_config(Treatment::kPressure, 2);
    const evo::EvolveConfig b = net.run_config(Treatment::kPressure, 2);
    EXPECT_EQ(b.controller.kind, ControllerKind::kDistributed) << name;
    EXPECT_EQ(sine.seeds, net.seeds) << name;
    EXPECT_EQ(a.population, b.population) << name;
    EXPECT_EQ(a.generations, b.generations) << name;
    EXPECT_EQ(a.physics.task, b.physics.task) << name;
  }
}

class TerrainTasksCli : public testing::ScratchDirTest {
 protected:
};

TEST_F(TerrainTasksCli, BadTaskIsOneLineAndANonZeroExit) {
  const std::string cfg = write("run.json", R"({"format": "plastivox-evolve-config",
      "version": 1, "task": {"name": "climb", "rise": 99}})");
  Output o = cli("evolve --config " + cfg + " --out " + path("run.h5"));
  EXPECT_EQ(o.status, 1);
  EXPECT_EQ(o.out, "plastivox evolve: error: " + cfg +
                       ": task.rise: must be in [0.05, 5] voxel lengths\n");
  o = cli(R"(simulate --duration 0.1 --physics '{"task": {"name": "rough", "cell": 0}}')");
  EXPECT_EQ(o.status, 1);
  EXPECT_EQ(o.out,
            "plastivox simulate: error: --physics: physics.task.cell: must be in [0.25, 10] voxel "
            "lengths\n");
}

TEST_F(TerrainTasksCli, SimulateNamesTheTaskAndScoresOnItsGround) {
  const nlohmann::json j = testing::cli_json("simulate --task rough --duration 0.6 --json");
  EXPECT_EQ(j.at("task"), "rough");
  EXPECT_EQ(j.at("fitness_unit"), "voxel lengths");
  // The ground is not the floor's: the life differs. (On slope's or climb's default, a body
  // that stays on the level ground around its start lives the floor's life, bit for bit.)
  EXPECT_NE(testing::cli_json("simulate --duration 0.6 --json").at("final_state_hash"),
            j.at("final_state_hash"));
}

TEST_F(TerrainTasksCli, EvolutionRecordsTheTaskWithItsParameters) {
  const std::string cfg = write("run.json", R"({"format": "plastivox-evolve-config",
      "version": 1, "seed": 3, "treatment": "stress", "population": 3, "generations": 1,
      "task": {"name": "climb", "rise": 0.25},
      "lattice": {"nx": 3, "ny": 3, "nz": 3}, "physics": {"duration": 0.3, "settle_time": 0.1}})");
  const std::string out = path("climb.h5");
  const Output o = cli("evolve --config " + cfg + " --out " + out + " --threads 1");
  ASSERT_EQ(o.status, 0) << o.out;
  // What the analysis re-simulates champions with (study_load.cpp: the run's config physics).
  const evo::ResultsFile f = evo::read_results(out);
  EXPECT_EQ(f.state.config.physics.task, Task::kClimb);
  const TaskParams want = {{"rise", 0.25}};
  EXPECT_EQ(f.state.config.physics.task_params, want);
  // Climb's criterion reads the ground under the centre of mass, which the file does not keep.
  EXPECT_TRUE(testing::cli_json("inspect " + out + " --json").at("champion_success").is_null());
  // The analysis names the task and its environment, in the report and stats.json.
  const Output a = cli("analyze " + out + " --out " + path("analysis"));
  ASSERT_EQ(a.status, 0) << a.out;
  const std::string env =
      "the default of climb: terraces: count steps of height rise, one every run, rising away from "
      "the start every way (rise 0.25, run 3, count 8; lengths in voxel lengths)";
  const nlohmann::json stats =
      nlohmann::json::parse(testing::file_text(path("analysis/stats.json")));
  EXPECT_EQ(stats.at("audit").at("task"), "climb");
  EXPECT_EQ(stats.at("audit").at("environment"), env);
  const std::string report = testing::file_text(path("analysis/report.html"));
  EXPECT_NE(report.find("The task is <b>climb</b>, on the default of climb: terraces"),
            std::string::npos);
}

}  // namespace
}  // namespace plastivox
