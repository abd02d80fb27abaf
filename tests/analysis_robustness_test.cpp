// Robustness R = F_test / F_train with short lives: the no-randomness control, reproducibility
// by seed, independence from the thread count, and removal of development.
#include <cmath>

#include "plastivox/analysis/robustness.hpp"
#include "plastivox/rules/life_rules.hpp"
#include "plastivox/task.hpp"
#include "test_support.hpp"

namespace plastivox::analysis {
namespace {

// A small walker: a 4x3x2 block with a phase gradient along x, uniform stiffness E.
RobotDef walker(double E) {
  RobotDef r = testing::block(4, 3, 2, E);
  for (int z = 0; z < 2; ++z)
    for (int y = 0; y < 3; ++y)
      for (int x = 0; x < 4; ++x) {
        r.phase[r.site(x, y, z)] = 0.25 * x;
        r.dev_rate[r.site(x, y, z)] = 5.0;  // development that must be removed
      }
  return r;
}

PhysicsDef short_life() {
  PhysicsDef p = preset_gecco2018_code();
  p.treatment = Treatment::kStress;
  p.duration = 0.6;  // 0.2 s settling + 0.4 s of walking: two actuation cycles
  return p;
}

TEST(Robustness, ForcedSameStiffnessGivesROfOne) {
  const double E = 1e8;
  RobustnessOptions o;
  o.draws = 3;
  o.e_lo = o.e_hi = E;  // every "random" voxel gets the evolved value
  const RobustnessResult r = robustness(walker(E), short_life(), o);
  ASSERT_TRUE(r.train_valid) << r.train_failure;
  EXPECT_GT(r.f_train, 0.0);
  ASSERT_EQ(r.draws.size(), 3u);
  for (const RobustnessDraw& d : r.draws) {
    EXPECT_TRUE(d.valid) << d.failure;
    EXPECT_NEAR(d.r, 1.0, 1e-12);
  }
  EXPECT_EQ(r.valid_draws, 3);
  EXPECT_NEAR(r.mean_r, 1.0, 1e-12);
  EXPECT_EQ(r.e_lo, E);
  EXPECT_EQ(r.distribution, "uniform");
}

TEST(Robustness, FTrainIsTheFitnessWithoutDevelopment) {
  const RobotDef robot = walker(1e8);
  RobustnessOptions o;
  o.draws = 1;
  const RobustnessResult r = robustness(robot, short_life(), o);
  PhysicsDef none = short_life();
  none.treatment = Treatment::kNone;
  EXPECT_EQ(r.f_train, simulate(compile(robot, none)).fitness);
  EXPECT_EQ(without_development(robot).dev_rate, std::vector<double>(robot.sites(), 0.0));
  EXPECT_EQ(robustness_physics(short_life()).treatment, Treatment::kNone);
}

// A life's fitness as evolution judged it (a sunk life counts 0 under sinking_invalid).
double judged_fitness(const Model& m) {
  SimResult r = simulate(m);
  judge_life(m.def, r);
  return r.fitness;
}

// Every task: the champion is re-simulated under its own task, parameters and so environment
// (the terrain tasks' default grounds are made from them, plastivox/task.hpp), each draw too.
TEST(Robustness, UsesTheChampionsTaskAndEnvironment) {
  const RobotDef robot = walker(1e8);
  for (const TaskInfo& t : all_tasks()) {
    PhysicsDef p = short_life();
    p.task = t.task;
    if (t.task == Task::kClimb) p.task_params = {{"rise", 0.25}};
    RobustnessOptions o;
    o.draws = 2;
    const RobustnessResult r = robustness(robot, p, o);
    const PhysicsDef none = robustness_physics(p);
    EXPECT_EQ(none.task, t.task);
    EXPECT_EQ(none.task_params, p.task_params);
    const Model trained = compile(without_development(robot), none);
    EXPECT_EQ(trained.terrain, t.environment != nullptr) << t.name;
    EXPECT_EQ(r.f_train, judged_fitness(trained)) << t.name;
    const RobotDef drawn = robustness_draw(robot, p, o, 1);
    EXPECT_EQ(r.draws[1].f_test, judged_fitness(compile(drawn, none))) << t.name;
  }
}

TEST(Robustness, DrawsAreReproducibleBySeedAndIndependentOfThreads) {
  const RobotDef robot = walker(1e8);
  RobustnessOptions o;
  o.draws = 4;
  o.seed = 5;
  o.e_lo = 1e7;  // a narrow range keeps the short test stable and fast
  o.e_hi = 1e9;
  o.threads = 1;
  const RobustnessResult one = robustness(robot, short_life(), o);
  o.threads = 3;
  const RobustnessResult three = robustness(robot, short_life(), o);
  ASSERT_EQ(one.draws.size(), 4u);
  for (int k = 0; k < 4; ++k) {
    EXPECT_EQ(one.draws[k].f_test, three.draws[k].f_test) << "draw " << k;
    EXPECT_TRUE(one.draws[k].valid) << one.draws[k].failure;
  }
  EXPECT_NE(one.draws[0].f_test, one.draws[1].f_test);  // different fields per draw
  o.seed = 6;
  const RobustnessResult other = robustness(robot, short_life(), o);
  EXPECT_NE(other.draws[0].f_test, one.draws[0].f_test);
  // Log-uniform draws are another distribution.
  o.seed = 5;
  o.distribution = StiffnessDistribution::kLogUniform;
  const RobustnessResult log = robustness(robot, short_life(), o);
  EXPECT_EQ(log.distribution, "log-uniform");
  EXPECT_NE(log.draws[0].f_test, one.draws[0].f_test);
}

TEST(Robustness, DrawnStiffnessLiesInTheRangeAndFollowsTheDistribution) {
  // A full 10^3 body gives 1000 values per draw.
  const RobotDef robot = testing::block(10, 10, 10, 1e8);
  const PhysicsDef phys = preset_gecco2018_code();  // E in [1e5, 1e11]
  RobustnessOptions o;
  std::vector<double> lin, log;
  for (int k = 0; k < 3; ++k) {
    const RobotDef d = robustness_draw(robot, phys, o, k);
    for (double e : d.stiffness) lin.push_back(e);
    EXPECT_EQ(d.dev_rate, std::vector<double>(robot.sites(), 0.0));
  }
  o.distribution = StiffnessDistribution::kLogUniform;
  for (int k = 0; k < 3; ++k)
    for (double e : robustness_draw(robot, phys, o, k).stiffness) log.push_back(e);
  int lin_below_mid = 0, log_below_geo = 0;
  for (size_t i = 0; i < lin.size(); ++i) {
    ASSERT_GE(lin[i], 1e5);
    ASSERT_LT(lin[i], 1e11);
    ASSERT_GE(log[i], 1e5);
    ASSERT_LT(log[i], 1e11 * (1 + 1e-12));
    lin_below_mid += lin[i] < 0.5e11;
    log_below_geo += log[i] < 1e8;
  }
  // Half the linear draws fall below the arithmetic midpoint, half the log-uniform ones below
  // the geometric midpoint (3000 draws: +-5 % is over 5 standard deviations).
  EXPECT_NEAR(lin_below_mid / 3000.0, 0.5, 0.05);
  EXPECT_NEAR(log_below_geo / 3000.0, 0.5, 0.05);
  // Same key, same field.
  EXPECT_EQ(robustness_draw(robot, phys, o, 2).stiffness,
            robustness_draw(robot, phys, o, 2).stiffness);
}

TEST(Robustness, RejectsBadOptions) {
  RobustnessOptions o;
  o.draws = 0;
  EXPECT_THROW(robustness(walker(1e8), short_life(), o), std::invalid_argument);
  o.draws = 1;
  o.e_lo = 1e9;
  o.e_hi = 1e8;
  EXPECT_THROW(robustness(walker(1e8), short_life(), o), std::invalid_argument);
}

}  // namespace
}  // namespace plastivox::analysis
