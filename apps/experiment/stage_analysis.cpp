// Stage 2: the study analysis over every run's champion (docs/analysis.md), into the folder:
// data only (stats.json, the CSV tables, analysis.h5); the report stage writes report.html.
#include <filesystem>

#include "experiment_run.hpp"
#include "plastivox/analysis/study.hpp"
#include "plastivox/evo/results_file.hpp"
#include "plastivox/evo/run.hpp"  // Cluster
#include "plastivox/io/atomic_file.hpp"
#include "stamps.hpp"

namespace plastivox::experiment {
namespace {

namespace fs = std::filesystem;

analysis::StudyOptions study_options(const StageContext& ctx) {
  const auto& a = ctx.config.analysis;
  analysis::StudyOptions o;
  o.generation = a.generation;
  o.robustness_draws = a.robustness_draws;
  o.robustness_sampling = a.robustness_sampling == "log"
                              ? analysis::StiffnessDistribution::kLogUniform
                              : analysis::StiffnessDistribution::kLinear;
  o.rotations = analysis::parse_rotation_search(a.rotations);
  o.translation = a.translation == "integer" ? analysis::TranslationSearch::kInteger
                                             : analysis::TranslationSearch::kNone;
  o.resamples = a.resamples;
  o.seed = a.seed;
  o.battery = a.battery;
  o.treatments = ctx.config.treatments;
  o.keep_artifacts = ctx.opt.keep_artifacts;
  o.keep_vertical = ctx.opt.keep_vertical;
  o.threads = ctx.opt.threads >= 0 ? ctx.opt.threads : ctx.config.threads;
  o.cache_dir = ctx.dir + "/cache/robustness";
  o.command = ctx.opt.command_line;
  o.stop_requested = ctx.opt.stop_requested;  // Ctrl-C: finish and checkpoint, then stop
  return o;
}

}  // namespace

const std::vector<std::string> kAnalysisOutputs{"stats.json", "champions.csv", "statistics.csv",
                                                "hausdorff.csv", "analysis.h5"};

std::vector<std::string> stage_analysis(StageContext& ctx) {
  const bool leader = !ctx.opt.cluster || ctx.opt.cluster->rank() == 0;
  analysis::StudyOptions options = study_options(ctx);
  if (ctx.shared_analysis) {  // every rank runs the study; its battery's lives are shared
    ctx.opt.share_battery(options);
    options.write_cache = leader;
    options.stop_requested = nullptr;  // the ranks would stop apart: a kill, then a rerun resumes
  }
  std::vector<std::string> files, digests;
  for (const auto& f : ctx.run_files) {
    files.push_back(ctx.dir + "/" + f);
    digests.push_back(evo::read_results(files.back()).content_digest);
  }
  const std::string fingerprint = analysis::study_fingerprint(digests, options);
  // Current when made from these runs with these options and every output still holds the
  // bytes written (stamps.hpp): then nothing is recomputed. A damaged output has the whole
  // analysis written again. Rank 0 decides for every rank.
  Stamps stamps(ctx.dir, "analysis");
  const bool force = ctx.opt.force.count("analysis") > 0;
  std::string decision;
  if (leader) {
    if (force) fs::remove_all(options.cache_dir);
    decision = !force && up_to_date(stamps, ctx.progress, "analysis", "outputs", fingerprint,
                                    kAnalysisOutputs)
                   ? "current"
                   : "analyse";
  }
  if (ctx.shared_analysis) ctx.opt.cluster->broadcast(decision);
  if (decision == "current") {
    if (leader)
      ctx.progress.log("[analysis] up to date (fingerprint " + fingerprint.substr(0, 12) +
                       "); nothing recomputed");
  } else {
    if (leader)
      ctx.progress.log("[analysis] " + std::to_string(files.size()) +
                       (files.size() == 1 ? " champion" : " champions") +
                       (ctx.shared_analysis ? "; the battery's lives shared by " +
                                                  std::to_string(ctx.opt.cluster->size()) + " ranks"
                                            : ""));
    const analysis::StudyResult result =
        analysis::analyze_study(files, options, [&](const analysis::StudyProgress& p) {
          if (leader && !p.message.empty()) ctx.progress.status("[analysis] " + p.message);
        });
    if (!leader) return {};  // rank 0 writes
    analysis::write_study_outputs(result, ctx.dir);
    stamps.record("outputs", fingerprint, kAnalysisOutputs);
    const auto& t = result.timings;
    char buf[320];
    std::snprintf(buf, sizeof buf,
                  "[analysis] done in %.1f s (robustness%s %.1f s: %d simulations, %d champions "
                  "cached; hausdorff %.2f s; statistics %.2f s)",
                  t.total, result.battery ? " and battery" : "", t.robustness,
                  t.robustness_simulations, t.robustness_cached, t.hausdorff, t.statistics);
    ctx.progress.log(buf);
    if (result.battery) {  // its lives are not among R's simulations above
      std::snprintf(buf, sizeof buf,
                    "[analysis] battery %s: %d lives (%d unstable, %d sank), %d champions from "
                    "checkpoint",
                    result.battery->name.c_str(), result.battery_lives, result.battery_unstable,
                    result.battery_sank, result.battery_cached);
      ctx.progress.log(buf);
    }
  }
  if (!leader) return {};
  // The later stages take the study as analysis.h5 holds it, whether written now or before,
  // with the champions' bodies from their runs (named as this session names them: the folder
  // may have moved since the analysis).
  auto result = std::make_shared<analysis::StudyResult>(
      analysis::read_study_result(ctx.dir + "/analysis.h5"));
  for (analysis::StudyInput& in : result->inputs)
    for (size_t i = 0; i < files.size(); ++i)
      if (digests[i] == in.content_digest) in.file = files[i];
  analysis::load_champion_bodies(*result);
  ctx.study = result;
  return kAnalysisOutputs;
}

}  // namespace plastivox::experiment
