// Galleries of champions (the paper's Figs. 2-4): one tile per results file, each robot
// after settling, coloured by congenital stiffness, turned so it travels towards the lower
// right of its tile (heading taken from its own simulated displacement), all at one scale,
// with a label under each tile (run, seed and fitness) and one shared colour bar.
#pragma once

#include <string>
#include <vector>

#include "plastivox/render/color_scale.hpp"
#include "plastivox/render/render_life.hpp"

namespace plastivox::render {

struct GalleryStyle {
  int width = 1920, height = 1080;  // pixels of the whole gallery
  int columns = 0;                  // 0: chosen so tiles are about as wide as tall
  double time = -1;                 // simulated time shown, s (< 0: the end of settling)
  int samples = 4;                  // Scene::samples: 4x multisampling (0: edge, 1: none)
  bool labels = true;               // "stress · seed 3 · fitness 11.6" under each tile
  bool colorbar = true;             // the shared colour bar on the right
  ColorRange color_range = ColorRange::kData;  // all champions' E0, or the paper's [1e5, 1e11]
  // An explicit congenital-stiffness range, Pa (0 < e0_lo < e0_hi), for every tile, taking
  // the place of color_range: the colour bar spans exactly it (titled "shared range") and
  // voxels outside take its end colours. One study's galleries of several treatments share
  // one this way (plastivox experiment); `plastivox gallery --e0-range LO,HI`.
  double e0_lo = 0, e0_hi = 0;
};

struct GalleryLayout {
  int columns = 0, rows = 0;
  std::vector<PixelRect> tiles;     // one per input, in input order
  std::vector<std::string> labels;  // the source's label (run and seed, or the robot's name)
  std::vector<double> fitness;      // displacement at the end of life, voxel lengths
  std::vector<double> heading_deg;  // direction of travel, degrees from +x
  double e0_lo = 0, e0_hi = 0;      // the colour bar's congenital-stiffness range, Pa
};

// The image is too small for the tiles and colour bar asked for (a command-line problem).
class GallerySizeError : public RenderError {
 public:
  using RenderError::RenderError;
};
// Throws GallerySizeError when a gallery of `inputs` tiles does not fit this style's size.
void check_gallery_size(const GalleryStyle& style, int inputs);

// Everything about a gallery of `tiles` champions to `out` that can be wrong before anything
// is simulated; throws RenderError.
void check_gallery_request(const GalleryStyle& style, size_t tiles, const std::string& out);

// A tile's champion and its life's frames at gallery_times(), in that order.
struct GalleryEntry {
  LifeSource source;
  FrameSet life;
};
// The times a gallery needs of each life: the frame shown (style.time, or the end of
// settling) and the end of life (for the heading).
std::vector<double> gallery_times(const PhysicsDef& physics, const GalleryStyle& style);
// Renders the gallery to a PNG at `out` (atomically) from champions already simulated
// (render_gallery_file, plastivox/render/files.hpp, reads and simulates them; the experiment
// shares one simulation per champion with the 3-D viewer's lives).
GalleryLayout render_gallery(const std::vector<GalleryEntry>& entries, const GalleryStyle& style,
                             const std::string& out);

}  // namespace plastivox::render
