// What an experiment will cost, from this machine's measured simulation speed: printed
// before any work starts so nobody launches a 10 000 core-hour job by accident.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "experiment_config.hpp"
#include "schedule.hpp"

namespace plastivox::experiment {

// Above kSampleSites lattice sites, the estimate draws and calibrates bodies on the lattice's
// shape scaled down to about that many sites, and scales voxel counts and expression times up
// by the ratio of sites (docs/experiment.md, "Large lattices"): drawing 96 bodies over a 100^3
// lattice took 314 s. The paper's 10^3 lattice is not scaled.
inline constexpr int kSampleSites = 1000;
struct SampleLattice {
  int nx = 0, ny = 0, nz = 0;
  double scale = 1;  // the config's lattice sites / this one's
  int sites() const { return nx * ny * nz; }
};
SampleLattice sample_lattice(const ExperimentConfig& config);

struct SpeedSample {
  double voxel_steps_per_second = 0;  // one core (the calibration thread's CPU time): the median
  double voxel_steps_low = 0, voxel_steps_high = 0;  // the slowest and fastest probe round
  int rounds = 0;                                    // probe rounds measured
  double steps_per_life = 0;                         // simulated life / dt of a typical body
  double voxels_per_body = 0;                        // typical body (half the lattice filled)
  double voxels_simulated = 0;        // the calibration body's (at most kSampleSites / 2)
  double seconds_per_evaluation = 0;  // one core, one full life, at the median speed
};

// Simulates a typical body of the config's lattice (scaled down as sample_lattice says) and
// physics (half the sites filled, stiffness spread log-uniformly over [E_min, E_max],
// development on) in `rounds` rounds of about `budget_seconds` / `rounds` of wall time each
// (each at least kMinRoundCpu of the thread's CPU time, so a loaded machine takes longer)
// and extrapolates a whole life at the median round's speed. Speed is per CPU second of the
// calibrating thread, so other jobs on a shared machine lower it less (they still do:
// caches, memory bandwidth); the spread of the rounds is reported with it.
inline constexpr double kMinRoundCpu = 0.05;
SpeedSample measure_speed(const ExperimentConfig& config, double budget_seconds = 0.6,
                          int rounds = 5);

struct CostEstimate {
  int64_t evolution_evaluations = 0;  // runs x (P + G (P + 1)), before cache hits
  int64_t analysis_evaluations = 0;   // champions x (1 + robustness draws + battery lives)
  int64_t battery_evaluations = 0;    // champions x the battery's lives (0 without a battery)
  double battery_core_seconds = 0;    // what those lives cost at the typical body's cost
  double core_hours = 0;              // simulation alone, at the typical body's cost (busy cores)
  SpeedSample speed;
  std::string summary() const;  // two lines for the terminal (three with a battery)
};

// Wall time and utilisation on a given layout: predict_schedule below.
CostEstimate estimate_cost(const ExperimentConfig& config, const SpeedSample& speed);

// What evolution's candidates cost: bodies of random genomes of the config's lattice (every
// treatment in turn, the same draws on every call), each priced at the measured speed.
// On a lattice of more than kSampleSites sites the genomes are expressed on sample_lattice's
// and each body's voxels and the expression time are scaled up by its `scale`.
struct BodySample {
  std::vector<Job> bodies;            // seconds = voxels x steps / voxel-steps per second
  double seconds_per_expression = 0;  // one genome drawn and expressed, one core
  double voxel_steps_per_second = 0;  // the speed they were priced at (SpeedSample's)
  int64_t sites_evaluated = 0;        // CPPN sites evaluated drawing them (the work done)
};
BodySample sample_bodies(const ExperimentConfig& config, const SpeedSample& speed, int count = 96);
// The same bodies priced at another speed: the estimate at the probe's slowest and fastest round.
BodySample repriced(BodySample sample, double voxel_steps_per_second);

// The experiment's evolution replayed on `layout` (schedule.hpp), candidates' costs drawn
// from `sample`, plus the analysis simulations spread evenly over the cores.
struct SchedulePrediction {
  Layout layout;
  Policy policy = Policy::kPool;      // what the code runs, in one process or under mpirun
  ScheduleResult evolution;           // under `policy`
  ScheduleResult run_by_run;          // the same workload run by run (the code before the pool)
  double analysis_seconds = 0;        // analysis simulations / cores
  double rendering_seconds = 0;       // figures, galleries, video: rendering_seconds() below
  double wall_seconds = 0;            // start-up + evolution + analysis + rendering, s
  double utilization = 0;             // of the whole: busy / (cores x wall), 0-1
  double core_hours = 0;              // cores x wall: what the allocation is charged
  int64_t simulations = 0;            // evolution + analysis simulations (before cache hits)
  double mean_candidate_seconds = 0;  // mean cost of one sampled body, one core, s
  // wall_seconds and core_hours at the speed probe's fastest and slowest round (equal to
  // them until with_spread fills them in).
  double wall_low = 0, wall_high = 0, core_hours_low = 0, core_hours_high = 0;
  std::string summary() const;  // two lines for the terminal
  std::string json() const;     // one object; keys: cores, ranks, utilization,
                                // wall_seconds, core_hours, simulations, their
                                // ranges (and more)
};
SchedulePrediction predict_schedule(const ExperimentConfig& config, const BodySample& sample,
                                    const Layout& layout);
// The same, with the wall time and core-hours of the probe's fastest and slowest rounds.
SchedulePrediction predict_with_spread(const ExperimentConfig& config, const BodySample& sample,
                                       const SpeedSample& speed, const Layout& layout);

// The rendering stage's wall time on `threads` threads: figure panels, one gallery per
// treatment and the video at their configured sizes, drawn at this machine's measured `speed`
// (voxel-steps/s; the drawing constants were measured against it, cost_calibration.hpp), and
// every champion simulated once (`life_seconds` each).
double rendering_seconds(const ExperimentConfig& config, double life_seconds, double speed,
                         int threads);

// What a study writes in its folder, bytes, from its plan: runs x individuals x the record
// of each, champions' genomes and phenotypes, the analysis tables, the figures, galleries
// and video at their configured sizes. Constants calibrated against real studies on disk
// (cost_calibration.hpp says which); a typical figure, not a bound.
struct DiskEstimate {
  uint64_t evolution = 0;           // runs/*.h5
  uint64_t analysis = 0;            // stats.json, CSV tables, analysis.h5, report.html, cache/
  uint64_t rendering = 0;           // figures/, videos/
  uint64_t viewer = 0;              // lives/ and the 3-D viewer's scripts in report.html
  uint64_t largest_file = 0;        // the biggest single output (atomic rewrites need it twice)
  uint64_t largest_checkpoint = 0;  // the biggest file a fresh study rewrites: a run's results
  uint64_t total() const { return evolution + analysis + rendering + viewer; }
};
DiskEstimate estimate_disk(const ExperimentConfig& config, bool viewer = true);

// Refuses (InputError, one line naming dir and both sizes) when the file system holding dir
// has less free space than the study still needs: the estimate less what dir already holds,
// plus room for the temporary copy of the largest file rewritten in place. In a new folder
// that is a run's results file (each checkpoint replaces it; every other output is written
// once); a resumed study may rewrite any output, so there it is the largest file. A folder
// that already holds the whole estimate is not refused (its rewrites are atomic). The environment
// variable PLASTIVOX_SKIP_DISK_CHECK (non-empty) turns the check off.
void check_free_space(const ExperimentConfig& config, const std::string& dir, bool viewer = true);

// "3 h 12 min", "48 s": durations for people.
std::string human_duration(double seconds);
// "3.1 GB", "1.4 MB", "312 kB", "80 B": sizes for people (MB = 2^20 bytes).
std::string human_size(uint64_t bytes);

}  // namespace plastivox::experiment
