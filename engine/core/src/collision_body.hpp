// Self-collision (contacts.cpp): the candidate pairs of a step, and one pair's contact for any
// number type, so that engine/grad's replica takes the engine's own candidates and records the
// engine's own arithmetic on them (as terrain_body.hpp does an environment's contact). A
// comparison here is of values (the recording type's does not fold its outcome into the
// replica's event signature here; the replica notes what pair_contact returns).
#pragma once

#include <algorithm>

#include "lanes.hpp"  // root, load, store
#include "workspace.hpp"

namespace plastivox {

// The candidate pairs that may touch this step, from the partner lists (brought up to date
// from s's centres; the pairs' centres and sizes read from w.centre_size): returns their count
// c, pair k < c being (w.contact_grid.pair_a[p], pair_b[p]) for p = w.contact_grid.touching[k],
// in increasing (i, j) order, i < j. Every pair that touches is among them; a few that do not
// may be (pair_contact decides).
int self_collision_candidates(const Model& m, const State& s, Workspace& w);

// What pair_contact found: apart, the self-contact spring, or an object's contact with no
// tangential velocity, sliding under kinetic friction, or stopped (the friction's cap).
enum class PairContact { kApart, kSpring, kObjectStill, kObjectSliding, kObjectStopped };

namespace {

// The contact of candidate pair (i, j), i < j, added to w.force, equal and opposite on the two.
// Contact engages when the centres are closer than half_d (size_i + size_j): half_d is half of
// contact_diameter between robot voxels, and with an object voxel (j >= robot_n) half of its
// lesser with 1 (faces touching). Its stiffness is the harmonic-mean axial bond constant E_b L.
// Between robot voxels it is a linear spring along the centres. With an object (object_contact)
// the spring is damped on the normal velocity by collision_damping (2 zeta sqrt(m_r k), m_r =
// m / 2 the pair's reduced mass), and kinetic friction mu_k N acts against the pair's relative
// tangential velocity, capped at the force that stops that sliding within the step
// (m_r |v_t| / dt), as the floor stops a voxel rather than reverse it. dt is this step's.
template <class T>
inline PairContact pair_contact(const Model& m, const State& s, Workspace& w, int i, int j, T dt) {
  const double* pos = s.pos[0].data();
  const double* size = s.size.data();
  T d[3];  // from i to j
  for (int c = 0; c < 3; ++c) d[c] = load(pos, 3 * j + c, T{}) - load(pos, 3 * i + c, T{});
  const bool object = j >= m.robot_n;
  const double half_d =
      0.5 * (object ? std::min(1.0, m.def.contact_diameter) : m.def.contact_diameter);
  const T contact = half_d * (load(size, i, T{}) + load(size, j, T{}));
  const T dist2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
  if (dist2 >= contact * contact) return PairContact::kApart;
  const T dist = root(dist2);
  if (dist == 0.0) return PairContact::kApart;  // coincident centres: no direction to push along
  const T ei = load(s.stiffness.data(), i, T{}), ej = load(s.stiffness.data(), j, T{});
  const T k = 2.0 * ei * ej / (ei + ej) * m.size;
  T f[3];  // on j
  PairContact what = PairContact::kSpring;
  if (!object) {
    const T scale = k * (contact - dist) / dist;  // pushes j away from i
    for (int c = 0; c < 3; ++c) f[c] = d[c] * scale;
  } else {
    const double* mom = s.lin_mom[0].data();
    T n[3], v[3], vt[3];  // v: j relative to i
    for (int c = 0; c < 3; ++c) {
      n[c] = d[c] / dist;
      v[c] = (load(mom, 3 * j + c, T{}) - load(mom, 3 * i + c, T{})) / m.mass;
    }
    const T vn = v[0] * n[0] + v[1] * n[1] + v[2] * n[2];
    const double m_r = 0.5 * m.mass;
    const T normal = k * (contact - dist);
    const T push = normal - m.def.collision_damping * 2.0 * root(m_r * k) * vn;
    for (int c = 0; c < 3; ++c) f[c] = n[c] * push, vt[c] = v[c] - vn * n[c];
    const T speed = root(vt[0] * vt[0] + vt[1] * vt[1] + vt[2] * vt[2]);
    what = PairContact::kObjectStill;
    if (speed > 0.0) {
      const T kinetic = m.def.mu_kinetic * normal, stop = m_r * speed / dt;
      const bool stopping = stop < kinetic;  // std::min(kinetic, stop)
      what = stopping ? PairContact::kObjectStopped : PairContact::kObjectSliding;
      const T friction = stopping ? stop : kinetic;
      for (int c = 0; c < 3; ++c) f[c] = f[c] - vt[c] * (friction / speed);
    }
  }
  for (int c = 0; c < 3; ++c) {
    store(w.force[c].data(), j, load(w.force[c].data(), j, T{}) + f[c]);
    store(w.force[c].data(), i, load(w.force[c].data(), i, T{}) - f[c]);
  }
  return what;
}

}  // namespace
}  // namespace plastivox
