// CSV tables of a study (RFC 4180: comma-separated, fields with a comma, quote or line break
// quoted). Numbers are the shortest text that reads back to the same double, so a table
// agrees with stats.json bit for bit; an empty field is an undefined value.
#include <sstream>
#include <string>
#include <vector>

#include "study_internal.hpp"

namespace plastivox::analysis {
namespace {

using study::number;

std::string field(const std::string& s) {
  if (s.find_first_of(",\"\n\r") == std::string::npos) return s;
  std::string q = "\"";
  for (char ch : s) {
    if (ch == '"') q += '"';
    q += ch;
  }
  q += '"';
  return q;
}

std::string row(const std::vector<std::string>& fields) {
  std::string s;
  for (size_t i = 0; i < fields.size(); ++i) {
    if (i) s += ',';
    s += field(fields[i]);
  }
  return s + "\n";
}

}  // namespace

std::string champions_csv(const StudyResult& r) {
  const int draws = r.options.robustness_draws;
  std::vector<std::string> head = {"label",
                                   "file",
                                   "treatment",
                                   "seed",
                                   "generation",
                                   "champion_id",
                                   "evaluation",
                                   "status",
                                   "status_detail",
                                   "fitness",
                                   "voxels",
                                   "f_train",
                                   "r_mean",
                                   "valid_draws",
                                   "m_body",
                                   "v_body",
                                   "v_gain",
                                   "body_plan",
                                   "body_plan_confidence",
                                   "body_plan_margin",
                                   "extent_x",
                                   "extent_y",
                                   "extent_z",
                                   "box_fill",
                                   "phenotype_digest",
                                   "health",
                                   "floor_depth",
                                   "vertical_share",
                                   "vertical_exploit",
                                   "excluded"};
  for (int k = 0; k < draws; ++k) head.push_back("r_draw_" + std::to_string(k));
  std::string out = row(head);
  for (const ChampionAnalysis& c : r.champions) {
    const BodyPlanFeatures& f = c.body_plan.features;
    const RobustnessResult& rb = c.robustness;
    std::vector<std::string> v = {c.label,
                                  r.inputs[c.input].file,
                                  to_string(c.treatment),
                                  std::to_string(c.run_seed),
                                  std::to_string(c.generation),
                                  std::to_string(c.id),
                                  c.evaluation,
                                  c.status,
                                  c.status_detail,
                                  c.evaluation == "ok" ? number(c.fitness) : "",
                                  std::to_string(c.voxels),
                                  rb.train_valid ? number(rb.f_train) : "",
                                  number(c.r_mean),
                                  std::to_string(rb.valid_draws),
                                  number(c.m_body),
                                  number(c.v_body),
                                  number(c.v_gain),
                                  to_string(c.body_plan.plan),
                                  number(c.body_plan.confidence),
                                  number(c.body_plan.margin),
                                  std::to_string(f.extent[0]),
                                  std::to_string(f.extent[1]),
                                  std::to_string(f.extent[2]),
                                  number(f.box_fill),
                                  c.phenotype_digest,
                                  c.health,
                                  number(c.floor_depth),
                                  number(c.vertical_share),
                                  c.vertical_exploit ? "true" : "false",
                                  c.artifact};
    // Every row has a cell per draw: a champion whose robustness was not measured (an
    // artifact, a vertical exploit) has them empty.
    for (size_t k = 0; k < static_cast<size_t>(draws); ++k)
      v.push_back(k < rb.draws.size() && rb.draws[k].valid ? number(rb.draws[k].r) : "");
    out += row(v);
  }
  return out;
}

std::string statistics_csv(const StudyResult& r) {
  const StudyOptions& o = r.options;
  std::string out =
      row({"kind",  "panel",       "metric",  "unit",        "treatment",   "n",
           "mean",  "ci_low",      "ci_high", "a",           "b",           "mean_diff",
           "p",     "p_corrected", "stars",   "effect_size", "comparisons", "correction",
           "alpha", "resamples",   "test"});
  const std::string test = "two-sample bootstrap, difference in means, two-sided, pooled null";
  const std::string ci = "percentile bootstrap CI of the mean, level " + number(o.ci_level);
  for (const PanelStats& p : r.panels) {
    for (const GroupStats& g : p.groups)
      out += row({"group",
                  p.id,
                  p.metric,
                  p.unit,
                  to_string(g.treatment),
                  std::to_string(g.values.size()),
                  number(g.mean),
                  g.ci ? number(g.ci->lower) : "",
                  g.ci ? number(g.ci->upper) : "",
                  "",
                  "",
                  "",
                  "",
                  "",
                  "",
                  "",
                  "",
                  "",
                  "",
                  std::to_string(o.resamples),
                  ci});
    for (const BootstrapTestResult& t : p.comparisons)
      out += row({"comparison",
                  p.id,
                  p.metric,
                  p.unit,
                  "",
                  "",
                  "",
                  "",
                  "",
                  t.name_a,
                  t.name_b,
                  number(t.difference),
                  number(t.p_value),
                  number(t.p_corrected),
                  study::stars_shown(p, t),
                  number(t.effect.hedges_g),
                  std::to_string(t.comparisons),
                  t.comparisons > 1 ? "Bonferroni" : "none",
                  number(t.level),
                  std::to_string(t.resamples),
                  test});
  }
  return out;
}

std::string hausdorff_csv(const StudyResult& r) {
  std::vector<std::string> head = {"label"};
  for (const ChampionAnalysis& c : r.champions) head.push_back(c.label);
  std::string out = row(head);
  for (int i = 0; i < r.hausdorff.n; ++i) {
    std::vector<std::string> v = {r.champions[i].label};
    for (int j = 0; j < r.hausdorff.n; ++j) v.push_back(number(r.hausdorff.at(i, j)));
    out += row(v);
  }
  return out;
}

}  // namespace plastivox::analysis
