// Rendering a robot's life: one frame as PNG, the whole life (or a part) as an MP4 video,
// and champions side by side (gallery.hpp). These are the library calls behind
// `plastivox render` and `plastivox video`; the experiment calls them in-process.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "plastivox/render/color_scale.hpp"
#include "plastivox/render/life.hpp"
#include "plastivox/render/overlay.hpp"
#include "plastivox/render/scene.hpp"

namespace plastivox::render {

// Message sink for progress lines (may be empty: silent).
using LogFn = std::function<void(const std::string&)>;

struct FrameStyle {
  int width = 1280, height = 720;  // pixels (1920x1080 and 3840x2160 work)
  ColorMode color = ColorMode::kCongenital;
  ColorRange color_range = ColorRange::kData;  // the data's own range or the paper's
  OverlayOptions overlay;
  bool orthographic = false;        // parallel projection (tests, technical views)
  double zoom = 1.0;                // > 1 closer
  double azimuth_deg = -60;         // camera direction about +z, from +x
  double elevation_deg = 25;        // camera height above the floor plane
  int samples = kEdgeAntialiasing;  // anti-aliasing: edge (0), none (1), multisampling (2..8)
  bool lit = true;                  // false: flat colours (tests)
  bool shadows = true;
  // Videos: kLife frames the camera from the whole life (life_cameras in scene.hpp: the body
  // and the floor under it stay in the image; the simulation runs before drawing), kFollow
  // per frame with follow_camera (the simulation runs alongside drawing; a body that rears
  // up or stretches may leave the image).
  enum class CameraPath { kLife, kFollow } camera = CameraPath::kLife;
};

// The camera `c` with the style's projection, azimuth and elevation.
Camera styled_camera(const FrameStyle& style, Camera c);

// Draws frames of lives with one style, reusing its GL context, shaders and fonts (create
// once, call render() for every frame; not thread-safe).
class FrameRenderer {
 public:
  explicit FrameRenderer(const FrameStyle& style);  // throws RenderError
  ~FrameRenderer();
  FrameRenderer(const FrameRenderer&) = delete;
  FrameRenderer& operator=(const FrameRenderer&) = delete;

  // One frame of `life` coloured by `scale`, camera following the robot; returns RGBA8 rows
  // top-down (4 * width * height bytes). `treatment` is the overlay's caption.
  std::vector<uint8_t> render(const FrameSet& life, const Frame& frame, const ColorScale& scale,
                              const std::string& treatment);
  // The same seen by `camera` (styled_camera already applied).
  std::vector<uint8_t> render(const FrameSet& life, const Frame& frame, const ColorScale& scale,
                              const std::string& treatment, const Camera& camera);
  const FrameStyle& style() const { return style_; }

 private:
  FrameStyle style_;
  std::unique_ptr<OffscreenContext> ctx_;
  std::unique_ptr<SceneRenderer> scene_;
  std::unique_ptr<ImGuiLayer> ui_;
};

// Throws RenderError unless a file can be created at path (its folder exists and is
// writable, and nothing but a regular file sits at path: plastivox::check_output_path), so a
// long job fails before it starts rather than at the end.
void check_output_path(const std::string& path);

// The frame at simulated time `time` (s) of `source`'s life as RGBA8 rows, top-down
// (4 * style.width * style.height bytes). Throws RenderError.
std::vector<uint8_t> render_frame(const LifeSource& source, double time, const FrameStyle& style);

struct VideoJob {
  double fps = 30;   // frames per second of the video
  double start = 0;  // simulated time of the first frame, s
  double end = -1;   // simulated time the video ends, s (< 0: the end of the life)
  int stride = 1;    // simulated time between frames = stride / fps (stride > 1: time-lapse)
  std::string codec = "auto";
};

struct VideoSummary {
  int frames = 0;
  double duration_s = 0;        // of the video
  std::string codec;            // as written
  double simulate_seconds = 0;  // time simulating (alongside drawing: the simulation
                                // thread's CPU time; for "change", before: wall time)
  double render_seconds = 0;    // wall time drawing and encoding (after the simulation
                                // started, or for "change" after it finished)
};

// Throws RenderError unless `job` is a valid request for a video at `out`.
void check_video_request(const VideoJob& job, const std::string& out);

// Renders a life as an MP4 at `out`: frames at simulated times start + k * stride / fps
// while < end; every frame uses one colour scale (make_color_scale over all frames) and, by
// default, the cameras of life_cameras over all frames. Drawing and encoding run at the same
// time on two threads, after the simulation when the camera path or the colour scale needs
// every frame, else alongside it on a third; the bytes are those of one after the other.
// (render_video_file, plastivox/render/files.hpp, reads the life from a file first.)
VideoSummary render_video(const LifeSource& source, const FrameStyle& style, const VideoJob& job,
                          const std::string& out, const LogFn& log = {});

}  // namespace plastivox::render
