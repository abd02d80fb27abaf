// Laying out one Fig. 5 panel: a bar per treatment (mean, from zero), a 95 % CI error bar with
// caps, the sample's values as points over the bar when there are at most 30 (kMaxPanelPoints;
// spread sideways where they would overlap, so each one shows), a y axis with "nice" ticks (1, 2, 5
// x 10^k), treatment names and sample sizes under the bars, the metric as title, its unit as y
// label, the panel letter, and one bracket with stars per significant comparison, stacked so
// brackets never cross.
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
constexpr Rgb kWhite{255, 255, 255};
constexpr Rgb kPointFill{40, 40, 40};

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

// The significant comparisons as bar index pairs, narrowest first (they are placed lowest).
struct Bracket {
  size_t left, right;  // bar indices, left < right
  std::string stars;
};

std::vector<Bracket> significant_brackets(const PanelStats& panel) {
  std::map<std::string, size_t> index;
  for (size_t i = 0; i < panel.groups.size(); ++i) index[panel.groups[i].treatment] = i;
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
  return brackets;
}

struct ValueAxis {  // ticks k * step
  double step = 1;
  long k_lo = 0, k_hi = 1;  // ticks k_lo * step .. k_hi * step
  double lo() const { return k_lo * step; }
  double hi() const { return k_hi * step; }
};

// About five ticks from lo to hi (values), rounded out to whole ticks.
ValueAxis axis_over(double lo, double hi) {
  if (hi - lo <= 0) hi = lo + 1;
  ValueAxis a;
  a.step = nice_step(hi - lo, 5);
  a.k_lo = static_cast<long>(std::floor(lo / a.step + 1e-9));
  a.k_hi = static_cast<long>(std::ceil(hi / a.step - 1e-9));
  return a;
}

// Whether a group's values are drawn as points.
bool shows_points(const PanelGroup& g) {
  return !g.values.empty() && g.values.size() <= static_cast<size_t>(kMaxPanelPoints);
}

// The value axis: 0, every mean and CI bound and every point drawn, rounded out to whole ticks.
ValueAxis value_axis(const PanelStats& panel) {
  double lo = 0, hi = 0;
  for (const PanelGroup& g : panel.groups) {
    for (const std::optional<double>& v : {g.mean, g.ci_low, g.ci_high}) {
      if (v) lo = std::min(lo, *v), hi = std::max(hi, *v);
    }
    if (shows_points(g))
      for (double v : g.values)
        if (std::isfinite(v)) lo = std::min(lo, v), hi = std::max(hi, v);
  }
  return axis_over(lo, hi);
}

// ---- The geometry both figures share ---------------------------------------------------

// Scale, fonts, the value axis and the margins that follow from them: padding, tick length,
// line width, the title's baseline and the plot's left edge (right of the y tick labels) and
// right edge. Each figure sets its own top and bottom.
struct FigureGeometry {
  float s = 1;  // scale of an 800 x 600 figure
  std::vector<FontFace> fonts;
  ValueAxis axis;
  float pad = 0, tick_len = 0, line_w = 1, y_title = 0;
  float left = 0, right = 0, top = 0, bottom = 0;  // plot area

  float px(Font f) const { return fonts[f].pixels; }
  float y_of(double v) const {
    return static_cast<float>(bottom - (v - axis.lo()) / (axis.hi() - axis.lo()) * (bottom - top));
  }
};

FigureGeometry figure_geometry(const ValueAxis& axis, int width, int height) {
  FigureGeometry f;
  f.s = std::min(width / 800.0f, height / 600.0f);
  f.fonts = panel_fonts(f.s);
  f.axis = axis;
  f.pad = std::round(14 * f.s);
  f.tick_len = std::round(7 * f.s);
  f.line_w = std::max(1.0f, std::round(1.5f * f.s * 2) / 2);
  size_t widest_tick = 1;
  for (long k = axis.k_lo; k <= axis.k_hi; ++k)
    widest_tick = std::max(widest_tick, tick_label(k * axis.step, axis.step).size());
  f.y_title = std::round(f.pad + 0.8f * f.px(kLetter));
  f.left = std::round(f.pad + f.px(kLabel) * 1.2f + 10 * f.s + 0.6f * f.px(kTick) * widest_tick +
                      f.tick_len + 5 * f.s);
  f.right = std::round(width - 2 * f.pad);
  return f;
}

// ---- A bar panel --------------------------------------------------------------------------

