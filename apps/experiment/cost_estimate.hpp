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

// "3 h 12 min", "48 s": durations for people.
std::string human_duration(double seconds);

}  // namespace plastivox::experiment
