// The neural controllers (docs/control.md, "Neural controllers"): deterministic, the same on
// any thread, wired to the face neighbours with one call's delay, carried by robot files,
// and refused with the field named when a definition is wrong.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <thread>

#include "plastivox/base/error.hpp"
#include "plastivox/base/rng.hpp"
#include "plastivox/demo_robots.hpp"
#include "plastivox/io/robot_file.hpp"
#include "plastivox/simd.hpp"
#include "plastivox/simulator.hpp"
#include "test_support.hpp"

namespace plastivox {
namespace {

// A controller of `kind` with weights drawn N(0, 1) from a fixed stream.
ControllerDef drawn(ControllerKind kind, int hidden, int every = 1, uint64_t seed = 7) {
  ControllerDef c;
  c.kind = kind;
  c.hidden = hidden;
  c.every = every;
  Rng rng(seed);
  c.weights.resize(weight_count(kind, hidden));
  for (double& w : c.weights) w = rng.normal();
  return c;
}

PhysicsDef short_life(double duration = 0.6) {
  PhysicsDef d = preset_gecco2018_code();
  d.treatment = Treatment::kStress;
  d.duration = duration;
  d.settle_time = 0.1;
  return d;
}

uint64_t life_hash(const RobotDef& robot, const PhysicsDef& physics) {
  return simulate(compile(robot, physics)).final_state_hash;
}

RobotDef walker_with(const ControllerDef& c) {
  RobotDef r = demo_walker();
  r.controller = c;
  return r;
}

TEST(NeuralControl, EachControllerIsDeterministicAndSteersTheBody) {
  const PhysicsDef physics = short_life();
  const uint64_t sine = life_hash(demo_walker(), physics);
  for (const ControllerDef& c :
       {drawn(ControllerKind::kDistributed, 4), drawn(ControllerKind::kDistributed, 0),
        drawn(ControllerKind::kCentral, 3), drawn(ControllerKind::kDistributed, 4, 3)}) {
    const RobotDef robot = walker_with(c);
    const SimResult a = simulate(compile(robot, physics));
    EXPECT_EQ(a.status, SimStatus::kFinished) << to_string(c.kind) << " " << a.failure;
    EXPECT_EQ(life_hash(robot, physics), a.final_state_hash) << to_string(c.kind);
    EXPECT_NE(a.final_state_hash, sine) << to_string(c.kind);
  }
  // The rate matters: every 3 steps is another life than every step.
  EXPECT_NE(life_hash(walker_with(drawn(ControllerKind::kDistributed, 4, 1)), physics),
            life_hash(walker_with(drawn(ControllerKind::kDistributed, 4, 3)), physics));
}

TEST(NeuralControl, DistributedGivesTheSameBitsOnOneAndTwoThreads) {
  const Model model = compile(walker_with(drawn(ControllerKind::kDistributed, 4)), short_life());
  const uint64_t alone = simulate(model).final_state_hash;
  uint64_t on[2] = {0, 0};
  std::thread first([&] { on[0] = simulate(model).final_state_hash; });
  std::thread second([&] { on[1] = simulate(model).final_state_hash; });
  first.join();
  second.join();
  EXPECT_EQ(on[0], alone);
  EXPECT_EQ(on[1], alone);
}

// The sensors and the sine input come through the SIMD kernels: every level gives the bits.
TEST(NeuralControl, EveryInstructionSetGivesTheSameBits) {
  const PhysicsDef physics = short_life(0.4);
  const SimdLevel best = best_simd_level();
  for (const ControllerDef& c :
       {drawn(ControllerKind::kDistributed, 3), drawn(ControllerKind::kCentral, 2)}) {
    const Model model = compile(walker_with(c), physics);
    set_simd_level(SimdLevel::kScalar);
    const uint64_t scalar = simulate(model).final_state_hash;
    for (int level = 1; level <= static_cast<int>(best); ++level) {
      set_simd_level(static_cast<SimdLevel>(level));
      EXPECT_EQ(simulate(model).final_state_hash, scalar)
          << to_string(c.kind) << " on " << to_string(static_cast<SimdLevel>(level));
    }
    set_simd_level(best);
  }
}

// A bar of two voxels along x, no hidden layer. Every signal is squash(1) = 1/2 (bias 1); the
// actuation is squash(+1 x the signal from the -x face - 1 x the signal from the +x face).
// The first call hears nothing; from the second on, voxel 1 hears voxel 0 across its -x face
// (+1/3) and voxel 0 hears voxel 1 across its +x face (-1/3).
// physics.act_max_rate bounds how fast a network's signal moves: each call at most
// act_max_rate * every * dt from the signal held, a bound this network reaches; 0 lifts it,
// and the same network then moves its signal faster.
TEST(NeuralControl, TheSignalMovesNoFasterThanActMaxRate) {
  const RobotDef robot = walker_with(drawn(ControllerKind::kCentral, 4));
  PhysicsDef physics = short_life();
  const double rate = physics.act_max_rate;
  ASSERT_GT(rate, 0);
  // The largest change of any voxel's signal in one step, over `rate` * dt.
  const auto fastest = [&](const PhysicsDef& p) {
    const Model model = compile(robot, p);
    Simulator sim(model);
    std::vector<double> before(model.n, 0.0);
    double most = 0;
    for (int k = 0; k < 400; ++k) {
      sim.step();
      const double bound = rate * sim.state().dt;  // the dt this step used
      for (int i = 0; i < model.n; ++i) {
        most = std::max(most, std::abs(sim.actuation()[i] - before[i]) / bound);
        before[i] = sim.actuation()[i];
      }
    }
    return most;
  };
  const double limited = fastest(physics);
  EXPECT_LE(limited, 1.0 + 1e-12);
  EXPECT_GT(limited, 0.99);
  physics.act_max_rate = 0;
  EXPECT_GT(fastest(physics), 2.0);
}

TEST(NeuralControl, SignalsCrossFacesWithOneCallsDelay) {
  RobotDef bar = make_empty_robot(2, 1, 1);
  for (int s = 0; s < 2; ++s) {
    bar.present[s] = 1;
    bar.stiffness[s] = 1e6;
  }
  bar.controller.kind = ControllerKind::kDistributed;
  bar.controller.hidden = 0;
  bar.controller.every = 2;
  const int inputs = kLocalInputs + kFaces;
  bar.controller.weights.assign(weight_count(ControllerKind::kDistributed, 0), 0.0);
  bar.controller.weights[1 + kLocalInputs + 0] = 1.0;   // actuation <- signal from -x
  bar.controller.weights[1 + kLocalInputs + 1] = -1.0;  // actuation <- signal from +x
  for (int f = 0; f < kFaces; ++f) bar.controller.weights[(1 + f) * (1 + inputs)] = 1.0;
  const Model model = compile(bar, short_life());
  Simulator sim(model);
  const double third = 0.5 / 1.5;
  sim.step();  // call 1, step 0
  EXPECT_EQ(sim.actuation()[0], 0.0);
  EXPECT_EQ(sim.actuation()[1], 0.0);
  sim.step();  // step 1: no call (every 2), the signal holds
  EXPECT_EQ(sim.actuation()[0], 0.0);
  sim.step();  // call 2, step 2
  EXPECT_EQ(sim.actuation()[0], -third);
  EXPECT_EQ(sim.actuation()[1], third);
  // reset() forgets the signals sent: the next call hears nothing again.
  sim.reset();
  sim.step();
  EXPECT_EQ(sim.actuation()[1], 0.0);
}

TEST(NeuralControl, ResetStartsTheSameLifeAgain) {
  const Model model = compile(walker_with(drawn(ControllerKind::kDistributed, 2)), short_life());
  Simulator fresh(model), again(model);
  for (int k = 0; k < 300; ++k) fresh.step();
  for (int k = 0; k < 200; ++k) again.step();
  again.reset();
  for (int k = 0; k < 300; ++k) again.step();
  EXPECT_EQ(state_hash(again.state()), state_hash(fresh.state()));
}

// The signals in flight are in the snapshot: a restored life continues bit for bit.
TEST(NeuralControl, SnapshotsCarryTheSignalsInFlight) {
  const Model model = compile(walker_with(drawn(ControllerKind::kDistributed, 3)), short_life());
  Simulator first(model);
  for (int k = 0; k < 250; ++k) first.step();
  const std::vector<uint8_t> snapshot = first.save_state();
  for (int k = 0; k < 250; ++k) first.step();
  Simulator second(model);
  for (int k = 0; k < 40; ++k) second.step();  // other signals in flight, to be replaced
  second.restore_state(snapshot);
  for (int k = 0; k < 250; ++k) second.step();
  EXPECT_EQ(state_hash(second.state()), state_hash(first.state()));
  // The memory is the State's (control_memory: the 7 outputs of every voxel), sized by the
  // model's controller: a Simulator of the model driven by the sine keeps it (unused) and
  // takes the network's snapshot.
  EXPECT_EQ(first.state().control_memory.size(), static_cast<size_t>(7 * model.n));
  Simulator sine(model);
  sine.set_controller(std::make_unique<SineController>());
  EXPECT_EQ(sine.save_state().size(), snapshot.size());
  sine.restore_state(snapshot);
  EXPECT_EQ(sine.state().steps, 250);
  // A snapshot of the same body without the network (no memory) is refused, naming the row.
  const Model plain = compile(walker_with(ControllerDef{}), short_life());
  EXPECT_NE(testing::error_of([&] {
              second.restore_state(Simulator(plain).save_state());
            }).find("field 'control_memory' holds 0 values"),
            std::string::npos);
}

TEST(NeuralControl, ARobotFileCarriesTheControllerAndReplaysBitForBit) {
  const PhysicsDef physics = short_life();
  EXPECT_EQ(robot_to_json(demo_walker()).find("controller"), std::string::npos);  // the default
  for (const ControllerDef& c :
       {drawn(ControllerKind::kDistributed, 4, 2), drawn(ControllerKind::kCentral, 5)}) {
    const RobotDef robot = walker_with(c);
    const RobotFile back = parse_robot_json(robot_to_json(robot, &physics), "walker.json");
    EXPECT_EQ(back.robot.controller, c);  // every weight, bit for bit
    EXPECT_EQ(life_hash(back.robot, back.physics), life_hash(robot, physics));
  }
}

TEST(NeuralControl, BadDefinitionsNameTheField) {
  const std::string head =
      R"({"format": "plastivox-robot", "version": 1, "lattice": {"nx": 1, "ny": 1, "nz": 1,
      "voxel_size": 0.01}, "voxels": [[0, 0, 0, 1e6, 0, 0]], "controller": )";
  const struct {
    std::string controller, expect;
  } cases[] = {
      {R"("neural")", "controller: expected an object"},
      {R"({"hidden": 2})", "controller.kind: missing"},
      {R"({"kind": "lstm"})",
       "controller.kind: 'lstm' is not a controller (use sine, "
       "distributed or central)"},
      {R"({"kind": "distributed", "hidden": 65, "weights": []})", "controller.hidden: must be in"},
      {R"({"kind": "distributed", "hidden": 1.5, "weights": []})", "controller.hidden"},
      {R"({"kind": "central", "hidden": 0, "weights": []})",
       "controller.hidden: must be in [1, 64]"},
      {R"({"kind": "distributed", "hidden": 0, "weights": [1, 2]})",
       "controller.weights: expected 105 numbers for distributed with hidden 0, got 2"},
      {R"({"kind": "distributed", "weights": "many"})", "controller.weights: expected an array"},
      {R"({"kind": "central", "hidden": 1, "weights": [1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12,
          13, 14, 15, 16, "x"]})",
       "controller.weights[16]"},
      {R"({"kind": "sine", "every": 0})", "controller.every: must be in [1, "},
      {R"({"kind": "sine", "gain": 2})", "controller.gain: unknown field"},
      // Written back without it, so it would not read back equal.
      {R"({"kind": "sine", "hidden": 3})", "controller.hidden: the sine has no network"},
  };
  for (const auto& c : cases) {
    const std::string msg =
        testing::error_of([&] { parse_robot_json(head + c.controller + "}", "bad.json"); });
    EXPECT_NE(msg.find("bad.json: " + c.expect), std::string::npos) << c.controller << "\n" << msg;
    EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
  }
  // Through the program: one line naming the file and the field, exit status 1.
  const std::string file = ::testing::TempDir() + "plastivox_bad_controller.json";
  std::ofstream(file) << head << R"({"kind": "distributed", "hidden": 2, "weights": [0]}})";
  const testing::Output o =
      testing::shell(std::string(PLASTIVOX_CLI) + " simulate " + file + " 2>&1");
  EXPECT_EQ(o.status, 1) << o.out;
  EXPECT_NE(o.out.find("controller.weights: expected 51 numbers"), std::string::npos) << o.out;
  EXPECT_EQ(std::count(o.out.begin(), o.out.end(), '\n'), 1) << o.out;
}

// How reports name a controller (the study's audit sentence and stats.json audit.controller).
TEST(NeuralControl, ControllerTextNamesKindHiddenUnitsAndRate) {
  EXPECT_EQ(controller_text(ControllerDef{}), "sine (open loop)");
  EXPECT_EQ(controller_text({ControllerKind::kSine, 0, 3, {}}), "sine (open loop), every 3 steps");
  EXPECT_EQ(controller_text({ControllerKind::kDistributed, 4, 1, {}}),
            "distributed, 4 hidden units, every step");
  EXPECT_EQ(controller_text({ControllerKind::kDistributed, 0, 2, {}}),
            "distributed, no hidden layer, every 2 steps");
  EXPECT_EQ(controller_text({ControllerKind::kCentral, 1, 1, {}}),
            "central, 1 hidden unit, every step");
}

}  // namespace
}  // namespace plastivox
