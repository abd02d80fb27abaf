// write_figures: every panel of a stats.json as DIR/panel_<id>.svg and .png, the evolution
// curves as DIR/evolution.svg and .png, and all panels together as DIR/figure_5.svg and .png
// (three columns). Files are written whole to a temporary
// and renamed (write_file_atomic, write_png), so a failure never leaves half a figure.
#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "plastivox/io/atomic_file.hpp"
#include "plastivox/render/offscreen.hpp"
#include "plastivox/render/panel_drawing.hpp"
#include "plastivox/render/panels.hpp"
#include "plastivox/render/qd_curve.hpp"

namespace plastivox::render {
namespace {

constexpr int kMinSide = 200, kMaxSide = 8192;  // pixels per panel

// Writes the drawing as <stem>.svg and/or <stem>.png; appends the paths to `written`.
void write_drawing(const Drawing& d, const std::string& stem, const FigureOptions& o,
                   std::vector<std::string>& written) {
  if (o.svg) {
    write_file_atomic(stem + ".svg", drawing_svg(d));
    written.push_back(stem + ".svg");
  }
  if (o.png) {
    write_png(stem + ".png", drawing_rgba(d), d.width, d.height);
    written.push_back(stem + ".png");
  }
}

}  // namespace

void check_figure_size(const FigureOptions& o, int panels) {
  const std::string size = std::to_string(o.width) + "x" + std::to_string(o.height);
  if (o.width < kMinSide || o.height < kMinSide || o.width > kMaxSide || o.height > kMaxSide)
    throw RenderError("panel size " + size + " is outside " + std::to_string(kMinSide) + "x" +
                      std::to_string(kMinSide) + " .. " + std::to_string(kMaxSide) + "x" +
                      std::to_string(kMaxSide));
  // The combined figure: 3 columns, as layout_figure lays it out.
  const int columns = std::max(1, std::min(3, panels)), rows = (panels + columns - 1) / columns;
  const int64_t w = int64_t{o.width} * columns, h = int64_t{o.height} * rows;
  if (o.combined && o.png && (w > kMaxImageSide || h > kMaxImageSide))
    throw RenderError(
        "panel size " + size + " makes the combined figure " + std::to_string(w) + "x" +
        std::to_string(h) + ", more than " + std::to_string(kMaxImageSide) +
        " pixels a side (use smaller panels or, with plastivox figures, --no-combined)");
}

std::vector<std::string> write_figures(const StatsFigure& figure, const std::string& out_dir,
                                       const FigureOptions& o) {
  check_figure_size(o, static_cast<int>(figure.panels.size()));
  if (!o.png && !o.svg) throw RenderError("no output format chosen (png, svg or both)");
  if (figure.panels.empty()) throw StatsError(figure.source + ": no panels to draw");
  // Lay every panel out before writing anything, so bad data stops the run with no files.
  std::vector<Drawing> drawings;
  for (const PanelStats& p : figure.panels) drawings.push_back(layout_panel(p, o.width, o.height));
  if (figure.evolution) layout_evolution(*figure.evolution, o.width, o.height);  // checks it
  std::optional<Drawing> combined;
  if (o.combined) combined = layout_figure(figure, o.width, o.height);
  std::error_code ec;
  std::filesystem::create_directories(out_dir, ec);
  if (ec) throw RenderError(out_dir + ": cannot create the output directory: " + ec.message());

  std::vector<std::string> written;
  const std::filesystem::path dir(out_dir);
  for (size_t i = 0; i < drawings.size(); ++i) {
    write_drawing(drawings[i], (dir / ("panel_" + figure.panels[i].id)).string(), o, written);
  }
  if (figure.evolution)
    write_drawing(layout_evolution(*figure.evolution, o.width, o.height),
                  (dir / "evolution").string(), o, written);
  if (combined) write_drawing(*combined, (dir / "figure_5").string(), o, written);
  if (figure.battery) {
    const std::vector<std::string> more = write_battery_heat_map(*figure.battery, out_dir, o);
    written.insert(written.end(), more.begin(), more.end());
  }
  return written;
}

namespace {

// One drawing written as DIR/<stem>.{svg,png}, creating DIR.
std::vector<std::string> write_drawing_in(const Drawing& d, const std::string& out_dir,
                                          const std::string& stem, const FigureOptions& o) {
  std::error_code ec;
  std::filesystem::create_directories(out_dir, ec);
  if (ec) throw RenderError(out_dir + ": cannot create the output directory: " + ec.message());
  std::vector<std::string> written;
  write_drawing(d, (std::filesystem::path(out_dir) / stem).string(), o, written);
  return written;
}

}  // namespace

std::vector<std::string> write_battery_heat_map(const BatteryHeatMap& map,
                                                const std::string& out_dir,
                                                const FigureOptions& o) {
  return write_drawing_in(layout_battery_heat_map(map, o.width, o.height), out_dir,
                          "robustness_heatmap", o);
}

std::vector<std::string> write_archive_map(const ArchiveMap& map, const std::string& out_dir,
                                           const FigureOptions& o) {
  return write_drawing_in(layout_archive_map(map, o.width, o.height), out_dir, "archive", o);
}

std::vector<std::string> write_qd_curve(const QdCurve& curve, const std::string& out_dir,
                                        const FigureOptions& o) {
  return write_drawing_in(layout_qd_curve(curve, o.width, o.height), out_dir, "qd", o);
}

}  // namespace plastivox::render
