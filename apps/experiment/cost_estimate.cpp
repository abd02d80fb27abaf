// Cost estimate: a short calibration simulation and the experiment's evaluation count.
#include "cost_estimate.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <memory>

#include <sys/statvfs.h>
#include <nlohmann/json.hpp>

#include "plastivox/evo/evolver.hpp"
#include "plastivox/evo/rng.hpp"
#include "plastivox/evo/variation.hpp"
#include "plastivox/model.hpp"
#include "plastivox/render/viewer.hpp"  // kViewerFps
#include "plastivox/robot.hpp"
#include "plastivox/robot_file.hpp"
#include "plastivox/simulator.hpp"

namespace plastivox::experiment {
namespace {

// CPU time of the calling thread, s: what one core gives, however loaded the machine is.
double thread_cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

}  // namespace

SpeedSample measure_speed(const ExperimentConfig& config, double budget_seconds) {
  const auto& e = config.evolution;
  RobotDef robot = make_empty_robot(e.nx, e.ny, e.nz, e.voxel_size);
  // The lower half of the lattice, a fixed pseudo-random stiffness pattern: a body of the
  // size and stiffness spread evolution typically produces, the same on every call.
  uint64_t lcg = 12345;
  auto uniform = [&lcg] {
    lcg = lcg * 6364136223846793005ull + 1442695040888963407ull;
    return static_cast<double>(lcg >> 11) / 9007199254740992.0;
  };
  const int zmax = std::max(1, e.nz / 2);
  for (int z = 0; z < zmax; ++z)
    for (int y = 0; y < e.ny; ++y)
      for (int x = 0; x < e.nx; ++x) {
        const int i = x + e.nx * (y + e.ny * z);
        robot.present[i] = 1;
        robot.stiffness[i] =
            e.physics.e_min * std::pow(e.physics.e_max / e.physics.e_min, uniform());
        robot.dev_rate[i] = 2 * uniform() - 1;
        robot.phase[i] = 2 * uniform() - 1;
      }
  PhysicsDef physics = e.physics;
  physics.treatment = Treatment::kStress;
  const Model model = compile(robot, physics);
  auto sim = std::make_unique<Simulator>(model);

  // Only steps actually taken count: a body this mixed can go unstable (a stopped
  // simulation's step() does nothing), and then the calibration starts it over.
  const auto t0 = std::chrono::steady_clock::now();
  const double cpu0 = thread_cpu_seconds();
  int64_t steps = 0;
  double elapsed = 0, dt = sim->state().dt;
  while (elapsed < budget_seconds) {
    if (sim->state().status != SimStatus::kRunning || sim->state().time >= physics.duration) {
      steps += sim->state().steps;
      sim = std::make_unique<Simulator>(model);
    }
    for (int k = 0; k < 50; ++k) sim->step();
    if (sim->state().status == SimStatus::kRunning) dt = sim->state().dt;
    elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }
  steps += sim->state().steps;
  const double cpu = thread_cpu_seconds() - cpu0;
  SpeedSample s;
  s.voxels_per_body = static_cast<double>(model.n);
  s.voxel_steps_per_second = s.voxels_per_body * static_cast<double>(steps) / std::max(cpu, 1e-9);
  s.steps_per_life = physics.duration / std::max(dt, 1e-12);
  s.seconds_per_evaluation = s.voxels_per_body * s.steps_per_life / s.voxel_steps_per_second;
  return s;
}

CostEstimate estimate_cost(const ExperimentConfig& config, const SpeedSample& speed) {
  CostEstimate c;
  c.speed = speed;
  const int64_t p = config.evolution.population, g = config.evolution.generations;
  c.evolution_evaluations = config.runs() * (p + g * (p + 1));
  c.analysis_evaluations =
      static_cast<int64_t>(config.runs()) * (1 + config.analysis.robustness_draws);
  const double evals = static_cast<double>(c.evolution_evaluations + c.analysis_evaluations);
  const double core_seconds = evals * speed.seconds_per_evaluation;
  c.core_hours = core_seconds / 3600.0;
  return c;
}

BodySample sample_bodies(const ExperimentConfig& config, const SpeedSample& speed, int count) {
  BodySample s;
  int64_t draws = 0;
  const double cpu0 = thread_cpu_seconds();
  for (int k = 0; k < count; ++k) {
    const Treatment t = config.treatments[static_cast<size_t>(k) % config.treatments.size()];
    const evo::EvolveConfig run = config.run_config(t, 1);
    const evo::Expresser expresser(run.expression());
    evo::Rng rng = evo::Rng::stream(1, evo::StreamPurpose::kNewcomer, 0, static_cast<uint64_t>(k));
    const evo::Offspring o = evo::random_individual(expresser, rng, run.max_mutation_tries);
    draws += o.tries;
    if (!o.phenotype.valid) continue;  // not simulated by evolution either
    Job j;
    j.voxels = o.phenotype.voxels;
    j.steps = evo::expected_steps(o.phenotype, run.physics);
    j.seconds = j.voxels * j.steps / std::max(speed.voxel_steps_per_second, 1e-9);
    s.bodies.push_back(j);
  }
  s.seconds_per_expression =
      (thread_cpu_seconds() - cpu0) / static_cast<double>(std::max<int64_t>(draws, 1));
  s.voxel_steps_per_second = speed.voxel_steps_per_second;
  return s;
}

namespace {

// ---- The stages around the simulations ----
//
// Seconds measured on the machine the constants were fitted on (2-core AMD EPYC, idle,
// 2026-12-04; the calibration read 19.7-21.4 M voxel-steps/s there), from the stage times of
// the tiny and default presets at 1 and 2 threads (docs/experiment.md, "Measured"). Drawing
// is priced at this machine's measured speed against that one: llvmpipe draws on the CPU.
constexpr double kReferenceSpeed = 20e6;      // voxel-steps/s of the calibration there
constexpr double kStartSeconds = 0.3;         // start-up and this calibration, before any stage
constexpr double kGenerationSeconds = 0.03;   // a run's generation recorded, checkpoint included
constexpr int kFigureStems = 8;               // figures drawn: evolution, panels A-F, figure 5
constexpr double kDrawStart = 0.15;           // the first OpenGL context (llvmpipe's shaders)
constexpr double kFigureSecondsPerMP = 0.37;  // a figure: drawn, PNG written (one thread)
// On one drawing thread: a gallery (4x multisampled) and a video frame (drawn and encoded), a
// fixed part and one per megapixel. The bodies' size mattered less than the pixels.
constexpr double kGallerySeconds = 0.13, kGallerySecondsPerMP = 0.44;
constexpr double kFrameSeconds = 0.030, kFrameSecondsPerMP = 0.076;
// llvmpipe's speed-up with t rasteriser threads: 1.55 measured at 2; assumed to grow at that
// rate up to 4 and no further.
double raster_speedup(int threads) {
  return 1 + 0.55 * (std::clamp(threads, 1, 4) - 1);
}

}  // namespace

double rendering_seconds(const ExperimentConfig& config, double life_seconds, double speed,
                         int threads) {
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
  return draw * kReferenceSpeed / std::max(speed, 1.0) + champions;
}

SchedulePrediction predict_schedule(const ExperimentConfig& config, const BodySample& sample,
                                    const Layout& layout) {
  SchedulePrediction p;
  p.layout = layout;
  p.policy = Policy::kPool;  // one process or mpirun: every rank serves the pool
  const int pop = config.evolution.population;
  Workload w;
  w.runs = config.runs();
  w.generations = config.evolution.generations + 1;
  // Candidate k of (run, generation): a fixed pseudo-random pick from the sample.
  w.jobs = [&](int run, int gen) {
    std::vector<Job> jobs;
    if (sample.bodies.empty()) return jobs;
    const int n = gen == 0 ? pop : pop + 1;
    for (int k = 0; k < n; ++k) {
      const uint64_t h = evo::mix64(
          evo::mix64(evo::mix64(static_cast<uint64_t>(run)) ^ static_cast<uint64_t>(gen)) ^
          static_cast<uint64_t>(k));
      jobs.push_back(sample.bodies[h % sample.bodies.size()]);
    }
    return jobs;
  };
  // Making and expressing a generation, and recording it (its rows and checkpoint): on every
  // thread of a rank run by run, on the run's own thread in the pool.
  const double express = (pop + 1) * sample.seconds_per_expression + kGenerationSeconds;
  w.seconds_between_generations = express;
  p.evolution = simulate_schedule(w, layout, p.policy);
  w.seconds_between_generations = express / layout.threads;
  p.run_by_run = simulate_schedule(w, layout, Policy::kRunByRun);
  double mean = 0;
  for (const Job& j : sample.bodies) mean += j.seconds / static_cast<double>(sample.bodies.size());
  const int64_t analysis =
      static_cast<int64_t>(config.runs()) * (1 + config.analysis.robustness_draws);
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
  return p;
}

std::string SchedulePrediction::summary() const {
  char buf[640];
  std::snprintf(buf, sizeof buf,
                "schedule: %d cores (%d rank%s x %d thread%s), %s: evolution %s at %.1f %% "
                "utilisation; with analysis and rendering about %s, %.3g core-hours\n"
                "schedule: run by run (as before the evaluation pool) the evolution would take "
                "%s at %.1f %%",
                layout.cores(), layout.ranks, layout.ranks == 1 ? "" : "s", layout.threads,
                layout.threads == 1 ? "" : "s",
                policy == Policy::kPool ? "evaluation pool" : "run by run",
                human_duration(evolution.wall_seconds).c_str(), 100 * evolution.utilization,
                human_duration(wall_seconds).c_str(), core_hours,
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

// ---- disk ----
//
// Bytes measured on real outputs (uncompressed HDF5, PNG, H.264; docs/experiment.md, "Disk
// space"), fitted per item: the tiny preset (6 runs of 2 generations, 1.5 MB in all) and a
// 200-generation evolution of population 6 (1.39 MB, 74 champions, 1406 individuals). A
// typical size, not a bound: champions and image content vary from run to run.
namespace {

constexpr double kRunFixed = 40e3;                 // a results file's headers, attributes, config
constexpr double kPerBirth = 70;                   // its /individuals row and cache entry
constexpr double kPerGeneration = 35;              // the /generations columns of one generation...
constexpr double kPerSurvivor = 30;                // ...and of each survivor in it
constexpr double kPerChampion = 14e3;              // genomes, groups and dataset headers
constexpr double kPerChampionSite = 33;            // phenotype: present u8 + four f64 per site
constexpr double kPerCheckpointGenome = 3e3;       // the stacked population in /checkpoint
constexpr double kAnalysisFixed = 120e3;           // analysis.h5 and report headers, CSS, stats
constexpr double kPerChampionAnalysis = 12e3;      // a champion's rows in every table
constexpr double kFigureBytesPerPixel = 0.085;     // PNG figures (lines on white)
constexpr double kGalleryBytesPerPixel = 0.29;     // PNG galleries (shaded bodies)
constexpr double kSvgBytes = 6e3;                  // one vector figure
constexpr double kVideoBytesPerPixelFrame = 0.02;  // H.264 of a body on a plain floor
// The 3-D viewer (docs/rendering.md): three.js, OrbitControls, the viewer and colour maps
// inlined in report.html once; per champion a life of 60 + 20F + n (8 + 13F) packed bytes
// (F frames at render::kViewerFps per simulated second, n voxels, about half the lattice for
// evolved bodies), a third more as base64, and its colour scales.
constexpr double kViewerScripts = 900e3;
constexpr double kLifeMeta = 2.5e3;
constexpr double kBodyFill = 0.5;

// New champions a run records: 3 in 2 generations, 74 in 200 (short, noisy lives); the
// rate falls as improvements get rarer.
double champions_per_run(int generations) {
  const double g = generations;
  return std::min(g + 1, 1 + std::pow(g, 0.8));
}

uint64_t folder_bytes(const std::string& dir) {
  std::error_code ec;
  uint64_t sum = 0;
  for (auto it = std::filesystem::recursive_directory_iterator(dir, ec);
       !ec && it != std::filesystem::recursive_directory_iterator(); it.increment(ec)) {
    std::error_code size_ec;
    if (it->is_regular_file(size_ec)) sum += it->file_size(size_ec);
  }
  return sum;
}

}  // namespace

DiskEstimate estimate_disk(const ExperimentConfig& config, bool viewer) {
  const evo::EvolveConfig& e = config.evolution;
  const double p = e.population, g = e.generations, runs = config.runs();
  const double sites = static_cast<double>(e.nx) * e.ny * e.nz;
  const double births = p + g * (p + 1);
  const double run_file =
      kRunFixed + births * kPerBirth + g * (kPerGeneration + p * kPerSurvivor) +
      champions_per_run(e.generations) * (kPerChampion + kPerChampionSite * sites) +
      p * kPerCheckpointGenome;
  DiskEstimate d;
  d.evolution = static_cast<uint64_t>(runs * run_file);
  const double draws = config.analysis.robustness_draws;
  d.analysis = static_cast<uint64_t>(kAnalysisFixed + runs * (kPerChampionAnalysis + 16 * draws) +
                                     runs * runs * 16);
  const RenderSettings& r = config.rendering;
  double figures = 0, galleries = 0, video = 0;
  if (r.figures)
    figures = kFigureStems * (r.figure_width * r.figure_height * kFigureBytesPerPixel + kSvgBytes);
  if (r.galleries)
    galleries =
        config.treatments.size() * r.gallery_width * r.gallery_height * kGalleryBytesPerPixel;
  if (r.video)
    video = r.video_width * r.video_height * kVideoBytesPerPixelFrame * r.video_fps *
            e.physics.duration;
  d.rendering = static_cast<uint64_t>(figures + galleries + video);
  if (viewer) {
    const double frames = std::floor(e.physics.duration * render::kViewerFps) + 1;
    const double voxels = kBodyFill * sites;
    const double life = 4.0 / 3.0 * (60 + 20 * frames + voxels * (8 + 13 * frames)) + kLifeMeta;
    d.viewer = static_cast<uint64_t>(kViewerScripts + runs * life);
  }
  d.largest_checkpoint = static_cast<uint64_t>(run_file);
  d.largest_file = static_cast<uint64_t>(
      std::max({run_file, video, d.analysis / 2.0 + (viewer ? kViewerScripts : 0)}));
  return d;
}

void check_free_space(const ExperimentConfig& config, const std::string& dir, bool viewer) {
  const char* skip = std::getenv("PLASTIVOX_SKIP_DISK_CHECK");
  if (skip && *skip) return;  // the estimate is typical, not a bound: the user knows better
  struct statvfs v {};
  if (statvfs(dir.c_str(), &v) != 0) return;  // unknown: the writes will say
  const uint64_t free_bytes = static_cast<uint64_t>(v.f_bavail) * v.f_frsize;
  const DiskEstimate d = estimate_disk(config, viewer);
  const uint64_t have = folder_bytes(dir);
  // A folder that already holds the estimate's bytes has nothing more to write but rewrites;
  // those are atomic, so a full disk fails them cleanly with nothing lost.
  if (have >= d.total()) return;
  const uint64_t need = d.total() - have + (have > 0 ? d.largest_file : d.largest_checkpoint);
  if (free_bytes < need)
    throw InputError(dir + ": the study needs about " + human_size(need) + " more on disk (" +
                     human_size(d.total()) + " in all) but only " + human_size(free_bytes) +
                     " is free there; free some space, use another --out folder, or set "
                     "PLASTIVOX_SKIP_DISK_CHECK=1");
}

std::string human_size(uint64_t b) {
  char buf[32];
  if (b >= uint64_t{1} << 30)
    std::snprintf(buf, sizeof buf, "%.1f GB", b / 1073741824.0);
  else if (b >= 1 << 20)
    std::snprintf(buf, sizeof buf, "%.1f MB", b / 1048576.0);
  else if (b >= 1 << 10)
    std::snprintf(buf, sizeof buf, "%.1f kB", b / 1024.0);
  else
    std::snprintf(buf, sizeof buf, "%ju B", static_cast<uintmax_t>(b));
  return buf;
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

std::string CostEstimate::summary() const {
  char buf[512];
  std::snprintf(buf, sizeof buf,
                "estimate: %lld evolution + %lld analysis simulations of ~%.0f voxels x %.0f "
                "steps; measured %.2f M voxel-steps/s per core = %.2f s per life\n"
                "estimate: %.3g core-hours of simulation at that body's cost",
                static_cast<long long>(evolution_evaluations),
                static_cast<long long>(analysis_evaluations), speed.voxels_per_body,
                speed.steps_per_life, speed.voxel_steps_per_second / 1e6,
                speed.seconds_per_evaluation, core_hours);
  return buf;
}

}  // namespace plastivox::experiment
