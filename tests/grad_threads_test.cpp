// The gradient's backward pass on threads (engine/grad, docs/gradients.md, "Threads"): on two
// threads a helper recomputes the segment before while the caller sweeps one, and every
// array comes out with the same bits as on one thread. The forward life is returned, as
// simulate() gives it, for the caller to judge instead of simulating it again.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "plastivox/control.hpp"
#include "plastivox/demo_robots.hpp"
#include "plastivox/grad/gradient.hpp"
#include "plastivox/simulator.hpp"
#include "test_support.hpp"

namespace plastivox {
namespace {

using grad::Gradient;

PhysicsDef short_life(double duration, double settle, Treatment treatment) {
  PhysicsDef def;
  def.duration = duration;
  def.settle_time = settle;
  def.treatment = treatment;
  return def;
}

bool same_bits(const std::vector<double>& a, const std::vector<double>& b) {
  return a.size() == b.size() &&
         (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0);
}
bool same_bits(double a, double b) {
  return std::memcmp(&a, &b, sizeof a) == 0;
}

Gradient on_threads(const Model& m, int threads, int checkpoint_every) {
  grad::GradientOptions o;
  o.threads = threads;
  o.checkpoint_every = checkpoint_every;
  return grad::gradient(m, o);
}

// Every array of the gradient, bit for bit, on 1 and 2 threads, with the spacing chosen and
// with short segments (many handed between the threads, and an odd count).
void expect_same_on_1_and_2_threads(const Model& m) {
  for (int every : {0, 7}) {
    SCOPED_TRACE("checkpoint_every " + std::to_string(every));
    const Gradient a = on_threads(m, 1, every), b = on_threads(m, 2, every);
    EXPECT_EQ(a.threads, 1);
    EXPECT_EQ(b.threads, 2);  // the pipeline ran
    EXPECT_GT(b.checkpoints, 2u);
    EXPECT_TRUE(same_bits(a.fitness, b.fitness));
    EXPECT_EQ(a.final_state_hash, b.final_state_hash);
    EXPECT_TRUE(same_bits(a.stiffness, b.stiffness));
    EXPECT_TRUE(same_bits(a.phase, b.phase));
    EXPECT_TRUE(same_bits(a.dev_rate, b.dev_rate));
    EXPECT_TRUE(same_bits(a.initial_position, b.initial_position));
    EXPECT_TRUE(same_bits(a.initial_velocity, b.initial_velocity));
    EXPECT_TRUE(same_bits(a.initial_orientation, b.initial_orientation));
    EXPECT_TRUE(same_bits(a.initial_angular_velocity, b.initial_angular_velocity));
    EXPECT_TRUE(same_bits(a.act_gain, b.act_gain));
    EXPECT_TRUE(same_bits(a.controller_weights, b.controller_weights));
    EXPECT_TRUE(same_bits(a.amplitude, b.amplitude));
    EXPECT_EQ(a.peak_tape_nodes, b.peak_tape_nodes);
    // Not all zero: the comparison compares something.
    double norm = 0;
    for (double d : a.phase) norm += d * d;
    EXPECT_GT(norm, 0.0);
  }
}

TEST(GradientThreads, TheWalkerGivesTheSameBitsOn1And2Threads) {
  expect_same_on_1_and_2_threads(compile(demo_walker(), short_life(0.08, 0.02, Treatment::kNone)));
}

// Self-contacts (contact at Voxelyze 0.9's 3 mean sizes: many pairs touch): the replica's
// candidate lists are kept from segment to segment, and on two threads each of two replicas sees
// every other segment, yet the candidates, and so the bits, are the same.
TEST(GradientThreads, SelfContactsGiveTheSameBitsOn1And2Threads) {
  PhysicsDef def = short_life(0.08, 0.02, Treatment::kNone);
  def.contact_diameter = 3;
  const Model m = compile(demo_walker(), def);
  EXPECT_GT(plastivox::testing::self_contacts_of(m), 1000);
  expect_same_on_1_and_2_threads(m);
}

// Development under stress, with a distributed network (its weights' sums cross segments too).
TEST(GradientThreads, ADevelopingBodyUnderStressGivesTheSameBitsOn1And2Threads) {
  RobotDef r = demo_walker();
  r.controller.kind = ControllerKind::kDistributed;
  r.controller.hidden = 2;
  for (int k = 0; k < weight_count(r.controller.kind, r.controller.hidden); ++k)
    r.controller.weights.push_back(0.8 * std::sin(1.3 * k + 0.7));
  const Model m = compile(r, short_life(0.06, 0.02, Treatment::kStress));
  expect_same_on_1_and_2_threads(m);
  double norm = 0;
  for (double d : on_threads(m, 1, 0).dev_rate) norm += d * d;
  EXPECT_GT(norm, 0.0);
}

// Under bond_model voxelyze09 every bond takes the scalar path, recorded on the tape.
TEST(GradientThreads, Voxelyze09GivesTheSameBitsOn1And2Threads) {
  PhysicsDef def = short_life(0.1, 0.02, Treatment::kStress);
  def.bond_model = BondModel::kVoxelyze09;
  RobotDef cube = demo_cube(4, 1e8);
  for (int v = 0; v < cube.sites(); ++v) cube.stiffness[v] *= 1.5 + std::sin(1.7 * v + 0.3);
  expect_same_on_1_and_2_threads(compile(cube, def));
}

// The second thread keeps a second segment's tape: the plan counts it, and takes one thread
// when only that tape would pass the memory limit.
TEST(GradientThreads, ThePlanCountsTheSecondTapeAndFallsBackToOneThread) {
  const Model m = compile(demo_walker(), short_life(0.1, 0.02, Treatment::kNone));
  grad::GradientOptions one, two;
  one.threads = 1;
  two.threads = 2;
  const grad::Plan p1 = grad::plan(m, one), p2 = grad::plan(m, two);
  EXPECT_EQ(p1.threads, 1);
  EXPECT_EQ(p2.threads, 2);
  EXPECT_EQ(p1.checkpoint_every, p2.checkpoint_every);  // the same segments: the same bits
  EXPECT_GT(p1.thread_bytes, p1.checkpoint_every * p1.tape_bytes_per_step);
  EXPECT_DOUBLE_EQ(p2.estimated_bytes, p1.estimated_bytes + p1.thread_bytes);
  two.memory_limit = p1.estimated_bytes + 0.5 * p1.thread_bytes;
  EXPECT_EQ(grad::plan(m, two).threads, 1);
  EXPECT_EQ(grad::gradient(m, two).threads, 1);
  two.threads = -1;
  EXPECT_THROW(grad::plan(m, two), std::invalid_argument);
}

// The forward life is simulate()'s summary, bit for bit, so a caller judges it instead of
// simulating the life again.
TEST(GradientThreads, TheForwardLifeIsSimulatesResult) {
  for (Treatment t : {Treatment::kNone, Treatment::kStress}) {
    const Model m = compile(demo_walker(), short_life(0.08, 0.02, t));
    const SimResult r = simulate(m);
    for (int threads : {1, 2}) {
      const Gradient g = on_threads(m, threads, 0);
      EXPECT_TRUE(same_bits(g.life.fitness, r.fitness));
      EXPECT_TRUE(same_bits(g.fitness, r.fitness));
      EXPECT_EQ(g.life.status, r.status);
      EXPECT_EQ(g.life.final_state_hash, r.final_state_hash);
      EXPECT_EQ(g.life.steps, r.steps);
      EXPECT_EQ(g.life.sank, r.sank);
      EXPECT_EQ(g.life.floor_health, r.floor_health);
      EXPECT_TRUE(same_bits(g.life.vertical_share, r.vertical_share));
      EXPECT_TRUE(same_bits(g.life.dt_initial, r.dt_initial));
      EXPECT_TRUE(same_bits(g.life.final_stiffness, r.final_stiffness));
      for (int k = 0; k < 3; ++k) EXPECT_TRUE(same_bits(g.life.displacement[k], r.displacement[k]));
    }
  }
}

// A judge that says the life does not count: no backward pass, the judged life returned.
TEST(GradientThreads, ALifeTheJudgeRejectsHasNoBackwardPass) {
  const Model m = compile(demo_walker(), short_life(0.08, 0.02, Treatment::kNone));
  grad::GradientOptions o;
  int judged = 0;
  o.judge = [&judged](SimResult& r) {
    ++judged;
    r.status = SimStatus::kUnstable;
    r.failure = "rejected";
    r.fitness = 0;
  };
  const Gradient g = grad::gradient(m, o);
  EXPECT_EQ(judged, 1);
  EXPECT_EQ(g.life.status, SimStatus::kUnstable);
  EXPECT_EQ(g.life.failure, "rejected");
  EXPECT_EQ(g.fitness, 0.0);
  EXPECT_TRUE(g.stiffness.empty());
  EXPECT_TRUE(g.phase.empty());
  EXPECT_EQ(g.peak_tape_nodes, 0u);
  EXPECT_GT(g.steps, 0);
}

}  // namespace
}  // namespace plastivox
