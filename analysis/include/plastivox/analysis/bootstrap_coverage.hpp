// How far the study's bootstrap can be trusted at a given sample size, measured on synthetic
// samples whose true mean is known (docs/analysis.md, "How many champions a comparison
// needs"): the coverage of bootstrap_mean_ci's interval and the power of bootstrap_test.
// bench/bootstrap_coverage prints the table in the docs; kMinBootstrapN is read from it.
//
// Why: a percentile bootstrap interval of the mean is too narrow in small samples (from n
// values it sees a spread (n - 1)/n of the true one, and a skewed population makes it worse),
// so a 95 % interval from 2 champions covers the mean about half the time, and a test between
// two such samples can never reach a Bonferroni-corrected 0.05. Functions are pure, seeded
// and thread-safe.
#pragma once

#include <cstdint>

namespace plastivox::analysis {

// The smallest n per treatment at which the study's 95 % percentile-bootstrap interval of a
// mean covers the true mean at least 93 % of the time (within 2 points of 95 %) for normal
// samples, and at least 92 % for moderately skewed ones (gamma-4, skewness 1), at this n and
// every larger n measured; at it the test holds its level and finds a difference of one standard
// deviation 72 % of the time (docs/analysis.md, "How many champions a comparison needs", which
// also says what strongly skewed measures need). Below it a comparison is reported as having no
// power: no stars, a warning in stats.json, a sentence in the report.
constexpr int kMinBootstrapN = 20;

// A population to draw synthetic samples from; each has standard deviation 1.
enum class SyntheticPopulation {
  kNormal,       // standard normal: mean 0, sd 1, skewness 0
  kGamma4,       // gamma of shape 4 scaled to sd 1: mean 2, skewness 1 (a moderate right tail)
  kExponential,  // exponential of rate 1: mean 1, sd 1, skewness 2 (a long right tail)
};
const char* to_string(SyntheticPopulation p);  // "normal", "gamma-4", "exponential"
double population_mean(SyntheticPopulation p);

struct CoverageOptions {
  int trials = 2000;     // synthetic samples (standard error of a coverage near 0.95: ~0.5 %)
  int resamples = 2000;  // bootstrap resamples per interval or test
  double level = 0.95;   // of the interval; the test's significance level is 1 - level
  uint64_t seed = 1;     // trial t draws its sample from Rng::stream(seed, kTest, n, t)
};

// Share of `trials` samples of n values for which bootstrap_mean_ci(sample, level, resamples)
// holds the population mean (inclusive bounds). n >= 1; throws std::invalid_argument otherwise.
double ci_coverage(SyntheticPopulation p, int n, const CoverageOptions& o = {});

// Share of `trials` pairs of samples of n values, the second shifted up by `shift` population
// standard deviations, that bootstrap_test (pooled null, Bonferroni-corrected for
// `comparisons`, level 1 - o.level) calls significant: the test's power (its size for shift 0).
// n >= 2; throws std::invalid_argument otherwise.
double test_power(SyntheticPopulation p, int n, double shift, int comparisons,
                  const CoverageOptions& o = {});

}  // namespace plastivox::analysis
