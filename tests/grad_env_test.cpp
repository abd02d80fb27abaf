// Gradients of lives with an environment and with free objects (engine/grad,
// docs/gradients.md, "Environments and free objects"): the ground's terraces, ramps and
// height fields, static blocks, and the payload and box the robot carries or pushes. On short
// lives the gradient of a loss of the final state of one's own (the robot's or the object's
// centre), and of climb's and carry's own fitness, agrees with central differences of the engine's
// life to 1e-6 on every kind of parameter, and the forward pass is the engine's life bit for bit.
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

// The 3x3x3 demo cube with distinct stiffness, phases and development rates (one stiffest
// voxel).
RobotDef cube3() {
  RobotDef r = demo_cube(3, 1e8);
  for (int s = 0; s < r.sites(); ++s) {
    const double u = std::sin(1.7 * s + 0.3);
    r.stiffness[s] *= 1.5 + u, r.phase[s] += 0.3 * u, r.dev_rate[s] = 2.0 + std::cos(1.3 * s);
  }
  return r;
}

// A 0.2 s life of `task` that develops under stress, settling over its first 0.05 s.
PhysicsDef short_life(Task task) {
  PhysicsDef def;
  def.task = task;
  def.duration = 0.2;
  def.settle_time = 0.05;
  def.treatment = Treatment::kStress;
  return def;
}

// The loss: the mean x of voxels [first, end) at the end of the life, plus half their mean z
// (the robot's centre, or the object's).
struct CentreLoss {
  int first, end;
  double value(const State& s) const {
    double v = 0;
    for (int i = first; i < end; ++i) v += s.pos[i].x() + 0.5 * s.pos[i].z();
    return v / (end - first);
  }
  grad::FinalLoss loss() const {
    return [*this](const State& s, std::vector<std::vector<double>>& d) {
      std::vector<double>& pos = d[&state_field("pos") - kStateFields.data()];
      for (int i = first; i < end; ++i) {
        pos[3 * size_t(i)] += 1.0 / (end - first);
        pos[3 * size_t(i) + 2] += 0.5 / (end - first);
      }
      return value(s);
    };
  }
};

// What a check differentiates: a loss of one's own (the centre of voxels [first, end) at the
// end of the life), or the model's task's own fitness (grad::gradient, simulate()'s score).
struct Objective {
  Objective(CentreLoss c) : centre(c) {}  // NOLINT: a centre loss is an objective
  Objective(int first, int end) : centre{first, end} {}
  // The task's fitness is in voxel lengths, and its derivatives with respect to an initial
  // velocity are small: at 1e-6 m/s carry's differences sit on their rounding floor (1.4e-6
  // off; 7e-7 at 1e-5, 2e-5 at 1e-7), so they step 1e-5 m/s.
  static Objective task_fitness() {
    Objective o(0, 1);
    o.task = true;
    o.velocity_step = 1e-5;
    return o;
  }
  Gradient gradient(const Model& m) const {
    return task ? grad::gradient(m) : grad::gradient_of(m, centre.loss());
  }
  double value(const Simulator& sim) const {
    return task ? sim.result().fitness : centre.value(sim.state());
  }
  CentreLoss centre;
  bool task = false;
  double velocity_step = 1e-6;  // m/s, the initial velocity's nudge
};

double final_value(const Model& m, const Objective& loss) {
  Simulator sim(m);
  while (sim.state().status == SimStatus::kRunning) sim.step();
  EXPECT_EQ(sim.state().status, SimStatus::kFinished) << sim.state().failure;
  return loss.value(sim);
}

// The branches a life takes (replicate_life's event signature), whatever its task: the
// physics do not read the task once compiled, and replicate_life scores walk.
uint64_t events_of(Model m) {
  m.def.task = Task::kWalk;
  return grad::replicate_life(m).events;
}

// One parameter: its kind, how to nudge it, and its gradient.
struct Param {
  std::string kind;
  int index;
  double h;
  std::function<void(Model&, double)> nudge;  // adds h (none: the initial velocity's)
  double gradient;
};

