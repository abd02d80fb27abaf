// The robustness battery (docs/analysis.md, "Robustness battery"): the paper's one question
// (how much fitness survives when development is taken away and the stiffness redrawn, Eq. 2)
// asked of a champion many ways, each graded in severities, each with seeds.
//
// A perturbation is a change to the robot (RobotDef) or its physics (PhysicsDef) made before
// compile(); the engine is not touched. Every perturbation applies to the champion as evolved,
// development and all, except `paper`, which is Eq. 2 itself. For each perturbation, severity
// and seed one life is simulated; fitness kept = F_perturbed / F_reference, where F_reference is
// the unperturbed life under the same physics (for `paper`: F_train of the robot without
// development, as R). A life that goes unstable or sinks is counted, never averaged in.
//
// Randomness: the life of (perturbation p, severity i, seed s) draws from
// Rng::stream(base, kBattery, s, kind) with base = the champion's seed, so a perturbation's
// random draws are the same at every severity (common random numbers: a curve that falls does
// so because of the severity, not a new draw). `paper` draws as robustness() does (draw k =
// seed s), so its severity 1 with seeds 0..9 reproduces R to the bit. Lives run in parallel;
// each is single-threaded and deterministic, so a profile is bit-identical on any thread count.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "plastivox/physics_def.hpp"
#include "plastivox/robot.hpp"

