#include "plastivox/analysis/significance.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "plastivox/analysis/canalization.hpp"  // mean

namespace plastivox::analysis {

double bonferroni(double p, int comparisons) {
  if (comparisons < 1)
    throw std::invalid_argument("bonferroni: comparisons must be >= 1, got " +
                                std::to_string(comparisons));
  if (!(p >= 0 && p <= 1))
    throw std::invalid_argument("bonferroni: p must be in [0, 1], got " + std::to_string(p));
  return std::min(1.0, p * comparisons);
}

std::string significance_stars(double p) {
  if (p < 0.001) return "***";
  if (p < 0.01) return "**";
  if (p < 0.05) return "*";
  return "";
}

namespace {
double sum_sq_dev(std::span<const double> x, double m) {
  double ss = 0;
  for (double v : x) ss += (v - m) * (v - m);
  return ss;
}
}  // namespace

EffectSize effect_size(std::span<const double> a, std::span<const double> b) {
  if (a.size() < 2 || b.size() < 2)
    throw std::invalid_argument("effect_size: each sample needs at least 2 values (got " +
                                std::to_string(a.size()) + " and " + std::to_string(b.size()) +
                                ")");
  const double ma = mean(a), mb = mean(b);
  const double na = static_cast<double>(a.size()), nb = static_cast<double>(b.size());
  EffectSize e;
  e.pooled_sd = std::sqrt((sum_sq_dev(a, ma) + sum_sq_dev(b, mb)) / (na + nb - 2));
  const double diff = ma - mb;
  if (e.pooled_sd > 0) {
    e.cohens_d = diff / e.pooled_sd;
  } else if (diff != 0) {
    e.cohens_d = std::copysign(std::numeric_limits<double>::infinity(), diff);
  }
  e.hedges_g = e.cohens_d * (1.0 - 3.0 / (4.0 * (na + nb) - 9.0));
  return e;
}

}  // namespace plastivox::analysis
