// Contact with an environment (terrain.cpp): the ground's height and penetration
// (HeightField), a box's nearest face, and one contact's forces and friction for any number
// type, so that engine/grad's replica records the engine's own arithmetic (as the kernels'
// *_body.hpp are instantiated on its recording type), and the stop of a thin box's crossing,
// apart from its application, so that the replica takes the same decision. A comparison here
// is of values (the recording type's does not fold its outcome into the replica's event
// signature outside the stages that ask it to; the replica notes the branches itself).
#pragma once

#include <algorithm>
#include <cstdint>
#include <limits>
#include <type_traits>
#include <vector>

#include "lanes.hpp"  // root, value_of
#include "plastivox/environment.hpp"
#include "plastivox/model.hpp"
#include "plastivox/model_constants.hpp"

namespace plastivox {
namespace {

// ---- The ground (HeightField, environment.hpp) ----

// Along one axis of n nodes: the cell index i (node i and i + 1, the latter clamped), the
// fraction f in it, and whether u lies inside the grid (where the slope is not 0). Past the
// grid f is a constant.
template <class T>
inline void ground_locate(T u, int n, int& i, T& f, bool& inside) {
  inside = false;
  if (n == 1 || !(u > 0.0)) {
    i = 0, f = T(0.0);
  } else if (u >= static_cast<double>(n - 1)) {
    i = n - 2, f = T(1.0);
  } else {
    i = std::min(static_cast<int>(value_of(u)), n - 2);
    f = u - static_cast<double>(i);
    inside = true;
  }
}

// The ground's height at (x, y), bilinear in its cell, and when asked its slopes dh/dx, dh/dy
// (which depend on x and y too: the ground's curvature within a cell) and the cell's indices.
template <class T>
inline T ground_height(const HeightField& g, T x, T y, T* gx, T* gy, int* cell = nullptr) {
  int i, j;
  T fu, fv;
  bool in_x, in_y;
  ground_locate((x - g.x0) / g.cell, g.nx, i, fu, in_x);
  ground_locate((y - g.y0) / g.cell, g.ny, j, fv, in_y);
  if (cell) cell[0] = i, cell[1] = j;
  const int i1 = std::min(i + 1, g.nx - 1), j1 = std::min(j + 1, g.ny - 1);
  const double h00 = g.h[i + size_t(g.nx) * j], h10 = g.h[i1 + size_t(g.nx) * j];
  const double h01 = g.h[i + size_t(g.nx) * j1], h11 = g.h[i1 + size_t(g.nx) * j1];
  if (gx) *gx = in_x ? ((1.0 - fv) * (h10 - h00) + fv * (h11 - h01)) / g.cell : T(0.0);
  if (gy) *gy = in_y ? ((1.0 - fu) * (h01 - h00) + fu * (h11 - h10)) / g.cell : T(0.0);
  return (1.0 - fv) * ((1.0 - fu) * h00 + fu * h10) + fv * ((1.0 - fu) * h01 + fu * h11);
}

// How far a ball of radius r at (x, y, z) presses into the ground: r less the distance from its
// centre to the tangent plane under it, whose upward unit normal goes to `normal` when asked
// (exactly (0, 0, 1) where level), the cell under the centre to `cell`.
template <class T>
inline T ground_penetration(const HeightField& g, T x, T y, T z, T r, T* normal,
                            int* cell = nullptr) {
  T gx(0.0), gy(0.0);
  const T h = ground_height(g, x, y, &gx, &gy, cell);
  if (gx == 0.0 && gy == 0.0) {
    if (normal) normal[0] = T(0.0), normal[1] = T(0.0), normal[2] = T(1.0);
    return r - (z - h);
  }
  const T inv = 1.0 / root(1.0 + gx * gx + gy * gy);
  if (normal) normal[0] = -gx * inv, normal[1] = -gy * inv, normal[2] = inv;
  return r - (z - h) * inv;
}

// ---- The boxes ----

// The box b grown by r on every side.
template <class T>
inline void grown_box(const ObstacleBox& b, T r, T lo[3], T hi[3]) {
  for (int a = 0; a < 3; ++a) lo[a] = b.min[a] - r, hi[a] = b.max[a] + r;
}

// Whether x lies strictly inside the box [lo, hi].
inline bool inside_box(const double lo[3], const double hi[3], const double x[3]) {
  return x[0] > lo[0] && x[0] < hi[0] && x[1] > lo[1] && x[1] < hi[1] && x[2] > lo[2] &&
         x[2] < hi[2];
}

// A contact's normal: +-axis `axis` exactly (sign +1 or -1), or any unit vector n (axis -1).
template <class T>
struct ContactNormal {
  int axis = -1;
  double sign = 1;
  T n[3] = {T(0.0), T(0.0), T(1.0)};
};

// The tangential part of v: v less its normal part (on an axis: v with that component 0).
template <class T>
inline void tangent(const ContactNormal<T>& c, const T v[3], T t[3]) {
  if (c.axis >= 0) {
    for (int k = 0; k < 3; ++k) t[k] = k == c.axis ? T(0.0) : v[k];
    return;
  }
  const T vn = v[0] * c.n[0] + v[1] * c.n[1] + v[2] * c.n[2];
  for (int k = 0; k < 3; ++k) t[k] = v[k] - vn * c.n[k];
}

// v less its tangential part (on an axis: the other components set to 0).
template <class T>
inline void drop_tangent(const ContactNormal<T>& c, T v[3]) {
  if (c.axis >= 0) {
    for (int k = 0; k < 3; ++k)
      if (k != c.axis) v[k] = T(0.0);
    return;
  }
  T t[3];
  tangent(c, v, t);
  for (int k = 0; k < 3; ++k) v[k] = v[k] - t[k];
}

// The face of the grown box [lo, hi] nearest to x inside it: its axis, its outward sign, and
// its depth (the penetration).
template <class T>
inline ContactNormal<T> nearest_face(const T lo[3], const T hi[3], const T x[3], T& depth) {
  ContactNormal<T> c;
  depth = T(std::numeric_limits<double>::infinity());
  for (int a = 0; a < 3; ++a) {
    const T below = x[a] - lo[a], above = hi[a] - x[a];
    if (below < depth) depth = below, c.axis = a, c.sign = -1;
    if (above < depth) depth = above, c.axis = a, c.sign = 1;
  }
  return c;
}

// One contact of penetration pen > 0 (m) on a voxel of modulus E (sqrt(E) = se): the normal
// force, damping and Coulomb friction on its force f (N), a stop on its momentum p (kg m/s);
// returns the normal force (N) and sets held when static friction holds the voxel or a stop
// brought it to rest.
template <class T>
inline T apply_contact(const ContactNormal<T>& c, T pen, T E, T se, bool was_held,
                       const ModelConstants& k, T dt, T f[3], T p[3], bool& held,
                       int* regime = nullptr) {
  const T normal = 2.0 * E * k.size * pen;
  T v[3], vt[3], ft[3];
  for (int a = 0; a < 3; ++a) v[a] = p[a] * k.inv_mass;
  const T vn = c.axis >= 0 ? c.sign * v[c.axis] : v[0] * c.n[0] + v[1] * c.n[1] + v[2] * c.n[2];
  const T c_col = k.c_col_unit * se;
  tangent(c, v, vt);
  tangent(c, f, ft);
  // At rest: stick unless the tangential load exceeds the static limit.
  const bool still = vt[0] == 0.0 && vt[1] == 0.0 && vt[2] == 0.0;
  const bool at_rest = still || (c.axis < 0 && was_held);
  const bool sticks =
      root(ft[0] * ft[0] + ft[1] * ft[1] + ft[2] * ft[2]) < k.def.mu_static * normal;
  // Sliding: kinetic friction against the tangential velocity, or a stop if it would reverse
  // the motion within this step.
  const T speed = root(vt[0] * vt[0] + vt[1] * vt[1] + vt[2] * vt[2]);
  const T fric = k.def.mu_kinetic * normal;
  const bool moving = !at_rest;
  const bool slides = moving && fric * dt < k.mass * speed;
  const bool stops = moving && !slides;
  if (slides)
    for (int a = 0; a < 3; ++a) f[a] = f[a] - fric * vt[a] / speed;
  if (stops) drop_tangent(c, p);
  const T push = normal - c_col * vn;
  if (c.axis >= 0)
    f[c.axis] = f[c.axis] + c.sign * push;
  else
    for (int a = 0; a < 3; ++a) f[a] = f[a] + push * c.n[a];
  const bool holds = (at_rest && sticks) || stops;
  if (holds) drop_tangent(c, f);
  // On a slope a held voxel's tangential momentum is zero only up to rounding: drop it, so it
  // does not creep. (On an axis it is exactly zero already, as on the floor.)
  if (holds && c.axis < 0) drop_tangent(c, p);
  held = held || holds;
  // (For engine/grad's event signature: held at rest, slipping from rest, sliding, stopped.)
  if (regime) *regime = at_rest ? (sticks ? 1 : 2) : (slides ? 3 : 4);
  return normal;
}

// One voxel's contacts with the ground (with m.def.floor) and with the boxes listed in `near`
// (indices into the environment's boxes, increasing: any list holding every box its centre lies
// in), in terrain.cpp's order: the ground, then the boxes. x is its centre, r half its actuated
// size, E its modulus and se sqrt(E); f and p its force and momentum, changed; held as
// apply_contact's. Returns the summed normal force. A contact is decided on values; on the
// recording type a voxel out of contact computes nothing. `note` receives each branch taken
// (engine/grad's event signature: voxel i on the ground and the cell under it, a box's face,
// each contact's friction regime); the engine's does nothing.
template <class T, class Note>
inline T voxel_terrain_contacts(const Model& m, const std::vector<int>& near, int i, const T x[3],
                                T r, T E, T se, bool was_held, T dt, T f[3], T p[3], bool& held,
                                Note&& note) {
  const ModelConstants& k = m;
  T normal(0.0);
  const auto contact = [&](const ContactNormal<T>& c, T pen) {
    int regime = 0;
    normal = normal + apply_contact(c, pen, E, se, was_held, k, dt, f, p, held, &regime);
    note(0xc0 + uint64_t(regime));
  };
  const double centre[3] = {value_of(x[0]), value_of(x[1]), value_of(x[2])};
  if (m.def.floor && (std::is_same_v<T, double> ||
                      m.ground.penetration(centre[0], centre[1], centre[2], value_of(r)) > 0)) {
    ContactNormal<T> c;
    int cell[2];
    const T pen = ground_penetration(m.ground, x[0], x[1], x[2], r, c.n, cell);
    if (pen > 0.0) {
      note(0x9000 + uint64_t(i));  // touching, and the cell (between cells: a kink)
      note((uint64_t(uint32_t(cell[0])) << 32) + uint32_t(cell[1]));
      if (c.n[0] == 0.0 && c.n[1] == 0.0) c.axis = 2;
      contact(c, pen);
    }
  }
  for (int b : near) {
    const ObstacleBox& box = m.def.environment.obstacles[b];
    double lo[3], hi[3];
    grown_box(box, value_of(r), lo, hi);
    if (!inside_box(lo, hi, centre)) continue;
    T glo[3], ghi[3], pen;
    grown_box(box, r, glo, ghi);
    const ContactNormal<T> c = nearest_face(glo, ghi, x, pen);
    note(0xb0000 + 8 * uint64_t(b) + 2 * uint64_t(c.axis) + (c.sign > 0 ? 1 : 0));
    contact(c, pen);
  }
  return normal;
}

}  // namespace

// Whether the path x0 -> x1 of a voxel's centre in one step is stopped by the grown box
// [lo, hi] (terrain.cpp, "Thin boxes"): the axis along which it is (its momentum along it then
// zeroed), or -1; `where` says at what along that axis: lo[axis] (0), hi[axis] (1), or back at
// x0[axis] (2).
int crossing_stop(const double lo[3], const double hi[3], const double x0[3], const double x1[3],
                  int& where);

namespace {

// The stops of a voxel's path x0 -> x1 in one step by the boxes listed in `near` (as in
// voxel_terrain_contacts), r half its actuated size: where crossing_stop stops it, x1 is put
// back at the face it entered by, box -+ r, or where it was, x0, and p zeroed along that axis.
// Returns whether any box stopped it. `note` as voxel_terrain_contacts'.
template <class T, class Note>
inline bool voxel_box_stops(const Model& m, const std::vector<int>& near, T r, const T x0[3],
                            T x1[3], T p[3], Note&& note) {
  bool stopped = false;
  for (int b : near) {
    const ObstacleBox& box = m.def.environment.obstacles[b];
    double lo[3], hi[3], from[3], to[3];
    grown_box(box, value_of(r), lo, hi);
    for (int a = 0; a < 3; ++a) from[a] = value_of(x0[a]), to[a] = value_of(x1[a]);
    int where = 0;
    const int a = crossing_stop(lo, hi, from, to, where);
    if (a < 0) continue;
    note(0x5700 + 4 * uint64_t(a) + uint64_t(where) + (uint64_t(b) << 16));
    x1[a] = where == 0 ? box.min[a] - r : where == 1 ? box.max[a] + r : x0[a];
    p[a] = T(0.0);
    stopped = true;
  }
  return stopped;
}

}  // namespace

}  // namespace plastivox
