// A camera path for a whole life. Why not follow_camera per frame: that frames the robot's
// rest extent around its centre of mass, so a robot that rears up, tips over or stretches
// leaves the image (the bottom row and its floor contact were cut off in videos). Here the
// whole life is known before drawing: each frame's bounding box (every voxel's circumscribed
// sphere, extended down to the ground) gives a target, the targets are smoothed so the camera
// glides, and one distance for the life is the smallest that keeps every frame's box inside
// the image around its smoothed target (so the scale bar holds for the whole video).
#include <algorithm>
#include <array>
#include <cmath>

#include "plastivox/render/scene.hpp"

namespace plastivox::render {
namespace {

struct Box3 {
  Eigen::Vector3d lo, hi;
};

// The frame's voxels as spheres of radius edge * sqrt(3) / 2 (whatever their orientation),
// and the ground under them (the floor z = 0, or the environment's ground under each voxel).
Box3 frame_box(const Model& model, const Frame& frame) {
  Box3 b{Eigen::Vector3d::Constant(1e30), Eigen::Vector3d::Constant(-1e30)};
  double ground = model.terrain ? 1e30 : 0.0;
  for (int i = 0; i < model.n; ++i) {
    const double r = 0.5 * std::sqrt(3.0) * frame.size[i];
    b.lo = b.lo.cwiseMin(frame.pos[i] - Eigen::Vector3d::Constant(r));
    b.hi = b.hi.cwiseMax(frame.pos[i] + Eigen::Vector3d::Constant(r));
    if (model.terrain)
      ground = std::min(ground, model.ground.height(frame.pos[i].x(), frame.pos[i].y()));
  }
  if (model.n == 0) {
    b.lo = b.hi = Eigen::Vector3d::Zero();
    ground = 0;
  }
  b.lo.z() = std::min(b.lo.z(), ground);
  return b;
}

// Whether the box's corners project inside `fill` of the image seen by camera c.
bool fits(const Camera& c, const Box3& b, double aspect, double fill) {
  const Eigen::Matrix4d vp = c.view_projection(aspect, 1e-3, 1e3);
  for (int k = 0; k < 8; ++k) {
    const Eigen::Vector4d p((k & 1) ? b.hi.x() : b.lo.x(), (k & 2) ? b.hi.y() : b.lo.y(),
                            (k & 4) ? b.hi.z() : b.lo.z(), 1.0);
    const Eigen::Vector4d q = vp * p;
    if (q.w() <= 1e-9) return false;  // behind the eye
    if (std::abs(q.x() / q.w()) > fill || std::abs(q.y() / q.w()) > fill) return false;
  }
  return true;
}

}  // namespace

std::vector<Camera> life_cameras(const Model& model, const std::vector<const Frame*>& frames,
                                 const Camera& base, double aspect, double zoom, double smoothing_s,
                                 double fill) {
  const size_t n = frames.size();
  std::vector<Camera> cams(n, base);
  if (n == 0) return cams;
  std::vector<Box3> boxes(n);
  std::vector<Eigen::Vector3d> centres(n);
  for (size_t k = 0; k < n; ++k) {
    boxes[k] = frame_box(model, *frames[k]);
    centres[k] = 0.5 * (boxes[k].lo + boxes[k].hi);
  }

  // Smoothing: a Gaussian of standard deviation smoothing_s / 2 over the frame times,
  // truncated at 3 sigma, normalised over the frames there are (so the ends do not sag).
  const double sigma = std::max(smoothing_s, 1e-9) / 2;
  for (size_t k = 0; k < n; ++k) {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    double weight = 0;
    for (size_t j = 0; j < n; ++j) {
      const double dt = frames[j]->time - frames[k]->time;
      if (std::abs(dt) > 3 * sigma) continue;
      const double w = std::exp(-0.5 * dt * dt / (sigma * sigma));
      sum += w * centres[j];
      weight += w;
    }
    cams[k].target = weight > 0 ? Eigen::Vector3d(sum / weight) : centres[k];
  }

  // One distance (or orthographic height) for the life: at least follow_camera's, then
  // doubled until every frame fits and bisected down to within 0.5 % of the smallest.
  const Camera rest = follow_camera(model, *frames[0], zoom);
  const auto all_fit = [&](double d) {
    for (size_t k = 0; k < n; ++k) {
      Camera c = cams[k];
      c.distance = d;
      c.ortho_height = d;
      if (!fits(c, boxes[k], aspect, fill)) return false;
    }
    return true;
  };
  double lo = base.orthographic ? rest.ortho_height : rest.distance;
  double hi = lo;
  if (!all_fit(hi)) {
    for (int i = 0; i < 40 && !all_fit(hi); ++i) {
      lo = hi;
      hi *= 2;
    }
    for (int i = 0; i < 40 && hi > lo * 1.005; ++i) {
      const double mid = 0.5 * (lo + hi);
      (all_fit(mid) ? hi : lo) = mid;
    }
  }
  for (Camera& c : cams) {
    c.distance = hi;
    c.ortho_height = hi;
  }
  return cams;
}

}  // namespace plastivox::render