// Where everything of one bar panel goes, in pixels. Margins: letter and title (top), y label
// and tick labels (left), treatment names and n (bottom), and headroom above the axis for the
// brackets.
struct PanelGeometry : FigureGeometry {
  float bracket_step = 0, y_zero = 0;
  float bar_w = 0;
  std::vector<float> centre;  // per bar: centre x
};

PanelGeometry panel_geometry(const PanelStats& panel, size_t brackets, int width, int height) {
  PanelGeometry f;
  static_cast<FigureGeometry&>(f) = figure_geometry(value_axis(panel), width, height);
  f.bracket_step = std::round(f.px(kStars) * 1.1f + 8 * f.s);
  f.top = std::round(f.y_title + 16 * f.s + brackets * f.bracket_step);
  f.bottom =
      std::round(height - f.pad - f.px(kSmall) * 1.4f - f.px(kLabel) * 1.2f - f.tick_len - 6 * f.s);
  f.y_zero = std::round(f.y_of(0));
  const size_t slots = std::max<size_t>(1, panel.groups.size());
  const float slot = (f.right - f.left) / slots;
  f.bar_w = std::round(std::min(0.6f * slot, 160 * f.s));
  for (size_t i = 0; i < panel.groups.size(); ++i)
    f.centre.push_back(std::round(f.left + (i + 0.5f) * slot));
  return f;
}

// The drawing a figure's parts are added to, in the order they are drawn, with its geometry
// (PanelGeometry or EvolutionGeometry: where things go, and the line width).
template <class Geometry>
struct Canvas {
  const Geometry& f;
  Drawing& d;
  void add(Shape shape) { d.shapes.push_back(std::move(shape)); }
  void line(float x0, float y0, float x1, float y1) {
    add(LineShape{x0, y0, x1, y1, f.line_w, kInk});
  }
};
using PanelCanvas = Canvas<PanelGeometry>;

void add_titles(PanelCanvas& c, const PanelStats& panel) {
  const PanelGeometry& f = c.f;
  c.add(text(panel.id, kLetter, f.pad, f.y_title, Anchor::kStart));
  c.add(text(markup(panel.title, kTitle, kTitleSub, 0.25f * f.px(kTitle)),
             std::round((f.left + f.right) / 2), f.y_title, Anchor::kMiddle));
}

// The group's values as dots centred on x, from the lowest value up; a dot that would
// overlap one already placed moves sideways (right, left, further right, ...) within the
// bar's width. Returns the highest dot's top edge.
float add_points(PanelCanvas& c, const PanelGroup& g, float x) {
  const PanelGeometry& f = c.f;
  const float r = std::max(2.5f, std::round(4.5f * f.s * 2) / 2);
  const float stroke = std::max(1.0f, std::round(1.0f * f.s * 2) / 2);
  const float reach = std::max(0.0f, f.bar_w / 2 - r);
  std::vector<size_t> order(g.values.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(),
                   [&](size_t a, size_t b) { return g.values[a] < g.values[b]; });
  std::vector<std::pair<float, float>> placed;
  float top = f.y_zero;
  for (const size_t i : order) {
    if (!std::isfinite(g.values[i])) continue;
    const float y = f.y_of(g.values[i]);
    float dx = 0;
    for (int k = 1;; ++k) {
      bool clear = true;
      for (const auto& [px, py] : placed) clear = clear && std::hypot(x + dx - px, y - py) >= 2 * r;
      if (clear) break;
      const float next = r * static_cast<float>((k + 1) / 2) * (k % 2 ? 1.0f : -1.0f);
      if (std::abs(next) > reach) break;  // no room left: overlap at the last place tried
      dx = next;
    }
    placed.emplace_back(x + dx, y);
    c.add(CircleShape{std::round((x + dx) * 2) / 2, std::round(y * 2) / 2, r, kPointFill, kWhite,
                      stroke, "point", g.treatment});
    top = std::min(top, y - r);
  }
  return top;
}

