// A whole study (docs/method.md §8, Fig. 5): the run champions of several evolution results
// files, grouped by treatment, measured (fitness, robustness, canalization, body plan,
// diversity) and compared with bootstrap statistics. Library plastivox_study; what
// `plastivox analyze` and `plastivox experiment` call.
//
// Why a separate library: it reads the evolver's HDF5 results and writes HDF5/JSON/CSV/HTML,
// while plastivox_analysis (the measures themselves) stays free of file formats.
//
// Inputs: results files of any algorithm the evolver writes, or robot files (.json, .vxa), each
// optionally labelled with its treatment as "TREATMENT=FILE" (docs/analysis.md).
//
// Determinism: champions are ordered by (treatment none, stress, pressure; run seed; a robot
// file's name; content digest), never by file order; every random draw is keyed by the champion's
// content (robustness) or by the panel and treatment (bootstrap), so the results do not depend on
// the order of the files, the thread count or on resuming. Resuming: the robustness simulations
// (the expensive part) are checkpointed per champion in options.cache_dir; a rerun reuses them.
//
// Threads: analyze_study parallelises simulations and Hausdorff pairs internally; call it and
// the writers from one thread at a time (HDF5 is not thread-safe).
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "plastivox/analysis/battery.hpp"
#include "plastivox/analysis/body_plan.hpp"
#include "plastivox/analysis/bootstrap.hpp"
#include "plastivox/analysis/canalization.hpp"
#include "plastivox/analysis/hausdorff.hpp"
#include "plastivox/analysis/robustness.hpp"
#include "plastivox/physics_def.hpp"
#include "plastivox/robot.hpp"

