#include "plastivox/render/color_scale.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "plastivox/base/names.hpp"
#include "plastivox/render/error.hpp"

namespace plastivox::render {
namespace {

// Smallest 1-2-5 number >= x (x > 0).
double nice_ceil(double x) {
  const double p = std::pow(10.0, std::floor(std::log10(x)));
  for (double m : {1.0, 2.0, 5.0, 10.0})
    if (m * p >= x * (1 - 1e-12)) return m * p;
  return 10 * p;
}

// Largest 1-2-5 number <= x (x > 0).
double nice_floor(double x) {
  const double p = std::pow(10.0, std::floor(std::log10(x)));
  for (double m : {10.0, 5.0, 2.0, 1.0})
    if (m * p <= x * (1 + 1e-12)) return m * p;
  return p;
}

// A 1-2-5 step giving about `target` intervals over span.
double nice_step(double span, int target) {
  return nice_ceil(span / target);
}

std::string superscript(int n) {
  static const char* digits[] = {"⁰", "¹", "²", "³", "⁴", "⁵", "⁶", "⁷", "⁸", "⁹"};
  std::string s = n < 0 ? "⁻" : "";
  const std::string d = std::to_string(std::abs(n));
  for (char c : d) s += digits[c - '0'];
  return s;
}

// Tick ratios for a "change" scale from 1/top to top (top > 1), ascending. From x2 up: 1-2-5
// ratios and their reciprocals (x0.5, x1, x2, x5; then only decades if that gives more than
// nine, then every second decade). Below: ratios 1 + k * step for a 1-2-5 step giving about
// six intervals (x0.9, x1, x1.1), which read better than x0.891 and x1.12.
std::vector<double> change_ticks(double top) {
  std::vector<double> out;
  if (top >= 2 * (1 - 1e-9)) {
    const int decades = static_cast<int>(std::floor(std::log10(top) + 1e-9));
    auto ticks_with = [&](std::vector<double> mantissas, int every) {
      std::vector<double> t;
      for (int e = -decades - 1; e <= decades; ++e) {
        if (((e % every) + every) % every != 0) continue;
        for (const double m : mantissas) {
          const double up = m * std::pow(10.0, e);
          if (up >= 1 - 1e-9 && up <= top * (1 + 1e-9)) t.push_back(up);
        }
      }
      std::vector<double> all;
      for (auto it = t.rbegin(); it != t.rend(); ++it)
        if (*it > 1 + 1e-9) all.push_back(1 / *it);
      all.insert(all.end(), t.begin(), t.end());
      return all;
    };
    out = ticks_with({1, 2, 5}, 1);
    if (out.size() > 9) out = ticks_with({1}, 1);
    if (out.size() > 9) out = ticks_with({1}, 2);
    return out;
  }
  const double step = nice_step(top - 1 / top, 6);
  const int below = static_cast<int>(std::floor((1 - 1 / top) / step + 1e-9));
  const int above = static_cast<int>(std::floor((top - 1) / step + 1e-9));
  for (int k = -below; k <= above; ++k) out.push_back(std::round((1 + k * step) * 1e9) / 1e9);
  return out;
}

// The top ratio of a data-range change scale: the largest change seen, x > 1, rounded up to
// two significant digits of x - 1 below x2 (x1.013, x1.4) and of x from x2 up (x4.4, x13).
double change_top(double x) {
  const auto up2 = [](double v) {
    const double p = std::pow(10.0, std::floor(std::log10(v)) - 1);
    return std::ceil(v / p * (1 - 1e-12)) * p;
  };
  return x < 2 ? 1 + up2(x - 1) : up2(x);
}

// "×0.5", "×1", "×1.05", "×20"; decades beyond a thousand as powers ("×10⁴", "×10⁻⁴").
std::string ratio_label(double r) {
  const double e = std::log10(r);
  if (std::abs(e) > 3 - 1e-9 && std::abs(e - std::round(e)) < 1e-9)
    return "×10" + superscript(static_cast<int>(std::round(e)));
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", r);
  return std::string("×") + buf;
}

// "10⁹", "2×10⁹", "5×10¹⁰" for a 1-2-5 (or other whole-mantissa) value given as log10.
std::string power_label(double log_value) {
  const int e = static_cast<int>(std::floor(log_value + 1e-9));
  const int m = static_cast<int>(std::round(std::pow(10.0, log_value - e)));
  return (m == 1 ? std::string() : std::to_string(m) + "×") + "10" + superscript(e);
}

// "0", "10⁸", "1.5×10⁸", "−5×10⁷": stimulus ticks in Pa.
std::string scientific(double v) {
  if (std::abs(v) < 1e-300) return "0";
  const int e = static_cast<int>(std::floor(std::log10(std::abs(v)) + 1e-9));
  char mantissa[32];
  std::snprintf(mantissa, sizeof mantissa, "%.3g", std::abs(v) / std::pow(10.0, e));
  std::string out = v < 0 ? "−" : "";
  if (std::string(mantissa) != "1") {
    out += mantissa;
    out += "×";
  }
  out += "10";
  out += superscript(e);
  return out;
}

std::string number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", std::abs(v) < 1e-12 ? 0.0 : v);
  std::string s = buf;
  if (!s.empty() && s[0] == '-') s = "−" + s.substr(1);  // U+2212 minus
  return s;
}

constexpr Named<ColorMode> kColorModeNames[] = {
    {ColorMode::kCongenital, "congenital"}, {ColorMode::kStiffness, "stiffness"},
    {ColorMode::kChange, "change"},         {ColorMode::kAlpha, "alpha"},
    {ColorMode::kPhase, "phase"},           {ColorMode::kStimulus, "stimulus"},
    {ColorMode::kActuation, "actuation"}};
constexpr Named<ColorRange> kColorRangeNames[] = {{ColorRange::kData, "data"},
                                                  {ColorRange::kPaper, "paper"}};

}  // namespace

