// Lives the rules flag (docs/evolution.md, "Flagged lives"): a life that scored by rising or
// falling under walk's 3-D fitness (the rules' vertical_exploit) never enters a MAP-Elites
// archive and is crowned by no algorithm while a life that counts exists. Each run here is
// chosen to provoke such lives (tall bodies topple; a tiny random 5x5x5 population falls), and
// each test first checks that a flagged life would have won without the rule.
#include <algorithm>
#include <map>

#include "plastivox/evo/evolver.hpp"
#include "plastivox/evo/results_file.hpp"
#include "plastivox/evo/run.hpp"
#include "plastivox/io/robot_file.hpp"
#include "plastivox/rules/life_rules.hpp"
#include "test_support.hpp"

namespace plastivox::evo {
namespace {

constexpr uint8_t kOk = static_cast<uint8_t>(EvalStatus::kOk);

RunState evolved(const EvolveConfig& c, int threads) {
  Evolver ev(Evolver::new_run(c), threads);
  while (!ev.finished()) ev.step();
  return ev.state();
}

// The best fitness among births that are ok, flagged or not.
double best_birth(const RunState& s, bool flagged) {
  double best = kWorstFitness;
  for (const BirthRecord& b : s.births)
    if (b.status == kOk && !b.sank && (b.vertical != 0) == flagged)
      best = std::max(best, b.fitness);
  return best;
}

// A 2x2x8 lattice: tall random bodies, many of which topple. MAP-Elites, or AFPO.
EvolveConfig tall(bool map_elites = true) {
  return parse_config(std::string(R"({"format": "plastivox-evolve-config", "version": 1,
      "seed": 5, "generations": 4, "population": 6, "treatment": "stress",
      "lattice": {"nx": 2, "ny": 2, "nz": 8}, "physics": {"duration": 0.3, "settle_time": 0.1})") +
                          (map_elites ? R"(, "algorithm": "map-elites", "map_elites": {
        "descriptors": [{"name": "fill", "bounds": [0.2, 1], "bins": 4},
        {"name": "pi", "bounds": [0, 1], "bins": 3},
        {"name": "floor_contact", "bounds": [0, 1], "bins": 4}]}})"
                                      : "}"),
                      "tall");
}

// A 2x2x6 column of 1 GPa, its phases staggered up it: under walk's 3-D fitness it topples, and
// its score is mostly the fall.
RobotDef column() {
  RobotDef r = make_empty_robot(2, 2, 6);
  for (int z = 0; z < 6; ++z)
    for (int s = 0; s < 4; ++s) {
      const int site = 4 * z + s;
      r.present[site] = 1;
      r.stiffness[site] = 1e9;
      r.dev_rate[site] = 0.5;
      r.phase[site] = 0.2 * z;
    }
  r.name = "column";
  return r;
}

const char* kColumnPhysics = R"({"duration": 0.4, "settle_time": 0.2})";

TEST(FlaggedLives, TheEvaluationCarriesTheRulesVerdict) {
  Phenotype p;
  p.robot = column();
  p.valid = true;
  p.voxels = p.robot.voxel_count();
  PhysicsDef physics = tall().physics;
  physics.duration = 0.4;
  physics.settle_time = 0.2;
  SimResult r = simulate(compile(p.robot, physics));
  judge_life(physics, r);
  const Evaluation e = evaluate_phenotype(p, physics);
  EXPECT_EQ(e.vertical, vertical_exploit(physics, r));
  EXPECT_TRUE(e.vertical) << "share " << r.vertical_share << ", dz " << r.displacement.z();
  physics.fitness = FitnessMode::kXY;  // the rule applies to 3-D walk fitness only
  EXPECT_FALSE(evaluate_phenotype(p, physics).vertical);
}

TEST(FlaggedLives, NoArchiveAdmitsOneAndEachCellHoldsTheBestLifeThatCounts) {
  const EvolveConfig c = tall();
  const RunState s = evolved(c, 2);
  // Replay the rule over the births: the best life that counts per cell, and whether a flagged
  // life would have taken a cell without the rule.
  std::map<int64_t, const BirthRecord*> best;
  int flagged = 0, would_take = 0;
  for (const BirthRecord& b : s.births) {
    if (b.status != kOk || b.sank) continue;
    const int64_t cell = cell_of(c.map_elites, b.descriptors);
    const auto at = best.find(cell);
    const bool beats = at == best.end() || b.fitness > at->second->fitness;
    if (b.vertical) {
      ++flagged;
      would_take += beats ? 1 : 0;
    } else if (beats) {
      best[cell] = &b;
    }
  }
  ASSERT_GT(would_take, 0) << flagged << " flagged lives, none would win a cell";
  ASSERT_EQ(s.archive.size(), best.size());
  for (const Individual& e : s.archive) {
    EXPECT_EQ(s.births[e.id].vertical, 0) << "elite " << e.id;
    EXPECT_FALSE(e.vertical);
    ASSERT_TRUE(best.count(e.cell));
    EXPECT_EQ(best[e.cell]->id, e.id);
  }
  EXPECT_EQ(s.births[s.champions.back().id].vertical, 0);
  EXPECT_EQ(s.champions.back().fitness, best_birth(s, false));
  EXPECT_GT(best_birth(s, true), s.champions.back().fitness);  // the fall would have been crowned
}

