// A snapshot resumes the score as well as the physics (the watches are rows of the State:
// floor_deepest, floor_deep_most, task_values, task_layout; the signal and the controller's
// memory too), and Simulator::result() gives a life's SimResult at any point: the same bits
// as simulate() of the same life, mid-life (a life simulate() ends at a frame time) and at
// the end.
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "plastivox/demo_robots.hpp"
#include "plastivox/simulator.hpp"
#include "plastivox/task.hpp"
#include "test_support.hpp"

namespace plastivox {
namespace {

// The demo walker under `task`, developing under stress, 0.8 s (0.6 s of walking).
Model walker_under(Task task, const ControllerDef& controller = {}) {
  PhysicsDef d = preset_gecco2018_code();
  d.treatment = Treatment::kStress;
  d.duration = 0.8;
  d.task = task;
  RobotDef robot = demo_walker();
  robot.controller = controller;
  return compile(robot, d);
}

// Everything of a SimResult but the recording and the wall time, bit for bit.
void expect_same(const SimResult& a, const SimResult& b, const std::string& what) {
  EXPECT_EQ(a.status, b.status) << what;
  EXPECT_EQ(a.failure, b.failure) << what;
  EXPECT_EQ(a.fitness, b.fitness) << what;
  EXPECT_EQ(a.displacement, b.displacement) << what;
  EXPECT_EQ(a.com_settled, b.com_settled) << what;
  EXPECT_EQ(a.com_final, b.com_final) << what;
  EXPECT_EQ(a.voxels, b.voxels) << what;
  EXPECT_EQ(a.steps, b.steps) << what;
  EXPECT_EQ(a.dt_initial, b.dt_initial) << what;
  EXPECT_EQ(a.dt_final, b.dt_final) << what;
  EXPECT_EQ(a.sim_time, b.sim_time) << what;
  EXPECT_EQ(a.final_stiffness, b.final_stiffness) << what;
  EXPECT_EQ(a.stiffness_change_mean, b.stiffness_change_mean) << what;
  EXPECT_EQ(a.stiffness_change_abs_mean, b.stiffness_change_abs_mean) << what;
  EXPECT_EQ(a.stiffness_change_var, b.stiffness_change_var) << what;
  EXPECT_EQ(a.final_state_hash, b.final_state_hash) << what;
  EXPECT_EQ(a.floor_health, b.floor_health) << what;
  EXPECT_EQ(a.floor_depth, b.floor_depth) << what;
  EXPECT_EQ(a.voxels_deep_max, b.voxels_deep_max) << what;
  EXPECT_EQ(a.voxels_below_floor, b.voxels_below_floor) << what;
  EXPECT_EQ(a.sank, b.sank) << what;
  EXPECT_EQ(a.vertical_share, b.vertical_share) << what;
  EXPECT_EQ(a.settled, b.settled) << what;
  EXPECT_EQ(a.warnings, b.warnings) << what;
}

// Saves the life of m at `save_at` s, restores the snapshot into a new Simulator (which had
// stepped a life of its own first, to be overwritten) and finishes it there: the result is
// simulate()'s, bit for bit. Returns the Simulator the snapshot was saved from, at the save.
Simulator expect_resumes(const Model& m, double save_at, const std::string& what) {
  const SimResult whole = simulate(m);
  EXPECT_EQ(whole.status, SimStatus::kFinished) << what << ": " << whole.failure;
  EXPECT_GT(whole.fitness, 0) << what;
  Simulator first(m);
  testing::run_until(first, save_at);
  const std::vector<uint8_t> snapshot = first.save_state();
  Simulator second(m);
  testing::run_until(second, 0.1);
  second.restore_state(snapshot);
  while (second.state().status == SimStatus::kRunning) second.step();
  expect_same(second.result(), whole, what);
  return first;
}

TEST(ResumeScore, EveryTaskFinishesFromASnapshotWithSimulatesFitnessAndFloorHealth) {
  for (Task task : {Task::kWalk, Task::kJump, Task::kTurn, Task::kClimb, Task::kCarry}) {
    const Model m = walker_under(task);
    const Simulator at_save = expect_resumes(m, 0.5, to_string(task));
    // The score was under way when saved: the watches had seen the floor and, for the tasks
    // that keep running values, the task.
    EXPECT_GT(at_save.state().floor_deepest, 0) << to_string(task);
    const TaskValues& v = at_save.state().task_values;
    if (task == Task::kJump) {
      EXPECT_GT(v[0], 0);  // the highest rise
    } else if (task == Task::kTurn) {
      EXPECT_EQ(v[0], 1);  // the layout taken
    } else if (task == Task::kCarry) {
      EXPECT_EQ(v[1], 1);  // carrying
    }
  }
}

// A weight for every input of a distributed network, small and fixed.
ControllerDef distributed() {
  ControllerDef c;
  c.kind = ControllerKind::kDistributed;
  c.hidden = 2;
  const int count = weight_count(c.kind, c.hidden);
  for (int k = 0; k < count; ++k) c.weights.push_back(0.8 * std::sin(1.7 * k + 0.3));
  return c;
}

TEST(ResumeScore, TheDistributedControllersMemoryResumesWithTheLife) {
  const Model m = walker_under(Task::kWalk, distributed());
  const Simulator at_save = expect_resumes(m, 0.5, "distributed");
  // Its signals in flight were in the snapshot, and not all zero.
  double sent = 0;
  for (double v : at_save.state().control_memory) sent += std::abs(v);
  EXPECT_GT(sent, 0);
}

// result() mid-life is simulate()'s for a life ended there (by frame_times), and at the
// end simulate()'s whole life.
TEST(ResumeScore, ResultMidLifeAndAtTheEndIsSimulates) {
  for (Task task : {Task::kWalk, Task::kJump, Task::kCarry}) {
    const Model m = walker_under(task);
    Simulator sim(m);
    for (double t : {0.1, 0.45}) {
      SimOptions o;
      o.frame_times = {t};
      o.on_frame = [](const State&, Frame&&) { return true; };
      const SimResult early = simulate(m, o);
      testing::run_until(sim, t);
      const SimResult now = sim.result();
      EXPECT_EQ(now.status, SimStatus::kRunning);
      expect_same(now, early, std::string(to_string(task)) + " at " + std::to_string(t));
    }
    EXPECT_GT(sim.result().fitness, 0) << to_string(task) << ": a score so far";
    while (sim.state().status == SimStatus::kRunning) sim.step();
    expect_same(sim.result(), simulate(m), std::string(to_string(task)) + " at the end");
  }
}

}  // namespace
}  // namespace plastivox
