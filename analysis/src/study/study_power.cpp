// Which comparisons of a study can resolve anything: below kMinBootstrapN champions per
// treatment the percentile-bootstrap interval misses the mean far more often than its level
// says and the test cannot reach significance after correction (docs/analysis.md, "How many
// champions a comparison needs"), so such a comparison is reported without stars and with a
// warning, never as a finding.
#include <algorithm>
#include <cmath>
#include <string>

#include "plastivox/analysis/bootstrap_coverage.hpp"
#include "study_internal.hpp"

namespace plastivox::analysis::study {

int champions_behind(const std::string& metric, size_t values) {
  if (metric != "diversity") return static_cast<int>(values);
  // n pairs = k (k - 1) / 2: k = (1 + sqrt(1 + 8 n)) / 2, exact for the pair counts that occur.
  return static_cast<int>(std::lround((1 + std::sqrt(1 + 8.0 * static_cast<double>(values))) / 2));
}

int comparison_champions(const PanelStats& p, const BootstrapTestResult& t) {
  int fewest = -1;
  for (const GroupStats& g : p.groups)
    if (to_string(g.treatment) == t.name_a || to_string(g.treatment) == t.name_b) {
      const int n = champions_behind(p.metric, g.values.size());
      fewest = fewest < 0 ? n : std::min(fewest, n);
    }
  return std::max(fewest, 0);
}

bool has_power(const PanelStats& p, const BootstrapTestResult& t) {
  return comparison_champions(p, t) >= kMinBootstrapN;
}

std::string stars_shown(const PanelStats& p, const BootstrapTestResult& t) {
  return has_power(p, t) ? t.stars : std::string();
}

PowerSummary power_summary(const StudyResult& r) {
  return power_summary(r.panels);
}

PowerSummary power_summary(const std::vector<PanelStats>& panels) {
  PowerSummary s;
  for (const PanelStats& p : panels)
    for (const BootstrapTestResult& t : p.comparisons) {
      ++s.comparisons;
      if (has_power(p, t)) continue;
      ++s.without_power;
      const int fewest = comparison_champions(p, t);
      s.fewest = s.without_power == 1 ? fewest : std::min(s.fewest, fewest);
      if (std::find(s.panels.begin(), s.panels.end(), p.id) == s.panels.end())
        s.panels.push_back(p.id);
    }
  return s;
}

std::string power_warning(const StudyResult& r) {
  const PowerSummary s = power_summary(r);
  if (s.without_power == 0) return "";
  std::string panels;
  for (const std::string& id : s.panels) panels += (panels.empty() ? "" : ", ") + id;
  return "no statistical power: " + std::to_string(s.without_power) + " of " +
         std::to_string(s.comparisons) + " comparisons (panels " + panels +
         ") rest on fewer than " + std::to_string(kMinBootstrapN) +
         " champions per treatment (the fewest: " + std::to_string(s.fewest) +
         "), the smallest sample at which a 95 % bootstrap interval reaches its coverage "
         "(docs/analysis.md, \"How many champions a comparison needs\"); they carry no "
         "significance stars, their intervals are too narrow, and a difference between "
         "treatments there is no evidence either way";
}

}  // namespace plastivox::analysis::study
