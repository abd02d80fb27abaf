// A MAP-Elites archive's map (panel_drawing.hpp): two descriptor axes, each cell coloured by
// the fitness of its best elite. Laid out as plain shapes, so the SVG and the PNG back ends
// draw it alike, as they draw the battery's heat map.
#include <algorithm>
#include <cstdio>

#include "plastivox/render/colormap.hpp"
#include "plastivox/render/panel_drawing.hpp"

namespace plastivox::render {
namespace {

constexpr Rgb kArchiveInk{0, 0, 0};
constexpr Rgb kArchiveEmpty{235, 235, 235};

Rgb archive_colour(double t) {
  const Rgb8 c = Colormap::sequential().at(std::clamp(t, 0.0, 1.0));
  return {c[0], c[1], c[2]};
}

TextShape archive_label(const std::string& s, int font, float x, float y, Anchor a,
                        bool up = false) {
  return TextShape{{{s, font, 0}}, x, y, a, up, kArchiveInk};
}

std::string archive_number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", v);
  return buf;
}

}  // namespace

Drawing layout_archive_map(const ArchiveMap& map, int width, int height) {
  Drawing d;
  d.width = width;
  d.height = height;
  const float s = std::min(width / 800.0f, height / 600.0f);
  d.fonts = {{13 * s, false}, {15 * s, true}, {12 * s, false}};
  const float left = 90 * s, top = 56 * s, right = 150 * s, bottom = 70 * s;
  const int nx = std::max(1, map.x_bins), ny = std::max(1, map.y_bins);
  const float cw = (width - left - right) / nx, ch = (height - top - bottom) / ny;
  double lo = 0, hi = 0;
  bool any = false;
  for (const std::optional<double>& f : map.fitness)
    if (f) {
      lo = any ? std::min(lo, *f) : *f;
      hi = any ? std::max(hi, *f) : *f;
      any = true;
    }
  const double span = hi > lo ? hi - lo : 1;
  d.shapes.push_back(archive_label(map.title, 1, width / 2.0f, 24 * s, Anchor::kMiddle));
  // Cells: x to the right, y upwards (bin 0 at the bottom).
  for (int y = 0; y < ny; ++y)
    for (int x = 0; x < nx; ++x) {
      const size_t k = static_cast<size_t>(y) * nx + x;
      const std::optional<double> f = k < map.fitness.size() ? map.fitness[k] : std::nullopt;
      const float cx = left + x * cw, cy = top + (ny - 1 - y) * ch;
      d.shapes.push_back(RectShape{cx + 0.5f, cy + 0.5f, cw - 1, ch - 1,
                                   f ? archive_colour((*f - lo) / span) : kArchiveEmpty, "cell",
                                   f ? archive_number(*f) : std::string("empty")});
    }
  // Axes: the bounds at the grid's edges, the names beside.
  const float gx1 = width - right, gy1 = height - bottom;
  d.shapes.push_back(
      archive_label(archive_number(map.x_lo), 2, left, gy1 + 16 * s, Anchor::kStart));
  d.shapes.push_back(archive_label(archive_number(map.x_hi), 2, gx1, gy1 + 16 * s, Anchor::kEnd));
  d.shapes.push_back(archive_label(map.x_name, 0, (left + gx1) / 2, gy1 + 34 * s, Anchor::kMiddle));
  d.shapes.push_back(archive_label(archive_number(map.y_lo), 2, left - 6 * s, gy1, Anchor::kEnd));
  d.shapes.push_back(
      archive_label(archive_number(map.y_hi), 2, left - 6 * s, top + 12 * s, Anchor::kEnd));
  d.shapes.push_back(
      archive_label(map.y_name, 0, left - 40 * s, (top + gy1) / 2, Anchor::kMiddle, true));
  // Legend: the fitness range, low at the bottom.
  const float lx = gx1 + 24 * s, lh = std::min(240 * s, gy1 - top);
  for (int i = 0; i < 32; ++i)
    d.shapes.push_back(RectShape{lx, top + lh - (i + 1) * lh / 32, 14 * s, lh / 32 + 1,
                                 archive_colour(i / 31.0), "", ""});
  d.shapes.push_back(
      archive_label(any ? archive_number(hi) : "-", 2, lx + 20 * s, top + 10 * s, Anchor::kStart));
  d.shapes.push_back(
      archive_label(any ? archive_number(lo) : "-", 2, lx + 20 * s, top + lh, Anchor::kStart));
  d.shapes.push_back(archive_label("fitness (" + map.fitness_unit + ")", 2, lx, top + lh + 20 * s,
                                   Anchor::kStart));
  d.shapes.push_back(RectShape{lx, top + lh + 30 * s, 14 * s, 10 * s, kArchiveEmpty, "", ""});
  d.shapes.push_back(archive_label("empty", 2, lx + 20 * s, top + lh + 40 * s, Anchor::kStart));
  return d;
}

}  // namespace plastivox::render
