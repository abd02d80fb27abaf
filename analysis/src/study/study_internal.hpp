// Internal pieces of the study (plastivox_study): loading, robustness with checkpoints,
// statistics, number formatting and atomic files. See plastivox/analysis/study.hpp.
#pragma once

#include <array>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "plastivox/analysis/study.hpp"

namespace plastivox::analysis::study {

// ---- study_load.cpp ----
// Reads every file, picks the champions, checks the inputs (no files, duplicates, expected
// treatments, usable champions, mixed physics) and returns them sorted (treatment, seed,
// digest) with unique labels; fills inputs, treatments and warnings of `out`.
// A robot file's own life is simulated here (its fitness and final stiffness, as a results file
// records them) unless `score_robot_files` is false (an estimate, which simulates one life only).
void load_champions(const std::vector<std::string>& files, const StudyOptions& options,
                    StudyResult& out, bool score_robot_files = true);

// ---- study_audit.cpp ----
// Simulates every champion's life again with its run's physics (sunk lives scored): sets
// life_status, health, floor_depth, vertical_share, and for an unstable or sunk life the
// status and, unless options.keep_artifacts, `artifact`; sets r.sinking_rule and
// r.fitness_direction, task, fitness_unit, environment and controller.
void audit_champions(StudyResult& r, const StudyProgressFn& progress);

// controller_text of the champions' controllers: one, or "mixed: a; b" when they differ ("" for
// no champions).
std::string controller_of(const std::vector<ChampionAnalysis>& champions);

// ---- study_robustness.cpp ----
// Robustness of every champion, in parallel, reusing and writing checkpoints in
// options.cache_dir. Sets robustness, robustness_seed, robustness_from_cache and r_mean.
void run_robustness(StudyResult& r, const StudyProgressFn& progress);

// ---- study_battery.cpp ----
// Every champion's robustness profile over r.battery (nothing without one; excluded artifacts
// get none): the lives of several champions at a time in one pool (options.threads, or
// options.battery_lives across MPI ranks), each champion checkpointed in options.cache_dir
// when its lives are done, and read back from there by a rerun.
void run_battery(StudyResult& r, const StudyProgressFn& progress);
// Per perturbation, the treatments' AUC compared as a Fig. 5 panel.
std::vector<PanelStats> compute_battery_panels(const StudyResult& r);
// stats.json's "robustness_battery" block ("null" without a battery).
std::string battery_block_json(const StudyResult& r);

// ---- study_stats.cpp ----
// A panel's group: its mean and, with n >= 2, its bootstrap CI (seed group_ci_seed(p.seed,
// treatment)); appended to p.groups and, with n >= 2, to the samples compare_groups tests.
void add_group(PanelStats& p, GroupStats g, const StudyOptions& o,
               std::vector<NamedSample>& samples);
// The Bonferroni-corrected pairwise bootstrap tests of the samples (seed p.seed), verdicts
// withheld where a comparison has no power; nothing with fewer than two samples.
void compare_groups(PanelStats& p, const std::vector<NamedSample>& samples, const StudyOptions& o);
// Panels A..F from the measured champions and the Hausdorff matrix.
std::vector<PanelStats> compute_panels(const StudyResult& r);
// Per treatment, the mean best-fitness curve over its runs with a bootstrap CI per generation
// (study_stats.cpp).
std::vector<EvolutionBand> compute_evolution(const StudyResult& r);
// The k pairs (i < j) of champions with the smallest (most_similar) or largest Hausdorff
// distance, in that order; ties in increasing (i, j).
std::vector<std::pair<int, int>> extreme_pairs(const HausdorffMatrix& m, size_t k,
                                               bool most_similar);
// Body-plan counts per treatment over the champions kept in the statistics (an excluded
// artifact is not counted): counts[t][plan], plan in the order Pi, Gamma, Upsilon, other.
std::map<Treatment, std::array<int, 4>> body_plan_counts(const StudyResult& r);
// How many runs started from the hand-built Π, Γ, Υ bodies (initial_population: body-plans).
int body_plan_start_runs(const StudyResult& r);

// Champions (indices) that share one body descended from a hand-built one: equal lattices and
// filled sites, the same seeded_plan; groups of two or more, in champion order.
struct SharedBody {
  int plan = 0;  // 0 Π, 1 Γ, 2 Υ
  std::vector<int> champions;
};
std::vector<SharedBody> shared_seeded_bodies(const StudyResult& r);
// One sentence per shared body for the report and stats.json's warnings.
std::vector<std::string> shared_body_notes(const StudyResult& r);

// ---- study_power.cpp ----
// How many champions a panel's group rests on: its n, or for panel B (every within-treatment
// pair) the k with k (k - 1) / 2 = n pairs.
int champions_behind(const std::string& metric, size_t values);
// The fewer champions behind the two groups a comparison of panel p compares (read from the
// panel's groups: a comparison read back from analysis.h5 has no n of its own).
int comparison_champions(const PanelStats& p, const BootstrapTestResult& t);
// Whether a comparison can resolve anything: both treatments rest on at least kMinBootstrapN
// champions (bootstrap_coverage.hpp). compute_panels gives one without power no stars.
bool has_power(const PanelStats& p, const BootstrapTestResult& t);
// The stars every output shows: t.stars with power, none without (also for a result read
// from an analysis.h5 written before the rule).
std::string stars_shown(const PanelStats& p, const BootstrapTestResult& t);
// The fewest champions behind any comparison of the study, and how many comparisons lack power.
struct PowerSummary {
  int comparisons = 0, without_power = 0, fewest = 0;
  std::vector<std::string> panels;  // ids of the panels with a comparison without power
};
PowerSummary power_summary(const StudyResult& r);  // of Fig. 5's panels (r.panels)
PowerSummary power_summary(const std::vector<PanelStats>& panels);
// stats.json's warning for comparisons without power ("" when every comparison has it).
std::string power_warning(const StudyResult& r);

// ---- study_paper.cpp ----
// One comparison the paper published (Kriegman et al. 2018, Fig. 5 and its Results text), in
// the study's pair order (a before b: none, stress, pressure).
struct PaperFinding {
  const char* panel;  // "A".."F"
  Treatment a, b;
  int direction;        // sign of mean(b) - mean(a) the paper found; 0: no difference at 0.05
  const char* p_level;  // as the paper states it, e.g. "P < 0.001", "P ≥ 0.05"
  const char* where;    // the passage that states it
};
const std::vector<PaperFinding>& paper_findings();
// The paper's finding beside this study's estimate.
struct PaperComparison {
  PaperFinding paper;
  std::string metric, title;  // of the panel
  bool measured = false;      // this study compared the two treatments in that panel
  int n_a = 0, n_b = 0;       // champions behind each group
  std::optional<ConfidenceInterval> difference;  // of mean(b) - mean(a), percentile bootstrap
  double p_corrected = 1;
  bool powered = false, significant = false;
  std::string verdict;  // how the two relate, one phrase
};
std::vector<PaperComparison> compare_with_paper(const StudyResult& r);
// "stress > none", "pressure < stress", "no difference between none and stress".
std::string direction_text(Treatment a, Treatment b, int direction);

// ---- study_format.cpp ----
// Shortest decimal text that reads back to the same double (std::to_chars); "" when absent
// or not finite.
std::string number(double x);
std::string number(const std::optional<double>& x);
// A double's 64 bits as 16 hex digits, and back (checkpoints store doubles so; from_bits
// throws std::runtime_error for anything else).
std::string bits(double x);
double from_bits(const std::string& hex);
// A checkpoint file's JSON when it exists, parses, and holds `format`, version 1 and `key`;
// nothing otherwise (a damaged or foreign checkpoint is recomputed, never trusted).
std::optional<nlohmann::ordered_json> read_checkpoint_json(const std::string& path,
                                                           const std::string& format,
                                                           const std::string& key);
// A double rounded for display ("%.*g").
std::string display(double x, int digits = 3);
std::string display(const std::optional<double>& x, int digits = 3);
// Writes `text` completely to path + ".tmp" (no rename yet); throws naming the file.
void write_temp(const std::string& path, const std::string& text);
// Renames path + ".tmp" to path.
void commit_temp(const std::string& path);
// fsyncs a finished file; throws naming for_file.
void sync_file(const std::string& path, const std::string& for_file);
// Atomically (plastivox::write_file_atomic).
void write_atomically(const std::string& path, const std::string& text);

// ---- study_h5.cpp ----
// Writes analysis.h5 to `path` (a temporary name; the caller syncs and renames it to
// final_path, which error messages name).
void write_analysis_h5(const StudyResult& r, const std::string& final_path,
                       const std::string& path);

// Body-plan label for tables ("Pi", ...) and the champion's plan symbol.
inline const char* plan_name(const ChampionAnalysis& c) {
  return to_string(c.body_plan.plan);
}

}  // namespace plastivox::analysis::study
