// Canalization (docs/method.md §8, Fig. 5 panels D, E, F): how much, and how unevenly, a
// champion's stiffness changed during its life, and how varied its development rates are.
//
//   M_body = mean_i |E+_i / E0_i - 1|            over body voxels i
//   V_body = var_i  |E+_i / E0_i - 1|
//   V_gain = var_i  (alpha_i - a_min) / (a_max - a_min)   [a_min, a_max]: the treatment's range
//
// Every variance here is the population variance (divide by n, numpy's default ddof=0, which
// is what the authors' Python computed). Means and sums run in voxel order, so results are
// bit-reproducible. All functions are pure and thread-safe.
#pragma once

#include <span>
#include <vector>

#include "plastivox/robot.hpp"

namespace plastivox::analysis {

struct Canalization {
  double m_body = 0;  // mean relative lifetime stiffness change, dimensionless
  double v_body = 0;  // its population variance over the body, dimensionless
  int voxels = 0;     // body voxels averaged over
};

// e0: congenital E per body voxel, Pa (> 0); e_final: final E per body voxel, Pa, same order
// (e.g. Model::e0 and SimResult::final_stiffness). Throws std::invalid_argument for empty or
// mismatched inputs and for non-finite or non-positive E0.
Canalization canalization(std::span<const double> e0, std::span<const double> e_final);

// The range of alpha used to normalise V_gain, 1/s. The paper: the smallest and largest alpha
// over the body voxels of all the treatment's champions (pressure -5.36..5.63, stress
// -10.00..6.42).
struct AlphaRange {
  double min = 0, max = 0;
};

// Population variance of (alpha - range.min) / (range.max - range.min) over body voxels.
// alpha: per body voxel, 1/s. Throws std::invalid_argument for empty input or range.max <=
// range.min. Values outside the range are not clipped (they give normalised values outside
// [0, 1]), so a wrong range shows instead of hiding.
double v_gain(std::span<const double> alpha, const AlphaRange& range);

// Smallest and largest alpha over several champions' body voxels (the "evolved range" of a
// treatment). Throws std::invalid_argument when there is no value at all.
AlphaRange evolved_alpha_range(const std::vector<std::vector<double>>& alphas);

// The values of a lattice-sized array (RobotDef::stiffness, ::dev_rate, ...) at the robot's
// present voxels, in increasing site order: the same order as Model's per-voxel arrays.
// Throws std::invalid_argument when the array is not lattice-sized.
std::vector<double> body_values(const RobotDef& robot, const std::vector<double>& lattice_array);

// Population mean and variance (divide by n) in index order; n must be > 0.
double mean(std::span<const double> x);
double population_variance(std::span<const double> x);

}  // namespace plastivox::analysis
