// The 2-D overlay drawn with Dear ImGui over a rendered frame: colour bar with labelled
// ticks, simulated time, treatment, displacement so far and a scale bar in voxel lengths.
#pragma once

#include <string>
#include <vector>

#include "plastivox/render/color_scale.hpp"
#include "plastivox/render/offscreen.hpp"

namespace plastivox::render {

struct OverlayOptions {
  bool colorbar = true;
  bool time = true;
  bool treatment = true;
  bool displacement = true;
  bool scalebar = true;
  bool any() const { return colorbar || time || treatment || displacement || scalebar; }
};

struct OverlayInfo {
  double time = 0;              // simulated time, s
  std::string treatment;        // "none", "stress", "pressure" (or a caption)
  double displacement = 0;      // centre-of-mass displacement since settling, voxel lengths
  double voxel_size = 0.01;     // m
  double pixels_per_metre = 0;  // image scale at the robot (0: no scale bar)
};

// Font sizes for an image `height` pixels tall: text (1/40 of the height, at least 11 px)
// and the smaller tick labels.
float overlay_text_px(int height);

// Fonts an overlay needs, in the order draw_overlay() expects them: text, small, bold.
std::vector<FontSpec> overlay_fonts(int height);

// Draws the overlay into a frame begun on `ui` (fonts from overlay_fonts()).
void draw_overlay(ImGuiLayer& ui, int width, int height, const ColorScale& scale,
                  const OverlayInfo& info, const OverlayOptions& options);

// A vertical colour bar with its title above and tick labels to its right, inside the box
// (x, y, w, h) in pixels; the bar itself takes `bar_w` pixels on the box's left. Each pixel
// row is filled with the map's exact colour at that position. Without a title column the
// title is right-aligned to the tick labels; with one ([title_left, title_right], pixels) it
// is centred in it, broken at spaces into as many lines as it needs to fit.
void draw_colorbar(ImDrawList* dl, ImFont* label_font, ImFont* title_font, const ColorScale& scale,
                   float x, float y, float bar_w, float bar_h, float title_left = -1,
                   float title_right = -1);

}  // namespace plastivox::render
