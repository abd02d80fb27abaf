// A controller evolved with the body (docs/evolution.md, "Evolving a controller"): the
// genome's controller part, its mutation, the same bits on any thread count, checkpoints that
// resume bit-identically, and champions whose robot files replay their lives.
#include <algorithm>
#include <cmath>
#include <filesystem>

#include "plastivox/evo/champion.hpp"
#include "plastivox/evo/results_file.hpp"
#include "plastivox/evo/run.hpp"
#include "plastivox/io/robot_file.hpp"
#include "test_support.hpp"

namespace plastivox::evo {
namespace {

namespace fs = std::filesystem;

const char* kDistributed = R"({"kind": "distributed", "hidden": 3, "every": 2})";

// 4x4x4 lattice, population 6, 0.2 s lives; `controller` the config's field, "" for none.
EvolveConfig tiny(const std::string& controller, uint64_t seed = 5, int generations = 3) {
  EvolveConfig c = parse_config(
      R"({"format": "plastivox-evolve-config", "version": 1, "treatment": "stress",
      "population": 6, "lattice": {"nx": 4, "ny": 4, "nz": 4},
      "physics": {"duration": 0.2, "settle_time": 0.1})" +
          (controller.empty() ? std::string() : ", \"controller\": " + controller) + "}",
      "tiny");
  c.seed = seed;
  c.generations = generations;
  return c;
}

std::string evolved_digest(const EvolveConfig& c, int threads) {
  Evolver ev(Evolver::new_run(c), threads);
  while (!ev.finished()) ev.step();
  return content_digest(ev.state()).hex();
}

TEST(EvoController, ConfigDefaultsAndIdentity) {
  const EvolveConfig c = tiny(kDistributed);
  EXPECT_EQ(c.controller.kind, ControllerKind::kDistributed);
  EXPECT_EQ(c.controller.hidden, 3);
  EXPECT_EQ(c.controller.every, 2);
  EXPECT_EQ(c.controller_genes.count, weight_count(ControllerKind::kDistributed, 3));
  EXPECT_EQ(c.controller_genes, (ControllerGenes{c.controller_genes.count, 1.0, 0.1, 0.3}));
  EXPECT_NE(c.identity_json().find("\"mutation_sigma\":0.3"), std::string::npos);
  // The sine named outright is the default: the identity (and so every digest) is unchanged.
  EXPECT_EQ(tiny(R"({"kind": "sine"})").identity_json(), tiny("").identity_json());
  // The canonical form parses back to the same config.
  EXPECT_EQ(parse_config(c.canonical_json(), "again").identity_json(), c.identity_json());
  const EvolveConfig tuned = tiny(
      R"({"kind": "central", "hidden": 2, "init_sigma": 0.5, "mutation_rate": 0.25,
          "mutation_sigma": 0.1})");
  EXPECT_EQ(tuned.controller_genes, (ControllerGenes{25, 0.5, 0.25, 0.1}));
}

TEST(EvoController, BadControllerFieldsAreNamed) {
  const struct {
    std::string controller, expect;
  } cases[] = {
      {R"({"kind": "lstm"})", "tiny: controller.kind: 'lstm' is not a controller"},
      {R"({"kind": "central"})", "tiny: controller.hidden: must be in [1, 64] for central"},
      {R"({"kind": "distributed", "weights": [1]})", "tiny: controller.weights: unknown field"},
      {R"({"kind": "distributed", "mutation_rate": 2})",
       "tiny: controller.mutation_rate: must be in [0, 1]"},
      {R"({"kind": "distributed", "every": 0})", "tiny: controller.every: must be in [1, "},
  };
  for (const auto& c : cases) {
    const std::string msg = testing::error_of([&] { tiny(c.controller); });
    EXPECT_NE(msg.find(c.expect), std::string::npos) << c.controller << "\n" << msg;
    EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
  }
}

TEST(EvoController, MutationPerturbsWeightsAtItsRate) {
  ControllerGenes genes{10000, 1.0, 0.1, 0.3};
  Rng rng(11);
  std::vector<double> w(genes.count, 0.0);
  mutate_controller(w, genes, rng);
  const auto changed = std::count_if(w.begin(), w.end(), [](double x) { return x != 0; });
  EXPECT_NEAR(static_cast<double>(changed), 1000.0, 150.0);  // binomial sd 30
  double sum_sq = 0;
  for (double x : w) sum_sq += x * x;
  EXPECT_NEAR(std::sqrt(sum_sq / changed), 0.3, 0.03);
  // A draw that picks no weight still changes one.
  genes.rate = 0;
  std::fill(w.begin(), w.end(), 0.0);
  mutate_controller(w, genes, rng);
  EXPECT_EQ(std::count_if(w.begin(), w.end(), [](double x) { return x != 0; }), 1);
}

TEST(EvoController, DistributedRunIsTheSameOnOneAndTwoThreadsAndDiffersFromTheSine) {
  const EvolveConfig c = tiny(kDistributed);
  const std::string one = evolved_digest(c, 1);
  EXPECT_EQ(evolved_digest(c, 2), one);
  EXPECT_NE(evolved_digest(tiny(""), 1), one);
  // Every genome carries the controller's weights, and every phenotype runs them.
  Evolver ev(Evolver::new_run(c), 2);
  ev.step();
  for (const Individual& ind : ev.state().population) {
    EXPECT_EQ(ind.genome.controller.size(), static_cast<size_t>(c.controller_genes.count));
    EXPECT_EQ(ind.phenotype.robot.controller.weights, ind.genome.controller);
    EXPECT_EQ(ind.phenotype.robot.controller.kind, ControllerKind::kDistributed);
  }
}

class EvoControllerFiles : public testing::ScratchDirTest {};

TEST_F(EvoControllerFiles, StopAndResumeEqualsUninterruptedAndChampionsReplay) {
  const EvolveConfig c = tiny(kDistributed, 9, 4);
  const RunReport full = run_evolution(c, path("full.h5"), {});
  RunOptions stop;
  stop.stop_after = 2;
  stop.threads = 1;
  EXPECT_EQ(run_evolution(c, path("part.h5"), stop).outcome, RunOutcome::kStopped);
  const RunReport rest = run_evolution(c, path("part.h5"), {});
  EXPECT_EQ(rest.resumed_from, 2);
  EXPECT_EQ(rest.content_digest, full.content_digest);

  const ResultsFile f = read_results(path("part.h5"));
  EXPECT_EQ(f.content_digest, full.content_digest);
  for (const Individual& ind : f.state.population)
    EXPECT_EQ(ind.genome.controller.size(), static_cast<size_t>(c.controller_genes.count));
  // The champion's robot file holds its controller and replays its evaluated life.
  const ChampionRecord& champ = champion_at(f.state, -1, "part.h5");
  ASSERT_EQ(champ.status, static_cast<uint8_t>(EvalStatus::kOk));
  const RobotDef robot = champion_robot(champ, f.state.generations_done);
  EXPECT_EQ(robot.controller.weights, champ.genome.controller);
  const RobotFile back = parse_robot_json(robot_to_json(robot, &c.physics), "champion.json");
  EXPECT_EQ(back.robot.controller, robot.controller);
  EXPECT_EQ(simulate(compile(back.robot, back.physics)).fitness, champ.fitness);
}

}  // namespace
}  // namespace plastivox::evo
