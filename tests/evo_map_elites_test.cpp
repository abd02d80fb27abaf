// MAP-Elites (docs/evolution.md, "MAP-Elites"): the config's fields and their refusals, the
// descriptors and cells, the life's measures (taken without changing the life), and runs
// through the evolver's machinery: golden bits on one and two threads, an archive that holds
// the best life seen for every cell, a resume equal to an uninterrupted run, a champion whose
// robot file replays its life.
#include <cmath>
#include <limits>
#include <map>

#include "plastivox/evo/champion.hpp"
#include "plastivox/evo/map_elites.hpp"
#include "plastivox/evo/results_file.hpp"
#include "plastivox/evo/run.hpp"
#include "plastivox/io/robot_file.hpp"
#include "plastivox/rules/life_rules.hpp"
#include "test_support.hpp"

namespace plastivox::evo {
namespace {

using testing::error_of;

const char* kAxes = R"({"descriptors": [
    {"name": "fill", "bounds": [0.2, 1], "bins": 4},
    {"name": "pi", "bounds": [0, 1], "bins": 3},
    {"name": "floor_contact", "bounds": [0, 1], "bins": 4}]})";

std::string config_text(const std::string& extra) {
  return R"({"format": "plastivox-evolve-config", "version": 1, "seed": 5, "generations": 4,
      "population": 6, "treatment": "stress", "lattice": {"nx": 4, "ny": 4, "nz": 4},
      "physics": {"duration": 0.3, "settle_time": 0.1})" +
         extra + "}";
}

EvolveConfig tiny(const std::string& axes = kAxes) {
  return parse_config(config_text(R"(, "algorithm": "map-elites", "map_elites": )" + axes), "tiny");
}

RunState evolved(const EvolveConfig& c, int threads) {
  Evolver ev(Evolver::new_run(c), threads);
  while (!ev.finished()) ev.step();
  return ev.state();
}

TEST(MapElitesConfig, TheFieldsAndTheirRefusalsBeforeAnyLife) {
  const auto error = [](const std::string& extra) {
    return error_of([&] { parse_config(config_text(extra), "run.json"); });
  };
  const std::string me = R"(, "algorithm": "map-elites", "map_elites": )";
  const auto axes = [](const std::string& second) {
    return R"({"descriptors": [{"name": "fill", "bounds": [0, 1], "bins": 2}, )" + second + "]}";
  };
  EXPECT_EQ(error(me + axes(R"({"name": "speed", "bounds": [0, 1], "bins": 2})")),
            "run.json: map_elites.descriptors[1].name: 'speed' is unknown (use voxels, fill, pi, "
            "gamma, upsilon, stiffness, development, floor_contact, com_height)");
  EXPECT_EQ(error(me + axes(R"({"name": "com_height", "bins": 2})")),
            "run.json: map_elites.descriptors[1].bounds: missing: give [lo, hi] "
            "(docs/evolution.md, \"MAP-Elites\", lists each descriptor's range)");
  EXPECT_EQ(error(me + axes(R"({"name": "com_height", "bounds": [0, 4], "bins": 0})")),
            "run.json: map_elites.descriptors[1].bins: must be in [1, 100000], got 0");
  EXPECT_EQ(error(me + axes(R"({"name": "com_height", "bounds": [4, 4], "bins": 2})")),
            "run.json: map_elites.descriptors[1].bounds: must be finite with lo < hi");
  EXPECT_EQ(error(me + axes(R"({"name": "fill", "bounds": [0, 1], "bins": 2})")),
            "run.json: map_elites.descriptors[1].name: 'fill' is given twice");
  EXPECT_EQ(error(me + R"({"descriptors": [{"name": "fill", "bounds": [0, 1], "bins": 2}]})"),
            "run.json: map_elites.descriptors: expected a list of 2 or more descriptors");
  EXPECT_EQ(error(me + R"({"descriptors": [{"name": "fill", "bounds": [0, 1], "bins": 100},
      {"name": "pi", "bounds": [0, 1], "bins": 100},
      {"name": "gamma", "bounds": [0, 1], "bins": 101}]})"),
            "run.json: map_elites.descriptors: 1010000 cells are too many (at most 1000000)");
  EXPECT_EQ(error(R"(, "algorithm": "map-elites")"),
            "run.json: map_elites: missing: map-elites needs its descriptors ({\"descriptors\": "
            "[{\"name\": ..., \"bounds\": [lo, hi], \"bins\": ...}, ...]})");
  EXPECT_EQ(error(me + kAxes + R"(, "genome": "phase")"),
            "run.json: genome: applies to algorithm cma-es only");
  EXPECT_EQ(error(me + kAxes + R"(, "cma": {"sigma": 1})"),
            "run.json: cma: applies to algorithm cma-es only");
  EXPECT_EQ(error(std::string(R"(, "map_elites": )") + kAxes),
            "run.json: map_elites: applies to algorithm map-elites only");
  EXPECT_EQ(error(me + R"({"descriptors": [], "cells": 4})"),
            "run.json: map_elites.cells: unknown field");
}