namespace plastivox::analysis {

enum class PerturbationKind {
  kPaper,          // development removed, stiffness redrawn; severity: spread of the draw (0, 1]
  kVoxelLoss,      // share of voxels removed at random, largest piece kept; [0, 0.9]
  kLimbLoss,       // the body's end along a seeded direction cut off; share of its extent [0, 0.9]
  kPhaseNoise,     // each voxel's phase shifted by u * severity, u in [-1/2, 1/2]; cycles [0, 1]
  kAmplitudeLoss,  // every voxel's actuation amplitude scaled by 1 - severity; [0, 1]
  kFriction,       // mu_static and mu_kinetic times severity (ice < 1 < rubber); (0, 10]
  kRoughGround,    // a rough ground, heights uniform in [-severity, 0] voxel lengths; [0, 5]
  kPayload,        // a load of severity x the body's weight on its top layer; [0, 5]
  kGravity,        // gravity times severity; (0, 5]
  kBondModel,      // the other bond model (exact <-> voxelyze09); severity 1 only
  kTimeStep,       // dt_frac times severity; (0, 1]
};
const char* to_string(PerturbationKind k);  // "paper", "voxel-loss", ...
// Throws std::invalid_argument listing the names for an unknown one.
PerturbationKind parse_perturbation_kind(const std::string& name);
std::string perturbation_kind_names();
// The unit of a kind's severity ("share of voxels", "cycles", ...).
const char* severity_unit(PerturbationKind k);
// The severities a kind accepts: [lo, hi], lo excluded when lo_open.
struct SeverityRange {
  double lo = 0, hi = 1;
  bool lo_open = false;
};
SeverityRange severity_range(PerturbationKind k);
// Whether the kind draws random numbers (the others give one life per severity, whatever the
// seeds).
bool is_random(PerturbationKind k);

struct Perturbation {
  std::string name;  // unique in its battery; the kind's name unless several share a kind
  PerturbationKind kind = PerturbationKind::kPaper;
  std::vector<double> severities;  // ascending
  std::vector<uint64_t> seeds;     // one life per seed per severity (random kinds)
};

struct Battery {
  std::string name;  // "default", "paper", "small" or the file it came from
  std::vector<Perturbation> perturbations;
};

// Throws std::invalid_argument "<where>: perturbations[i].field: why" for an empty battery, a
// duplicate name, no severities, a severity out of range or not ascending, no seeds.
void validate(const Battery& battery, const std::string& where = "battery");

// The built-in batteries: "default" (every kind, three or more severities, three seeds),
// "paper" (Eq. 2 alone: severity 1, seeds 0..draws-1) and "small" (the default study's: paper,
// voxel-loss, friction, gravity at three severities, one seed: 14 lives a champion). Throws for
// another name.
Battery builtin_battery(const std::string& name, int paper_draws = 10);

// The battery named by `spec`: a built-in name or a JSON file (docs/analysis.md). Throws
// std::invalid_argument naming the file and the field for a bad file. Implemented in
// plastivox_study (it reads JSON).
Battery load_battery(const std::string& spec, int paper_draws = 10);
// A battery from JSON text; `where` names it in errors (the file) and becomes its name.
Battery parse_battery(const std::string& text, const std::string& where);
// The battery as JSON text (what load_battery reads).
std::string battery_json(const Battery& battery);

// ---- applying one perturbation ----
// What one life of the battery simulates: the robot and physics after the perturbation.
struct PerturbedLife {
  RobotDef robot;
  PhysicsDef physics;
};
// The life of (p, severity, seed) for `champion` under `physics`; `base_seed` is the champion's
// (champion_robustness_seed). Throws std::invalid_argument for a severity outside the kind's
// range.
PerturbedLife perturb(const RobotDef& champion, const PhysicsDef& physics, PerturbationKind kind,
                      double severity, uint64_t seed, uint64_t base_seed);
// The unperturbed life the kind's fitness is kept of (for kPaper: without development,
// treatment none).
PerturbedLife reference_life(const RobotDef& champion, const PhysicsDef& physics,
                             PerturbationKind kind);

// ---- the profile ----
struct PerturbedOutcome {
  double fitness = 0;   // voxel lengths (of the task), 0 when not valid
  double kept = 0;      // fitness / F_reference (0 when not valid)
  bool valid = false;   // finished, did not sink, and the reference is valid
  std::string status;   // "ok", "unstable", "sank" or "no-reference"
  std::string failure;  // the simulator's reason, when not ok
};

struct SeverityLevel {
  double severity = 0;
  std::vector<uint64_t> seeds;          // the lives' seeds (one for a kind that draws nothing)
  std::vector<PerturbedOutcome> lives;  // in seed order
  int valid = 0, unstable = 0, sank = 0;
  std::optional<double> mean_kept;  // over valid lives, in seed order
  std::optional<double> sd_kept;    // sample standard deviation, when valid >= 2
};

struct PerturbationProfile {
  std::string name;
  PerturbationKind kind = PerturbationKind::kPaper;
  std::string unit;  // of severity
  double f_reference = 0;
  bool reference_valid = false;  // finished, not sunk, F > 0
  std::string reference_failure;
  std::vector<SeverityLevel> levels;
  // Area under the mean-kept curve over [first, last severity] divided by that span
  // (trapezoids): the mean fitness kept over the graded range; with one severity, its mean.
  // None when a level has no valid life.
  std::optional<double> auc;
};

struct RobustnessProfile {
  std::string battery;
  uint64_t seed = 0;  // base seed of the draws
  std::vector<PerturbationProfile> perturbations;
  int lives = 0, unstable = 0, sank = 0;  // over every life simulated
};

struct ProfileOptions {
  uint64_t seed = 1;  // base seed (the study passes champion_robustness_seed)
  int threads = 0;    // 0 = the hardware's count
  Limits limits;
};

// Number of lives profile() simulates for the battery (references included).
int battery_lives(const Battery& battery);

// The battery's work on one champion, in voxel-steps: over every life it simulates, voxels x
// duration / the time step at its stiffest voxel (time_step_at; developing bodies may stiffen
// and shorten it, so this is a floor). --estimate-only scales it by a timed life.
double battery_voxel_steps(const RobotDef& champion, const PhysicsDef& physics,
                           const Battery& battery, uint64_t base_seed);

// ---- the profile in three steps (what robustness_profile does), for callers that spread the
// lives of many champions over one pool of threads or MPI ranks (the study) ----
// Every life of the battery on this champion, references first, in the profile's order; each
// robot and physics validated (std::invalid_argument) before any life is simulated.
std::vector<PerturbedLife> battery_lives_of(const RobotDef& champion, const PhysicsDef& physics,
                                            const Battery& battery, uint64_t base_seed,
                                            const Limits& limits);
// One life simulated and judged (judge_life): its fitness and status "ok", "unstable" or
// "sank" (failure: the simulator's reason). Deterministic: the same on any thread or rank.
struct BatteryRun {
  double fitness = 0;
  std::string status, failure;
};
BatteryRun run_battery_life(const PerturbedLife& life, const Limits& limits);
// Its cost for ordering and sharing work: voxels x duration / time step at the stiffest voxel.
double life_voxel_steps(const PerturbedLife& life);
// The profile from the lives' outcomes, in battery_lives_of's order.
RobustnessProfile assemble_profile(const Battery& battery, uint64_t base_seed,
                                   const std::vector<BatteryRun>& runs);

// Validates robot, physics and battery (std::invalid_argument) before any life is simulated.
RobustnessProfile robustness_profile(const RobotDef& champion, const PhysicsDef& physics,
                                     const Battery& battery, const ProfileOptions& options = {});

}  // namespace plastivox::analysis
