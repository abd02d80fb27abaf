// The robustness battery in a study (battery.hpp; docs/analysis.md, "Robustness battery"):
// every champion's profile, champions in parallel with each champion's lives on the spare
// threads (as run_robustness splits them), and per perturbation the treatments' AUC compared as
// a Fig. 5 panel: means with percentile bootstrap CIs, Bonferroni-corrected bootstrap tests.
//
// Seeds: a champion's lives draw from its robustness seed (champion_robustness_seed), so its
// `paper` lives are R's draws; perturbation i's panel resamples with panel_seed(seed, 100 + i),
// apart from Fig. 5's panels (1..6) and the evolution bands (100 is mixed differently).
#include <chrono>
#include <cstdio>
#include <mutex>
#include <sstream>

#include <nlohmann/json.hpp>

#include "plastivox/base/clock.hpp"
#include "plastivox/base/parallel.hpp"
#include "plastivox/io/limits.hpp"
#include "plastivox/io/provenance.hpp"
#include "plastivox/model.hpp"
#include "plastivox/simulator.hpp"
#include "study_internal.hpp"

namespace plastivox::analysis {
namespace study {

void run_battery(StudyResult& r, const StudyProgressFn& progress) {
  if (!r.battery) return;
  const Battery& battery = *r.battery;
  std::vector<int> todo;
  for (int i = 0; i < static_cast<int>(r.champions.size()); ++i)
    if (r.champions[i].artifact.empty()) todo.push_back(i);
  if (todo.empty()) return;
  const int per = battery_lives(battery);
  const int threads = r.options.threads > 0 ? r.options.threads : hardware_threads();
  const int outer = std::min(threads, static_cast<int>(todo.size()));
  const int inner = std::max(1, threads / outer);
  std::mutex mutex;
  int done = 0;
  parallel_for(todo.size(), outer, [&](size_t k) {
    if (r.options.stop_requested && r.options.stop_requested->load())
      throw StudyStopped("stopped on request during the robustness battery");
    ChampionAnalysis& c = r.champions[todo[k]];
    ProfileOptions o;
    o.seed = champion_robustness_seed(r.options.seed, c.robot);
    o.threads = inner;
    o.limits = limits_from_environment();
    const auto t0 = std::chrono::steady_clock::now();
    c.profile = robustness_profile(c.robot, c.physics, battery, o);
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::lock_guard<std::mutex> lock(mutex);
    ++done;
    r.battery_lives += c.profile->lives;
    r.battery_unstable += c.profile->unstable;
    r.battery_sank += c.profile->sank;
    char buf[160];
    std::snprintf(buf, sizeof buf, "battery %d/%zu %s: %d lives (%d unstable, %d sank), %.1f s",
                  done, todo.size(), c.label.c_str(), per, c.profile->unstable, c.profile->sank, s);
    if (progress) progress({"battery", done, static_cast<int>(todo.size()), buf});
  });
}

std::vector<PanelStats> compute_battery_panels(const StudyResult& r) {
  std::vector<PanelStats> panels;
  if (!r.battery) return panels;
  const StudyOptions& o = r.options;
  for (size_t i = 0; i < r.battery->perturbations.size(); ++i) {
    const Perturbation& pert = r.battery->perturbations[i];
    PanelStats p;
    p.id = "P" + std::to_string(i + 1);
    p.metric = "battery:" + pert.name;
    p.title = pert.name;
    p.unit = "fitness kept, area under the curve / severity span";
    p.seed = panel_seed(o.seed, 100 + static_cast<int>(i));
    std::vector<NamedSample> samples;
    for (Treatment t : r.treatments) {
      GroupStats g;
      g.treatment = t;
      for (const ChampionAnalysis& c : r.champions) {
        if (c.treatment != t) continue;
        if (!c.artifact.empty() || !c.profile) {
          g.excluded.push_back({c.label, "excluded as an artifact: " + c.artifact});
          continue;
        }
        const PerturbationProfile& pp = c.profile->perturbations[i];
        if (pp.auc) {
          g.values.push_back(*pp.auc);
          g.value_labels.push_back(c.label);
        } else {
          g.excluded.push_back({c.label, pp.reference_valid
                                             ? "a severity with no valid life (all unstable "
                                               "or sank): AUC undefined"
                                             : pp.reference_failure});
        }
      }
      add_group(p, std::move(g), o, samples);
    }
    compare_groups(p, samples, o);
    panels.push_back(std::move(p));
  }
  return panels;
}

namespace {

using Json = nlohmann::ordered_json;

Json optional_number(const std::optional<double>& x) {
  return x ? Json(*x) : Json(nullptr);
}

Json profile_json(const RobustnessProfile& prof) {
  Json ps = Json::array();
  for (const PerturbationProfile& p : prof.perturbations) {
    Json levels = Json::array();
    for (const SeverityLevel& l : p.levels) {
      Json kept = Json::array(), fitness = Json::array(), status = Json::array();
      for (const LifeOutcome& o : l.lives) {
        kept.push_back(o.valid ? Json(o.kept) : Json(nullptr));
        fitness.push_back(o.status == "ok" || o.status == "no-reference" ? Json(o.fitness)
                                                                         : Json(nullptr));
        status.push_back(o.status);
      }
      levels.push_back({{"severity", l.severity},
                        {"seeds", l.seeds},
                        {"kept", kept},
                        {"fitness", fitness},
                        {"status", status},
                        {"valid", l.valid},
                        {"unstable", l.unstable},
                        {"sank", l.sank},
                        {"mean_kept", optional_number(l.mean_kept)},
                        {"sd_kept", optional_number(l.sd_kept)}});
    }
    ps.push_back({{"name", p.name},
                  {"kind", to_string(p.kind)},
                  {"severity_unit", p.unit},
                  {"f_reference", p.f_reference},
                  {"reference_valid", p.reference_valid},
                  {"reference_failure", p.reference_failure},
                  {"auc", optional_number(p.auc)},
                  {"levels", levels}});
  }
  return {{"seed", prof.seed},
          {"lives", prof.lives},
          {"unstable", prof.unstable},
          {"sank", prof.sank},
          {"perturbations", ps}};
}

Json panel_json(const PanelStats& p) {
  Json groups = Json::array();
  for (const GroupStats& g : p.groups) {
    Json ex = Json::array();
    for (const Exclusion& e : g.excluded) ex.push_back({{"champion", e.label}, {"why", e.reason}});
    groups.push_back({{"treatment", to_string(g.treatment)},
                      {"n", g.values.size()},
                      {"mean", optional_number(g.mean)},
                      {"ci_low", g.ci ? Json(g.ci->lower) : Json(nullptr)},
                      {"ci_high", g.ci ? Json(g.ci->upper) : Json(nullptr)},
                      {"values", g.values},
                      {"champions", g.value_labels},
                      {"excluded", ex}});
  }
  Json tests = Json::array();
  for (const BootstrapTestResult& t : p.comparisons)
    tests.push_back({{"a", t.name_a},
                     {"b", t.name_b},
                     {"difference", t.difference},
                     {"p", t.p_value},
                     {"p_corrected", t.p_corrected},
                     {"significant", t.significant},
                     {"stars", stars_shown(p, t)}});
  return {{"id", p.id},     {"metric", p.metric}, {"perturbation", p.title}, {"unit", p.unit},
          {"seed", p.seed}, {"groups", groups},   {"comparisons", tests}};
}

}  // namespace

// The battery's block of stats.json (and robustness.json's body).
std::string battery_block_json(const StudyResult& r) {
  if (!r.battery) return "null";
  Json champions = Json::array();
  for (const ChampionAnalysis& c : r.champions) {
    Json j = {{"label", c.label}, {"treatment", to_string(c.treatment)}};
    if (c.profile)
      j["profile"] = profile_json(*c.profile);
    else
      j["excluded"] = c.artifact;
    champions.push_back(j);
  }
  Json panels = Json::array();
  for (const PanelStats& p : r.battery_panels) panels.push_back(panel_json(p));
  const Json j = {{"battery", Json::parse(battery_json(*r.battery))},
                  {"name", r.battery->name},
                  {"units",
                   {{"kept", "F_perturbed / F_reference (dimensionless)"},
                    {"fitness", r.fitness_unit},
                    {"auc", "fitness kept, area under the curve / severity span"}}},
                  {"champions", champions},
                  {"comparisons", panels}};
  return j.dump();
}

}  // namespace study

StudyResult battery_study(const std::vector<std::string>& files, const StudyOptions& options,
                          const StudyProgressFn& progress) {
  if (options.battery.empty()) throw std::invalid_argument("battery_study: no battery given");
  if (options.resamples < 2) throw std::invalid_argument("bootstrap resamples must be >= 2");
  StudyResult r;
  r.options = options;
  r.battery = load_battery(options.battery, options.robustness_draws);  // before any life
  study::load_champions(files, options, r);
  const Provenance prov = current_provenance(options.threads);
  r.version = prov.plastivox_version;
  r.commit = prov.git_commit;
  r.date = prov.date_created;
  study::audit_champions(r, progress);
  study::run_battery(r, progress);
  r.battery_panels = study::compute_battery_panels(r);
  return r;
}

StudyResult battery_study_of_robots(const std::vector<std::string>& labels,
                                    const std::vector<RobotDef>& robots,
                                    const std::vector<PhysicsDef>& physics,
                                    const StudyOptions& options, const StudyProgressFn& progress) {
  if (options.battery.empty()) throw std::invalid_argument("battery_study: no battery given");
  if (labels.size() != robots.size() || physics.size() != robots.size())
    throw std::invalid_argument("battery_study_of_robots: one label and physics per robot");
  StudyResult r;
  r.options = options;
  r.battery = load_battery(options.battery, options.robustness_draws);
  for (size_t i = 0; i < robots.size(); ++i) {
    ChampionAnalysis c;
    c.label = labels[i];
    c.robot = robots[i];
    c.physics = physics[i];
    c.treatment = physics[i].treatment;
    c.voxels = robots[i].voxel_count();
    r.champions.push_back(std::move(c));
  }
  for (Treatment t : all_treatments())
    for (const ChampionAnalysis& c : r.champions)
      if (c.treatment == t) {
        r.treatments.push_back(t);
        break;
      }
  const Provenance prov = current_provenance(options.threads);
  r.version = prov.plastivox_version;
  r.commit = prov.git_commit;
  r.date = prov.date_created;
  study::run_battery(r, progress);
  r.battery_panels = study::compute_battery_panels(r);
  return r;
}

BatteryEstimate estimate_battery(const std::vector<std::string>& files,
                                 const StudyOptions& options) {
  if (options.battery.empty()) throw std::invalid_argument("estimate_battery: no battery given");
  StudyResult r;
  r.options = options;
  const Battery battery = load_battery(options.battery, options.robustness_draws);
  study::load_champions(files, options, r);
  BatteryEstimate e;
  e.champions = static_cast<int>(r.champions.size());
  e.lives = e.champions * battery_lives(battery);
  e.threads = options.threads > 0 ? options.threads : hardware_threads();
  for (const ChampionAnalysis& c : r.champions)
    e.voxel_steps += battery_voxel_steps(c.robot, c.physics, battery,
                                         champion_robustness_seed(options.seed, c.robot));
  if (r.champions.empty()) return e;
  const ChampionAnalysis& first = r.champions.front();
  const auto t0 = std::chrono::steady_clock::now();
  simulate(compile(first.robot, first.physics, limits_from_environment()));  // timed, not judged
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  Battery one;
  one.name = "one life";
  one.perturbations = {{"gravity", PerturbationKind::kGravity, {1.0}, {0}}};
  // A battery of one unperturbed-gravity life costs the reference plus that life: half is one.
  const double units = battery_voxel_steps(first.robot, first.physics, one, 0) / 2;
  e.seconds_per_voxel_step = units > 0 ? s / units : 0;
  e.seconds = e.voxel_steps * e.seconds_per_voxel_step / std::min(e.threads, std::max(1, e.lives));
  return e;
}

std::string battery_stats_json(const StudyResult& r) {
  nlohmann::ordered_json j = nlohmann::ordered_json::parse(study::battery_block_json(r));
  nlohmann::ordered_json out = {{"format", "plastivox-robustness"},
                                {"version", 1},
                                {"plastivox_version", r.version},
                                {"seed", r.options.seed}};
  for (auto& [k, v] : j.items()) out[k] = v;
  return out.dump(1) + "\n";
}

std::string battery_csv(const StudyResult& r) {
  std::ostringstream out;
  out << "champion,treatment,perturbation,kind,severity,severity_unit,lives,valid,unstable,sank,"
         "mean_kept,sd_kept,auc\n";
  for (const ChampionAnalysis& c : r.champions) {
    if (!c.profile) continue;
    for (const PerturbationProfile& p : c.profile->perturbations)
      for (const SeverityLevel& l : p.levels)
        out << c.label << ',' << to_string(c.treatment) << ',' << p.name << ',' << to_string(p.kind)
            << ',' << study::number(l.severity) << ",\"" << p.unit << "\"," << l.lives.size() << ','
            << l.valid << ',' << l.unstable << ',' << l.sank << ',' << study::number(l.mean_kept)
            << ',' << study::number(l.sd_kept) << ',' << study::number(p.auc) << '\n';
  }
  return out.str();
}

}  // namespace plastivox::analysis