TEST(MapElitesConfig, TheArchiveIsPartOfTheIdentityAndAfpoFieldsApply) {
  const EvolveConfig c = tiny();
  EXPECT_EQ(c.algorithm, Algorithm::kMapElites);
  ASSERT_EQ(c.map_elites.axes.size(), 3u);
  EXPECT_EQ(c.map_elites.cells(), 4 * 3 * 4);
  EXPECT_EQ(c.map_elites.axes[1].what, Descriptor::kPi);
  EXPECT_EQ(c.nx, 4);  // the CPPN genomes' fields apply
  EXPECT_EQ(parse_config(c.canonical_json(), "again").identity_json(), c.identity_json());
  EXPECT_NE(tiny(R"({"descriptors": [{"name": "fill", "bounds": [0.2, 1], "bins": 5},
      {"name": "pi", "bounds": [0, 1], "bins": 3}]})")
                .identity_json(),
            c.identity_json());
}

TEST(MapElitesCells, BinsAreEqualOverTheBoundsAndTheEndsTakeWhatIsOutside) {
  MapElitesSettings s;
  s.axes = {{Descriptor::kFill, 0, 1, 4}, {Descriptor::kComHeight, -2, 2, 2}};
  EXPECT_EQ(cell_of(s, {0.0, -2.0}), 0);
  EXPECT_EQ(cell_of(s, {0.26, 0.0}), 1 * 2 + 1);
  EXPECT_EQ(cell_of(s, {1.0, 5.0}), 3 * 2 + 1);    // the upper bound is in the last bin
  EXPECT_EQ(cell_of(s, {-7.0, -9.0}), 0);          // below: the first
  EXPECT_EQ(cell_of(s, {0.5, std::nan("")}), -1);  // not measured: no cell
  EXPECT_EQ(bins_of(s, 7), (std::vector<int>{3, 1}));
  for (int64_t cell = 0; cell < s.cells(); ++cell) {
    const std::vector<int> b = bins_of(s, cell);
    EXPECT_EQ(cell_of(s, {(b[0] + 0.5) / 4, -2 + (b[1] + 0.5) * 2}), cell);
  }
}

// A 2x2x2 block in a 4x4x4 lattice: 8 voxels, 2 and 6 GPa, development 0.5/s.
Phenotype block() {
  Phenotype p;
  p.robot = make_empty_robot(4, 4, 4);
  for (int z = 0; z < 2; ++z)
    for (int y = 0; y < 2; ++y)
      for (int x = 0; x < 2; ++x) {
        const int site = p.robot.site(x, y, z);
        p.robot.present[site] = 1;
        p.robot.stiffness[site] = x == 0 ? 2e9 : 6e9;
        p.robot.phase[site] = 0.1 * x;
        p.robot.dev_rate[site] = 0.5;
      }
  p.valid = true;
  p.voxels = 8;
  return p;
}

