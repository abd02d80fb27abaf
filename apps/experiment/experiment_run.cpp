// Orchestration: the folder's manifest, then the stages in order.
#include "experiment_run.hpp"

#include <ctime>
#include <filesystem>

#include <nlohmann/json.hpp>

#include "cost_estimate.hpp"
#include "plastivox/analysis/study.hpp"
#include "plastivox/base/error.hpp"  // InputError
#include "plastivox/evo/run.hpp"
#include "plastivox/io/atomic_file.hpp"
#include "plastivox/io/json_input.hpp"
#include "plastivox/io/provenance.hpp"
#include "plastivox_version.hpp"

namespace plastivox::experiment {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// experiment.json: which experiment the folder holds and when it began. A folder holding a
// different experiment is refused rather than mixed.
std::string claim_folder(const ExperimentConfig& config, const std::string& dir) {
  const std::string manifest = dir + "/experiment.json";
  const json identity = json::parse(config.identity_json());
  if (fs::exists(manifest)) {
    json m;
    try {
      m = json::parse(read_file_bytes(manifest));
    } catch (const json::exception&) {
      throw InputError(manifest + ": not a plastivox experiment manifest (invalid JSON)");
    }
    if (!m.is_object() || m.value("format", "") != "plastivox-experiment" ||
        !m.contains("identity") || !m.contains("created"))
      throw InputError(manifest + ": not a plastivox experiment manifest");
    const std::string d = first_difference(m["identity"], identity, "in the folder", "now");
    if (!d.empty())
      throw InputError(dir + ": holds another experiment (" + d +
                       "); use a new --out folder or the original config");
    return m["created"].get<std::string>();
  }
  json m;
  m["format"] = "plastivox-experiment";
  m["format_version"] = 1;
  m["created"] = utc_timestamp();
  m["plastivox_version"] = PLASTIVOX_VERSION;
  m["git_commit"] = build_git_commit();
  m["config"] = json::parse(config.canonical_json());
  m["identity"] = identity;
  write_file_atomic(manifest, m.dump(2) + "\n");
  return m["created"].get<std::string>();
}

void make_folder(const std::string& dir) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec || !fs::is_directory(dir))
    throw InputError(dir + ": cannot create the output folder (" + ec.message() + ")");
  // Probe writability now rather than after an hour of evolution.
  const std::string probe = dir + "/.write-test";
  write_file_atomic(probe, "ok\n");
  fs::remove(probe, ec);
}

}  // namespace

ExperimentOutcome run_experiment(const ExperimentConfig& config, const ExperimentOptions& opt,
                                 Progress& progress) {
  for (const auto& s : opt.force) {
    bool known = false;
    for (const auto& k : kStages) known = known || s == k;
    if (!known)
      throw InputError("--force: unknown stage '" + s +
                       "' (evolution | analysis | rendering | report)");
  }
  const bool leader = !opt.cluster || opt.cluster->rank() == 0;
  const std::string& dir = opt.out_dir;
  std::string created, refusal;
  if (leader) {
    try {
      make_folder(dir);
      check_free_space(config, dir, opt.viewer);  // before an hour of work, not when the disk fills
      make_folder(dir + "/runs");
      created = claim_folder(config, dir);
    } catch (const std::exception& e) {
      if (!opt.cluster) throw;
      refusal = e.what();
    }
    if (refusal.empty()) {
      progress.set_log_file(dir + "/experiment.log");
      progress.log("[experiment] " + config.name + " in " + dir + " (started " + created + ")");
    }
  }
  // Under MPI rank 0 decides and every rank raises the same refusal (none waits forever).
  if (opt.cluster) {
    opt.cluster->broadcast(refusal);
    if (!refusal.empty()) throw evo::RunRefused(refusal);
  }

  StageContext ctx{config, opt, progress, dir, created, {}, {}, 0, nullptr};
  for (auto seed : config.seeds)
    for (auto t : config.treatments) {
      const std::string label = ExperimentConfig::run_label(t, seed);
      ctx.run_labels.push_back(label);
      ctx.run_files.push_back("runs/" + label + ".h5");
    }
  if (!opt.only_run.empty()) {
    size_t i = 0;
    while (i < ctx.run_labels.size() && ctx.run_labels[i] != opt.only_run) ++i;
    if (i == ctx.run_labels.size())
      throw InputError("--run: '" + opt.only_run + "' is not a run of this experiment (" +
                       ctx.run_labels.front() + " ... " + ctx.run_labels.back() + ")");
    ctx.run_labels = {ctx.run_labels[i]};
    ctx.run_files = {ctx.run_files[i]};
    ctx.run_index_offset = static_cast<int>(i);
  }
  if (opt.force.count("evolution") && leader)
    for (const auto& f : ctx.run_files) fs::remove(dir + "/" + f);
  if (opt.cluster) opt.cluster->barrier();

  ExperimentOutcome out;
  out.outputs.push_back("experiment.json");
  out.outputs.push_back("experiment.log");
  if (!stage_evolution(ctx)) return out;
  for (const auto& f : ctx.run_files) out.outputs.push_back(f);
  // Analysis, rendering and the report run on rank 0 alone; under mpirun with a battery the
  // other ranks stay for the analysis and share the battery's lives (docs/analysis.md).
  ctx.shared_analysis = opt.cluster && opt.cluster->size() > 1 && opt.share_battery &&
                        !config.analysis.battery.empty() && opt.only_run.empty();
  if ((!leader && !ctx.shared_analysis) || !opt.only_run.empty()) {
    out.completed = true;
    return out;
  }
  // A stop request between stages ends the session cleanly; every stage is resumable.
  auto stopping = [&] { return opt.stop_requested && opt.stop_requested->load(); };
  if (ctx.shared_analysis) {  // rank 0's flag decides for every rank
    std::string go = stopping() ? "stop" : "go";
    opt.cluster->broadcast(go);
    if (go == "stop") return out;
  } else if (stopping()) {
    return out;
  }
  try {
    for (const auto& f : stage_analysis(ctx)) out.outputs.push_back(f);
  } catch (const analysis::StudyStopped&) {
    progress.log("[analysis] stopped; the champions done are checkpointed (rerun to resume)");
    return out;
  }
  if (!leader) {  // it helped with the battery; rank 0 renders and reports
    out.completed = true;
    return out;
  }
  if (stopping()) return out;
  for (const auto& f : stage_rendering(ctx)) out.outputs.push_back(f);
  if (stopping()) return out;
  for (const auto& f : stage_report(ctx, out.outputs)) out.outputs.push_back(f);
  out.completed = true;
  return out;
}

}  // namespace plastivox::experiment
