// The drawing model behind the figure panels: a panel laid out once as plain shapes in pixel
// coordinates (origin top-left, y down), then written by two back ends, SVG text and a PNG drawn
// with Dear ImGui, which therefore agree on every position. Text is placed by its baseline and
// an anchor, so each back end measures glyphs itself (SVG leaves it to the viewer).
#pragma once

#include <cstdint>
#include <string>
#include <variant>
#include <vector>

#include "plastivox/render/panels.hpp"

namespace plastivox::render {

struct Rgb {  // opaque colour, sRGB
  uint8_t r = 0, g = 0, b = 0;
};

// A face the drawing uses: DejaVu Sans (regular or bold) at a pixel size; SVG names it
// "DejaVu Sans, Arial, Helvetica, sans-serif".
struct FontFace {
  float pixels = 16;
  bool bold = false;
};

struct RectShape {
  float x = 0, y = 0, w = 0, h = 0;  // pixels, top-left corner and size
  Rgb fill;
  std::string css_class;  // SVG class, e.g. "bar"
  std::string data;       // SVG data-group attribute (the treatment of a bar), or empty
};

struct CircleShape {
  float x = 0, y = 0, r = 0;  // pixels, centre and radius
  Rgb fill, stroke;           // outline 1 pixel wide (scaled like the panel's lines)
  float stroke_width = 1;
  std::string css_class;  // SVG class, e.g. "point"
  std::string data;       // SVG data-group attribute (the treatment), or empty
};

struct LineShape {
  float x0 = 0, y0 = 0, x1 = 0, y1 = 0;  // pixels
  float width = 1;                       // pixels
  Rgb color;
};

enum class Anchor { kStart, kMiddle, kEnd };

// One run of text in one face; a subscript run sits lower on a smaller face.
struct TextSpan {
  std::string text;  // UTF-8, Latin-1 range
  int font = 0;      // index into Drawing::fonts
  float dy = 0;      // baseline shift, pixels, + is down
};

struct TextShape {
  std::vector<TextSpan> spans;
  float x = 0, y = 0;  // pixels: the anchor point on the baseline
  Anchor anchor = Anchor::kStart;
  bool vertical = false;  // rotated 90 degrees counter-clockwise about (x, y): reads upwards
  Rgb color;
};

using Shape = std::variant<RectShape, LineShape, TextShape, CircleShape>;

struct Drawing {
  int width = 0, height = 0;    // pixels
  std::vector<FontFace> fonts;  // every face a TextSpan may name
  std::vector<Shape> shapes;    // painted in order
};

// Lays out one panel at width x height pixels (fonts and strokes scale with the size).
// Bars start at 0 so their heights are proportional to the means. Throws StatsError if a
// comparison names a treatment that has no group.
Drawing layout_panel(const PanelStats& panel, int width, int height);

// The evolution figure: generation on x, best fitness on y; per treatment a tinted 95 % CI
// band (a step per generation), one thin line per run and a thick line for the mean; a legend
// with each treatment's number of runs. Long runs are thinned to at most ~400 points a line.
Drawing layout_evolution(const EvolutionStats& evolution, int width, int height);

// The robustness battery's heat map: a row per perturbation, a column per treatment, each
// cell coloured by its mean fitness kept (diverging map: red below 1, white at 1, blue above)
// and labelled with it and its n; the significant tests beside each row.
Drawing layout_battery_heat_map(const BatteryHeatMap& map, int width, int height);
// The archive's map (ArchiveMap, panels.hpp): each cell coloured by the fitness of its best
// elite (a sequential map over the elites' range), empty cells grey, bin 0 of y at the bottom;
// the bounds and names on the axes.
Drawing layout_archive_map(const ArchiveMap& map, int width, int height);
// All panels in a grid of `columns` columns, each cell width x height.
Drawing layout_figure(const StatsFigure& figure, int width, int height, int columns = 3);

// The drawing as a standalone SVG 1.1 document (deterministic text).
std::string drawing_svg(const Drawing& drawing);

// The drawing rendered off-screen (OSMesa + Dear ImGui) on white: RGBA8, rows top-down.
std::vector<uint8_t> drawing_rgba(const Drawing& drawing);

}  // namespace plastivox::render
