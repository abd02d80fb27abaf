// simulate()'s options: frames recorded at a rate or at given times, a frame callback that can
// end the life, progress reports and per-stage timings, none of which changes the bits.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "plastivox/demo_robots.hpp"
#include "plastivox/life.hpp"
#include "test_support.hpp"

namespace plastivox {
namespace {

TEST(Recording, SixtyFramesPerSimulatedSecondOfEveryVoxel) {
  PhysicsDef d;
  d.treatment = Treatment::kStress;
  d.duration = 0.5;
  const Model m = compile(demo_walker(), d);
  SimOptions o;
  o.record_fps = 60;
  const SimResult r = simulate(m, o);
  ASSERT_EQ(r.status, SimStatus::kFinished);
  // Frames at 0, 1/60, ..., 29/60 s, then the final state (the first step past 0.5 s).
  ASSERT_EQ(r.recording.frames.size(), 31u);
  EXPECT_NEAR(r.recording.frames.back().time, 0.5, 0.001);
  for (size_t k = 0; k + 1 < r.recording.frames.size(); ++k) {
    const Frame& f = r.recording.frames[k];
    EXPECT_GE(f.time, k / 60.0);
    EXPECT_LT(f.time, k / 60.0 + 0.001);  // within one step of the frame time
    EXPECT_EQ(f.pos.size(), static_cast<size_t>(m.n));
    EXPECT_EQ(f.orient.size(), static_cast<size_t>(m.n));
    EXPECT_EQ(f.size.size(), static_cast<size_t>(m.n));
    EXPECT_EQ(f.stiffness.size(), static_cast<size_t>(m.n));
    EXPECT_EQ(f.stimulus.size(), static_cast<size_t>(m.n));
  }
  // The last frame is the final state: its stiffness is the result's final stiffness, and
  // stimulus and stiffness histories move after settling.
  EXPECT_EQ(r.recording.frames.back().stiffness, r.final_stiffness);
  EXPECT_NE(r.recording.frames[20].stimulus, r.recording.frames[25].stimulus);
  EXPECT_NE(r.recording.frames[0].stiffness, r.recording.frames.back().stiffness);
}

TEST(Recording, OffByDefault) {
  PhysicsDef d;
  d.duration = 0.3;
  EXPECT_TRUE(simulate(compile(demo_walker(), d)).recording.frames.empty());
}

// Frames at given times: each the first state at or after its time (two times inside one
// step share a state), and the life ends after the last one, at the same bits as the
// uninterrupted life had there.
TEST(Recording, AtGivenTimesEndsTheLifeAfterTheLast) {
  PhysicsDef d = preset_gecco2018_code();
  d.treatment = Treatment::kStress;
  d.duration = 0.5;
  const Model m = compile(demo_walker(), d);
  SimOptions o;
  o.frame_times = {0.0, 0.1, 0.1 + 1e-9, 0.3};
  const SimResult r = simulate(m, o);
  EXPECT_EQ(r.status, SimStatus::kRunning);  // ended early, by design
  ASSERT_EQ(r.recording.frames.size(), 4u);
  EXPECT_EQ(r.recording.frames[0].time, 0.0);
  EXPECT_EQ(r.recording.frames[1].time, r.recording.frames[2].time);
  for (size_t k = 0; k < 4; ++k) {
    EXPECT_GE(r.recording.frames[k].time, o.frame_times[k]);
    EXPECT_LT(r.recording.frames[k].time, o.frame_times[k] + 2 * r.dt_initial);
  }
  EXPECT_EQ(r.sim_time, r.recording.frames.back().time);

  Simulator sim(m);
  testing::run_until(sim, 0.3);
  EXPECT_EQ(sim.state().time, r.sim_time);
  EXPECT_EQ(state_hash(sim.state()), r.final_state_hash);
}

// on_frame sees every frame and can end the life; frames then stay out of the result.
// A life ends at its first step past the duration: its end, SimResult::sim_time, is a time of
// the life that a frame can be asked for at (render --time, Python's render(time=...)), and so
// is any time between the duration and it. A time past the last step is refused in one line,
// before simulating when it is past anything the life could reach. With and without
// development (whose time step follows the stiffness).
TEST(FramesAtTimes, TheLifesLastStepIsWithinIt) {
  for (const Treatment t : {Treatment::kNone, Treatment::kStress}) {
    SCOPED_TRACE(to_string(t));
    PhysicsDef d;
    d.treatment = t;
    d.settle_time = 0.05;
    d.duration = 0.3;
    RobotDef robot = testing::block(2, 2, 2, 1e9);
    for (double& a : robot.dev_rate) a = -10;  // softens: the step grows
    const auto model = std::make_shared<const Model>(compile(robot, d));
    const SimResult whole = simulate(*model);
    ASSERT_EQ(whole.status, SimStatus::kFinished);
    ASSERT_GT(whole.sim_time, d.duration);
    EXPECT_LE(whole.sim_time, d.duration + longest_step(*model));
    const FrameSource frames = simulated_frames(model);
    for (const double at :
         {std::nextafter(d.duration, 1.0), (d.duration + whole.sim_time) / 2, whole.sim_time}) {
      std::vector<Frame> got;
      const SimResult r = frames({at},
                                 [&](SourcedFrame&& f) {
                                   got.push_back(std::move(f.frame));
                                   return true;
                                 },
                                 {});
      ASSERT_EQ(got.size(), 1u) << at;
      EXPECT_EQ(got[0].time, whole.sim_time) << at;  // the last state
      EXPECT_EQ(r.final_state_hash, whole.final_state_hash) << at;
    }
    auto refusal = [&](double at) {
      return testing::error_of([&] { frames({at}, [](SourcedFrame&&) { return true; }, {}); });
    };
    // Past the last step but before the bound: refused once the life is known.
    const double past = std::nextafter(whole.sim_time, 1.0);
    char end[32];
    *std::to_chars(end, end + sizeof end - 1, whole.sim_time).ptr = '\0';
    const std::string late = refusal(past);
    EXPECT_TRUE(late.starts_with("time ")) << late;
    EXPECT_TRUE(
        late.ends_with(" s is outside the life [0, " + std::string(end) + "] s (its last step)"))
        << late;
    // Clearly past the end: refused before anything runs.
    EXPECT_EQ(refusal(d.duration + 1),
              "time 1.3 s is outside the life [0, 0.3] s (it ends at its first step past 0.3 s)");
    EXPECT_EQ(refusal(-0.1),
              "time -0.1 s is outside the life [0, 0.3] s (it ends at its first step past 0.3 s)");
  }
}

TEST(Recording, OnFrameReceivesFramesAndCanStop) {
  PhysicsDef d;
  d.duration = 0.5;
  const Model m = compile(demo_walker(), d);
  SimOptions o;
  o.record_fps = 20;
  std::vector<double> seen;
  o.on_frame = [&](const State& s, Frame&& frame) {
    EXPECT_EQ(frame.time, s.time);
    seen.push_back(s.time);
    return seen.size() < 3;
  };
  const SimResult r = simulate(m, o);
  EXPECT_EQ(r.status, SimStatus::kRunning);
  EXPECT_TRUE(r.recording.frames.empty());
  ASSERT_EQ(seen.size(), 3u);
  EXPECT_EQ(r.sim_time, seen.back());
  EXPECT_GE(seen[2], 2 / 20.0);
}

// Progress runs from 0 to 1 and never backwards; per-stage timings add up, count every
// step, and change no bits.
TEST(Simulate, ProgressAndStageTimings) {
  PhysicsDef d = preset_gecco2018_code();
  d.treatment = Treatment::kPressure;
  d.duration = 0.4;
  const Model m = compile(demo_walker(), d);
  const SimResult plain = simulate(m);
  StageTimings timings;
  std::vector<double> progress;
  SimOptions o;
  o.timings = &timings;
  o.progress = [&](double f) { progress.push_back(f); };
  const SimResult r = simulate(m, o);
  EXPECT_EQ(r.final_state_hash, plain.final_state_hash);
  EXPECT_EQ(r.status, SimStatus::kFinished);
  EXPECT_EQ(timings.steps, r.steps);
  EXPECT_GT(timings.bond_forces, 0);
  EXPECT_GT(timings.integrate, 0);
  EXPECT_GT(timings.develop, 0);
  EXPECT_LE(timings.total(), r.wall_seconds);
  ASSERT_GE(progress.size(), 50u);
  EXPECT_EQ(progress.front(), 0.0);
  EXPECT_EQ(progress.back(), 1.0);
  EXPECT_TRUE(std::is_sorted(progress.begin(), progress.end()));
}

}  // namespace
}  // namespace plastivox
