// Control (plastivox/control.hpp, docs/control.md): the actuation signal, the sine as one
// controller among others, the control rate, the sensors, per-voxel actuation scales.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <memory>
#include <sstream>
#include <stdexcept>

#include "plastivox/base/error.hpp"
#include "plastivox/control.hpp"
#include "plastivox/demo_robots.hpp"
#include "plastivox/io/robot_file.hpp"
#include "plastivox/simulator.hpp"
#include "test_support.hpp"

namespace plastivox {
namespace {

Model walker(Treatment t, double duration) {
  PhysicsDef d = preset_gecco2018_code();
  d.treatment = t;
  d.duration = duration;
  return compile(demo_walker(), d);
}

uint64_t run_life(Simulator& sim) {
  while (sim.state().status == SimStatus::kRunning) sim.step();
  return state_hash(sim.state());
}

// Reverses the sine wherever the voxel touches the floor: a closed loop that reads a sensor.
class ReverseOnTouch final : public Controller {
 public:
  void act(const Sensors& sensors, std::span<double> actuation, std::span<double> m) override {
    sine_.act(sensors, actuation, m);
    const std::span<const double> touch = sensors.read(Sensor::kTouch);
    for (size_t i = 0; i < actuation.size(); ++i)
      if (touch[i] == 1.0) actuation[i] = -actuation[i];
  }