const char* to_string(ColorMode m) {
  return name_in(kColorModeNames, m);
}

bool stimulus_is_signed(Treatment t) {
  return t == Treatment::kPressure;
}

const char* to_string(ColorRange r) {
  return name_in(kColorRangeNames, r);
}

ColorRange parse_color_range(const std::string& name) {
  if (const auto r = value_in(kColorRangeNames, name)) return *r;
  throw RenderError("unknown colour range '" + name + "' (expected " +
                    choices_in(kColorRangeNames) + ")");
}

ColorMode parse_color_mode(const std::string& name) {
  if (const auto m = value_in(kColorModeNames, name)) return *m;
  throw RenderError("unknown colour mode '" + name + "' (expected " + choices_in(kColorModeNames) +
                    ")");
}

const Colormap& ColorScale::map() const {
  switch (mode) {
    case ColorMode::kChange:
    case ColorMode::kAlpha:
    case ColorMode::kActuation:
      return Colormap::diverging();
    case ColorMode::kPhase:
      return Colormap::cyclic_map();
    case ColorMode::kStimulus:
      return lo < 0 ? Colormap::diverging() : Colormap::sequential();
    default:
      return Colormap::sequential();
  }
}

double ColorScale::value(const Model& model, const Frame& frame, int i) const {
  switch (mode) {
    case ColorMode::kCongenital:
      return std::log10(model.e0[i]);
    case ColorMode::kStiffness:
      return std::log10(frame.stiffness[i]);
    case ColorMode::kChange:
      return std::log10(frame.stiffness[i] / model.e0[i]);
    case ColorMode::kAlpha:
      return model.alpha[i];
    case ColorMode::kPhase:
      return model.phase[i];
    case ColorMode::kStimulus:
      return frame.stimulus.empty() ? 0.0 : frame.stimulus[i];
    case ColorMode::kActuation:
      return frame.actuation.empty() ? 0.0 : frame.actuation[i];
  }
  return 0;
}

double ColorScale::position(double v) const {
  if (mode == ColorMode::kPhase) return v - std::floor(v);
  if (!std::isfinite(v)) return 0.5;
  return std::clamp((v - lo) / (hi - lo), 0.0, 1.0);
}

