// write_figures: every panel of a stats.json as DIR/panel_<id>.svg and .png, the evolution
// curves as DIR/evolution.svg and .png, and all panels together as DIR/figure_5.svg and .png
// (three columns). Files are written whole to a temporary
// and renamed (write_file_atomic, write_png), so a failure never leaves half a figure.
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "plastivox/atomic_file.hpp"
#include "plastivox/render/offscreen.hpp"
#include "plastivox/render/panel_drawing.hpp"
#include "plastivox/render/panels.hpp"

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

std::vector<std::string> write_figures(const StatsFigure& figure, const std::string& out_dir,
                                       const FigureOptions& o) {
  if (o.width < kMinSide || o.height < kMinSide || o.width > kMaxSide || o.height > kMaxSide)
    throw RenderError("panel size " + std::to_string(o.width) + "x" + std::to_string(o.height) +
                      " is outside " + std::to_string(kMinSide) + "x" + std::to_string(kMinSide) +
                      " .. " + std::to_string(kMaxSide) + "x" + std::to_string(kMaxSide));
  if (!o.png && !o.svg) throw RenderError("no output format chosen (png, svg or both)");
  if (figure.panels.empty()) throw StatsError(figure.source + ": no panels to draw");
  // Lay every panel out before writing anything, so bad data stops the run with no files.
  std::vector<Drawing> drawings;
  for (const PanelStats& p : figure.panels) drawings.push_back(layout_panel(p, o.width, o.height));
  if (figure.evolution) layout_evolution(*figure.evolution, o.width, o.height);  // checks it
  std::optional<Drawing> combined;
  if (o.combined) {  // its size too, before anything is drawn
    combined = layout_figure(figure, o.width, o.height);
    if (o.png && (combined->width > kMaxImageSide || combined->height > kMaxImageSide))
      throw RenderError("panel size " + std::to_string(o.width) + "x" + std::to_string(o.height) +
                        " makes the combined figure " + std::to_string(combined->width) + "x" +
                        std::to_string(combined->height) + ", more than " +
                        std::to_string(kMaxImageSide) +
                        " pixels a side (use a smaller --size, "
                        "or --no-combined)");
  }
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
  return written;
}

}  // namespace plastivox::render
