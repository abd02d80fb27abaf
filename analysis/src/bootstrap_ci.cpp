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

void check(std::span<const double> x, double level, int resamples, const char* who) {
  const std::string w = who;
  if (x.empty()) throw std::invalid_argument(w + ": empty sample");
  for (double v : x)
    if (!std::isfinite(v)) throw std::invalid_argument(w + ": non-finite value");
  if (!(level > 0 && level < 1)) throw std::invalid_argument(w + ": level not in (0, 1)");
  if (resamples < 2) throw std::invalid_argument(w + ": resamples must be >= 2");
}

// The mean of x.size() values drawn from x with replacement.
double resampled_mean(std::span<const double> x, Rng& rng) {
  double sum = 0;
  for (size_t k = 0; k < x.size(); ++k) sum += x[rng.below(x.size())];
  return sum / static_cast<double>(x.size());
}

// Sorts the resampled statistics and sets the interval's bounds from their quantiles.
void set_bounds(std::vector<double>& stats, ConfidenceInterval& ci) {
  std::sort(stats.begin(), stats.end());
  ci.lower = quantile_sorted(stats, (1 - ci.level) / 2);
  ci.upper = quantile_sorted(stats, (1 + ci.level) / 2);
}
}  // namespace

ConfidenceInterval bootstrap_mean_ci(std::span<const double> x, double level, int resamples,
                                     uint64_t seed) {
  check(x, level, resamples, "bootstrap_mean_ci");

  ConfidenceInterval ci;
  ci.level = level;
  ci.resamples = resamples;
  ci.seed = seed;
  ci.n = static_cast<int>(x.size());
  ci.mean = mean(x);

  Rng rng = Rng::stream(seed, StreamPurpose::kBootstrapCi, 0, 0);
  std::vector<double> means(static_cast<size_t>(resamples));
  for (double& m : means) m = resampled_mean(x, rng);
  set_bounds(means, ci);
  return ci;
}

ConfidenceInterval bootstrap_difference_ci(std::span<const double> a, std::span<const double> b,
                                           double level, int resamples, uint64_t seed) {
  check(a, level, resamples, "bootstrap_difference_ci");
  check(b, level, resamples, "bootstrap_difference_ci");
  ConfidenceInterval ci;
  ci.method = "percentile bootstrap of the difference in means (b - a)";
  ci.level = level;
  ci.resamples = resamples;
  ci.seed = seed;
  ci.n = static_cast<int>(a.size() + b.size());
  ci.mean = mean(b) - mean(a);
  Rng rng = Rng::stream(seed, StreamPurpose::kBootstrapCi, 1, 0);
  std::vector<double> differences(static_cast<size_t>(resamples));
  for (double& d : differences) {
    const double ma = resampled_mean(a, rng);
    d = resampled_mean(b, rng) - ma;
  }
  set_bounds(differences, ci);
  return ci;
}

}  // namespace plastivox::analysis
