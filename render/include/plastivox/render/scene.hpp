// A plain description of what to draw (no GL): coloured, posed boxes on a floor or an
// environment's ground, obstacle boxes of the world, a camera and a light. frame_boxes() and
// show_world() turn one recorded frame of a model into a Scene; SceneRenderer (the only GL
// code besides offscreen.cpp) rasterizes it.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <memory>
#include <span>
#include <vector>

#include "plastivox/environment.hpp"

#include "plastivox/model.hpp"
#include "plastivox/recording.hpp"
#include "plastivox/render/color_scale.hpp"

namespace plastivox::render {

class OffscreenContext;

struct Box {
  Eigen::Vector3f center;     // m, world axes (z up)
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
  // The world beyond the flat floor (show_world; docs/rendering.md, "The world"). Not owned:
  // they must outlive draw(). `ground`, when set, is drawn instead of the floor plane z = 0,
  // in the floor's colour and with its grid, lit by its slope; `obstacles` are drawn in
  // obstacle_color. Neither casts a shadow; both receive the robot's.
  const HeightField* ground = nullptr;
  std::span<const ObstacleBox> obstacles;
  Rgb8 obstacle_color{150, 132, 112};  // a warm stone grey, apart from every colour map
  // Anti-aliasing: kEdgeAntialiasing (0, default), 1 = none, 2..8 = multisampling with
  // that many samples per pixel.
  int samples = kEdgeAntialiasing;
};

// The camera framing a robot: target at the robot's centre of mass (z at half its rest
// height above the ground under it: the floor, z = 0, or its environment's ground), distance
// so the robot's largest rest dimension fills about 60 % of the image height (times zoom).
Camera follow_camera(const Model& model, const Frame& frame, double zoom = 1.0);

// The cameras of a whole life, one per frame, that keep every voxel and the ground under the
// body (the floor, or the environment's ground under each voxel) in the image in every frame
// (render/src/camera_path.cpp). `base` gives the view direction, field of view and projection; its
// target and distance are replaced: the target follows the centre of each frame's bounding box
// (voxels as their circumscribed spheres, down to the ground), smoothed over about `smoothing_s`
// seconds of frames; the distance (or orthographic height) is one for the whole life, at least
// follow_camera's for `zoom`, and far enough that every frame's box projects inside `fill` of the
// image (fraction of the half-width and half-height around the centre). `aspect` = image width /
// height.
std::vector<Camera> life_cameras(const Model& model, const std::vector<const Frame*>& frames,
                                 const Camera& base, double aspect, double zoom = 1.0,
                                 double smoothing_s = 0.5, double fill = 0.92);

// Boxes of one frame: each voxel at its recorded centre, orientation and actuated edge
// length, coloured by `scale`.
std::vector<Box> frame_boxes(const Model& model, const Frame& frame, const ColorScale& scale);

// Sets the scene's world from the model's environment (model.def.environment): its ground
// when one is defined (pointing into `model`, which must outlive the scene) and its obstacle
// boxes. The default environment leaves the scene's flat floor as it is.
void show_world(Scene& scene, const Model& model);

// Height of the ground under (x, y), m: the environment's ground, or the floor's 0.
double ground_height(const Model& model, double x, double y);

// The world's surfaces as the renderer draws them (no GL; render/src/world_mesh.cpp): the
// ground (none when null) and the boxes, over the square `centre` +- `half` (x, y, m) where
// the floor would be drawn. Per triangle corner:
// position (m, world axes) and its face's unit normal (outward; upward on the ground), 6
// floats. The ground is cut along the node lines of its height field where the surface bends
// (at most kMaxGroundLines per axis inside the square: beyond that every k-th), and along the
// rectangle (lo, hi), where the robot's shadow may fall; boxes outside the square are left
// out. Four runs, in this order, of the counts given: ground inside (lo, hi), the rest of
// the ground, boxes overlapping (lo, hi), the other boxes.
struct WorldTriangles {
  std::vector<float> corners;
  int counts[4] = {0, 0, 0, 0};  // corners per run
};
constexpr int kMaxGroundLines = 256;
WorldTriangles world_triangles(const HeightField* ground, std::span<const ObstacleBox> obstacles,
                               const Eigen::Vector2d& centre, double half,
                               const Eigen::Vector2d& lo, const Eigen::Vector2d& hi);

// The node lines of `field` along `axis` (0: x, 1: y) strictly inside (from, to) where the
// ground bends: lines the surface is not straight across along that axis (past the grid the
// heights continue level, so an end line bends where the grid slopes there), m, ascending. More
// than `max_lines` are thinned to every k-th. A ramp gives its two ends, stairs two lines per
// riser.
std::vector<double> ground_bends(const HeightField& field, int axis, double from, double to,
                                 int max_lines);

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
