// A whole study (plastivox/analysis/study.hpp and `plastivox analyze`) on tiny evolutions (4^3
// lattice, population 4, one generation, 0.2 s lives): the outputs exist and agree with each
// other and with the library's measures; results do not depend on the thread count, the file
// order or on resuming from checkpoints; bad inputs give one clear line and leave no output.
#include <hdf5.h>

#include <algorithm>
#include <atomic>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "plastivox/analysis/bootstrap_coverage.hpp"
#include "plastivox/analysis/study.hpp"
#include "plastivox/evo/champion.hpp"
#include "plastivox/evo/results_file.hpp"
#include "plastivox/evo/run.hpp"
#include "plastivox/io/h5_util.hpp"  // to read analysis.h5 back
#include "plastivox/io/robot_file.hpp"
#include "plastivox/io/robot_io.hpp"
#include "plastivox/rules/life_rules.hpp"
#include "plastivox/simulator.hpp"
#include "study_internal.hpp"  // the audit of replayed champions
#include "test_support.hpp"

namespace plastivox::analysis {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;

std::string read_text(const std::string& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// stats.json without its date (the only field allowed to differ between equal analyses).
std::string without_date(const std::string& stats) {
  Json j = Json::parse(stats);
  j["provenance"].erase("date");
  return j.dump();
}

std::vector<std::vector<std::string>> read_csv(const std::string& text) {
  std::vector<std::vector<std::string>> rows;
  std::vector<std::string> row;
  std::string field;
  bool quoted = false;
  for (size_t i = 0; i < text.size(); ++i) {
    const char ch = text[i];
    if (quoted) {
      if (ch == '"' && i + 1 < text.size() && text[i + 1] == '"') {
        field += '"';
        ++i;
      } else if (ch == '"') {
        quoted = false;
      } else {
        field += ch;
      }
    } else if (ch == '"') {
      quoted = true;
    } else if (ch == ',') {
      row.push_back(field);
      field.clear();
    } else if (ch == '\n') {
      row.push_back(field);
      rows.push_back(row);
      row.clear();
      field.clear();
    } else {
      field += ch;
    }
  }
  return rows;
}

// A CSV cell equals a JSON number (or null for an empty cell), bit for bit.
::testing::AssertionResult SameNumber(const std::string& cell, const Json& j) {
  if (j.is_null())
    return cell.empty() ? ::testing::AssertionSuccess()
                        : ::testing::AssertionFailure() << "'" << cell << "' vs null";
  if (cell.empty()) return ::testing::AssertionFailure() << "empty vs " << j.dump();
  if (std::stod(cell) == j.get<double>()) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << cell << " vs " << j.dump();
}

class Study : public testing::ScratchDirTest {
 protected:
  // A finished tiny run; `physics` is the JSON object of physics fields, `controller` the
  // config's controller field ("" for none: the sine). By default walk is scored in the
  // horizontal plane: 0.1 s of settling leaves some of these bodies toppling, and under the 3-D
  // fitness the vertical rule flags such a champion (stress-s4 of six_runs falls 0.59 voxel
  // lengths; docs/engine.md, "Vertical motion"), which the tests below test on their own.
  std::string run(Treatment t, uint64_t seed,
                  const std::string& physics = R"({"duration": 0.2, "settle_time": 0.1,
                                                   "fitness": "xy"})",
                  const std::string& controller = "") {
    evo::EvolveConfig c = evo::parse_config(
        R"({"format": "plastivox-evolve-config", "version": 1, "treatment": ")" +
            std::string(to_string(t)) + R"(", "seed": )" + std::to_string(seed) +
            R"(, "population": 4, "generations": 1, "lattice": {"nx": 4, "ny": 4, "nz": 4},
               "physics": )" +
            physics + (controller.empty() ? "" : ", \"controller\": " + controller) + "}",
        "tiny");
    const std::string p = path(std::string(to_string(t)) + "-" + std::to_string(seed) + ".h5");
    evo::RunOptions o;
    o.threads = 1;
    EXPECT_EQ(evo::run_evolution(c, p, o).outcome, evo::RunOutcome::kFinished);
    return p;
  }
  // Two runs of each treatment, seeds 1..6 (one seed in two developing treatments would
  // start from the same robots, and identical champions are simulated only once).
  std::vector<std::string> six_runs() {
    std::vector<std::string> files;
    uint64_t seed = 0;
    for (Treatment t : {Treatment::kNone, Treatment::kStress, Treatment::kPressure})
      for (int k = 0; k < 2; ++k) files.push_back(run(t, ++seed));
    return files;
  }
  static StudyOptions quick() {
    StudyOptions o;
    o.robustness_draws = 3;
    o.resamples = 2000;
    o.threads = 2;
    return o;
  }
};

using testing::error_of;

