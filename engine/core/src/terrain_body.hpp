// Contact with an environment (terrain.cpp): one contact's forces and friction for any number
// type, so that engine/grad's replica records the engine's own arithmetic (as the kernels'
// *_body.hpp are instantiated on its recording type), and the stop of a thin box's crossing,
// apart from its application, so that the replica takes the same decision.
#pragma once

#include "lanes.hpp"  // root
#include "plastivox/model_constants.hpp"

namespace plastivox {
namespace {

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

}  // namespace

// Whether the path x0 -> x1 of a voxel's centre in one step is stopped by the grown box
// [lo, hi] (terrain.cpp, "Thin boxes"): the axis along which it is (its momentum along it then
// zeroed), or -1; `where` says at what along that axis: lo[axis] (0), hi[axis] (1), or back at
// x0[axis] (2).
int crossing_stop(const double lo[3], const double hi[3], const double x0[3], const double x1[3],
                  int& where);

}  // namespace plastivox
