// The robustness battery's heat map (panel_drawing.hpp): perturbations x treatments, each cell
// the treatment's mean area under the fitness-kept curve. Laid out as plain shapes, so the SVG
// and the PNG back ends of the Fig. 5 panels draw it alike.
#include <algorithm>
#include <cstdio>

#include "plastivox/render/colormap.hpp"
#include "plastivox/render/panel_drawing.hpp"

namespace plastivox::render {
namespace {

constexpr Rgb kHeatInk{0, 0, 0};
constexpr Rgb kHeatGrey{110, 110, 110};
constexpr Rgb kHeatEmpty{230, 230, 230};

// Diverging: all fitness lost (0) red, all kept (1) white, doubled (2) blue.
Rgb heat_kept_colour(double mean) {
  const Rgb8 c = Colormap::diverging().at(std::clamp(0.5 + (1 - mean) / 2, 0.0, 1.0));
  return {c[0], c[1], c[2]};
}

// Dark text on light cells, white on dark ones.
Rgb heat_text_on(Rgb fill) {
  return 0.299 * fill.r + 0.587 * fill.g + 0.114 * fill.b > 140 ? kHeatInk : Rgb{255, 255, 255};
}

TextShape heat_label(const std::string& s, int font, float x, float y, Anchor a, Rgb c = kHeatInk) {
  return TextShape{{{s, font, 0}}, x, y, a, false, c};
}

}  // namespace

Drawing layout_battery_heat_map(const BatteryHeatMap& map, int width, int height) {
  Drawing d;
  d.width = width;
  d.height = height;
  const size_t rows = std::max<size_t>(1, map.perturbations.size());
  const size_t cols = std::max<size_t>(1, map.treatments.size());
  const float s = std::min(width / 800.0f, height / 600.0f);
  d.fonts = {{13 * s, false}, {15 * s, true}, {12 * s, false}};
  const float left = 130 * s, top = 64 * s, right = 190 * s, bottom = 40 * s;
  const float cw = (width - left - right) / cols, ch = (height - top - bottom) / rows;
  d.shapes.push_back(heat_label("Robustness battery: fitness kept (AUC), mean per treatment", 1,
                                width / 2.0f, 24 * s, Anchor::kMiddle));
  for (size_t t = 0; t < map.treatments.size(); ++t)
    d.shapes.push_back(
        heat_label(map.treatments[t], 1, left + (t + 0.5f) * cw, top - 10 * s, Anchor::kMiddle));
  d.shapes.push_back(heat_label("tests (Bonferroni)", 2, width - right + 8 * s, top - 10 * s,
                                Anchor::kStart, kHeatGrey));
  for (size_t p = 0; p < map.perturbations.size(); ++p) {
    const float y = top + p * ch;
    d.shapes.push_back(
        heat_label(map.perturbations[p], 0, left - 8 * s, y + ch / 2 + 5 * s, Anchor::kEnd));
    for (size_t t = 0; t < map.treatments.size(); ++t) {
      const size_t k = p * map.treatments.size() + t;
      const std::optional<double> m = k < map.mean.size() ? map.mean[k] : std::nullopt;
      const Rgb fill = m ? heat_kept_colour(*m) : kHeatEmpty;
      d.shapes.push_back(
          RectShape{left + t * cw + 1, y + 1, cw - 2, ch - 2, fill, "cell", map.treatments[t]});
      char buf[48];
      if (m)
        std::snprintf(buf, sizeof buf, "%.2f (n=%d)", *m, k < map.n.size() ? map.n[k] : 0);
      else
        std::snprintf(buf, sizeof buf, "undefined");
      d.shapes.push_back(heat_label(buf, 0, left + (t + 0.5f) * cw, y + ch / 2 + 5 * s,
                                    Anchor::kMiddle, heat_text_on(fill)));
    }
    if (p < map.tests.size() && !map.tests[p].empty())
      d.shapes.push_back(
          heat_label(map.tests[p], 2, width - right + 8 * s, y + ch / 2 + 5 * s, Anchor::kStart));
  }
  // Legend: 0 .. 2 fitness kept.
  const float ly = height - bottom + 12 * s, lw = std::min(240 * s, width - left - right);
  for (int i = 0; i < 32; ++i)
    d.shapes.push_back(RectShape{left + i * lw / 32, ly, lw / 32 + 1, 10 * s,
                                 heat_kept_colour(2.0 * i / 31), "", ""});
  d.shapes.push_back(heat_label("0", 2, left, ly + 24 * s, Anchor::kMiddle));
  d.shapes.push_back(heat_label("1 (all kept)", 2, left + lw / 2, ly + 24 * s, Anchor::kMiddle));
  d.shapes.push_back(heat_label("2", 2, left + lw, ly + 24 * s, Anchor::kMiddle));
  return d;
}

}  // namespace plastivox::render