TEST_F(Study, OutputsExistAndAgreeWithEachOther) {
  const std::vector<std::string> files = six_runs();
  StudyOptions o = quick();
  o.cache_dir = path("out/cache");
  const StudyResult r = analyze_study(files, o);
  write_study_outputs(r, path("out"));

  for (const char* f :
       {"stats.json", "champions.csv", "statistics.csv", "hausdorff.csv", "analysis.h5"})
    EXPECT_TRUE(fs::exists(path("out/") + f)) << f;
  EXPECT_FALSE(fs::exists(path("out/report.html"))) << "the analysis writes data only";
  // The study read back from analysis.h5 makes the very report the computed study makes, so
  // the report needs nothing recomputed.
  const StudyResult back = read_study_result(path("out/analysis.h5"));
  EXPECT_EQ(report_html(back), report_html(r));
  EXPECT_EQ(back.fingerprint, r.fingerprint);
  EXPECT_EQ(options_json(back.options), options_json(r.options));
  ASSERT_EQ(back.champions.size(), r.champions.size());
  StudyResult bodies = back;
  load_champion_bodies(bodies);
  for (size_t i = 0; i < r.champions.size(); ++i) {
    EXPECT_EQ(bodies.champions[i].robot.stiffness, r.champions[i].robot.stiffness) << i;
    EXPECT_EQ(bodies.champions[i].final_stiffness, r.champions[i].final_stiffness) << i;
    EXPECT_EQ(bodies.champions[i].fitness, r.champions[i].fitness) << i;
  }
  for (const auto& e : fs::directory_iterator(path("out")))
    EXPECT_EQ(e.path().string().find(".tmp"), std::string::npos) << e.path();

  const std::string stats_text = read_text(path("out/stats.json"));
  EXPECT_EQ(stats_text, stats_json(r));
  const Json j = Json::parse(stats_text);
  EXPECT_EQ(j["format"], "plastivox-analysis");
  EXPECT_EQ(j["format_version"], 1);
  EXPECT_EQ(j["treatments"], Json({"none", "stress", "pressure"}));
  EXPECT_EQ(j["provenance"]["inputs"].size(), 6u);
  EXPECT_EQ(j["provenance"]["fingerprint"], r.fingerprint);
  EXPECT_EQ(j["statistics"]["correction"], "Bonferroni");
  EXPECT_EQ(j["statistics"]["resamples"], 2000);

  // Panels A..F; D, E, F only for the developing treatments.
  ASSERT_EQ(j["panels"].size(), 6u);
  const char* ids[] = {"A", "B", "C", "D", "E", "F"};
  for (int p = 0; p < 6; ++p) {
    const Json& panel = j["panels"][p];
    EXPECT_EQ(panel["id"], ids[p]);
    EXPECT_EQ(panel["groups"].size(), p < 3 ? 3u : 2u) << ids[p];
    for (const Json& c : panel["comparisons"]) {
      EXPECT_EQ(c["p_corrected"].get<double>(),
                std::min(1.0, c["p"].get<double>() * panel["comparisons"].size()));
      EXPECT_EQ(c["comparisons"], panel["comparisons"].size());
    }
  }

  // Champions: 6, sorted by treatment then seed; the JSON measures are the library's.
  ASSERT_EQ(j["champions"].size(), 6u);
  EXPECT_EQ(j["champions"][0]["label"], "none-s1");
  EXPECT_EQ(j["champions"][5]["label"], "pressure-s6");
  for (const ChampionAnalysis& c : r.champions) {
    if (c.evaluation != "ok") continue;
    const Canalization k = canalization(body_values(c.robot, c.robot.stiffness),
                                        body_values(c.robot, c.final_stiffness));
    EXPECT_EQ(*c.m_body, k.m_body) << c.label;
    EXPECT_EQ(*c.v_body, k.v_body) << c.label;
    if (c.treatment == Treatment::kNone) {
      // Without development the robustness baseline is the evolved robot itself.
      EXPECT_EQ(c.robustness.f_train, c.fitness) << c.label;
      EXPECT_EQ(*c.m_body, 0.0);
      EXPECT_FALSE(c.v_gain.has_value());
    } else {
      std::vector<std::vector<double>> alphas;
      for (const ChampionAnalysis& d : r.champions)
        if (d.treatment == c.treatment) alphas.push_back(body_values(d.robot, d.robot.dev_rate));
      EXPECT_EQ(*c.v_gain,
                v_gain(body_values(c.robot, c.robot.dev_rate), evolved_alpha_range(alphas)));
    }
    EXPECT_EQ(c.body_plan.plan, classify_body_plan(voxel_set(c.robot)).plan);
  }

  // champions.csv: one row per champion, the same numbers as stats.json.
  const auto rows = read_csv(read_text(path("out/champions.csv")));
  ASSERT_EQ(rows.size(), 7u);
  auto col = [&](const std::string& name) {
    return static_cast<size_t>(std::find(rows[0].begin(), rows[0].end(), name) - rows[0].begin());
  };
  for (size_t i = 0; i < 6; ++i) {
    const Json& c = j["champions"][i];
    EXPECT_EQ(rows[i + 1][col("label")], c["label"]);
    EXPECT_EQ(rows[i + 1][col("body_plan")], c["body_plan"]);
    EXPECT_TRUE(SameNumber(rows[i + 1][col("fitness")], c["fitness"]));
    EXPECT_TRUE(SameNumber(rows[i + 1][col("r_mean")], c["robustness"]["R_mean"]));
    EXPECT_TRUE(SameNumber(rows[i + 1][col("m_body")], c["m_body"]));
    EXPECT_TRUE(SameNumber(rows[i + 1][col("v_body")], c["v_body"]));
    EXPECT_TRUE(SameNumber(rows[i + 1][col("v_gain")], c["v_gain"]));
    for (int k = 0; k < 3; ++k)
      EXPECT_TRUE(
          SameNumber(rows[i + 1][col("r_draw_" + std::to_string(k))], c["robustness"]["draws"][k]));
  }

  // statistics.csv: one row per panel x treatment and per comparison.
  const auto stats_rows = read_csv(read_text(path("out/statistics.csv")));
  size_t row = 1;
  for (const Json& panel : j["panels"]) {
    for (const Json& g : panel["groups"]) {
      ASSERT_LT(row, stats_rows.size());
      EXPECT_EQ(stats_rows[row][0], "group");
      EXPECT_EQ(stats_rows[row][1], panel["id"]);
      EXPECT_EQ(stats_rows[row][4], g["treatment"]);
      EXPECT_TRUE(SameNumber(stats_rows[row][6], g["mean"]));
      EXPECT_TRUE(SameNumber(stats_rows[row][7], g["ci_low"]));
      EXPECT_TRUE(SameNumber(stats_rows[row][8], g["ci_high"]));
      ++row;
    }
    for (const Json& c : panel["comparisons"]) {
      ASSERT_LT(row, stats_rows.size());
      EXPECT_EQ(stats_rows[row][0], "comparison");
      EXPECT_EQ(stats_rows[row][9], c["a"]);
      EXPECT_TRUE(SameNumber(stats_rows[row][12], c["p"]));
      EXPECT_TRUE(SameNumber(stats_rows[row][13], c["p_corrected"]));
      EXPECT_EQ(stats_rows[row][14], c["stars"]);
      ++row;
    }
  }
  EXPECT_EQ(row, stats_rows.size());

  // The Hausdorff matrix: symmetric, zero diagonal, the same in CSV; panel B's values are the
  // within-treatment pairs.
  const Json& m = j["hausdorff"]["matrix"];
  const auto hrows = read_csv(read_text(path("out/hausdorff.csv")));
  ASSERT_EQ(hrows.size(), 7u);
  for (int a = 0; a < 6; ++a)
    for (int b = 0; b < 6; ++b) {
      EXPECT_EQ(m[a][b], m[b][a]);
      if (a == b) {
        EXPECT_EQ(m[a][b].get<double>(), 0.0);
      }
      EXPECT_TRUE(SameNumber(hrows[a + 1][b + 1], m[a][b]));
    }
  double lo = 1e300, hi = 0;
  for (int a = 0; a < 6; ++a)
    for (int b = a + 1; b < 6; ++b) {
      lo = std::min(lo, m[a][b].get<double>());
      hi = std::max(hi, m[a][b].get<double>());
    }
  const Json& most = j["hausdorff"]["most_similar"];
  const Json& least = j["hausdorff"]["least_similar"];
  ASSERT_EQ(most.size(), 5u);
  ASSERT_EQ(least.size(), 5u);
  EXPECT_EQ(most[0]["distance"].get<double>(), lo);
  EXPECT_EQ(least[0]["distance"].get<double>(), hi);
  for (int k = 1; k < 5; ++k) {
    EXPECT_LE(most[k - 1]["distance"].get<double>(), most[k]["distance"].get<double>());
    EXPECT_GE(least[k - 1]["distance"].get<double>(), least[k]["distance"].get<double>());
  }
  const Json& b_groups = j["panels"][1]["groups"];
  for (int t = 0; t < 3; ++t) EXPECT_EQ(b_groups[t]["values"], Json::array({m[2 * t][2 * t + 1]}));

  // analysis.h5 holds the same stats.json and matrix.
  {
    const h5::Ctx ctx{path("out/analysis.h5"), 0};
    h5::Handle f(H5Fopen(path("out/analysis.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT),
                 h5::Handle::Kind::kFile);
    ASSERT_GE(f.id(), 0);
    EXPECT_EQ(h5::read_strings(ctx, f.id(), "stats_json", 1)[0], stats_text);
    EXPECT_EQ(h5::read_attr_string(ctx, f.id(), "/", "format"), "plastivox-analysis");
    std::vector<hsize_t> dims = {6, 6};
    EXPECT_EQ(h5::read<double>(ctx, f.id(), "hausdorff/matrix", dims), r.hausdorff.distance);
  }

  // The report: self-contained HTML with the heat map, every champion and the statistics.
  const std::string html = report_html(read_study_result(path("out/analysis.h5")));
  EXPECT_NE(html.find("<svg"), std::string::npos);
  // The heat map's legend: the largest distance alone under the bar's end, the unit after the
  // bar (a number and the unit under a short bar overran its 0).
  char top[64];
  std::snprintf(top, sizeof top, ">%.4g</text>",
                *std::max_element(r.hausdorff.distance.begin(), r.hausdorff.distance.end()));
  EXPECT_NE(html.find(top), std::string::npos) << top;
  EXPECT_NE(html.find("\">voxel lengths</text>"), std::string::npos);
  EXPECT_EQ(html.find("<script"), std::string::npos);
  for (const ChampionAnalysis& c : r.champions) EXPECT_NE(html.find(c.label), std::string::npos);
  EXPECT_NE(html.find("Bonferroni"), std::string::npos);
  EXPECT_NE(html.find(r.inputs[0].content_digest), std::string::npos);
}

// The evolution curves come from each file's stored history: best fitness per generation as
// recorded, mean fitness over the valid survivors, lineages among the survivors; the band is
// the mean over a treatment's runs inside its bootstrap CI. Nothing is written to the runs.
TEST_F(Study, EvolutionCurvesComeFromTheRunsHistory) {
  const std::vector<std::string> files = {run(Treatment::kStress, 1), run(Treatment::kStress, 2)};
  std::vector<std::string> digests;
  for (const auto& f : files) digests.push_back(evo::read_results(f).content_digest);
  const StudyResult r = analyze_study(files, quick());
  ASSERT_EQ(r.inputs.size(), 2u);
  for (size_t k = 0; k < r.inputs.size(); ++k) {
    const evo::ResultsFile rf = evo::read_results(r.inputs[k].file);
    EXPECT_EQ(rf.content_digest, digests[k]);  // reading changed nothing
    const EvolutionCurve& e = r.inputs[k].evolution;
    ASSERT_EQ(e.best.size(), rf.state.history.size());
    for (size_t g = 0; g < e.best.size(); ++g) {
      const evo::GenerationRecord& h = rf.state.history[g];
      EXPECT_EQ(e.best[g], h.best_fitness);
      double sum = 0;
      int valid = 0;
      for (size_t i = 0; i < h.fitness.size(); ++i)
        if (h.status[i] == 0) sum += h.fitness[i], ++valid;
      if (valid) {
        EXPECT_DOUBLE_EQ(e.mean[g], sum / valid);
      }
      EXPECT_GE(e.lineages[g], 1);
      EXPECT_LE(e.lineages[g], static_cast<int>(h.id.size()));
    }
    // Generation 0 is all random individuals: as many lineages as survivors.
    EXPECT_EQ(e.lineages[0], static_cast<int>(rf.state.history[0].id.size()));
  }
  ASSERT_EQ(r.evolution.size(), 1u);
  const EvolutionBand& b = r.evolution[0];
  EXPECT_EQ(b.runs, 2);
  ASSERT_EQ(b.mean.size(), r.inputs[0].evolution.best.size());
  for (size_t g = 0; g < b.mean.size(); ++g) {
    EXPECT_DOUBLE_EQ(b.mean[g],
                     (r.inputs[0].evolution.best[g] + r.inputs[1].evolution.best[g]) / 2);
    EXPECT_LE(b.ci_low[g], b.mean[g]);
    EXPECT_GE(b.ci_high[g], b.mean[g]);
  }
  const Json j = Json::parse(stats_json(r));
  ASSERT_TRUE(j.contains("evolution"));
  EXPECT_EQ(j["evolution"]["runs"].size(), 2u);
  EXPECT_EQ(j["evolution"]["runs"][0]["best_fitness"].size(), b.mean.size());
  EXPECT_EQ(j["evolution"]["treatments"][0]["treatment"], "stress");
}

TEST_F(Study, ReportTakesExtraSections) {
  const StudyResult r =
      analyze_study({run(Treatment::kStress, 1), run(Treatment::kStress, 2)}, quick());
  ReportExtras x;
  x.title = "My <experiment>";
  ReportSection sec;
  sec.title = "Figures";
  sec.paragraphs = {"Panels A-F."};
  ReportMedia panel, video;
  panel.path = "figures/panel_A.png";
  panel.caption = "Fitness";
  panel.links = {{"SVG", "figures/panel_A.svg"}};
  video.kind = ReportMedia::Kind::kVideo;
  video.path = "videos/best.mp4";
  video.caption = "Callus growth";
  sec.media = {panel, video};
  x.sections.push_back(sec);
  const std::string html = report_html(r, x);
  // The figure's own caption carries its vector link, inside the same <figure>.
  EXPECT_NE(html.find("<figure><img src=\"figures/panel_A.png\" alt=\"Fitness\"><figcaption>"
                      "Fitness <a href=\"figures/panel_A.svg\">SVG</a></figcaption></figure>"),
            std::string::npos)
      << html;
  EXPECT_NE(html.find("<title>My &lt;experiment&gt;</title>"), std::string::npos);
  EXPECT_NE(html.find("<img src=\"figures/panel_A.png\""), std::string::npos);
  EXPECT_NE(html.find("<video controls src=\"videos/best.mp4\""), std::string::npos);
  write_study_report(r, path("report.html"), x);
  EXPECT_EQ(read_text(path("report.html")), html);
}

TEST_F(Study, ResultsDoNotDependOnThreadsOrFileOrder) {
  std::vector<std::string> files = six_runs();
  StudyOptions o = quick();
  o.threads = 1;
  const std::string one = without_date(stats_json(analyze_study(files, o)));
  o.threads = 2;
  std::reverse(files.begin(), files.end());
  const StudyResult two = analyze_study(files, o);
  EXPECT_EQ(without_date(stats_json(two)), one);

  // Another seed draws other stiffness fields (and another bootstrap).
  o.seed = 7;
  const StudyResult other = analyze_study(files, o);
  int differ = 0;
  for (size_t i = 0; i < other.champions.size(); ++i) {
    EXPECT_NE(other.champions[i].robustness_seed, two.champions[i].robustness_seed);
    EXPECT_EQ(other.champions[i].robustness.f_train, two.champions[i].robustness.f_train);
    differ += other.champions[i].robustness.draws[0].f_test !=
              two.champions[i].robustness.draws[0].f_test;
  }
  EXPECT_GT(differ, 0);
}

TEST_F(Study, ResumesFromCheckpointsWithIdenticalResults) {
  const std::vector<std::string> files = six_runs();
  StudyOptions o = quick();
  const std::string uninterrupted = without_date(stats_json(analyze_study(files, o)));

  o.cache_dir = path("cache");
  const StudyResult first = analyze_study(files, o);
  EXPECT_EQ(first.timings.robustness_cached, 0);
  EXPECT_EQ(first.timings.robustness_simulations, 6 * (1 + 3));
  std::vector<fs::path> checkpoints;
  for (const auto& e : fs::directory_iterator(path("cache"))) checkpoints.push_back(e.path());
  std::sort(checkpoints.begin(), checkpoints.end());
  ASSERT_EQ(checkpoints.size(), 6u);

  // As if killed after three champions: three checkpoints gone, one damaged.
  for (int k = 0; k < 3; ++k) fs::remove(checkpoints[k]);
  std::ofstream(checkpoints[3], std::ios::trunc) << "{\"format\": \"plastivox-robustness";
  std::vector<std::string> messages;
  const StudyResult resumed =
      analyze_study(files, o, [&](const StudyProgress& p) { messages.push_back(p.message); });
  EXPECT_EQ(resumed.timings.robustness_cached, 2);
  EXPECT_EQ(resumed.timings.robustness_simulations, 4 * (1 + 3));
  EXPECT_EQ(without_date(stats_json(resumed)), uninterrupted);
  EXPECT_EQ(without_date(stats_json(first)), uninterrupted);
  const auto from_checkpoint = std::count_if(messages.begin(), messages.end(), [](auto& m) {
    return m.find("(from checkpoint)") != std::string::npos;
  });
  EXPECT_EQ(from_checkpoint, 2);

  // A third run does no simulation at all.
  const StudyResult again = analyze_study(files, o);
  EXPECT_EQ(again.timings.robustness_simulations, 0);
  EXPECT_EQ(without_date(stats_json(again)), uninterrupted);
}

TEST_F(Study, StopRequestKeepsFinishedChampionsAndResumes) {
  const std::vector<std::string> files = six_runs();
  StudyOptions o = quick();
  o.threads = 1;
  const std::string uninterrupted = without_date(stats_json(analyze_study(files, o)));

  // Ctrl-C while the first champion runs: it finishes and is checkpointed, nothing else starts.
  std::atomic<bool> stop{false};
  o.cache_dir = path("cache");
  o.stop_requested = &stop;
  const std::string msg = error_of([&] {
    analyze_study(files, o, [&](const StudyProgress& p) {
      if (p.stage == "robustness") stop.store(true);
    });
  });
  EXPECT_NE(msg.find("stopped on request with 1 of 6 champions"), std::string::npos) << msg;
  EXPECT_EQ(std::distance(fs::directory_iterator(path("cache")), fs::directory_iterator()), 1);

  stop.store(false);
  const StudyResult resumed = analyze_study(files, o);
  EXPECT_EQ(resumed.timings.robustness_cached, 1);
  EXPECT_EQ(without_date(stats_json(resumed)), uninterrupted);
}

TEST_F(Study, BadInputsGiveOneClearLine) {
  const std::string a = run(Treatment::kStress, 1), b = run(Treatment::kPressure, 1);
  auto expect_error = [](const std::string& msg, const std::string& needle) {
    EXPECT_NE(msg.find(needle), std::string::npos) << msg;
    EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
  };
  const StudyOptions o = quick();
  expect_error(error_of([&] { analyze_study({}, o); }), "no results files");
  expect_error(error_of([&] {
                 analyze_study({a, path("missing.h5")}, o);
               }),
               path("missing.h5") + ": no such file");
  expect_error(error_of([&] { analyze_study({a, a}, o); }), "the same run as");

  // An HDF5 file from another tool.
  {
    const hid_t f = H5Fcreate(path("other.h5").c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
    ASSERT_GE(f, 0);
    H5Fclose(f);
  }
  expect_error(error_of([&] { analyze_study({a, path("other.h5")}, o); }), path("other.h5") + ": ");

  // A generation the run never reached: no champion there.
  StudyOptions late = o;
  late.generation = 5;
  expect_error(error_of([&] { analyze_study({a}, late); }), a + ": generation 5 not reached");

  // An expected treatment without files.
  StudyOptions all = o;
  all.treatments = {Treatment::kNone, Treatment::kStress, Treatment::kPressure};
  expect_error(error_of([&] {
                 analyze_study({a, b}, all);
               }),
               "treatment none: no results file given (empty treatment)");

  // Mixed physics: refused unless allowed, then a warning.
  const std::string c =
      run(Treatment::kNone, 3,
          R"({"duration": 0.2, "settle_time": 0.1, "fitness": "xy", "mu_static": 0.9})");
  expect_error(error_of([&] { analyze_study({a, c}, o); }), "mixed physics");
  // ... naming the first field that differs, with both files' values.
  expect_error(error_of([&] {
                 analyze_study({a, c}, o);
               }),
               "(mu_static: 0.9 in " + c + ", 1.0 in " + a + ")");

  // Reading a study back: anything but an analysis.h5 is refused by name.
  expect_error(error_of([&] { read_study_result(path("missing.h5")); }),
               path("missing.h5") + ": no such file");
  expect_error(error_of([&] { read_study_result(path("other.h5")); }),
               path("other.h5") + ": not a plastivox analysis");
  expect_error(error_of([&] { read_study_result(a); }), a + ": not a plastivox analysis");
  StudyOptions mixed = o;
  mixed.allow_mixed_physics = true;
  const StudyResult r = analyze_study({a, c}, mixed);
  ASSERT_EQ(r.warnings.size(), 1u);
  EXPECT_NE(r.warnings[0].find("mu_static"), std::string::npos) << r.warnings[0];
  EXPECT_EQ(r.champions.size(), 2u);
}

// The run of `seed` stopped after generation 0 of 1, written to `name`: a copy of run(t, seed)
// (its default physics) that did not finish.
std::string unfinished_run(const std::string& file, Treatment t, uint64_t seed) {
  evo::EvolveConfig c = evo::parse_config(
      R"({"format": "plastivox-evolve-config", "version": 1, "treatment": ")" +
          std::string(to_string(t)) + R"(", "seed": )" + std::to_string(seed) +
          R"(, "population": 4, "generations": 1, "lattice": {"nx": 4, "ny": 4, "nz": 4},
             "physics": {"duration": 0.2, "settle_time": 0.1, "fitness": "xy"}})",
      "tiny");
  evo::RunOptions o;
  o.threads = 1;
  o.stop_after = 0;
  EXPECT_EQ(evo::run_evolution(c, file, o).outcome, evo::RunOutcome::kStopped);
  return file;
}

