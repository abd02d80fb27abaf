// plastivox experiment: the whole study (evolve, analyse, render, report) in one folder,
// resumable stage by stage (apps/experiment/, docs/experiment.md).
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <sstream>
#include <thread>

#include "battery_ranks.hpp"
#include "cli.hpp"
#include "experiment/cost_estimate.hpp"
#include "experiment/experiment_run.hpp"
#include "plastivox/analysis/study.hpp"  // StudyOptions
#include "plastivox/base/error.hpp"      // InputError
#include "plastivox/evo/run.hpp"
#include "plastivox/render/offscreen.hpp"  // limit_raster_threads, RenderError

namespace plastivox::cli {
namespace {

std::set<std::string> parse_force(const std::string& s) {
  std::set<std::string> out;
  std::stringstream ss(s);
  std::string item;
  while (std::getline(ss, item, ','))
    if (!item.empty()) out.insert(item == "all" ? "" : item);
  if (out.count("")) {
    out.erase("");
    for (const auto& st : experiment::kStages) out.insert(st);
  }
  for (const auto& st : out)
    if (std::find(experiment::kStages.begin(), experiment::kStages.end(), st) ==
        experiment::kStages.end())
      throw UsageError{"--force: unknown stage '" + st +
                       "' (evolution | analysis | rendering | report | all)"};
  return out;
}

}  // namespace

int cmd_experiment(const Args& in) {
  Args args = in;
  const std::string config_path = take_option(args, "--config", "");
  const std::string preset = take_option(args, "--preset", "");
  const std::string out = take_option(args, "--out", "");
  const std::string threads = take_option(args, "--threads", "");
  const std::string force = take_option(args, "--force", "");
  const std::string print_preset = take_option(args, "--print-preset", "");
  const std::string only_run = take_option(args, "--run", "");
  const bool estimate_only = take_flag(args, "--estimate-only");
  const std::string cores_opt = take_option(args, "--cores", "");
  const std::string ranks_opt = take_option(args, "--ranks", "");
  const bool json_out = take_flag(args, "--json");
  const bool no_viewer = take_flag(args, "--no-viewer");
  const bool keep_artifacts = take_flag(args, "--keep-artifacts");
  const bool keep_vertical = take_flag(args, "--keep-vertical");
  reject_unknown_options(args);
  if (!args.empty()) throw UsageError{"unexpected argument '" + args[0] + "'"};
  const std::pair<const char*, std::string> named[] = {{"--preset", preset},
                                                       {"--print-preset", print_preset}};
  for (const auto& [option, name] : named) {
    const auto known = experiment::preset_names();
    if (name.empty() || std::find(known.begin(), known.end(), name) != known.end()) continue;
    std::string list;
    for (const auto& k : known) list += (list.empty() ? "" : " | ") + k;
    throw UsageError{std::string(option) + ": unknown preset '" + name + "' (known: " + list + ")"};
  }
  if (!print_preset.empty()) {
    std::fputs(experiment::preset_text(print_preset).c_str(), stdout);
    return 0;
  }
  if (!config_path.empty() && !preset.empty())
    throw UsageError{"give --config FILE or --preset NAME, not both"};
  if (out.empty() && !estimate_only) throw UsageError{"--out DIR is required"};
  if (!estimate_only && (!cores_opt.empty() || !ranks_opt.empty() || json_out))
    throw UsageError{"--cores, --ranks and --json go with --estimate-only"};

  const experiment::ExperimentConfig config =
      config_path.empty() ? experiment::preset_config(preset.empty() ? "default" : preset)
                          : experiment::read_experiment_config(config_path);
  experiment::ExperimentOptions opt;
  opt.out_dir = out;
  opt.force = parse_force(force);
  opt.only_run = only_run;
  opt.viewer = !no_viewer;
  opt.keep_artifacts = keep_artifacts;
  opt.keep_vertical = keep_vertical;
  for (const auto& a : in) opt.command_line += (opt.command_line.empty() ? "" : " ") + a;
  opt.command_line = "plastivox experiment " + opt.command_line;
  if (!threads.empty()) opt.threads = parse_count(threads, "--threads");

  const std::unique_ptr<evo::Cluster> mpi = join_mpi_job();
  opt.cluster = mpi.get();
  // Under mpirun the analysis's battery is shared by every rank (battery_ranks.hpp).
  if (BatteryLives lives =
          battery_lives_over_ranks(mpi.get(), opt.threads >= 0 ? opt.threads : config.threads))
    opt.share_battery = [lives](analysis::StudyOptions& o) { o.battery_lives = lives; };
  const bool leader = !opt.cluster || opt.cluster->rank() == 0;
  const int ranks = opt.cluster ? opt.cluster->size() : 1;

  // The cost, from this machine's measured speed, before any work starts: the schedule of
  // this layout (or of --cores/--ranks) replayed with costs of this lattice's bodies.
  if (leader) {
    int t = opt.threads >= 0 ? opt.threads : config.threads;
    if (t == 0) t = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
    experiment::Layout layout{ranks, t};
    if (!ranks_opt.empty()) layout.ranks = parse_count(ranks_opt, "--ranks");
    if (!cores_opt.empty()) {
      const int cores = parse_count(cores_opt, "--cores");
      if (cores < 1) throw UsageError{"--cores must be at least 1, got " + cores_opt};
      if (layout.ranks < 1 || cores % layout.ranks != 0)
        throw UsageError{"--cores " + cores_opt + " must be a multiple of --ranks " +
                         std::to_string(layout.ranks)};
      layout.threads = cores / layout.ranks;
    } else if (layout.ranks < 1) {
      throw UsageError{"--ranks must be at least 1, got " + ranks_opt};
    }
    const auto speed = experiment::measure_speed(config);
    const auto est = experiment::estimate_cost(config, speed);
    const auto bodies = experiment::sample_bodies(config, speed);
    const auto plan = experiment::predict_with_spread(config, bodies, speed, layout);
    // A lattice of more than kSampleSites sites is sampled at a coarser one (cost_estimate.hpp).
    const experiment::SampleLattice sample = experiment::sample_lattice(config);
    std::string scaled;
    if (sample.scale > 1)
      scaled = "estimate: bodies drawn and calibrated on a " + std::to_string(sample.nx) + "x" +
               std::to_string(sample.ny) + "x" + std::to_string(sample.nz) +
               " lattice of the same shape, voxels scaled up " +
               std::to_string(static_cast<int>(std::lround(sample.scale))) +
               "x (docs/experiment.md, \"Large lattices\")\n";
    std::fprintf(
        stderr,
        "plastivox experiment: '%s': %zu treatment%s x %zu seed%s, %s %d, %d generations "
        "(%lld lives a run), %.1f s lives\n%s%s\n%s\nestimate: about %s on disk\n",
        config.name.c_str(), config.treatments.size(), config.treatments.size() == 1 ? "" : "s",
        config.seeds.size(), config.seeds.size() == 1 ? "" : "s",
        config.evolution.algorithm == evo::Algorithm::kMapElites ? "map-elites, population"
                                                                 : "population",
        config.evolution.population, config.evolution.generations,
        static_cast<long long>(config.lives_per_run()), config.evolution.physics.duration,
        scaled.c_str(), est.summary().c_str(), plan.summary().c_str(),
        experiment::human_size(experiment::estimate_disk(config, !no_viewer).total()).c_str());
    if (json_out) std::printf("%s\n", plan.json().c_str());
  }
  if (estimate_only) return 0;
  render::limit_raster_threads(opt.threads >= 0 ? opt.threads : config.threads);

  opt.stop_requested = install_stop_signals("experiment");
  experiment::Progress progress(stderr);
  experiment::ExperimentOutcome outcome;
  try {
    outcome = experiment::run_experiment(config, opt, progress);
  } catch (const evo::RunRefused& e) {  // decided by rank 0, raised on every rank
    if (!opt.cluster) throw;
    return refuse_together(*opt.cluster, "experiment", e.what());
  }
  if (!leader) return 0;
  if (outcome.completed && !only_run.empty()) {
    std::printf("plastivox experiment: run %s evolved into %s/runs/%s.h5\n", only_run.c_str(),
                out.c_str(), only_run.c_str());
    return 0;
  }
  if (!outcome.completed) {
    std::fprintf(stderr, "plastivox experiment: stopped; run the same command again to resume\n");
    return 130;
  }
  std::printf("plastivox experiment: done. Outputs in %s:\n", out.c_str());
  for (const auto& f : outcome.outputs) {
    std::error_code ec;
    const auto size = std::filesystem::file_size(out + "/" + f, ec);
    std::printf("  %-44s %s\n", f.c_str(), ec ? "(missing)" : experiment::human_size(size).c_str());
  }
  return 0;
}

}  // namespace plastivox::cli
