// A MAP-Elites run's QD score and coverage over evaluations (qd_curve.hpp): two line plots
// sharing the x axis, laid out as plain shapes like the archive's map.
#include "plastivox/render/qd_curve.hpp"

#include <algorithm>
#include <cstdio>

#include "plastivox/render/error.hpp"

namespace plastivox::render {
namespace {

constexpr Rgb kQdInk{0, 0, 0}, kQdGrid{200, 200, 200}, kQdLine{31, 119, 180},
    kCoverLine{214, 97, 0};

TextShape qd_label(const std::string& s, int font, float x, float y, Anchor a, bool up = false) {
  return TextShape{{{s, font, 0}}, x, y, a, up, kQdInk};
}

std::string qd_number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4g", v);
  return buf;
}

// One plot in the box (x0, y0)-(x1, y1): axes, the y range [0, top] and the series as lines.
void qd_plot(Drawing& d, float s, float x0, float y0, float x1, float y1, double right,
             const std::vector<int64_t>& x, const std::vector<double>& y, double top,
             const std::string& name, Rgb colour) {
  d.shapes.push_back(LineShape{x0, y1, x1, y1, 1 * s, kQdInk});
  d.shapes.push_back(LineShape{x0, y0, x0, y1, 1 * s, kQdInk});
  d.shapes.push_back(LineShape{x0, y0, x1, y0, 1 * s, kQdGrid});
  d.shapes.push_back(qd_label(qd_number(top), 2, x0 - 6 * s, y0 + 4 * s, Anchor::kEnd));
  d.shapes.push_back(qd_label("0", 2, x0 - 6 * s, y1, Anchor::kEnd));
  d.shapes.push_back(qd_label(name, 0, x0 - 44 * s, (y0 + y1) / 2, Anchor::kMiddle, true));
  const auto px = [&](size_t k) { return x0 + static_cast<float>(x[k] / right) * (x1 - x0); };
  const auto py = [&](size_t k) { return y1 - static_cast<float>(y[k] / top) * (y1 - y0); };
  for (size_t k = 1; k < x.size(); ++k)
    d.shapes.push_back(LineShape{px(k - 1), py(k - 1), px(k), py(k), 2 * s, colour});
  for (size_t k = 0; k < x.size(); ++k)
    d.shapes.push_back(CircleShape{px(k), py(k), 2.5f * s, colour, colour, 1, "point", name});
}

}  // namespace

Drawing layout_qd_curve(const QdCurve& c, int width, int height) {
  if (c.qd_score.size() != c.evaluations.size() || c.filled.size() != c.evaluations.size())
    throw RenderError("QD curve: evaluations, QD score and filled cells differ in length");
  Drawing d;
  d.width = width;
  d.height = height;
  const float s = std::min(width / 800.0f, height / 600.0f);
  d.fonts = {{13 * s, false}, {15 * s, true}, {12 * s, false}};
  d.shapes.push_back(qd_label(c.title, 1, width / 2.0f, 24 * s, Anchor::kMiddle));
  const float left = 90 * s, right = width - 30 * s, top = 50 * s, bottom = height - 60 * s;
  const float gap = 40 * s, h = (bottom - top - gap) / 2;
  double last = 1, best = 0;
  for (int64_t e : c.evaluations) last = std::max(last, static_cast<double>(e));
  for (double q : c.qd_score) best = std::max(best, q);
  std::vector<double> coverage;
  for (int64_t f : c.filled)
    coverage.push_back(c.cells > 0 ? 100.0 * static_cast<double>(f) / c.cells : 0.0);
  double covered = 0;
  for (double v : coverage) covered = std::max(covered, v);
  qd_plot(d, s, left, top, right, top + h, last, c.evaluations, c.qd_score, best > 0 ? best : 1,
          "QD score (" + c.fitness_unit + ")", kQdLine);
  qd_plot(d, s, left, top + h + gap, right, bottom, last, c.evaluations, coverage,
          covered > 0 ? covered : 1, "coverage (%)", kCoverLine);
  d.shapes.push_back(qd_label("0", 2, left, bottom + 16 * s, Anchor::kStart));
  d.shapes.push_back(qd_label(qd_number(last), 2, right, bottom + 16 * s, Anchor::kEnd));
  d.shapes.push_back(qd_label("evaluations (lives made)", 0, (left + right) / 2, bottom + 36 * s,
                              Anchor::kMiddle));
  return d;
}

}  // namespace plastivox::render
