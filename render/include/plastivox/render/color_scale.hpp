// What a voxel's colour means: the colour modes of `plastivox render --color MODE`, the
// range each maps onto its colour map, and the colour bar's ticks. Plain data, no GL.
#pragma once

#include <string>
#include <vector>

#include "plastivox/model.hpp"
#include "plastivox/recording.hpp"
#include "plastivox/render/colormap.hpp"

namespace plastivox::render {

enum class ColorMode {
  kCongenital,  // congenital stiffness E0, log10 over [e_min, e_max], sequential map
  kStiffness,   // current stiffness E, log10 over [e_min, e_max], sequential map
  kChange,      // lifetime change E/E0, log10 symmetric about 1, diverging map
  kAlpha,       // development rate alpha (1/s), symmetric about 0, diverging map
  kPhase,       // actuation phase (cycles, modulo 1), cyclic map
  kStimulus,    // the treatment's stimulus (Pa, docs/plasticity.md), linear from 0 on a
                // sequential map, or symmetric about 0 on a diverging map for a signed one
  kActuation,   // the actuation signal in [-1, 1] (recorded control channel; docs/control.md),
                // diverging map: shrinking blue, swelling red
};
// Whether a treatment's stimulus can be negative: only pressure's (negative in tension).
// Every other stimulus is >= 0 by definition (docs/plasticity.md), and so is shown one-sided.
bool stimulus_is_signed(Treatment t);
// "congenital", "stiffness", "change", "alpha", "phase", "stimulus", "actuation"
const char* to_string(ColorMode m);
// Throws RenderError listing the valid names.
ColorMode parse_color_mode(const std::string& name);

// Which range a stiffness or change scale spans (`--color-range`): the data's own (default:
// the values shown, rounded outward to readable ticks) or the paper's fixed one (the
// physics' [e_min, e_max] for stiffness; for change the widest change that range allows).
enum class ColorRange { kData, kPaper };
const char* to_string(ColorRange r);  // "data", "paper"
// Throws RenderError listing the valid names.
ColorRange parse_color_range(const std::string& name);

struct Tick {
  double t = 0;       // position along the map, [0, 1]
  std::string label;  // UTF-8, e.g. "10⁶", "×2", "-5", "0.25"
};

// A colour mode with its fixed range. `lo`/`hi` are in the mapped coordinate: log10 Pa for
// the stiffness modes, log10 of the ratio for change, 1/s for alpha, cycles for phase.
struct ColorScale {
  ColorMode mode = ColorMode::kCongenital;
  double lo = 5, hi = 11;
  std::string title;  // colour-bar title with unit, e.g. "congenital stiffness E₀ (Pa)"

  const Colormap& map() const;
  double value(const Model& model, const Frame& frame, int voxel) const;  // mapped coordinate
  double position(double value) const;  // t in [0, 1] (clamped; phase wraps)
  Rgb8 color(const Model& model, const Frame& frame, int voxel) const {
    return map().at(position(value(model, frame, voxel)));
  }
  std::vector<Tick> ticks() const;  // 3..11 labelled ticks, ascending t
};

// The scale for `mode` that stays fixed over `frames` (so a video's colours mean the same
// in every frame). With ColorRange::kData, stiffness modes span the values shown (E0 for
// congenital, E over `frames` for stiffness, E0 when there are none) rounded outward to 1-2-5
// values (to decades beyond three decades); change spans 1/x..x for the largest change x
// (E/E0 or E0/E) seen, x rounded up to two significant digits (of x - 1 below x2; at least
// x1.01), symmetric in log about x1. With kPaper, stiffness modes span the physics'
// [e_min, e_max] and change +-log10(e_max / e_min). Alpha spans the largest |alpha|, rounded up
// to a 1-2-5 value; phase one cycle (both whatever the range); stimulus from 0 (from -max for
// a signed stimulus, stimulus_is_signed) to the largest |stimulus| over `frames`, rounded up
// to a 1-2-5 value; actuation [-1, 1]. The title says which range.
ColorScale make_color_scale(ColorMode mode, const Model& model,
                            const std::vector<const Frame*>& frames,
                            ColorRange range = ColorRange::kData);

// A congenital or stiffness scale over the data range [lo_value, hi_value] (log10 Pa),
// rounded outward as make_color_scale does (for a gallery spanning several robots).
ColorScale stiffness_data_scale(ColorMode mode, double lo_value, double hi_value);

// A life's controller activity as an image (RGBA8, rows top-down): one row per voxel, in voxel
// order, and one column per frame, in time order, each cell the actuation signal on the
// actuation scale's map, drawn as a block of cell x cell pixels (so that the image is shown at
// its own size, never scaled up). Beyond max_rows voxels (max_columns frames) consecutive ones
// share a row (column) in equal groups, coloured by the group's root-mean-square signal with the
// sign of its mean: a mean would let voxels of different phase cancel, and a body swinging at
// +-1 would look at rest. A frame without the actuation channel counts as 0.
struct ActivityRaster {
  int width = 0, height = 0;  // pixels
  int rows = 0, columns = 0;  // voxel groups, frame groups
  int voxels_per_row = 1, frames_per_column = 1;
  std::vector<uint8_t> rgba;  // 4 * width * height
};
ActivityRaster actuation_raster(const std::vector<Frame>& frames, int max_rows, int max_columns,
                                int cell = 1);

}  // namespace plastivox::render
