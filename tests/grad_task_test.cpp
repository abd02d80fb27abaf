// Losses over a life's states (engine/grad, docs/gradients.md): a user's loss that reads states
// in the middle of the life agrees with central differences, and every task's fitness, as a
// loss (grad::task_loss), is simulate()'s bit for bit and has the derivative with respect to
// the states it reads that differences of the loss give.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <string>
#include <vector>

#include "plastivox/grad/gradient.hpp"
#include "plastivox/simulator.hpp"
#include "plastivox/task.hpp"
#include "test_support.hpp"

namespace plastivox {
namespace {

using grad::Gradient;
using grad::TrajectoryLoss;
using plastivox::testing::RelNear;
using Rows = std::vector<std::vector<double>>;

size_t row(const char* name) {
  return static_cast<size_t>(&state_field(name) - kStateFields.data());
}

// A 3 x 2 x 3 body of distinct stiffness (about `E`), phases and rates.
RobotDef block(double E) {
  RobotDef r = make_empty_robot(3, 2, 3);
  r.name = "block";
  for (int s = 0; s < r.sites(); ++s) {
    r.present[s] = 1;
    r.stiffness[s] = E * (1.4 + std::cos(2.1 * s + 0.4));
    r.phase[s] = 0.3 * std::cos(1.1 * s) - 0.04 * s;
    r.dev_rate[s] = 1.5 + std::sin(0.7 * s);
  }
  return r;
}

PhysicsDef life(Task task, double duration, double settle) {
  PhysicsDef def;
  def.task = task;
  def.duration = duration;
  def.settle_time = settle;
  return def;
}

// The loss's value of the life the engine runs for x: see every state, then value.
double value_of_life(const Model& x, const std::function<TrajectoryLoss(const Model&)>& make) {
  const TrajectoryLoss loss = make(x);
  Simulator sim(x);
  loss.see(sim.state());
  while (sim.state().status == SimStatus::kRunning) {
    sim.step();
    loss.see(sim.state());
  }
  return loss.value(sim.state());
}

// A user's loss of states in the middle of the life: at every 7th step, a weighted x of voxel
// 4, the square of voxel 13's height (per voxel length) and voxel 2's vertical momentum; and
// the final x of voxel 0.
TrajectoryLoss mid_life_loss(const Model& m) {
  auto total = std::make_shared<double>(0);
  auto last = std::make_shared<int64_t>(-1);
  const auto reads = [](int64_t step) { return step % 7 == 0; };
  const auto weight = [](int64_t step) { return std::sin(0.01 * double(step) + 0.5); };
  TrajectoryLoss loss;
  loss.see = [&m, total, last, reads, weight](const State& s) {
    if (reads(s.steps))
      *total += weight(s.steps) * s.pos[4].x() + s.pos[13].z() * s.pos[13].z() / m.size +
                1e-3 * s.lin_mom[2].z();
    *last = s.steps;
  };
  loss.value = [total](const State& s) { return *total + s.pos[0].x(); };
  loss.adjoint = [&m, last, reads, weight](const State& s, Rows& d) {
    if (!reads(s.steps) && s.steps != *last) return false;
    if (reads(s.steps)) {
      d[row("pos")][3 * 4] += weight(s.steps);
      d[row("pos")][3 * 13 + 2] += 2 * s.pos[13].z() / m.size;
      d[row("lin_mom")][3 * 2 + 2] += 1e-3;
    }
    if (s.steps == *last) d[row("pos")][0] += 1;
    return true;
  };
  return loss;
}

// Central differences, Richardson-extrapolated (error O(h^4)), of f(p + h).
double richardson(const std::function<double(double)>& f, double h) {
  const double d1 = (f(h) - f(-h)) / (2 * h), d2 = (f(h / 2) - f(-h / 2)) / h;
  return (4 * d2 - d1) / 3;
}

// The loss reads the state at steps inside every segment, across segments and at the end; its
// derivative reaches E0, the phases, the rates, the amplitude and the initial state, and agrees
// with central differences of the same loss of the engine's life to 1e-6 where the nudged
// lives take the life's branches.
TEST(TrajectoryLoss, OfStatesInTheMiddleOfTheLifeMatchesCentralDifferences) {
  PhysicsDef def = life(Task::kWalk, 0.2, 0.05);
  def.treatment = Treatment::kStress;
  const Model m = compile(block(1e8), def);  // 68 steps
  const Gradient g = grad::gradient_of(m, mid_life_loss(m));
  EXPECT_EQ(g.fitness, value_of_life(m, mid_life_loss));
  const uint64_t events = grad::replicate_life(m).events;
  struct Case {
    const char* name;
    int i;
    double gradient, h;
    std::function<void(Model&, double)> nudge;
  };
  std::vector<Case> cases;
  for (int i : {0, 5, 11, 16}) {
    cases.push_back({"stiffness", i, g.stiffness[i], 1e-4 * m.e0[i],
                     [i](Model& x, double h) { x.e0[i] += h; }});
    cases.push_back({"phase", i, g.phase[i], 1e-4, [i](Model& x, double h) { x.phase[i] += h; }});
    // A rate's derivative is small against the loss (1e-7 of it per 1/s here): at 1e-4 of the
    // rate the differences sit on their rounding floor (3e-6 off; 2e-8 at 1e-2, Richardson
    // keeping the truncation below that).
    cases.push_back({"dev_rate", i, g.dev_rate[i], 1e-2 * m.alpha[i],
                     [i](Model& x, double h) { x.alpha[i] += h; }});
  }
  cases.push_back(
      {"amplitude", -1, g.amplitude, 1e-4 * m.def.act_amplitude, [](Model& x, double h) {
         x.def.act_amplitude += h, x.act_amplitude_xi += h, x.act_amplitude_max += h;
       }});
  std::vector<double> ds;
  std::vector<bool> same;
  for (const Case& c : cases) {
    bool kept = true;
    ds.push_back(richardson(
        [&](double h) {
          Model x = m;
          c.nudge(x, h);
          kept = kept && grad::replicate_life(x).events == events;
          return value_of_life(x, mid_life_loss);
        },
        c.h));
    same.push_back(kept);
  }
  // Each error against the larger of the difference and 1e-3 of its kind's largest (as
  // grad_gradient_test holds a component near zero to its kind's scale).
  int smooth = 0;
  for (size_t k = 0; k < cases.size(); ++k) {
    const Case& c = cases[k];
    if (!same[k]) {
      std::printf("  %s[%d] crosses a kink\n", c.name, c.i);
      continue;
    }
    double scale = 0;
    for (size_t j = 0; j < cases.size(); ++j)
      if (std::string(cases[j].name) == c.name) scale = std::max(scale, std::abs(ds[j]));
    ++smooth;
    EXPECT_LT(std::abs(c.gradient - ds[k]), 1e-6 * std::max(std::abs(ds[k]), 1e-3 * scale))
        << c.name << "[" << c.i << "]: gradient " << c.gradient << ", difference " << ds[k];
  }
  EXPECT_GE(smooth, static_cast<int>(cases.size()) - 3);
  // The snapshots' spacing moves the reads into other segments (and onto their boundaries):
  // the same gradient to rounding.
  for (int every : {1, 7, 20}) {
    grad::GradientOptions o;
    o.checkpoint_every = every;
    const Gradient a = grad::gradient_of(m, mid_life_loss(m), o);
    EXPECT_EQ(a.fitness, g.fitness);
    for (int i = 0; i < m.robot_n; ++i) {
      EXPECT_TRUE(RelNear(a.stiffness[i], g.stiffness[i], 1e-10)) << every << " " << i;
      EXPECT_TRUE(RelNear(a.phase[i], g.phase[i], 1e-10)) << every << " " << i;
    }
  }
}

// A loss of the initial state alone: its derivative is the loss's own, on the initial
// position and velocity, and nothing reaches the parameters.
TEST(TrajectoryLoss, OfTheInitialStateIsTheLosssOwnDerivative) {
  const Model m = compile(block(1e10), life(Task::kWalk, 0.05, 0.02));
  TrajectoryLoss loss;
  loss.see = [](const State&) {};
  loss.value = [](const State&) { return 0.0; };
  loss.adjoint = [&m](const State& s, Rows& d) {
    if (s.steps != 0) return false;
    d[row("pos")][3 * 7 + 1] = 2.5;
    d[row("lin_mom")][3 * 3] = 4.0;  // per kg m/s: per m/s of velocity, times the mass
    return true;
  };
  const Gradient g = grad::gradient_of(m, loss);
  for (size_t k = 0; k < g.initial_position.size(); ++k) {
    EXPECT_EQ(g.initial_position[k], k == 3 * 7 + 1 ? 2.5 : 0.0) << k;
    EXPECT_EQ(g.initial_velocity[k], k == 3 * 3 ? 4.0 * m.mass : 0.0) << k;
  }
  for (int i = 0; i < m.robot_n; ++i) EXPECT_EQ(g.stiffness[i], 0.0);
  // A derivative sized unlike its row is refused, naming the row, in one line.
  loss.adjoint = [](const State&, Rows& d) {
    d[row("size")].assign(3, 1.0);
    return true;
  };
  const std::string e = testing::error_of([&] { grad::gradient_of(m, loss); });
  EXPECT_NE(e.find("'size'"), std::string::npos) << e;
  EXPECT_EQ(e.find('\n'), std::string::npos);
}

// Every state of a life the engine runs.
std::vector<State> states_of(const Model& m) {
  Simulator sim(m);
  std::vector<State> out{sim.state()};
  while (sim.state().status == SimStatus::kRunning) {
    sim.step();
    out.push_back(sim.state());
  }
  return out;
}

double task_value(const Model& m, const std::vector<State>& states) {
  const TrajectoryLoss loss = grad::task_loss(m);
  for (const State& s : states) loss.see(s);
  return loss.value(states.back());
}

Rows zero_rows(const State& s) {
  Rows d;
  for (const StateField& f : kStateFields) {
    const StateFieldBytes b = f.bytes(s);
    d.emplace_back(b.kind == 'f' && b.value_bytes == sizeof(double) ? b.count : 0, 0.0);
  }
  return d;
}

// The task's loss of a recorded life against central differences of the loss itself, state by
// state: at every state it reads, the derivative with respect to each voxel centre (x, y, z)
// of the robot and the objects and to com_settled; at one it does not read, nothing. Returns
// the steps it read.
std::vector<int64_t> check_task_loss(const Model& m) {
  SCOPED_TRACE(to_string(m.def.task));
  std::vector<State> states = states_of(m);
  EXPECT_EQ(task_value(m, states), simulate(m).fitness);  // bit for bit
  const TrajectoryLoss loss = grad::task_loss(m);
  for (const State& s : states) loss.see(s);
  loss.value(states.back());
  std::vector<int64_t> read;
  for (State& s : states) {
    Rows d = zero_rows(s);
    if (!loss.adjoint(s, d)) {
      for (const auto& r : d)
        for (double v : r) EXPECT_EQ(v, 0.0);
      continue;
    }
    read.push_back(s.steps);
    std::vector<std::pair<double*, double>> checks;  // the value nudged, its derivative
    for (int i = 0; i < m.n; ++i)
      for (int k = 0; k < 3; ++k) checks.push_back({&s.pos[i][k], d[row("pos")][3 * i + k]});
    for (int k = 0; k < 3; ++k) checks.push_back({&s.com_settled[k], d[row("com_settled")][k]});
    double scale = 0;
    for (const auto& c : checks) scale = std::max(scale, std::abs(c.second));
    EXPECT_GT(scale, 0.0) << "step " << s.steps;
    for (const auto& [x, gradient] : checks) {
      const double x0 = *x, h = 1e-6 * m.size;
      const double diff = richardson(
          [&](double dx) {
            *x = x0 + dx;
            const double f = task_value(m, states);
            *x = x0;
            return f;
          },
          h);
      EXPECT_LT(std::abs(gradient - diff), 1e-6 * std::max(std::abs(diff), scale))
          << "step " << s.steps << ": gradient " << gradient << ", difference " << diff;
    }
  }
  return read;
}

// The tasks whose life the gradient runs whole (flat floor, no objects), and those whose
// environment or objects it does not differentiate yet: each one's loss, alone, on a life of
// its own environment.
TEST(TaskLoss, EveryTasksLossIsItsFitnessAndMatchesDifferencesOfItself) {
  const RobotDef body = block(1e10);
  // walk, rough, obstacles: the last state alone.
  for (Task t : {Task::kWalk, Task::kRough, Task::kObstacles}) {
    const Model m = compile(body, life(t, 0.1, 0.03));
    EXPECT_GT(simulate(m).fitness, 0.0) << to_string(t);
    EXPECT_EQ(check_task_loss(m), std::vector<int64_t>{simulate(m).steps}) << to_string(t);
  }
  // jump: the highest state after settling, which is not the last here.
  {
    const Model m = compile(body, life(Task::kJump, 0.1, 0.03));
    const std::vector<int64_t> read = check_task_loss(m);
    ASSERT_EQ(read.size(), 1u);
    EXPECT_LT(read[0], simulate(m).steps);
    EXPECT_GT(simulate(m).fitness, 0.0);
  }
  // turn: the first state after settling (the layout) and the last.
  {
    const Model m = compile(body, life(Task::kTurn, 0.1, 0.03));
    EXPECT_EQ(check_task_loss(m).size(), 2u);
    EXPECT_GT(simulate(m).fitness, 0.0);
  }
  // carry and push: their object's travel (and carry's body's) between two states.
  // push's box rides on the body here (a given object), so that it moves in so short a life.
  for (Task t : {Task::kCarry, Task::kPush}) {
    PhysicsDef def = life(t, 0.15, 0.03);
    if (t == Task::kPush) {
      ObjectDef box;
      box.voxels = {2, 2, 1};
      box.at = {0.5 * body.voxel_size, 0, 3 * body.voxel_size};
      def.environment.objects = {box};
    }
    const Model m = compile(body, def);
    EXPECT_EQ(check_task_loss(m).size(), 2u) << to_string(t);
    EXPECT_GT(simulate(m).fitness, 0.0) << to_string(t);
  }
  // climb and slope on a ramp under the whole body (a given environment), so the ground's
  // slope enters the derivative; and climb on its own terraces, on level ground.
  for (Task t : {Task::kClimb, Task::kSlope}) {
    PhysicsDef def = life(t, 0.1, 0.03);
    GroundDef& g = def.environment.ground;
    g.kind = GroundKind::kRamp;
    g.at = -1, g.edge = 0.005, g.angle_deg = -4, g.length = 2;
    const Model m = compile(body, def);
    EXPECT_EQ(check_task_loss(m).size(), 1u) << to_string(t);
    if (t == Task::kClimb) {
      EXPECT_GT(simulate(m).fitness, 0.0);
    }
  }
  EXPECT_EQ(check_task_loss(compile(body, life(Task::kClimb, 0.1, 0.03))).size(), 1u);
}

// jump and turn run whole on the flat floor: gradient()'s fitness is simulate()'s, bit for
// bit, under either bond model (nothing is refused today).
TEST(TaskLoss, GradientTakesTheModelsTaskUnderEitherBondModel) {
  for (Task t : {Task::kWalk, Task::kJump, Task::kTurn, Task::kClimb, Task::kSlope, Task::kRough,
                 Task::kObstacles, Task::kCarry, Task::kPush}) {
    const Model m = compile(block(1e10), life(t, 0.1, 0.03));
    const SimResult r = simulate(m);
    const Gradient g = grad::gradient(m);
    EXPECT_EQ(g.fitness, r.fitness) << to_string(t);
    EXPECT_EQ(g.final_state_hash, r.final_state_hash) << to_string(t);
    EXPECT_EQ(grad::replicate_life(m).fitness, r.fitness) << to_string(t);
  }
  // Under bond_model voxelyze09 too (scalar_bond_adjoint.hpp).
  PhysicsDef def = life(Task::kJump, 0.1, 0.03);
  def.bond_model = BondModel::kVoxelyze09;
  const Model m = compile(block(1e10), def);
  EXPECT_EQ(grad::gradient(m).final_state_hash, simulate(m).final_state_hash);
}

}  // namespace
}  // namespace plastivox
