// A MAP-Elites run's QD score and coverage over its evaluations (docs/evolution.md,
// "MAP-Elites"), as QD papers plot them: two line plots stacked on one evaluations axis.
// Laid out as plain shapes (panel_drawing.hpp), so the SVG and the PNG agree.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "plastivox/render/panel_drawing.hpp"
#include "plastivox/render/panels.hpp"

namespace plastivox::render {

struct QdCurve {
  std::string title, fitness_unit;
  int64_t cells = 0;                 // cells of the archive (coverage = filled / cells)
  std::vector<int64_t> evaluations;  // lives made up to and including each generation
  std::vector<double> qd_score;      // the archive's QD score after each generation
  std::vector<int64_t> filled;       // its filled cells after each generation
};

// The QD score (top) and the coverage in % (bottom) against evaluations, a point a generation
// joined by lines; each axis from 0 to its largest value. Throws RenderError when the three
// series differ in length.
Drawing layout_qd_curve(const QdCurve& curve, int width, int height);

// Writes DIR/qd.{svg,png} (as options.svg/png ask) at options' panel size; returns the paths.
std::vector<std::string> write_qd_curve(const QdCurve& curve, const std::string& out_dir,
                                        const FigureOptions& options);

}  // namespace plastivox::render
