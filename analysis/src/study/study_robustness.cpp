// Robustness of a study's champions (panel C), in parallel, checkpointed per champion.
//
// Why checkpoints: robustness is the only expensive step of an analysis (1 + draws full lives
// per champion, seconds each), and `plastivox experiment` must resume a killed analysis without
// losing work. After each champion its result is written atomically to
// <cache_dir>/robustness-<key>.json, where key hashes everything the result depends on (the
// champion's phenotype digest, the physics it is simulated with, the draws, distribution and
// seed). A rerun finds the file and reads the result back bit for bit (doubles are stored as
// their 64-bit patterns), so a resumed analysis writes the same stats.json as an uninterrupted
// one. A checkpoint that cannot be read or belongs to other inputs is ignored and recomputed.
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <sstream>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "plastivox/base/hash.hpp"
#include "plastivox/base/parallel.hpp"
#include "plastivox/evo/config.hpp"
#include "plastivox/io/limits.hpp"
#include "study_internal.hpp"

namespace plastivox::analysis::study {
namespace {

using Json = nlohmann::ordered_json;

RobustnessOptions robustness_options(const StudyOptions& o, uint64_t seed, int threads) {
  RobustnessOptions r;
  r.limits = limits_from_environment();
  r.draws = o.robustness_draws;
  r.seed = seed;
  r.distribution = o.robustness_sampling;
  r.threads = threads;
  return r;
}

uint64_t champion_seed(uint64_t seed, const std::string& phenotype_digest) {
  Hasher h;
  h.str("plastivox-robustness-seed-v1");
  h.u64(seed);
  h.str(phenotype_digest);
  return h.finish().lo;
}

std::string checkpoint_key(const ChampionAnalysis& c, const StudyOptions& o) {
  Hasher h;
  h.str("plastivox-robustness-checkpoint-v2");
  h.str(c.phenotype_digest);
  h.str(evo::resolved_physics_json(robustness_physics(c.physics)));
  h.u64(static_cast<uint64_t>(o.robustness_draws));
  h.str(to_string(o.robustness_sampling));
  h.u64(c.robustness_seed);
  return h.finish().hex();
}

std::string checkpoint_path(const std::string& dir, const std::string& key) {
  return (std::filesystem::path(dir) / ("robustness-" + key + ".json")).string();
}

std::string checkpoint_text(const ChampionAnalysis& c, const std::string& key) {
  const RobustnessResult& r = c.robustness;
  Json draws = Json::array();
  for (const RobustnessDraw& d : r.draws)
    draws.push_back({{"f_test", bits(d.f_test)},
                     {"r", bits(d.r)},
                     {"valid", d.valid},
                     {"failure", d.failure},
                     {"f_test_value", d.f_test}});
  const Json j = {{"format", "plastivox-robustness-checkpoint"},
                  {"version", 1},
                  {"key", key},
                  {"label", c.label},
                  {"phenotype_digest", c.phenotype_digest},
                  {"seed", c.robustness_seed},
                  {"distribution", r.distribution},
                  {"e_lo", bits(r.e_lo)},
                  {"e_hi", bits(r.e_hi)},
                  {"f_train", bits(r.f_train)},
                  {"f_train_value", r.f_train},
                  {"train_valid", r.train_valid},
                  {"train_failure", r.train_failure},
                  {"valid_draws", r.valid_draws},
                  {"mean_r", bits(r.mean_r)},
                  {"mean_r_value", r.mean_r},
                  {"draws", draws}};
  return j.dump(1) + "\n";
}

// The checkpoint's result, or nothing when absent, unreadable or for another key.
std::optional<RobustnessResult> read_checkpoint(const std::string& path, const std::string& key,
                                                int draws) {
  const std::optional<Json> read =
      read_checkpoint_json(path, "plastivox-robustness-checkpoint", key);
  if (!read) return std::nullopt;
  const Json& j = *read;
  try {
    if (j.at("draws").size() != static_cast<size_t>(draws)) return std::nullopt;
    RobustnessResult r;
    r.distribution = j.at("distribution").get<std::string>();
    r.e_lo = from_bits(j.at("e_lo").get<std::string>());
    r.e_hi = from_bits(j.at("e_hi").get<std::string>());
    r.seed = j.at("seed").get<uint64_t>();
    r.f_train = from_bits(j.at("f_train").get<std::string>());
    r.train_valid = j.at("train_valid").get<bool>();
    r.train_failure = j.at("train_failure").get<std::string>();
    r.valid_draws = j.at("valid_draws").get<int>();
    r.mean_r = from_bits(j.at("mean_r").get<std::string>());
    for (const Json& d : j.at("draws")) {
      RobustnessDraw x;
      x.f_test = from_bits(d.at("f_test").get<std::string>());
      x.r = from_bits(d.at("r").get<std::string>());
      x.valid = d.at("valid").get<bool>();
      x.failure = d.at("failure").get<std::string>();
      r.draws.push_back(x);
    }
    return r;
  } catch (const std::exception&) {
    return std::nullopt;
  }
}

// r_mean and the champion's status from its robustness result.
void summarise(ChampionAnalysis& c) {
  const RobustnessResult& r = c.robustness;
  c.r_mean.reset();
  if (r.valid_draws > 0) c.r_mean = r.mean_r;
  std::string problem, detail;
  if (!r.train_valid) {
    problem = "robustness-undefined";
    detail = "robustness: F_train undefined (" + r.train_failure + ")";
    c.undefined["robustness"] = detail;
  } else if (r.valid_draws < static_cast<int>(r.draws.size())) {
    problem = "robustness-unstable";
    int bad = 0;
    std::string first;
    for (const RobustnessDraw& d : r.draws)
      if (!d.valid) {
        if (bad++ == 0) first = d.failure;
      }
    detail = "robustness: " + std::to_string(bad) + " of " + std::to_string(r.draws.size()) +
             " draws invalid, excluded from R (first: " + first + ")";
    if (r.valid_draws == 0) c.undefined["robustness"] = detail;
  }
  if (problem.empty()) return;
  if (c.status == "ok") c.status = problem;
  c.status_detail += (c.status_detail.empty() ? "" : "; ") + detail;
}

std::string r_text(const ChampionAnalysis& c) {
  if (!c.r_mean) return "R undefined";
  char buf[64];
  std::snprintf(buf, sizeof buf, "R=%.3g", *c.r_mean);
  return buf;
}

}  // namespace

void run_robustness(StudyResult& r, const StudyProgressFn& progress) {
  const StudyOptions& o = r.options;
  const int n = static_cast<int>(r.champions.size());
  std::vector<std::string> keys(n);
  std::vector<int> todo;
  int done = 0;
  std::mutex mutex;
  auto report = [&](const std::string& message) {
    if (progress) progress({"robustness", done, n, message});
  };

  // Reuse what an earlier, interrupted analysis finished. Champions with equal keys (identical
  // robots under identical physics) are simulated once: `first[key]` is the one that runs.
  std::map<std::string, int> first;
  for (int i = 0; i < n; ++i) {
    ChampionAnalysis& c = r.champions[i];
    c.robustness_seed = champion_seed(o.seed, c.phenotype_digest);
    keys[i] = checkpoint_key(c, o);
    if (!c.artifact.empty()) {  // left out of the statistics: nothing to measure
      c.undefined["robustness"] = "excluded as an artifact: " + c.artifact;
      ++done;
      report("robustness " + std::to_string(done) + "/" + std::to_string(n) + " " + c.label +
             " excluded (" + c.artifact + ")");
      continue;
    }
    std::optional<RobustnessResult> cached;
    if (!o.cache_dir.empty())
      cached = read_checkpoint(checkpoint_path(o.cache_dir, keys[i]), keys[i], o.robustness_draws);
    if (!cached) {
      if (first.emplace(keys[i], i).second) todo.push_back(i);
      continue;
    }
    c.robustness = *cached;
    c.robustness_from_cache = true;
    summarise(c);
    ++done;
    ++r.timings.robustness_cached;
    report("robustness " + std::to_string(done) + "/" + std::to_string(n) + " " + c.label + " " +
           r_text(c) + " (from checkpoint)");
  }
  if (todo.empty()) return;
  if (!o.cache_dir.empty() && o.write_cache) std::filesystem::create_directories(o.cache_dir);

  // Champions in parallel; a champion's own 1 + draws simulations share the spare threads.
  const int threads = o.threads > 0 ? o.threads : hardware_threads();
  const int outer = std::min(threads, static_cast<int>(todo.size()));
  const int inner = std::max(1, threads / outer);
  try {
    parallel_for(todo.size(), outer, [&](size_t k_) {
      const int k = static_cast<int>(k_);
      if (o.stop_requested && o.stop_requested->load()) throw StudyStopped("stopped on request");
      ChampionAnalysis& c = r.champions[todo[k]];
      const auto t0 = std::chrono::steady_clock::now();
      c.robustness =
          robustness(c.robot, c.physics, robustness_options(o, c.robustness_seed, inner));
      summarise(c);
      if (!o.cache_dir.empty() && o.write_cache)
        write_atomically(checkpoint_path(o.cache_dir, keys[todo[k]]),
                         checkpoint_text(c, keys[todo[k]]));
      const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      std::lock_guard<std::mutex> lock(mutex);
      ++done;
      r.timings.robustness_simulations += 1 + o.robustness_draws;
      char buf[64];
      std::snprintf(buf, sizeof buf, " (%d simulations, %.1f s)", 1 + o.robustness_draws, s);
      report("robustness " + std::to_string(done) + "/" + std::to_string(n) + " " + c.label + " " +
             r_text(c) + buf);
    });
  } catch (const StudyStopped&) {  // the champions in progress have finished by now
    throw StudyStopped("stopped on request with " + std::to_string(done) + " of " +
                       std::to_string(n) + " champions' robustness done and checkpointed");
  }
  for (int i = 0; i < n; ++i) {
    ChampionAnalysis& c = r.champions[i];
    const auto it = first.find(keys[i]);
    if (c.robustness_from_cache || it == first.end() || it->second == i) continue;
    c.robustness = r.champions[it->second].robustness;
    summarise(c);
    ++done;
    report("robustness " + std::to_string(done) + "/" + std::to_string(n) + " " + c.label + " " +
           r_text(c) + " (same robot as " + r.champions[it->second].label + ")");
  }
}

}  // namespace plastivox::analysis::study

namespace plastivox::analysis {

uint64_t champion_robustness_seed(uint64_t seed, const RobotDef& robot) {
  return study::champion_seed(seed, phenotype_digest(robot));
}

}  // namespace plastivox::analysis
