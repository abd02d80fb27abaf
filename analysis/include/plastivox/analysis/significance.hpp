// Small statistics shared by every comparison the analysis reports: Bonferroni correction,
// the paper's significance stars, and an effect size. Pure functions, thread-safe.
#pragma once

#include <span>
#include <string>

namespace plastivox::analysis {

// Bonferroni: p * comparisons, capped at 1. comparisons >= 1 (std::invalid_argument otherwise);
// p in [0, 1].
double bonferroni(double p, int comparisons);

// The paper's convention: "***" for p < 0.001, "**" for p < 0.01, "*" for p < 0.05, "" else.
// Pass the corrected p-value.
std::string significance_stars(double p);

// Standardised difference of means a - b.
//   Cohen's d = (mean_a - mean_b) / s_pooled,
//   s_pooled  = sqrt(((n_a - 1) s_a^2 + (n_b - 1) s_b^2) / (n_a + n_b - 2))  (sample variances)
//   Hedges' g = d * (1 - 3 / (4 (n_a + n_b) - 9))   (small-sample bias correction)
// When s_pooled is 0: 0 if the means are equal, else +-infinity.
struct EffectSize {
  double cohens_d = 0;
  double hedges_g = 0;
  double pooled_sd = 0;  // s_pooled, in the samples' unit
};
// Each sample needs >= 2 values (std::invalid_argument otherwise).
EffectSize effect_size(std::span<const double> a, std::span<const double> b);

}  // namespace plastivox::analysis
