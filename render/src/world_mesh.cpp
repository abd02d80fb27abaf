// The world's surfaces as triangles (no GL): an environment's ground over the square the
// floor would cover, and its obstacle boxes (plastivox/render/scene.hpp, world_triangles).
//
// Why cut the ground along its bends: a height field is bilinear between nodes, and the
// generated grounds are sampled every `edge` (1 mm by default), so a ramp half a metre long
// has 500 nodes along x of which two matter; stairs have two per riser. Cutting only where
// the surface bends keeps the mesh small and exact (a riser stays one edge wide) and
// leaves a flat ground as two triangles, like the floor.
#include <algorithm>
#include <cmath>

#include "plastivox/render/scene.hpp"

namespace plastivox::render {
namespace {

// Appends the triangle (p, q, r) with the unit normal n to `out`.
void triangle(std::vector<float>& out, const Eigen::Vector3d& p, const Eigen::Vector3d& q,
              const Eigen::Vector3d& r, const Eigen::Vector3d& n) {
  for (const Eigen::Vector3d* c : {&p, &q, &r})
    out.insert(out.end(),
               {static_cast<float>(c->x()), static_cast<float>(c->y()), static_cast<float>(c->z()),
                static_cast<float>(n.x()), static_cast<float>(n.y()), static_cast<float>(n.z())});
}

// The ground's triangles over the cells of the cuts xs x ys; `inside` selects the cells in
// the rectangle (lo, hi) or the others.
void ground_cells(std::vector<float>& out, const HeightField& f, const std::vector<double>& xs,
                  const std::vector<double>& ys, const Eigen::Vector2d& lo,
                  const Eigen::Vector2d& hi, bool inside) {
  const size_t nx = xs.size();
  std::vector<Eigen::Vector3d> p(nx * ys.size());
  for (size_t j = 0; j < ys.size(); ++j)
    for (size_t i = 0; i < nx; ++i) p[i + nx * j] = {xs[i], ys[j], f.height(xs[i], ys[j])};
  for (size_t j = 0; j + 1 < ys.size(); ++j)
    for (size_t i = 0; i + 1 < nx; ++i) {
      const bool in =
          xs[i] >= lo.x() && xs[i + 1] <= hi.x() && ys[j] >= lo.y() && ys[j + 1] <= hi.y();
      if (in != inside) continue;
      const Eigen::Vector3d &a = p[i + nx * j], &b = p[i + 1 + nx * j];
      const Eigen::Vector3d &c = p[i + 1 + nx * (j + 1)], &d = p[i + nx * (j + 1)];
      // Counter-clockwise seen from above, so each normal points up.
      triangle(out, a, b, c, (b - a).cross(c - a).normalized());
      triangle(out, a, c, d, (c - a).cross(d - a).normalized());
    }
}

// The 12 triangles of an axis-aligned box, outward normals.
void box_faces(std::vector<float>& out, const ObstacleBox& box) {
  const Eigen::Vector3d lo(box.min[0], box.min[1], box.min[2]);
  const Eigen::Vector3d hi(box.max[0], box.max[1], box.max[2]);
  for (int axis = 0; axis < 3; ++axis)
    for (int side = 0; side < 2; ++side) {
      const int u = (axis + 1) % 3, v = (axis + 2) % 3;
      Eigen::Vector3d corner[4];
      for (int k = 0; k < 4; ++k) {
        corner[k][axis] = side ? hi[axis] : lo[axis];
        corner[k][u] = (k == 1 || k == 2) ? hi[u] : lo[u];
        corner[k][v] = k >= 2 ? hi[v] : lo[v];
      }
      Eigen::Vector3d n = Eigen::Vector3d::Zero();
      n[axis] = side ? 1 : -1;
      triangle(out, corner[0], corner[1], corner[2], n);
      triangle(out, corner[0], corner[2], corner[3], n);
    }
}

}  // namespace

std::vector<double> ground_bends(const HeightField& f, int axis, double from, double to,
                                 int max_lines) {
  const int n = axis == 0 ? f.nx : f.ny, across = axis == 0 ? f.ny : f.nx;
  const double origin = axis == 0 ? f.x0 : f.y0;
  std::vector<double> lines;
  if (n < 2 || !(to > from)) return lines;
  const auto height = [&](int i, int j) {
    return axis == 0 ? f.h[i + size_t(f.nx) * j] : f.h[j + size_t(f.nx) * i];
  };
  // The nodes inside (from, to), found without stepping through the others.
  const auto node = [&](double u) {
    return static_cast<int>(std::clamp(std::floor((u - origin) / f.cell), 0.0, n - 1.0));
  };
  for (int i = node(from), last = std::min(node(to) + 1, n - 1); i <= last; ++i) {
    const double u = origin + i * f.cell;
    if (!(u > from && u < to)) continue;
    bool bends = false;
    for (int j = 0; j < across && !bends; ++j) {
      // Past the grid the heights continue level: an end line bends where the grid slopes.
      const double b = height(i, j);
      const double a = i > 0 ? height(i - 1, j) : b, c = i + 1 < n ? height(i + 1, j) : b;
      // Straight across up to rounding (profiles are sampled in floating point).
      bends = std::abs(a - 2 * b + c) > 1e-7 * (f.cell + std::abs(a) + std::abs(b) + std::abs(c));
    }
    if (bends) lines.push_back(u);
  }
  if (static_cast<int>(lines.size()) > max_lines) {
    const size_t k = (lines.size() + max_lines - 1) / max_lines;
    std::vector<double> kept;
    for (size_t i = 0; i < lines.size(); i += k) kept.push_back(lines[i]);
    lines = std::move(kept);
  }
  return lines;
}

WorldTriangles world_triangles(const HeightField* ground, std::span<const ObstacleBox> obstacles,
                               const Eigen::Vector2d& centre, double half,
                               const Eigen::Vector2d& lo_in, const Eigen::Vector2d& hi_in) {
  WorldTriangles out;
  const Eigen::Vector2d a = centre.array() - half, b = centre.array() + half;
  const Eigen::Vector2d lo = lo_in.cwiseMax(a).cwiseMin(b);
  const Eigen::Vector2d hi = hi_in.cwiseMax(lo).cwiseMin(b);
  if (ground) {
    std::vector<double> cuts[2];
    for (int axis = 0; axis < 2; ++axis) {
      cuts[axis] = ground_bends(*ground, axis, a[axis], b[axis], kMaxGroundLines);
      cuts[axis].insert(cuts[axis].end(), {a[axis], lo[axis], hi[axis], b[axis]});
      std::sort(cuts[axis].begin(), cuts[axis].end());
      cuts[axis].erase(std::unique(cuts[axis].begin(), cuts[axis].end()), cuts[axis].end());
    }
    for (int run = 0; run < 2; ++run) {
      const size_t before = out.corners.size();
      ground_cells(out.corners, *ground, cuts[0], cuts[1], lo, hi, run == 0);
      out.counts[run] = static_cast<int>((out.corners.size() - before) / 6);
    }
  }
  for (int run = 2; run < 4; ++run) {
    const size_t before = out.corners.size();
    for (const ObstacleBox& box : obstacles) {
      const auto overlaps = [&](const Eigen::Vector2d& l, const Eigen::Vector2d& h) {
        return box.min[0] <= h.x() && box.max[0] >= l.x() && box.min[1] <= h.y() &&
               box.max[1] >= l.y();
      };
      if (!overlaps(a, b)) continue;  // past where the floor fades out
      const bool shadowed = hi.x() > lo.x() && hi.y() > lo.y() && overlaps(lo, hi);
      if (shadowed == (run == 2)) box_faces(out.corners, box);
    }
    out.counts[run] = static_cast<int>((out.corners.size() - before) / 6);
  }
  return out;
}

}  // namespace plastivox::render
