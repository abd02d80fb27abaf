// Contact with an environment (environment.hpp): the ground as a height field and static
// boxes, with the floor's own contact model, voxel by voxel (scalar; only when an
// environment is defined: the flat floor keeps its batched kernel, voxel_body.hpp).
//
// The model is the floor's, with the floor's plane replaced by the plane under the voxel:
// - a voxel is a ball of half its actuated size (tilt ignored) at its centre. Against the
//   ground, its penetration is that half size less the centre's distance to the ground's
//   tangent plane under the centre; against a box, the box grown by the half size holds the
//   centre, and the contact is through the nearest face (least penetration), normal along
//   that face's axis;
// - the normal force is 2 E L per unit of penetration, damped by the collision damping on
//   the normal velocity; static friction holds the voxel while the tangential load is below
//   mu_s N; a sliding voxel feels mu_k N against its tangential velocity and is stopped when
//   that would reverse it within the step.
// Where the contact normal is an axis (a level ground, every box face) each operation is the
// floor kernel's, in the same order, so a flat ground at height 0 gives the floor's bits. On
// a slope the tangential parts are the vectors less their normal parts; a voxel held there
// keeps being held while its tangential load stays under the static limit (its tangential
// velocity is zero only up to rounding, so "at rest" also reads last step's static flag).
// Contacts are applied in order: the ground, then the boxes in their order.
//
// Thin boxes: a penalty contact cannot stop a voxel that crosses a box within one step (at
// 100 m/s, the speed limit, a step of 1.4 ms is 14 cm). After the update each step's path
// of the centre is tested against each grown box: a path that reaches the box's middle plane
// along the axis it entered by (or, from inside, crosses the middle plane of its nearest
// face) is stopped at the face it entered by (or where it was), its momentum along that axis
// zeroed: an inelastic impact. Slower contacts never reach the middle and feel the penalty
// alone.
#include <algorithm>
#include <cmath>
#include <limits>

#include "terrain_body.hpp"
#include "workspace.hpp"

