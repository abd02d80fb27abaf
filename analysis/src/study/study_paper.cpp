// The paper's published comparisons beside this study's: what Kriegman et al. (2018) report
// for the run champions of Fig. 5, restated here as data, and how this study's estimate
// relates to each. Every finding cites the passage of the paper's Results that states it
// (docs/method.md §8 restates them); the P levels are the paper's, Bonferroni-corrected for
// three comparisons, 20 champions per treatment.
#include <string>

#include "plastivox/analysis/bootstrap_coverage.hpp"
#include "plastivox/analysis/rng.hpp"
#include "study_internal.hpp"

namespace plastivox::analysis::study {

const std::vector<PaperFinding>& paper_findings() {
  using T = Treatment;
  static const std::vector<PaperFinding> findings = {
      // Results, "Evolvability" (Fig. 5A): after correcting for three comparisons, no
      // difference in mean displacement between adaptive and nonadaptive champions at 0.05.
      {"A", T::kNone, T::kStress, 0, "P ≥ 0.05", "Results, Evolvability; Fig. 5A"},
      {"A", T::kNone, T::kPressure, 0, "P ≥ 0.05", "Results, Evolvability; Fig. 5A"},
      // Results, "Geometric diversity" (Fig. 5B): pressure-adaptive bodies more diverse than
      // stress-adaptive ones (P < 0.001); adaptive against nonadaptive not different at 0.05.
      {"B", T::kNone, T::kStress, 0, "P ≥ 0.05", "Results, Geometric diversity; Fig. 5B"},
      {"B", T::kNone, T::kPressure, 0, "P ≥ 0.05", "Results, Geometric diversity; Fig. 5B"},
      {"B", T::kStress, T::kPressure, +1, "P < 0.001", "Results, Geometric diversity; Fig. 5B"},
      // Results, "Interoceptive robustness" (Fig. 5C): reduced stress-adaptive champions more
      // robust than nonadaptive ones (P < 0.01); pressure-adaptive against nonadaptive not
      // different at 0.05.
      {"C", T::kNone, T::kStress, +1, "P < 0.01", "Results, Interoceptive robustness; Fig. 5C"},
      {"C", T::kNone, T::kPressure, 0, "P ≥ 0.05", "Results, Interoceptive robustness; Fig. 5C"},
      // Results, "Canalization": stress-adaptive voxels change their stiffness less (lower
      // M_body, P < 0.001, Fig. 5D) and more uniformly (lower V_body, P < 0.05, Fig. 5E) than
      // pressure-adaptive ones; no evidence that V_gain differs (Fig. 5F).
      {"D", T::kStress, T::kPressure, +1, "P < 0.001", "Results, Canalization; Fig. 5D"},
      {"E", T::kStress, T::kPressure, +1, "P < 0.05", "Results, Canalization; Fig. 5E"},
      {"F", T::kStress, T::kPressure, 0, "P ≥ 0.05", "Results, Canalization; Fig. 5F"},
  };
  return findings;
}

std::string direction_text(Treatment a, Treatment b, int direction) {
  const std::string ta = to_string(a), tb = to_string(b);
  if (direction > 0) return tb + " > " + ta;
  if (direction < 0) return tb + " < " + ta;
  return "no difference between " + ta + " and " + tb;
}

namespace {

const GroupStats* group_of(const PanelStats& p, Treatment t) {
  for (const GroupStats& g : p.groups)
    if (g.treatment == t) return &g;
  return nullptr;
}

// How the study's estimate relates to the paper's finding, in one phrase.
std::string verdict(const PaperComparison& c) {
  const double d = c.difference->mean;
  const int sign = d > 0 ? 1 : d < 0 ? -1 : 0;
  const std::string n =
      "n = " + std::to_string(std::min(c.n_a, c.n_b)) + " < " + std::to_string(kMinBootstrapN);
  if (!c.powered)
    return c.paper.direction == 0 ? "cannot tell: " + n + " has no power"
           : sign == c.paper.direction
               ? "same direction, but " + n + " cannot resolve it"
               : "opposite direction at a sample size that cannot resolve it (" + n +
                     "): not a contradiction";
  if (c.paper.direction == 0)
    return c.significant ? "disagrees: this study finds a difference"
                         : "agrees: no difference found";
  if (sign == c.paper.direction)
    return c.significant ? "agrees" : "same direction, not significant";
  return c.significant ? "contradicts: significant in the opposite direction"
                       : "opposite direction, not significant";
}

}  // namespace

std::vector<PaperComparison> compare_with_paper(const StudyResult& r) {
  std::vector<PaperComparison> out;
  const std::vector<PaperFinding>& findings = paper_findings();
  for (size_t k = 0; k < findings.size(); ++k) {
    PaperComparison c;
    c.paper = findings[k];
    for (const PanelStats& p : r.panels) {
      if (p.id != c.paper.panel) continue;
      c.metric = p.metric;
      c.title = p.title;
      const GroupStats *a = group_of(p, c.paper.a), *b = group_of(p, c.paper.b);
      if (!a || !b) break;
      c.n_a = champions_behind(p.metric, a->values.size());
      c.n_b = champions_behind(p.metric, b->values.size());
      if (a->values.size() < 2 || b->values.size() < 2) {  // e.g. panel B from 2 champions
        c.verdict = "cannot tell: n = " + std::to_string(std::min(c.n_a, c.n_b)) + " < " +
                    std::to_string(kMinBootstrapN) + ", too few values for a test";
        break;
      }
      for (const BootstrapTestResult& t : p.comparisons)
        if (t.name_a == to_string(c.paper.a) && t.name_b == to_string(c.paper.b)) {
          c.measured = true;
          c.p_corrected = t.p_corrected;
          c.significant = t.significant && has_power(p, t);
          c.powered = has_power(p, t);
        }
      if (!c.measured) break;
      // Seed: the panel's, mixed with the finding's index (apart from its CIs and tests).
      c.difference = bootstrap_difference_ci(a->values, b->values, r.options.ci_level,
                                             r.options.resamples, mix64(p.seed ^ mix64(1000 + k)));
      c.verdict = verdict(c);
    }
    if (c.verdict.empty()) c.verdict = "not compared in this study";
    out.push_back(std::move(c));
  }
  return out;
}

}  // namespace plastivox::analysis::study
