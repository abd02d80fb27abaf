// State's field table (kStateFields, state.hpp): it covers every field, drives state_hash,
// and matches docs/engine.md; a life driven through the public halves of the step ends where
// simulate() does; and a State copied into another Simulator carries everything the rest of
// the life depends on.
#include <fstream>
#include <set>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "plastivox/demo_robots.hpp"
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
    ASSERT_GT(b.count, 0u) << f.name;
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
                    sizeof s.stim_ref_set + sizeof s.settled + 3 * sizeof(double);
  expected += m.n * (3 + 4 + 3 + 3 + 5) * sizeof(double) + m.n * sizeof(uint8_t);
  expected += m.bond_count() * (9 * sizeof(double) + 2 * sizeof(uint8_t));
  EXPECT_EQ(bytes, expected);
}

TEST(StateFields, DocsListEveryFieldWithItsUnit) {
  std::ifstream in(std::string(PLASTIVOX_SOURCE_DIR) + "/docs/engine.md");
  std::stringstream text;
  text << in.rdbuf();
  const std::string doc = text.str();
  for (const StateField& f : kStateFields) {
    const std::string row = std::string("| `") + f.name + "` | " + f.shape + " | " + f.unit +
                            " | " + f.frame + " | " + f.meaning + " |";
    EXPECT_NE(doc.find(row), std::string::npos) << "docs/engine.md lacks the row " << row;
  }
}

// The two public halves, called with nothing between them, are step(): the life ends where
// simulate() ends it, at the same hash, and the Simulator says it finished.
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

}  // namespace
}  // namespace plastivox
