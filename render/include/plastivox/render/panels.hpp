// Figure panels (the paper's Fig. 5, panels A-F): one bar chart per metric, treatment means
// with 95 % confidence-interval error bars, the individual values as points (small samples)
// and significance brackets with stars, read from the
// analysis output stats.json (contract: docs/analysis.md, "stats.json").
//
// Pipeline: read_stats_figure() parses and validates stats.json into a StatsFigure;
// layout_panel() (panel_drawing.hpp) turns one panel into a Drawing, a flat list of
// rectangles, lines and texts in pixel coordinates; that one Drawing is written both as SVG
// text (panel_svg) and as a PNG drawn with Dear ImGui off-screen (panel_png), so the two
// formats agree. write_figures() does all of it for a directory and is what `plastivox figures`
// and `plastivox experiment` call. Everything is deterministic: same stats, same bytes.
#pragma once

#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "plastivox/base/error.hpp"

#include <nlohmann/json_fwd.hpp>

namespace plastivox::render {

// A malformed or foreign stats.json: one line naming the file and the field, e.g.
// "stats.json: panels[1].groups[0].mean: missing".
class StatsError : public Error {
 public:
  using Error::Error;
};

// One bar: a treatment's mean with its confidence interval.
struct PanelGroup {
  std::string treatment;          // "none", "stress", "pressure" (or another producer name)
  int n = 0;                      // sample size
  std::optional<double> mean;     // metric unit; absent when undefined (no bar is drawn)
  std::optional<double> ci_low;   // 95 % CI of the mean; absent when n < 2
  std::optional<double> ci_high;  // present exactly when ci_low is
  // The sample itself (one value per champion, or per pair in panel B), when stats.json has
  // it; drawn as points over the bar when n <= kMaxPanelPoints.
  std::vector<double> values;
};
constexpr int kMaxPanelPoints = 30;

// One pairwise test between two groups of the panel.
struct PanelComparison {
  std::string a, b;  // treatments compared (each names a group of the panel)
  std::optional<double> p_corrected;
  std::string stars;  // "", "*", "**" or "***" (after correction); "" draws no bracket
};

struct PanelStats {
  std::string id;                  // "A".."F": the panel letter and the output file name panel_<id>
  std::string metric;              // e.g. "fitness"
  std::string title;               // e.g. "Fitness", "M_body" ('_' starts a subscript when drawn)
  std::string unit;                // y-axis label, e.g. "voxel lengths"
  std::vector<PanelGroup> groups;  // bars, left to right
  std::vector<PanelComparison> comparisons;
};

// The evolution curves of stats.json's "evolution" (docs/analysis.md): best fitness per
// generation of every run, and per treatment the mean over its runs with a 95 % CI band.
struct EvolutionRunCurve {
  std::string label, treatment;
  std::vector<std::optional<double>> best;  // per generation from 0; absent = undefined
};
struct EvolutionTreatmentBand {
  std::string treatment;
  int runs = 0;
  std::vector<std::optional<double>> mean, ci_low, ci_high;  // per generation, same length
};
struct EvolutionStats {
  std::string unit;  // of the fitness axis, e.g. "voxel lengths"
  std::vector<EvolutionRunCurve> runs;
  std::vector<EvolutionTreatmentBand> treatments;
};

// The robustness battery's heat map (docs/analysis.md, "Robustness battery"): per
// perturbation (row) and treatment (column) the mean area under the fitness-kept curve, from
// the "comparisons" of stats.json's "robustness_battery" (or of plastivox robustness's
// robustness.json).
struct BatteryHeatMap {
  std::vector<std::string> treatments, perturbations;
  std::vector<std::optional<double>> mean;  // [perturbation * treatments.size() + treatment]
  std::vector<int> n;                       // champions behind each mean, same index
  std::vector<std::string> tests;           // per perturbation: "a-b ***" for each significant pair
};
// `block` holds "comparisons" (stats.json's robustness_battery, or robustness.json itself);
// `where` is its path for messages ("robustness_battery" or ""). Throws StatsError.
BatteryHeatMap parse_battery_heat_map(const nlohmann::json& block, const std::string& source,
                                      const std::string& where);

// A MAP-Elites archive on two descriptor axes (plastivox archive; docs/evolution.md,
// "MAP-Elites"): per cell the fitness of its best elite (over any further axes).
struct ArchiveMap {
  std::string title, x_name, y_name, fitness_unit;
  double x_lo = 0, x_hi = 1, y_lo = 0, y_hi = 1;
  int x_bins = 1, y_bins = 1;
  std::vector<std::optional<double>> fitness;  // [y_bin * x_bins + x_bin]; empty cell: none
};

struct StatsFigure {
  std::string source;  // file the data came from (for messages)
  std::vector<PanelStats> panels;
  std::optional<BatteryHeatMap> battery;    // when the study ran a robustness battery
  std::optional<EvolutionStats> evolution;  // absent in stats.json written before it existed
};

// Parses a stats.json document; `source` names it in error messages. Checks the format tag
// ("plastivox-analysis"), format_version (1) and every field the panels use. Throws StatsError.
StatsFigure parse_stats_figure(const nlohmann::json& stats, const std::string& source);
// Reads and parses the file. Throws StatsError (also for unreadable files and bad JSON).
StatsFigure read_stats_figure(const std::string& path);

struct FigureOptions {
  int width = 800;  // one panel's size in pixels (PNG) and SVG user units, each 200..8192
  int height = 600;
  bool png = true;       // write panel_<id>.png
  bool svg = true;       // write panel_<id>.svg
  bool combined = true;  // also figure_5.{png,svg}: all panels in a grid of 3 columns
};

// Writes DIR/panel_<id>.{svg,png} for every panel, DIR/evolution.{svg,png} when the stats
// have evolution curves (and the combined figure), creating DIR if
// needed. Each file is written to a temporary and renamed. Returns the paths written, in order.
// Throws StatsError/RenderError (one line) on bad input or an unwritable directory.
std::vector<std::string> write_figures(const StatsFigure& figure, const std::string& out_dir,
                                       const FigureOptions& options);

// Writes DIR/robustness_heatmap.{svg,png} (as options.svg/png ask) at options' panel size;
// returns the paths written.
std::vector<std::string> write_battery_heat_map(const BatteryHeatMap& map,
                                                const std::string& out_dir,
                                                const FigureOptions& options);

// Writes DIR/archive.{svg,png} (as options.svg/png ask) at options' panel size; returns the
// paths written.
std::vector<std::string> write_archive_map(const ArchiveMap& map, const std::string& out_dir,
                                           const FigureOptions& options);

// Throws RenderError (one line) when panels of options.width x options.height cannot be
// drawn: each side in [200, 8192], and the combined PNG of `panels` panels (3 columns) at
// most kMaxImageSide pixels a side. write_figures checks it; a study checks it from its
// config, before any evolution.
void check_figure_size(const FigureOptions& options, int panels);

}  // namespace plastivox::render
