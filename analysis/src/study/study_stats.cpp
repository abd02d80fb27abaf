// The six panels of Fig. 5 (docs/method.md §8): per treatment a sample, its mean and 95 %
// bootstrap CI; between treatments two-sample bootstrap tests, Bonferroni-corrected for the
// number of comparisons made in the panel.
//
// Seeds: panel p (1 = A ... 6 = F) resamples with panel_seed = mix64(seed ^ mix64(p)); the CI of
// treatment t uses mix64(panel_seed + 1 + t) (t = 0 none, 1 stress, 2 pressure), the tests use
// panel_seed as pairwise_bootstrap_tests documents. So a number depends only on the seed, the
// panel, the treatment(s) and the values.
#include <algorithm>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>

#include "plastivox/analysis/rng.hpp"
#include "study_internal.hpp"

namespace plastivox::analysis::study {
namespace {

// A champion's value for a panel, or the reason it has none.
struct Value {
  std::optional<double> x;
  std::string why_not;
};
using Measure = std::function<Value(const ChampionAnalysis&)>;

struct PanelDef {
  const char *id, *metric, *title, *unit;
  bool developing_only;
  Measure measure;  // nullptr: panel B (pairs)
};

Value value_of(const std::optional<double>& x, const ChampionAnalysis& c, const char* metric) {
  if (x) return {x, ""};
  const auto it = c.undefined.find(metric);
  return {std::nullopt, it != c.undefined.end() ? it->second : std::string(metric) + " undefined"};
}

std::vector<PanelDef> panel_defs() {
  return {
      {"A", "fitness", "Fitness", "voxel lengths", false,
       [](const ChampionAnalysis& c) {
         return value_of(c.evaluation == "ok" ? std::optional<double>(c.fitness) : std::nullopt, c,
                         "fitness");
       }},
      {"B", "diversity", "Diversity", "Hausdorff distance (voxel lengths)", false, nullptr},
      {"C", "robustness", "Robustness", "F_test / F_train", false,
       [](const ChampionAnalysis& c) { return value_of(c.r_mean, c, "robustness"); }},
      {"D", "m_body", "M_body", "mean |E+/E0 - 1|", true,
       [](const ChampionAnalysis& c) { return value_of(c.m_body, c, "m_body"); }},
      {"E", "v_body", "V_body", "var |E+/E0 - 1|", true,
       [](const ChampionAnalysis& c) { return value_of(c.v_body, c, "v_body"); }},
      {"F", "v_gain", "V_gain", "var of normalised alpha", true,
       [](const ChampionAnalysis& c) { return value_of(c.v_gain, c, "v_gain"); }},
  };
}

GroupStats group_values(const StudyResult& r, const PanelDef& def, Treatment t) {
  GroupStats g;
  g.treatment = t;
  const int n = static_cast<int>(r.champions.size());
  if (!def.measure) {  // panel B: every within-treatment pair
    for (int i = 0; i < n; ++i)
      for (int j = i + 1; j < n; ++j)
        if (r.champions[i].treatment == t && r.champions[j].treatment == t &&
            r.champions[i].artifact.empty() && r.champions[j].artifact.empty()) {
          g.values.push_back(r.hausdorff.at(i, j));
          g.value_labels.push_back(r.champions[i].label + "|" + r.champions[j].label);
        }
    return g;
  }
  for (const ChampionAnalysis& c : r.champions) {
    if (c.treatment != t) continue;
    if (!c.artifact.empty()) {  // an unstable or sunk life: left out of every panel
      g.excluded.push_back({c.label, "excluded as an artifact: " + c.artifact});
      continue;
    }
    const Value v = def.measure(c);
    if (v.x) {
      g.values.push_back(*v.x);
      g.value_labels.push_back(c.label);
    } else {
      g.excluded.push_back({c.label, v.why_not});
    }
  }
  return g;
}

}  // namespace

void add_group(PanelStats& p, GroupStats g, const StudyOptions& o,
               std::vector<NamedSample>& samples) {
  if (!g.values.empty()) g.mean = mean(g.values);
  if (g.values.size() >= 2) {
    g.ci = bootstrap_mean_ci(g.values, o.ci_level, o.resamples, group_ci_seed(p.seed, g.treatment));
    samples.push_back({to_string(g.treatment), g.values});
  }
  p.groups.push_back(std::move(g));
}

void compare_groups(PanelStats& p, const std::vector<NamedSample>& samples, const StudyOptions& o) {
  if (samples.size() < 2) return;
  BootstrapTestOptions bo;
  bo.resamples = o.resamples;
  bo.seed = p.seed;
  bo.level = o.alpha;
  p.comparisons = pairwise_bootstrap_tests(samples, bo);
  // Too few champions to resolve anything (study_power.cpp): p is kept, the verdict is not.
  for (BootstrapTestResult& t : p.comparisons)
    if (!study::has_power(p, t)) {
      t.stars.clear();
      t.significant = false;
    }
}

std::vector<PanelStats> compute_panels(const StudyResult& r) {
  const StudyOptions& o = r.options;
  std::vector<PanelStats> panels;
  int number = 0;
  for (const PanelDef& def : panel_defs()) {
    PanelStats p;
    p.id = def.id;
    p.metric = def.metric;
    p.title = def.title;
    // Fitness is in the runs' task's unit (voxel lengths under walk; docs/tasks.md).
    p.unit = def.metric == std::string("fitness") ? r.fitness_unit : def.unit;
    p.seed = panel_seed(o.seed, ++number);
    std::vector<NamedSample> samples;
    for (Treatment t : r.treatments) {
      if (def.developing_only && t == Treatment::kNone) continue;
      add_group(p, group_values(r, def, t), o, samples);
    }
    compare_groups(p, samples, o);
    panels.push_back(std::move(p));
  }
  return panels;
}

std::vector<EvolutionBand> compute_evolution(const StudyResult& r) {
  const StudyOptions& o = r.options;
  // Seeds: generation g of treatment t resamples with mix64(evolution_seed + 1000003 * t + g),
  // evolution_seed = mix64(seed ^ mix64(100)), apart from the panels' (which use 1..6).
  const uint64_t evolution_seed = mix64(o.seed ^ mix64(100));
  std::vector<EvolutionBand> bands;
  for (Treatment t : r.treatments) {
    EvolutionBand b;
    b.treatment = t;
    std::vector<const EvolutionCurve*> curves;
    size_t length = SIZE_MAX;
    for (const ChampionAnalysis& c : r.champions)
      if (c.treatment == t && c.artifact.empty()) {  // runs won by an artifact are left out
        const StudyInput& in = r.inputs[c.input];
        curves.push_back(&in.evolution);
        length = std::min(length, in.evolution.best.size());
      }
    b.runs = static_cast<int>(curves.size());
    if (curves.empty()) length = 0;
    for (size_t g = 0; g < length; ++g) {
      std::vector<double> x;
      for (const EvolutionCurve* c : curves) x.push_back(c->best[g]);
      const double m = mean(x);
      b.mean.push_back(m);
      if (x.size() >= 2) {
        const ConfidenceInterval ci =
            bootstrap_mean_ci(x, o.ci_level, std::min(o.resamples, 2000),
                              mix64(evolution_seed + 1000003 * static_cast<uint64_t>(t) + g));
        b.ci_low.push_back(ci.lower);
        b.ci_high.push_back(ci.upper);
      } else {
        b.ci_low.push_back(m);
        b.ci_high.push_back(m);
      }
    }
    bands.push_back(std::move(b));
  }
  return bands;
}

std::vector<std::pair<int, int>> extreme_pairs(const HausdorffMatrix& m, size_t k,
                                               bool most_similar) {
  std::vector<std::pair<int, int>> pairs;
  for (int i = 0; i < m.n; ++i)
    for (int j = i + 1; j < m.n; ++j) pairs.push_back({i, j});
  std::stable_sort(pairs.begin(), pairs.end(), [&](const auto& a, const auto& b) {
    const double da = m.at(a.first, a.second), db = m.at(b.first, b.second);
    return most_similar ? da < db : da > db;
  });
  pairs.resize(std::min(k, pairs.size()));
  return pairs;
}

int body_plan_start_runs(const StudyResult& r) {
  int n = 0;
  for (const StudyInput& in : r.inputs) n += in.body_plan_start ? 1 : 0;
  return n;
}

std::vector<SharedBody> shared_seeded_bodies(const StudyResult& r) {
  std::vector<SharedBody> groups;
  std::vector<bool> placed(r.champions.size(), false);
  const auto same_body = [](const RobotDef& a, const RobotDef& b) {
    return a.nx == b.nx && a.ny == b.ny && a.nz == b.nz && a.present == b.present;
  };
  for (size_t i = 0; i < r.champions.size(); ++i) {
    const ChampionAnalysis& c = r.champions[i];
    if (placed[i] || c.seeded_plan < 0 || c.robot.present.empty()) continue;
    SharedBody g;
    g.plan = c.seeded_plan;
    g.champions.push_back(static_cast<int>(i));
    for (size_t j = i + 1; j < r.champions.size(); ++j) {
      const ChampionAnalysis& d = r.champions[j];
      if (!placed[j] && d.seeded_plan == c.seeded_plan && same_body(c.robot, d.robot)) {
        g.champions.push_back(static_cast<int>(j));
        placed[j] = true;
      }
    }
    if (g.champions.size() >= 2) groups.push_back(std::move(g));
  }
  return groups;
}

std::vector<std::string> shared_body_notes(const StudyResult& r) {
  static const char* const plans[] = {"Π", "Γ", "Υ"};
  std::vector<std::string> notes;
  for (const SharedBody& g : shared_seeded_bodies(r)) {
    std::string labels;
    for (int i : g.champions) labels += (labels.empty() ? "" : ", ") + r.champions[i].label;
    notes.push_back(std::to_string(g.champions.size()) + " champions (" + labels +
                    ") share one body, descended from the hand-built " + plans[g.plan] +
                    " that generation 0 held: the same filled voxels, Hausdorff distance 0. "
                    "Evolution changed their materials and actuation, not their shape, so "
                    "their distances measure the seed, not diversity that evolved");
  }
  return notes;
}

std::map<Treatment, std::array<int, 4>> body_plan_counts(const StudyResult& r) {
  std::map<Treatment, std::array<int, 4>> counts;
  for (Treatment t : r.treatments) counts[t] = {0, 0, 0, 0};
  for (const ChampionAnalysis& c : r.champions)
    if (c.artifact.empty()) ++counts[c.treatment][static_cast<int>(c.body_plan.plan)];
  return counts;
}

}  // namespace plastivox::analysis::study

namespace plastivox::analysis {

uint64_t panel_seed(uint64_t seed, int panel) {
  return mix64(seed ^ mix64(static_cast<uint64_t>(panel)));
}

uint64_t group_ci_seed(uint64_t panel_seed, Treatment t) {
  return mix64(panel_seed + 1 + static_cast<uint64_t>(t));
}

}  // namespace plastivox::analysis