// Bar i from zero (or "no data"), its error bar with caps, its points, its treatment's name
// and sample size. Returns its highest point: where the brackets above it start.
float add_bar(PanelCanvas& c, const PanelGroup& g, size_t i) {
  const PanelGeometry& f = c.f;
  const float x = f.centre[i];
  float top = f.y_zero;
  if (g.mean) {
    const float y_mean = std::round(f.y_of(*g.mean));
    c.add(RectShape{std::round(x - f.bar_w / 2), std::min(y_mean, f.y_zero), f.bar_w,
                    std::abs(f.y_zero - y_mean), treatment_colour(g.treatment, i), "bar",
                    g.treatment});
    top = std::min(top, y_mean);
  } else {
    c.add(text("no data", kSmall, x, f.y_zero - 6 * f.s, Anchor::kMiddle, kGrey));
    top = f.y_zero - 6 * f.s - f.px(kSmall);
  }
  if (g.ci_low && g.ci_high) {
    const float lo = f.y_of(*g.ci_low), hi = f.y_of(*g.ci_high), cap = std::round(f.bar_w * 0.15f);
    c.line(x, lo, x, hi);
    c.line(x - cap, lo, x + cap, lo);
    c.line(x - cap, hi, x + cap, hi);
    top = std::min(top, hi);
  }
  if (shows_points(g)) top = std::min(top, add_points(c, g, x));
  const float y_name = f.bottom + f.tick_len + 6 * f.s + 0.8f * f.px(kLabel);
  c.add(text(display_treatment(g.treatment), kLabel, x, y_name, Anchor::kMiddle));
  c.add(text("n = " + std::to_string(g.n), kSmall, x, y_name + f.px(kSmall) * 1.3f, Anchor::kMiddle,
             kGrey));
  return top;
}

// The y axis with ticks, tick labels and the unit; the zero line under the bars.
void add_value_axis(PanelCanvas& c, const std::string& unit) {
  const PanelGeometry& f = c.f;
  const ValueAxis& a = f.axis;
  c.line(f.left, f.y_of(a.lo()), f.left, f.y_of(a.hi()));
  c.line(f.left, f.y_zero, f.right, f.y_zero);
  for (long k = a.k_lo; k <= a.k_hi; ++k) {
    const float y = std::round(f.y_of(k * a.step));
    c.line(f.left - f.tick_len, y, f.left, y);
    c.add(text(tick_label(k * a.step, a.step), kTick, f.left - f.tick_len - 5 * f.s,
               std::round(y + 0.35f * f.px(kTick)), Anchor::kEnd));
  }
  TextShape label = text(markup(unit, kLabel, kLabelSub, 0.25f * f.px(kLabel)),
                         std::round(f.pad + 0.8f * f.px(kLabel)),
                         std::round((f.y_of(a.hi()) + f.bottom) / 2), Anchor::kMiddle);
  label.vertical = true;
  c.add(std::move(label));
}

// Each bracket just above the highest bar or error bar it spans (`bar_top`, per bar), and a
// step above every bracket placed before it that it overlaps; legs stop short of the bars.
void add_brackets(PanelCanvas& c, const std::vector<Bracket>& brackets,
                  const std::vector<float>& bar_top) {
  const PanelGeometry& f = c.f;
  const float gap = std::round(10 * f.s), leg = std::round(6 * f.s);
  std::vector<std::pair<Bracket, float>> placed;
  for (const Bracket& b : brackets) {
    float y = *std::min_element(bar_top.begin() + b.left, bar_top.begin() + b.right + 1) - gap;
    for (const auto& [other, other_y] : placed) {
      if (other.left <= b.right && b.left <= other.right) y = std::min(y, other_y - f.bracket_step);
    }
    y = std::round(y);
    placed.emplace_back(b, y);
    const float xl = f.centre[b.left], xr = f.centre[b.right];
    c.line(xl, y + leg, xl, y);
    c.line(xl, y, xr, y);
    c.line(xr, y, xr, y + leg);
    c.add(text(b.stars, kStars, std::round((xl + xr) / 2), y - 4 * f.s + 0.3f * f.px(kStars),
               Anchor::kMiddle));
  }
}

// ---- The evolution figure ----------------------------------------------------------------

// c mixed with white: amount 0 = c, 1 = white (opaque tints stand in for transparency).
Rgb tint(Rgb c, float amount) {
  const auto mix = [&](uint8_t v) {
    return static_cast<uint8_t>(std::lround(v + (255 - v) * amount));
  };
  return {mix(c.r), mix(c.g), mix(c.b)};
}

// Where everything of the evolution figure goes, in pixels, and the axes: generations
// 0..last; fitness over every value drawn, from 0 when all are >= 0.
struct EvolutionGeometry : FigureGeometry {
  int last = -1;  // last generation
  double x_step = 1;
  std::map<std::string, size_t> colour_index;  // treatment -> colour index