// Two champions per treatment (the default study's n): every comparison is reported without
// power, with no stars in any output, a warning in stats.json and a sentence in the report,
// and the paper's published comparisons stand beside this study's estimates, none of them
// called a contradiction.
TEST_F(Study, TwoChampionsPerTreatmentHaveNoPowerAndThePaperStandsBeside) {
  const StudyResult r = analyze_study(six_runs(), quick());
  write_study_outputs(r, path("out"));
  const Json j = Json::parse(read_text(path("out/stats.json")));
  EXPECT_EQ(j["statistics"]["min_champions_for_power"], kMinBootstrapN);
  int comparisons = 0;
  for (const Json& p : j["panels"])
    for (const Json& c : p["comparisons"]) {
      ++comparisons;
      EXPECT_EQ(c["stars"], "") << p["id"];
      EXPECT_FALSE(c["powered"].get<bool>()) << p["id"];
      EXPECT_FALSE(c["significant"].get<bool>()) << p["id"];
    }
  // A and C over three treatments, D, E, F over two; B has one pair per treatment: no test.
  EXPECT_EQ(comparisons, 3 + 3 + 1 + 1 + 1);
  std::string warning;
  for (const Json& w : j["warnings"])
    if (w.get<std::string>().starts_with("no statistical power")) warning = w;
  EXPECT_NE(
      warning.find("9 of 9 comparisons (panels A, C, D, E, F) rest on fewer than " +
                   std::to_string(kMinBootstrapN) + " champions per treatment (the fewest: 2)"),
      std::string::npos)
      << j["warnings"].dump();
  const Json& rows = j["paper_comparison"]["rows"];
  ASSERT_EQ(rows.size(), 10u);
  for (const Json& row : rows) {
    EXPECT_EQ(row["measured"].get<bool>(), row["panel"] != "B") << row.dump();
    EXPECT_EQ(row["n_a"], 2) << row.dump();
    EXPECT_FALSE(row["powered"].get<bool>()) << row.dump();
    if (row["measured"].get<bool>()) {
      EXPECT_LE(row["ci_low"].get<double>(), row["difference"].get<double>()) << row.dump();
      EXPECT_GE(row["ci_high"].get<double>(), row["difference"].get<double>()) << row.dump();
    }
    const std::string verdict = row["verdict"];
    EXPECT_FALSE(verdict.starts_with("contradicts")) << verdict;
    EXPECT_NE(verdict.find("n = 2 < " + std::to_string(kMinBootstrapN)), std::string::npos)
        << verdict;
  }
  EXPECT_EQ(rows[5]["paper_found"], "stress > none");  // robustness, Fig. 5C
  EXPECT_EQ(rows[5]["paper_p"], "P < 0.01");
  for (const std::vector<std::string>& row : read_csv(read_text(path("out/statistics.csv"))))
    EXPECT_TRUE(row[14].empty() || row[14] == "stars") << row[14];

  const std::string html = report_html(r);
  EXPECT_NE(html.find("<p class=\"warn\" id=\"no-power\">These comparisons have no statistical "
                      "power: 9 of 9 rest on fewer than"),
            std::string::npos);
  EXPECT_EQ(html.find("<td class=\"stars\">*"), std::string::npos);
  EXPECT_NE(html.find("<h3 id=\"paper-comparison\">The paper found / this study found</h3>"),
            std::string::npos);
  EXPECT_NE(html.find("<td>none (n = 2)</td>"), std::string::npos);
}

// A comparison's stars follow the sample it rests on, in every output, whatever its result
// carries (a study read back from an analysis.h5 written before the rule carries stars at any
// n): none below kMinBootstrapN champions per treatment, the test's own at or above it.
TEST(StudyPower, StarsOnlyWhereTheSampleCanBearThem) {
  const auto result_with = [](int n) {
    NamedSample none{"none", {}}, stress{"stress", {}};
    for (int i = 0; i < n; ++i) {
      none.values.push_back(0.1 * (i % 3));
      stress.values.push_back(1 + 0.1 * (i % 3));
    }
    StudyResult r;
    r.treatments = {Treatment::kNone, Treatment::kStress};
    PanelStats p;
    p.id = "C";
    p.metric = "robustness";
    p.title = "Robustness";
    for (const NamedSample* s : {&none, &stress}) {
      GroupStats g;
      g.treatment = s == &none ? Treatment::kNone : Treatment::kStress;
      g.values = s->values;
      g.mean = mean(g.values);
      p.groups.push_back(g);
    }
    BootstrapTestOptions o;
    o.resamples = 2000;
    p.comparisons = pairwise_bootstrap_tests({none, stress}, o);
    r.panels.push_back(p);
    return r;
  };
  const StudyResult few = result_with(5), enough = result_with(kMinBootstrapN);
  ASSERT_NE(few.panels[0].comparisons[0].stars, "");  // the test alone would star it
  ASSERT_EQ(enough.panels[0].comparisons[0].stars, "***");
  const Json j_few = Json::parse(stats_json(few)), j_enough = Json::parse(stats_json(enough));
  const Json &c_few = j_few["panels"][0]["comparisons"][0],
             &c_enough = j_enough["panels"][0]["comparisons"][0];
  EXPECT_EQ(c_few["stars"], "");
  EXPECT_FALSE(c_few["powered"].get<bool>());
  EXPECT_FALSE(c_few["significant"].get<bool>());
  EXPECT_EQ(c_enough["stars"], "***");
  EXPECT_TRUE(c_enough["powered"].get<bool>());
  const auto csv_stars = [](const StudyResult& r) {  // column 14 of the comparison's row
    for (const std::vector<std::string>& row : read_csv(statistics_csv(r)))
      if (row[0] == "comparison") return row[14];
    return std::string("no comparison");
  };
  EXPECT_EQ(csv_stars(few), "");
  EXPECT_EQ(csv_stars(enough), "***");
  const std::string html_few = report_html(few), html_enough = report_html(enough);
  EXPECT_NE(html_few.find("<td class=\"stars\"></td>"), std::string::npos);
  EXPECT_EQ(html_few.find("<td class=\"stars\">*"), std::string::npos);
  EXPECT_NE(html_few.find("id=\"no-power\""), std::string::npos);
  EXPECT_NE(html_enough.find("<td class=\"stars\">***</td>"), std::string::npos);
  EXPECT_EQ(html_enough.find("id=\"no-power\""), std::string::npos);
  // The paper's robustness finding (stress > none, P < 0.01) beside each.
  const Json& row_few = j_few["paper_comparison"]["rows"][5];
  ASSERT_EQ(row_few["panel"], "C");
  EXPECT_EQ(row_few["verdict"],
            "same direction, but n = 5 < " + std::to_string(kMinBootstrapN) + " cannot resolve it");
  EXPECT_EQ(j_enough["paper_comparison"]["rows"][5]["verdict"], "agrees");
  EXPECT_EQ(j_enough["paper_comparison"]["rows"][0]["verdict"], "not compared in this study");
  EXPECT_TRUE(j_enough["warnings"].empty());
}

