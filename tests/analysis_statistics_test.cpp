// Bootstrap test and CI, Bonferroni, effect size, stars, and the pinned RNG behind them.
#include <cmath>
#include <vector>

#include "plastivox/analysis/bootstrap.hpp"
#include "plastivox/analysis/bootstrap_coverage.hpp"
#include "plastivox/analysis/canalization.hpp"  // mean
#include "plastivox/analysis/rng.hpp"
#include "plastivox/analysis/significance.hpp"
#include "test_support.hpp"

namespace plastivox::analysis {
namespace {

std::vector<double> uniform_sample(Rng& rng, int n, double lo, double hi) {
  std::vector<double> x(n);
  for (double& v : x) v = rng.uniform(lo, hi);
  return x;
}

// ---- RNG ---------------------------------------------------------------------------------------

TEST(Rng, IsPinned) {
  // Golden values: a change here changes every published number; do it knowingly. The analysis
  // draws from the base layer's SplitMix64 (the evolver's generator); these are the first
  // outputs of each draw from state 42 and of the analysis's streams, as this code gives them
  // (checked against an independent transcription of SplitMix64, its keyed streams and the
  // reject-then-modulo integer draw).
  Rng r(42);
  for (const uint64_t v : {0xbdd732262feb6e95ULL, 0x28efe333b266f103ULL, 0x47526757130f9f52ULL,
                           0x581ce1ff0e4ae394ULL, 0x09bc585a244823f2ULL})
    EXPECT_EQ(r.next_u64(), v);

  Rng small(42);
  for (const int v : {3, 1, 8, 4, 0, 2, 5, 8, 5, 4}) EXPECT_EQ(small.below(10), uint64_t(v));
  // n = 2^63 + 1 rejects almost half of the draws (here 10 draws for 4 numbers): the
  // rejection loop is pinned too.
  Rng large(42);
  for (const uint64_t v :
       {0x3dd732262feb6e94ULL, 0x5e4431fa3c80db05ULL, 0x4cf635ee9e9e2fa3ULL, 0x1e54d738297f77adULL})
    EXPECT_EQ(large.below((uint64_t{1} << 63) + 1), v);
  Rng after_ten(42);
  for (int k = 0; k < 10; ++k) after_ten.next_u64();
  EXPECT_EQ(large.next_u64(), after_ten.next_u64()) << "4 numbers below 2^63 + 1 take 10 draws";
  Rng unit(42);
  for (const double v :
       {0x1.7bae644c5fd6dp-1, 0x1.477f199d93378p-3, 0x1.1d499d5c4c3e6p-2, 0x1.607387fc392b8p-2})
    EXPECT_EQ(unit.uniform(), v);
  Rng ranged(42);
  for (const double v :
       {1.7078243938591164, -1.2004480356153995, -0.6069943487243066, -0.27904641738181235})
    EXPECT_EQ(ranged.uniform(-2, 3), v);

  // Streams: each key its own generator.
  EXPECT_EQ(Rng::stream(1, StreamPurpose::kTest, 0, 0).next_u64(), 0x7c7771b14ab93ed6ULL);
  EXPECT_EQ(Rng::stream(1, StreamPurpose::kTest, 1, 0).next_u64(), 0x26b17a2e57984508ULL);
  EXPECT_EQ(Rng::stream(1, StreamPurpose::kBootstrapTest, 0, 0).next_u64(), 0x3228d95675209ee3ULL);
  EXPECT_EQ(Rng::stream(1, StreamPurpose::kBootstrapCi, 0, 0).next_u64(), 0x92ab9b30fc96454bULL);
  EXPECT_EQ(Rng::stream(1, StreamPurpose::kRobustness, 5, 0).next_u64(), 0x5718e99e123704eeULL);
}

TEST(Rng, BelowIsUniformAndInRange) {
  Rng r(3);
  const int n = 7, draws = 70000;
  std::vector<int> count(n, 0);
  for (int i = 0; i < draws; ++i) {
    const uint64_t v = r.below(n);
    ASSERT_LT(v, uint64_t(n));
    ++count[v];
  }
  // Chi-square with 6 degrees of freedom; 22.46 is its 0.999 quantile.
  double chi2 = 0;
  for (int c : count) chi2 += (c - 10000.0) * (c - 10000.0) / 10000.0;
  EXPECT_LT(chi2, 22.46);
  for (int i = 0; i < 1000; ++i) EXPECT_EQ(r.below(1), 0u);
}

TEST(Rng, UniformIsInHalfOpenRange) {
  Rng r(5);
  for (int i = 0; i < 10000; ++i) {
    const double u = r.uniform();
    ASSERT_GE(u, 0.0);
    ASSERT_LT(u, 1.0);
  }
  EXPECT_EQ(r.uniform(2.5, 2.5), 2.5);
}

// ---- Bonferroni, stars, effect size -------------------------------------------------------------

TEST(Significance, BonferroniMultipliesAndCaps) {
  EXPECT_DOUBLE_EQ(bonferroni(0.01, 3), 0.03);
  EXPECT_DOUBLE_EQ(bonferroni(0.02, 1), 0.02);
  EXPECT_EQ(bonferroni(0.4, 3), 1.0);
  EXPECT_EQ(bonferroni(1.0, 5), 1.0);
  EXPECT_THROW(bonferroni(0.1, 0), std::invalid_argument);
  EXPECT_THROW(bonferroni(1.5, 2), std::invalid_argument);
}

TEST(Significance, StarsFollowThePaper) {
  EXPECT_EQ(significance_stars(0.0009), "***");
  EXPECT_EQ(significance_stars(0.001), "**");
  EXPECT_EQ(significance_stars(0.0099), "**");
  EXPECT_EQ(significance_stars(0.01), "*");
  EXPECT_EQ(significance_stars(0.049), "*");
  EXPECT_EQ(significance_stars(0.05), "");
  EXPECT_EQ(significance_stars(0.7), "");
}

TEST(Significance, EffectSizeOnHandMadeSamples) {
  // a: mean 2, sample variance 1; b: mean 0, sample variance 1 -> d = 2.
  const std::vector<double> a = {1, 2, 3}, b = {-1, 0, 1};
  const EffectSize e = effect_size(a, b);
  EXPECT_DOUBLE_EQ(e.pooled_sd, 1.0);
  EXPECT_DOUBLE_EQ(e.cohens_d, 2.0);
  EXPECT_DOUBLE_EQ(e.hedges_g, 2.0 * (1 - 3.0 / (4 * 6 - 9)));
  const std::vector<double> c = {5, 5}, d = {5, 5}, f = {6, 6};
  EXPECT_EQ(effect_size(c, d).cohens_d, 0.0);
  EXPECT_TRUE(std::isinf(effect_size(f, c).cohens_d));
  EXPECT_THROW(effect_size(std::vector<double>{1}, a), std::invalid_argument);
}

// ---- bootstrap test
// -------------------------------------------------------------------------------

TEST(BootstrapTest, LargeKnownDifferenceIsHighlySignificant) {
  Rng rng(1);
  const std::vector<double> a = uniform_sample(rng, 20, 0, 1), b = uniform_sample(rng, 20, 2, 3);
  for (BootstrapNull null : {BootstrapNull::kPooled, BootstrapNull::kShiftedMeans}) {
    BootstrapTestOptions o;
    o.null_model = null;
    o.comparisons = 3;
    const BootstrapTestResult r = bootstrap_test(a, b, o);
    EXPECT_EQ(r.resamples, 10000);
    EXPECT_LT(r.p_value, 0.001);
    EXPECT_DOUBLE_EQ(r.p_value, 1.0 / 10001);  // no resample is as extreme
    EXPECT_DOUBLE_EQ(r.p_corrected, 3.0 / 10001);
    EXPECT_TRUE(r.significant);
    EXPECT_EQ(r.stars, "***");
    EXPECT_LT(r.difference, -1.5);
    EXPECT_LT(r.effect.hedges_g, -3);
    // The record says how it was made.
    EXPECT_EQ(r.correction, "bonferroni");
    EXPECT_EQ(r.comparisons, 3);
    EXPECT_EQ(r.level, 0.05);
    EXPECT_EQ(r.null_model, to_string(null));
    EXPECT_FALSE(r.test.empty());
  }
}

TEST(BootstrapTest, IdenticalSamplesGiveP1) {
  const std::vector<double> a = {1, 2, 3, 4};
  const BootstrapTestResult r = bootstrap_test(a, a);
  EXPECT_EQ(r.p_value, 1.0);
  EXPECT_EQ(r.correction, "none");
  EXPECT_FALSE(r.significant);
}

TEST(BootstrapTest, IsReproducibleBySeed) {
  Rng rng(2);
  const std::vector<double> a = uniform_sample(rng, 15, 0, 1),
                            b = uniform_sample(rng, 15, 0.2, 1.2);
  BootstrapTestOptions o;
  o.seed = 77;
  const double p1 = bootstrap_test(a, b, o).p_value;
  EXPECT_EQ(bootstrap_test(a, b, o).p_value, p1);
  o.seed = 78;
  EXPECT_NE(bootstrap_test(a, b, o).p_value, p1);  // (different resamples, almost surely)
}

TEST(BootstrapTest, RejectionRateUnderTheNullIsNearTheLevel) {
  // 400 seeded trials of two samples of 20 from one distribution; each test with 1000
  // resamples (enough for a p-value near 0.05, and fast). Over 4000 trials the rates were
  // 5.1 % (pooled) and 6.4 % (shifted means, known to be slightly liberal for small n).
  for (BootstrapNull null : {BootstrapNull::kPooled, BootstrapNull::kShiftedMeans}) {
    int rejected = 0;
    const int trials = 400;
    for (int t = 0; t < trials; ++t) {
      Rng data = Rng::stream(2024, StreamPurpose::kTest, t, 0);
      const std::vector<double> a = uniform_sample(data, 20, 0, 1),
                                b = uniform_sample(data, 20, 0, 1);
      BootstrapTestOptions o;
      o.resamples = 1000;
      o.seed = static_cast<uint64_t>(t);
      o.null_model = null;
      rejected += bootstrap_test(a, b, o).significant;
    }
    const double rate = double(rejected) / trials;
    std::printf("%s null: rejection rate %.3f at level 0.05\n", to_string(null), rate);
    EXPECT_GE(rate, 0.02);
    EXPECT_LE(rate, 0.09);
  }
}

TEST(BootstrapTest, RejectsTinyOrBadSamples) {
  const std::vector<double> one = {1}, ok = {1, 2}, inf = {1, INFINITY};
  EXPECT_THROW(bootstrap_test(one, ok), std::invalid_argument);
  EXPECT_THROW(bootstrap_test(ok, inf), std::invalid_argument);
  BootstrapTestOptions o;
  o.resamples = 0;
  EXPECT_THROW(bootstrap_test(ok, ok, o), std::invalid_argument);
}

TEST(BootstrapTest, PairwiseTestsCorrectForThePairCount) {
  Rng rng(9);
  const std::vector<NamedSample> s = {{"none", uniform_sample(rng, 20, 0, 1)},
                                      {"stress", uniform_sample(rng, 20, 0.5, 1.5)},
                                      {"pressure", uniform_sample(rng, 20, 0, 1)}};
  const std::vector<BootstrapTestResult> r = pairwise_bootstrap_tests(s);
  ASSERT_EQ(r.size(), 3u);
  EXPECT_EQ(r[0].name_a, "none");
  EXPECT_EQ(r[0].name_b, "stress");
  EXPECT_EQ(r[2].name_a, "stress");
  EXPECT_EQ(r[2].name_b, "pressure");
  for (const BootstrapTestResult& x : r) {
    EXPECT_EQ(x.comparisons, 3);
    EXPECT_EQ(x.correction, "bonferroni");
    EXPECT_DOUBLE_EQ(x.p_corrected, std::min(1.0, 3 * x.p_value));
  }
  EXPECT_TRUE(r[0].significant);
}

// ---- confidence interval
// ---------------------------------------------------------------------------

TEST(BootstrapCi, CoversTheMeanAndShrinksWithN) {
  Rng rng(4);
  const std::vector<double> small = uniform_sample(rng, 10, 0, 1),
                            big = uniform_sample(rng, 1000, 0, 1);
  const ConfidenceInterval a = bootstrap_mean_ci(small), b = bootstrap_mean_ci(big);
  EXPECT_LE(a.lower, a.mean);
  EXPECT_GE(a.upper, a.mean);
  EXPECT_LT(b.upper - b.lower, a.upper - a.lower);
  // Normal approximation for the large sample: half-width ~ 1.96 * (1/sqrt(12)) / sqrt(1000).
  EXPECT_NEAR((b.upper - b.lower) / 2, 1.96 * std::sqrt(1.0 / 12) / std::sqrt(1000.0), 0.004);
  EXPECT_EQ(a.level, 0.95);
  EXPECT_EQ(a.resamples, 10000);
  EXPECT_EQ(a.method, "percentile bootstrap of the mean");
}

TEST(BootstrapCi, ConstantSampleHasZeroWidthAndIsReproducible) {
  const std::vector<double> c = {3, 3, 3};
  const ConfidenceInterval ci = bootstrap_mean_ci(c);
  EXPECT_EQ(ci.lower, 3.0);
  EXPECT_EQ(ci.upper, 3.0);
  Rng rng(6);
  const std::vector<double> x = uniform_sample(rng, 20, 0, 1);
  EXPECT_EQ(bootstrap_mean_ci(x, 0.9, 500, 3).lower, bootstrap_mean_ci(x, 0.9, 500, 3).lower);
  EXPECT_THROW(bootstrap_mean_ci(std::vector<double>{}), std::invalid_argument);
  EXPECT_THROW(bootstrap_mean_ci(x, 1.0), std::invalid_argument);
}

TEST(BootstrapCi, DifferenceOfMeansCoversTheShiftAndIsReproducible) {
  Rng rng(8);
  const std::vector<double> a = uniform_sample(rng, 200, 0, 1), b = uniform_sample(rng, 300, 2, 3);
  const ConfidenceInterval d = bootstrap_difference_ci(a, b, 0.95, 2000, 5);
  EXPECT_DOUBLE_EQ(d.mean, mean(b) - mean(a));
  EXPECT_LT(d.lower, d.mean);
  EXPECT_GT(d.upper, d.mean);
  // Half-width ~ 1.96 sqrt(1/12 (1/200 + 1/300)) = 0.052 for two uniform samples.
  EXPECT_NEAR((d.upper - d.lower) / 2, 1.96 * std::sqrt((1.0 / 200 + 1.0 / 300) / 12), 0.006);
  EXPECT_EQ(d.n, 500);
  EXPECT_EQ(bootstrap_difference_ci(a, b, 0.95, 2000, 5).lower, d.lower);
  const std::vector<double> one = {1}, two = {1, 3};
  const ConfidenceInterval fixed = bootstrap_difference_ci(one, one);
  EXPECT_EQ(fixed.lower, 0.0);
  EXPECT_EQ(fixed.upper, 0.0);
  EXPECT_GT(bootstrap_difference_ci(one, two).upper, 0.0);
  EXPECT_THROW(bootstrap_difference_ci(std::vector<double>{}, two), std::invalid_argument);
}

// ---- coverage and power against n (bootstrap_coverage.hpp) ------------------------------------

// From two values the 95 % percentile interval is their range (3 of 4 resamples fall inside
// it, and the 2.5 % and 97.5 % quantiles are its ends), which holds the mean exactly when the
// two fall on either side of it: probability 1/2 for any symmetric population.
TEST(BootstrapCoverage, TwoValuesCoverTheMeanHalfTheTime) {
  CoverageOptions o;
  o.trials = 2000;
  o.resamples = 200;
  EXPECT_NEAR(ci_coverage(SyntheticPopulation::kNormal, 2, o), 0.5, 0.035);
  EXPECT_THROW(ci_coverage(SyntheticPopulation::kNormal, 0, o), std::invalid_argument);
}

// At kMinBootstrapN the interval is within 2 points of its level for normal samples and within
// 3 for moderately skewed ones, and far short of it a few champions below (docs/analysis.md's
// table, 10 000 trials by bench/bootstrap_coverage: 93.0 % and 92.0 % at 20, 83.4 % and 82.5 %
// at 5; here 1 000 trials, a few tenths of a second, so a point of slack).
TEST(BootstrapCoverage, TheDocumentedSampleSizeReachesTheLevel) {
  CoverageOptions o;
  o.trials = 1000;
  o.resamples = 500;
  EXPECT_GE(ci_coverage(SyntheticPopulation::kNormal, kMinBootstrapN, o), 0.92);
  EXPECT_GE(ci_coverage(SyntheticPopulation::kGamma4, kMinBootstrapN, o), 0.91);
  for (SyntheticPopulation p : {SyntheticPopulation::kNormal, SyntheticPopulation::kGamma4})
    EXPECT_LT(ci_coverage(p, 5, o), 0.86) << to_string(p);
}

// Two champions per treatment can never give a star: even three standard deviations apart,
// the pooled test's p after a Bonferroni correction for three comparisons stays above 0.05.
TEST(BootstrapCoverage, TwoValuesPerSampleHaveNoPower) {
  CoverageOptions o;
  o.trials = 200;
  o.resamples = 1000;
  EXPECT_EQ(test_power(SyntheticPopulation::kNormal, 2, 3.0, 3, o), 0.0);
  EXPECT_GT(test_power(SyntheticPopulation::kNormal, kMinBootstrapN, 1.0, 3, o), 0.5);
}

}  // namespace
}  // namespace plastivox::analysis
