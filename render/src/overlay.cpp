#include "plastivox/render/overlay.hpp"

#include <sstream>
#include <vector>

#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "plastivox/render/offscreen.hpp"
#include "text_format.hpp"

namespace plastivox::render {
namespace {

const ImU32 kText = IM_COL32(34, 38, 46, 255);

ImU32 to_col(const Rgb8& c) {
  return IM_COL32(c[0], c[1], c[2], 255);
}

void text(ImDrawList* dl, ImFont* f, float x, float y, const std::string& s, ImU32 col = kText) {
  dl->AddText(f, f->FontSize, ImVec2(std::round(x), std::round(y)), col, s.c_str());
}

float text_width(ImFont* f, const std::string& s) {
  return f->CalcTextSizeA(f->FontSize, 1e9f, 0, s.c_str()).x;
}

}  // namespace

float overlay_text_px(int height) {
  return std::max(11.0f, std::round(height / 40.0f));
}

std::vector<FontSpec> overlay_fonts(int height) {
  const float px = overlay_text_px(height);
  return {{"DejaVuSans.ttf", px},
          {"DejaVuSans.ttf", std::max(10.0f, std::round(px * 0.8f))},
          {"DejaVuSans-Bold.ttf", px}};
}

void draw_colorbar(ImDrawList* dl, ImFont* label_font, ImFont* title_font, const ColorScale& scale,
                   float x, float y, float bar_w, float bar_h, float title_left,
                   float title_right) {
  const Colormap& map = scale.map();
  const int rows = static_cast<int>(std::round(bar_h));
  x = std::round(x);
  y = std::round(y);
  // Top row = high end of the scale.
  for (int r = 0; r < rows; ++r) {
    const double t = rows > 1 ? 1.0 - (r + 0.5) / rows : 0.5;
    dl->AddRectFilled(ImVec2(x, y + r), ImVec2(x + bar_w, y + r + 1), to_col(map.at(t)));
  }
  dl->AddRect(ImVec2(x - 1, y - 1), ImVec2(x + bar_w + 1, y + rows + 1), kText);
  const float tick = std::max(3.0f, bar_w * 0.25f);
  for (const Tick& t : scale.ticks()) {
    const float ty = std::round(y + (1.0f - static_cast<float>(t.t)) * rows);
    dl->AddLine(ImVec2(x + bar_w, ty), ImVec2(x + bar_w + tick, ty), kText, 1.0f);
    text(dl, label_font, x + bar_w + tick + 3, ty - label_font->FontSize * 0.55f, t.label);
  }
  const float line_h = title_font->FontSize * 1.25f;
  if (title_left >= 0 && title_right > title_left) {
    // Greedy line breaking at spaces within the column, lines centred, the last just above
    // the bar.
    std::vector<std::string> lines;
    std::string line, word;
    std::istringstream words(scale.title);
    while (words >> word) {
      const std::string longer = line.empty() ? word : line + " " + word;
      if (!line.empty() && text_width(title_font, longer) > title_right - title_left) {
        lines.push_back(line);
        line = word;
      } else {
        line = longer;
      }
    }
    if (!line.empty()) lines.push_back(line);
    float ty = y - title_font->FontSize * 0.35f - line_h * static_cast<float>(lines.size());
    for (const std::string& l : lines) {
      const float w = text_width(title_font, l);
      text(dl, title_font, std::round(title_left + (title_right - title_left - w) / 2), ty, l);
      ty += line_h;
    }
    return;
  }
  const float title_w = text_width(title_font, scale.title);
  // Title above the bar, right-aligned to the tick labels' column so it stays in the image.
  const float right = x + bar_w + tick + 3 + text_width(label_font, "10⁻⁰⁰");
  text(dl, title_font, std::min(x, right - title_w), y - title_font->FontSize * 1.6f, scale.title);
}

void draw_overlay(ImGuiLayer& ui, int width, int height, const ColorScale& scale,
                  const OverlayInfo& info, const OverlayOptions& options) {
  ImDrawList* dl = ui.draw_list();
  ImFont* body = ui.font(0);
  ImFont* small = ui.font(1);
  ImFont* bold = ui.font(2);
  const float px = body->FontSize;
  const float margin = std::round(px * 1.2f);

  // Text block, top-left.
  float y = margin;
  auto line = [&](const std::string& label, const std::string& value) {
    text(dl, bold, margin, y, label);
    text(dl, body, margin + text_width(bold, label), y, value);
    y += px * 1.3f;
  };
  if (options.time) line("t = ", format("%.2f s", info.time));
  if (options.treatment) line("treatment: ", info.treatment);
  if (options.displacement) line("displacement: ", format("%.2f voxel lengths", info.displacement));

  // Colour bar, right side.
  if (options.colorbar) {
    const float bar_h = std::round(height * 0.42f);
    const float bar_w = std::round(std::max(8.0f, px * 0.9f));
    const float labels = text_width(small, "10⁻⁰⁰") + std::max(3.0f, bar_w * 0.25f) + 3;
    const float x = width - margin - labels - bar_w;
    draw_colorbar(dl, small, body, scale, x, margin + px * 1.8f, bar_w, bar_h);
  }

  // Scale bar, bottom-left: a 1-2-5 number of voxel lengths about 12 % of the width.
  if (options.scalebar && info.pixels_per_metre > 0 && info.voxel_size > 0) {
    const double px_per_voxel = info.pixels_per_metre * info.voxel_size;
    double n = 1;
    for (double m : {1.0, 2.0, 5.0, 10.0, 20.0, 50.0, 100.0, 200.0, 500.0})
      if (m * px_per_voxel <= width * 0.15) n = m;
    const float len = static_cast<float>(std::round(n * px_per_voxel));
    const float by = height - margin - px * 1.6f;
    const float thick = std::max(2.0f, std::round(px * 0.22f));
    dl->AddRectFilled(ImVec2(margin, by), ImVec2(margin + len, by + thick), kText);
    dl->AddRectFilled(ImVec2(margin, by - thick * 1.5f), ImVec2(margin + thick * 0.7f, by + thick),
                      kText);
    dl->AddRectFilled(ImVec2(margin + len - thick * 0.7f, by - thick * 1.5f),
                      ImVec2(margin + len, by + thick), kText);
    const std::string label = format("%g", n) + (n == 1 ? " voxel length" : " voxel lengths") +
                              format(" (%g cm)", n * info.voxel_size * 100);
    text(dl, small, margin, by + thick + px * 0.3f, label);
  }
}

}  // namespace plastivox::render