TEST(MapElitesDescriptors, TheBodysAreCountedAndTheLifesMeasuredWithoutChangingIt) {
  MapElitesSettings s;
  for (Descriptor d : {Descriptor::kVoxels, Descriptor::kFill, Descriptor::kPi, Descriptor::kGamma,
                       Descriptor::kUpsilon, Descriptor::kStiffness, Descriptor::kDevelopment,
                       Descriptor::kFloorContact, Descriptor::kComHeight})
    s.axes.push_back({d, 0, 1, 2});
  const Phenotype p = block();
  std::vector<double> v = body_descriptors(s, p);
  EXPECT_EQ(v[0], 8);
  EXPECT_EQ(v[1], 8.0 / 64);
  for (int k = 2; k < 5; ++k) EXPECT_TRUE(v[k] >= 0 && v[k] <= 1) << k;
  EXPECT_LT(v[2], 0.75);  // a solid block is no Π
  EXPECT_EQ(v[5], 4e9);
  for (int k = 6; k < 9; ++k) EXPECT_TRUE(std::isnan(v[k])) << k;

  PhysicsDef physics = tiny().physics;  // stress, 0.3 s
  const Evaluation e = evaluate_phenotype(p, physics);
  ASSERT_EQ(e.status, EvalStatus::kOk);
  // The watched life is simulate()'s, bit for bit.
  SimResult r = simulate(compile(p.robot, physics));
  judge_life(physics, r);
  EXPECT_EQ(e.fitness, r.fitness);
  ASSERT_TRUE(e.measures.measured);
  EXPECT_EQ(e.measures.development, r.stiffness_change_abs_mean);
  EXPECT_GT(e.measures.development, 0);  // stress develops
  // The lower layer stands on the floor, the upper does not; the centre sits a voxel up.
  EXPECT_NEAR(e.measures.floor_contact, 0.5, 0.05);
  EXPECT_NEAR(e.measures.com_height, 1.0, 0.1);
  life_descriptors(s, e.measures, v);
  EXPECT_EQ(v[6], e.measures.development);
  EXPECT_EQ(v[7], e.measures.floor_contact);
  EXPECT_EQ(v[8], e.measures.com_height);

  // Without a floor nothing touches it.
  physics.floor = false;
  EXPECT_EQ(evaluate_phenotype(p, physics).measures.floor_contact, 0);
}

// Golden bits of a tiny MAP-Elites run, on one and two threads.
TEST(MapElitesRun, TinyRunDigestOnOneAndTwoThreads) {
  const EvolveConfig c = tiny();
  const RunState one = evolved(c, 1);
  EXPECT_EQ(content_digest(one).hex(), "665366aa17a994d55557fa025409686d");
  EXPECT_EQ(content_digest(evolved(c, 2)), content_digest(one));
}

// Every life is replayed from the births (id order): a life that counts (ok, not sunk, not
// flagged by the vertical rule: evo_flagged_test provokes such lives) goes to the cell its
// descriptors give when it beats the best before it there; the archive holds exactly those.
TEST(MapElitesRun, EachCellHoldsTheBestLifeSeenForIt) {
  EvolveConfig c = tiny();
  c.generations = 6;
  const RunState s = evolved(c, 2);
  std::map<int64_t, const BirthRecord*> best;
  int counted = 0;
  for (const BirthRecord& b : s.births) {
    ASSERT_EQ(b.descriptors.size(), 3u);
    if (b.status != static_cast<uint8_t>(EvalStatus::kOk) || b.sank || b.vertical) continue;
    const int64_t cell = cell_of(c.map_elites, b.descriptors);
    ASSERT_GE(cell, 0);
    ++counted;
    const auto at = best.find(cell);
    if (at == best.end() || b.fitness > at->second->fitness) best[cell] = &b;
  }
  ASSERT_GT(counted, 10);
  ASSERT_EQ(s.archive.size(), best.size());
  ASSERT_GT(best.size(), 3u);
  size_t k = 0;
  double qd = 0;
  const Individual* top = &s.archive[0];
  for (const auto& [cell, b] : best) {
    const Individual& e = s.archive[k++];
    EXPECT_EQ(e.cell, cell);
    EXPECT_EQ(e.id, b->id);
    EXPECT_EQ(e.fitness, b->fitness);
    EXPECT_EQ(e.descriptors, b->descriptors);
    qd += e.fitness;
    if (e.fitness > top->fitness) top = &e;
  }
  EXPECT_EQ(s.history.back().filled, static_cast<int64_t>(best.size()));
  EXPECT_DOUBLE_EQ(s.history.back().qd_score, qd);  // qd_offset 0, every fitness >= 0
  EXPECT_EQ(s.champions.back().id, top->id);        // the champion is the best elite
  for (size_t g = 1; g < s.history.size(); ++g) {   // the archive only grows and improves
    EXPECT_GE(s.history[g].filled, s.history[g - 1].filled);
    EXPECT_GE(s.history[g].qd_score, s.history[g - 1].qd_score);
  }
  // Children are of elites: every parent is an individual of an earlier generation.
  for (const BirthRecord& b : s.births)
    if (b.generation > 0) {
      ASSERT_GE(b.parent_id, 0);
      EXPECT_LT(s.births[b.parent_id].generation, b.generation);
    }
}

