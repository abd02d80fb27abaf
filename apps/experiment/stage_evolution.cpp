// Stage 1: one evolutionary run per (seed, treatment), each in runs/<label>.h5.
#include <algorithm>
#include <chrono>
#include <cstdio>

#include "cost_estimate.hpp"
#include "experiment_run.hpp"
#include "plastivox/evo/run.hpp"

namespace plastivox::experiment {

bool stage_evolution(StageContext& ctx) {
  const auto& cfg = ctx.config;
  const int64_t p = cfg.evolution.population, g = cfg.evolution.generations;
  const int64_t per_run = p + g * (p + 1);  // candidates made, before cache hits
  const int64_t total = per_run * static_cast<int64_t>(ctx.run_files.size());
  int64_t done_before_session = 0, done = 0;
  const auto t0 = std::chrono::steady_clock::now();
  const bool leader = !ctx.opt.cluster || ctx.opt.cluster->rank() == 0;  // rank 0 talks
  auto log = [&](const std::string& line) {
    if (leader) ctx.progress.log(line);
  };

  for (size_t r = 0; r < ctx.run_files.size(); ++r) {
    const auto& label = ctx.run_labels[r];
    const size_t global = r + static_cast<size_t>(ctx.run_index_offset);
    const auto treatment = cfg.treatments[global % cfg.treatments.size()];
    const auto seed = cfg.seeds[global / cfg.treatments.size()];
    const std::string path = ctx.dir + "/" + ctx.run_files[r];

    evo::RunOptions ro;
    ro.cluster = ctx.opt.cluster;
    ro.threads = ctx.opt.threads;
    ro.stop_requested = ctx.opt.stop_requested;
    ro.on_message = [&](const std::string& m) { log("[evolution] " + m); };
    bool first_report = true;
    ro.on_generation = [&](const evo::RunProgress& rp) {
      const int64_t run_done = p + static_cast<int64_t>(rp.generations_done) * (p + 1);
      if (first_report && rp.generations_done > 0)  // resumed: earlier sessions did the rest
        done_before_session += run_done - (p + 1);
      first_report = false;
      done = per_run * static_cast<int64_t>(r) + run_done;
      const double el =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      const double rate = (done - done_before_session) / std::max(el, 1e-9);
      char buf[256];
      std::snprintf(buf, sizeof buf,
                    "[evolution] run %zu/%zu %s  generation %d/%d  best %.3f  | %.0f%% of "
                    "evolution, ETA %s",
                    r + 1, ctx.run_files.size(), label.c_str(), rp.generations_done,
                    rp.generations_total, rp.stats.best_fitness, 100.0 * done / total,
                    rate > 0 ? human_duration((total - done) / rate).c_str() : "?");
      ctx.progress.status(buf);
    };
    const evo::RunReport rep = evo::run_evolution(cfg.run_config(treatment, seed), path, ro);
    if (rep.outcome == evo::RunOutcome::kAlreadyFinished) {
      done_before_session += per_run;
      log("[evolution] " + label + ": already finished (" + std::to_string(rep.generations_done) +
          " generations), kept");
    } else if (rep.outcome == evo::RunOutcome::kStopped) {
      log("[evolution] " + label + ": stopped after generation " +
          std::to_string(rep.generations_done) + " (checkpointed; rerun to resume)");
      return false;
    } else {
      log("[evolution] " + label + ": finished " + std::to_string(rep.generations_done) +
          " generations, digest " + rep.content_digest.substr(0, 12));
    }
  }
  return true;
}

}  // namespace plastivox::experiment