// Panel B's values are pairs: its power counts the champions behind them, read from the
// panel's groups (a comparison read back from analysis.h5 carries no n of its own).
TEST(StudyPower, DiversityCountsChampionsNotPairs) {
  const auto powered = [](const std::string& metric, int values) {
    StudyResult r;
    PanelStats p;
    p.id = "B";
    p.metric = metric;
    for (Treatment t : {Treatment::kNone, Treatment::kStress}) {
      GroupStats g;
      g.treatment = t;
      g.values.assign(static_cast<size_t>(values), 1.0);
      p.groups.push_back(g);
    }
    BootstrapTestResult t;
    t.name_a = "none";
    t.name_b = "stress";
    p.comparisons = {t};
    r.panels = {p};
    return Json::parse(stats_json(r))["panels"][0]["comparisons"][0]["powered"].get<bool>();
  };
  const int n = kMinBootstrapN;
  EXPECT_TRUE(powered("diversity", n * (n - 1) / 2));
  EXPECT_FALSE(powered("diversity", (n - 1) * (n - 2) / 2));
  EXPECT_TRUE(powered("fitness", (n - 1) * (n - 2) / 2));  // as many champions as values
  EXPECT_FALSE(powered("fitness", n - 1));
}

// Champions that share one body descended from a hand-built one are named beside the
// diversity panel and in stats.json; a champion of the same plan with another body is not.
TEST(StudySharedBody, ChampionsOfOneSeededBodyAreNamed) {
  StudyResult r;
  r.treatments = {Treatment::kNone, Treatment::kStress, Treatment::kPressure};
  const std::vector<std::string> labels = {"none-s1", "stress-s1", "pressure-s1"};
  for (int i = 0; i < 3; ++i) {
    StudyInput in;
    in.file = labels[i] + ".h5";
    r.inputs.push_back(in);
    ChampionAnalysis c;
    c.label = labels[i];
    c.input = i;
    c.treatment = r.treatments[i];
    c.seeded_plan = 0;
    c.robot.nx = c.robot.ny = c.robot.nz = 2;
    c.robot.present = {1, 1, 1, 1, 1, 0, 1, 0};
    r.champions.push_back(c);
  }
  r.champions[2].robot.present[7] = 1;  // pressure-s1 grew a voxel: another body
  r.hausdorff.n = 3;
  r.hausdorff.distance = {0, 0, 1, 0, 0, 1, 1, 1, 0};
  const Json j = Json::parse(stats_json(r));
  ASSERT_EQ(j["hausdorff"]["shared_seeded_bodies"].size(), 1u);
  EXPECT_EQ(j["hausdorff"]["shared_seeded_bodies"][0]["seeded_plan"], "Pi");
  EXPECT_EQ(j["hausdorff"]["shared_seeded_bodies"][0]["labels"],
            Json::array({"none-s1", "stress-s1"}));
  const std::string note =
      "2 champions (none-s1, stress-s1) share one body, descended from the hand-built Π that "
      "generation 0 held";
  bool warned = false;
  for (const Json& w : j["warnings"]) warned |= w.get<std::string>().starts_with(note);
  EXPECT_TRUE(warned) << j["warnings"].dump();
  const std::string html = report_html(r);
  const size_t at = html.find("<p class=\"warn\" id=\"shared-body\">" + note);
  ASSERT_NE(at, std::string::npos);
  EXPECT_LT(html.find("Diversity: Hausdorff distances"), at);  // beside the panel
  EXPECT_LT(at, html.find("<svg", at - 1));
  // Not seeded (a random start): nothing to say.
  for (ChampionAnalysis& c : r.champions) c.seeded_plan = -1;
  EXPECT_TRUE(Json::parse(stats_json(r))["hausdorff"]["shared_seeded_bodies"].empty());
  EXPECT_EQ(report_html(r).find("id=\"shared-body\""), std::string::npos);
}

// The load records which hand-built body a champion's lineage began from: at generation 0 of a
// run seeded with them, the first three individuals are Π, Γ, Υ and any other is random.
TEST_F(Study, TheLoadKnowsWhichChampionsDescendFromAHandBuiltBody) {
  std::vector<std::string> files;
  for (uint64_t seed : {1, 2, 3}) {
    evo::EvolveConfig c = evo::parse_config(
        R"({"format": "plastivox-evolve-config", "version": 1, "treatment": "none", "seed": )" +
            std::to_string(seed) +
            R"(, "population": 4, "generations": 1, "lattice": {"nx": 6, "ny": 6, "nz": 6},
               "initial_population": "body-plans",
               "physics": {"duration": 0.2, "settle_time": 0.1}})",
        "seeded");
    files.push_back(path("seeded-" + std::to_string(seed) + ".h5"));
    evo::RunOptions o;
    o.threads = 1;
    ASSERT_EQ(evo::run_evolution(c, files.back(), o).outcome, evo::RunOutcome::kFinished);
  }
  StudyOptions o = quick();
  o.generation = 0;
  int seeded = 0;
  for (const ChampionAnalysis& c : analyze_study(files, o).champions) {
    EXPECT_EQ(c.seeded_plan, c.id < 3 ? static_cast<int>(c.id) : -1) << c.label;
    seeded += c.seeded_plan >= 0;
  }
  EXPECT_GT(seeded, 0);
  // A random start has no seeded ancestor.
  for (const ChampionAnalysis& c : analyze_study({run(Treatment::kNone, 1)}, quick()).champions)
    EXPECT_EQ(c.seeded_plan, -1);
}

TEST_F(Study, TwoFilesOfOneRunAreOneReplicateNotTwo) {
  // A finished run and an unfinished copy of it (same config and seed, 0 of 1 generations):
  // one replicate, refused in one line naming both, not counted as stress-s1-r2.
  const std::string a = run(Treatment::kStress, 1);
  const std::string copy = unfinished_run(path("copy.h5"), Treatment::kStress, 1);
  const std::string msg = error_of([&] { analyze_study({a, copy}, quick()); });
  EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
  EXPECT_NE(msg.find(" are the same run (treatment stress, seed 1, config digest "),
            std::string::npos)
      << msg;
  EXPECT_NE(msg.find(a), std::string::npos) << msg;
  EXPECT_NE(msg.find(copy), std::string::npos) << msg;
  EXPECT_NE(msg.find("analyse one"), std::string::npos) << msg;
  // The same seed under another treatment is another replicate.
  EXPECT_EQ(analyze_study({a, run(Treatment::kNone, 1)}, quick()).champions.size(), 2u);
}

TEST_F(Study, RunsAtDifferentGenerationsAreAnalysedWithAWarning) {
  const std::string done = run(Treatment::kStress, 1);
  const std::string half = unfinished_run(path("half.h5"), Treatment::kStress, 2);
  const StudyResult r = analyze_study({done, half}, quick());
  ASSERT_EQ(r.warnings.size(), 1u);
  const std::string& w = r.warnings[0];
  EXPECT_NE(w.find("the runs reached different generations (" + half + ": 0, " + done + ": 1)"),
            std::string::npos)
      << w;
  EXPECT_NE(w.find("--generation 0"), std::string::npos) << w;
  // At one generation for all, no warning.
  StudyOptions at0 = quick();
  at0.generation = 0;
  EXPECT_TRUE(analyze_study({done, half}, at0).warnings.empty());
}

TEST_F(Study, UnstableSimulationsAreRecordedNeverTurnedIntoNumbers) {
  // A run whose every simulation goes unstable (max_speed far below gravity's first step)
  // next to a normal one of the same treatment.
  const std::string ok = run(Treatment::kStress, 3);
  const std::string bad =
      run(Treatment::kStress, 9, R"({"duration": 0.2, "settle_time": 0.1, "max_speed": 1e-4})");
  StudyOptions o = quick();
  o.allow_mixed_physics = true;
  o.keep_artifacts = true;  // measured like any other champion (by default it is left out)
  const StudyResult r = analyze_study({ok, bad}, o);
  write_study_outputs(r, path("out"));
  const Json j = Json::parse(read_text(path("out/stats.json")));
  ASSERT_EQ(j["champions"].size(), 2u);
  const Json& u = j["champions"][1];
  ASSERT_EQ(u["label"], "stress-s9");
  EXPECT_EQ(u["status"], "unstable");
  EXPECT_NE(u["status_detail"].get<std::string>().find("max_speed"), std::string::npos);
  EXPECT_TRUE(u["fitness"].is_null());
  EXPECT_TRUE(u["m_body"].is_null());
  EXPECT_TRUE(u["robustness"]["F_train"].is_null());
  EXPECT_TRUE(u["robustness"]["R_mean"].is_null());
  for (const Json& d : u["robustness"]["draws"]) EXPECT_TRUE(d.is_null());
  for (const Json& s : u["robustness"]["draw_status"]) EXPECT_NE(s, "ok");
  for (const char* m : {"fitness", "robustness", "m_body", "v_body"})
    EXPECT_TRUE(u["undefined"].contains(m)) << m;
  EXPECT_FALSE(u["v_gain"].is_null());  // alpha is defined whatever the simulation did
  EXPECT_EQ(u["life_status"], "unstable");
  EXPECT_TRUE(u["excluded"].is_null());
  EXPECT_EQ(j["champions"][0]["status"], "ok");

  // Each panel keeps the valid value and lists the unstable champion with its reason.
  for (const Json& panel : j["panels"]) {
    if (panel["id"] == "B" || panel["id"] == "F") continue;
    const Json& g = panel["groups"][0];
    EXPECT_EQ(g["n"], 1) << panel["id"];
    ASSERT_EQ(g["excluded"].size(), 1u) << panel["id"];
    EXPECT_EQ(g["excluded"][0]["label"], "stress-s9");
    EXPECT_NE(g["excluded"][0]["reason"].get<std::string>().find("unstable"), std::string::npos);
  }
  const auto rows = read_csv(read_text(path("out/champions.csv")));
  ASSERT_EQ(rows.size(), 3u);
  EXPECT_EQ(rows[2][9], "");   // fitness
  EXPECT_EQ(rows[2][12], "");  // r_mean
  EXPECT_EQ(rows[2][7], "unstable");

  // By default the unstable champion is an artifact: left out of every panel (diversity
  // too), its robustness not measured.
  o.keep_artifacts = false;
  const StudyResult d = analyze_study({ok, bad}, o);
  ASSERT_EQ(d.champions.size(), 2u);
  EXPECT_TRUE(d.champions[0].artifact.empty());
  EXPECT_NE(d.champions[1].artifact.find("its life is unstable"), std::string::npos);
  EXPECT_TRUE(d.champions[1].robustness.draws.empty());
  for (const PanelStats& p : d.panels) {
    ASSERT_EQ(p.groups.size(), 1u);
    if (p.id == "B") {
      EXPECT_TRUE(p.groups[0].values.empty());  // no pair without the artifact
      continue;
    }
    if (p.id != "F") {  // F: V_gain of s3, when its alpha range is defined
      EXPECT_EQ(p.groups[0].values.size(), 1u) << p.id;
    }
    ASSERT_FALSE(p.groups[0].excluded.empty()) << p.id;
    EXPECT_EQ(p.groups[0].excluded.back().label, "stress-s9") << p.id;
    EXPECT_NE(p.groups[0].excluded.back().reason.find("excluded as an artifact"),
              std::string::npos);
  }
}

