// Running an experiment: stages evolve -> analyse -> render -> report over one output folder.
//
// Every stage skips work already done, judged by content: evolution resumes each run's
// results file (same config identity, evo/run.hpp); analysis is redone only when the
// champions' content digests or the analysis settings changed; rendering only when the
// statistics or the rendering settings changed; the report is rewritten only if its bytes
// differ. So `plastivox experiment` after a kill continues where it stopped.
#pragma once

#include <atomic>
#include <functional>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "experiment_config.hpp"
#include "progress.hpp"

namespace plastivox::evo {
class Cluster;
}
namespace plastivox::analysis {
struct StudyResult;
struct StudyOptions;
}  // namespace plastivox::analysis

namespace plastivox::experiment {

inline const std::vector<std::string> kStages{"evolution", "analysis", "rendering", "report"};

struct ExperimentOptions {
  std::string out_dir;
  int threads = -1;             // -1: the config's; 0: all cores
  std::set<std::string> force;  // stages to redo from scratch (names from kStages)
  const std::atomic<bool>* stop_requested = nullptr;  // Ctrl-C: stop at the next checkpoint
  evo::Cluster* cluster = nullptr;                    // under mpirun: evolution runs on every rank
  std::string command_line;                           // for provenance
  // Evolve only this run ("stress-s3") and stop: one task of a cluster job array; a final
  // `plastivox experiment` without it then analyses, renders and reports.
  std::string only_run;
  // The report's 3-D viewer: every champion's life in lives/ (--no-viewer: none).
  bool viewer = true;
  bool keep_artifacts = false;  // keep champions whose life is unstable or sank in the statistics
  bool keep_vertical = false;   // keep champions the vertical rule flags in the statistics
  // Under mpirun: sets the analysis's StudyOptions::battery_lives so that a robustness battery
  // is shared by every rank (cmd_experiment, apps/battery_ranks.hpp). Then, with a battery in
  // the config, the other ranks stay after evolution and run the analysis with rank 0; without
  // it (or a battery) analysis, rendering and the report run on rank 0 alone.
  std::function<void(analysis::StudyOptions&)> share_battery;
};

struct ExperimentOutcome {
  bool completed = false;            // false: stopped by request (resumable)
  std::vector<std::string> outputs;  // every file written or kept, relative to out_dir
};

// Throws InputError / std::runtime_error with one line for anything that prevents the
// experiment (unwritable folder, a folder holding another experiment, ...).
ExperimentOutcome run_experiment(const ExperimentConfig& config, const ExperimentOptions& opt,
                                 Progress& progress);

// Stage parts (one file each); `dir` is the experiment folder. Each returns the files it
// produced, relative to dir.
struct StageContext {
  const ExperimentConfig& config;
  const ExperimentOptions& opt;
  Progress& progress;
  std::string dir;
  std::string manifest_date;           // when the experiment was first started (UTC, ISO 8601)
  std::vector<std::string> run_files;  // runs/<label>.h5, in run order
  std::vector<std::string> run_labels;
  int run_index_offset = 0;  // index of run_files[0] among all runs (with --run)
  std::shared_ptr<const analysis::StudyResult> study;  // set by stage_analysis
  // Every rank runs the analysis stage (a battery shared over MPI ranks); rank 0 decides and
  // alone writes.
  bool shared_analysis = false;
};
bool stage_evolution(StageContext& ctx);  // false: stopped by request
std::vector<std::string> stage_analysis(StageContext& ctx);
std::vector<std::string> stage_rendering(StageContext& ctx);
std::vector<std::string> stage_report(StageContext& ctx, const std::vector<std::string>& outputs);

}  // namespace plastivox::experiment