std::vector<Param> params_of(const Model& m, const Gradient& g, const std::vector<int>& voxels,
                             double velocity_step) {
  std::vector<Param> out;
  for (int i : voxels) {
    out.push_back({"stiffness", i, 1e-4 * m.e0[i], [i](Model& x, double h) { x.e0[i] += h; },
                   g.stiffness[i]});
    out.push_back({"phase", i, 1e-4, [i](Model& x, double h) { x.phase[i] += h; }, g.phase[i]});
    out.push_back({"dev_rate", i, 1e-2 * m.alpha[i], [i](Model& x, double h) { x.alpha[i] += h; },
                   g.dev_rate[i]});
  }
  out.push_back({"amplitude", -1, 1e-4 * m.def.act_amplitude,
                 [](Model& x, double h) {
                   x.def.act_amplitude += h;
                   x.act_amplitude_xi += h;
                   x.act_amplitude_max += h;
                 },
                 g.amplitude});
  // The initial velocity of the middle voxel, along x and z (1e-6 m/s for a loss in metres:
  // faster nudges move a contact event within the life). Not a voxel in contact: its tangential
  // velocity starts at rest, where the friction's regime changes (sticking, or slipping from rest).
  for (int k : {39, 41})
    out.push_back({"initial_velocity", k, velocity_step, nullptr, g.initial_velocity[k]});
  return out;
}

// Central differences, Richardson-extrapolated ((4 D(h/2) - D(h)) / 3, error O(h^4)), and
// whether all four nudged lives took the life's branches.
struct Difference {
  double value = 0;
  bool smooth = true;
};
Difference central(const Model& m, const Param& p, double H, const Objective& loss,
                   uint64_t events) {
  Difference d;
  double f[4];
  const double steps[4] = {H, -H, 0.5 * H, -0.5 * H};
  for (int k = 0; k < 4; ++k) {
    Model x = m;
    if (!p.nudge) {  // an initial velocity: the State's, before the first step
      Simulator sim(x);
      sim.mutable_state().lin_mom[p.index / 3][p.index % 3] += steps[k] * x.mass;
      while (sim.state().status == SimStatus::kRunning) sim.step();
      f[k] = loss.value(sim);
      continue;  // (the event signature of a nudged initial state is not replicated)
    }
    p.nudge(x, steps[k]);
    f[k] = final_value(x, loss);
    d.smooth = d.smooth && events_of(x) == events;
  }
  const double d1 = (f[0] - f[1]) / (2 * H), d2 = (f[2] - f[3]) / H;
  d.value = (4 * d2 - d1) / 3;
  return d;
}

// The differences at p.h, or where those lives cross a kink at p.h / 10, then p.h / 100: the
// largest step whose nudged lives are smooth (a life in contact crosses a kink every so often:
// a voxel passing between two cells of the ground, or its friction changing regime).
Difference smoothest(const Model& m, const Param& p, const Objective& loss, uint64_t events) {
  Difference d;
  for (double H = p.h; H >= 0.99e-2 * p.h; H *= 0.1)
    if ((d = central(m, p, H, loss, events)).smooth) break;
  return d;
}

// What a case's check found.
struct Checked {
  int smooth = 0, kinked = 0;
  std::vector<std::string> kinds;  // the kinds with at least one smooth parameter checked
};