TEST_F(Study, ChampionsAreAuditedAndArtifactsExcluded) {
  // Three runs of one treatment: a healthy one; one evolved under the authors' rule whose
  // every body is soft (E <= 2e5 Pa) and heavy, so its champion sank through the floor
  // (docs/engine.md); one whose every simulation goes unstable.
  const std::string ok = run(Treatment::kStress, 3, R"({"duration": 0.2, "settle_time": 0.1})");
  const std::string sank = run(Treatment::kStress, 5,
                               R"({"duration": 1.0, "settle_time": 0.1, "e_max": 2e5,
                                   "act_frequency": 1, "sinking_invalid": false})");
  const std::string bad =
      run(Treatment::kStress, 9, R"({"duration": 0.2, "settle_time": 0.1, "max_speed": 1e-4})");
  for (const auto& [file, sinks] : {std::pair{ok, false}, {sank, true}}) {
    const evo::ResultsFile f = evo::read_results(file);
    const uint64_t champion = f.state.history.back().champion_id;
    EXPECT_EQ(f.state.births.at(champion).sank, sinks) << file;
  }
  StudyOptions o = quick();
  o.allow_mixed_physics = true;
  const StudyResult r = analyze_study({ok, sank, bad}, o);
  write_study_outputs(r, path("out"));

  const char* expect_label[] = {"stress-s3", "stress-s5", "stress-s9"};
  const char* expect_status[] = {"ok", "sank", "unstable"};
  const char* expect_life[] = {"finished", "finished", "unstable"};
  const bool expect_excluded[] = {false, true, true};
  ASSERT_EQ(r.champions.size(), 3u);
  EXPECT_NE(r.champions[0].health, "sank");
  EXPECT_EQ(r.champions[1].health, "sank");
  EXPECT_GT(r.champions[1].floor_depth, kFloorSankDepth);
  EXPECT_GT(r.champions[1].vertical_share, 0.9);
  EXPECT_LT(r.champions[0].floor_depth, kFloorSankDepth);
  // champions.csv, stats.json and analysis.h5 say the same.
  const auto rows = read_csv(read_text(path("out/champions.csv")));
  ASSERT_EQ(rows.size(), 4u);
  const auto column = [&](const std::string& name) {
    const auto at = std::find(rows[0].begin(), rows[0].end(), name);
    EXPECT_NE(at, rows[0].end()) << name << " column";
    return static_cast<size_t>(at - rows[0].begin());
  };
  const size_t label = column("label"), status = column("status"), health = column("health"),
               depth = column("floor_depth"), excluded = column("excluded");
  const Json j = Json::parse(read_text(path("out/stats.json")));
  ASSERT_EQ(j["champions"].size(), 3u);
  const h5::Ctx ctx{path("out/analysis.h5"), 0};
  h5::Handle f(H5Fopen(path("out/analysis.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT),
               h5::Handle::Kind::kFile);
  const std::vector<std::string> h5_health = h5::read_strings(ctx, f.id(), "champions/health", 3);
  for (size_t i = 0; i < 3; ++i) {
    const ChampionAnalysis& c = r.champions[i];
    EXPECT_EQ(c.label, expect_label[i]);
    EXPECT_EQ(c.status, expect_status[i]) << c.label;
    EXPECT_EQ(c.life_status, expect_life[i]) << c.label;
    EXPECT_EQ(!c.artifact.empty(), expect_excluded[i]) << c.label;
    EXPECT_EQ(rows[i + 1][label], c.label);
    EXPECT_EQ(rows[i + 1][status], c.status) << c.label;
    EXPECT_EQ(rows[i + 1][health], c.health) << c.label;
    EXPECT_EQ(rows[i + 1][excluded], c.artifact) << c.label;
    EXPECT_DOUBLE_EQ(std::stod(rows[i + 1][depth]), c.floor_depth) << c.label;
    EXPECT_EQ(j["champions"][i]["health"], c.health) << c.label;
    EXPECT_EQ(j["champions"][i]["excluded"].is_null(), c.artifact.empty()) << c.label;
    EXPECT_EQ(h5_health[i], c.health) << c.label;
  }
  // The fitness panel and the evolution band keep the healthy run only.
  const PanelStats& a = r.panels[0];
  ASSERT_EQ(a.id, "A");
  EXPECT_EQ(a.groups[0].values.size(), 1u);
  ASSERT_EQ(a.groups[0].excluded.size(), 2u);
  EXPECT_EQ(a.groups[0].excluded[0].label, "stress-s5");
  EXPECT_NE(a.groups[0].excluded[0].reason.find("sank through the floor"), std::string::npos);
  ASSERT_EQ(r.evolution.size(), 1u);
  EXPECT_EQ(r.evolution[0].runs, 1);
  // report.html says so at the top, in one sentence with the count, and states the rule
  // and the direction of fitness.
  const std::string report = report_html(read_study_result(path("out/analysis.h5")));
  const size_t sentence = report.find(
      "2 of 3 champions are excluded from the statistics and "
      "figures because their lives, simulated again, are "
      "unstable or sank through the floor (stress-s5: it sank");
  ASSERT_NE(sentence, std::string::npos) << report.substr(0, 2000);
  EXPECT_LT(sentence, report.find("<h2>"));
  EXPECT_NE(report.find("Fitness is the 3-D displacement of the centre of mass (as in the "
                        "authors&#39; code)"),
            std::string::npos);
  EXPECT_NE(report.find("Lives that sank through the floor were mixed: invalid; scored (the "
                        "authors&#39; rule) during evolution"),
            std::string::npos);
  EXPECT_EQ(j["audit"]["sinking_rule"], "mixed: invalid; scored (the authors' rule)");

  // --keep-artifacts keeps them in: flagged, counted in the statistics, no sentence.
  o.keep_artifacts = true;
  const StudyResult kept = analyze_study({ok, sank, bad}, o);
  EXPECT_EQ(kept.champions[1].status, "sank");
  EXPECT_TRUE(kept.champions[1].artifact.empty());
  EXPECT_EQ(kept.panels[0].groups[0].values.size(), 2u);  // s9's fitness stays undefined
  EXPECT_EQ(report_html(kept).find("excluded from the statistics"), std::string::npos);
}

// Issue 37: the report and stats.json name the controller beside the task and environment,
// and analysis.h5 keeps it; one written before the field gets it from the champions' bodies.
TEST_F(Study, TheReportAndStatsNameTheController) {
  const std::string physics = R"({"duration": 0.2, "settle_time": 0.1})";
  const std::string sine = run(Treatment::kNone, 1, physics);
  const std::string neural =
      run(Treatment::kNone, 2, physics, R"({"kind": "distributed", "hidden": 2, "every": 3})");
  StudyOptions o = quick();
  o.robustness_draws = 1;
  const StudyResult plain = analyze_study({sine}, o);
  EXPECT_EQ(plain.controller, "sine (open loop)");
  EXPECT_NE(report_html(plain).find("in voxel lengths. The controller is <b>sine (open "
                                    "loop)</b> (docs/control.md). Lives that sank"),
            std::string::npos);

  const StudyResult r = analyze_study({neural}, o);
  const std::string expect = "distributed, 2 hidden units, every 3 steps";
  EXPECT_EQ(r.controller, expect);
  write_study_outputs(r, path("out"));
  const Json j = Json::parse(read_text(path("out/stats.json")));
  EXPECT_EQ(j["audit"]["controller"], expect);
  EXPECT_EQ(j["audit"]["task"], "walk");
  StudyResult back = read_study_result(path("out/analysis.h5"));
  EXPECT_EQ(back.controller, expect);
  EXPECT_NE(report_html(back).find("The controller is <b>" + expect + "</b> (docs/control.md)."),
            std::string::npos);
  EXPECT_EQ(report_html(back), report_html(r));

  // An analysis.h5 from before the field: the report takes it from the runs' champions.
  {
    h5::Handle f(H5Fopen(path("out/analysis.h5").c_str(), H5F_ACC_RDWR, H5P_DEFAULT),
                 h5::Handle::Kind::kFile);
    ASSERT_GE(f.id(), 0);
    ASSERT_GE(H5Adelete_by_name(f.id(), "/", "controller", H5P_DEFAULT), 0);
  }
  back = read_study_result(path("out/analysis.h5"));
  EXPECT_EQ(back.controller, "");
  EXPECT_EQ(report_html(back).find("The controller is"), std::string::npos);
  for (StudyInput& in : back.inputs) in.file = neural;
  load_champion_bodies(back);
  EXPECT_EQ(back.controller, expect);
}

TEST_F(Study, AChampionOfAnOldResultsFileIsSimulatedAgainAndExcluded) {
  // Written before sunk lives became invalid (tests/data/results/README.md): its champion
  // was scored for falling through the floor, and the study finds that out by itself.
  const std::string old =
      std::string(PLASTIVOX_SOURCE_DIR) + "/tests/data/results/old-rule-sinker.h5";
  const StudyResult r = analyze_study({old}, quick());
  ASSERT_EQ(r.champions.size(), 1u);
  const ChampionAnalysis& c = r.champions[0];
  EXPECT_EQ(c.evaluation, "ok");  // what the old rule said
  EXPECT_GT(c.fitness, 100);
  EXPECT_EQ(c.status, "sank");
  EXPECT_EQ(c.health, "sank");
  EXPECT_NE(c.artifact.find("it sank through the floor"), std::string::npos);
  EXPECT_EQ(r.sinking_rule, "scored (the authors' rule)");
  EXPECT_TRUE(r.panels[0].groups[0].values.empty());
  const std::string report = report_html(r);
  EXPECT_NE(report.find("1 of 1 champion is excluded from the statistics and figures because "
                        "its life, simulated again, is unstable or sank through the floor "
                        "(none-s3: it sank through the floor ("),
            std::string::npos);
  EXPECT_NE(report.find("sank</span>, excluded</td><td>sank</td>"), std::string::npos);
}

// Issue 54: the vertical rule, end to end. A run without the floor crowns a body that falls:
// walk's 3-D distance is then nearly all vertical, and the audit flags the champion (status
// "vertical") and leaves it out of the statistics, says so at the top of the report, counts it
// in stats.json, and keeps it with keep_vertical; under xy fitness the rule does not apply.
TEST_F(Study, AChampionWhoseFitnessIsMostlyVerticalIsFlaggedAndExcluded) {
  const std::string falls = R"({"duration": 0.2, "settle_time": 0.1, "floor": false)";
  const std::string file = run(Treatment::kStress, 4, falls + "}");
  StudyOptions o = quick();
  o.robustness_draws = 1;
  const StudyResult r = analyze_study({file}, o);
  ASSERT_EQ(r.champions.size(), 1u);
  const ChampionAnalysis& c = r.champions[0];
  EXPECT_GT(c.vertical_share, kVerticalShareLimit);
  EXPECT_TRUE(c.vertical_exploit);
  EXPECT_EQ(c.status, "vertical");
  EXPECT_NE(c.artifact.find("its fitness owes too much to vertical motion (vertical share"),
            std::string::npos)
      << c.artifact;
  EXPECT_TRUE(r.panels[0].groups[0].values.empty());
  ASSERT_EQ(r.panels[0].groups[0].excluded.size(), 1u);
  EXPECT_TRUE(c.robustness.draws.empty());  // an excluded champion's robustness is not measured
  write_study_outputs(r, path("out"));
  const Json j = Json::parse(read_text(path("out/stats.json")));
  EXPECT_EQ(j["champions"][0]["vertical_exploit"], true);
  EXPECT_EQ(j["champions"][0]["status"], "vertical");
  const Json& rule = j["audit"]["vertical_rule"];
  EXPECT_EQ(rule["applies"], true);
  EXPECT_EQ(rule["flagged"], 1);
  EXPECT_EQ(rule["excluded"], 1);
  EXPECT_EQ(rule["keep_vertical"], false);
  EXPECT_EQ(rule["vertical_share_limit"].get<double>(), kVerticalShareLimit);
  const auto rows = read_csv(read_text(path("out/champions.csv")));
  ASSERT_EQ(rows.size(), 2u);
  // A cell for every column: its robustness draw, not measured, is an empty cell.
  ASSERT_EQ(rows[1].size(), rows[0].size());
  EXPECT_EQ(rows[0].back(), "r_draw_0");
  EXPECT_EQ(rows[1].back(), "");
  const size_t column = static_cast<size_t>(
      std::find(rows[0].begin(), rows[0].end(), "vertical_exploit") - rows[0].begin());
  ASSERT_LT(column, rows[0].size());
  EXPECT_EQ(rows[1][column], "true");
  // analysis.h5 keeps the flag: the report made from it says so at the top, with the count.
  const StudyResult back = read_study_result(path("out/analysis.h5"));
  EXPECT_TRUE(back.champions[0].vertical_exploit);
  const std::string report = report_html(back);
  EXPECT_EQ(report, report_html(r));
  const size_t sentence = report.find(
      "1 of 1 champion owes too much of its fitness to vertical motion, rising (or "
      "falling) rather than walking, and is excluded from the statistics and figures "
      "(stress-s4: vertical share ");
  ASSERT_NE(sentence, std::string::npos) << report.substr(0, 3000);
  EXPECT_LT(sentence, report.find("<h2>"));
  EXPECT_NE(report.find("<code>--keep-vertical</code> keeps it)."), std::string::npos);
  EXPECT_NE(report.find("This distance pays for a rise as for a stride: a champion whose "
                        "vertical share (dz&sup2; / |d|&sup2;) is above 0.1, with |dz| of 0.25 "
                        "voxel lengths or more, is flagged and excluded (docs/engine.md"),
            std::string::npos);
  EXPECT_NE(report.find("vertical</span>, excluded</td>"), std::string::npos);

  // keep_vertical keeps it in the statistics, still flagged and counted.
  o.keep_vertical = true;
  const StudyResult kept = analyze_study({file}, o);
  EXPECT_TRUE(kept.champions[0].vertical_exploit);
  EXPECT_EQ(kept.champions[0].status, "vertical");
  EXPECT_TRUE(kept.champions[0].artifact.empty());
  EXPECT_EQ(kept.panels[0].groups[0].values.size(), 1u);
  EXPECT_EQ(vertical_audit(kept).flagged, 1);
  EXPECT_EQ(vertical_audit(kept).excluded, 0);
  EXPECT_NE(
      report_html(kept).find("1 of 1 champion owes too much of its fitness to vertical motion, "
                             "rising (or falling) rather than walking, and is kept in the "
                             "statistics and figures by <code>--keep-vertical</code>"),
      std::string::npos);
  EXPECT_NE(study_fingerprint({"x"}, o), study_fingerprint({"x"}, quick()));

  // Under xy fitness the same fall scores nothing vertical: the rule does not apply.
  o.keep_vertical = false;
  const StudyResult xy =
      analyze_study({run(Treatment::kStress, 5, falls + R"(, "fitness": "xy"})")}, o);
  EXPECT_FALSE(xy.champions[0].vertical_exploit);
  EXPECT_EQ(xy.champions[0].vertical_share, 0);
  EXPECT_TRUE(xy.champions[0].artifact.empty());
  EXPECT_FALSE(vertical_audit(xy).applies);
  EXPECT_NE(report_html(xy).find("The vertical rule (docs/engine.md) does not apply"),
            std::string::npos);
  EXPECT_EQ(report_html(xy).find("owes too much of its fitness"), std::string::npos);
}

// The champions of tests/data/vertical (README.md there says how each was made), replayed by
// the audit as one study's champions under the physics of their files (gecco2018-code: walk in
// 3-D) or the same physics scoring walk in the horizontal plane.
StudyResult replayed(const StudyOptions& o, bool xy) {
  StudyResult r;
  r.options = o;
  for (const char* name : {"crouching", "riser"}) {
    const LoadedRobot f =
        load_robot(std::string(PLASTIVOX_SOURCE_DIR) + "/tests/data/vertical/" + name + ".json");
    ChampionAnalysis c;
    c.label = name;
    c.input = static_cast<int>(r.inputs.size());
    c.treatment = f.physics.treatment;
    c.robot = f.robot;
    c.physics = f.physics;
    if (xy) c.physics.fitness = FitnessMode::kXY;
    c.voxels = f.robot.voxel_count();  // fitness stays 0: the audit's own life is what counts
    StudyInput in;
    in.file = std::string(name) + ".json";
    in.treatment = c.treatment;
    in.physics_json = R"({"sinking_invalid": true})";
    r.inputs.push_back(in);
    r.champions.push_back(c);
    if (r.treatments.empty() || r.treatments.back() != c.treatment)
      r.treatments.push_back(c.treatment);
  }
  study::audit_champions(r, {});
  std::vector<VoxelSet> sets;
  for (const ChampionAnalysis& c : r.champions) sets.push_back(voxel_set(c.robot));
  r.hausdorff = hausdorff_matrix(sets, {}, 1);
  r.panels = study::compute_panels(r);
  return r;
}

// The champion of two generations of CMA-ES under the 3-D fitness, which walked 0.60 voxel
// lengths and crouched 0.28 (vertical share 0.18: its rise, downwards, scored as a stride),
// and a riser (its fitness mostly rise): both flagged and excluded under walk's 3-D fitness,
// neither flagged under xy (keep_vertical is tested on the falling champion above).
TEST_F(Study, ReplayedCrouchingAndRisingChampionsAreFlaggedUnderThe3DRuleOnly) {
  const StudyResult r = replayed(quick(), false);
  ASSERT_EQ(r.champions.size(), 2u);
  for (const ChampionAnalysis& c : r.champions) {
    EXPECT_EQ(c.life_status, "finished") << c.label;
    EXPECT_EQ(c.health, "ok") << c.label;
    EXPECT_GT(c.vertical_share, kVerticalShareLimit) << c.label;
    EXPECT_TRUE(c.vertical_exploit) << c.label;
    EXPECT_EQ(c.status, "vertical") << c.label;
    EXPECT_NE(c.artifact.find("too much to vertical motion"), std::string::npos) << c.label;
  }
  EXPECT_LT(r.champions[0].vertical_share, 0.5);  // the crouching one walks most of its fitness
  EXPECT_GT(r.champions[1].vertical_share, 0.5);  // the riser rises most of it
  const PanelStats& a = r.panels[0];
  ASSERT_EQ(a.id, "A");
  size_t values = 0, excluded = 0;
  for (const GroupStats& g : a.groups) values += g.values.size(), excluded += g.excluded.size();
  EXPECT_EQ(values, 0u);
  EXPECT_EQ(excluded, 2u);
  const Json j = Json::parse(stats_json(r));
  EXPECT_EQ(j["audit"]["vertical_rule"]["flagged"], 2);
  EXPECT_EQ(j["audit"]["vertical_rule"]["excluded"], 2);
  EXPECT_NE(
      report_html(r).find("2 of 2 champions owe too much of their fitness to vertical motion"),
      std::string::npos);

  const StudyResult xy = replayed(quick(), true);
  for (const ChampionAnalysis& c : xy.champions) {
    EXPECT_EQ(c.vertical_share, 0) << c.label;
    EXPECT_FALSE(c.vertical_exploit) << c.label;
    EXPECT_EQ(c.status, "ok") << c.label;
    EXPECT_TRUE(c.artifact.empty()) << c.label;
  }
  EXPECT_EQ(Json::parse(stats_json(xy))["audit"]["vertical_rule"]["flagged"], 0);
}

// ---- the command line ----

testing::Output cli(const std::string& args) {
  return testing::shell(std::string(PLASTIVOX_CLI) + " analyze " + args + " 2>&1");
}

TEST_F(Study, CommandWritesEveryOutputAndResumes) {
  const std::vector<std::string> files = six_runs();
  std::string list;
  for (const std::string& f : files) list += f + " ";
  const std::string opts = " --robustness-draws 2 --resamples 1000";
  const testing::Output o1 = cli(list + "--out " + path("a") + opts + " --threads 1");
  ASSERT_EQ(o1.status, 0) << o1.out;
  EXPECT_NE(o1.out.find("plastivox analyze: robustness 6/6"), std::string::npos) << o1.out;
  EXPECT_NE(o1.out.find("time: "), std::string::npos) << o1.out;
  for (const char* f : {"stats.json", "champions.csv", "statistics.csv", "hausdorff.csv",
                        "analysis.h5", "report.html"})
    EXPECT_TRUE(fs::exists(path("a/") + f)) << f;
  // The report's 3-D viewer, one life per champion beside it (--no-viewer below: none).
  const Json stats = Json::parse(read_text(path("a/stats.json")));
  for (const auto& c : stats.at("champions")) {
    const std::string life = path("a/lives/") + c.at("label").get<std::string>() + ".js";
    EXPECT_TRUE(fs::exists(life)) << life;
  }
  EXPECT_NE(read_text(path("a/report.html")).find("pv-viewer"), std::string::npos);

  // Two threads, files in another order: the same statistics.
  std::string reversed;
  for (auto it = files.rbegin(); it != files.rend(); ++it) reversed += *it + " ";
  const testing::Output o2 =
      cli(reversed + "--out " + path("b") + opts + " --threads 2 --no-viewer");
  ASSERT_EQ(o2.status, 0) << o2.out;
  EXPECT_FALSE(fs::exists(path("b/lives")));
  EXPECT_EQ(read_text(path("b/report.html")).find("pv-viewer"), std::string::npos);
  ASSERT_EQ(o2.status, 0) << o2.out;
  Json a = Json::parse(read_text(path("a/stats.json")));
  Json b = Json::parse(read_text(path("b/stats.json")));
  for (Json* j : {&a, &b}) {
    (*j)["provenance"].erase("date");
    (*j)["provenance"].erase("command");
  }
  EXPECT_EQ(a, b);

  // Interrupted after some champions (outputs and half the checkpoints gone): the rerun
  // simulates only the rest and writes the same stats.json.
  const std::string before = without_date(read_text(path("a/stats.json")));
  fs::remove(path("a/stats.json"));
  int removed = 0;
  for (const auto& e : fs::directory_iterator(path("a/cache")))
    if (removed++ % 2 == 0) fs::remove(e.path());
  const testing::Output o3 = cli(list + "--out " + path("a") + opts + " --threads 1");
  ASSERT_EQ(o3.status, 0) << o3.out;
  EXPECT_NE(o3.out.find("3 from checkpoint"), std::string::npos) << o3.out;
  EXPECT_EQ(without_date(read_text(path("a/stats.json"))), before);
}

// --keep-vertical: the falling champion of a run without the floor stays in the statistics,
// flagged; without the option it is excluded (the library's side is tested above).
TEST_F(Study, CommandKeepsVerticalChampionsWithKeepVertical) {
  const std::string file =
      run(Treatment::kNone, 4, R"({"duration": 0.2, "settle_time": 0.1, "floor": false})");
  const std::string opts = " --robustness-draws 1 --resamples 200 --no-viewer --threads 1";
  for (const bool keep : {false, true}) {
    const std::string out = path(keep ? "kept" : "default");
    const testing::Output o = cli(file + " --out " + out + opts + (keep ? " --keep-vertical" : ""));
    ASSERT_EQ(o.status, 0) << o.out;
    const Json j = Json::parse(read_text(out + "/stats.json"));
    EXPECT_EQ(j["audit"]["vertical_rule"]["keep_vertical"], keep);
    EXPECT_EQ(j["audit"]["vertical_rule"]["flagged"], 1);
    EXPECT_EQ(j["champions"][0]["vertical_exploit"], true);
    EXPECT_EQ(j["champions"][0]["excluded"].is_null(), keep) << j["champions"][0].dump();
    EXPECT_NE(o.out.find("1 too vertical, " + std::string(keep ? "0" : "1") + " excluded"),
              std::string::npos)
        << o.out;
  }
}

// analyze's report, made from analysis.h5 with the bodies loaded again as the experiment's is,
// names the champions that share a hand-built body as stats.json does. Three treatments of one
// seed start from the same hand-built bodies; at generation 0 their champions share one.
TEST_F(Study, CommandReportNamesSharedSeededBodiesAsStatsJsonDoes) {
  std::string files;
  for (const char* t : {"none", "stress", "pressure"}) {
    evo::EvolveConfig c = evo::parse_config(
        std::string(R"({"format": "plastivox-evolve-config", "version": 1, "treatment": ")") + t +
            R"(", "seed": 1, "population": 4, "generations": 1,
               "lattice": {"nx": 6, "ny": 6, "nz": 6}, "initial_population": "body-plans",
               "physics": {"duration": 0.2, "settle_time": 0.1, "fitness": "xy"}})",
        "seeded");
    const std::string file = path(std::string("seeded-") + t + ".h5");
    evo::RunOptions o;
    o.threads = 1;
    ASSERT_EQ(evo::run_evolution(c, file, o).outcome, evo::RunOutcome::kFinished);
    files += file + " ";
  }
  const testing::Output o = cli(files + "--generation 0 --out " + path("out") +
                                " --robustness-draws 1 --resamples 200 --no-viewer --threads 1");
  ASSERT_EQ(o.status, 0) << o.out;
  const Json j = Json::parse(read_text(path("out/stats.json")));
  ASSERT_FALSE(j["hausdorff"]["shared_seeded_bodies"].empty()) << j["hausdorff"].dump();
  EXPECT_NE(read_text(path("out/report.html")).find("id=\"shared-body\""), std::string::npos);
}