// initial_population body-plans seeds generation 0 as under AFPO: the first three bodies are
// the paper's Π, Γ and Υ, and each one's own template score is its highest.
TEST(MapElitesRun, BodyPlanSeedsStartTheArchiveWithTheirOwnPlanScores) {
  std::string text = config_text(R"(, "algorithm": "map-elites",
      "initial_population": "body-plans", "map_elites": {"descriptors": [
      {"name": "pi", "bounds": [0, 1], "bins": 4}, {"name": "gamma", "bounds": [0, 1], "bins": 4},
      {"name": "upsilon", "bounds": [0, 1], "bins": 4}]})");
  const std::string small = R"("nx": 4, "ny": 4, "nz": 4)";
  text.replace(text.find(small), small.size(), R"("nx": 6, "ny": 6, "nz": 6)");
  EvolveConfig c = parse_config(text, "seeded");
  c.generations = 0;
  const RunState s = evolved(c, 2);
  for (size_t plan = 0; plan < 3; ++plan) {
    const std::vector<double>& d = s.births[plan].descriptors;
    for (size_t other = 0; other < 3; ++other)
      if (other != plan) {
        EXPECT_GT(d[plan], d[other]) << plan << " " << other;
      }
    EXPECT_GE(d[plan], 0.75) << plan;  // labelled as its plan by the classifier's threshold
  }
}

class MapElitesFiles : public testing::ScratchDirTest {};

TEST_F(MapElitesFiles, StopAndResumeEqualsUninterruptedAndTheChampionReplays) {
  const EvolveConfig c = tiny();
  const RunReport full = run_evolution(c, path("full.h5"), {});
  RunOptions stop;
  stop.stop_after = 2;
  stop.threads = 1;
  EXPECT_EQ(run_evolution(c, path("part.h5"), stop).outcome, RunOutcome::kStopped);
  const RunReport rest = run_evolution(c, path("part.h5"), {});
  EXPECT_EQ(rest.resumed_from, 2);
  EXPECT_EQ(rest.content_digest, full.content_digest);
  EXPECT_EQ(full.content_digest, content_digest(evolved(c, 1)).hex());

  const ResultsFile f = read_results(path("part.h5"));
  EXPECT_EQ(f.state.config.algorithm, Algorithm::kMapElites);
  const RunState direct = evolved(c, 1);
  ASSERT_EQ(f.state.archive.size(), direct.archive.size());
  for (size_t k = 0; k < direct.archive.size(); ++k) {
    EXPECT_EQ(f.state.archive[k].cell, direct.archive[k].cell);
    EXPECT_EQ(f.state.archive[k].genome, direct.archive[k].genome);
  }
  const ChampionRecord& champ = champion_at(f.state, -1, "part.h5");
  ASSERT_EQ(champ.status, static_cast<uint8_t>(EvalStatus::kOk));
  const RobotDef robot = champion_robot(champ, f.state.generations_done);
  const RobotFile back = parse_robot_json(robot_to_json(robot, &c.physics), "champion.json");
  EXPECT_EQ(simulate(compile(back.robot, back.physics)).fitness, champ.fitness);
}

}  // namespace
}  // namespace plastivox::evo