// The gradient of `loss` on model m against central differences of every parameter of
// `voxels` (and the amplitude and an initial velocity): relative error below 1e-6 wherever the
// nudged lives take the life's branches, against the larger of the difference and 1e-3 of the
// largest difference of its kind. The forward pass is simulate()'s, bit for bit.
Checked check(const Model& m, const Objective& loss, const std::vector<int>& voxels) {
  const Gradient g = loss.gradient(m);
  const SimResult r = simulate(m);
  EXPECT_EQ(g.final_state_hash, r.final_state_hash);
  EXPECT_EQ(g.steps, r.steps);
  EXPECT_EQ(g.fitness, final_value(m, loss));
  const uint64_t events = events_of(m);
  std::vector<Param> ps = params_of(m, g, voxels, loss.velocity_step);
  std::vector<Difference> ds;
  for (const Param& p : ps) ds.push_back(smoothest(m, p, loss, events));
  Checked out;
  double largest = 0;
  for (size_t k = 0; k < ps.size(); ++k) {
    double scale = 0;
    for (size_t j = 0; j < ps.size(); ++j)
      if (ps[j].kind == ps[k].kind) scale = std::max(scale, std::abs(ds[j].value));
    const double err =
        std::abs(ps[k].gradient - ds[k].value) / std::max(std::abs(ds[k].value), 1e-3 * scale);
    if (!ds[k].smooth) {
      std::printf("  %s[%d]: nudged lives cross a kink (gradient %.6e, difference %.6e)\n",
                  ps[k].kind.c_str(), ps[k].index, ps[k].gradient, ds[k].value);
      ++out.kinked;
      continue;
    }
    ++out.smooth;
    if (std::find(out.kinds.begin(), out.kinds.end(), ps[k].kind) == out.kinds.end())
      out.kinds.push_back(ps[k].kind);
    EXPECT_GT(scale, 0.0) << ps[k].kind;
    largest = std::max(largest, err);
    EXPECT_LT(err, 1e-6) << ps[k].kind << "[" << ps[k].index << "]: gradient " << ps[k].gradient
                         << ", central difference " << ds[k].value;
  }
  std::printf("  %d parameters smooth, largest relative error %.2e; %d across a kink\n", out.smooth,
              largest, out.kinked);
  return out;
}

// Every kind of parameter was checked smooth somewhere, and most of the nudges were smooth.
void expect_every_kind(const Checked& c) {
  for (const char* kind : {"stiffness", "phase", "dev_rate", "amplitude", "initial_velocity"})
    EXPECT_NE(std::find(c.kinds.begin(), c.kinds.end(), kind), c.kinds.end()) << kind;
  EXPECT_GE(c.smooth, 3 * (c.smooth + c.kinked) / 4);
}

// Voxels on the bottom (0, 4: touching the ground), in the middle (13) and on top (22, 26).
const std::vector<int> kVoxels = {0, 4, 13, 22, 26};

// The contacts of a life, counted over its steps (voxel by voxel, or pair by pair): with the
// ground where it is level and where it is not (its normal off the vertical), with the boxes,
// and between the robot and an object. The checks below are of lives that meet what they
// check.
struct Contacts {
  int level = 0, sloped = 0, box = 0, object = 0;
};
Contacts contacts_of(const Model& m) {
  Contacts c;
  Simulator sim(m);
  const State& s = sim.state();
  while (s.status == SimStatus::kRunning) {
    sim.step();
    for (int i = 0; i < m.n; ++i) {
      const Vec3& x = s.pos[i];
      const double r = 0.5 * s.size[i];
      double normal[3];
      if (m.def.floor && m.ground.penetration(x.x(), x.y(), x.z(), r, normal) > 0)
        ++(normal[2] == 1 ? c.level : c.sloped);
      for (const ObstacleBox& b : m.def.environment.obstacles) {
        bool inside = true;
        for (int a = 0; a < 3; ++a) inside = inside && x[a] > b.min[a] - r && x[a] < b.max[a] + r;
        c.box += inside;
      }
      for (int j = m.robot_n; j < m.n && i < m.robot_n; ++j)
        c.object += (s.pos[j] - x).norm() < 0.5 * (s.size[i] + s.size[j]);
    }
  }
  std::printf("  contacts over the life: level %d, sloped %d, box %d, robot-object %d\n", c.level,
              c.sloped, c.box, c.object);
  return c;
}

// climb: the task's terraces, with the body standing across a riser of a `stairs` ground
// (the terraces' edge: a slope one node wide between two levels).
TEST(GradientEnvironment, ClimbTerracesMatchCentralDifferences) {
  PhysicsDef def = short_life(Task::kClimb);
  def.environment.ground.kind = GroundKind::kStairs;
  def.environment.ground.at = 0.012;
  def.environment.ground.edge = 0.0025;
  def.environment.ground.rise = 0.0015;
  def.environment.ground.run = 0.01;
  def.environment.ground.count = 3;
  const Model m = compile(cube3(), def);
  ASSERT_TRUE(m.terrain);
  EXPECT_GT(contacts_of(m).sloped, 0);  // on the riser
  expect_every_kind(check(m, {0, m.robot_n}, kVoxels));
  // And the task's default terraces (level under the body for 0.2 s).
  const Model terraces = compile(cube3(), short_life(Task::kClimb));
  ASSERT_TRUE(terraces.terrain);
  expect_every_kind(check(terraces, {0, terraces.robot_n}, {0, 13}));
}

