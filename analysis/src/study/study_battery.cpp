// The robustness battery in a study (battery.hpp; docs/analysis.md, "Robustness battery"):
// every champion's profile, the lives of a round of champions in one pool (this process's
// threads, or MPI ranks through StudyOptions::battery_lives), each champion checkpointed when
// its round is back (a rerun reads it, bit for bit); and per perturbation the treatments' AUC
// compared as a Fig. 5 panel: means with percentile bootstrap CIs, Bonferroni-corrected tests.
//
// Seeds: a champion's lives draw from its robustness seed (champion_robustness_seed), so its
// `paper` lives are R's draws; perturbation i's panel resamples with panel_seed(seed, 100 + i),
// apart from Fig. 5's panels (1..6) and the evolution bands (100 is mixed differently).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "plastivox/base/clock.hpp"
#include "plastivox/base/hash.hpp"
#include "plastivox/base/parallel.hpp"
#include "plastivox/evo/config.hpp"  // resolved_physics_json
#include "plastivox/io/limits.hpp"
#include "plastivox/io/provenance.hpp"
#include "plastivox/model.hpp"
#include "plastivox/simulator.hpp"
#include "study_internal.hpp"

namespace plastivox::analysis {
namespace study {

namespace {

using Json = nlohmann::ordered_json;

// A champion's battery checkpoint: <cache_dir>/battery-<key>.json holds every life's outcome
// (fitness as its 64 bits), from which assemble_profile makes the profile again bit for bit.
// The key hashes all the outcomes depend on: the robot, its physics, the battery and the seed.
std::string checkpoint_key(const ChampionAnalysis& c, const Battery& b, uint64_t seed) {
  Hasher h;
  h.str("plastivox-battery-checkpoint-v1");
  h.str(c.phenotype_digest.empty() ? phenotype_digest(c.robot) : c.phenotype_digest);
  h.str(evo::resolved_physics_json(c.physics));
  h.str(battery_json(b));
  h.u64(seed);
  return h.finish().hex();
}

std::string checkpoint_path(const std::string& dir, const std::string& key) {
  return (std::filesystem::path(dir) / ("battery-" + key + ".json")).string();
}

std::string checkpoint_text(const std::string& key, const std::string& label,
                            const std::vector<BatteryRun>& runs) {
  Json lives = Json::array();
  for (const BatteryRun& l : runs)
    lives.push_back({{"fitness", bits(l.fitness)}, {"status", l.status}, {"failure", l.failure}});
  const Json j = {{"format", "plastivox-battery-checkpoint"},
                  {"version", 1},
                  {"key", key},
                  {"label", label},
                  {"lives", lives}};
  return j.dump(1) + "\n";
}

// The outcomes, or nothing when the file is absent, unreadable, for another key or of another
// length.
std::optional<std::vector<BatteryRun>> read_checkpoint(const std::string& path,
                                                       const std::string& key, size_t lives) {
  const std::optional<Json> read = read_checkpoint_json(path, "plastivox-battery-checkpoint", key);
  if (!read) return std::nullopt;
  const Json& j = *read;
  try {
    if (j.at("lives").size() != lives) return std::nullopt;
    std::vector<BatteryRun> runs;
    for (const Json& l : j.at("lives")) {
      BatteryRun x;
      x.fitness = from_bits(l.at("fitness").get<std::string>());
      x.status = l.at("status").get<std::string>();
      x.failure = l.at("failure").get<std::string>();
      if (x.status != "ok" && x.status != "unstable" && x.status != "sank") return std::nullopt;
      runs.push_back(x);
    }
    return runs;
  } catch (const std::exception&) {
    return std::nullopt;
  }
}

// This process's pool: every life of the round on `threads`, the longest first.
std::vector<BatteryRun> lives_on_threads(const std::vector<PerturbedLife>& lives, int threads,
                                         const Limits& limits) {
  std::vector<size_t> order(lives.size());
  std::vector<double> cost(lives.size());
  for (size_t i = 0; i < lives.size(); ++i) {
    order[i] = i;
    cost[i] = life_voxel_steps(lives[i]);
  }
  std::stable_sort(order.begin(), order.end(),
                   [&](size_t a, size_t b) { return cost[a] > cost[b]; });
  std::vector<BatteryRun> runs(lives.size());
  parallel_for(order.size(), threads,
               [&](size_t k) { runs[order[k]] = run_battery_life(lives[order[k]], limits); });
  return runs;
}

}  // namespace

void run_battery(StudyResult& r, const StudyProgressFn& progress) {
  if (!r.battery) return;
  const Battery& battery = *r.battery;
  const StudyOptions& o = r.options;
  const Limits limits = limits_from_environment();
  std::vector<int> todo;
  std::vector<std::string> keys(r.champions.size());
  int done = 0, from_cache = 0;
  const int total =
      static_cast<int>(std::count_if(r.champions.begin(), r.champions.end(),
                                     [](const ChampionAnalysis& c) { return c.artifact.empty(); }));
  auto finish = [&](ChampionAnalysis& c, const std::vector<BatteryRun>& runs, const char* how) {
    c.profile = assemble_profile(battery, champion_robustness_seed(o.seed, c.robot), runs);
    ++done;
    r.battery_lives += c.profile->lives;
    r.battery_unstable += c.profile->unstable;
    r.battery_sank += c.profile->sank;
    char buf[200];
    std::snprintf(buf, sizeof buf, "battery %d/%d %s: %d lives (%d unstable, %d sank)%s", done,
                  total, c.label.c_str(), c.profile->lives, c.profile->unstable, c.profile->sank,
                  how);
    if (progress) progress({"battery", done, total, buf});
  };
  // What an earlier, interrupted analysis finished is read back, not simulated again.
  for (int i = 0; i < static_cast<int>(r.champions.size()); ++i) {
    ChampionAnalysis& c = r.champions[i];
    if (!c.artifact.empty()) continue;
    keys[i] = checkpoint_key(c, battery, o.seed);
    std::optional<std::vector<BatteryRun>> cached;
    if (!o.cache_dir.empty())
      cached = read_checkpoint(checkpoint_path(o.cache_dir, keys[i]), keys[i],
                               static_cast<size_t>(battery_lives(battery)));
    if (!cached) {
      todo.push_back(i);
      continue;
    }
    ++from_cache;
    finish(c, *cached, " (from checkpoint)");
  }
  r.battery_cached = from_cache;
  if (todo.empty()) return;
  if (!o.cache_dir.empty() && o.write_cache) std::filesystem::create_directories(o.cache_dir);

  // Rounds of as many champions as there are threads: every life of a round goes into one pool
  // (on this process's threads, or over MPI ranks through options.battery_lives), and each
  // champion of the round is checkpointed once the round is back.
  const int threads = o.threads > 0 ? o.threads : hardware_threads();
  const size_t per_round = static_cast<size_t>(std::max(1, threads));
  for (size_t first = 0; first < todo.size(); first += per_round) {
    if (o.stop_requested && o.stop_requested->load())
      throw StudyStopped("stopped on request with " + std::to_string(done) + " of " +
                         std::to_string(total) + " champions' battery done and checkpointed");
    const size_t last = std::min(todo.size(), first + per_round);
    std::vector<PerturbedLife> lives;
    std::vector<size_t> start;  // where each champion's lives begin in `lives`
    for (size_t k = first; k < last; ++k) {
      const ChampionAnalysis& c = r.champions[todo[k]];
      start.push_back(lives.size());
      for (PerturbedLife& l : battery_lives_of(c.robot, c.physics, battery,
                                               champion_robustness_seed(o.seed, c.robot), limits))
        lives.push_back(std::move(l));
    }
    start.push_back(lives.size());
    const auto t0 = std::chrono::steady_clock::now();
    const std::vector<BatteryRun> runs =
        o.battery_lives ? o.battery_lives(lives) : lives_on_threads(lives, threads, limits);
    if (runs.size() != lives.size())
      throw std::runtime_error("battery: " + std::to_string(runs.size()) + " outcomes for " +
                               std::to_string(lives.size()) + " lives");
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    for (size_t k = first; k < last; ++k) {
      ChampionAnalysis& c = r.champions[todo[k]];
      const std::vector<BatteryRun> mine(runs.begin() + static_cast<long>(start[k - first]),
                                         runs.begin() + static_cast<long>(start[k - first + 1]));
      if (!o.cache_dir.empty() && o.write_cache)
        write_atomically(checkpoint_path(o.cache_dir, keys[todo[k]]),
                         checkpoint_text(keys[todo[k]], c.label, mine));
      char how[64];
      std::snprintf(how, sizeof how, ", round of %zu in %.1f s", last - first, s);
      finish(c, mine, how);
    }
  }
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

Json optional_number(const std::optional<double>& x) {
  return x ? Json(*x) : Json(nullptr);
}

Json profile_json(const RobustnessProfile& prof) {
  Json ps = Json::array();
  for (const PerturbationProfile& p : prof.perturbations) {
    Json levels = Json::array();
    for (const SeverityLevel& l : p.levels) {
      Json kept = Json::array(), fitness = Json::array(), status = Json::array();
      for (const PerturbedOutcome& o : l.lives) {
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
                     {"powered", has_power(p, t)},
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

BatteryEstimate estimate_battery(const std::vector<std::string>& files,
                                 const StudyOptions& options) {
  if (options.battery.empty()) throw std::invalid_argument("estimate_battery: no battery given");
  StudyResult r;
  r.options = options;
  const Battery battery = load_battery(options.battery, options.robustness_draws);
  study::load_champions(files, options, r, /*score_robot_files=*/false);
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
  e.core_seconds = e.voxel_steps * e.seconds_per_voxel_step;
  e.seconds = e.core_seconds / std::min(e.threads, std::max(1, e.lives));
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