 private:
  SineController sine_;
};

// Counts its calls and writes the step count into the signal (scaled into [-1, 1]).
class Counting final : public Controller {
 public:
  void act(const Sensors& sensors, std::span<double> actuation, std::span<double>) override {
    ++calls;
    for (double& u : actuation) u = std::sin(0.01 * static_cast<double>(sensors.state().steps));
  }
  void reset() override { calls = 0; }
  int calls = 0;
};

TEST(Control, SineIsTheDefaultAndAnExternalReplayOfItGivesTheSameBits) {
  const Model m = walker(Treatment::kStress, 1.0);
  const uint64_t built_in = simulate(m).final_state_hash;

  Simulator explicit_sine(m);
  explicit_sine.set_controller(std::make_unique<SineController>());
  EXPECT_EQ(run_life(explicit_sine), built_in);

  // No controller: the caller writes the signal between the halves of every step, from the
  // sensors' time and the model's phases, with the engine's own sine.
  Simulator replay(m);
  replay.set_controller(nullptr);
  while (replay.state().status == SimStatus::kRunning) {
    const double t = replay.sensors().read(Sensor::kTime)[0];
    std::span<double> u = replay.actuation();
    for (int i = 0; i < m.n; ++i) u[i] = sin_cycles_of(m.def.act_frequency * t + m.phase[i]);
    replay.step2();
  }
  EXPECT_EQ(state_hash(replay.state()), built_in);
}

// The batch sine (vectorised, what Python's sin_cycles calls) gives the scalar one's bits.
TEST(Control, BatchSineIsTheScalarSine) {
  std::vector<double> u;
  for (int k = -4000; k <= 4000; ++k) u.push_back(k * 0.00123456789 + 1e-3 / (k + 0.5));
  for (int k = -8; k <= 8; ++k) u.push_back(k / 4.0 + (k == 0 ? 0.5 : 0.0));
  std::vector<double> out(u.size());
  sin_cycles_of(u, out);
  for (size_t i = 0; i < u.size(); ++i) EXPECT_EQ(out[i], sin_cycles_of(u[i])) << u[i];
}

TEST(Control, ReversingActuationOnTouchChangesTheGaitDeterministically) {
  const Model m = walker(Treatment::kNone, 2.0);
  const SimResult sine = simulate(m);
  ASSERT_EQ(sine.status, SimStatus::kFinished);
  uint64_t hashes[2];
  Vec3 com[2];
  for (int k = 0; k < 2; ++k) {
    Simulator sim(m);
    sim.set_controller(std::make_unique<ReverseOnTouch>());
    hashes[k] = run_life(sim);
    ASSERT_EQ(sim.state().status, SimStatus::kFinished) << sim.state().failure;
    com[k] = center_of_mass(sim.state());
  }
  EXPECT_EQ(hashes[0], hashes[1]);
  EXPECT_NE(hashes[0], sine.final_state_hash);
  // A different gait, not a different rounding: the body ends elsewhere.
  EXPECT_GT((com[0] - sine.com_final).norm(), 0.01 * m.size);
}

TEST(Control, ControlRateHoldsTheSignalAndSnapshotsCarryIt) {
  const Model m = walker(Treatment::kStress, 0.8);
  Simulator sim(m);
  auto counting = std::make_unique<Counting>();
  Counting* c = counting.get();
  sim.set_controller(std::move(counting), 4);
  EXPECT_EQ(sim.control_every(), 4);
  testing::run_until(sim, 0.5);
  const int64_t steps = sim.state().steps;
  EXPECT_EQ(c->calls, (steps + 3) / 4);
  // Mid-hold (steps % 4 != 0): the held signal is in the snapshot.
  while (sim.state().steps % 4 != 2) sim.step();
  const std::vector<uint8_t> snapshot = sim.save_state();
  const uint64_t end = run_life(sim);
  Simulator fresh(m);
  fresh.set_controller(std::make_unique<Counting>(), 4);
  fresh.restore_state(snapshot);
  EXPECT_EQ(run_life(fresh), end);
  // The same life at every step differs.
  Simulator every(m);
  every.set_controller(std::make_unique<Counting>(), 1);
  EXPECT_NE(run_life(every), end);

  EXPECT_THROW(sim.set_controller(nullptr, 0), std::invalid_argument);
}

TEST(Control, SnapshotsBetweenTheHalvesAreTheStateBeforeTheStepAndResetStartsAgain) {
  const Model m = walker(Treatment::kStress, 0.5);
  const uint64_t whole = simulate(m).final_state_hash;
  Simulator sim(m);
  testing::run_until(sim, 0.3);
  const std::vector<uint8_t> before = sim.save_state();
  (void)sim.sensors();  // runs step1, which writes only the workspace
  EXPECT_EQ(sim.save_state(), before);
  sim.step();  // finishes the step
  EXPECT_NE(sim.save_state(), before);
  sim.reset();
  EXPECT_EQ(sim.state().steps, 0);
  EXPECT_EQ(run_life(sim), whole);
}

TEST(Sensors, TableFollowsTheEnumAndShapes) {
  const Model m = walker(Treatment::kStress, 0.5);
  Simulator sim(m);
  const Sensors s = sim.sensors();
  for (int k = 0; k < kSensorCount; ++k) {
    const SensorField& f = kSensorFields[k];
    EXPECT_EQ(static_cast<int>(f.id), k) << f.name;
    const size_t expected = f.per_voxel ? static_cast<size_t>(m.n * f.width) : f.width;
    EXPECT_EQ(s.read(f.id).size(), expected) << f.name;
    EXPECT_EQ(s.read(f.id).data(), s.read(f.id).data()) << f.name << ": computed once a step";
  }
}

TEST(Sensors, DocsListEverySensorWithItsUnit) {
  testing::expect_doc_lists_every_field("docs/control.md", kSensorFields);
}

// A stiff block resting on the floor: the bottom layer touches and carries the weight, the
// top does not; every voxel upright and (nearly) at rest.
// A resting block: its bottom layer touches, and the contact forces sum to its weight.
void expect_bottom_touches_and_carries_the_weight(const Model& m, const Sensors& s,
                                                  const char* where) {
  const auto touch = s.read(Sensor::kTouch), force = s.read(Sensor::kFloorForce);
  double total = 0, lowest = m.rest_pos[0].z();  // the bottom layer's centres, m
  for (const Vec3& p : m.rest_pos) lowest = std::min(lowest, p.z());
  for (int i = 0; i < m.n; ++i) {
    const bool bottom = m.rest_pos[i].z() < lowest + 0.5 * m.size;
    EXPECT_EQ(touch[i], bottom ? 1.0 : 0.0) << i << " " << where;
    EXPECT_EQ(force[i] > 0, bottom) << i << " " << where;
    total += force[i];
  }
  EXPECT_TRUE(testing::RelNear(total, -m.n * m.mass * m.def.gravity, 0.02))  // gravity < 0
      << total << " " << where;
}

TEST(Sensors, ARestingBlockTouchesWithItsBottomAndCarriesItsWeight) {
  PhysicsDef d = testing::passive_physics();
  d.duration = 1.0;
  d.density = 1e6;  // a 1 kg voxel: pressed 1e-3 voxel lengths into the floor
  const Model m = compile(testing::block(3, 3, 2, 1e8), d);
  Simulator sim(m);
  testing::run_until(sim, 0.8);
  const Sensors s = sim.sensors();
  expect_bottom_touches_and_carries_the_weight(m, s, "on the floor");
  const auto up = s.read(Sensor::kUp), v = s.read(Sensor::kVelocity);
  for (int i = 0; i < m.n; ++i) {
    EXPECT_NEAR(up[3 * i + 2], 1.0, 1e-6);
    for (int c = 0; c < 3; ++c) EXPECT_EQ(v[3 * i + c], sim.state().lin_mom[i][c] / m.mass);
  }
  const auto com = s.read(Sensor::kComVelocity);
  EXPECT_LT(std::hypot(com[0], com[1], com[2]), 1e-3);
  EXPECT_EQ(s.read(Sensor::kTime)[0], sim.state().time);
}

// In an environment the same: a block that fell onto a ground 1 cm below the floor's level,
// and one resting on a box, touch with their bottom layer and carry their weight.
TEST(Sensors, OnAGroundOrABoxTheBottomTouchesAndCarriesTheWeight) {
  for (const bool on_box : {false, true}) {
    PhysicsDef d = testing::passive_physics();
    d.duration = 1.0;
    d.density = 1e6;
    if (on_box) {
      d.floor = false;  // only the box holds it
      d.environment.obstacles.push_back({{-0.05, -0.05, -0.02}, {0.08, 0.08, -0.005}});
    } else {
      d.environment.ground.kind = GroundKind::kFlat;
      d.environment.ground.height = -0.01;
    }
    const Model m = compile(testing::block(3, 3, 2, 1e8), d);
    Simulator sim(m);
    testing::run_until(sim, 0.8);
    expect_bottom_touches_and_carries_the_weight(m, sim.sensors(),
                                                 on_box ? "on a box" : "on a ground");
  }
}

// strain, stress and pressure are the development stimuli of this step: under a treatment the
// sensor read between the halves is the stimulus step2 then stores, bit for bit.
TEST(Sensors, StimuliAreTheDevelopmentStimuliOfTheStep) {
  for (auto [t, id] : {std::pair{Treatment::kStress, Sensor::kStress},
                       std::pair{Treatment::kPressure, Sensor::kPressure},
                       std::pair{Treatment::kStrain, Sensor::kStrain}}) {
    const Model m = walker(t, 0.6);
    Simulator sim(m);
    testing::run_until(sim, 0.5);
    const std::span<const double> sensed = sim.sensors().read(id);
    const std::vector<double> copy(sensed.begin(), sensed.end());
    sim.step2();
    EXPECT_EQ(copy, sim.state().stimulus) << to_string(t);
    double largest = 0;
    for (double v : copy) largest = std::max(largest, std::abs(v));
    EXPECT_GT(largest, 0) << to_string(t);
  }
}

TEST(Sensors, PhaseIsTheSinesPhaseInACycle) {
  const Model m = walker(Treatment::kNone, 0.5);
  Simulator sim(m);
  testing::run_until(sim, 0.37);
  const double t = sim.state().time;
  const double phase = sim.sensors().read(Sensor::kPhase)[0];
  EXPECT_GE(phase, 0);
  EXPECT_LT(phase, 1);
  EXPECT_NEAR(phase, std::fmod(m.def.act_frequency * t, 1.0), 1e-12);
}

// act_scale: 0 makes passive tissue (the size never moves), 1 everywhere changes no bit; the
// robot file carries it and reads it back; a bad value is named.
TEST(ActuationScale, PassiveTissueAndRoundTrip) {
  PhysicsDef d = preset_gecco2018_code();
  d.duration = 0.6;
  RobotDef r = demo_walker();
  const uint64_t plain = simulate(compile(r, d)).final_state_hash;
  r.act_scale.assign(r.sites(), 1.0);
  EXPECT_EQ(simulate(compile(r, d)).final_state_hash, plain);

  int passive = -1;  // the first voxel, made passive
  for (int s = 0; s < r.sites() && passive < 0; ++s)
    if (r.present[s]) passive = s;
  r.act_scale[passive] = 0.0;
  const Model m = compile(r, d);
  Simulator sim(m);
  bool others_move = false;
  while (sim.state().status == SimStatus::kRunning) {
    sim.step();
    EXPECT_EQ(sim.state().size[0], m.size);
    others_move = others_move || sim.state().size[1] != m.size;
  }
  EXPECT_TRUE(others_move);

  r.act_scale[passive] = 0.25;
  const RobotFile back = parse_robot_json(robot_to_json(r, nullptr), "inline.json");
  EXPECT_EQ(back.robot.act_scale, r.act_scale);
  const RobotFile unscaled = parse_robot_json(robot_to_json(demo_walker(), nullptr), "u.json");
  EXPECT_TRUE(unscaled.robot.act_scale.empty());

  const std::string bad = testing::error_of([&] {
    parse_robot_json(R"({"format": "plastivox-robot", "version": 1,
      "lattice": {"nx": 2, "ny": 1, "nz": 1, "voxel_size": 0.01},
      "voxels": [[0, 0, 0, 1e7, 0, 0], [1, 0, 0, 1e7, 0, 0]], "act_scale": [1, 1.5]})",
                     "bad.json");
  });
  EXPECT_NE(bad.find("bad.json"), std::string::npos) << bad;
  EXPECT_NE(bad.find("act_scale[1]"), std::string::npos) << bad;
}

}  // namespace
}  // namespace plastivox