// slope: a ramp under the body (a planar slope: the normal is not an axis).
TEST(GradientEnvironment, SlopeRampMatchesCentralDifferences) {
  PhysicsDef def = short_life(Task::kSlope);
  def.environment.ground.kind = GroundKind::kRamp;
  def.environment.ground.at = -0.05;
  def.environment.ground.edge = 0.005;
  def.environment.ground.angle_deg = 12;
  def.environment.ground.length = 0.2;
  const Model m = compile(cube3(), def);
  EXPECT_GT(contacts_of(m).sloped, 0);
  expect_every_kind(check(m, {0, m.robot_n}, kVoxels));
}

// rough: the task's own seeded height field (bilinear cells: normals vary within a cell).
TEST(GradientEnvironment, RoughHeightFieldMatchesCentralDifferences) {
  const Model m = compile(cube3(), short_life(Task::kRough));
  ASSERT_EQ(m.def.environment.ground.kind, GroundKind::kRough);
  EXPECT_GT(contacts_of(m).sloped, 0);
  expect_every_kind(check(m, {0, m.robot_n}, kVoxels));
}

// obstacles: blocks, one under part of the body (its top face) and one against its side.
TEST(GradientEnvironment, ObstacleBlocksMatchCentralDifferences) {
  PhysicsDef def = short_life(Task::kObstacles);
  def.environment.ground.kind = GroundKind::kFlat;
  def.environment.obstacles.push_back({{0.012, -0.01, -0.01}, {0.04, 0.04, 0.002}});
  def.environment.obstacles.push_back({{-0.03, -0.01, -0.01}, {0.0005, 0.04, 0.05}});
  const Model m = compile(cube3(), def);
  ASSERT_TRUE(m.terrain);
  EXPECT_GT(contacts_of(m).box, 0);
  expect_every_kind(check(m, {0, m.robot_n}, kVoxels));
}

// carry: the task's payload on the body's back (free-object contact through the collision
// lists, on the flat floor's kernel); the loss is the payload's centre.
TEST(GradientEnvironment, CarryPayloadMatchesCentralDifferences) {
  const Model m = compile(cube3(), short_life(Task::kCarry));
  ASSERT_GT(m.n, m.robot_n);
  EXPECT_FALSE(m.terrain);
  EXPECT_GT(contacts_of(m).object, 0);
  expect_every_kind(check(m, {m.robot_n, m.n}, kVoxels));
}

// push: a box against the body's +x face (the task's box, moved up to touch), on a level
// ground of the environment's (the terrain's contact, not the floor's kernel, under the body
// and the box); the loss is the box's centre.
TEST(GradientEnvironment, PushBoxMatchesCentralDifferences) {
  PhysicsDef def = short_life(Task::kPush);
  def.environment.ground.kind = GroundKind::kFlat;
  ObjectDef box;
  box.voxels = {2, 2, 2};
  box.at = {0.029, 0.005, 0.0};
  def.environment.objects.push_back(box);
  const Model m = compile(cube3(), def);
  ASSERT_EQ(m.n, m.robot_n + 8);
  ASSERT_TRUE(m.terrain);
  EXPECT_GT(contacts_of(m).object, 0);
  expect_every_kind(check(m, {m.robot_n, m.n}, kVoxels));
}

// The tasks' own fitness through these lives (grad::gradient, task_losses.cpp): climb's
// distance plus its weighted height on the task's default terraces, and carry's lesser travel of
// the payload and the body, against central differences of simulate()'s score.
TEST(GradientEnvironment, ClimbAndCarryFitnessMatchCentralDifferences) {
  for (Task t : {Task::kClimb, Task::kCarry}) {
    const Model m = compile(cube3(), short_life(t));
    ASSERT_GT(simulate(m).fitness, 0.0) << to_string(t);
    std::printf(" %s\n", to_string(t));
    expect_every_kind(check(m, Objective::task_fitness(), {0, 13, 26}));
  }
}