TEST_F(Study, CommandRefusesBadInputWithoutOutputs) {
  const std::string a = run(Treatment::kStress, 1);
  std::ofstream(path("junk.h5")) << "not hdf5";
  const std::string file = write("afile", "x");
  struct Case {
    std::string args;
    int status;
    std::string expect;
  } cases[] = {
      {"--out " + path("o"), 2, "expected results or robot files"},
      {a, 2, "--out DIR is required"},
      {a + " --out " + path("o") + " --rotations some", 2, "--rotations expects"},
      {a + " --out " + path("o") + " --robustness-draws 0", 2, "--robustness-draws expects"},
      {a + " --out " + path("o") + " --bogus", 2, "unknown option --bogus"},
      {a + " " + path("junk.h5") + " --out " + path("o"), 1, path("junk.h5") + ": "},
      {a + " --out " + path("o") + " --generation 9", 1, a + ": generation 9 not reached"},
      {a + " --out " + path("o") + " --treatments stress,pressure", 1,
       "treatment pressure: no results file given"},
      // An --out that cannot be a folder: refused before any champion is loaded (the one
      // line below is the whole output: no "load" line first).
      {a + " --out " + file, 1, "--out " + file + ": is a file, not a folder"},
      {a + " --out /dev/null", 1, "--out /dev/null: is a device, pipe or socket, not a folder"},
      {a + " --out " + file + "/o", 1,
       "--out " + file + "/o: cannot create the folder: " + file + " is not a folder"},
  };
  for (const Case& c : cases) {
    const testing::Output o = cli(c.args);
    EXPECT_EQ(o.status, c.status) << c.args << "\n" << o.out;
    EXPECT_NE(o.out.find(c.expect), std::string::npos) << c.args << "\n" << o.out;
    EXPECT_EQ(std::count(o.out.begin(), o.out.end(), '\n'), 1) << o.out;
    EXPECT_FALSE(fs::exists(path("o"))) << c.args;
  }
}

