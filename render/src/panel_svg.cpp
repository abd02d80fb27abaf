// A Drawing as SVG 1.1 text: one element per shape in paint order, coordinates with at most two
// decimals, fonts named generically (DejaVu Sans, then Arial, Helvetica, any sans-serif), bars
// tagged class="bar" data-group="TREATMENT" (and the sample's points class="point") so they
// can be found and restyled by hand.
// Deterministic: the text depends only on the drawing.
#include <cmath>
#include <cstdio>
#include <string>

#include "plastivox/base/markup.hpp"
#include "plastivox/render/panel_drawing.hpp"

namespace plastivox::render {
namespace {

// "12.5", "3", "-0.25": fixed two decimals with trailing zeros dropped, never "-0".
std::string num(double v) {
  if (std::abs(v) < 0.005) v = 0;
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.2f", v);
  std::string s = buf;
  while (s.back() == '0') s.pop_back();
  if (s.back() == '.') s.pop_back();
  return s;
}

std::string colour(const Rgb& c) {
  char buf[8];
  std::snprintf(buf, sizeof buf, "#%02x%02x%02x", c.r, c.g, c.b);
  return buf;
}

std::string escape(const std::string& text) {
  return escape_markup(text, false);
}

std::string font_attributes(const FontFace& f) {
  return " font-size=\"" + num(f.pixels) + "\"" + (f.bold ? " font-weight=\"bold\"" : "");
}

void write(std::string& out, const RectShape& r, const Drawing&) {
  out += "<rect";
  if (!r.css_class.empty()) out += " class=\"" + escape(r.css_class) + "\"";
  if (!r.data.empty()) out += " data-group=\"" + escape(r.data) + "\"";
  out += " x=\"" + num(r.x) + "\" y=\"" + num(r.y) + "\" width=\"" + num(r.w) + "\" height=\"" +
         num(r.h) + "\" fill=\"" + colour(r.fill) + "\"/>\n";
}

void write(std::string& out, const LineShape& l, const Drawing&) {
  out += "<line x1=\"" + num(l.x0) + "\" y1=\"" + num(l.y0) + "\" x2=\"" + num(l.x1) + "\" y2=\"" +
         num(l.y1) + "\" stroke=\"" + colour(l.color) + "\" stroke-width=\"" + num(l.width) +
         "\" stroke-linecap=\"square\"/>\n";
}

void write(std::string& out, const CircleShape& c, const Drawing&) {
  out += "<circle";
  if (!c.css_class.empty()) out += " class=\"" + escape(c.css_class) + "\"";
  if (!c.data.empty()) out += " data-group=\"" + escape(c.data) + "\"";
  out += " cx=\"" + num(c.x) + "\" cy=\"" + num(c.y) + "\" r=\"" + num(c.r) + "\" fill=\"" +
         colour(c.fill) + "\" stroke=\"" + colour(c.stroke) + "\" stroke-width=\"" +
         num(c.stroke_width) + "\"/>\n";
}

void write(std::string& out, const TextShape& t, const Drawing& d) {
  static const char* anchors[] = {"start", "middle", "end"};
  out += "<text x=\"" + num(t.x) + "\" y=\"" + num(t.y) + "\"";
  if (t.anchor != Anchor::kStart)
    out += std::string(" text-anchor=\"") + anchors[static_cast<int>(t.anchor)] + "\"";
  if (t.vertical) out += " transform=\"rotate(-90 " + num(t.x) + " " + num(t.y) + ")\"";
  out += " fill=\"" + colour(t.color) + "\"";
  if (t.spans.size() == 1 && t.spans[0].dy == 0) {
    out += font_attributes(d.fonts.at(t.spans[0].font));
    out += '>';
    out += escape(t.spans[0].text);
    out += "</text>\n";
    return;
  }
  out += " xml:space=\"preserve\">";  // keep spaces at span edges ("F_test / F_train")
  float shift = 0;                    // tspan dy is relative to the previous span's baseline
  for (const TextSpan& span : t.spans) {
    out += "<tspan" + font_attributes(d.fonts.at(span.font));
    if (span.dy != shift) out += " dy=\"" + num(span.dy - shift) + "\"";
    shift = span.dy;
    out += '>';  // appended piecewise: GCC 12 warns falsely (-Wrestrict) on "<" + string
    out += escape(span.text);
    out += "</tspan>";
  }
  out += "</text>\n";
}

}  // namespace

std::string drawing_svg(const Drawing& d) {
  std::string out =
      "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
      "<svg xmlns=\"http://www.w3.org/2000/svg\" version=\"1.1\" width=\"" +
      std::to_string(d.width) + "\" height=\"" + std::to_string(d.height) + "\" viewBox=\"0 0 " +
      std::to_string(d.width) + " " + std::to_string(d.height) +
      "\" font-family=\"DejaVu Sans, Arial, Helvetica, sans-serif\">\n"
      "<rect width=\"100%\" height=\"100%\" fill=\"#ffffff\"/>\n";
  for (const Shape& shape : d.shapes) {
    std::visit([&](const auto& s) { write(out, s, d); }, shape);
  }
  out += "</svg>\n";
  return out;
}

}  // namespace plastivox::render