std::vector<Tick> ColorScale::ticks() const {
  std::vector<Tick> out;
  auto add = [&](double v, std::string label) {
    out.push_back({std::clamp((v - lo) / (hi - lo), 0.0, 1.0), std::move(label)});
  };
  const double span = hi - lo;
  switch (mode) {
    case ColorMode::kCongenital:
    case ColorMode::kStiffness: {
      // Decades, every second one when there are many; within three decades 1-2-5 values
      // (or 1-3, or decades alone) when they give at most nine ticks.
      if (span <= 3 + 1e-9) {
        for (const std::vector<double>& ms :
             {std::vector<double>{1, 2, 5}, std::vector<double>{1, 3}, std::vector<double>{1}}) {
          std::vector<double> values;
          for (int e = static_cast<int>(std::floor(lo)) - 1; e <= hi + 1; ++e)
            for (double m : ms) {
              const double v = e + std::log10(m);
              if (v >= lo - 1e-9 && v <= hi + 1e-9) values.push_back(v);
            }
          if (values.size() <= 9 || ms.size() == 1) {
            for (double v : values) add(v, power_label(v));
            break;
          }
        }
        break;
      }
      const int step = span > 8 ? 2 : 1;
      for (int e = static_cast<int>(std::ceil(lo - 1e-9)); e <= hi + 1e-9; e += step)
        add(e, "10" + superscript(e));
      break;
    }
    case ColorMode::kChange: {
      // Ratios with short exact labels, each at its own log10 position (not necessarily
      // symmetric about x1); the bar's ends too ("×4.4", "×1/4.4"), unless a tick is near.
      const double top = std::pow(10.0, hi);
      for (const double r : change_ticks(top)) add(std::log10(r), ratio_label(r));
      const auto near = [&](double t) {
        for (const Tick& k : out)
          if (std::abs(k.t - t) < 0.12) return true;
        return false;
      };
      const bool bottom = !near(0), upper = !near(1);
      char end[32];
      std::snprintf(end, sizeof end, "%.4g", top);
      if (bottom) out.insert(out.begin(), Tick{0, std::string("×1/") + end});
      if (upper) add(hi, std::string("×") + end);
      break;
    }
    case ColorMode::kAlpha: {
      const double step = nice_step(span, 4);
      for (double v = -std::floor(hi / step) * step; v <= hi + 1e-9; v += step) add(v, number(v));
      break;
    }
    case ColorMode::kPhase:
      for (double v : {0.0, 0.25, 0.5, 0.75, 1.0}) add(v, number(v));
      break;
    case ColorMode::kActuation:
      for (double v : {-1.0, -0.5, 0.0, 0.5, 1.0}) add(v, number(v));
      break;
    case ColorMode::kStimulus: {
      const double step = nice_step(hi, lo < 0 ? 2 : 4);
      for (int k = static_cast<int>(std::ceil(lo / step - 1e-9)); k * step <= hi * (1 + 1e-9); ++k)
        add(k * step, scientific(k * step));
      break;
    }
  }
  return out;
}

ColorScale stiffness_data_scale(ColorMode mode, double lo_value, double hi_value) {
  ColorScale s;
  s.mode = mode;
  if (hi_value - lo_value > 3) {  // decades
    s.lo = std::floor(lo_value + 1e-9);
    s.hi = std::ceil(hi_value - 1e-9);
  } else {  // 1-2-5 values
    s.lo = std::log10(nice_floor(std::pow(10.0, lo_value)));
    s.hi = std::log10(nice_ceil(std::pow(10.0, hi_value)));
  }
  // One value (a uniform robot): up to the next 1-2-5 value, so the bar has a span.
  if (s.hi - s.lo < 1e-9) s.hi = std::log10(nice_ceil(std::pow(10.0, s.lo) * 1.0001));
  s.title = std::string(mode == ColorMode::kCongenital ? "congenital stiffness E₀ (Pa)"
                                                       : "stiffness E (Pa)") +
            ", range of the data";
  return s;
}

