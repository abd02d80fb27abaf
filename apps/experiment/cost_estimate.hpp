// What an experiment will cost, from this machine's measured simulation speed: printed
// before any work starts so nobody launches a 10 000 core-hour job by accident.
#pragma once

#include <cstdint>
#include <string>

#include "experiment_config.hpp"

namespace plastivox::experiment {

struct SpeedSample {
  double voxel_steps_per_second = 0;  // one core
  double steps_per_life = 0;          // simulated life / dt of a typical body
  double voxels_per_body = 0;         // typical body (half the lattice filled)
  double seconds_per_evaluation = 0;  // one core, one full life
};

// Simulates a typical body of the config's lattice and physics (half the sites filled,
// stiffness spread log-uniformly over [E_min, E_max], development on) for about
// `budget_seconds` of wall time and extrapolates a whole life.
SpeedSample measure_speed(const ExperimentConfig& config, double budget_seconds = 0.5);

struct CostEstimate {
  int64_t evolution_evaluations = 0;  // runs x (P + G (P + 1)), before cache hits
  int64_t analysis_evaluations = 0;   // champions x (1 + robustness draws)
  double core_hours = 0;
  double wall_seconds = 0;  // on `threads` cores of this machine (parallel efficiency 0.9)
  int threads = 1;
  SpeedSample speed;
  std::string summary() const;  // two lines for the terminal
};

CostEstimate estimate_cost(const ExperimentConfig& config, const SpeedSample& speed, int threads);

// What a study writes in its folder, bytes, from its plan: runs x individuals x the record
// of each, champions' genomes and phenotypes, the analysis tables, the figures, galleries
// and video at their configured sizes. Constants calibrated against real studies on disk
// (cost_estimate.cpp says which); a typical figure, not a bound.
struct DiskEstimate {
  uint64_t evolution = 0;     // runs/*.h5
  uint64_t analysis = 0;      // stats.json, CSV tables, analysis.h5, report.html, cache/
  uint64_t rendering = 0;     // figures/, videos/
  uint64_t largest_file = 0;  // the biggest single output (atomic rewrites need it twice)
  uint64_t total() const { return evolution + analysis + rendering; }
};
DiskEstimate estimate_disk(const ExperimentConfig& config);

// Refuses (InputError, one line naming dir and both sizes) when the file system holding dir
// has less free space than the study still needs: the estimate less what dir already holds
// (a resumed study), plus room for one temporary copy of the largest file. The environment
// variable PLASTIVOX_SKIP_DISK_CHECK (non-empty) turns the check off.
void check_free_space(const ExperimentConfig& config, const std::string& dir);

// "3 h 12 min", "48 s": durations for people.
std::string human_duration(double seconds);
// "3.1 GB", "1.4 MB", "312 kB", "80 B": sizes for people (MB = 2^20 bytes).
std::string human_size(uint64_t bytes);

}  // namespace plastivox::experiment
