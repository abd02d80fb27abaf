// Colour-map generation. Each map is a path in CIE LCh (lightness, chroma, hue) chosen by
// hand for its purpose; the path is sampled finely, brought into the sRGB gamut by lowering
// chroma at constant lightness and hue, and resampled at equal CIE76 arc length, so the
// perceived colour difference per unit of data is constant along the map.
#include "plastivox/render/colormap.hpp"

#include <algorithm>
#include <cmath>
#include <functional>

namespace plastivox::render {
namespace {

constexpr double kPi = 3.14159265358979323846;
using Vec = std::array<double, 3>;

// D65 reference white, CIE 1931 2-degree observer.
constexpr double kXn = 0.95047, kYn = 1.0, kZn = 1.08883;

double srgb_encode(double c) {  // linear -> sRGB transfer function
  return c <= 0.0031308 ? 12.92 * c : 1.055 * std::pow(c, 1.0 / 2.4) - 0.055;
}
double srgb_decode(double c) {
  return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
}

bool in_gamut(const Vec& rgb) {
  for (double c : rgb)
    if (c < -1e-9 || c > 1 + 1e-9) return false;
  return true;
}

Vec lch_to_lab(double l, double c, double h_deg) {
  const double h = h_deg * kPi / 180.0;
  return {l, c * std::cos(h), c * std::sin(h)};
}

// Largest chroma <= c at (l, h) inside the sRGB gamut (bisection).
Vec gamut_map(double l, double c, double h, bool& clipped) {
  clipped = false;
  if (in_gamut(lab_to_srgb(lch_to_lab(l, c, h)))) return lch_to_lab(l, c, h);
  clipped = true;
  double lo = 0, hi = c;
  for (int i = 0; i < 50; ++i) {
    const double mid = 0.5 * (lo + hi);
    (in_gamut(lab_to_srgb(lch_to_lab(l, mid, h))) ? lo : hi) = mid;
  }
  return lch_to_lab(l, lo, h);
}

double delta_e(const Vec& a, const Vec& b) {
  return std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
                   (a[2] - b[2]) * (a[2] - b[2]));
}

// Samples lch(s), s in [0, 1], finely; gamut-maps; resamples `count` points at equal arc
// length (or equal lightness steps, for paths whose lightness is monotonic). Adds the number of
// gamut-mapped output points to *clipped.
std::vector<Vec> uniform_path(const std::function<Vec(double)>& lch, int count, int* clipped,
                              bool by_lightness = false) {
  const int fine = 4096;
  std::vector<Vec> pts(fine + 1);
  std::vector<uint8_t> was_clipped(fine + 1);
  std::vector<double> arc(fine + 1, 0.0);
  for (int i = 0; i <= fine; ++i) {
    const Vec p = lch(static_cast<double>(i) / fine);
    bool c = false;
    pts[i] = gamut_map(p[0], p[1], p[2], c);
    was_clipped[i] = c;
    if (i > 0)
      arc[i] = arc[i - 1] +
               (by_lightness ? std::abs(pts[i][0] - pts[i - 1][0]) : delta_e(pts[i - 1], pts[i]));
  }
  std::vector<Vec> out(count);
  int j = 0;
  for (int k = 0; k < count; ++k) {
    const double target = arc[fine] * k / (count - 1);
    while (j < fine - 1 && arc[j + 1] < target) ++j;
    const double span = arc[j + 1] - arc[j];
    const double f = span > 0 ? std::clamp((target - arc[j]) / span, 0.0, 1.0) : 0.0;
    for (int d = 0; d < 3; ++d) out[k][d] = pts[j][d] + f * (pts[j + 1][d] - pts[j][d]);
    if (was_clipped[j] || was_clipped[j + 1]) ++*clipped;
  }
  return out;
}

double mix(double a, double b, double t) {
  return a + (b - a) * t;
}

}  // namespace

Vec lab_to_srgb(const Vec& lab) {
  const double fy = (lab[0] + 16.0) / 116.0;
  const double fx = fy + lab[1] / 500.0;
  const double fz = fy - lab[2] / 200.0;
  auto finv = [](double f) {
    const double d = 6.0 / 29.0;
    return f > d ? f * f * f : 3 * d * d * (f - 4.0 / 29.0);
  };
  const double x = kXn * finv(fx), y = kYn * finv(fy), z = kZn * finv(fz);
  const double r = 3.2404542 * x - 1.5371385 * y - 0.4985314 * z;
  const double g = -0.9692660 * x + 1.8760108 * y + 0.0415560 * z;
  const double b = 0.0556434 * x - 0.2040259 * y + 1.0572252 * z;
  auto enc = [](double c) { return c < 0 ? -srgb_encode(-c) : srgb_encode(c); };
  return {enc(r), enc(g), enc(b)};
}

