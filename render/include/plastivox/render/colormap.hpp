// Perceptually uniform colour maps, generated at start-up from a path through CIELAB
// (docs/rendering.md, "Colour maps"): a sequential map (dark violet -> teal -> yellow, like
// viridis), a diverging map (blue -> near-white -> red) and a cyclic map (a hue circle of
// constant lightness). Each path is resampled so equal steps in the map are equal CIE76
// colour differences; out-of-gamut colours are brought in by reducing chroma only.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace plastivox::render {

using Rgb8 = std::array<uint8_t, 3>;  // sRGB, 8 bits per channel

class Colormap {
 public:
  static constexpr int kEntries = 256;

  const std::string& name() const { return name_; }
  // Colour at t in [0, 1] (clamped; cyclic maps wrap), linearly interpolated between the
  // table's entries and rounded: the same t always gives the same bytes.
  Rgb8 at(double t) const;
  bool cyclic() const { return cyclic_; }
  const std::vector<std::array<double, 3>>& lab() const { return lab_; }  // CIELAB per entry
  int clipped_entries() const { return clipped_; }  // entries whose chroma was reduced

  // The three maps, built once on first use (thread-safe).
  static const Colormap& sequential();
  static const Colormap& diverging();
  static const Colormap& cyclic_map();

 private:
  // `clipped`: how many entries of lab_path the gamut mapping reduced in chroma.
  Colormap(std::string name, bool cyclic, const std::vector<std::array<double, 3>>& lab_path,
           int clipped);
  std::string name_;
  bool cyclic_ = false;
  std::vector<std::array<double, 3>> lab_;  // kEntries CIELAB colours (after gamut mapping)
  std::vector<std::array<double, 3>> rgb_;  // kEntries sRGB colours in [0, 1]
  int clipped_ = 0;
};

// CIELAB (D65 white) to sRGB in [0, 1] per channel, unclamped (out of gamut when any
// channel leaves [0, 1]).
std::array<double, 3> lab_to_srgb(const std::array<double, 3>& lab);
// sRGB in [0, 1] to CIELAB (D65).
std::array<double, 3> srgb_to_lab(const std::array<double, 3>& rgb);

}  // namespace plastivox::render
