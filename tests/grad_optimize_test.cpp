// `plastivox optimize` (apps/cmd_optimize.cpp, docs/gradients.md): gradient ascent raises the
// walker's fitness on a short life, the written robot replays under `simulate` to the fitness
// the log's last line reports, bit for bit, and bad input is refused in one line.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "plastivox/control.hpp"
#include "plastivox/io/robot_file.hpp"
#include "test_support.hpp"

namespace plastivox {
namespace {

using testing::cli;
using testing::Output;

const std::string kWalker = std::string(PLASTIVOX_SOURCE_DIR) + "/examples/walker.json";
// A short life: 0.06 s of walking after 0.04 s of settling, scored on horizontal travel.
const std::string kShort =
    " --physics '{\"duration\": 0.1, \"settle_time\": 0.04, \"fitness\": \"xy\"}'";

std::vector<nlohmann::json> lines_of(const std::string& text) {
  std::vector<nlohmann::json> out;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) out.push_back(nlohmann::json::parse(line));
  return out;
}

class Optimize : public testing::ScratchDirTest {};

TEST_F(Optimize, RaisesTheWalkersFitnessAndTheWrittenRobotReplaysBitForBit) {
  const Output o = cli("optimize " + kWalker + " --wrt phase,stiffness --method adam --steps 2" +
                       " --lr 0.02" + kShort + " --out " + path("opt.json"));
  ASSERT_EQ(o.status, 0) << o.out;
  EXPECT_NE(o.out.find("plastivox optimize: step 1/2 fitness "), std::string::npos) << o.out;
  const std::vector<nlohmann::json> log = lines_of(testing::file_text(path("opt.log.jsonl")));
  ASSERT_EQ(log.size(), 5u);  // header, steps 0, 1, 2, the written robot
  EXPECT_EQ(log[0]["format"], "plastivox-optimize-log");
  EXPECT_EQ(log[0]["wrt"], nlohmann::json({"phase", "stiffness"}));
  EXPECT_EQ(log[0]["physics"]["duration"], 0.1);
  EXPECT_FALSE(log[0]["provenance"]["plastivox_version"].get<std::string>().empty());
  EXPECT_FALSE(log[0]["provenance"]["date_created"].get<std::string>().empty());
  for (int k = 0; k <= 2; ++k) EXPECT_EQ(log[1 + k]["step"], k);
  EXPECT_TRUE(log[1]["gradient_norm"]["phase"].get<double>() > 0);
  const double first = log[1]["fitness"], last = log[3]["fitness"];
  EXPECT_GT(last, first * 1.2) << o.out;  // measured: 0.052 -> 0.143 (2 steps at lr 0.02)
  // The last line names the best robot, written; simulate replays it to that fitness.
  EXPECT_EQ(log[4]["written"], path("opt.json"));
  EXPECT_EQ(log[4]["step"], 2);
  const nlohmann::json replay = testing::cli_json("simulate " + path("opt.json") + " --json");
  EXPECT_EQ(replay["fitness"].get<double>(), log[4]["fitness"].get<double>());
  EXPECT_EQ(log[4]["fitness"].get<double>(), last);
  // Each step's line carries its cost: the judged life's engine steps (the replay's) and the
  // process's CPU seconds for the step (a life and a gradient: more than nothing).
  EXPECT_EQ(log[3]["life_steps"].get<int64_t>(), replay["steps"].get<int64_t>());
  for (int k = 0; k <= 2; ++k) EXPECT_GT(log[1 + k]["cpu_seconds"].get<double>(), 0.0);
  // Every value stays valid: stiffness within the physics' range, phases within half a cycle,
  // and the arrays not optimised untouched.
  const RobotFile before = read_robot_file(kWalker), after = read_robot_file(path("opt.json"));
  int moved = 0;
  for (int s = 0; s < after.robot.sites(); ++s) {
    if (!after.robot.present[s]) continue;
    EXPECT_GE(after.robot.stiffness[s], after.physics.e_min);
    EXPECT_LE(after.robot.stiffness[s], after.physics.e_max);
    EXPECT_LE(std::abs(after.robot.phase[s]), 0.5);
    EXPECT_EQ(after.robot.dev_rate[s], before.robot.dev_rate[s]);
    moved += after.robot.phase[s] != before.robot.phase[s];
  }
  EXPECT_GT(moved, 100);
  // One thread gives the same run, bit for bit: the backward pass's bits do not depend on it.
  const Output one = cli("optimize " + kWalker + " --wrt phase,stiffness --method adam --steps 2" +
                         " --lr 0.02 --threads 1" + kShort + " --out " + path("opt1.json"));
  ASSERT_EQ(one.status, 0) << one.out;
  const std::vector<nlohmann::json> log1 = lines_of(testing::file_text(path("opt1.log.jsonl")));
  ASSERT_EQ(log1.size(), 5u);
  for (int k = 1; k <= 3; ++k) {
    EXPECT_EQ(log1[k]["fitness"].get<double>(), log[k]["fitness"].get<double>());
    EXPECT_EQ(log1[k].value("gradient_norm", nlohmann::json()),
              log[k].value("gradient_norm", nlohmann::json()));
  }
}

// A network's weights: a 3x3x3 body driven by a distributed network without a hidden layer
// (without the rate limit: its clamps make the fitness rougher still). Measured: 0.966, 1.106,
// 1.185 over two steps at lr 0.01 (at lr 0.03: 0.966, 0.973, then it falls: the fitness of a
// network on the floor is rough, and the best robot seen is the one written).
TEST_F(Optimize, RaisesANetworksFitnessThroughItsWeights) {
  RobotDef r = make_empty_robot(3, 3, 3);
  for (int s = 0; s < r.sites(); ++s) {
    r.present[s] = 1;
    r.stiffness[s] = 1e9 * (1.5 + std::sin(1.7 * s + 0.3));
  }
  r.controller.kind = ControllerKind::kDistributed;
  for (int k = 0; k < weight_count(r.controller.kind, 0); ++k)
    r.controller.weights.push_back(0.8 * std::sin(1.3 * k + 0.7));
  PhysicsDef physics;
  physics.duration = 0.3;
  physics.settle_time = 0.05;
  physics.fitness = FitnessMode::kXY;
  physics.act_max_rate = 0;
  write_robot_file(path("net.json"), r, &physics);
  const Output o = cli("optimize " + path("net.json") + " --wrt controller --steps 2 --lr 0.01" +
                       " --out " + path("net-opt.json"));
  ASSERT_EQ(o.status, 0) << o.out;
  const std::vector<nlohmann::json> log = lines_of(testing::file_text(path("net-opt.log.jsonl")));
  ASSERT_EQ(log.size(), 5u);
  EXPECT_GT(log[4]["fitness"].get<double>(), 1.1 * log[1]["fitness"].get<double>()) << o.out;
  const nlohmann::json replay = testing::cli_json("simulate " + path("net-opt.json") + " --json");
  EXPECT_EQ(replay["fitness"].get<double>(), log[4]["fitness"].get<double>());
  const RobotFile after = read_robot_file(path("net-opt.json"));
  EXPECT_EQ(after.robot.stiffness, r.stiffness);
  EXPECT_EQ(after.robot.controller.weights.size(), r.controller.weights.size());
  EXPECT_NE(after.robot.controller.weights, r.controller.weights);
  // The sine has no weights to move.
  const Output sine = cli("optimize " + kWalker + " --wrt controller --out " + path("x.json"));
  EXPECT_EQ(sine.status, 2);
  EXPECT_NE(sine.out.find("the robot's controller is the sine"), std::string::npos) << sine.out;
}

// A later life whose gradient is refused (here a stiffer body takes more steps than
// --memory-limit allows) ends the run after that step's line: the best robot so far is
// written, the last line says why, and the exit status is 0.
TEST_F(Optimize, StopsWhenALaterLifeIsRefusedAndWritesTheBestSoFar) {
  const Output first =
      cli("optimize " + kWalker + kShort + " --memory-limit 1 --out " + path("x.json"));
  const size_t at = first.out.find("needs about ");
  ASSERT_NE(at, std::string::npos) << first.out;
  const double mb = std::stod(first.out.substr(at + 12));  // the first life's estimate
  const Output o =
      cli("optimize " + kWalker + kShort + " --wrt stiffness --lr 0.3 --steps 3" +
          " --memory-limit " + std::to_string(mb * 1.01) + " --out " + path("opt.json"));
  ASSERT_EQ(o.status, 0) << o.out;
  EXPECT_NE(o.out.find("warning: stopped at step 1: gradient: the life needs about"),
            std::string::npos)
      << o.out;
  const std::vector<nlohmann::json> log = lines_of(testing::file_text(path("opt.log.jsonl")));
  ASSERT_EQ(log.size(), 4u);  // header, steps 0 and 1, the written robot
  EXPECT_FALSE(log[2].contains("gradient_norm"));
  EXPECT_NE(log[3]["stopped"].get<std::string>().find("memory_limit"), std::string::npos);
  const nlohmann::json replay = testing::cli_json("simulate " + path("opt.json") + " --json");
  EXPECT_EQ(replay["fitness"].get<double>(), log[3]["fitness"].get<double>());
  EXPECT_EQ(log[3]["fitness"].get<double>(),
            std::max(log[1]["fitness"].get<double>(), log[2]["fitness"].get<double>()));
}

// The amplitudes: the physics' (written with the robot) and a robot's own, each moved by its
// gradient and held to [0, 0.9) (at the bound: the largest double below 0.9, or 0).
TEST_F(Optimize, MovesTheAmplitudesWithinTheirRange) {
  const RobotFile before = read_robot_file(kWalker);
  Output o = cli("optimize " + kWalker + " --wrt amplitude --steps 2 --lr 0.01" + kShort +
                 " --out " + path("amp.json"));
  ASSERT_EQ(o.status, 0) << o.out;
  std::vector<nlohmann::json> log = lines_of(testing::file_text(path("amp.log.jsonl")));
  ASSERT_EQ(log.size(), 5u);
  EXPECT_GT(log[1]["gradient_norm"]["amplitude"].get<double>(), 0.0);
  EXPECT_GT(log[4]["fitness"].get<double>(), log[1]["fitness"].get<double>()) << o.out;
  RobotFile after = read_robot_file(path("amp.json"));
  EXPECT_NE(after.physics.act_amplitude, before.physics.act_amplitude);
  EXPECT_EQ(after.robot.phase, before.robot.phase);
  EXPECT_EQ(testing::cli_json("simulate " + path("amp.json") + " --json")["fitness"].get<double>(),
            log[4]["fitness"].get<double>());
  // At a step far past the range, every value stops at its bound.
  o = cli("optimize " + kWalker + " --wrt amplitude --method sgd --steps 1 --lr 1e6" + kShort +
          " --out " + path("top.json"));
  ASSERT_EQ(o.status, 0) << o.out;
  log = lines_of(testing::file_text(path("top.log.jsonl")));
  ASSERT_EQ(log.back()["step"], 1) << o.out;
  EXPECT_EQ(read_robot_file(path("top.json")).physics.act_amplitude, std::nextafter(0.9, 0.0));
  // A robot's own amplitudes.
  RobotDef own = before.robot;
  own.act_amplitude.assign(own.sites(), 0.0);
  for (int s = 0; s < own.sites(); ++s) own.act_amplitude[s] = own.present[s] ? 0.1 : 0.0;
  write_robot_file(path("own.json"), own, &before.physics);
  o = cli("optimize " + path("own.json") + " --wrt act_amplitude --steps 2 --lr 0.01" + kShort +
          " --out " + path("own-opt.json"));
  ASSERT_EQ(o.status, 0) << o.out;
  log = lines_of(testing::file_text(path("own-opt.log.jsonl")));
  ASSERT_EQ(log.size(), 5u);
  EXPECT_GT(log[4]["fitness"].get<double>(), log[1]["fitness"].get<double>()) << o.out;
  after = read_robot_file(path("own-opt.json"));
  int moved = 0;
  for (int s = 0; s < own.sites(); ++s) {
    if (!own.present[s]) continue;
    EXPECT_GE(after.robot.act_amplitude[s], 0.0);
    EXPECT_LT(after.robot.act_amplitude[s], 0.9);
    moved += after.robot.act_amplitude[s] != 0.1;
  }
  EXPECT_GT(moved, 100);
  EXPECT_EQ(after.physics.act_amplitude, before.physics.act_amplitude);
  EXPECT_EQ(
      testing::cli_json("simulate " + path("own-opt.json") + " --json")["fitness"].get<double>(),
      log[4]["fitness"].get<double>());
}

TEST_F(Optimize, MovesTheActuationScalesWithinTheirRangeAndWritesThem) {
  // The walker has no act_scale (1 at every voxel): --wrt act_scale starts there, writes the
  // array, and the fitness rises (measured: 0.0519, 0.0631, 0.0754 at lr 0.1).
  ASSERT_TRUE(read_robot_file(kWalker).robot.act_scale.empty());
  const Output o = cli("optimize " + kWalker + " --wrt act_scale --steps 2 --lr 0.1" + kShort +
                       " --out " + path("scaled.json"));
  ASSERT_EQ(o.status, 0) << o.out;
  const std::vector<nlohmann::json> log = lines_of(testing::file_text(path("scaled.log.jsonl")));
  ASSERT_EQ(log.size(), 5u);
  EXPECT_TRUE(log[1]["gradient_norm"]["act_scale"].get<double>() > 0);
  const double first = log[1]["fitness"], last = log[3]["fitness"];
  EXPECT_GT(last, first * 1.2) << o.out;
  const RobotFile before = read_robot_file(kWalker), after = read_robot_file(path("scaled.json"));
  ASSERT_EQ(after.robot.act_scale.size(), static_cast<size_t>(after.robot.sites()));
  int moved = 0;
  for (int s = 0; s < after.robot.sites(); ++s) {
    if (!after.robot.present[s]) continue;
    EXPECT_GE(after.robot.act_scale[s], 0.0);
    EXPECT_LE(after.robot.act_scale[s], 1.0);
    EXPECT_EQ(after.robot.phase[s], before.robot.phase[s]);
    moved += after.robot.act_scale[s] != 1.0;
  }
  EXPECT_GT(moved, 100);
  EXPECT_EQ(
      testing::cli_json("simulate " + path("scaled.json") + " --json")["fitness"].get<double>(),
      log[4]["fitness"].get<double>());
  // Amplitudes and scales moved in one step: each one's derivative is read at the robot the
  // gradient was taken of (the other's chain rule unmoved), so the order of --wrt changes
  // nothing. Plain steps, whose size is the derivative's (Adam's first is its sign).
  RobotDef own = read_robot_file(kWalker).robot;
  own.act_amplitude.assign(own.sites(), 0.1);
  write_robot_file(path("own.json"), own);
  double moved_fitness[2] = {0, 0};
  for (int order = 0; order < 2; ++order) {
    const std::string name = "both" + std::to_string(order);
    const Output b =
        cli("optimize " + path("own.json") + " --wrt " +
            (order == 0 ? "act_amplitude,act_scale" : "act_scale,act_amplitude") +
            " --method sgd --steps 1 --lr 10" + kShort + " --out " + path(name + ".json"));
    ASSERT_EQ(b.status, 0) << b.out;
    const std::vector<nlohmann::json> l = lines_of(testing::file_text(path(name + ".log.jsonl")));
    ASSERT_EQ(l.size(), 4u);
    moved_fitness[order] = l[2]["fitness"];
    EXPECT_NE(moved_fitness[order], l[1]["fitness"].get<double>());
  }
  EXPECT_EQ(moved_fitness[0], moved_fitness[1]);
  // A .vxa cannot hold the scales: refused before anything runs.
  const Output vxa =
      cli("optimize " + kWalker + " --wrt act_scale" + kShort + " --out " + path("scaled.vxa"));
  EXPECT_EQ(vxa.status, 2);
  EXPECT_EQ(std::count(vxa.out.begin(), vxa.out.end(), '\n'), 1) << vxa.out;
  EXPECT_NE(vxa.out.find("--wrt act_scale: a .vxa file cannot hold"), std::string::npos) << vxa.out;
  EXPECT_FALSE(std::filesystem::exists(path("scaled.vxa")));
  // Nor a robot's own amplitudes or scales whatever --wrt moves: refused before the run too,
  // rather than after it, when the file is written.
  for (const std::string& robot : {path("own.json"), path("scaled.json")}) {
    const Output held =
        cli("optimize " + robot + " --wrt phase" + kShort + " --out " + path("held.vxa"));
    EXPECT_EQ(held.status, 2);
    EXPECT_EQ(std::count(held.out.begin(), held.out.end(), '\n'), 1) << held.out;
    EXPECT_NE(held.out.find("--out " + path("held.vxa") + ": write_vxa: robot.act_"),
              std::string::npos)
        << held.out;
    EXPECT_FALSE(std::filesystem::exists(path("held.vxa")));
    EXPECT_FALSE(std::filesystem::exists(path("held.log.jsonl")));
  }
}

// Killed with SIGKILL once step 1 is checkpointed (at once, or a step or two later on a busy
// machine), the same command resumes from OUT.resume.json to the robot and the fitnesses an
// uninterrupted run gives, bit for bit.
TEST_F(Optimize, KilledMidRunResumesToTheSameRobot) {
  const std::string run =
      "optimize " + kWalker + " --wrt phase,stiffness --steps 4 --lr 0.02" + kShort + " --out ";
  ASSERT_EQ(cli(run + path("whole.json")).status, 0);
  EXPECT_FALSE(std::filesystem::exists(path("whole.json.resume.json")));
  const std::string out = path("killed.json"), ckpt = out + ".resume.json";
  const Output killed = testing::shell(
      "(" + std::string(PLASTIVOX_CLI) + " " + run + out + " >/dev/null 2>&1 & pid=$!; " +
      "for i in $(seq 1 6000); do if grep -q '\"next\":[234]' " + ckpt +
      " 2>/dev/null; then kill -KILL $pid; wait $pid; exit 9; fi; sleep 0.01; done; wait $pid)");
  ASSERT_EQ(killed.status, 9) << "the run finished before it could be killed";
  EXPECT_FALSE(std::filesystem::exists(out));
  // Another run's checkpoint is refused (here: another --lr), in one line.
  const Output other = cli("optimize " + kWalker + " --wrt phase,stiffness --steps 4 --lr 0.03" +
                           kShort + " --out " + out);
  EXPECT_EQ(other.status, 2);
  EXPECT_EQ(std::count(other.out.begin(), other.out.end(), '\n'), 1) << other.out;
  EXPECT_NE(other.out.find(ckpt + ": the checkpoint of another optimize run"), std::string::npos)
      << other.out;
  const Output resumed = cli(run + out);
  ASSERT_EQ(resumed.status, 0) << resumed.out;
  EXPECT_NE(resumed.out.find("resuming at step "), std::string::npos) << resumed.out;
  EXPECT_EQ(resumed.out.find("step 1/4"), std::string::npos) << resumed.out;
  EXPECT_EQ(testing::file_text(out), testing::file_text(path("whole.json")));
  EXPECT_FALSE(std::filesystem::exists(ckpt));
  const std::vector<nlohmann::json> a = lines_of(testing::file_text(path("whole.log.jsonl")));
  const std::vector<nlohmann::json> b = lines_of(testing::file_text(path("killed.log.jsonl")));
  ASSERT_EQ(a.size(), 7u);  // header, steps 0 to 4, the written robot
  ASSERT_EQ(b.size(), a.size());
  for (size_t k = 1; k < a.size(); ++k) EXPECT_EQ(b[k]["fitness"], a[k]["fitness"]) << k;
}

TEST_F(Optimize, RefusesBadInputInOneLine) {
  const auto one_line = [](const Output& r) {
    EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 1) << r.out;
  };
  const std::string out = " --out " + path("x.json");
  Output r = cli("optimize " + kWalker + " --wrt phase,mass" + kShort + out);
  EXPECT_EQ(r.status, 2);
  one_line(r);
  EXPECT_NE(r.out.find("--wrt: no parameter is called 'mass' (stiffness, phase, dev_rate, "
                       "act_amplitude, act_scale, amplitude, controller)"),
            std::string::npos)
      << r.out;
  // The robot's own amplitudes, for a robot without them; the physics' one, for a robot with.
  r = cli("optimize " + kWalker + " --wrt phase,act_amplitude" + kShort + out);
  EXPECT_EQ(r.status, 2);
  one_line(r);
  EXPECT_NE(r.out.find("--wrt act_amplitude: the robot has no amplitudes of its own"),
            std::string::npos)
      << r.out;
  RobotDef own = read_robot_file(kWalker).robot;
  own.act_amplitude.assign(own.sites(), 0.1);
  write_robot_file(path("own.json"), own);
  r = cli("optimize " + path("own.json") + " --wrt amplitude" + kShort + out);
  EXPECT_EQ(r.status, 2);
  one_line(r);
  EXPECT_NE(r.out.find("--wrt amplitude: the robot gives its own amplitudes"), std::string::npos)
      << r.out;
  // A life too long for the memory bound, before anything runs.
  r = cli("optimize " + kWalker + " --memory-limit 1" + out);
  EXPECT_EQ(r.status, 1);
  one_line(r);
  EXPECT_NE(r.out.find("more than memory_limit 1.0"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("--memory-limit"), std::string::npos) << r.out;
  // A first life whose plan passes the bound but which, stiffening under pressure, takes more
  // snapshots than planned as it runs.
  const std::string grows =
      " --treatment pressure --physics '{\"duration\": 0.3, \"settle_time\": 0.02}'";
  r = cli("optimize " + kWalker + grows + " --memory-limit 1" + out);
  const size_t at = r.out.find("needs about ");
  ASSERT_NE(at, std::string::npos) << r.out;
  const double planned_mb = std::stod(r.out.substr(at + 12));
  r = cli("optimize " + kWalker + grows + " --memory-limit " + std::to_string(planned_mb + 0.05) +
          out);
  EXPECT_EQ(r.status, 1);
  one_line(r);
  EXPECT_NE(r.out.find("as it stiffened"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("--memory-limit"), std::string::npos) << r.out;
  r = cli("optimize " + kWalker + " --wrt dev_rate --treatment none" + kShort + out);
  EXPECT_EQ(r.status, 2);
  one_line(r);
  EXPECT_NE(r.out.find("no development"), std::string::npos) << r.out;
  // A life that does not count (a soft block sinks through the floor: fitness 0 whatever its
  // parameters) has no gradient.
  RobotDef soft = make_empty_robot(2, 2, 2);
  for (int s = 0; s < soft.sites(); ++s) soft.present[s] = 1, soft.stiffness[s] = 1e5;
  PhysicsDef sinks;
  sinks.duration = 1.0;
  sinks.sinking_invalid = true;
  write_robot_file(path("soft.json"), soft, &sinks);
  r = cli("optimize " + path("soft.json") + out);
  EXPECT_EQ(r.status, 1);
  one_line(r);
  EXPECT_NE(r.out.find("the life does not count, so it has no gradient: "), std::string::npos)
      << r.out;
  r = cli("optimize " + kWalker + " --method newton" + out);
  EXPECT_EQ(r.status, 2);
  one_line(r);
  r = cli("optimize " + kWalker + " --threads two" + out);
  EXPECT_EQ(r.status, 2);
  one_line(r);
  EXPECT_NE(r.out.find("--threads expects a non-negative integer, got 'two'"), std::string::npos)
      << r.out;
  EXPECT_FALSE(std::filesystem::exists(path("x.json")));
}

}  // namespace
}  // namespace plastivox
