// A Drawing rasterised with Dear ImGui into an OSMesa off-screen context (offscreen.hpp).
// Rectangles are filled quads; axis-aligned lines are drawn as filled rectangles with square
// ends, exactly the area the SVG's stroke-linecap="square" lines cover; text is placed by its
// baseline (ImGui places a line by its top: top = baseline - ascent) and anchored with ImGui's
// own glyph measurements; vertical text is drawn horizontally and its vertices rotated.
#include <imgui.h>

#include <algorithm>
#include <cfloat>
#include <cmath>

#include "plastivox/render/offscreen.hpp"
#include "plastivox/render/panel_drawing.hpp"

namespace plastivox::render {
namespace {

ImU32 im_colour(const Rgb& c) {
  return IM_COL32(c.r, c.g, c.b, 255);
}

class Painter {
 public:
  Painter(ImGuiLayer& ui, const Drawing& d)
      : ui_(ui),
        dl_(ui.draw_list()),
        width_(static_cast<float>(d.width)),
        height_(static_cast<float>(d.height)) {}

  void operator()(const RectShape& r) {
    dl_->AddRectFilled({r.x, r.y}, {r.x + r.w, r.y + r.h}, im_colour(r.fill));
  }

  // The SVG's stroke is centred on the circle's edge: the filled disc out to r + w/2 in the
  // stroke colour, then the fill inside r - w/2.
  void operator()(const CircleShape& c) {
    const float h = c.stroke_width / 2;
    dl_->AddCircleFilled({c.x, c.y}, c.r + h, im_colour(c.stroke), 32);
    dl_->AddCircleFilled({c.x, c.y}, std::max(0.0f, c.r - h), im_colour(c.fill), 32);
  }

  void operator()(const LineShape& l) {
    const float h = l.width / 2;
    if (l.x0 == l.x1 || l.y0 == l.y1) {
      dl_->AddRectFilled({std::min(l.x0, l.x1) - h, std::min(l.y0, l.y1) - h},
                         {std::max(l.x0, l.x1) + h, std::max(l.y0, l.y1) + h}, im_colour(l.color));
    } else {
      dl_->AddLine({l.x0, l.y0}, {l.x1, l.y1}, im_colour(l.color), l.width);
    }
  }

  void operator()(const TextShape& t) {
    // Vertical text is laid out horizontally about the image centre (ImGui culls glyphs outside
    // the image, which the text might cross before it is turned), then rotated into place.
    const ImVec2 at =
        t.vertical ? ImVec2(std::round(width_ / 2), std::round(height_ / 2)) : ImVec2(t.x, t.y);
    float total = 0;
    for (const TextSpan& s : t.spans) total += advance(s);
    float x = at.x - (t.anchor == Anchor::kMiddle ? total / 2
                      : t.anchor == Anchor::kEnd  ? total
                                                  : 0);
    x = std::round(x);
    const int first_vertex = dl_->VtxBuffer.Size;
    for (const TextSpan& s : t.spans) {
      ImFont* font = ui_.font(s.font);
      const float top = std::round(at.y + s.dy - font->Ascent);
      dl_->AddText(font, font->FontSize, {x, top}, im_colour(t.color), s.text.c_str());
      x += advance(s);
    }
    if (t.vertical) {
      // Rotate 90 degrees counter-clockwise (right becomes up) and move onto (t.x, t.y).
      for (int i = first_vertex; i < dl_->VtxBuffer.Size; ++i) {
        ImVec2& p = dl_->VtxBuffer[i].pos;
        p = ImVec2(t.x + (p.y - at.y), t.y - (p.x - at.x));
      }
    }
  }

 private:
  float advance(const TextSpan& s) const {
    ImFont* font = ui_.font(s.font);
    return font->CalcTextSizeA(font->FontSize, FLT_MAX, 0, s.text.c_str()).x;
  }

  ImGuiLayer& ui_;
  ImDrawList* dl_;
  float width_, height_;  // pixels
};

}  // namespace

std::vector<uint8_t> drawing_rgba(const Drawing& d) {
  OffscreenContext ctx(d.width, d.height);
  ctx.clear(1, 1, 1);
  {
    std::vector<FontSpec> fonts;
    for (const FontFace& f : d.fonts)
      fonts.push_back({f.bold ? "DejaVuSans-Bold.ttf" : "DejaVuSans.ttf", f.pixels});
    ImGuiLayer ui(ctx, fonts);
    ui.begin_frame();
    Painter paint(ui, d);
    for (const Shape& shape : d.shapes) std::visit(paint, shape);
    ui.end_frame_and_render();
  }
  return ctx.read_rgba();
}

}  // namespace plastivox::render
