// Laying out one Fig. 5 panel: a bar per treatment (mean, from zero), a 95 % CI error bar with
// caps, a y axis with "nice" ticks (1, 2, 5 x 10^k), treatment names and sample sizes under the
// bars, the metric as title, its unit as y label, the panel letter, and one bracket with stars
// per significant comparison, stacked so brackets never cross.
//
// Sizes are those of an 800 x 600 panel scaled by min(width/800, height/600). Bar edges are
// whole pixels, so a bar's height is its mean times the axis scale to within one pixel in the
// SVG and the PNG alike. Text widths are only estimated here (0.6 em a character, DejaVu Sans's
// average), to size the left margin; back ends align text by its anchor.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <map>
#include <string>

#include "plastivox/render/panel_drawing.hpp"

namespace plastivox::render {
namespace {

// Font indices of a panel drawing; panel_fonts() lists them in this order.
enum Font : int { kTick, kLabel, kLabelSub, kTitle, kTitleSub, kLetter, kStars, kSmall };

std::vector<FontFace> panel_fonts(float s) {
  const auto px = [s](float base) { return std::max(6.0f, std::round(base * s)); };
  return {{px(17), false}, {px(19), false}, {px(13), false}, {px(23), true},
          {px(16), true},  {px(34), true},  {px(24), true},  {px(14), false}};
}

constexpr Rgb kInk{0, 0, 0};
constexpr Rgb kGrey{90, 90, 90};

// Okabe-Ito colours (safe for colour-blind readers): the paper's three treatments first.
Rgb treatment_colour(const std::string& treatment, size_t index) {
  static const std::map<std::string, Rgb> known = {
      {"none", {153, 153, 153}}, {"stress", {0, 114, 178}}, {"pressure", {230, 159, 0}}};
  static const Rgb others[] = {{0, 158, 115}, {204, 121, 167}, {86, 180, 233}, {213, 94, 0}};
  const auto it = known.find(treatment);
  return it != known.end() ? it->second : others[index % 4];
}

// "M_body" -> "M" then subscript "body": '_' followed by letters or digits starts a subscript.
std::vector<TextSpan> markup(const std::string& text, int font, int sub_font, float sub_dy) {
  std::vector<TextSpan> spans;
  std::string run;
  const auto flush = [&](int f, float dy) {
    if (!run.empty()) spans.push_back({run, f, dy});
    run.clear();
  };
  for (size_t i = 0; i < text.size(); ++i) {
    if (text[i] == '_' && i + 1 < text.size() &&
        std::isalnum(static_cast<unsigned char>(text[i + 1]))) {
      flush(font, 0);
      size_t j = i + 1;
      while (j < text.size() && std::isalnum(static_cast<unsigned char>(text[j]))) run += text[j++];
      flush(sub_font, sub_dy);
      i = j - 1;
    } else {
      run += text[i];
    }
  }
  flush(font, 0);
  return spans;
}

TextShape text(std::vector<TextSpan> spans, float x, float y, Anchor anchor, Rgb color = kInk) {
  return TextShape{std::move(spans), x, y, anchor, false, color};
}
TextShape text(const std::string& s, int font, float x, float y, Anchor anchor, Rgb color = kInk) {
  return text({TextSpan{s, font, 0}}, x, y, anchor, color);
}

std::string display_treatment(std::string t) {
  if (!t.empty()) t[0] = static_cast<char>(std::toupper(static_cast<unsigned char>(t[0])));
  return t;
}

// Tick step: 1, 2 or 5 times a power of ten, giving about `target` intervals over span.
double nice_step(double span, int target) {
  const double raw = span / target;
  const double mag = std::pow(10.0, std::floor(std::log10(raw)));
  for (double m : {1.0, 2.0, 5.0}) {
    if (m * mag >= raw * (1 - 1e-9)) return m * mag;
  }
  return 10 * mag;
}

std::string tick_label(double v, double step) {
  char buf[32];
  if (std::abs(v) < step * 1e-6) v = 0;  // no "-0"
  if (step < 1e-4 || step >= 1e6) {
    std::snprintf(buf, sizeof buf, "%.1e", v);
  } else {
    const int decimals = std::clamp(static_cast<int>(std::ceil(-std::log10(step) - 1e-9)), 0, 6);
    std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
  }
  return buf;
}

// A group's extent: the values its bar and error bar reach (with 0, where bars start).
void extend(const PanelGroup& g, double& lo, double& hi) {
  for (const std::optional<double>& v : {g.mean, g.ci_low, g.ci_high}) {
    if (v) {
      lo = std::min(lo, *v);
      hi = std::max(hi, *v);
    }
  }
}

}  // namespace

Drawing layout_panel(const PanelStats& panel, int width, int height) {
  const float s = std::min(width / 800.0f, height / 600.0f);
  Drawing d;
  d.width = width;
  d.height = height;
  d.fonts = panel_fonts(s);
  const auto px = [&](Font f) { return d.fonts[f].pixels; };
  std::vector<Shape>& out = d.shapes;

  // The significant comparisons, as bar index pairs, narrowest first (they sit lowest).
  std::map<std::string, size_t> index;
  for (size_t i = 0; i < panel.groups.size(); ++i) index[panel.groups[i].treatment] = i;
  struct Bracket {
    size_t left, right;
    std::string stars;
  };
  std::vector<Bracket> brackets;
  for (const PanelComparison& c : panel.comparisons) {
    if (c.stars.empty()) continue;
    const auto a = index.find(c.a), b = index.find(c.b);
    if (a == index.end() || b == index.end())
      throw StatsError("panel " + panel.id + ": comparison " + c.a + " vs " + c.b +
                       " names a treatment without a group");
    brackets.push_back({std::min(a->second, b->second), std::max(a->second, b->second), c.stars});
  }
  std::stable_sort(brackets.begin(), brackets.end(), [](const Bracket& x, const Bracket& y) {
    return x.right - x.left < y.right - y.left;
  });

  // Value axis: 0 and every mean and CI bound, rounded out to whole ticks.
  double lo = 0, hi = 0;
  for (const PanelGroup& g : panel.groups) extend(g, lo, hi);
  if (hi - lo <= 0) hi = lo + 1;
  const double step = nice_step(hi - lo, 5);
  const long k_lo = static_cast<long>(std::floor(lo / step + 1e-9));
  const long k_hi = static_cast<long>(std::ceil(hi / step - 1e-9));
  const double axis_lo = k_lo * step, axis_hi = k_hi * step;

  // Frame: margins for the letter and title (top), y label and tick labels (left), treatment
  // names and n (bottom), and headroom above the axis for the brackets.
  const float pad = std::round(14 * s), tick_len = std::round(7 * s);
  size_t widest_tick = 1;
  for (long k = k_lo; k <= k_hi; ++k)
    widest_tick = std::max(widest_tick, tick_label(k * step, step).size());
  const float y_title = std::round(pad + 0.8f * px(kLetter));
  const float bracket_step = std::round(px(kStars) * 1.1f + 8 * s),
              bracket_gap = std::round(10 * s);
  const float plot_left = std::round(pad + px(kLabel) * 1.2f + 10 * s +
                                     0.6f * px(kTick) * widest_tick + tick_len + 5 * s);
  const float plot_right = std::round(width - 2 * pad);
  const float plot_top = std::round(y_title + 16 * s + brackets.size() * bracket_step);
  const float plot_bottom =
      std::round(height - pad - px(kSmall) * 1.4f - px(kLabel) * 1.2f - tick_len - 6 * s);
  const auto y_of = [&](double v) {
    return static_cast<float>(plot_bottom -
                              (v - axis_lo) / (axis_hi - axis_lo) * (plot_bottom - plot_top));
  };
  const float y_zero = std::round(y_of(0));

  // Panel letter and title.
  out.push_back(text(panel.id, kLetter, pad, y_title, Anchor::kStart));
  out.push_back(text(markup(panel.title, kTitle, kTitleSub, 0.25f * px(kTitle)),
                     std::round((plot_left + plot_right) / 2), y_title, Anchor::kMiddle));

  // Bars, error bars, names and sample sizes.
  const size_t n = std::max<size_t>(1, panel.groups.size());
  const float slot = (plot_right - plot_left) / n;
  const float bar_w = std::round(std::min(0.6f * slot, 160 * s));
  const float line_w = std::max(1.0f, std::round(1.5f * s * 2) / 2);
  std::vector<float> centre(panel.groups.size()), top(panel.groups.size());
  for (size_t i = 0; i < panel.groups.size(); ++i) {
    const PanelGroup& g = panel.groups[i];
    centre[i] = std::round(plot_left + (i + 0.5f) * slot);
    top[i] = y_zero;
    if (g.mean) {
      const float y_mean = std::round(y_of(*g.mean));
      out.push_back(RectShape{std::round(centre[i] - bar_w / 2), std::min(y_mean, y_zero), bar_w,
                              std::abs(y_zero - y_mean), treatment_colour(g.treatment, i), "bar",
                              g.treatment});
      top[i] = std::min(top[i], y_mean);
    } else {
      out.push_back(text("no data", kSmall, centre[i], y_zero - 6 * s, Anchor::kMiddle, kGrey));
      top[i] = y_zero - 6 * s - px(kSmall);
    }
    if (g.ci_low && g.ci_high) {
      const float y_low = y_of(*g.ci_low), y_high = y_of(*g.ci_high),
                  cap = std::round(bar_w * 0.15f);
      out.push_back(LineShape{centre[i], y_low, centre[i], y_high, line_w, kInk});
      out.push_back(LineShape{centre[i] - cap, y_low, centre[i] + cap, y_low, line_w, kInk});
      out.push_back(LineShape{centre[i] - cap, y_high, centre[i] + cap, y_high, line_w, kInk});
      top[i] = std::min(top[i], y_high);
    }
    const float y_name = plot_bottom + tick_len + 6 * s + 0.8f * px(kLabel);
    out.push_back(text(display_treatment(g.treatment), kLabel, centre[i], y_name, Anchor::kMiddle));
    out.push_back(text("n = " + std::to_string(g.n), kSmall, centre[i], y_name + px(kSmall) * 1.3f,
                       Anchor::kMiddle, kGrey));
  }

  // Axes: the y axis with ticks and labels, the zero line under the bars.
  out.push_back(LineShape{plot_left, y_of(axis_lo), plot_left, y_of(axis_hi), line_w, kInk});
  out.push_back(LineShape{plot_left, y_zero, plot_right, y_zero, line_w, kInk});
  for (long k = k_lo; k <= k_hi; ++k) {
    const float y = std::round(y_of(k * step));
    out.push_back(LineShape{plot_left - tick_len, y, plot_left, y, line_w, kInk});
    out.push_back(text(tick_label(k * step, step), kTick, plot_left - tick_len - 5 * s,
                       std::round(y + 0.35f * px(kTick)), Anchor::kEnd));
  }
  TextShape ylabel = text(markup(panel.unit, kLabel, kLabelSub, 0.25f * px(kLabel)),
                          std::round(pad + 0.8f * px(kLabel)),
                          std::round((y_of(axis_hi) + plot_bottom) / 2), Anchor::kMiddle);
  ylabel.vertical = true;
  out.push_back(std::move(ylabel));

  // Brackets: each just above the highest bar or error bar it spans and above every bracket
  // placed before it that it overlaps.
  std::vector<std::pair<Bracket, float>> placed;
  const float drop = std::round(6 * s);  // legs stop short of the bars
  for (const Bracket& b : brackets) {
    float y = *std::min_element(top.begin() + b.left, top.begin() + b.right + 1) - bracket_gap;
    for (const auto& [other, oy] : placed) {
      if (other.left <= b.right && b.left <= other.right) y = std::min(y, oy - bracket_step);
    }
    y = std::round(y);
    placed.emplace_back(b, y);
    const float xl = centre[b.left], xr = centre[b.right];
    out.push_back(LineShape{xl, y + drop, xl, y, line_w, kInk});
    out.push_back(LineShape{xl, y, xr, y, line_w, kInk});
    out.push_back(LineShape{xr, y, xr, y + drop, line_w, kInk});
    out.push_back(text(b.stars, kStars, std::round((xl + xr) / 2), y - 4 * s + 0.3f * px(kStars),
                       Anchor::kMiddle));
  }
  return d;
}

Drawing layout_figure(const StatsFigure& figure, int width, int height, int columns) {
  const int cells = static_cast<int>(figure.panels.size());
  columns = std::max(1, std::min(columns, cells));
  const int rows = (cells + columns - 1) / columns;
  Drawing all;
  all.width = width * columns;
  all.height = height * rows;
  for (int i = 0; i < cells; ++i) {
    Drawing one = layout_panel(figure.panels[i], width, height);
    all.fonts = one.fonts;  // the same for every panel of one size
    const float dx = static_cast<float>(width * (i % columns)),
                dy = static_cast<float>(height * (i / columns));
    for (Shape& shape : one.shapes) {
      std::visit(
          [&](auto& sh) {
            if constexpr (std::is_same_v<std::decay_t<decltype(sh)>, LineShape>) {
              sh.x0 += dx, sh.x1 += dx, sh.y0 += dy, sh.y1 += dy;
            } else {
              sh.x += dx, sh.y += dy;
            }
          },
          shape);
      all.shapes.push_back(std::move(shape));
    }
  }
  return all;
}

}  // namespace plastivox::render
