#include "plastivox/analysis/canalization.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace plastivox::analysis {

double mean(std::span<const double> x) {
  if (x.empty()) throw std::invalid_argument("mean of an empty sample");
  double sum = 0;
  for (double v : x) sum += v;
  return sum / static_cast<double>(x.size());
}

double population_variance(std::span<const double> x) {
  // Two-pass: mean first, then squared deviations; stable for the small spreads of
  // relative stiffness changes, where the one-pass formula would cancel.
  const double m = mean(x);
  double ss = 0;
  for (double v : x) ss += (v - m) * (v - m);
  return ss / static_cast<double>(x.size());
}

Canalization canalization(std::span<const double> e0, std::span<const double> e_final) {
  if (e0.empty()) throw std::invalid_argument("canalization: no body voxels");
  if (e0.size() != e_final.size())
    throw std::invalid_argument("canalization: " + std::to_string(e0.size()) + " congenital but " +
                                std::to_string(e_final.size()) +
                                " final stiffness values (pass one of each per body voxel)");
  std::vector<double> change(e0.size());
  for (size_t i = 0; i < e0.size(); ++i) {
    if (!std::isfinite(e0[i]) || !(e0[i] > 0) || !std::isfinite(e_final[i]))
      throw std::invalid_argument("canalization: voxel " + std::to_string(i) +
                                  " has E0 or final E not finite or E0 <= 0");
    change[i] = std::abs(e_final[i] / e0[i] - 1.0);
  }
  Canalization c;
  c.m_body = mean(change);
  c.v_body = population_variance(change);
  c.voxels = static_cast<int>(change.size());
  return c;
}

double v_gain(std::span<const double> alpha, const AlphaRange& range) {
  if (alpha.empty()) throw std::invalid_argument("v_gain: no body voxels");
  if (!(range.max > range.min))
    throw std::invalid_argument("v_gain: alpha range max must exceed min (got " +
                                std::to_string(range.min) + ".." + std::to_string(range.max) + ")");
  std::vector<double> normalised(alpha.size());
  const double width = range.max - range.min;
  for (size_t i = 0; i < alpha.size(); ++i) normalised[i] = (alpha[i] - range.min) / width;
  return population_variance(normalised);
}

AlphaRange evolved_alpha_range(const std::vector<std::vector<double>>& alphas) {
  bool any = false;
  AlphaRange r;
  for (const std::vector<double>& a : alphas)
    for (double v : a) {
      if (!any || v < r.min) r.min = v;
      if (!any || v > r.max) r.max = v;
      any = true;
    }
  if (!any) throw std::invalid_argument("evolved_alpha_range: no alpha values");
  return r;
}

std::vector<double> body_values(const RobotDef& robot, const std::vector<double>& lattice_array) {
  if (static_cast<int>(lattice_array.size()) != robot.sites() ||
      static_cast<int>(robot.present.size()) != robot.sites())
    throw std::invalid_argument("body_values: array has " + std::to_string(lattice_array.size()) +
                                " entries, the lattice " + std::to_string(robot.sites()));
  std::vector<double> out;
  for (int s = 0; s < robot.sites(); ++s)
    if (robot.present[s]) out.push_back(lattice_array[s]);
  return out;
}

}  // namespace plastivox::analysis
