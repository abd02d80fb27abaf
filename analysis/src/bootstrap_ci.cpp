// Percentile bootstrap confidence interval of a mean (see bootstrap.hpp).
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "plastivox/analysis/bootstrap.hpp"
#include "plastivox/analysis/canalization.hpp"  // mean
#include "plastivox/analysis/rng.hpp"

namespace plastivox::analysis {

namespace {
// numpy.percentile's default ("linear"): position q * (n - 1) between order statistics.
double quantile_sorted(const std::vector<double>& sorted, double q) {
  const double pos = q * static_cast<double>(sorted.size() - 1);
  const size_t lo = static_cast<size_t>(std::floor(pos));
  const size_t hi = std::min(lo + 1, sorted.size() - 1);
  const double frac = pos - static_cast<double>(lo);
  return sorted[lo] + frac * (sorted[hi] - sorted[lo]);
}
}  // namespace

ConfidenceInterval bootstrap_mean_ci(std::span<const double> x, double level, int resamples,
                                     uint64_t seed) {
  if (x.empty()) throw std::invalid_argument("bootstrap_mean_ci: empty sample");
  for (double v : x)
    if (!std::isfinite(v)) throw std::invalid_argument("bootstrap_mean_ci: non-finite value");
  if (!(level > 0 && level < 1))
    throw std::invalid_argument("bootstrap_mean_ci: level not in (0, 1)");
  if (resamples < 2) throw std::invalid_argument("bootstrap_mean_ci: resamples must be >= 2");

  ConfidenceInterval ci;
  ci.level = level;
  ci.resamples = resamples;
  ci.seed = seed;
  ci.n = static_cast<int>(x.size());
  ci.mean = mean(x);

  Rng rng = Rng::stream(seed, StreamPurpose::kBootstrapCi, 0, 0);
  std::vector<double> means(static_cast<size_t>(resamples));
  for (double& m : means) {
    double sum = 0;
    for (size_t k = 0; k < x.size(); ++k) sum += x[rng.below(x.size())];
    m = sum / static_cast<double>(x.size());
  }
  std::sort(means.begin(), means.end());
  ci.lower = quantile_sorted(means, (1 - level) / 2);
  ci.upper = quantile_sorted(means, (1 + level) / 2);
  return ci;
}

}  // namespace plastivox::analysis