ColorScale make_color_scale(ColorMode mode, const Model& model,
                            const std::vector<const Frame*>& frames, ColorRange range) {
  ColorScale s;
  s.mode = mode;
  const bool paper = range == ColorRange::kPaper;
  switch (mode) {
    case ColorMode::kCongenital:
    case ColorMode::kStiffness:
      if (!paper && model.n > 0) {
        double lo = 1e300, hi = -1e300;
        const auto see = [&](double e) {
          if (!(e > 0) || !std::isfinite(e)) return;
          lo = std::min(lo, std::log10(e));
          hi = std::max(hi, std::log10(e));
        };
        if (mode == ColorMode::kStiffness && !frames.empty()) {
          for (const Frame* f : frames)
            for (int i = 0; i < model.n; ++i) see(f->stiffness[i]);
        } else {
          for (int i = 0; i < model.n; ++i) see(model.e0[i]);
        }
        if (lo <= hi) return stiffness_data_scale(mode, lo, hi);
      }
      s.lo = std::log10(model.def.e_min);
      s.hi = std::log10(model.def.e_max);
      s.title = std::string(mode == ColorMode::kCongenital ? "congenital stiffness E₀ (Pa)"
                                                           : "stiffness E (Pa)") +
                ", paper's range";
      break;
    case ColorMode::kChange: {
      if (paper) {
        s.hi = std::log10(model.def.e_max / model.def.e_min);
        s.title = "lifetime change E / E₀, paper's range";
      } else {
        double m = 0;
        for (const Frame* f : frames)
          for (int i = 0; i < model.n; ++i) {
            const double v = std::abs(std::log10(f->stiffness[i] / model.e0[i]));
            if (std::isfinite(v)) m = std::max(m, v);
          }
        s.hi = std::log10(change_top(std::pow(10.0, std::max(m, std::log10(1.01)))));
        s.title = "lifetime change E / E₀, range of the data";
      }
      s.lo = -s.hi;
      break;
    }
    case ColorMode::kAlpha: {
      double m = 0;
      for (int i = 0; i < model.n; ++i) m = std::max(m, std::abs(model.alpha[i]));
      s.hi = nice_ceil(std::max(m, 1e-6));
      s.lo = -s.hi;
      s.title = "development rate α (1/s)";
      break;
    }
    case ColorMode::kPhase:
      s.lo = 0;
      s.hi = 1;
      s.title = "actuation phase (cycles)";
      break;
    case ColorMode::kActuation:
      s.lo = -1;
      s.hi = 1;
      s.title = "actuation signal (shrink −1 … +1 swell)";
      break;
    case ColorMode::kStimulus: {
      double m = 0;
      for (const Frame* f : frames)
        for (double v : f->stimulus)
          if (std::isfinite(v)) m = std::max(m, std::abs(v));
      s.hi = nice_ceil(std::max(m, 1e-12));
      s.lo = stimulus_is_signed(model.def.treatment) ? -s.hi : 0;
      s.title =
          std::string("stimulus (Pa), ") + to_string(model.def.treatment) + ", range of the data";
      break;
    }
  }
  return s;
}

ActivityRaster actuation_raster(const std::vector<Frame>& frames, int max_rows, int max_columns,
                                int cell) {
  ActivityRaster out;
  const int n = frames.empty() ? 0 : static_cast<int>(frames.front().pos.size());
  const int t = static_cast<int>(frames.size());
  if (n == 0 || max_rows < 1 || max_columns < 1 || cell < 1) return out;
  out.voxels_per_row = (n + max_rows - 1) / max_rows;
  out.frames_per_column = (t + max_columns - 1) / max_columns;
  out.rows = (n + out.voxels_per_row - 1) / out.voxels_per_row;
  out.columns = (t + out.frames_per_column - 1) / out.frames_per_column;
  out.width = out.columns * cell;
  out.height = out.rows * cell;
  out.rgba.assign(4 * static_cast<size_t>(out.width) * out.height, 255);
  ColorScale scale;
  scale.mode = ColorMode::kActuation;
  scale.lo = -1;
  scale.hi = 1;
  for (int row = 0; row < out.rows; ++row)
    for (int col = 0; col < out.columns; ++col) {
      // A group's root-mean-square signal with the sign of its mean: one voxel in one frame
      // is its own signal; a group swinging at +-1 out of phase is as strong as each member.
      double sum = 0, squares = 0;
      int count = 0;
      for (int k = col * out.frames_per_column; k < std::min(t, (col + 1) * out.frames_per_column);
           ++k)
        for (int i = row * out.voxels_per_row; i < std::min(n, (row + 1) * out.voxels_per_row);
             ++i, ++count) {
          const double u = frames[k].actuation.empty() ? 0.0 : frames[k].actuation[i];
          sum += u;
          squares += u * u;
        }
      const double rms = std::sqrt(squares / count);
      const Rgb8 c = scale.map().at(scale.position(sum < 0 ? -rms : rms));
      for (int y = row * cell; y < (row + 1) * cell; ++y)
        for (int x = col * cell; x < (col + 1) * cell; ++x)
          std::copy(c.begin(), c.end(), &out.rgba[4 * (static_cast<size_t>(y) * out.width + x)]);
    }
  return out;
}

}  // namespace plastivox::render
