// A plain description of what to draw (no GL): coloured, posed boxes on a floor, a camera
// and a light. build_scene() turns one recorded frame into a Scene; draw_scene() (the only
// GL code besides offscreen.cpp) rasterizes it.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <memory>
#include <vector>

#include "plastivox/model.hpp"
#include "plastivox/recording.hpp"
#include "plastivox/render/color_scale.hpp"

namespace plastivox::render {

class OffscreenContext;

struct Box {
  Eigen::Vector3f center;     // m, world frame (z up)
  Eigen::Quaternionf orient;  // body-to-world rotation
  float edge = 0.01f;         // edge length, m
  Rgb8 color{};               // sRGB
};

struct Camera {
  Eigen::Vector3d target = Eigen::Vector3d::Zero();  // point looked at, m
  double azimuth_deg = -60;   // direction from target to eye, about +z, from +x
  double elevation_deg = 25;  // above the floor plane
  double distance = 0.5;      // eye to target, m (perspective)
  double fov_y_deg = 30;      // vertical field of view (perspective)
  bool orthographic = false;
  double ortho_height = 0.2;  // visible height at the target, m (orthographic)

  Eigen::Vector3d eye() const;
  // World -> clip transform for an image of the given aspect (width / height).
  Eigen::Matrix4d view_projection(double aspect, double near_m, double far_m) const;
  // Pixels per metre at the target's depth, for an image `height_px` tall.
  double pixels_per_metre(int height_px) const;
};

// Scene::samples value selecting edge anti-aliasing: one sample per pixel, then a
// post-process pass that smooths stair-stepped edges (assets/shaders/edge_aa.frag). On
// llvmpipe it costs a fraction of multisampling, which shades every covered sample of every
// box, hidden or not (the front-to-back order then saves nothing).
constexpr int kEdgeAntialiasing = 0;

struct Scene {
  std::vector<Box> boxes;
  Camera camera;
  bool floor = true;
  double grid_spacing = 0.01;  // floor grid, m (one voxel length); every 10th line bolder
  bool lit = true;             // false: flat colours exactly as given (for tests)
  bool shadows = true;         // soft shadow from the key light (shadow map, PCF)
  bool outlines = true;        // darken voxel edges slightly so voxels read individually
  Eigen::Vector3d light_dir = Eigen::Vector3d(-0.35, -0.5, 1.0).normalized();  // to light
  Rgb8 background{236, 239, 243};
  Rgb8 floor_color{214, 216, 220};
  // Anti-aliasing: kEdgeAntialiasing (0, default), 1 = none, 2..8 = multisampling with
  // that many samples per pixel.
  int samples = kEdgeAntialiasing;
};

// The camera framing a robot: target at the robot's centre of mass (z at half its rest
// height), distance so the robot's largest rest dimension fills about 60 % of the image
// height (times zoom).
Camera follow_camera(const Model& model, const Frame& frame, double zoom = 1.0);

// The cameras of a whole life, one per frame, that keep every voxel and the floor under the
// body in the image in every frame (render/src/camera_path.cpp). `base` gives the view
// direction, field of view and projection; its target and distance are replaced: the target
// follows the centre of each frame's bounding box (voxels as their circumscribed spheres,
// down to the floor), smoothed over about `smoothing_s` seconds of frames; the distance (or
// orthographic height) is one for the whole life, at least follow_camera's for `zoom`, and
// far enough that every frame's box projects inside `fill` of the image (fraction of the
// half-width and half-height around the centre). `aspect` = image width / height.
std::vector<Camera> life_cameras(const Model& model, const std::vector<const Frame*>& frames,
                                 const Camera& base, double aspect, double zoom = 1.0,
                                 double smoothing_s = 0.5, double fill = 0.92);

// Boxes of one frame: each voxel at its recorded centre, orientation and actuated edge
// length, coloured by `scale`.
std::vector<Box> frame_boxes(const Model& model, const Frame& frame, const ColorScale& scale);

// Viewport in pixels: x from the left, y from the top of the image.
struct PixelRect {
  int x = 0, y = 0, width = 0, height = 0;
};

// Rasterizes scenes into an OffscreenContext with GLSL 3.30 shaders from assets/shaders:
// shadow-map pass from the key light, then floor and instanced voxel boxes into a
// multisampled buffer that is resolved into the viewport. Holds GL objects of ctx (create
// and use it while ctx is alive, on ctx's thread). Deterministic: the same scene gives the
// same pixels.
class SceneRenderer {
 public:
  explicit SceneRenderer(OffscreenContext& ctx);  // throws RenderError (assets, shaders)
  ~SceneRenderer();
  SceneRenderer(const SceneRenderer&) = delete;
  SceneRenderer& operator=(const SceneRenderer&) = delete;

  // Draws the scene into `viewport` of the image (whole image when its width is 0),
  // replacing what was there: background, floor, shadow, boxes.
  void draw(const Scene& scene, PixelRect viewport = {});

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace plastivox::render