namespace plastivox::analysis {

constexpr int kStudyFormatVersion = 1;  // of stats.json ("plastivox-analysis") and analysis.h5

struct StudyOptions {
  int generation = -1;  // champion at the end of this generation; -1 = each file's last
  int robustness_draws = 10;
  StiffnessDistribution robustness_sampling = StiffnessDistribution::kLinear;
  RotationSearch rotations = RotationSearch::kPaper;
  TranslationSearch translation = TranslationSearch::kNone;
  int resamples = 10000;              // bootstrap resamples, tests and confidence intervals
  uint64_t seed = 1;                  // of every bootstrap and robustness draw
  double alpha = 0.05;                // significance level, applied after the Bonferroni correction
  double ci_level = 0.95;             // coverage of the confidence intervals of the means
  bool allow_mixed_physics = false;   // false: files simulated with different physics -> error
  std::vector<Treatment> treatments;  // expected treatments (each must have files); empty = any
  // false: a champion whose re-simulated life is unstable or sank through the floor is left
  // out of the statistics and figures (counted and listed); true keeps it in.
  bool keep_artifacts = false;
  // false: a champion the vertical rule flags (walk scored in 3-D with vertical_share above
  // kVerticalShareLimit, plastivox/rules/life_rules.hpp) is left out the same way; true keeps it
  // in.
  bool keep_vertical = false;
  // The robustness battery to run on every champion (battery.hpp; docs/analysis.md,
  // "Robustness battery"): a built-in name or a battery file; empty (the default): none, and
  // the outputs are what they were before batteries existed.
  std::string battery;
  // Not part of the results (never written to stats.json):
  int threads = 0;        // 0 = all cores
  std::string cache_dir;  // robustness checkpoints (created on demand); empty = no cache
  std::string command;    // the command line, recorded in provenance
  // Polled before each champion's robustness starts: when it reads true, analyze_study lets
  // the champions in progress finish (and checkpoint) and throws StudyStopped. nullptr: never.
  const std::atomic<bool>* stop_requested = nullptr;
  // false: checkpoints in cache_dir are read but never written (an MPI rank other than 0,
  // which computes what rank 0 computes and writes).
  bool write_cache = true;
  // Where a round of battery lives is simulated: empty = this process's `threads` (one pool
  // for every champion's lives); set under MPI to spread them over the ranks (apps' cli,
  // every rank calling it with the same lives in the same order). Returns the outcomes in the
  // lives' order; the same bits whoever simulates.
  std::function<std::vector<BatteryRun>(const std::vector<PerturbedLife>&)> battery_lives;
};

// Thrown by analyze_study when options.stop_requested was set; rerun to resume.
class StudyStopped : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The options as canonical JSON (the fields that can change results; not threads, cache_dir
// or command), e.g. {"generation":"last","robustness_draws":10,...}.
std::string options_json(const StudyOptions& o);

// Progress, reported from any thread but never concurrently (calls are serialised).
struct StudyProgress {
  std::string stage;  // "load", "robustness", "canalization", "hausdorff", "statistics"
  int done = 0, total = 0;
  std::string message;  // one human-readable line, e.g. "robustness 3/12 stress-s2 R=0.41"
};
using StudyProgressFn = std::function<void(const StudyProgress&)>;

// One run's course, one value per generation 0..StudyInput::generation, derived from the
// results file's stored history (the population after selection each generation) and births.
struct EvolutionCurve {
  std::vector<double> best;  // best fitness, voxel lengths
  std::vector<double> mean;  // mean fitness of the valid survivors (NaN when none is valid)
  // Population diversity: distinct lineages among the survivors (individuals descending from
  // different random individuals; AFPO injects a new random one each generation).
  std::vector<int> lineages;
};

// One treatment's best-fitness curves summarised per generation, over the generations every
// one of its runs has: the mean over runs and its percentile-bootstrap CI (n >= 2).
struct EvolutionBand {
  Treatment treatment = Treatment::kNone;
  int runs = 0;
  std::vector<double> mean, ci_low, ci_high;  // voxel lengths; CI = mean when runs < 2
};

// One input file.
struct StudyInput {
  std::string file;            // as given
  std::string content_digest;  // the results file's content digest (hex)
  Treatment treatment = Treatment::kNone;
  uint64_t seed = 0;             // run seed
  int generation = 0;            // of the champion analysed
  int generations_done = 0;      // in the file
  std::string physics_json;      // resolved physics of the run (treatment included)
  bool body_plan_start = false;  // generation 0 held the hand-built Π, Γ, Υ bodies
  EvolutionCurve evolution;      // generations 0..generation
};

// A value that is left out of a statistic, and why.
struct Exclusion {
  std::string label;
  std::string reason;
};

struct ChampionAnalysis {
  std::string label;  // "<treatment>-s<seed>", unique in the study
  int input = 0;      // index into StudyResult::inputs
  Treatment treatment = Treatment::kNone;
  uint64_t run_seed = 0;
  int generation = 0;  // the champion is the best individual at the end of this generation
  uint64_t id = 0;     // individual id in its run
  std::string phenotype_digest;         // the evolver's phenotype hash (evo::hash_robot), hex
  RobotDef robot;                       // the champion as evolved (E0 congenital, alpha, phase)
  std::vector<double> final_stiffness;  // lattice-sized, Pa, end of its evolved life
  PhysicsDef physics;                   // the run's physics (treatment included)
  int voxels = 0;
  double fitness = 0;             // from the results file, voxel lengths
  std::string evaluation = "ok";  // the champion's own evaluation: ok, invalid, unstable
  // "ok" when every measure is defined; otherwise a short code naming the first problem
  // ("unstable", "robustness-unstable", ...) with the reasons in status_detail.
  std::string status = "ok";
  std::string status_detail;
  // The audit: the champion's life simulated again with its run's physics (sunk lives scored,
  // so that a fall is measured, not cut short), whatever rule it was evolved under.
  std::string life_status;    // "finished" or "unstable"
  std::string health;         // "ok", "penetrating" or "sank" (SimResult::floor_health)
  double floor_depth = 0;     // deepest penetration below the floor, voxel lengths
  double vertical_share = 0;  // share of its fitness from vertical displacement, [0, 1]
  // The vertical rule (vertical_exploit, plastivox/rules/life_rules.hpp): a finished life, not
  // sunk, whose walk is scored in 3-D and owes more than kVerticalShareLimit to vertical motion.
  bool vertical_exploit = false;
  // Why it is left out of every statistic and figure (an unstable or sunk life, unless
  // StudyOptions::keep_artifacts; a vertical_exploit, unless StudyOptions::keep_vertical);
  // empty when it is in.
  std::string artifact;
  // Why a measure has no value: metric ("fitness", "robustness", "m_body", "v_body", "v_gain")
  // -> reason. A metric absent here has a value.
  std::map<std::string, std::string> undefined;
  uint64_t robustness_seed = 0;  // derived from options.seed and phenotype_digest
  RobustnessResult robustness;
  bool robustness_from_cache = false;  // this run reused a checkpoint (not written to outputs)
  std::optional<double> r_mean;        // mean R over valid draws; none if no draw is valid
  std::optional<double> m_body, v_body, v_gain;
  BodyPlanResult body_plan;
  // The hand-built body (0 Π, 1 Γ, 2 Υ; evo::body_plan_geometry) its lineage began from, when
  // its run started from them (initial_population: body-plans) and it descends from one; -1
  // otherwise. Read from the results file's births (not stored in analysis.h5:
  // load_champion_bodies fills it again).
  int seeded_plan = -1;
  // The champion's robustness profile over StudyOptions::battery (none without a battery, or
  // for an excluded artifact).
  std::optional<RobustnessProfile> profile;
};

// One treatment's values in one panel.
struct GroupStats {
  Treatment treatment = Treatment::kNone;
  std::vector<double> values;             // the sample
  std::vector<std::string> value_labels;  // champion label, or "a|b" for a pair (panel B)
  std::vector<Exclusion> excluded;        // champions left out, with the reason
  std::optional<ConfidenceInterval> ci;   // percentile bootstrap CI of the mean, when n >= 2
  std::optional<double> mean;             // when n >= 1
};

struct PanelStats {
  std::string id, metric, title, unit;
  std::vector<GroupStats> groups;                // in treatment order
  std::vector<BootstrapTestResult> comparisons;  // pairs of groups with n >= 2, Bonferroni
  uint64_t seed = 0;                             // the panel's bootstrap seed
};

// Wall time of each step, s (also in analysis.h5; never in stats.json).
struct StudyTimings {
  double load = 0, robustness = 0, canalization = 0, body_plans = 0, hausdorff = 0, statistics = 0,
         total = 0;
  int robustness_simulations = 0;  // simulations run by this call
  int robustness_cached = 0;       // champions whose robustness came from the cache
};

struct StudyResult {
  StudyOptions options;
  std::vector<StudyInput> inputs;                // in champion order
  std::vector<Treatment> treatments;             // present, in the order none, stress, pressure
  std::vector<ChampionAnalysis> champions;       // sorted: treatment, run seed, content digest
  std::map<Treatment, AlphaRange> alpha_ranges;  // evolved alpha range of developing treatments
  HausdorffMatrix hausdorff;                     // over `champions`, in their order
  std::vector<PanelStats> panels;                // A..F
  std::vector<EvolutionBand> evolution;          // one per treatment, in treatment order
  std::vector<std::string> warnings;             // e.g. mixed physics when allowed
  // The battery run (options.battery; none without one) and, per perturbation, its AUC
  // compared between treatments as a Fig. 5 panel (id "P1", "P2", ...; metric "battery:NAME").
  std::optional<Battery> battery;
  std::vector<PanelStats> battery_panels;
  // Every battery life simulated, and those that went unstable or sank (left out of the means).
  int battery_lives = 0, battery_unstable = 0, battery_sank = 0;
  int battery_cached = 0;  // champions whose battery this call read from checkpoints
  // What the report states of the runs' physics: the rule for sunk lives in force while they
  // evolved ("invalid", "scored (the authors' rule)" or "mixed: ...") and the direction fitness
  // is measured in ("3-D ..." or "xy-plane ...").
  std::string sinking_rule, fitness_direction;
  // The task the runs' lives were scored on and its unit ("walk", "voxel lengths"; "mixed:
  // ..." when they differ, docs/tasks.md).
  std::string task = "walk", fitness_unit = "voxel lengths";
  // Where they lived (plastivox/task.hpp, environment_text): the task's default environment
  // with its parameters, or "given: ground ...".
  std::string environment = "flat floor with friction";
  // What controlled their bodies (controller_text of the champions' controllers, "mixed: ..."
  // when they differ): "sine (open loop)", "distributed, 4 hidden units, every step". Empty
  // when unknown (no champions, or an analysis.h5 written before the field, until
  // load_champion_bodies fills it from the bodies).
  std::string controller;
  // Provenance.
  std::string version, commit, date;  // of this program; date UTC ISO 8601
  std::string fingerprint;            // study_fingerprint(input digests, options)
  StudyTimings timings;
};

// Loads every file, picks the champions, measures them and computes the statistics. Throws
// std::runtime_error (or a subclass) with one line naming the file for bad input (no files, a
// file that is not a results file, a missing generation or champion, the same run twice, an
// expected treatment without files, a treatment without one usable champion, mixed physics);
// it checks all inputs before any simulation runs and writes nothing but cache files.
StudyResult analyze_study(const std::vector<std::string>& files, const StudyOptions& options,
                          const StudyProgressFn& progress = {});

// The robustness battery alone (plastivox robustness): loads and audits the champions as
// analyze_study does, loads options.battery (throws naming the file and field before any life
// is simulated), runs every champion's profile (excluded artifacts get none) and compares the
// treatments per perturbation (battery_panels). No canalization, Hausdorff or Fig. 5 panels.
StudyResult battery_study(const std::vector<std::string>& files, const StudyOptions& options,
                          const StudyProgressFn& progress = {});
// What the battery will cost (--estimate-only): champions, lives, voxel-steps
// (battery_voxel_steps), the core-seconds they take at the speed of one timed life (the first
// champion's, unperturbed) and the wall time over the threads. Loads the champions and the
// battery (errors as battery_study's) and simulates that one life only; counts every champion
// (the audit, which may leave some out, is not run).
struct BatteryEstimate {
  int champions = 0, lives = 0, threads = 1;
  double voxel_steps = 0;
  double seconds_per_voxel_step = 0;  // measured
  double core_seconds = 0;            // predicted CPU time of the battery
  double seconds = 0;                 // predicted wall time on `threads`
};
BatteryEstimate estimate_battery(const std::vector<std::string>& files,
                                 const StudyOptions& options);
// The battery's part of stats.json as its own document ("plastivox-robustness"): the battery,
// every champion's profile and the comparisons (robustness.json of plastivox robustness).
std::string battery_stats_json(const StudyResult& r);
// One row per champion x perturbation x severity: mean and sd of fitness kept, lives, unstable,
// sank, AUC (robustness.csv).
std::string battery_csv(const StudyResult& r);

// The vertical rule in a study (docs/analysis.md, "The audit"): whether it applies (some of
// the runs score walk in 3-D, as fitness_direction says), how many champions it flagged and
// how many of those are left out of the statistics (all of them unless keep_vertical).
struct VerticalAudit {
  bool applies = false;
  int flagged = 0, excluded = 0;
};
VerticalAudit vertical_audit(const StudyResult& r);

// A hex fingerprint of what a study's results depend on: the inputs' content digests (in any
// order), options_json(options) and, with a battery, the battery itself (a file's content: an
// edited battery file changes it; throws like load_battery). Equal to stats.json's
// provenance.fingerprint when the outputs were made from these inputs with these options (the
// "already done" check).
std::string study_fingerprint(const std::vector<std::string>& content_digests,
                              const StudyOptions& options);

// ---- Outputs (study_output.cpp, study_report.cpp) ----

// stats.json's text (docs/analysis.md, "stats.json"): deterministic, only the date varies.
std::string stats_json(const StudyResult& r);

// Extra material for report.html (the experiment adds figures, galleries, a video).
struct ReportMedia {
  enum class Kind { kImage, kVideo, kLink };
  Kind kind = Kind::kImage;
  std::string path;     // relative to the report's folder (written into src/href as is)
  std::string caption;  // plain text
  // Further files of the same figure, shown in its caption: (label, path), e.g. ("SVG", ...).
  std::vector<std::pair<std::string, std::string>> links;
};
struct ReportSection {
  std::string title;                    // plain text
  std::vector<std::string> paragraphs;  // plain text (escaped)
  std::vector<ReportMedia> media;
  std::string raw_html;  // inserted unescaped after the paragraphs (caller's responsibility)
  bool wide = false;     // media in wider grid cells (galleries, videos)
};
struct ReportExtras {
  std::string title;                    // default "plastivox diversity report"
  std::vector<ReportSection> sections;  // after the summary, before the statistics
};

// The self-contained HTML report: inline CSS and SVG (heat map of the Hausdorff matrix), body
// plans per treatment, most and least similar pairs, the statistics table, provenance.
std::string report_html(const StudyResult& r, const ReportExtras& extras = {});

// Writes the study's data: DIR/stats.json, champions.csv, statistics.csv, hausdorff.csv and
// analysis.h5 (DIR is created). Every file is first written under a temporary name; the final
// names appear only once all are complete. Throws std::runtime_error naming the file.
// report.html is not among them: the report is made from the data (write_study_report).
void write_study_outputs(const StudyResult& r, const std::string& dir);

// report.html, atomically.
void write_study_report(const StudyResult& r, const std::string& path,
                        const ReportExtras& extras = {});

// A finished study read back from its analysis.h5 (as write_study_outputs wrote it), for the
// report and the figures, so nothing is recomputed: inputs, champions and their measures, the
// Hausdorff matrix, the panels' statistics, warnings and provenance. Not read back: the
// champions' bodies (load_champion_bodies), per-pair placements, value labels, evolution bands
// and timings. Throws std::runtime_error (or a subclass) naming the file and object.
StudyResult read_study_result(const std::string& path);

// Fills each champion's evolved body (robot, final_stiffness), its run's physics and its
// recorded fitness from the results file inputs[c.input].file. Throws std::runtime_error
// naming the file when it is not the run analysed (another content digest).
void load_champion_bodies(StudyResult& r);

// The evolver's phenotype hash of a robot (evo::hash_robot: lattice, voxel size, present, E0,
// alpha, phase, controller; not its name), hex: ChampionAnalysis::phenotype_digest.
std::string phenotype_digest(const RobotDef& robot);

// The seed of a champion's robustness draws in a study seeded with `seed`: a hash of the seed
// and the champion's phenotype digest, so its draws depend on the robot, not on its position
// among the champions or on the thread count (ChampionAnalysis::robustness_seed).
uint64_t champion_robustness_seed(uint64_t seed, const RobotDef& robot);

// The seeds of a study's statistics: panel p (1 = A ... 6 = F) resamples with
// panel_seed(seed, p) = mix64(seed ^ mix64(p)), which its tests pass to
// pairwise_bootstrap_tests; the CI of treatment t's group uses
// group_ci_seed(panel seed, t) = mix64(panel seed + 1 + t), t the Treatment's value (none 0,
// stress 1, pressure 2).
uint64_t panel_seed(uint64_t seed, int panel);
uint64_t group_ci_seed(uint64_t panel_seed, Treatment t);

// The text of one output, as written (for callers and tests).
std::string champions_csv(const StudyResult& r);
std::string statistics_csv(const StudyResult& r);
std::string hausdorff_csv(const StudyResult& r);

}  // namespace plastivox::analysis