namespace plastivox {

int crossing_stop(const double lo[3], const double hi[3], const double x0[3], const double x1[3],
                  int& where) {
  for (int a = 0; a < 3; ++a)  // the path's bounds miss the box
    if (std::max(x0[a], x1[a]) <= lo[a] || std::min(x0[a], x1[a]) >= hi[a]) return -1;
  double t_in = -std::numeric_limits<double>::infinity();
  double t_out = std::numeric_limits<double>::infinity();
  int axis_in = -1;
  for (int a = 0; a < 3; ++a) {
    const double d = x1[a] - x0[a];
    if (d == 0) {
      if (!(x0[a] > lo[a] && x0[a] < hi[a])) return -1;
      continue;
    }
    double t0 = (lo[a] - x0[a]) / d, t1 = (hi[a] - x0[a]) / d;
    if (t0 > t1) std::swap(t0, t1);
    if (t0 > t_in) t_in = t0, axis_in = a;
    t_out = std::min(t_out, t1);
  }
  if (!(t_in < t_out) || t_out <= 0 || t_in >= 1) return -1;  // the path misses the box
  int a;
  if (t_in > 0) {  // from outside, through the face on axis_in facing x0
    a = axis_in;
    where = x1[a] > x0[a] ? 0 : 1;
  } else {  // from inside: along the axis of the nearest face, back where it was
    double depth;
    a = nearest_face(lo, hi, x0, depth).axis;
    where = 2;
  }
  const double mid = 0.5 * (lo[a] + hi[a]);
  if (x1[a] == x0[a] || (x0[a] - mid) * (x1[a] - mid) > 0) return -1;  // stays on its half
  const double t_mid = (mid - x0[a]) / (x1[a] - x0[a]);
  if (t_mid > t_out) return -1;  // left the box by a side before the middle
  return a;
}

namespace {

// The boxes (indices, increasing) that a voxel of half size up to r_max whose centre lies
// in [lo, hi] may touch: a cheap pass over the boxes once a step, so each voxel tests only
// the boxes near the body.
void boxes_near(const std::vector<ObstacleBox>& boxes, const Vec3& lo, const Vec3& hi, double r_max,
                std::vector<int>& out) {
  out.clear();
  for (size_t b = 0; b < boxes.size(); ++b) {
    bool near = true;
    for (int a = 0; a < 3; ++a)
      near = near && boxes[b].min[a] - r_max < hi[a] && boxes[b].max[a] + r_max > lo[a];
    if (near) out.push_back(static_cast<int>(b));
  }
}

// The bounds of the voxels' centres (and, when given, of a second set of centres), and the
// largest half size.
void body_bounds(const State& s, const std::vector<Vec3>* also, Vec3& lo, Vec3& hi, double& r_max) {
  lo = hi = s.pos[0];
  r_max = 0;
  for (size_t i = 0; i < s.pos.size(); ++i) {
    lo = lo.cwiseMin(s.pos[i]), hi = hi.cwiseMax(s.pos[i]);
    if (also) lo = lo.cwiseMin((*also)[i]), hi = hi.cwiseMax((*also)[i]);
    r_max = std::max(r_max, 0.5 * s.size[i]);
  }
}

}  // namespace

void terrain_contacts(const Model& m, State& s, Workspace& w) {
  const std::vector<ObstacleBox>& boxes = m.def.environment.obstacles;
  if (!boxes.empty()) {
    Vec3 lo, hi;
    double r_max;
    body_bounds(s, nullptr, lo, hi, r_max);
    boxes_near(boxes, lo, hi, r_max, w.terrain_boxes);
  }
  for (int i = 0; i < m.n; ++i) {
    const Vec3& x = s.pos[i];
    double f[3] = {w.force[0][i], w.force[1][i], w.force[2][i]};
    bool held = false;
    w.terrain_normal[i] = voxel_terrain_contacts(
        m, w.terrain_boxes, i, x.data(), 0.5 * s.size[i], s.stiffness[i], w.sqrt_e[i],
        s.static_friction[i] != 0, s.dt, f, s.lin_mom[i].data(), held, [](uint64_t) {});
    for (int a = 0; a < 3; ++a) w.force[a][i] = f[a];
    w.terrain_held[i] = held;
    w.terrain_prev[i] = x;
  }
}

double terrain_penetration(const Model& m, const Vec3& x, double r) {
  double total = 0;
  if (m.def.floor) total += std::max(0.0, m.ground.penetration(x.x(), x.y(), x.z(), r));
  for (const ObstacleBox& b : m.def.environment.obstacles) {
    double lo[3], hi[3];
    grown_box(b, r, lo, hi);
    if (!inside_box(lo, hi, x.data())) continue;
    double pen;
    nearest_face(lo, hi, x.data(), pen);
    total += pen;
  }
  return total;
}

void terrain_after_update(const Model& m, State& s, Workspace& w) {
  const std::vector<ObstacleBox>& boxes = m.def.environment.obstacles;
  if (!boxes.empty()) {  // the boxes near the paths of this step
    Vec3 lo, hi;
    double r_max;
    body_bounds(s, &w.terrain_prev, lo, hi, r_max);
    boxes_near(boxes, lo, hi, r_max, w.terrain_boxes);
  }
  for (int i = 0; i < m.n; ++i) {
    if (m.fixed[i]) continue;  // the update kept its flag
    s.static_friction[i] = w.terrain_held[i];
    voxel_box_stops(m, w.terrain_boxes, 0.5 * s.size[i], w.terrain_prev[i].data(), s.pos[i].data(),
                    s.lin_mom[i].data(), [](uint64_t) {});
  }
  if (!w.floor_normal.empty())
    std::copy(w.terrain_normal.begin(), w.terrain_normal.end(), w.floor_normal.begin());
}

}  // namespace plastivox