// ---- the robustness battery ----

// With a battery the study measures every champion's profile, compares the treatments per
// perturbation and writes both to stats.json, analysis.h5 (read back) and the report; without
// one the options and stats.json carry no trace of it. The paper perturbation at spread 1 is
// R's own draws: the same numbers as panel C's.
TEST_F(Study, BatteryProfilesGoToStatsH5AndTheReport) {
  const std::vector<std::string> files = {run(Treatment::kNone, 1), run(Treatment::kNone, 2),
                                          run(Treatment::kStress, 3), run(Treatment::kStress, 4)};
  const std::string battery = write("battery.json", R"({"format": "plastivox-battery",
      "version": 1, "perturbations": [
      {"name": "eq2", "kind": "paper", "severities": [0.5, 1], "seeds": [0, 1, 2]},
      {"kind": "gravity", "severities": [0.5, 1.5, 2], "seeds": [0]}]})");
  StudyOptions o = quick();
  o.battery = battery;
  const StudyResult r = analyze_study(files, o);
  ASSERT_TRUE(r.battery);
  ASSERT_EQ(r.battery_panels.size(), 2u);
  EXPECT_EQ(r.battery_lives, 4 * battery_lives(*r.battery));
  for (const ChampionAnalysis& c : r.champions) {
    ASSERT_TRUE(c.profile) << c.label;
    const SeverityLevel& eq2 = c.profile->perturbations[0].levels[1];
    ASSERT_TRUE(c.r_mean && eq2.mean_kept) << c.label;
    EXPECT_EQ(*eq2.mean_kept, *c.r_mean) << c.label;  // quick(): three draws, seeds 0..2
  }
  write_study_outputs(r, path("out"));
  const Json stats = Json::parse(read_text(path("out/stats.json")));
  const Json& block = stats.at("robustness_battery");
  EXPECT_EQ(block.at("champions").size(), 4u);
  EXPECT_EQ(block.at("comparisons").size(), 2u);
  EXPECT_EQ(block.at("comparisons")[1].at("perturbation"), "gravity");
  EXPECT_EQ(block.at("units").at("kept"), "F_perturbed / F_reference (dimensionless)");
  EXPECT_EQ(block.at("comparisons")[0].at("groups")[0].at("mean").get<double>(),
            *r.battery_panels[0].groups[0].mean);
  const StudyResult back = read_study_result(path("out/analysis.h5"));
  ASSERT_TRUE(back.battery);
  EXPECT_EQ(battery_json(*back.battery), battery_json(*r.battery));
  EXPECT_EQ(back.options.battery, battery);
  EXPECT_EQ(back.battery_lives, r.battery_lives);
  ASSERT_EQ(back.battery_panels.size(), 2u);
  for (size_t i = 0; i < 2; ++i)
    for (size_t g = 0; g < 2; ++g) {
      EXPECT_EQ(back.battery_panels[i].groups[g].values, r.battery_panels[i].groups[g].values);
      EXPECT_EQ(back.battery_panels[i].groups[g].ci->lower,
                r.battery_panels[i].groups[g].ci->lower);
    }
  const std::string html = report_html(back);
  EXPECT_NE(html.find("<h2>Robustness battery</h2>"), std::string::npos);
  EXPECT_NE(html.find("<td>gravity</td>"), std::string::npos);
  // Two champions a treatment: the battery's table carries Fig. 5's warning, and each test
  // says it has no power (as stats.json does).
  const size_t section = html.find("<h2>Robustness battery</h2>");
  EXPECT_NE(html.find("id=\"battery-no-power\">These comparisons have no statistical power: 2 "
                      "of 2 rest on fewer than 20 champions per treatment (the fewest: 2)",
                      section),
            std::string::npos);
  EXPECT_NE(html.find("none-stress p=", section), std::string::npos);
  EXPECT_NE(html.find("(no power: n = 2)", section), std::string::npos);
  EXPECT_FALSE(block.at("comparisons")[0].at("comparisons")[0].at("powered").get<bool>());
  EXPECT_NE(html.find("Cells are red where fitness is lost", section), std::string::npos);
  EXPECT_EQ(html.find("left out (no valid life", section), std::string::npos);
  // A champion without an AUC (every life of a severity failed) is counted in its cell, and a
  // perturbation nothing could be compared in says so rather than leaving the cell blank.
  StudyResult thin = back;
  thin.battery_panels[0].groups[0].values.pop_back();
  thin.battery_panels[1].comparisons.clear();
  const std::string thin_html = report_html(thin);
  EXPECT_NE(thin_html.find(" n=1, 1 left out (no valid life at a severity)</td>"),
            std::string::npos);
  EXPECT_NE(thin_html.find("<td>no test: fewer than two treatments with two or more "
                           "champions</td>"),
            std::string::npos);

  // The fingerprint follows the battery file's content, not only its name.
  const std::string before = study_fingerprint({"d"}, o);
  write("battery.json", R"({"format": "plastivox-battery", "version": 1, "perturbations": [
      {"kind": "gravity", "severities": [0.5, 1.5, 2.5], "seeds": [0]}]})");
  EXPECT_NE(study_fingerprint({"d"}, o), before);

  // Without a battery: nothing of it anywhere, the options as before.
  StudyOptions plain = quick();
  const StudyResult none = analyze_study(files, plain);
  EXPECT_FALSE(none.battery);
  EXPECT_EQ(options_json(plain).find("battery"), std::string::npos);
  EXPECT_EQ(stats_json(none).find("robustness_battery"), std::string::npos);
  EXPECT_EQ(report_html(none).find("Robustness battery"), std::string::npos);
  EXPECT_EQ(Json::parse(stats_json(none)).at("panels"), stats.at("panels"));
}