  float x_of(double g) const {
    return static_cast<float>(left + (last > 0 ? g / last : 0.5) * (right - left));
  }
  Rgb colour(const std::string& treatment) const {
    return treatment_colour(treatment, colour_index.at(treatment));
  }
  // Generations drawn: every one up to ~400, else every k-th and the last.
  std::vector<int> thinned() const {
    const int every = std::max(1, (last + 399) / 400);
    std::vector<int> g;
    for (int k = 0; k <= last; k += every) g.push_back(k);
    if (g.back() != last) g.push_back(last);
    return g;
  }
};

EvolutionGeometry evolution_geometry(const EvolutionStats& e, int width, int height) {
  int last = -1;
  double lo = 0, hi = 0;
  bool any = false;
  const auto see = [&](const std::vector<std::optional<double>>& v) {
    last = std::max(last, static_cast<int>(v.size()) - 1);
    for (const auto& x : v)
      if (x) {
        lo = any ? std::min(lo, *x) : std::min(0.0, *x);
        hi = any ? std::max(hi, *x) : std::max(0.0, *x);
        any = true;
      }
  };
  for (const EvolutionRunCurve& r : e.runs) see(r.best);
  for (const EvolutionTreatmentBand& b : e.treatments) {
    see(b.mean);
    see(b.ci_low);
    see(b.ci_high);
  }
  if (last < 0) throw StatsError("evolution: no generations to draw");

  EvolutionGeometry f;
  static_cast<FigureGeometry&>(f) = figure_geometry(axis_over(lo, hi), width, height);
  f.last = last;
  f.x_step = last > 0 ? nice_step(last, 6) : 1;
  if (f.x_step < 1) f.x_step = 1;
  for (size_t i = 0; i < e.treatments.size(); ++i) f.colour_index[e.treatments[i].treatment] = i;
  for (const EvolutionRunCurve& r : e.runs)
    f.colour_index.emplace(r.treatment, f.colour_index.size());  // a run without a band
  f.top = std::round(f.y_title + 20 * f.s);
  f.bottom =
      std::round(height - f.pad - f.px(kLabel) * 1.3f - f.px(kTick) * 1.2f - f.tick_len - 6 * f.s);
  return f;
}

using EvolutionCanvas = Canvas<EvolutionGeometry>;

// 95 % CI per generation as a step: one rectangle per generation drawn, in a light tint.
void add_bands(EvolutionCanvas& c, const EvolutionStats& e) {
  const EvolutionGeometry& f = c.f;
  const std::vector<int> g = f.thinned();
  for (const EvolutionTreatmentBand& b : e.treatments) {
    const Rgb fill = tint(f.colour(b.treatment), 0.8f);
    for (size_t i = 0; i < g.size(); ++i) {
      const int k = g[i];
      if (k >= static_cast<int>(b.mean.size()) || !b.ci_low[k] || !b.ci_high[k]) continue;
      const double half = (i + 1 < g.size() ? g[i + 1] - k : (i > 0 ? k - g[i - 1] : 1)) / 2.0;
      const float x0 = std::max(f.left, f.x_of(k - half)), x1 = std::min(f.right, f.x_of(k + half));
      const float y0 = f.y_of(*b.ci_high[k]), y1 = f.y_of(*b.ci_low[k]);
      c.add(RectShape{x0, y0, std::max(0.0f, x1 - x0), std::max(1.0f, y1 - y0), fill, "band",
                      b.treatment});
    }
  }
}

void add_polyline(EvolutionCanvas& c, const std::vector<std::optional<double>>& v, float width,
                  Rgb colour) {
  const EvolutionGeometry& f = c.f;
  const std::vector<int> g = f.thinned();
  for (size_t i = 1; i < g.size(); ++i) {
    const int a = g[i - 1], b = g[i];
    if (b >= static_cast<int>(v.size()) || !v[a] || !v[b]) continue;
    c.add(LineShape{f.x_of(a), f.y_of(*v[a]), f.x_of(b), f.y_of(*v[b]), width, colour});
  }
}

void add_lines(EvolutionCanvas& c, const EvolutionStats& e) {
  const EvolutionGeometry& f = c.f;
  const float thin = std::max(1.0f, std::round(1.0f * f.s * 2) / 2);
  // Each band's edges over every fill, so a band under another one still shows.
  for (const EvolutionTreatmentBand& b : e.treatments)
    for (const auto* edge : {&b.ci_low, &b.ci_high})
      add_polyline(c, *edge, thin, tint(f.colour(b.treatment), 0.5f));
  for (const EvolutionRunCurve& r : e.runs)
    add_polyline(c, r.best, thin, tint(f.colour(r.treatment), 0.35f));
  for (const EvolutionTreatmentBand& b : e.treatments)
    add_polyline(c, b.mean, std::max(1.5f, std::round(3.0f * f.s * 2) / 2), f.colour(b.treatment));
}

