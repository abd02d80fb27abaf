// The in-browser 3-D viewer (issue 20): a recorded life packed compactly (quantised poses,
// sizes, stiffness and stimulus; layout in docs/rendering.md, "The 3-D viewer") and a page
// that replays it with three.js (Debian's libjs-three, inlined: the page works from file://
// with no network and no server). No GL here: the browser draws.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "plastivox/model.hpp"
#include "plastivox/recording.hpp"
#include "plastivox/render/life.hpp"

namespace plastivox::render {

// One life to show: the compiled model (E0, phase, voxel size, settle time, fitness mode),
// its frames, and what the overlay reads out.
struct ViewerItem {
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
// bits each, and the index of the largest), size, log10 E and stimulus as u8 each; then, when
// the recording carries the control channels, per frame and voxel the actuation signal as u8
// over [-1, 1].
std::string pack_life(const ViewerItem& life);

// Bytes of pack_life per frame and voxel (13) and fixed per life.
constexpr int kPackedBytesPerVoxelFrame = 13;

// Standard base64 of `bytes` (for embedding a packed life in a page or a script).
std::string base64(const std::string& bytes);

// The JSON the viewer reads beside a packed life: label, treatment, fitness, per colour mode
// (congenital, stiffness, change, stimulus, phase, actuation) the renderer's scale (range, map
// and colour-bar ticks) and, for a life in an environment, its "world": the ground as heights
// on the lines where it bends and the obstacle boxes, around the life (docs/rendering.md).
std::string life_meta_json(const ViewerItem& life);

// Where three.js comes from: Debian's libjs-three. Throws RenderError saying which package
// to install when a file is missing.
struct ViewerScripts {
  std::string three;   // three.min.js
  std::string orbit;   // examples/js/controls/OrbitControls.js
  std::string viewer;  // assets/viewer/viewer.js (plastivox's own)
};
ViewerScripts viewer_scripts();

// A life to show that owns its model and frames: as recorded (a recorded-life file) or
// simulated once at `fps` frames per simulated second (a robot, or a results file's
// champion of `generation`, -1 the last). `failure` says why a simulation did not finish
// ("" when it did; the frames are then unusable). Throws on unreadable input, one line.
struct ShownLife {
  Model model;
  Recording recording;
  ViewerItem info;  // label, treatment, settling and fitness; model and recording unset
  std::string failure;
  // `info` pointing at this object's model and frames (valid while this object lives).
  ViewerItem life() const;
};
// One pass over the frames of `source` for a report: the viewer's life at `fps` frames per
// simulated second (the state at the first step at or after each k / fps, and the last state) and,
// from the same run, a frame at each of `times` (ascending, within the life; a gallery's, see
// gallery_times()), so a report showing both simulates each champion once. `frames_failure`
// says why `frames` is empty (the life went unstable before the last of `times`).
struct ReportFrames {
  ShownLife shown;
  FrameSet frames;
  std::string frames_failure;
};
ReportFrames report_life(const LifeSource& source, double fps, const std::vector<double>& times);
// The viewer's life of `source`: its recording as recorded, or its frames at `fps` frames per
// simulated second.
ShownLife show_life(const LifeSource& source, double fps);

// A self-contained page replaying `lives` (one at a time; a list to pick from when there are
// several): everything inlined, so it opens from file:// with the network off.
std::string viewer_page(const std::vector<ViewerItem>& lives, const std::string& title);

// ---- Lives beside a report ---------------------------------------------------------------
// A report links its lives rather than embedding them: each is a small script,
// lives/<id>.js, that hands its packed bytes to the page's viewer when first picked (a
// <script> element loads from file://, where fetch() is refused).

// The script of one life: plastivoxViewer.deliver(id, {meta, data}).
std::string life_script(const std::string& id, const ViewerItem& life);

// One life a report offers: its id (the run label), and its script relative to the page.
struct ViewerLink {
  std::string id;
  std::string src;
};

// The viewer as part of a larger page: panel, styles, three.js, the viewer and the list of
// lives, the first of them loaded at once. With `buttons`, a button per life above the
// viewer; without, the page offers its own way to call plastivoxViewer.load(i), as the
// experiment's report does from its champions' thumbnails.
std::string viewer_fragment(const std::vector<ViewerLink>& lives, bool buttons);

// Frames per simulated second of the lives a report replays.
constexpr double kViewerFps = 30;

// Writes one life to `dir`/lives/<id>.js (atomically) and returns its link.
ViewerLink write_report_life(const std::string& dir, const std::string& id, const ViewerItem& life);
// Removes every life in `dir`/lives/ but those of `keep` (lives of runs no longer shown).
void remove_other_lives(const std::string& dir, const std::vector<ViewerLink>& keep);
}  // namespace plastivox::render
