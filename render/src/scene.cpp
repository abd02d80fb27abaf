// Scene building: camera math and voxel boxes from a recorded frame (no GL).
#include <algorithm>
#include <cmath>

#include "plastivox/render/life.hpp"
#include "plastivox/render/scene.hpp"
#include "plastivox/state.hpp"

namespace plastivox::render {
namespace {

constexpr double kDegToRad = 3.14159265358979323846 / 180.0;

}  // namespace

Eigen::Vector3d Camera::eye() const {
  const double az = azimuth_deg * kDegToRad, el = elevation_deg * kDegToRad;
  return target + distance * Eigen::Vector3d(std::cos(el) * std::cos(az),
                                             std::cos(el) * std::sin(az), std::sin(el));
}

Eigen::Matrix4d Camera::view_projection(double aspect, double near_m, double far_m) const {
  // View: right-handed look-at with +z up.
  const Eigen::Vector3d e = eye();
  const Eigen::Vector3d f = (target - e).normalized();
  Eigen::Vector3d up(0, 0, 1);
  if (std::abs(f.dot(up)) > 0.999) up = Eigen::Vector3d(0, 1, 0);
  const Eigen::Vector3d r = f.cross(up).normalized();
  const Eigen::Vector3d u = r.cross(f);
  Eigen::Matrix4d view = Eigen::Matrix4d::Identity();
  view.block<1, 3>(0, 0) = r.transpose();
  view.block<1, 3>(1, 0) = u.transpose();
  view.block<1, 3>(2, 0) = -f.transpose();
  view(0, 3) = -r.dot(e);
  view(1, 3) = -u.dot(e);
  view(2, 3) = f.dot(e);
  Eigen::Matrix4d proj = Eigen::Matrix4d::Zero();
  if (orthographic) {
    const double h = ortho_height / 2, w = h * aspect;
    proj(0, 0) = 1 / w;
    proj(1, 1) = 1 / h;
    proj(2, 2) = -2 / (far_m - near_m);
    proj(2, 3) = -(far_m + near_m) / (far_m - near_m);
    proj(3, 3) = 1;
  } else {
    const double t = 1 / std::tan(fov_y_deg * kDegToRad / 2);
    proj(0, 0) = t / aspect;
    proj(1, 1) = t;
    proj(2, 2) = -(far_m + near_m) / (far_m - near_m);
    proj(2, 3) = -2 * far_m * near_m / (far_m - near_m);
    proj(3, 2) = -1;
  }
  return proj * view;
}

double Camera::pixels_per_metre(int height_px) const {
  const double visible =
      orthographic ? ortho_height : 2 * distance * std::tan(fov_y_deg * kDegToRad / 2);
  return height_px / visible;
}

Camera follow_camera(const Model& model, const Frame& frame, double zoom) {
  Camera c;
  // Rest extent of the robot (bounding box of its voxels).
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e30), hi = -lo;
  for (const Eigen::Vector3d& p : model.rest_pos) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  if (model.n == 0) lo = hi = Eigen::Vector3d::Zero();
  const Eigen::Vector3d dims = (hi - lo).array() + model.size;
  const double extent = dims.maxCoeff();
  // Following the robot (free objects are framed by the extent, not followed).
  c.target = model.n ? center_of_mass(frame.pos, model.robot_n) : Eigen::Vector3d::Zero();
  c.target.z() = ground_height(model, c.target.x(), c.target.y()) + 0.5 * dims.z();
  const double visible = extent / 0.6 / std::max(zoom, 1e-3);
  c.distance = visible / (2 * std::tan(c.fov_y_deg * kDegToRad / 2));
  c.ortho_height = visible;
  return c;
}

std::vector<Box> frame_boxes(const Model& model, const Frame& frame, const ColorScale& scale) {
  std::vector<Box> boxes(model.n);
  for (int i = 0; i < model.n; ++i) {
    Box& b = boxes[i];
    b.center = frame.pos[i].cast<float>();
    b.orient = frame.orient[i].cast<float>();
    b.edge = static_cast<float>(frame.size[i]);
    b.color = scale.color(model, frame, i);
  }
  return boxes;
}

void show_world(Scene& scene, const Model& model) {
  const Environment& env = model.def.environment;
  if (model.terrain && env.ground.kind != GroundKind::kNone) scene.ground = &model.ground;
  scene.obstacles = env.obstacles;
}

double ground_height(const Model& model, double x, double y) {
  return model.terrain ? model.ground.height(x, y) : 0.0;
}

}  // namespace plastivox::render