Vec srgb_to_lab(const Vec& rgb) {
  const double r = srgb_decode(rgb[0]), g = srgb_decode(rgb[1]), b = srgb_decode(rgb[2]);
  const double x = 0.4124564 * r + 0.3575761 * g + 0.1804375 * b;
  const double y = 0.2126729 * r + 0.7151522 * g + 0.0721750 * b;
  const double z = 0.0193339 * r + 0.1191920 * g + 0.9503041 * b;
  auto f = [](double t) {
    const double d = 6.0 / 29.0;
    return t > d * d * d ? std::cbrt(t) : t / (3 * d * d) + 4.0 / 29.0;
  };
  const double fx = f(x / kXn), fy = f(y / kYn), fz = f(z / kZn);
  return {116 * fy - 16, 500 * (fx - fy), 200 * (fy - fz)};
}

Colormap::Colormap(std::string name, bool cyclic, const std::vector<Vec>& lab_path, int clipped)
    : name_(std::move(name)), cyclic_(cyclic), lab_(lab_path), clipped_(clipped) {
  for (const Vec& lab : lab_) {
    Vec rgb = lab_to_srgb(lab);
    for (double& c : rgb) c = std::clamp(c, 0.0, 1.0);
    rgb_.push_back(rgb);
  }
}

Rgb8 Colormap::at(double t) const {
  if (!std::isfinite(t)) t = 0;
  if (cyclic_) {
    t -= std::floor(t);
  } else {
    t = std::clamp(t, 0.0, 1.0);
  }
  const double x = t * (kEntries - 1);
  const int i = std::min(static_cast<int>(x), kEntries - 2);
  const double f = x - i;
  Rgb8 out{};
  for (int d = 0; d < 3; ++d) {
    const double c = rgb_[i][d] + f * (rgb_[i + 1][d] - rgb_[i][d]);
    out[d] = static_cast<uint8_t>(std::lround(std::clamp(c, 0.0, 1.0) * 255.0));
  }
  return out;
}

// Sequential: lightness rises linearly from 18 to 90 while the hue turns from violet (295°)
// through blue and teal to yellow (100°); chroma dips in the blue-green middle, where sRGB
// has little room, and rises to a saturated yellow.
const Colormap& Colormap::sequential() {
  static const Colormap map = [] {
    int clipped = 0;
    auto path = uniform_path(
        [](double s) {
          const double c = 48 - 30 * std::sin(kPi * s) + 38 * s * s;
          return Vec{mix(18, 90, s), c, mix(295, 100, s)};
        },
        kEntries, &clipped);
    return Colormap("sequential", false, path, clipped);
  }();
  return map;
}

// Diverging: blue (hue 265°) at lightness 32 -> near-white (L 96, chroma 0) -> red (hue 30°)
// at lightness 32, lightness and chroma linear on each side, each half resampled at equal
// lightness steps, so the neutral midpoint stays at t = 0.5 and the halves mirror in L.
const Colormap& Colormap::diverging() {
  static const Colormap map = [] {
    int clipped = 0;
    const int half = kEntries / 2;
    auto low = uniform_path(
        [](double s) {
          return Vec{mix(32, 96, s), mix(58, 0, s), 265};
        },
        half, &clipped, true);
    auto high = uniform_path(
        [](double s) {
          return Vec{mix(96, 32, s), mix(0, 62, s), 30};
        },
        half, &clipped, true);
    low.insert(low.end(), high.begin(), high.end());
    return Colormap("diverging", false, low, clipped);
  }();
  return map;
}

// Cyclic: the hue circle at constant lightness 70 and chroma 37 (every hue fits in sRGB
// there), starting at red-magenta; the end meets the start.
const Colormap& Colormap::cyclic_map() {
  static const Colormap map = [] {
    int clipped = 0;
    auto path = uniform_path([](double s) { return Vec{70, 37, 360 * s}; }, kEntries, &clipped);
    return Colormap("cyclic", true, path, clipped);
  }();
  return map;
}

}  // namespace plastivox::render
