// The rules outside the core (plastivox/rules/life_rules.hpp): the core measures a life,
// judge_life decides whether it counts, and every front end asks it. The sunk life is the
// champion of tests/data/results/old-rule-sinker.h5 (tests/data/results/README.md), a soft,
// heavy 3x3x3 body that falls through the floor.
#include <string>

#include <nlohmann/json.hpp>

#include "plastivox/evo/champion.hpp"
#include "plastivox/evo/evolver.hpp"
#include "plastivox/evo/results_file.hpp"
#include "plastivox/io/robot_file.hpp"
#include "plastivox/rules/life_rules.hpp"
#include "test_support.hpp"

namespace plastivox {
namespace {

using nlohmann::json;

class LifeRules : public testing::ScratchDirTest {};

TEST_F(LifeRules, ASunkLifeGetsOneVerdictFromSimulateEvolutionAndTheRule) {
  const std::string file = testing::data_dir() + "/results/old-rule-sinker.h5";
  const evo::RunState run = evo::read_results(file).state;
  const RobotDef robot = evo::champion_robot(evo::champion_at(run, -1, file), run.generations_done);
  for (const bool invalid : {true, false}) {
    PhysicsDef physics = run.config.physics;
    physics.sinking_invalid = invalid;
    // The core measures the life to its end, whatever the rule: finished, sunk, scored.
    SimResult life = simulate(compile(robot, physics));
    ASSERT_EQ(life.status, SimStatus::kFinished) << life.failure;
    ASSERT_TRUE(life.sank);
    const double measured = life.fitness;
    ASSERT_GT(measured, 1.0);
    judge_life(physics, life);
    EXPECT_EQ(life.status, invalid ? SimStatus::kUnstable : SimStatus::kFinished) << invalid;
    EXPECT_EQ(life.fitness, invalid ? 0.0 : measured);
    if (invalid) {
      EXPECT_NE(life.failure.find("sunk lives are invalid: physics.sinking_invalid"),
                std::string::npos)
          << life.failure;
    }

    // Evolution's evaluation: failed with the same reason, or scored the same.
    evo::Phenotype body;
    body.robot = robot;
    body.valid = true;
    const evo::Evaluation e = evo::evaluate_phenotype(body, physics);
    EXPECT_TRUE(e.sank);
    EXPECT_EQ(e.status, invalid ? evo::EvalStatus::kUnstable : evo::EvalStatus::kOk) << invalid;
    EXPECT_EQ(e.status == evo::EvalStatus::kOk ? e.fitness : 0.0, life.fitness);
    EXPECT_EQ(e.failure, life.failure);

    // plastivox simulate: its exit status, status, fitness and failure.
    write_robot_file(path("sinker.json"), robot, &physics);
    const testing::Output o = testing::shell(std::string(PLASTIVOX_CLI) + " simulate " +
                                             path("sinker.json") + " --json 2>/dev/null");
    EXPECT_EQ(o.status, invalid ? 3 : 0) << o.out;
    const json j = json::parse(o.out);
    EXPECT_EQ(j.at("status"), to_string(life.status));
    EXPECT_EQ(j.at("health"), "sank");
    EXPECT_EQ(j.at("fitness").get<double>(), life.fitness);
    EXPECT_EQ(j.value("failure", ""), life.failure);
  }
}

TEST_F(LifeRules, TheVerticalRuleFlagsOnlyAFinishedWalkScoredIn3D) {
  PhysicsDef walk;  // walk, 3-D fitness
  SimResult r;
  r.status = SimStatus::kFinished;
  r.displacement = Vec3(0.1, 0, -0.5);
  r.vertical_share = 0.96;
  EXPECT_TRUE(vertical_exploit(walk, r));
  SimResult warned = r;
  judge_life(walk, warned);
  ASSERT_EQ(warned.warnings.size(), 1u);
  EXPECT_TRUE(warned.warnings[0].starts_with("fitness owes too much to vertical motion"));
  EXPECT_EQ(warned.status, SimStatus::kFinished);
  PhysicsDef xy = walk;
  xy.fitness = FitnessMode::kXY;
  EXPECT_FALSE(vertical_exploit(xy, r));
  SimResult sunk = r;
  sunk.sank = true;  // a fall through the floor is judged as sinking, not as vertical
  EXPECT_FALSE(vertical_exploit(walk, sunk));
  r.displacement = Vec3(0.01, 0, -0.1);  // too small a rise to say
  EXPECT_FALSE(vertical_exploit(walk, r));
}

}  // namespace
}  // namespace plastivox
