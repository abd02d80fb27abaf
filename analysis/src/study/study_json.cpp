// stats.json: the contract between the analysis and its consumers (figures, experiment report).
// Field names follow docs/analysis.md ("stats.json"); fields may be added, never renamed.
// Undefined values are null (JSON has no NaN or infinity). Keys keep the documented order.
#include <algorithm>
#include <cmath>
#include <string>

#include <nlohmann/json.hpp>

#include "plastivox/analysis/bootstrap_coverage.hpp"
#include "plastivox/rules/life_rules.hpp"
#include "plastivox/simulator.hpp"
#include "study_internal.hpp"

namespace plastivox::analysis {
namespace {

using Json = nlohmann::ordered_json;

Json num(double x) {
  return std::isfinite(x) ? Json(x) : Json(nullptr);
}
Json num(const std::optional<double>& x) {
  return x ? num(*x) : Json(nullptr);
}

Json numbers(const std::vector<double>& xs) {
  Json a = Json::array();
  for (double x : xs) a.push_back(num(x));
  return a;
}

Json strings(const std::vector<std::string>& xs) {
  Json a = Json::array();
  for (const std::string& x : xs) a.push_back(x);
  return a;
}

Json provenance(const StudyResult& r) {
  Json inputs = Json::array();
  for (const StudyInput& in : r.inputs)
    inputs.push_back({{"file", in.file},
                      {"content_digest", in.content_digest},
                      {"treatment", to_string(in.treatment)},
                      {"seed", in.seed},
                      {"generation", in.generation},
                      {"generations_done", in.generations_done}});
  return {{"version", r.version},
          {"commit", r.commit},
          {"date", r.date},
          {"command", r.options.command},
          {"inputs", inputs},
          {"options", Json::parse(options_json(r.options))},
          {"fingerprint", r.fingerprint}};
}

int most_comparisons(const StudyResult& r) {
  int m = 0;
  for (const PanelStats& p : r.panels) m = std::max(m, static_cast<int>(p.comparisons.size()));
  return m;
}

Json statistics(const StudyResult& r) {
  const StudyOptions& o = r.options;
  const std::string level = study::display(o.ci_level * 100, 4) + "%";
  return {{"test", "two-sample bootstrap test of the difference in means (two-sided)"},
          {"null_model",
           "pooled: both samples resampled with replacement from their union (Efron & "
           "Tibshirani 1993, Algorithm 16.1)"},
          {"p_value", "(1 + #{resamples with |t*| >= |t|}) / (resamples + 1)"},
          {"resamples", o.resamples},
          {"alpha", o.alpha},
          {"correction", "Bonferroni"},
          {"comparisons", most_comparisons(r)},
          {"comparisons_rule",
           "per panel: p is multiplied by the number of treatment pairs compared in that panel "
           "(the panel's comparisons_made) and capped at 1"},
          {"ci", level + " bootstrap percentile interval of the mean"},
          {"ci_level", o.ci_level},
          {"stars", "* p<0.05, ** p<0.01, *** p<0.001 (after correction)"},
          {"effect_size", "Hedges' g of a relative to b (Cohen's d with small-sample correction)"},
          {"seed", o.seed},
          {"min_champions_for_power", kMinBootstrapN},
          {"power_rule",
           "a comparison has power when both treatments rest on at least "
           "min_champions_for_power champions (panel B: the champions behind its pairs), the "
           "smallest n at which the 95% bootstrap interval reaches its coverage "
           "(docs/analysis.md); one without power has powered false, no stars and significant "
           "false"}};
}

Json group(const GroupStats& g) {
  Json excluded = Json::array();
  for (const Exclusion& e : g.excluded)
    excluded.push_back({{"label", e.label}, {"reason", e.reason}});
  return {{"treatment", to_string(g.treatment)},
          {"n", g.values.size()},
          {"mean", num(g.mean)},
          {"ci_low", g.ci ? num(g.ci->lower) : Json(nullptr)},
          {"ci_high", g.ci ? num(g.ci->upper) : Json(nullptr)},
          {"values", numbers(g.values)},
          {"value_labels", strings(g.value_labels)},
          {"excluded", excluded}};
}

Json comparison(const PanelStats& p, const BootstrapTestResult& t) {
  return {{"a", t.name_a},
          {"b", t.name_b},
          {"mean_diff", num(t.difference)},
          {"p", num(t.p_value)},
          {"p_corrected", num(t.p_corrected)},
          {"stars", study::stars_shown(p, t)},
          {"effect_size", num(t.effect.hedges_g)},
          {"cohens_d", num(t.effect.cohens_d)},
          {"significant", t.significant && study::has_power(p, t)},
          {"powered", study::has_power(p, t)},
          {"n_a", t.n_a},
          {"n_b", t.n_b},
          {"mean_a", num(t.mean_a)},
          {"mean_b", num(t.mean_b)},
          {"correction", t.comparisons > 1 ? "Bonferroni" : "none"},
          {"comparisons", t.comparisons},
          {"resamples", t.resamples},
          {"seed", t.seed}};
}

Json panel(const PanelStats& p) {
  Json groups = Json::array(), comps = Json::array();
  for (const GroupStats& g : p.groups) groups.push_back(group(g));
  for (const BootstrapTestResult& t : p.comparisons) comps.push_back(comparison(p, t));
  return {{"id", p.id},
          {"metric", p.metric},
          {"title", p.title},
          {"unit", p.unit},
          {"groups", groups},
          {"comparisons", comps},
          {"comparisons_made", p.comparisons.size()},
          {"correction", p.comparisons.size() > 1 ? "Bonferroni" : "none"},
          {"seed", p.seed}};
}

Json plan_features(const BodyPlanResult& b) {
  const BodyPlanFeatures& f = b.features;
  Json matches = Json::array();
  for (const PlanMatch& m : f.matches)
    matches.push_back({{"plan", to_string(m.plan)},
                       {"score", num(m.score)},
                       {"fill", num(m.fill)},
                       {"empty", num(m.empty)},
                       {"inside", num(m.inside)},
                       {"quarter_turns", m.quarter_turns},
                       {"parameters", m.parameters}});
  return {{"voxels", f.voxels},          {"extent", {f.extent[0], f.extent[1], f.extent[2]}},
          {"box_fill", num(f.box_fill)}, {"footprint_components", f.footprint_components},
          {"margin", num(b.margin)},     {"matches", matches}};
}

Json robustness(const ChampionAnalysis& c) {
  const RobustnessResult& r = c.robustness;
  Json draws = Json::array(), f_test = Json::array(), status = Json::array();
  for (const RobustnessDraw& d : r.draws) {
    draws.push_back(d.valid ? num(d.r) : Json(nullptr));
    f_test.push_back(d.valid ? num(d.f_test) : Json(nullptr));
    status.push_back(d.valid ? std::string("ok") : d.failure);
  }
  return {{"F_train", r.train_valid ? num(r.f_train) : Json(nullptr)},
          {"draws", draws},
          {"R_mean", num(c.r_mean)},
          {"train_status", r.train_valid ? std::string("ok") : r.train_failure},
          {"F_test", f_test},
          {"draw_status", status},
          {"valid_draws", r.valid_draws},
          {"distribution", r.distribution},
          {"e_lo", num(r.e_lo)},
          {"e_hi", num(r.e_hi)},
          {"seed", c.robustness_seed}};
}

Json champion(const StudyResult& r, const ChampionAnalysis& c) {
  Json undefined = Json::object();
  for (const auto& [metric, why] : c.undefined) undefined[metric] = why;
  return {{"label", c.label},
          {"file", r.inputs[c.input].file},
          {"treatment", to_string(c.treatment)},
          {"seed", c.run_seed},
          {"generation", c.generation},
          {"fitness", c.evaluation == "ok" ? num(c.fitness) : Json(nullptr)},
          {"voxels", c.voxels},
          {"status", c.status},
          {"status_detail", c.status_detail},
          {"undefined", undefined},
          {"evaluation", c.evaluation},
          {"health", c.health},
          {"life_status", c.life_status},
          {"floor_depth", num(c.floor_depth)},
          {"vertical_share", num(c.vertical_share)},
          {"vertical_exploit", c.vertical_exploit},
          {"excluded", c.artifact.empty() ? Json(nullptr) : Json(c.artifact)},
          {"champion_id", c.id},
          {"phenotype_digest", c.phenotype_digest},
          {"body_plan", to_string(c.body_plan.plan)},
          {"body_plan_confidence", num(c.body_plan.confidence)},
          {"body_plan_features", plan_features(c.body_plan)},
          {"robustness", robustness(c)},
          {"m_body", num(c.m_body)},
          {"v_body", num(c.v_body)},
          {"v_gain", num(c.v_gain)}};
}

Json pair_list(const StudyResult& r, const std::vector<std::pair<int, int>>& pairs) {
  Json a = Json::array();
  for (const auto& [i, j] : pairs)
    a.push_back({{"a", r.champions[i].label},
                 {"b", r.champions[j].label},
                 {"distance", num(r.hausdorff.at(i, j))}});
  return a;
}

Json hausdorff(const StudyResult& r) {
  const HausdorffMatrix& m = r.hausdorff;
  Json labels = Json::array(), matrix = Json::array();
  for (const ChampionAnalysis& c : r.champions) labels.push_back(c.label);
  for (int i = 0; i < m.n; ++i) {
    Json row = Json::array();
    for (int j = 0; j < m.n; ++j) row.push_back(num(m.at(i, j)));
    matrix.push_back(row);
  }
  static const char* const plans[] = {"Pi", "Gamma", "Upsilon"};
  Json shared = Json::array();
  for (const study::SharedBody& g : study::shared_seeded_bodies(r)) {
    Json members = Json::array();
    for (int i : g.champions) members.push_back(r.champions[i].label);
    shared.push_back({{"seeded_plan", plans[g.plan]}, {"labels", members}});
  }
  return {{"rotations", to_string(m.options.rotations)},
          {"translation", to_string(m.options.translation)},
          {"labels", labels},
          {"matrix", matrix},
          {"units", "voxel lengths"},
          {"most_similar", pair_list(r, study::extreme_pairs(m, 5, true))},
          {"least_similar", pair_list(r, study::extreme_pairs(m, 5, false))},
          {"shared_seeded_bodies", shared}};
}

// Per run and per treatment, one value per generation (docs/analysis.md, "evolution").
Json evolution(const StudyResult& r) {
  Json runs = Json::array(), bands = Json::array();
  for (const ChampionAnalysis& c : r.champions) {
    const EvolutionCurve& e = r.inputs[c.input].evolution;
    runs.push_back({{"label", c.label},
                    {"treatment", to_string(c.treatment)},
                    {"seed", c.run_seed},
                    {"best_fitness", numbers(e.best)},
                    {"mean_fitness", numbers(e.mean)},
                    {"lineages", e.lineages}});
  }
  for (const EvolutionBand& b : r.evolution)
    bands.push_back({{"treatment", to_string(b.treatment)},
                     {"runs", b.runs},
                     {"mean", numbers(b.mean)},
                     {"ci_low", numbers(b.ci_low)},
                     {"ci_high", numbers(b.ci_high)}});
  return {{"metric", "best fitness"},
          {"unit", "voxel lengths"},
          {"ci",
           {{"method", "percentile bootstrap of the mean over runs"},
            {"level", r.options.ci_level},
            {"resamples", std::min(r.options.resamples, 2000)}}},
          {"runs", runs},
          {"treatments", bands}};
}

// Kriegman et al. (2018)'s published comparisons beside this study's (study_paper.cpp).
Json paper_comparison(const StudyResult& r) {
  Json rows = Json::array();
  for (const study::PaperComparison& c : study::compare_with_paper(r)) {
    const ConfidenceInterval* d = c.difference ? &*c.difference : nullptr;
    rows.push_back({{"panel", c.paper.panel},
                    {"metric", c.metric},
                    {"a", to_string(c.paper.a)},
                    {"b", to_string(c.paper.b)},
                    {"paper_direction", c.paper.direction},
                    {"paper_found", study::direction_text(c.paper.a, c.paper.b, c.paper.direction)},
                    {"paper_p", c.paper.p_level},
                    {"paper_where", c.paper.where},
                    {"measured", c.measured},
                    {"n_a", c.n_a},
                    {"n_b", c.n_b},
                    {"difference", d ? num(d->mean) : Json(nullptr)},
                    {"ci_low", d ? num(d->lower) : Json(nullptr)},
                    {"ci_high", d ? num(d->upper) : Json(nullptr)},
                    {"p_corrected", c.measured ? num(c.p_corrected) : Json(nullptr)},
                    {"powered", c.powered},
                    {"significant", c.significant},
                    {"verdict", c.verdict}});
  }
  return {{"paper",
           "Kriegman, Cheney, Corucci, Bongard (2018), Interoceptive robustness through "
           "environment-mediated morphological development, GECCO: the run champions' "
           "comparisons of Fig. 5 as its Results state them (20 champions per treatment, "
           "Bonferroni-corrected for three comparisons)"},
          {"difference", "mean(b) - mean(a) with its percentile bootstrap interval"},
          {"rows", rows}};
}

}  // namespace

std::string stats_json(const StudyResult& r) {
  Json treatments = Json::array(), panels = Json::array(), champions = Json::array();
  for (Treatment t : r.treatments) treatments.push_back(to_string(t));
  for (const PanelStats& p : r.panels) panels.push_back(panel(p));
  for (const ChampionAnalysis& c : r.champions) champions.push_back(champion(r, c));
  Json ranges = Json::object();
  for (const auto& [t, a] : r.alpha_ranges)
    ranges[to_string(t)] = {{"min", num(a.min)}, {"max", num(a.max)}};
  Json counts = Json::object();
  for (const auto& [t, k] : study::body_plan_counts(r))
    counts[to_string(t)] = {{"Pi", k[0]}, {"Gamma", k[1]}, {"Upsilon", k[2]}, {"other", k[3]}};
  // The study's own warnings, then what its statistics cannot bear.
  std::vector<std::string> warnings = r.warnings;
  if (const std::string w = study::power_warning(r); !w.empty()) warnings.push_back(w);
  for (const std::string& n : study::shared_body_notes(r)) warnings.push_back(n);
  const VerticalAudit vertical = vertical_audit(r);
  const Json j = {{"format", "plastivox-analysis"},
                  {"format_version", kStudyFormatVersion},
                  {"provenance", provenance(r)},
                  {"statistics", statistics(r)},
                  {"treatments", treatments},
                  {"panels", panels},
                  {"evolution", evolution(r)},
                  {"champions", champions},
                  {"hausdorff", hausdorff(r)},
                  {"body_plans",
                   {{"counts", counts},
                    {"threshold", BodyPlanOptions{}.threshold},
                    {"runs_started_from_body_plans", study::body_plan_start_runs(r)}}},
                  {"alpha_ranges", ranges},
                  {"audit",
                   {{"sinking_rule", r.sinking_rule},
                    {"fitness_direction", r.fitness_direction},
                    {"task", r.task},
                    {"fitness_unit", r.fitness_unit},
                    {"environment", r.environment},
                    {"controller", r.controller},
                    {"keep_artifacts", r.options.keep_artifacts},
                    {"vertical_rule",
                     {{"applies", vertical.applies},
                      {"vertical_share_limit", kVerticalShareLimit},
                      {"flagged", vertical.flagged},
                      {"excluded", vertical.excluded},
                      {"keep_vertical", r.options.keep_vertical}}}}},
                  {"paper_comparison", paper_comparison(r)},
                  {"warnings", strings(warnings)}};
  if (!r.battery) return j.dump(1) + "\n";  // without a battery: what it always wrote
  Json with_battery = j;
  with_battery["robustness_battery"] = Json::parse(study::battery_block_json(r));
  return with_battery.dump(1) + "\n";
}

}  // namespace plastivox::analysis
