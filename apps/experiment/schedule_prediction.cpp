// The experiment's wall time on a layout of ranks and threads: evolution replayed on the
// schedule simulator with sampled candidate costs, the analysis simulations, and the
// rendering stage priced by the calibration in cost_calibration.hpp (cost_estimate.hpp).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cost_calibration.hpp"
#include "cost_estimate.hpp"
#include "plastivox/evo/rng.hpp"  // mix64

namespace plastivox::experiment {

double rendering_seconds(const ExperimentConfig& config, double life_seconds, double speed,
                         int threads) {
  using namespace calibration;
  // Every champion simulated once for the galleries and the 3-D viewer, on every thread.
  const double champions = config.runs() * life_seconds / std::max(threads, 1);
  const RenderSettings& r = config.rendering;
  if (!r.figures && !r.galleries && !r.video) return champions;
  const auto mp = [](int w, int h) { return static_cast<double>(w) * h / 1e6; };
  const double raster = raster_speedup(threads);
  double draw = kDrawStart;
  if (r.figures) draw += kFigureStems * kFigureSecondsPerMP * mp(r.figure_width, r.figure_height);
  if (r.galleries)
    draw += static_cast<double>(config.treatments.size()) *
            (kGallerySeconds + kGallerySecondsPerMP * mp(r.gallery_width, r.gallery_height)) /
            raster;
  if (r.video) {
    // As render_video counts them: every 1/fps s of the life.
    const double frames = std::floor(r.video_fps * config.evolution.physics.duration + 1e-9);
    draw +=
        frames * (kFrameSeconds + kFrameSecondsPerMP * mp(r.video_width, r.video_height)) / raster;
  }
  // A MAP-Elites run's archive: two figures, and its best elites simulated and drawn as a
  // gallery (archives/<run>/, stage_rendering.cpp).
  double elites = 0;
  if (config.evolution.algorithm == evo::Algorithm::kMapElites && r.figures) {
    draw += config.runs() * 2 * kFigureSecondsPerMP * mp(r.figure_width, r.figure_height);
    if (r.galleries) {
      draw += config.runs() *
              (kGallerySeconds + kGallerySecondsPerMP * mp(r.gallery_width, r.gallery_height)) /
              raster;
      elites = config.runs() * kArchiveElites * life_seconds / std::max(threads, 1);
    }
  }
  return draw * kReferenceSpeed / std::max(speed, 1.0) + champions + elites;
}

SchedulePrediction predict_schedule(const ExperimentConfig& config, const BodySample& sample,
                                    const Layout& layout) {
  using namespace calibration;
  SchedulePrediction p;
  p.layout = layout;
  p.policy = Policy::kPool;  // one process or mpirun: every rank serves the pool
  Workload w;
  w.runs = config.runs();
  w.generations = config.evolution.generations + 1;
  // Candidate k of (run, generation): a fixed pseudo-random pick from the sample.
  w.jobs = [&](int run, int gen) {
    std::vector<Job> jobs;
    if (sample.bodies.empty()) return jobs;
    const int64_t n = config.lives_in_generation(gen);
    for (int64_t k = 0; k < n; ++k) {
      const uint64_t h = evo::mix64(
          evo::mix64(evo::mix64(static_cast<uint64_t>(run)) ^ static_cast<uint64_t>(gen)) ^
          static_cast<uint64_t>(k));
      jobs.push_back(sample.bodies[h % sample.bodies.size()]);
    }
    return jobs;
  };
  // Making and expressing a generation, and recording it (its rows and checkpoint): on every
  // thread of a rank run by run, on the run's own thread in the pool.
  const double express =
      static_cast<double>(config.lives_in_generation(1)) * sample.seconds_per_expression +
      kGenerationSeconds;
  w.seconds_between_generations = express;
  p.evolution = simulate_schedule(w, layout, p.policy);
  w.seconds_between_generations = express / layout.threads;
  p.run_by_run = simulate_schedule(w, layout, Policy::kRunByRun);
  double mean = 0;
  for (const Job& j : sample.bodies) mean += j.seconds / static_cast<double>(sample.bodies.size());
  const int64_t analysis =
      static_cast<int64_t>(config.runs()) * config.analysis.lives_per_champion();
  p.analysis_seconds = static_cast<double>(analysis) * mean / layout.cores();
  p.rendering_seconds =
      rendering_seconds(config, mean, sample.voxel_steps_per_second, layout.threads);
  p.wall_seconds =
      kStartSeconds + p.evolution.wall_seconds + p.analysis_seconds + p.rendering_seconds;
  p.simulations = p.evolution.simulations + analysis;
  p.mean_candidate_seconds = mean;
  const double capacity = p.wall_seconds * layout.cores();
  // Rendering keeps about one core busy (the champions' simulation, on every thread, is small).
  p.utilization =
      capacity > 0 ? (p.evolution.busy_seconds + analysis * mean + p.rendering_seconds) / capacity
                   : 0;
  p.core_hours = capacity / 3600.0;
  p.wall_low = p.wall_high = p.wall_seconds;
  p.core_hours_low = p.core_hours_high = p.core_hours;
  return p;
}

SchedulePrediction predict_with_spread(const ExperimentConfig& config, const BodySample& sample,
                                       const SpeedSample& speed, const Layout& layout) {
  SchedulePrediction p = predict_schedule(config, sample, layout);
  const SchedulePrediction fast =
      predict_schedule(config, repriced(sample, speed.voxel_steps_high), layout);
  const SchedulePrediction slow =
      predict_schedule(config, repriced(sample, speed.voxel_steps_low), layout);
  p.wall_low = std::min(fast.wall_seconds, p.wall_seconds);
  p.wall_high = std::max(slow.wall_seconds, p.wall_seconds);
  p.core_hours_low = std::min(fast.core_hours, p.core_hours);
  p.core_hours_high = std::max(slow.core_hours, p.core_hours);
  return p;
}

std::string SchedulePrediction::summary() const {
  char buf[896];
  std::snprintf(buf, sizeof buf,
                "schedule: %d cores (%d rank%s x %d thread%s), %s: evolution %s at %.1f %% "
                "utilisation; with analysis and rendering about %s, %.3g core-hours (%s to %s, "
                "%.3g to %.3g core-hours, at the speed probe's fastest and slowest round)\n"
                "schedule: run by run (as before the evaluation pool) the evolution would take "
                "%s at %.1f %%",
                layout.cores(), layout.ranks, layout.ranks == 1 ? "" : "s", layout.threads,
                layout.threads == 1 ? "" : "s",
                policy == Policy::kPool ? "evaluation pool" : "run by run",
                human_duration(evolution.wall_seconds).c_str(), 100 * evolution.utilization,
                human_duration(wall_seconds).c_str(), core_hours, human_duration(wall_low).c_str(),
                human_duration(wall_high).c_str(), core_hours_low, core_hours_high,
                human_duration(run_by_run.wall_seconds).c_str(), 100 * run_by_run.utilization);
  return buf;
}

std::string SchedulePrediction::json() const {
  nlohmann::json j;
  j["cores"] = layout.cores();
  j["ranks"] = layout.ranks;
  j["threads_per_rank"] = layout.threads;
  j["policy"] = policy == Policy::kPool ? "pool" : "run-by-run";
  j["utilization"] = utilization;
  j["wall_seconds"] = wall_seconds;
  j["core_hours"] = core_hours;
  j["wall_seconds_range"] = {wall_low, wall_high};
  j["core_hours_range"] = {core_hours_low, core_hours_high};
  j["simulations"] = simulations;
  j["evolution"] = {{"wall_seconds", evolution.wall_seconds},
                    {"utilization", evolution.utilization},
                    {"simulations", evolution.simulations}};
  j["run_by_run"] = {{"wall_seconds", run_by_run.wall_seconds},
                     {"utilization", run_by_run.utilization}};
  j["analysis_seconds"] = analysis_seconds;
  j["rendering_seconds"] = rendering_seconds;
  j["mean_candidate_seconds"] = mean_candidate_seconds;
  return j.dump(2);
}

std::string human_duration(double s) {
  char buf[64];
  if (!std::isfinite(s) || s < 0) return "?";
  if (s < 90) {
    std::snprintf(buf, sizeof buf, "%.0f s", s);
  } else if (s < 5400) {
    std::snprintf(buf, sizeof buf, "%.0f min", s / 60);
  } else if (s < 3 * 86400) {
    std::snprintf(buf, sizeof buf, "%.0f h %02.0f min", std::floor(s / 3600),
                  std::floor(std::fmod(s, 3600) / 60));
  } else {
    std::snprintf(buf, sizeof buf, "%.1f days", s / 86400);
  }
  return buf;
}

}  // namespace plastivox::experiment