void add_axes(EvolutionCanvas& c, const EvolutionStats& e) {
  const EvolutionGeometry& f = c.f;
  c.line(f.left, f.top, f.left, f.bottom);
  c.line(f.left, f.bottom, f.right, f.bottom);
  for (long k = f.axis.k_lo; k <= f.axis.k_hi; ++k) {
    const float y = std::round(f.y_of(k * f.axis.step));
    c.line(f.left - f.tick_len, y, f.left, y);
    c.add(text(tick_label(k * f.axis.step, f.axis.step), kTick, f.left - f.tick_len - 5 * f.s,
               std::round(y + 0.35f * f.px(kTick)), Anchor::kEnd));
  }
  for (double g = 0; g <= f.last + 1e-9; g += f.x_step) {
    const float x = std::round(f.x_of(g));
    c.line(x, f.bottom, x, f.bottom + f.tick_len);
    c.add(text(tick_label(g, f.x_step), kTick, x,
               std::round(f.bottom + f.tick_len + 4 * f.s + f.px(kTick)), Anchor::kMiddle));
  }
  c.add(text("generation", kLabel, std::round((f.left + f.right) / 2),
             std::round(c.d.height - f.pad), Anchor::kMiddle));
  TextShape unit =
      text("best fitness (" + e.unit + ")", kLabel, std::round(f.pad + 0.8f * f.px(kLabel)),
           std::round((f.top + f.bottom) / 2), Anchor::kMiddle);
  unit.vertical = true;
  c.add(std::move(unit));
}

// Top left of the plot: a swatch and "Stress (2 runs)" per treatment, then the key.
void add_legend(EvolutionCanvas& c, const EvolutionStats& e) {
  const EvolutionGeometry& f = c.f;
  float y = f.top + f.px(kSmall) * 1.4f;
  const float x = f.left + 14 * f.s, sw = std::round(22 * f.s);
  for (const EvolutionTreatmentBand& b : e.treatments) {
    const Rgb colour = f.colour(b.treatment);
    c.add(RectShape{x, std::round(y - 0.7f * f.px(kSmall)), sw, std::round(0.7f * f.px(kSmall)),
                    tint(colour, 0.72f), "legend", b.treatment});
    c.add(LineShape{x, std::round(y - 0.35f * f.px(kSmall)), x + sw,
                    std::round(y - 0.35f * f.px(kSmall)), std::max(1.5f, 3.0f * f.s), colour});
    c.add(text(display_treatment(b.treatment) + " (" + std::to_string(b.runs) +
                   (b.runs == 1 ? " run)" : " runs)"),
               kSmall, x + sw + 8 * f.s, y, Anchor::kStart));
    y += f.px(kSmall) * 1.5f;
  }
  c.add(text("thick: mean over runs; band: 95 % bootstrap CI; thin: each run", kSmall, x, y,
             Anchor::kStart, kGrey));
}

}  // namespace

Drawing layout_panel(const PanelStats& panel, int width, int height) {
  const std::vector<Bracket> brackets = significant_brackets(panel);
  const PanelGeometry geometry = panel_geometry(panel, brackets.size(), width, height);
  Drawing d;
  d.width = width;
  d.height = height;
  d.fonts = geometry.fonts;
  PanelCanvas c{geometry, d};
  add_titles(c, panel);
  std::vector<float> bar_top;  // per bar: highest point of bar, error bar, points or "no data"
  for (size_t i = 0; i < panel.groups.size(); ++i)
    bar_top.push_back(add_bar(c, panel.groups[i], i));
  add_value_axis(c, panel.unit);
  add_brackets(c, brackets, bar_top);
  return d;
}

Drawing layout_evolution(const EvolutionStats& evolution, int width, int height) {
  const EvolutionGeometry geometry = evolution_geometry(evolution, width, height);
  Drawing d;
  d.width = width;
  d.height = height;
  d.fonts = geometry.fonts;
  EvolutionCanvas c{geometry, d};
  c.add(text("Best fitness over generations", kTitle,
             std::round((geometry.left + geometry.right) / 2), geometry.y_title, Anchor::kMiddle));
  add_bands(c, evolution);
  add_lines(c, evolution);
  add_axes(c, evolution);
  add_legend(c, evolution);
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
