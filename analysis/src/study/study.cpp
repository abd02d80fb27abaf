// analyze_study: load, measure, compare (see plastivox/analysis/study.hpp). Each step is a
// named stage, timed; the expensive one (robustness) lives in study_robustness.cpp.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <initializer_list>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "plastivox/base/clock.hpp"
#include "plastivox/base/hash.hpp"
#include "plastivox/evo/results_file.hpp"
#include "study_internal.hpp"

namespace plastivox::analysis {
namespace {

using Clock = WallClock;

// Records why `metrics` have no value, and the champion's status.
void note(ChampionAnalysis& c, const std::string& code, const std::string& why,
          std::initializer_list<const char*> metrics) {
  for (const char* m : metrics) c.undefined[m] = why;
  if (c.status == "ok") c.status = code;
  c.status_detail += (c.status_detail.empty() ? "" : "; ") + why;
}

// Panels D, E, F: M_body and V_body from congenital vs final stiffness; V_gain from alpha
// normalised over the range that evolved in the champion's treatment.
void measure_canalization(StudyResult& r) {
  std::map<Treatment, std::vector<std::vector<double>>> alphas;
  for (const ChampionAnalysis& c : r.champions)
    if (c.treatment != Treatment::kNone)
      alphas[c.treatment].push_back(body_values(c.robot, c.robot.dev_rate));
  for (const auto& [t, a] : alphas) r.alpha_ranges[t] = evolved_alpha_range(a);

  for (ChampionAnalysis& c : r.champions) {
    if (c.evaluation == "ok") {
      try {
        const Canalization k = canalization(body_values(c.robot, c.robot.stiffness),
                                            body_values(c.robot, c.final_stiffness));
        c.m_body = k.m_body;
        c.v_body = k.v_body;
      } catch (const std::exception& e) {
        note(c, "canalization-undefined", std::string("canalization: ") + e.what(),
             {"m_body", "v_body"});
      }
    }
    if (c.treatment == Treatment::kNone) {  // no development: V_gain has no range
      c.undefined["v_gain"] = "no development under treatment none";
      continue;
    }
    const AlphaRange range = r.alpha_ranges.at(c.treatment);
    if (range.max > range.min)
      c.v_gain = v_gain(body_values(c.robot, c.robot.dev_rate), range);
    else
      note(c, "v-gain-undefined",
           std::string("V_gain: every alpha of treatment ") + to_string(c.treatment) +
               " is the same, so it cannot be normalised",
           {"v_gain"});
  }
}

void report(const StudyProgressFn& progress, const std::string& stage, int done, int total,
            const std::string& message) {
  if (progress) progress({stage, done, total, message});
}

}  // namespace

std::string options_json(const StudyOptions& o) {
  nlohmann::ordered_json j;
  if (o.generation < 0)
    j["generation"] = "last";
  else
    j["generation"] = o.generation;
  j["robustness_draws"] = o.robustness_draws;
  j["robustness_sampling"] =
      o.robustness_sampling == StiffnessDistribution::kLinear ? "linear" : "log";
  j["rotations"] = to_string(o.rotations);
  j["translation"] = to_string(o.translation);
  j["resamples"] = o.resamples;
  j["seed"] = o.seed;
  j["alpha"] = o.alpha;
  j["ci_level"] = o.ci_level;
  j["allow_mixed_physics"] = o.allow_mixed_physics;
  j["keep_artifacts"] = o.keep_artifacts;
  j["keep_vertical"] = o.keep_vertical;
  nlohmann::ordered_json ts = nlohmann::ordered_json::array();
  for (Treatment t : o.treatments) ts.push_back(to_string(t));
  j["treatments"] = ts;
  if (!o.battery.empty()) j["battery"] = o.battery;  // absent without one: the same options
  return j.dump();
}

std::string study_fingerprint(const std::vector<std::string>& content_digests,
                              const StudyOptions& options) {
  std::vector<std::string> sorted = content_digests;
  std::sort(sorted.begin(), sorted.end());
  Hasher h;
  // The tag changes whenever the outputs gain or change a field, so a study analysed by an
  // older build is analysed again rather than reused without it (v3: audit.controller; v4:
  // the vertical rule).
  h.str("plastivox-analysis-fingerprint-v4");
  h.u64(static_cast<uint64_t>(kStudyFormatVersion));
  h.u64(sorted.size());
  for (const std::string& d : sorted) h.str(d);
  h.str(options_json(options));
  // A battery file's content, not only its name: an edited battery is analysed again.
  if (!options.battery.empty())
    h.str(battery_json(load_battery(options.battery, options.robustness_draws)));
  return h.finish().hex();
}

StudyResult analyze_study(const std::vector<std::string>& files, const StudyOptions& options,
                          const StudyProgressFn& progress) {
  if (options.robustness_draws < 1) throw std::invalid_argument("robustness draws must be >= 1");
  if (options.resamples < 2) throw std::invalid_argument("bootstrap resamples must be >= 2");
  if (!(options.alpha > 0 && options.alpha < 1) || !(options.ci_level > 0 && options.ci_level < 1))
    throw std::invalid_argument("alpha and ci_level must lie in (0, 1)");
  const auto start = Clock::now();
  StudyResult r;
  r.options = options;
  // A battery is read and checked before any results file is read or life simulated.
  if (!options.battery.empty()) r.battery = load_battery(options.battery, options.robustness_draws);

  auto t0 = Clock::now();
  study::load_champions(files, options, r);
  r.timings.load = seconds_since(t0);
  const int n = static_cast<int>(r.champions.size());
  {
    std::string counts;
    for (Treatment t : r.treatments) {
      const auto k = std::count_if(r.champions.begin(), r.champions.end(),
                                   [&](const ChampionAnalysis& c) { return c.treatment == t; });
      counts += (counts.empty() ? "" : ", ") + std::string(to_string(t)) + " " + std::to_string(k);
    }
    report(progress, "load", n, n,
           "load: " + std::to_string(n) + (n == 1 ? " champion (" : " champions (") + counts + ")");
    for (const std::string& w : r.warnings) report(progress, "load", n, n, "warning: " + w);
  }
  std::vector<std::string> digests;
  for (const StudyInput& in : r.inputs) digests.push_back(in.content_digest);
  r.fingerprint = study_fingerprint(digests, options);
  const Provenance prov = current_provenance(options.threads);
  r.version = prov.plastivox_version;
  r.commit = prov.git_commit;
  r.date = prov.date_created;

  study::audit_champions(r, progress);

  t0 = Clock::now();
  study::run_robustness(r, progress);
  study::run_battery(r, progress);
  r.timings.robustness = seconds_since(t0);

  t0 = Clock::now();
  measure_canalization(r);
  r.timings.canalization = seconds_since(t0);

  t0 = Clock::now();
  for (ChampionAnalysis& c : r.champions) c.body_plan = classify_body_plan(voxel_set(c.robot));
  r.timings.body_plans = seconds_since(t0);

  t0 = Clock::now();
  std::vector<VoxelSet> sets;
  for (const ChampionAnalysis& c : r.champions) sets.push_back(voxel_set(c.robot));
  HausdorffOptions ho;
  ho.rotations = options.rotations;
  ho.translation = options.translation;
  r.hausdorff = hausdorff_matrix(sets, ho, options.threads);
  r.timings.hausdorff = seconds_since(t0);
  {
    char buf[128];
    std::snprintf(buf, sizeof buf, "hausdorff: %d pairs, rotations %s, translation %s, %.2f s",
                  n * (n - 1) / 2, to_string(options.rotations), to_string(options.translation),
                  r.timings.hausdorff);
    report(progress, "hausdorff", 1, 1, buf);
  }

  t0 = Clock::now();
  r.panels = study::compute_panels(r);
  r.battery_panels = study::compute_battery_panels(r);
  r.evolution = study::compute_evolution(r);
  r.timings.statistics = seconds_since(t0);
  {
    char buf[128];
    std::snprintf(buf, sizeof buf, "statistics: %zu panels, %d resamples, %.2f s", r.panels.size(),
                  options.resamples, r.timings.statistics);
    report(progress, "statistics", 1, 1, buf);
  }
  r.timings.total = seconds_since(start);
  return r;
}

}  // namespace plastivox::analysis
