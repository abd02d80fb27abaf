// Two-sample bootstrap hypothesis test for a difference in means (see bootstrap.hpp).
#include <cmath>
#include <stdexcept>
#include <string>

#include "plastivox/analysis/bootstrap.hpp"
#include "plastivox/analysis/canalization.hpp"  // mean
#include "plastivox/analysis/rng.hpp"

namespace plastivox::analysis {

const char* to_string(BootstrapNull n) {
  return n == BootstrapNull::kPooled ? "pooled" : "shifted-means";
}

namespace {

void check_sample(std::span<const double> x, const char* which) {
  if (x.size() < 2)
    throw std::invalid_argument(std::string("bootstrap_test: sample ") + which +
                                " needs at least 2 values, got " + std::to_string(x.size()));
  for (double v : x)
    if (!std::isfinite(v))
      throw std::invalid_argument(std::string("bootstrap_test: sample ") + which +
                                  " holds a non-finite value");
}

// Mean of n values drawn with replacement from pool.
double resampled_mean(const std::vector<double>& pool, size_t n, Rng& rng) {
  double sum = 0;
  for (size_t k = 0; k < n; ++k) sum += pool[rng.below(pool.size())];
  return sum / static_cast<double>(n);
}

}  // namespace

BootstrapTestResult bootstrap_test(std::span<const double> a, std::span<const double> b,
                                   const BootstrapTestOptions& options) {
  check_sample(a, "a");
  check_sample(b, "b");
  if (options.resamples < 1) throw std::invalid_argument("bootstrap_test: resamples must be >= 1");
  if (!(options.level > 0 && options.level < 1))
    throw std::invalid_argument("bootstrap_test: level must be in (0, 1)");

  BootstrapTestResult r;
  r.test = "two-sample bootstrap, difference in means, two-sided";
  r.null_model = to_string(options.null_model);
  r.comparisons = options.comparisons;
  r.correction = options.comparisons > 1 ? "bonferroni" : "none";
  r.level = options.level;
  r.resamples = options.resamples;
  r.seed = options.seed;
  r.n_a = static_cast<int>(a.size());
  r.n_b = static_cast<int>(b.size());
  r.mean_a = mean(a);
  r.mean_b = mean(b);
  r.difference = r.mean_a - r.mean_b;
  r.effect = effect_size(a, b);

  // The null world to resample from.
  std::vector<double> pool_a, pool_b;
  if (options.null_model == BootstrapNull::kPooled) {
    pool_a.assign(a.begin(), a.end());
    pool_a.insert(pool_a.end(), b.begin(), b.end());
  } else {
    std::vector<double> all(a.begin(), a.end());
    all.insert(all.end(), b.begin(), b.end());
    const double pooled_mean = mean(all);
    for (double v : a) pool_a.push_back(v - r.mean_a + pooled_mean);
    for (double v : b) pool_b.push_back(v - r.mean_b + pooled_mean);
  }
  const std::vector<double>& from_a = pool_a;
  const std::vector<double>& from_b =
      options.null_model == BootstrapNull::kPooled ? pool_a : pool_b;

  // Resampled differences that are at least as extreme as the observed one. A resample that
  // reproduces the data with its values summed in another order may differ from |t| in the
  // last bits; a relative slack of 1e-12 counts it as a tie (as extreme), as it should.
  const double observed = std::abs(r.difference) * (1.0 - 1e-12);
  Rng rng = Rng::stream(options.seed, StreamPurpose::kBootstrapTest, 0, 0);
  long long extreme = 0;
  for (int k = 0; k < options.resamples; ++k) {
    const double ma = resampled_mean(from_a, a.size(), rng);
    const double mb = resampled_mean(from_b, b.size(), rng);
    if (std::abs(ma - mb) >= observed) ++extreme;
  }
  r.p_value = static_cast<double>(1 + extreme) / static_cast<double>(options.resamples + 1);
  r.p_corrected = bonferroni(r.p_value, options.comparisons);
  r.significant = r.p_corrected < options.level;
  r.stars = significance_stars(r.p_corrected);
  return r;
}

std::vector<BootstrapTestResult> pairwise_bootstrap_tests(const std::vector<NamedSample>& samples,
                                                          const BootstrapTestOptions& options) {
  const int n = static_cast<int>(samples.size());
  if (n < 2) throw std::invalid_argument("pairwise_bootstrap_tests: need at least 2 samples");
  const int pairs = n * (n - 1) / 2;
  std::vector<BootstrapTestResult> out;
  int k = 0;
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; ++j, ++k) {
      BootstrapTestOptions o = options;
      o.seed = mix64(options.seed + static_cast<uint64_t>(k));
      if (options.comparisons <= 1) o.comparisons = pairs;
      BootstrapTestResult r = bootstrap_test(samples[i].values, samples[j].values, o);
      r.name_a = samples[i].name;
      r.name_b = samples[j].name;
      out.push_back(std::move(r));
    }
  return out;
}

}  // namespace plastivox::analysis
