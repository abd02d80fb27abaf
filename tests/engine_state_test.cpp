// State's field table (kStateFields, state.hpp): it covers every field, drives state_hash,
// and matches docs/engine.md; a life driven through the public halves of the step ends where
// simulate() does; and a State copied into another Simulator carries everything the rest of
// the life depends on.
#include <algorithm>
#include <cstring>
#include <fstream>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

#include "plastivox/demo_robots.hpp"
#include "plastivox/model_fields.hpp"
#include "plastivox/simulator.hpp"
#include "test_support.hpp"

namespace plastivox {
namespace {

Model developing_walker(double duration) {
  PhysicsDef d = preset_gecco2018_code();
  d.treatment = Treatment::kStress;
  d.duration = duration;
  return compile(demo_walker(), d);
}

TEST(StateFields, EveryByteOfEveryFieldIsInTheHash) {
  const Model m = developing_walker(0.5);
  Simulator sim(m);
  testing::run_until(sim, 0.3);  // settled, actuated, developing: no field at its start value
  State s = sim.state();
  const uint64_t h = state_hash(s);
  std::set<std::string> names;
  size_t bytes = 0;
  for (const StateField& f : kStateFields) {
    EXPECT_TRUE(names.insert(f.name).second) << f.name << " listed twice";
    const StateFieldBytes b = f.bytes(s);
    if (b.count == 0) {  // the sine remembers nothing
      EXPECT_STREQ(f.name, "control_memory");
      continue;
    }
    bytes += b.count * b.value_bytes;
    // Change the field's last byte (a bool or status stays a valid value: 1 <-> 0, a
    // double's lowest mantissa bit): the hash sees it.
    auto* last = const_cast<unsigned char*>(static_cast<const unsigned char*>(b.data)) +
                 b.count * b.value_bytes - b.value_bytes;
    last[0] ^= 1;
    EXPECT_NE(state_hash(s), h) << f.name << " is not in the hash";
    last[0] ^= 1;
    EXPECT_EQ(state_hash(s), h) << f.name;
  }
  // Every byte of State's arrays and values is in some field (the failure text aside).
  size_t expected = sizeof s.time + sizeof s.steps + sizeof s.dt + sizeof s.status +
                    sizeof s.stim_ref_set + sizeof s.settled + 3 * sizeof(double) +
                    sizeof s.floor_deepest + sizeof s.floor_deep_most + sizeof s.task_values;
  // pos, orient, momenta, stiffness, size, stimulus, its integral and reference, the
  // actuation signal, the turn's layout (2).
  expected += m.n * (3 + 4 + 3 + 3 + 5 + 1 + 2) * sizeof(double) + m.n * sizeof(uint8_t);
  expected += m.bond_count() * (9 * sizeof(double) + 2 * sizeof(uint8_t));
  EXPECT_EQ(bytes, expected);
}

TEST(StateFields, DocsListEveryFieldWithItsUnit) {
  testing::expect_doc_lists_every_field("docs/engine.md", kStateFields);
}

// The Model's table: every row reads the model's own numbers, and docs/engine.md lists it.
TEST(ModelFields, EveryRowReadsTheModelAndTheDocsListIt) {
  const Model m = developing_walker(0.5);
  std::set<std::string> names;
  for (const ModelField& f : kModelFields) {
    EXPECT_TRUE(names.insert(f.name).second) << f.name << " listed twice";
    const StateFieldBytes b = f.bytes(m);
    EXPECT_GT(b.count, 0u) << f.name;
    EXPECT_EQ(b.count % b.width, 0u) << f.name;
  }
  const auto first = [&](const char* name) { return model_field(name).bytes(m).data; };
  EXPECT_EQ(*static_cast<const int*>(first("n")), m.n);
  EXPECT_EQ(*static_cast<const double*>(first("mass")), m.mass);
  EXPECT_EQ(*static_cast<const double*>(first("kb3")), m.kb3);
  EXPECT_EQ(static_cast<const double*>(first("weight"))[2], m.weight[2]);
  EXPECT_EQ(first("rest_pos"), m.rest_pos.data());
  EXPECT_EQ(model_field("rest_pos").bytes(m).count, static_cast<size_t>(3 * m.n));
  EXPECT_EQ(model_field("voxel_bonds").bytes(m).count, static_cast<size_t>(6 * m.n));
  EXPECT_EQ(static_cast<const int*>(first("voxel_bonds"))[6 * 2 + 1], m.voxel_bonds[2][1]);
  EXPECT_EQ(model_field("bond_a").bytes(m).count, static_cast<size_t>(m.bond_count()));
  EXPECT_THROW(model_field("no_such_field"), std::invalid_argument);
  testing::expect_doc_lists_every_field("docs/engine.md", kModelFields);
}

// The two public halves, called with nothing between them, are step(): the life ends where
// simulate() ends it, at the same hash, and the Simulator says it finished.
// Each recorded channel copies a State field of its width, bit for bit, and an array made of
// the frames (file and Python order) comes back to the same frames.
TEST(FrameFields, EachChannelCopiesItsStateFieldAndRoundTrips) {
  const Model m = developing_walker(0.5);
  Simulator sim(m);
  testing::run_until(sim, 0.3);
  const Frame frame = capture_frame(sim.state());
  std::set<std::string> names;
  for (const FrameField& f : kFrameFields) {
    EXPECT_TRUE(names.insert(f.name).second) << f.name;
    const StateFieldBytes b = state_field(f.state_field).bytes(sim.state());
    ASSERT_EQ(b.kind, 'f') << f.name;
    ASSERT_EQ(b.width, static_cast<size_t>(f.width)) << f.name;
    ASSERT_EQ(b.count, static_cast<size_t>(m.n) * b.width) << f.name;
    EXPECT_EQ(std::memcmp(f.values(frame), b.data, b.count * sizeof(double)), 0) << f.name;
    std::set<int> order(f.order, f.order + f.width);  // a permutation of the components
    EXPECT_EQ(order.size(), static_cast<size_t>(f.width)) << f.name;
    EXPECT_EQ(*order.begin(), 0) << f.name;
    EXPECT_EQ(*order.rbegin(), f.width - 1) << f.name;
  }
  EXPECT_THROW(state_field("no_such_field"), std::invalid_argument);
  const std::vector<Frame> frames = {frame, capture_frame(sim.state())};
  std::vector<Frame> back(frames.size());
  for (const FrameField& f : kFrameFields) {
    const std::vector<double> values = frame_channel(frames, f);
    ASSERT_EQ(values.size(), frames.size() * static_cast<size_t>(m.n * f.width));
    set_frame_channel(back, f, static_cast<size_t>(m.n), values.data());
  }
  for (size_t k = 0; k < frames.size(); ++k)
    for (const FrameField& f : kFrameFields)
      EXPECT_EQ(std::memcmp(f.values(back[k]), f.values(frames[k]),
                            static_cast<size_t>(m.n * f.width) * sizeof(double)),
                0)
          << f.name;
  // The quaternion is w first outside the engine, as the file formats hold it.
  const auto orientation = std::find_if(kFrameFields.begin(), kFrameFields.end(),
                                        [](const FrameField& f) { return f.width == 4; });
  ASSERT_NE(orientation, kFrameFields.end());
  const std::vector<double> q = frame_channel({frame}, *orientation);
  EXPECT_EQ(q[0], frame.orient[0].w());
  EXPECT_EQ(q[1], frame.orient[0].x());
}

TEST(SimulatorStages, ALifeDrivenThroughStep1AndStep2EndsAtSimulatesHash) {
  const Model m = developing_walker(1.0);
  const SimResult whole = simulate(m);
  ASSERT_EQ(whole.status, SimStatus::kFinished) << whole.failure;
  Simulator sim(m);
  int64_t steps = 0;
  while (sim.state().status == SimStatus::kRunning) {
    sim.step1();
    sim.step2();
    ++steps;
  }
  EXPECT_EQ(sim.state().status, SimStatus::kFinished);
  EXPECT_GT(sim.state().time, m.def.duration);
  EXPECT_EQ(steps, whole.steps);
  EXPECT_EQ(state_hash(sim.state()), whole.final_state_hash);
  // A finished life takes no more steps.
  sim.step();
  EXPECT_EQ(sim.state().steps, whole.steps);
}

// State is the whole state: a life stopped 1 s in (developing, actuated, stiffness and dt
// changing every step), its State copied into a new Simulator and continued, ends at the
// same bits as the uninterrupted life.
TEST(Determinism, CopiedStateContinuesBitIdentically) {
  for (Treatment t : {Treatment::kStress, Treatment::kPressure}) {
    PhysicsDef d = preset_gecco2018_code();
    d.treatment = t;
    d.duration = 1.5;
    const Model m = compile(demo_walker(), d);
    const SimResult whole = simulate(m);
    ASSERT_EQ(whole.status, SimStatus::kFinished) << whole.failure;

    Simulator first(m);
    testing::run_until(first, 1.0);
    ASSERT_EQ(first.state().status, SimStatus::kRunning);
    Simulator second(m);
    second.mutable_state() = first.state();
    while (second.state().status == SimStatus::kRunning) second.step();
    EXPECT_EQ(state_hash(second.state()), whole.final_state_hash) << to_string(t);
    EXPECT_EQ(second.state().stiffness, whole.final_stiffness) << to_string(t);
  }
}

// save_state/restore_state (state.hpp, driven by kStateFields): k steps, save, m more;
// back to the snapshot, m more again; and m more from the snapshot in a fresh Simulator of
// the same model: all three end at the same bits. Under both bond models (Voxelyze 0.9's
// switches frames per bond: bond_small_angle must carry over).
TEST(Determinism, RestoredStateContinuesBitIdentically) {
  for (BondModel bonds : {BondModel::kExact, BondModel::kVoxelyze09}) {
    PhysicsDef d = preset_gecco2018_code();
    d.treatment = Treatment::kStress;
    d.bond_model = bonds;
    d.duration = 1.0;
    const Model m = compile(demo_walker(), d);
    const auto run = [](Simulator& sim, int steps) {
      for (int i = 0; i < steps && sim.state().status == SimStatus::kRunning; ++i) sim.step();
    };
    Simulator sim(m);
    testing::run_until(sim, 0.6);  // settled, actuated, developing
    ASSERT_EQ(sim.state().status, SimStatus::kRunning);
    const std::vector<uint8_t> snapshot = sim.save_state();
    const uint64_t at_save = state_hash(sim.state());
    run(sim, 500);
    const uint64_t after = state_hash(sim.state());
    ASSERT_NE(after, at_save);

    sim.restore_state(snapshot);
    EXPECT_EQ(state_hash(sim.state()), at_save);
    run(sim, 500);
    EXPECT_EQ(state_hash(sim.state()), after);

    Simulator fresh(m);
    fresh.restore_state(snapshot);
    EXPECT_EQ(state_hash(fresh.state()), at_save);
    run(fresh, 500);
    EXPECT_EQ(state_hash(fresh.state()), after);
    EXPECT_EQ(fresh.save_state(), sim.save_state());
  }
}

// A snapshot of another model's state, or a damaged one, is refused with a line naming the
// field, and the state is left as it was.
TEST(StateSnapshot, MismatchedOrDamagedSnapshotsAreRefused) {
  const Model walker = developing_walker(0.5);
  const Model cube = compile(demo_cube(2, 1e7), preset_gecco2018_code());
  Simulator sim(walker);
  testing::run_until(sim, 0.1);
  const uint64_t before = state_hash(sim.state());
  const auto refused = [&](const std::vector<uint8_t>& snapshot, const std::string& says) {
    try {
      sim.restore_state(snapshot);
      ADD_FAILURE() << "accepted a snapshot that should say: " << says;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(says), std::string::npos) << e.what();
    }
    EXPECT_EQ(state_hash(sim.state()), before);
  };
  refused(Simulator(cube).save_state(), "field 'pos' holds");

