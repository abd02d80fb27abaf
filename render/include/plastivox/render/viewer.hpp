// The in-browser 3-D viewer (issue 20): a recorded life packed compactly (quantised poses,
// sizes, stiffness and stimulus; layout in docs/rendering.md, "The 3-D viewer") and a page
// that replays it with three.js (Debian's libjs-three, inlined: the page works from file://
// with no network and no server). No GL here: the browser draws.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "plastivox/model.hpp"
#include "plastivox/recording.hpp"

namespace plastivox::render {

// One life to show: the compiled model (E0, phase, voxel size, settle time, fitness mode),
// its frames, and what the overlay reads out.
struct ViewerLife {
  std::string label;      // caption, e.g. "stress · seed 3"
  std::string treatment;  // "none", "stress" or "pressure"
  const Model* model = nullptr;
  const Recording* recording = nullptr;
  Vec3 com_settled = Vec3::Zero();  // m
  bool settled = false;
  double fitness = 0;  // voxel lengths, as recorded (for the page's caption)
};

// The packed life ("PVL1", little-endian; docs/rendering.md): a header, per-voxel E0 and
// phase, per-frame time and displacement, then per frame and voxel 13 bytes: centre as 3 x
// u16 over the life's bounding box, orientation as 32 bits (smallest three components, 10
// bits each, and the index of the largest), size, log10 E and stimulus as u8 each.
std::string pack_life(const ViewerLife& life);

// Bytes of pack_life per frame and voxel (13) and fixed per life.
constexpr int kPackedBytesPerVoxelFrame = 13;

// Standard base64 of `bytes` (for embedding a packed life in a page or a script).
std::string base64(const std::string& bytes);

// The JSON the viewer reads beside a packed life: label, treatment, fitness and, per colour
// mode (congenital, stiffness, change, stimulus, phase), the renderer's scale: range, map and
// colour-bar ticks.
std::string life_meta_json(const ViewerLife& life);

// Where three.js comes from: Debian's libjs-three. Throws RenderError saying which package
// to install when a file is missing.
struct ViewerScripts {
  std::string three;   // three.min.js
  std::string orbit;   // examples/js/controls/OrbitControls.js
  std::string viewer;  // assets/viewer/viewer.js (plastivox's own)
};
ViewerScripts viewer_scripts();

// A self-contained page replaying `lives` (one at a time; a list to pick from when there are
// several): everything inlined, so it opens from file:// with the network off.
std::string viewer_page(const std::vector<ViewerLife>& lives, const std::string& title);

}  // namespace plastivox::render