// AFPO's tiny golden runs (5x5x5, 0.5 s lives): in each, a life that fell outscored every walker
// and was the recorded champion before the rule; now the champion is the best life that counts
// among the survivors, and the best fitness still never falls.
TEST(FlaggedLives, AfpoCrownsNoFlaggedLife) {
  for (const char* treatment : {"none", "stress", "pressure"}) {
    const EvolveConfig c = parse_config(std::string(R"({"format": "plastivox-evolve-config",
        "version": 1, "seed": 3, "population": 6, "generations": 3, "treatment": ")") +
                                            treatment + R"(", "lattice": {"nx": 5, "ny": 5,
        "nz": 5}, "physics": {"duration": 0.5, "settle_time": 0.2}})",
                                        "golden");
    const RunState s = evolved(c, 2);
    const ChampionRecord& champ = s.champions.back();
    EXPECT_GT(best_birth(s, true), champ.fitness) << treatment;
    for (const ChampionRecord& r : s.champions) EXPECT_EQ(s.births[r.id].vertical, 0) << treatment;
    for (const Individual& ind : s.population) {
      if (ind.status == EvalStatus::kOk && !ind.vertical) {
        EXPECT_LE(ind.fitness, champ.fitness) << treatment;
      }
    }
    for (size_t g = 1; g < s.history.size(); ++g)
      EXPECT_GE(s.history[g].best_fitness, s.history[g - 1].best_fitness) << treatment;
    EXPECT_EQ(s.history.back().champion_id, champ.id);
  }
}

// CMA-ES on the phases of a 2x2x6 column, which topples under most phases: the champion is the
// best sample that counts; the update still ranks samples by fitness alone.
TEST(FlaggedLives, CmaEsCrownsTheBestSampleThatCounts) {
  const EvolveConfig c =
      parse_config(std::string(R"({"format": "plastivox-evolve-config", "version": 1, "seed": 3,
      "generations": 4, "treatment": "stress", "algorithm": "cma-es", "genome": "phase",
      "physics": )") + kColumnPhysics +
                       R"(, "body": )" + robot_to_json(column()) + "}",
                   "column");
  const RunState s = evolved(c, 2);
  ASSERT_GT(best_birth(s, true), best_birth(s, false));  // a fall outscored every counted life
  EXPECT_EQ(s.births[s.champions.back().id].vertical, 0);
  EXPECT_EQ(s.champions.back().fitness, best_birth(s, false));
}

class FlaggedFiles : public testing::ScratchDirTest {};

// The flag is kept with each life (/individuals/vertical) and each cached one
// (/checkpoint/cache/vertical), so a run stopped and resumed (its cache serving the lives it saw)
// ends as an uninterrupted one, for MAP-Elites and AFPO.
TEST_F(FlaggedFiles, ResumeKeepsTheFlagsAndTheDigest) {
  for (const EvolveConfig& c : {tall(), tall(false)}) {
    const std::string name = to_string(c.algorithm);
    const RunReport full = run_evolution(c, path(name + "-full.h5"), {});
    RunOptions stop;
    stop.stop_after = 2;
    stop.threads = 1;
    ASSERT_EQ(run_evolution(c, path(name + "-part.h5"), stop).outcome, RunOutcome::kStopped);
    const ResultsFile part = read_results(path(name + "-part.h5"));
    int flagged = 0;
    for (const auto& [key, e] : part.state.cache) flagged += e.vertical ? 1 : 0;
    EXPECT_GT(flagged, 0) << name;
    const RunReport rest = run_evolution(c, path(name + "-part.h5"), {});
    EXPECT_EQ(rest.resumed_from, 2) << name;
    EXPECT_EQ(rest.content_digest, full.content_digest) << name;
    const RunState a = read_results(path(name + "-full.h5")).state;
    const RunState b = read_results(path(name + "-part.h5")).state;
    ASSERT_EQ(a.births.size(), b.births.size());
    for (size_t i = 0; i < a.births.size(); ++i)
      EXPECT_EQ(a.births[i].vertical, b.births[i].vertical) << name << " birth " << i;
    const RunState direct = evolved(c, 1);
    for (size_t i = 0; i < a.births.size(); ++i)
      EXPECT_EQ(a.births[i].vertical, direct.births[i].vertical) << name << " birth " << i;
  }
}

// A results file written before the flag has no such field: its lives read as not flagged.
TEST(FlaggedOldFiles, AFileWithoutTheFlagReadsAsNoneFlagged) {
  const ResultsFile old =
      read_results(std::string(PLASTIVOX_SOURCE_DIR) + "/tests/data/results/old-rule-sinker.h5");
  ASSERT_FALSE(old.state.births.empty());
  for (const BirthRecord& b : old.state.births) EXPECT_EQ(b.vertical, 0);
  for (const auto& [key, e] : old.state.cache) EXPECT_FALSE(e.vertical);
}

}  // namespace
}  // namespace plastivox::evo