// A thin box's stop (terrain.cpp, "Thin boxes"): a body dropped half a metre onto a plate
// reaches 3 m/s, over a centimetre a step, crosses the grown plate's middle plane within a
// step and is put back at its face, its vertical momentum zeroed. The replica takes the same
// stops (gradient_of checks it at every snapshot), and the gradient agrees with central
// differences through them.
TEST(GradientEnvironment, ThinBoxStopIsTheEnginesLife) {
  RobotDef r = make_empty_robot(2, 1, 1);
  for (int s = 0; s < 2; ++s) r.present[s] = 1, r.stiffness[s] = 1e8, r.phase[s] = 0.3 * s;
  PhysicsDef def;
  def.floor = false;
  def.duration = 0.4;
  def.settle_time = 0.05;
  def.environment.obstacles.push_back({{-0.5, -0.5, -0.5}, {0.5, 0.5, -0.499}});
  const Model m = compile(r, def);
  // The engine's life stops the voxel: a step ends with it at the plate, its vertical momentum
  // exactly 0 (no penalty contact gives that).
  Simulator sim(m);
  int stops = 0;
  while (sim.state().status == SimStatus::kRunning) {
    sim.step();
    stops += sim.state().pos[0].z() < -0.4 && sim.state().lin_mom[0].z() == 0;
  }
  ASSERT_EQ(sim.state().status, SimStatus::kFinished) << sim.state().failure;
  EXPECT_GT(stops, 0);
  const CentreLoss loss{0, 1};
  const Gradient g = grad::gradient_of(m, loss.loss());
  EXPECT_EQ(g.final_state_hash, sim.result().final_state_hash);
  for (int k : {0, 2}) {  // a start sideways, and downwards
    const Param p{"initial_velocity", k, 1e-6, nullptr, g.initial_velocity[k]};
    const Difference d = central(m, p, p.h, loss, 0);
    EXPECT_TRUE(testing::RelNear(p.gradient, d.value, 1e-6)) << "initial velocity " << k;
  }
}

// A neural controller's touch sensor reads the environment's ground (control.cpp): the
// replica's does too, so a network's life on rough ground is the engine's (gradient_of checks
// the replica against it at every snapshot, and throws where they part), and the gradient of
// its weights agrees with central differences. So is its life carrying a payload.
TEST(GradientEnvironment, NetworkOnRoughGroundAndCarryingIsTheEnginesLife) {
  RobotDef r = cube3();
  r.controller.kind = ControllerKind::kDistributed;
  r.controller.hidden = 2;
  for (int k = 0; k < weight_count(r.controller.kind, r.controller.hidden); ++k)
    r.controller.weights.push_back(0.8 * std::sin(1.3 * k + 0.7));
  const Model m = compile(r, short_life(Task::kRough));
  const CentreLoss loss{0, m.robot_n};
  const Gradient g = grad::gradient_of(m, loss.loss());
  EXPECT_EQ(g.final_state_hash, simulate(m).final_state_hash);
  const uint64_t events = events_of(m);
  int smooth = 0;
  for (int k : {0, 7, 15}) {
    const Param p{"weight", k, 3e-4 * std::max(std::abs(m.controller.weights[k]), 1e-2),
                  [k](Model& x, double h) { x.controller.weights[k] += h; },
                  g.controller_weights[k]};
    const Difference d = smoothest(m, p, loss, events);
    if (!d.smooth) continue;
    ++smooth;
    EXPECT_TRUE(testing::RelNear(p.gradient, d.value, 1e-6)) << "weight " << k;
  }
  EXPECT_GE(smooth, 2);
  // And with carry's payload on its back (the network's sensors see the object's voxels too).
  const Model carry = compile(r, short_life(Task::kCarry));
  const CentreLoss payload{carry.robot_n, carry.n};
  EXPECT_EQ(grad::gradient_of(carry, payload.loss()).final_state_hash,
            simulate(carry).final_state_hash);
}

}  // namespace
}  // namespace plastivox
