// Stage 1: one evolutionary run per (seed, treatment), each in runs/<label>.h5. Every
// unfinished run advances at once over one evaluation pool (evo/run.hpp run_evolutions):
// this process's threads, and under mpirun every rank's threads.
#include <algorithm>
#include <chrono>
#include <cstdio>

#include "cost_estimate.hpp"
#include "experiment_run.hpp"
#include "plastivox/evo/run.hpp"

namespace plastivox::experiment {

bool stage_evolution(StageContext& ctx) {
  const auto& cfg = ctx.config;
  const size_t runs = ctx.run_files.size();
  const int64_t total = cfg.lives_per_run() * static_cast<int64_t>(runs);  // before cache hits
  const auto t0 = std::chrono::steady_clock::now();
  const bool leader = !ctx.opt.cluster || ctx.opt.cluster->rank() == 0;  // rank 0 talks
  auto log = [&](const std::string& line) {
    if (leader) ctx.progress.log(line);
  };

  std::vector<evo::RunSpec> specs;
  for (size_t r = 0; r < runs; ++r) {
    const size_t global = r + static_cast<size_t>(ctx.run_index_offset);
    const auto treatment = cfg.treatments[global % cfg.treatments.size()];
    const auto seed = cfg.seeds[global / cfg.treatments.size()];
    specs.push_back({cfg.run_config(treatment, seed), ctx.dir + "/" + ctx.run_files[r]});
  }

  // Progress over all runs: candidates made per run, and how many earlier sessions made.
  std::vector<int64_t> made(runs, 0), made_before(runs, -1);
  auto on_generation = [&](size_t r, const evo::RunProgress& rp) {
    made[r] = cfg.lives_through(rp.generations_done);
    if (made_before[r] < 0) made_before[r] = made[r] - cfg.lives_in_generation(rp.generations_done);
    int64_t done = 0, before = 0;
    for (size_t k = 0; k < runs; ++k) {
      done += made[k];
      before += std::max<int64_t>(made_before[k], 0);
    }
    const double el = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const double rate = (done - before) / std::max(el, 1e-9);
    char buf[256];
    std::snprintf(buf, sizeof buf,
                  "[evolution] run %zu/%zu %s  generation %d/%d  best %.3f  | %.0f%% of "
                  "evolution, ETA %s",
                  r + 1, runs, ctx.run_labels[r].c_str(), rp.generations_done, rp.generations_total,
                  rp.stats.best_fitness, 100.0 * done / total,
                  rate > 0 ? human_duration((total - done) / rate).c_str() : "?");
    ctx.progress.status(buf);
  };
  auto on_message = [&](size_t, const std::string& m) { log("[evolution] " + m); };

  evo::ManyRunOptions mo;
  mo.cluster = ctx.opt.cluster;
  mo.threads = ctx.opt.threads;
  mo.stop_requested = ctx.opt.stop_requested;
  mo.on_generation = on_generation;
  mo.on_message = on_message;
  const std::vector<evo::RunReport> reports = evo::run_evolutions(specs, mo);  // none off rank 0

  bool stopped = false;
  for (size_t r = 0; r < reports.size(); ++r) {
    const evo::RunReport& rep = reports[r];
    const std::string& label = ctx.run_labels[r];
    if (rep.outcome == evo::RunOutcome::kAlreadyFinished) {
      log("[evolution] " + label + ": already finished (" + std::to_string(rep.generations_done) +
          " generations), kept");
    } else if (rep.outcome == evo::RunOutcome::kStopped) {
      log("[evolution] " + label + ": stopped after generation " +
          std::to_string(rep.generations_done) + " (checkpointed; rerun to resume)");
      stopped = true;
    } else {
      log("[evolution] " + label + ": finished " + std::to_string(rep.generations_done) +
          " generations, digest " + rep.content_digest.substr(0, 12));
    }
  }
  return !stopped;
}

}  // namespace plastivox::experiment