// plastivox robustness: profiles, the comparison, robustness.json/csv and the heat map; a bad
// battery is refused in one line before any results file is read or life simulated;
// --estimate-only simulates one life.
TEST_F(Study, RobustnessCommandWritesProfilesAndRefusesBadBatteries) {
  const std::string a = run(Treatment::kNone, 1), b = run(Treatment::kStress, 2);
  const testing::Output ok =
      testing::cli("robustness " + a + " " + b +
                   " --battery small --resamples 200 --threads 2 --out " + path("rb"));
  ASSERT_EQ(ok.status, 0) << ok.out;
  EXPECT_NE(ok.out.find("voxel-loss      AUC"), std::string::npos) << ok.out;
  for (const char* f :
       {"robustness.json", "robustness.csv", "robustness_heatmap.svg", "robustness_heatmap.png"})
    EXPECT_TRUE(fs::exists(path("rb/") + f)) << f;
  const Json j = Json::parse(read_text(path("rb/robustness.json")));
  EXPECT_EQ(j.at("format"), "plastivox-robustness");
  EXPECT_EQ(j.at("battery").at("perturbations").size(), 4u);
  EXPECT_NE(read_text(path("rb/robustness_heatmap.svg")).find("voxel-loss"), std::string::npos);

  const testing::Output est =
      testing::cli("robustness " + a + " " + b + " --battery default --estimate-only");
  ASSERT_EQ(est.status, 0) << est.out;
  EXPECT_NE(est.out.find("63 lives per champion; 2 champions: 126 lives"), std::string::npos)
      << est.out;
  EXPECT_NE(est.out.find(" core-seconds, "), std::string::npos) << est.out;

  // Robot files: each under its own physics, labelled by its name; mixed with results: refused.
  const std::string robot = std::string(PLASTIVOX_SOURCE_DIR) + "/examples/mixture.json";
  const std::string short_battery = write("short.json", R"({"format": "plastivox-battery",
      "version": 1, "perturbations": [{"kind": "gravity", "severities": [2], "seeds": [0]}]})");
  const testing::Output robots =
      testing::cli("robustness " + robot + " --threads 2 --battery " + short_battery);
  ASSERT_EQ(robots.status, 0) << robots.out;
  EXPECT_NE(robots.out.find("mixture: 2 lives"), std::string::npos) << robots.out;
  // Robot and results files together are one study: here of different physics, refused so.
  const testing::Output mixed = testing::cli("robustness " + robot + " " + a);
  EXPECT_EQ(mixed.status, 1) << mixed.out;
  EXPECT_NE(mixed.out.find("mixed physics"), std::string::npos) << mixed.out;

  const std::string bad = write("bad.json", R"({"format": "plastivox-battery", "version": 1,
      "perturbations": [{"kind": "voxel-loss", "severities": [0.1, 2], "seeds": [0]}]})");
  for (const std::string& command : {"robustness " + a, "analyze " + a + " --out " + path("o")}) {
    const testing::Output o = testing::cli(command + " --battery " + bad);
    EXPECT_EQ(o.status, 1) << o.out;
    EXPECT_NE(o.out.find(bad + ": perturbations[0].severities[1]: 2.000000 is outside [0, 0.9]"),
              std::string::npos)
        << o.out;
    EXPECT_EQ(std::count(o.out.begin(), o.out.end(), '\n'), 1) << o.out;  // no "load" line
    EXPECT_FALSE(fs::exists(path("o")));
  }
}

// The champion of each results file written as a robot file named after its label, as
// `plastivox export` writes it (with the run's physics).
std::vector<std::string> exported(const std::vector<std::string>& files, const std::string& dir) {
  std::vector<std::string> out;
  for (const std::string& f : files) {
    const evo::ResultsFile rf = evo::read_results(f);
    const evo::RunState& run = rf.state;
    const std::string name = dir + "/" + to_string(run.config.treatment) + "-s" +
                             std::to_string(run.config.seed) + ".json";
    write_robot_file(name, evo::champion_robot(evo::champion_at(run, -1, f), run.generations_done),
                     &run.config.physics);
    out.push_back(name);
  }
  return out;
}

// Robot files exported from results files give analyze's numbers for those results files to the
// bit: every Fig. 5 panel and the battery (the robot's own life, scored as evolution scored it,
// is the recorded fitness and final stiffness; the audit runs on each).
TEST_F(Study, RobotFilesGiveTheNumbersOfTheirResultsFiles) {
  const std::vector<std::string> files = {run(Treatment::kNone, 1), run(Treatment::kNone, 2),
                                          run(Treatment::kStress, 3), run(Treatment::kStress, 4)};
  const std::vector<std::string> robots = exported(files, path(""));
  StudyOptions o = quick();
  o.battery = "small";
  const Json a = Json::parse(stats_json(analyze_study(files, o)));
  const StudyResult rb = analyze_study(robots, o);
  const Json b = Json::parse(stats_json(rb));
  EXPECT_EQ(a.at("panels"), b.at("panels"));
  EXPECT_EQ(a.at("robustness_battery"), b.at("robustness_battery"));
  EXPECT_EQ(a.at("hausdorff"), b.at("hausdorff"));
  EXPECT_EQ(a.at("audit"), b.at("audit"));
  ASSERT_EQ(a.at("champions").size(), 4u);
  for (size_t i = 0; i < 4; ++i) {
    Json ca = a.at("champions")[i], cb = b.at("champions")[i];
    for (const char* k : {"file", "seed", "generation", "champion_id"}) {
      ca.erase(k);
      cb.erase(k);
    }
    EXPECT_EQ(ca, cb) << i;
  }
  EXPECT_EQ(rb.champions[0].label, "none-s1");  // a robot file is labelled by its name
  // The estimate counts robot files' lives as results files' (simulating one life only).
  const BatteryEstimate from_robots = estimate_battery(robots, o);
  EXPECT_EQ(from_robots.lives, 4 * 14);
  EXPECT_EQ(from_robots.voxel_steps, estimate_battery(files, o).voxel_steps);

  // Labels: TREATMENT=FILE sets a robot file's treatment (through resolve_physics), must equal a
  // results file's, and anything else is refused in one line naming the argument.
  StudyOptions plain = quick();
  const StudyResult relabelled =
      analyze_study({"stress=" + robots[0], "stress=" + robots[1], robots[2], robots[3]}, plain);
  EXPECT_EQ(relabelled.treatments, std::vector<Treatment>{Treatment::kStress});
  EXPECT_EQ(relabelled.champions[0].physics.treatment, Treatment::kStress);
  EXPECT_EQ(analyze_study({"none=" + files[0], files[1]}, plain).champions.size(), 2u);
  for (const auto& [args, says] : std::vector<std::pair<std::vector<std::string>, std::string>>{
           {{"stress=" + files[0]},
            "stress=" + files[0] + ": the run's treatment is none, not stress"},
           {{"fast=" + robots[0]}, "fast=" + robots[0] + ": 'fast' is not a treatment"},
           {{"none="}, "none=: no file after the treatment label"},
           {{path("absent.json")}, path("absent.json") + ": cannot open"}}) {
    const std::string msg = error_of([&] { analyze_study(args, plain); });
    EXPECT_EQ(msg.rfind(says, 0), 0u) << msg;
    EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
  }
}

// The battery is checkpointed per champion: an analysis stopped in the middle of the battery
// resumes without simulating the finished champions' lives again and gives the uninterrupted
// analysis's bits; on 1 and 2 threads the same.
TEST_F(Study, BatteryResumesFromCheckpointsToTheSameBits) {
  const std::vector<std::string> files = {run(Treatment::kNone, 1), run(Treatment::kNone, 2),
                                          run(Treatment::kStress, 3), run(Treatment::kStress, 4)};
  StudyOptions o = quick();
  o.battery = "small";
  o.threads = 1;
  const std::string uninterrupted = without_date(stats_json(analyze_study(files, o)));
  o.threads = 2;
  EXPECT_EQ(without_date(stats_json(analyze_study(files, o))), uninterrupted);

  o.threads = 1;  // a round is one champion
  o.cache_dir = path("cache");
  std::atomic<bool> stop{false};
  o.stop_requested = &stop;
  const std::string msg = error_of([&] {
    analyze_study(files, o, [&](const StudyProgress& p) {
      if (p.stage == "battery") stop.store(true);  // after the first champion's battery
    });
  });
  EXPECT_NE(msg.find("stopped on request with 1 of 4 champions' battery done"), std::string::npos)
      << msg;
  int battery_files = 0;
  for (const auto& e : fs::directory_iterator(path("cache")))
    battery_files += e.path().filename().string().rfind("battery-", 0) == 0 ? 1 : 0;
  EXPECT_EQ(battery_files, 1);

  stop.store(false);
  const StudyResult resumed = analyze_study(files, o);
  EXPECT_EQ(resumed.battery_cached, 1);
  EXPECT_EQ(without_date(stats_json(resumed)), uninterrupted);
  const StudyResult again = analyze_study(files, o);  // everything from checkpoints
  EXPECT_EQ(again.battery_cached, 4);
  EXPECT_EQ(again.timings.robustness_simulations, 0);
  EXPECT_EQ(without_date(stats_json(again)), uninterrupted);
}

}  // namespace
}  // namespace plastivox::analysis
