// An experiment: the paper's whole study described by one config (docs/experiment.md).
// JSON, format "plastivox-experiment-config", version 1. Every field has a default; every
// field present is validated and an error names it ("study.json: seeds[2]: ...").
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "plastivox/evo/config.hpp"

namespace plastivox::experiment {

constexpr int kExperimentConfigVersion = 1;
// A MAP-Elites run's gallery of elites in the study (archives/<run>/elites.png): its best six.
constexpr int kArchiveElites = 6;

struct AnalysisSettings {
  int generation = -1;                         // champion generation; -1 = the last
  int robustness_draws = 10;                   // random-stiffness draws per champion
  std::string robustness_sampling = "linear";  // linear | log
  int resamples = 10000;                       // bootstrap resamples
  std::string rotations = "paper";             // none | paper | all
  std::string translation = "none";            // none | integer
  uint64_t seed = 1;                           // statistics and robustness draws
  // The robustness battery run on every champion (docs/analysis.md, "Robustness battery"):
  // "" (none), default, paper, small or a battery file; checked when the config is read.
  std::string battery;
  int battery_lives = 0;  // lives per champion it simulates (from the battery; 0 without)
  // Simulations the analysis runs per champion: F_train, the draws and the battery's lives.
  int lives_per_champion() const { return 1 + robustness_draws + battery_lives; }
};

struct RenderSettings {
  bool figures = true;    // Fig. 5 panels A-F
  bool galleries = true;  // one champion gallery per treatment (Figs. 2-4)
  bool video = true;      // callus-growth video of the best developing champion
  int figure_width = 900, figure_height = 700;
  int gallery_width = 1920, gallery_height = 1080;
  int video_width = 1280, video_height = 720;
  double video_fps = 30;
  std::string video_color = "change";
};

struct ExperimentConfig {
  std::string name = "default";
  std::vector<Treatment> treatments{Treatment::kNone, Treatment::kStress, Treatment::kPressure};
  std::vector<uint64_t> seeds{1, 2};
  // Evolution settings shared by every run; seed and treatment are set per run.
  evo::EvolveConfig evolution;
  AnalysisSettings analysis;
  RenderSettings rendering;
  int threads = 0;  // 0 = all cores; --threads overrides; results never depend on it

  // Number of runs and the config of run (treatment t, seed s).
  int runs() const { return static_cast<int>(treatments.size() * seeds.size()); }
  // Lives a run makes (individuals created, before cache hits) in generation g, up to and
  // including generation g, and in all: AFPO makes P in generation 0 and P + 1 (children and
  // a newcomer) in each later one; MAP-Elites P in every generation (docs/evolution.md).
  int64_t lives_in_generation(int g) const;
  int64_t lives_through(int g) const;
  int64_t lives_per_run() const { return lives_through(evolution.generations); }
  evo::EvolveConfig run_config(Treatment t, uint64_t seed) const;
  // "stress-s3": the run's label and the stem of its results file.
  static std::string run_label(Treatment t, uint64_t seed);

  // Canonical JSON of every field (sorted keys); identity_json() drops the fields that
  // cannot change results (threads, checkpoint_every).
  std::string canonical_json() const;
  std::string identity_json() const;
};

// Parses and validates; throws plastivox::InputError ("<source>: <field>: <problem>").
ExperimentConfig parse_experiment_config(const std::string& text, const std::string& source);
ExperimentConfig read_experiment_config(const std::string& path);

// The presets shipped in assets/presets/experiment-<name>.json, embedded at build time.
std::vector<std::string> preset_names();                  // default, tiny, gecco2018
ExperimentConfig preset_config(const std::string& name);  // throws InputError if unknown
std::string preset_text(const std::string& name);

}  // namespace plastivox::experiment
