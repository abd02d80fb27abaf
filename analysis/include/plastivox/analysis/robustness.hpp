// Robustness (docs/method.md §8, Fig. 5 panel C): how much of a champion's fitness survives
// when its evolved stiffness is replaced by noise.
//
//   The reduced robot: the champion with development removed (every alpha = 0, treatment none).
//   F_train  = its fitness with its evolved (congenital) stiffness.
//   F_test_k = its fitness with every voxel's stiffness drawn independently from [E_lo, E_hi]
//              (uniform on a linear scale, as the authors did; log-uniform as an option).
//   R_k      = F_test_k / F_train, for draws k = 0 .. draws-1 (10 by default).
//
// Draw k takes its numbers from Rng::stream(seed, kRobustness, k, 0), one value per present
// voxel in increasing site order, so the stiffness fields depend only on (seed, k) and the robot.
// The 1 + draws simulations run in parallel (one per thread at a time); each is single-threaded
// and deterministic, so results are bit-identical for any thread count. Recording is switched
// off.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "plastivox/physics_def.hpp"
#include "plastivox/robot.hpp"

namespace plastivox::analysis {

enum class StiffnessDistribution { kLinear, kLogUniform };
const char* to_string(StiffnessDistribution d);  // "uniform", "log-uniform"

struct RobustnessOptions {
  int draws = 10;
  uint64_t seed = 1;
  StiffnessDistribution distribution = StiffnessDistribution::kLinear;
  // Range of the random stiffness, Pa. Both 0: the physics' [e_min, e_max]. lo == hi is
  // allowed (every voxel gets that value: a control with no randomness at all).
  double e_lo = 0, e_hi = 0;
  int threads = 0;  // 0 = the hardware's count
  Limits limits;    // the engine's bounds on each life (the program's: limits_from_environment)
};

struct RobustnessDraw {
  double f_test = 0;    // fitness, voxel lengths
  double r = 0;         // f_test / f_train (0 when invalid)
  bool valid = false;   // false when the simulation went unstable or F_train was unusable
  std::string failure;  // why, when not valid
};

struct RobustnessResult {
  // How it was obtained.
  std::string distribution;   // "uniform" or "log-uniform"
  double e_lo = 0, e_hi = 0;  // Pa
  uint64_t seed = 0;
  // F_train and the draws.
  double f_train = 0;        // voxel lengths
  bool train_valid = false;  // simulation stable and F_train > 0 (else no R is defined)
  std::string train_failure;
  std::vector<RobustnessDraw> draws;
  int valid_draws = 0;
  double mean_r = 0;  // mean of R over valid draws (0 if none)
};

// Validates the robot and physics (std::invalid_argument) and the options (draws >= 1,
// 0 < e_lo <= e_hi, finite). Unstable simulations do not throw: they are reported per draw.
RobustnessResult robustness(const RobotDef& champion, const PhysicsDef& physics,
                            const RobustnessOptions& options = {});

// The robot simulated for draw k: the reduced robot with draw k's stiffness field (what
// robustness() runs; exposed so callers can store or render the fields). Throws like
// robustness() for bad options; k >= 0.
RobotDef robustness_draw(const RobotDef& champion, const PhysicsDef& physics,
                         const RobustnessOptions& options, int k);

// The reduced robot (alpha = 0 everywhere) and the physics it is simulated under (treatment
// none, no recording). Exposed so callers can re-run F_train themselves.
RobotDef without_development(const RobotDef& robot);
PhysicsDef robustness_physics(const PhysicsDef& physics);

}  // namespace plastivox::analysis
