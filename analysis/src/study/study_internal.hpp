// Internal pieces of the study (plastivox_study): loading, robustness with checkpoints,
// statistics, number formatting and atomic files. See plastivox/analysis/study.hpp.
#pragma once

#include <array>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "plastivox/analysis/study.hpp"

namespace plastivox::analysis::study {

// ---- study_load.cpp ----
// Reads every file, picks the champions, checks the inputs (no files, duplicates, expected
// treatments, usable champions, mixed physics) and returns them sorted (treatment, seed,
// digest) with unique labels; fills inputs, treatments and warnings of `out`.
void load_champions(const std::vector<std::string>& files, const StudyOptions& options,
                    StudyResult& out);

// Hex hash of a robot's definition (lattice, voxel size, present, E0, alpha, phase).
std::string phenotype_digest(const RobotDef& robot);

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

// ---- study_stats.cpp ----
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

// ---- study_format.cpp ----
// Shortest decimal text that reads back to the same double (std::to_chars); "" when absent
// or not finite.
std::string number(double x);
std::string number(const std::optional<double>& x);
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
