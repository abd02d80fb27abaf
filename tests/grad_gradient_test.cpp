// Reverse-mode gradients of a life (engine/grad, docs/gradients.md): the forward pass is the
// engine's life bit for bit, the replica that the backward pass records is the engine's life
// bit for bit, and the gradient agrees with central differences of simulate()'s fitness.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <string>
#include <vector>

#include "plastivox/control.hpp"
#include "plastivox/demo_robots.hpp"
#include "plastivox/grad/gradient.hpp"
#include "plastivox/simulator.hpp"
#include "plastivox/task.hpp"
#include "test_support.hpp"

namespace plastivox {
namespace {

using grad::Gradient;
using plastivox::testing::error_of;
using plastivox::testing::RelNear;
using plastivox::testing::self_contacts_of;

// A short life with actuation: settling ends early so the phases matter.
PhysicsDef short_life(double duration, double settle, Treatment treatment = Treatment::kNone) {
  PhysicsDef def;
  def.duration = duration;
  def.settle_time = settle;
  def.treatment = treatment;
  return def;
}

// A 3x3x3 body with distinct stiffness (one stiffest voxel), phases and development rates.
RobotDef cube3() {
  RobotDef r = make_empty_robot(3, 3, 3);
  r.name = "cube3";
  for (int s = 0; s < r.sites(); ++s) {
    r.present[s] = 1;
    r.stiffness[s] = 1e8 * (1.5 + std::sin(1.7 * s + 0.3));
    r.phase[s] = 0.37 * std::sin(0.9 * s) + 0.05 * s;
    r.dev_rate[s] = 2.0 + std::cos(1.3 * s);
  }
  return r;
}

// One kind of parameter of a Model: how to nudge it, and its gradient.
struct Param {
  std::string name;
  int index;
  double value;
  std::function<void(Model&, double)> nudge;  // adds h
  double gradient;
};

std::vector<Param> params_of(const Model& m, const Gradient& g, const std::vector<int>& voxels,
                             bool dev_rate) {
  std::vector<Param> out;
  for (int i : voxels) {
    out.push_back(
        {"stiffness", i, m.e0[i], [i](Model& x, double h) { x.e0[i] += h; }, g.stiffness[i]});
    out.push_back(
        {"phase", i, m.phase[i], [i](Model& x, double h) { x.phase[i] += h; }, g.phase[i]});
    if (dev_rate)
      out.push_back(
          {"dev_rate", i, m.alpha[i], [i](Model& x, double h) { x.alpha[i] += h; }, g.dev_rate[i]});
  }
  out.push_back({"amplitude", -1, m.def.act_amplitude,
                 [](Model& x, double h) {
                   x.def.act_amplitude += h;
                   x.act_amplitude_xi += h;
                   x.act_amplitude_max += h;
                 },
                 g.amplitude});
  return out;
}

// Central differences of simulate()'s fitness, Richardson-extrapolated: D(h) has error
// c2 h^2 + c4 h^4, so (4 D(h/2) - D(h)) / 3 has error O(h^4), and h can be large enough that
// rounding (~1e-16 of the fitness, over 2h) stays far below 1e-6 of the derivative.
// `smooth` says whether all four nudged lives took the branches the life itself took
// (replicate_life's event signature): otherwise the difference spans a kink.
struct Difference {
  double value = 0;
  bool smooth = true;
};
Difference central(const Model& m, const Param& p, double h, uint64_t events) {
  Difference d;
  double f[4];
  const double steps[4] = {h, -h, 0.5 * h, -0.5 * h};
  for (int k = 0; k < 4; ++k) {
    Model x = m;
    p.nudge(x, steps[k]);
    f[k] = simulate(x).fitness;
    d.smooth = d.smooth && grad::replicate_life(x).events == events;
  }
  const double d1 = (f[0] - f[1]) / (2 * h), d2 = (f[2] - f[3]) / h;
  d.value = (4 * d2 - d1) / 3;
  return d;
}

// Checks every parameter given against central differences: relative error below `tol`
// wherever the nudged lives take the life's branches (an error measured against the larger of
// the difference and 1e-3 of the largest difference of that kind, so a component near zero is
// held to the kind's scale). Returns how many were checked smooth.
// A rate is nudged by `rate_h` of itself (where its derivative is small against the fitness,
// 1e-4 leaves the differences on their rounding floor).
int check_against_differences(const Model& m, const std::vector<int>& voxels, bool dev_rate,
                              double tol, double rate_h = 1e-4) {
  const Gradient g = grad::gradient(m);
  const uint64_t events = grad::replicate_life(m).events;
  std::vector<Param> ps = params_of(m, g, voxels, dev_rate);
  std::vector<Difference> ds;
  for (const Param& p : ps) {
    const double h = p.name == "phase"      ? 1e-4
                     : p.name == "dev_rate" ? rate_h * std::max(std::abs(p.value), 1e-3)
                                            : 1e-4 * std::max(std::abs(p.value), 1e-3);
    ds.push_back(central(m, p, h, events));
  }
  int smooth = 0;
  for (size_t k = 0; k < ps.size(); ++k) {
    double scale = 0;
    for (size_t j = 0; j < ps.size(); ++j)
      if (ps[j].name == ps[k].name) scale = std::max(scale, std::abs(ds[j].value));
    const double err =
        std::abs(ps[k].gradient - ds[k].value) / std::max(std::abs(ds[k].value), 1e-3 * scale);
    if (!ds[k].smooth) {
      std::printf("  %s[%d]: nudged lives cross a kink (gradient %.6e, difference %.6e)\n",
                  ps[k].name.c_str(), ps[k].index, ps[k].gradient, ds[k].value);
      continue;
    }
    ++smooth;
    EXPECT_LT(err, tol) << ps[k].name << "[" << ps[k].index << "]: gradient " << ps[k].gradient
                        << ", central difference " << ds[k].value;
  }
  return smooth;
}

// The last state of the engine's life of m.
State final_state(const Model& m) {
  Simulator sim(m);
  while (sim.state().status == SimStatus::kRunning) sim.step();
  return sim.state();
}

TEST(Gradient, ForwardIsSimulateBitForBit) {
  const Model m = compile(demo_walker(), short_life(0.1, 0.02));
  const SimResult r = simulate(m);
  const Gradient g = grad::gradient(m);
  EXPECT_EQ(g.fitness, r.fitness);
  EXPECT_EQ(g.final_state_hash, r.final_state_hash);
  EXPECT_EQ(g.steps, r.steps);
  EXPECT_GT(g.fitness, 0.0);
}

// The replica the backward pass records is the engine's life: same fitness, bit for bit (and
// gradient() checks every snapshot), with and without development, with self-collision on.
TEST(Gradient, ReplicaIsTheEnginesLife) {
  for (Treatment t : {Treatment::kNone, Treatment::kStress, Treatment::kPressure}) {
    const Model walker = compile(demo_walker(), short_life(0.1, 0.02, t));
    EXPECT_EQ(grad::replicate_life(walker).fitness, simulate(walker).fitness);
    const Model cube = compile(cube3(), short_life(0.2, 0.05, t));
    EXPECT_EQ(grad::replicate_life(cube).fitness, simulate(cube).fitness);
  }
}

TEST(Gradient, MatchesCentralDifferencesOnA3x3x3Body) {
  const Model m = compile(cube3(), short_life(0.2, 0.05));
  std::vector<int> all(m.n);
  for (int i = 0; i < m.n; ++i) all[i] = i;
  const int smooth = check_against_differences(m, all, false, 1e-6);
  EXPECT_GE(smooth, 2 * m.n + 1 - 4);  // nearly every parameter's nudges are smooth
}

TEST(Gradient, MatchesCentralDifferencesWithDevelopment) {
  const Model m = compile(cube3(), short_life(0.2, 0.05, Treatment::kStress));
  std::vector<int> all(m.n);
  for (int i = 0; i < m.n; ++i) all[i] = i;
  const int smooth = check_against_differences(m, all, true, 1e-6);
  EXPECT_GE(smooth, 3 * m.n + 1 - 6);
}

// An arch of 7 voxels, one bond after another: up a column at (0, 0), across the top to (1, 1)
// and down a column there. Its legs stand diagonally across an empty cell, centres sqrt(2) L
// apart, closer than the contact distance (1.5 L) and 4 and 6 bonds apart along the arch
// (beyond the 3 that exclude a pair): two self-contacts from the start.
RobotDef arch() {
  RobotDef r = make_empty_robot(2, 2, 3);
  r.name = "arch";
  const int path[7][3] = {{0, 0, 0}, {0, 0, 1}, {0, 0, 2}, {0, 1, 2},
                          {1, 1, 2}, {1, 1, 1}, {1, 1, 0}};
  for (int k = 0; k < 7; ++k) {
    const int s = r.site(path[k][0], path[k][1], path[k][2]);
    r.present[s] = 1;
    r.stiffness[s] = 1e8 * (1.5 + std::sin(1.7 * k + 0.3));
    r.phase[s] = 0.37 * std::sin(0.9 * k) + 0.05 * k;
    r.dev_rate[s] = 2.0 + std::cos(1.3 * k);
  }
  return r;
}

// Self-collision (the engine's candidate pairs, each contact's spring recorded): every
// parameter of a body in self-contact throughout its life, with and without development.
TEST(Gradient, SelfCollisionMatchesCentralDifferences) {
  for (Treatment t : {Treatment::kNone, Treatment::kStress}) {
    SCOPED_TRACE(to_string(t));
    const Model m = compile(arch(), short_life(0.2, 0.05, t));
    // Not vacuous: a pair in contact at nearly every step.
    EXPECT_GT(self_contacts_of(m), simulate(m).steps * 9 / 10);
    std::vector<int> all(m.n);
    for (int i = 0; i < m.n; ++i) all[i] = i;
    const bool dev = t != Treatment::kNone;
    const int smooth = check_against_differences(m, all, dev, 1e-6);
    EXPECT_GE(smooth, (dev ? 3 : 2) * m.n + 1 - 2);
  }
}

// The walker: a spread of voxels, and the stiffest, which sets dt. That one ties with another
// voxel of the same stiffness (to the rule's 1e-9), where dt has no derivative: its stiffness
// differences are reported as crossing a kink, and every other parameter is held to 1e-6.
TEST(Gradient, MatchesCentralDifferencesOnTheDemoWalker) {
  const Model m = compile(demo_walker(), short_life(0.04, 0.02));
  std::vector<int> some = {0, 300};
  some.push_back(static_cast<int>(std::max_element(m.e0.begin(), m.e0.end()) - m.e0.begin()));
  const int smooth = check_against_differences(m, some, false, 1e-6);
  EXPECT_GE(smooth, 2 * static_cast<int>(some.size()));
}

// The initial positions, velocities, orientations and angular velocities: central differences
// of lives started from a nudged initial state (a Simulator's state changed before its first
// step), under walk and turn.
TEST(Gradient, InitialStateMatchesCentralDifferences) {
  for (Task task : {Task::kWalk, Task::kTurn}) {
    SCOPED_TRACE(to_string(task));
    PhysicsDef def = short_life(0.2, 0.05);
    def.task = task;
    const Model m = compile(cube3(), def);
    const Gradient g = grad::gradient(m);
    const auto fitness = [&](int k, double dx, double dv) {
      Simulator sim(m);
      sim.mutable_state().pos[k / 3][k % 3] += dx;
      sim.mutable_state().lin_mom[k / 3][k % 3] += dv * m.mass;
      while (sim.state().status == SimStatus::kRunning) sim.step();
      return sim.result().fitness;
    };
    // Components of voxels 0, 4, 13 and 20: not the z of a voxel on the floor, which starts
    // exactly at the floor contact's threshold (a kink: its penetration is 0).
    for (int k : {1, 12, 40, 62}) {
      // A velocity of 1e-4 m/s already moves a contact event within the life (the differences
      // of 1e-3, 1e-4, 1e-5 and 1e-6 m/s approach the gradient only from 1e-5 on): 1e-6.
      const double hx = 1e-4 * m.size, hv = 1e-6;
      const double dx1 = (fitness(k, hx, 0) - fitness(k, -hx, 0)) / (2 * hx);
      const double dx2 = (fitness(k, hx / 2, 0) - fitness(k, -hx / 2, 0)) / hx;
      const double dv1 = (fitness(k, 0, hv) - fitness(k, 0, -hv)) / (2 * hv);
      const double dv2 = (fitness(k, 0, hv / 2) - fitness(k, 0, -hv / 2)) / hv;
      EXPECT_TRUE(RelNear(g.initial_position[k], (4 * dx2 - dx1) / 3, 1e-6)) << k;
      EXPECT_TRUE(RelNear(g.initial_velocity[k], (4 * dv2 - dv1) / 3, 1e-6)) << k;
    }
    // Orientations and angular velocities: a voxel turned by a small angle a about a world
    // axis (its quaternion (sin(a/2) e, cos(a/2)): d / da is half the gradient's x, y or z;
    // w's component is projected out) and spinning about it.
    ASSERT_EQ(g.initial_orientation.size(), 4 * size_t(m.n));
    ASSERT_EQ(g.initial_angular_velocity.size(), 3 * size_t(m.n));
    const auto turned = [&](int i, int axis, double turn, double spin) {
      Simulator sim(m);
      sim.mutable_state().orient[i] = Quat(Eigen::AngleAxisd(turn, Vec3::Unit(axis)));
      sim.mutable_state().ang_mom[i][axis] += spin * m.inertia;
      while (sim.state().status == SimStatus::kRunning) sim.step();
      return sim.result().fitness;
    };
    for (const auto& [i, axis] :
         {std::pair{0, 0}, std::pair{4, 1}, std::pair{13, 2}, std::pair{20, 0}, std::pair{26, 1}}) {
      EXPECT_EQ(g.initial_orientation[4 * i + 3], 0.0) << i;
      const double ha = 1e-4, hw = 1e-4;  // rad, rad/s
      const double da1 = (turned(i, axis, ha, 0) - turned(i, axis, -ha, 0)) / (2 * ha);
      const double da2 = (turned(i, axis, ha / 2, 0) - turned(i, axis, -ha / 2, 0)) / ha;
      const double dw1 = (turned(i, axis, 0, hw) - turned(i, axis, 0, -hw)) / (2 * hw);
      const double dw2 = (turned(i, axis, 0, hw / 2) - turned(i, axis, 0, -hw / 2)) / hw;
      EXPECT_NE(da1, 0.0);
      EXPECT_NE(dw1, 0.0);
      EXPECT_TRUE(RelNear(0.5 * g.initial_orientation[4 * i + axis], (4 * da2 - da1) / 3, 1e-6))
          << i << " axis " << axis;
      EXPECT_TRUE(RelNear(g.initial_angular_velocity[3 * i + axis], (4 * dw2 - dw1) / 3, 1e-6))
          << i << " axis " << axis;
    }
  }
}

// A robot with its own amplitudes (voxcraft's rule) and an actuation scale: the gain of each
// voxel is their product, and the gradient is with respect to it (Gradient::act_gain); the
// physics' amplitude then changes nothing (its gradient 0).
TEST(Gradient, PerVoxelActuationGainsMatchCentralDifferences) {
  RobotDef r = cube3();
  r.act_amplitude.assign(r.sites(), 0.0);
  r.act_scale.assign(r.sites(), 1.0);
  for (int s = 0; s < r.sites(); ++s) {
    r.act_amplitude[s] = 0.12 + 0.05 * std::sin(2.3 * s);
    r.act_scale[s] = s % 4 == 0 ? 0.5 : 1.0;
  }
  for (Treatment t : {Treatment::kNone, Treatment::kStress}) {
    SCOPED_TRACE(to_string(t));
    const Model m = compile(r, short_life(0.2, 0.05, t));
    ASSERT_TRUE(m.act_per_voxel);
    const Gradient g = grad::gradient(m);
    ASSERT_EQ(g.act_gain.size(), size_t(m.n));
    EXPECT_EQ(g.amplitude, 0.0);
    const uint64_t events = grad::replicate_life(m).events;
    double scale = 0;
    std::vector<Difference> ds;
    for (int i = 0; i < m.n; ++i) {
      const Param p{"act_gain", i, m.act_gain[i], [i](Model& x, double h) { x.act_gain[i] += h; },
                    g.act_gain[i]};
      ds.push_back(central(m, p, 1e-4 * m.act_gain[i], events));
      scale = std::max(scale, std::abs(ds.back().value));
    }
    int smooth = 0;
    for (int i = 0; i < m.n; ++i) {
      if (!ds[i].smooth) continue;
      ++smooth;
      EXPECT_LT(
          std::abs(g.act_gain[i] - ds[i].value) / std::max(std::abs(ds[i].value), 1e-3 * scale),
          1e-6)
          << "act_gain[" << i << "]: gradient " << g.act_gain[i] << ", difference " << ds[i].value;
    }
    EXPECT_GT(scale, 0.0);
    EXPECT_GE(smooth, m.n - 3);
  }
  // Actuation off (every gain 0): the stage is skipped, and the gains' gradient is 0.
  RobotDef still = r;
  std::fill(still.act_amplitude.begin(), still.act_amplitude.end(), 0.0);
  const Gradient g0 = grad::gradient(compile(still, short_life(0.1, 0.05)));
  EXPECT_EQ(g0.act_gain, std::vector<double>(still.sites(), 0.0));
}

// A loss of the final state of one's own (here a voxel's final x and another's final vertical
// momentum) instead of the task's fitness.
TEST(Gradient, OfAUsersLossOfTheFinalStateMatchesCentralDifferences) {
  const Model m = compile(cube3(), short_life(0.2, 0.05));
  const auto value = [](const State& s) { return s.pos[13].x() + 1e-3 * s.lin_mom[2].z(); };
  const grad::FinalLoss loss = [&](const State& s, std::vector<std::vector<double>>& d) {
    d[&state_field("pos") - kStateFields.data()][3 * 13] += 1.0;
    d[&state_field("lin_mom") - kStateFields.data()][3 * 2 + 2] += 1e-3;
    return value(s);
  };
  const Gradient g = grad::gradient_of(m, loss);
  const auto final_value = [&](const Model& x) { return value(final_state(x)); };
  EXPECT_EQ(g.fitness, final_value(m));
  for (int i : {1, 2, 13}) {
    const auto difference = [&](double h, bool stiffness) {
      Model a = m, b = m;
      (stiffness ? a.e0[i] : a.phase[i]) += h;
      (stiffness ? b.e0[i] : b.phase[i]) -= h;
      return (final_value(a) - final_value(b)) / (2 * h);
    };
    for (bool stiffness : {true, false}) {
      const double h = stiffness ? 1e-4 * m.e0[i] : 1e-4;
      const double d = (4 * difference(h / 2, stiffness) - difference(h, stiffness)) / 3;
      EXPECT_TRUE(RelNear(stiffness ? g.stiffness[i] : g.phase[i], d, 1e-6))
          << (stiffness ? "stiffness " : "phase ") << i;
    }
  }
  const grad::FinalLoss wrong = [](const State&, std::vector<std::vector<double>>& d) {
    d[&state_field("pos") - kStateFields.data()].assign(2, 1.0);
    return 0.0;
  };
  EXPECT_NE(error_of([&] { grad::gradient_of(m, wrong); }).find("'pos'"), std::string::npos);
}

// The bound: a 10^3 body over a whole 5.2 s life within 2 GB. The plan (snapshots and
// one segment's tape) is checked here without running the life; the measured peak of the whole
// process, 823 MiB, is in docs/gradients.md ("Cost and memory").
TEST(Gradient, A10CubedBodyOverAWholeLifeIsPlannedUnder2GB) {
  RobotDef r = demo_cube(10, 1e10);
  for (int s = 0; s < r.sites(); ++s) r.stiffness[s] *= 1.0 + 1e-3 * (s % 7);
  const grad::Plan p = grad::plan(compile(r, PhysicsDef{}));
  EXPECT_GT(p.steps, 11000);
  EXPECT_LT(p.estimated_bytes, 2e9);
  EXPECT_GT(p.checkpoint_every, 1);
}

// The automatic spacing (docs/gradients.md, "The snapshots' spacing"): a short life keeps its
// least-memory spacing; a longer one takes segments of 16 steps while the estimate on two
// threads stays within 1 GB; a life too long for that takes the shortest spacing that keeps
// within it; and the spacing is the same whatever the threads and the memory limit.
TEST(Gradient, SpacingIsSixteenStepsWhileTheEstimateStaysWithin1GB) {
  const RobotDef walker = demo_walker();
  const auto spacing = [&](double duration, const grad::GradientOptions& o = {}) {
    PhysicsDef phys;
    phys.duration = duration;
    return grad::plan(compile(walker, phys), o);
  };
  const grad::Plan short_life = spacing(0.2);
  EXPECT_LT(short_life.checkpoint_every, 16);  // its least-memory spacing, about 8
  EXPECT_GT(short_life.checkpoint_every, 1);
  const grad::Plan whole = spacing(5.2);  // least memory would take about 40
  EXPECT_EQ(whole.checkpoint_every, 16);
  grad::GradientOptions one_thread_limited;
  one_thread_limited.threads = 1;
  one_thread_limited.memory_limit = 1e12;
  EXPECT_EQ(spacing(5.2, one_thread_limited).checkpoint_every, 16);
  // 100 s: about 220 000 steps, whose snapshots every 16 steps would pass 1 GB.
  const grad::Plan is_long = spacing(100);
  EXPECT_GT(is_long.checkpoint_every, 16);
  grad::GradientOptions two;
  two.threads = 2;
  const grad::Plan is_long_on_two = spacing(100, two);
  EXPECT_EQ(is_long_on_two.checkpoint_every, is_long.checkpoint_every);
  EXPECT_LE(is_long_on_two.estimated_bytes, 1e9);
  grad::GradientOptions shorter = two;
  shorter.checkpoint_every = is_long.checkpoint_every - 1;  // the shortest within the budget
  EXPECT_GT(spacing(100, shorter).estimated_bytes, 1e9);
}

// A body driven by a neural controller (docs/control.md) with distinct weights of both signs.
RobotDef cube3_with_network(ControllerKind kind, int hidden) {
  RobotDef r = cube3();
  r.controller.kind = kind;
  r.controller.hidden = hidden;
  for (int k = 0; k < weight_count(kind, hidden); ++k)
    r.controller.weights.push_back(0.8 * std::sin(1.3 * k + 0.7));
  return r;
}

// Every `stride`-th weight of the controller against central differences of simulate()'s
// fitness, as check_against_differences holds the robot's arrays, with h = 3e-4 of the weight
// (at 1e-4 the weights that act only through the neighbours' signals, whose derivatives are
// near 1e-3 of the largest, sit on the differences' rounding floor: their differences wander
// by about 1e-10 as h goes from 1e-5 to 1e-4, and agree with the gradient to 1e-8 at 1e-2). A
// nudge that flips the sign of a unit's input is an event: softsign's curvature jumps there,
// so Richardson's O(h^4) does not hold across it. Returns how many were smooth.
int check_weights(const Model& m, double tol, size_t stride = 1) {
  const Gradient g = grad::gradient(m);
  EXPECT_EQ(g.fitness, simulate(m).fitness);
  EXPECT_EQ(g.controller_weights.size(), m.controller.weights.size());
  const uint64_t events = grad::replicate_life(m).events;
  std::vector<Difference> ds;
  double scale = 0;
  std::vector<size_t> ks;
  for (size_t k = 0; k < m.controller.weights.size(); k += stride) {
    ks.push_back(k);
    const Param p{"weight", static_cast<int>(k), m.controller.weights[k],
                  [k](Model& x, double h) { x.controller.weights[k] += h; },
                  g.controller_weights[k]};
    ds.push_back(central(m, p, 3e-4 * std::max(std::abs(p.value), 1e-2), events));
    scale = std::max(scale, std::abs(ds.back().value));
  }
  int smooth = 0;
  for (size_t c = 0; c < ds.size(); ++c) {
    const size_t k = ks[c];
    const double gk = g.controller_weights[k], d = ds[c].value;
    if (!ds[c].smooth) {
      std::printf("  weight %zu: nudged lives cross a kink (gradient %.6e, difference %.6e)\n", k,
                  gk, d);
      continue;
    }
    ++smooth;
    EXPECT_LT(std::abs(gk - d) / std::max(std::abs(d), 1e-3 * scale), tol)
        << "weight " << k << ": gradient " << gk << ", central difference " << d;
  }
  EXPECT_GT(scale, 0.0);
  return smooth;
}

// The weights of a neural controller, through its sensors (strain, pressure / E, velocity,
// orientation, the centre of mass's velocity; touch is 0 or 1) and its memory (the distributed
// network's signals to its neighbours), on short lives: the replica is the engine's life, and
// the gradient agrees with central differences to 1e-6. With the default rate limit and
// without it (act_max_rate 0), where the limit binds (a clamp, a kink) the nudges cross it.
TEST(Gradient, ControllerWeightsMatchCentralDifferences) {
  struct Case {
    ControllerKind kind;
    int hidden;
    double max_rate;
    Treatment treatment;
  };
  for (const Case& c :
       {Case{ControllerKind::kDistributed, 2, 0.0, Treatment::kNone},
        Case{ControllerKind::kDistributed, 0, 31.415926535897931, Treatment::kStress},
        Case{ControllerKind::kCentral, 2, 0.0, Treatment::kPressure},
        Case{ControllerKind::kCentral, 3, 31.415926535897931, Treatment::kNone}}) {
    PhysicsDef def = short_life(0.2, 0.05, c.treatment);
    def.act_max_rate = c.max_rate;
    const Model m = compile(cube3_with_network(c.kind, c.hidden), def);
    SCOPED_TRACE(controller_text(m.controller) + ", act_max_rate " + std::to_string(c.max_rate) +
                 ", treatment " + to_string(c.treatment));
    EXPECT_EQ(grad::replicate_life(m).fitness, simulate(m).fitness);
    const size_t stride = m.controller.weights.size() > 60 ? 4 : 1;  // a quarter of the 105
    const int checked = static_cast<int>((m.controller.weights.size() + stride - 1) / stride);
    const int smooth = check_weights(m, 1e-6, stride);
    std::printf("%s: %d of %d weights smooth\n", controller_text(m.controller).c_str(), smooth,
                checked);
    EXPECT_GE(smooth, checked * 3 / 5);
  }
  // The demo walker (512 voxels, faces inside and out) under each network: the replica is the
  // engine's life.
  for (const auto& [kind, hidden] :
       {std::pair{ControllerKind::kDistributed, 4}, std::pair{ControllerKind::kCentral, 2}}) {
    RobotDef r = demo_walker();
    r.controller = cube3_with_network(kind, hidden).controller;
    const Model m = compile(r, short_life(0.1, 0.02, Treatment::kStress));
    EXPECT_EQ(grad::replicate_life(m).fitness, simulate(m).fitness) << to_string(kind);
  }
}

// jump (a maximum over the states after settling) and turn (an angle of the last state's
// layout against the settled one) on the flat floor, every kind of parameter: E0, the phases
// and the amplitude (every third voxel), the rates under development (turn, under pressure)
// and a central network's weights (turn: every other one); relative error below 1e-6 wherever
// the nudged lives take the life's branches (the loss's own among them: jump's highest step,
// turn's whole turns). The cube is a hundred times stiffer for jump: at 1e8 Pa its centre
// never rises above its settled height within 0.2 s (jump's fitness 0). (Under a network the
// stiff cube's jump crosses a branch at every weight's nudge, and under stress its rates'
// derivatives, 1e-8 to 1e-9, are on the differences' rounding floor: neither is checked here.)
TEST(Gradient, JumpAndTurnMatchCentralDifferencesOnA3x3x3Body) {
  struct Case {
    Task task;
    Treatment treatment;
    double stiffer, duration, settle;
    bool network;
  };
  for (const Case& c : {Case{Task::kJump, Treatment::kNone, 100, 0.1, 0.03, false},
                        Case{Task::kTurn, Treatment::kPressure, 1, 0.2, 0.05, true}}) {
    SCOPED_TRACE(to_string(c.task));
    PhysicsDef def = short_life(c.duration, c.settle, c.treatment);
    def.task = c.task;
    RobotDef r = cube3();
    for (double& e : r.stiffness) e *= c.stiffer;
    const Model m = compile(r, def);
    EXPECT_EQ(grad::gradient(m).fitness, simulate(m).fitness);
    EXPECT_GT(simulate(m).fitness, 0.0);
    std::vector<int> some;  // every third voxel
    for (int i = 0; i < m.n; i += 3) some.push_back(i);
    const bool rates = c.treatment != Treatment::kNone;  // else compile() zeroes them
    const int count = (rates ? 3 : 2) * static_cast<int>(some.size()) + 1;
    const int smooth = check_against_differences(m, some, rates, 1e-6, 1e-2);
    std::printf("%s: %d of %d parameters smooth\n", to_string(c.task), smooth, count);
    EXPECT_GE(smooth, count * 4 / 5);
    if (!c.network) continue;
    def.act_max_rate = 0;
    RobotDef net = cube3_with_network(ControllerKind::kCentral, 2);
    net.stiffness = r.stiffness;
    const Model mn = compile(net, def);
    const int weights = static_cast<int>(mn.controller.weights.size());
    EXPECT_GE(check_weights(mn, 1e-6, 2), (weights + 1) / 2 * 3 / 5);  // every other weight
  }
}

// Snapshots every step, or few: the same gradient (to rounding: the segments' sums group
// differently).
TEST(Gradient, CheckpointSpacingChangesNothingButRounding) {
  const Model m = compile(cube3(), short_life(0.2, 0.05));
  grad::GradientOptions every1, every7;
  every1.checkpoint_every = 1;
  every7.checkpoint_every = 7;
  const Gradient a = grad::gradient(m, every1), b = grad::gradient(m, every7),
                 c = grad::gradient(m);
  EXPECT_EQ(a.fitness, b.fitness);
  for (int i = 0; i < m.n; ++i) {
    EXPECT_TRUE(RelNear(a.stiffness[i], b.stiffness[i], 1e-11));
    EXPECT_TRUE(RelNear(a.phase[i], c.phase[i], 1e-11));
  }
  EXPECT_GT(a.checkpoints, b.checkpoints);
}

// Under bond_model voxelyze09 every bond takes the scalar path (its two frames and their switch,
// its rotation vectors, its own time step): the replica is the engine's life, bit for bit, with
// and without development, and its gradient agrees with central differences on every kind of
// parameter, the time step's dependence on stiffness included.
PhysicsDef voxelyze09(double duration, double settle, Treatment treatment = Treatment::kNone) {
  PhysicsDef def = short_life(duration, settle, treatment);
  def.bond_model = BondModel::kVoxelyze09;
  return def;
}

TEST(Gradient, Voxelyze09ReplicaIsTheEnginesLife) {
  for (Treatment t : {Treatment::kNone, Treatment::kStress}) {
    const Model walker = compile(demo_walker(), voxelyze09(0.1, 0.02, t));
    EXPECT_EQ(grad::replicate_life(walker).fitness, simulate(walker).fitness);
    const Model cube = compile(cube3(), voxelyze09(0.2, 0.05, t));
    const SimResult r = simulate(cube);
    const Gradient g = grad::gradient(cube);
    EXPECT_EQ(g.fitness, r.fitness);
    EXPECT_EQ(g.final_state_hash, r.final_state_hash);
  }
}

TEST(Gradient, Voxelyze09MatchesCentralDifferencesOnA3x3x3Body) {
  const Model m = compile(cube3(), voxelyze09(0.2, 0.05));
  std::vector<int> all(m.n);
  for (int i = 0; i < m.n; ++i) all[i] = i;
  // Its discontinuities (docs/gradients.md: the switch of frames, a rotation below about 2e-8
  // rad that is none) put more nudged lives across a kink than the exact model's: 45 of 55
  // smooth when measured.
  EXPECT_GE(check_against_differences(m, all, false, 1e-6), 40);
}

TEST(Gradient, Voxelyze09MatchesCentralDifferencesWithDevelopment) {
  const Model m = compile(cube3(), voxelyze09(0.2, 0.05, Treatment::kStress));
  std::vector<int> all(m.n);
  for (int i = 0; i < m.n; ++i) all[i] = i;
  // The rates' derivatives are ~1e-6 of the fitness: nudged by 1e-2 of themselves, off the
  // differences' rounding floor.
  EXPECT_GE(check_against_differences(m, all, true, 1e-6, 1e-2), 45);
}

// The bonds of the exact model that take the scalar path, step by step: the batched kernel's
// test (bond_body.hpp), a degenerate chord or a relative rotation near half a turn, on the
// engine's life. Each as (step, bond).
std::vector<std::pair<int64_t, int>> scalar_path_bonds(const Model& m) {
  std::vector<std::pair<int64_t, int>> out;
  Simulator sim(m);
  while (sim.state().status == SimStatus::kRunning) {
    const State& s = sim.state();
    for (int b = 0; b < m.bond_count(); ++b) {
      const int ia = m.bond_a[b], ib = m.bond_b[b], d = m.bond_axis[b];
      const Vec3 c = s.orient[ia].conjugate() * (s.pos[ib] - s.pos[ia]);
      const Quat q = s.orient[ia].conjugate() * s.orient[ib];
      const double r[3] = {c[d], c[(d + 1) % 3], c[(d + 2) % 3]};
      const double v[3] = {q.vec()[d], q.vec()[(d + 1) % 3], q.vec()[(d + 2) % 3]};
      const double len = c.norm(), h = len + r[0];
      const double w2 = h * q.w() - r[2] * v[1] + r[1] * v[2];
      if (h <= 1e-6 * len || w2 * w2 <= 2e-6 * (len * h)) out.push_back({s.steps, b});
    }
    sim.step();
  }
  return out;
}

// A life whose snapshots and tape would exceed the memory limit is refused before it runs.
TEST(Gradient, RefusesALifeBeyondItsMemoryInOneLine) {
  grad::GradientOptions tight;
  tight.memory_limit = 1e6;
  const Model walker = compile(demo_walker(), short_life(0.03, 0.02));
  const std::string big = error_of([&] { grad::gradient(walker, tight); });
  EXPECT_NE(big.find("memory_limit"), std::string::npos) << big;
  EXPECT_EQ(big.find('\n'), std::string::npos);
  grad::GradientOptions long_segments;
  long_segments.checkpoint_every = 1 << 20;
  const std::string nodes = error_of([&] { grad::gradient(walker, long_segments); });
  EXPECT_NE(nodes.find("2^31"), std::string::npos) << nodes;
  tight.memory_limit = 1e9;
  EXPECT_LT(grad::gradient(walker, tight).estimated_bytes, 1e9);
}

// A body that stiffens as it develops takes more steps than its initial time step gives, and so
// more snapshots than plan() counted. Under a memory limit the plan passes: on one thread the
// gradient stops with one line once the snapshots pass the limit, not past it silently; planned
// on two threads, it takes one instead (a segment's tape fewer) when that keeps within the limit;
// a limit that holds the life's own snapshots lets it through. The gradient is the same bits.
TEST(Gradient, RefusesALifeThatStiffensPastItsMemoryInOneLine) {
  const Model m = compile(demo_walker(), short_life(0.3, 0.02, Treatment::kPressure));
  grad::GradientOptions o;
  o.checkpoint_every = 4;
  o.threads = 1;
  const grad::Plan p = grad::plan(m, o);
  const grad::Gradient whole = grad::gradient(m, o);
  const double planned = std::ceil(p.steps / o.checkpoint_every);
  const double extra = (static_cast<double>(whole.checkpoints) - planned) * p.snapshot_bytes;
  ASSERT_GT(static_cast<double>(whole.checkpoints), planned + 2) << whole.steps << " " << p.steps;
  o.memory_limit = p.estimated_bytes + 0.5 * p.snapshot_bytes;
  EXPECT_EQ(grad::plan(m, o).estimated_bytes, p.estimated_bytes);
  EXPECT_THROW(grad::gradient(m, o), grad::MemoryLimitError);
  const std::string past = error_of([&] { grad::gradient(m, o); });
  EXPECT_NE(past.find("stiffened"), std::string::npos) << past;
  EXPECT_NE(past.find("memory_limit"), std::string::npos) << past;
  EXPECT_EQ(past.find('\n'), std::string::npos);
  o.memory_limit = p.estimated_bytes + extra;
  const grad::Gradient held = grad::gradient(m, o);
  EXPECT_EQ(held.fitness, whole.fitness);
  EXPECT_EQ(held.stiffness, whole.stiffness);
  // Planned on two threads; the extra snapshots fit beside one thread's segment, not two's.
  o.threads = 2;
  o.memory_limit = 0;
  const grad::Plan p2 = grad::plan(m, o);
  ASSERT_EQ(p2.threads, 2);
  ASSERT_LT(extra, p2.thread_bytes);
  o.memory_limit = p2.estimated_bytes + 0.5 * p.snapshot_bytes;
  ASSERT_EQ(grad::plan(m, o).threads, 2);
  const grad::Gradient fewer = grad::gradient(m, o);
  EXPECT_EQ(fewer.threads, 1);
  EXPECT_EQ(fewer.fitness, whole.fitness);
  EXPECT_EQ(fewer.stiffness, whole.stiffness);
  o.memory_limit = p2.estimated_bytes + extra;
  EXPECT_EQ(grad::gradient(m, o).threads, 2);
}

// Under the exact model, the bonds the batched kernel hands to the scalar path (here an
// irregular 150-voxel body's, bent near half a turn as it sinks through the floor, from step 412
// on) are differentiated by that path (each on a small tape of its own, in the bond stage's
// block's reverse): the forward is simulate()'s, bit for bit, and the gradient agrees with
// central differences on both voxels of the first such bond, for the fitness and for a loss of
// their own final centres (which their bond's forces move directly; the centre of mass feels
// them only through the floor).
TEST(Gradient, ExactModelsScalarPathMatchesCentralDifferences) {
  PhysicsDef def = short_life(0.06, 0.02);
  def.sinking_invalid = false;
  const Model m = compile(demo_irregular(150, 1), def);
  const auto scalar = scalar_path_bonds(m);
  ASSERT_FALSE(scalar.empty());
  const int ia = m.bond_a[scalar.front().second], ib = m.bond_b[scalar.front().second];
  const SimResult r = simulate(m);
  const Gradient g = grad::gradient(m);
  EXPECT_EQ(g.final_state_hash, r.final_state_hash);
  EXPECT_EQ(g.fitness, r.fitness);
  EXPECT_GE(check_against_differences(m, {ia, ib}, false, 1e-6), 4);
  const auto value = [&](const State& s) { return s.pos[ia].sum() - s.pos[ib].sum(); };
  const grad::FinalLoss loss = [&](const State& s, std::vector<std::vector<double>>& d) {
    for (int k = 0; k < 3; ++k) {
      d[&state_field("pos") - kStateFields.data()][3 * ia + k] += 1.0;
      d[&state_field("pos") - kStateFields.data()][3 * ib + k] -= 1.0;
    }
    return value(s);
  };
  const Gradient gl = grad::gradient_of(m, loss);
  const auto final_value = [&](const Model& x) { return value(final_state(x)); };
  // Central differences, Richardson-extrapolated, each held to the larger of itself and 1e-3 of
  // the larger of the two (a stiff voxel's is ~1e-6 of its soft neighbour's, at the
  // differences' rounding floor), as check_against_differences does.
  double d[2];
  for (int k = 0; k < 2; ++k) {
    const int i = k == 0 ? ia : ib;
    const auto difference = [&](double h) {
      Model a = m, b = m;
      a.e0[i] += h, b.e0[i] -= h;
      return (final_value(a) - final_value(b)) / (2 * h);
    };
    const double h = 1e-4 * m.e0[i];
    d[k] = (4 * difference(h / 2) - difference(h)) / 3;
  }
  const double scale = std::max(std::abs(d[0]), std::abs(d[1]));
  for (int k = 0; k < 2; ++k) {
    const double g_i = gl.stiffness[k == 0 ? ia : ib];
    EXPECT_LT(std::abs(g_i - d[k]), 1e-6 * std::max(std::abs(d[k]), 1e-3 * scale))
        << (k == 0 ? ia : ib) << ": gradient " << g_i << ", central difference " << d[k];
  }
}

}  // namespace
}  // namespace plastivox
namespace plastivox {}  // namespace plastivox