  // The State's own format, which a Simulator's snapshot is (the signal, the controller's
  // memory and the watches are rows of the State).
  const std::vector<uint8_t> good = save_state(sim.state());
  EXPECT_EQ(good, sim.save_state());
  refused(std::vector<uint8_t>(good.begin(), good.end() - 3), "ends inside the failure text");
  refused(std::vector<uint8_t>(good.begin(), good.begin() + 40), "ends inside field");
  std::vector<uint8_t> longer = good;
  longer.push_back(0);
  refused(longer, "1 bytes past the end");
  std::vector<uint8_t> header = good;
  header[0] ^= 1;
  refused(header, "not a plastivox state");
  refused({}, "ends inside the header");
  // A bool field holding 2.
  std::vector<uint8_t> bad_bool = good;
  size_t settled_byte = 16;  // past the header: each row is its count, value size and bytes
  for (const StateField& f : kStateFields) {
    settled_byte += 16;
    if (std::string(f.name) == "settled") break;
    const StateFieldBytes b = f.bytes(sim.state());
    settled_byte += b.count * b.value_bytes;
  }
  bad_bool[settled_byte] = 2;
  refused(bad_bool, "field 'settled' is not 0 or 1");

  sim.restore_state(good);  // and the good one is taken
  EXPECT_EQ(state_hash(sim.state()), before);
}

}  // namespace
}  // namespace plastivox
