// Coverage and power of the study's bootstrap on synthetic samples (see bootstrap_coverage.hpp).
#include "plastivox/analysis/bootstrap_coverage.hpp"

#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "plastivox/analysis/bootstrap.hpp"
#include "plastivox/analysis/rng.hpp"

namespace plastivox::analysis {

const char* to_string(SyntheticPopulation p) {
  switch (p) {
    case SyntheticPopulation::kNormal:
      return "normal";
    case SyntheticPopulation::kGamma4:
      return "gamma-4";
    case SyntheticPopulation::kExponential:
      return "exponential";
  }
  return "?";
}

double population_mean(SyntheticPopulation p) {
  switch (p) {
    case SyntheticPopulation::kNormal:
      return 0;
    case SyntheticPopulation::kGamma4:
      return 2;  // 4 x 1, halved to sd 1
    case SyntheticPopulation::kExponential:
      return 1;
  }
  return 0;
}

namespace {

double exponential(Rng& rng) {
  return -std::log(1.0 - rng.uniform());  // inverse CDF; 1 - u is in (0, 1]
}

double draw(SyntheticPopulation p, Rng& rng) {
  switch (p) {
    case SyntheticPopulation::kNormal:
      return rng.normal();
    case SyntheticPopulation::kGamma4:  // the sum of 4 exponentials: variance 4, halved to sd 1
      return (exponential(rng) + exponential(rng) + exponential(rng) + exponential(rng)) / 2;
    case SyntheticPopulation::kExponential:
      return exponential(rng);
  }
  return 0;
}

std::vector<double> sample(SyntheticPopulation p, int n, Rng& rng, double shift = 0) {
  std::vector<double> x(static_cast<size_t>(n));
  for (double& v : x) v = draw(p, rng) + shift;
  return x;
}

void check(int n, int least, const CoverageOptions& o, const char* what) {
  if (n < least)
    throw std::invalid_argument(std::string(what) + ": n must be >= " + std::to_string(least) +
                                ", got " + std::to_string(n));
  if (o.trials < 1) throw std::invalid_argument(std::string(what) + ": trials must be >= 1");
}

}  // namespace

double ci_coverage(SyntheticPopulation p, int n, const CoverageOptions& o) {
  check(n, 1, o, "ci_coverage");
  const double mu = population_mean(p);
  int covered = 0;
  for (int t = 0; t < o.trials; ++t) {
    Rng rng = Rng::stream(o.seed, StreamPurpose::kTest, static_cast<uint64_t>(n),
                          static_cast<uint64_t>(t));
    const ConfidenceInterval ci =
        bootstrap_mean_ci(sample(p, n, rng), o.level, o.resamples, mix64(o.seed + t));
    covered += ci.lower <= mu && mu <= ci.upper;
  }
  return static_cast<double>(covered) / o.trials;
}

double test_power(SyntheticPopulation p, int n, double shift, int comparisons,
                  const CoverageOptions& o) {
  check(n, 2, o, "test_power");
  BootstrapTestOptions bo;
  bo.resamples = o.resamples;
  bo.level = 1 - o.level;
  bo.comparisons = comparisons;
  int significant = 0;
  for (int t = 0; t < o.trials; ++t) {
    Rng rng = Rng::stream(o.seed, StreamPurpose::kTest, static_cast<uint64_t>(n),
                          static_cast<uint64_t>(t));
    const std::vector<double> a = sample(p, n, rng), b = sample(p, n, rng, shift);
    bo.seed = mix64(o.seed + t);
    significant += bootstrap_test(a, b, bo).significant;
  }
  return static_cast<double>(significant) / o.trials;
}

}  // namespace plastivox::analysis
