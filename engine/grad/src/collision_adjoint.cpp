// Self-collision, recorded (collision_adjoint.hpp).
#include "collision_adjoint.hpp"

#include <algorithm>

#include "terrain_adjoint.hpp"

namespace plastivox::grad {

// The pairs that can touch until the next refresh, in increasing order: those whose centres
// were within reach when the list was made (anchor_ the centres then). A pair touching now is
// closer than half_d (size_i + size_j) <= 2 half_d size_top_; while no voxel has moved more
// than kDrift L from its anchor and no size has grown past size_top_, its centres were then
// closer than that plus 2 kDrift L, which is reach. Otherwise the list is made again.
void CollisionReplica::refresh_near_pairs(const Model& m, const State& s, double half_d) {
  static constexpr double kDrift = 0.05;  // of a voxel's edge
  const double drift = kDrift * m.size;
  double size_top = 0, moved2 = 0;
  for (int i = 0; i < m.n; ++i) size_top = std::max(size_top, s.size[i]);
  if (anchor_.size() == 3 * size_t(m.n))
    for (int i = 0; i < m.n && moved2 <= drift * drift; ++i) {
      const double* a = &anchor_[3 * size_t(i)];
      const double dx = s.pos[i].x() - a[0], dy = s.pos[i].y() - a[1], dz = s.pos[i].z() - a[2];
      moved2 = std::max(moved2, dx * dx + dy * dy + dz * dz);
    }
  if (anchor_.size() == 3 * size_t(m.n) && moved2 <= drift * drift && size_top <= size_top_) return;
  anchor_.resize(3 * size_t(m.n));
  for (int i = 0; i < m.n; ++i)
    for (int k = 0; k < 3; ++k) anchor_[3 * size_t(i) + k] = s.pos[i][k];
  size_top_ = size_top * (1 + 1e-3);
  const double reach = (2 * half_d * size_top_ + 2 * drift) * (1 + 1e-9);
  near_.clear();
  for (size_t p = 0; p < pair_a_.size(); ++p) {
    const Vec3 d = s.pos[pair_b_[p]] - s.pos[pair_a_[p]];
    if (d.squaredNorm() < reach * reach) near_.push_back(static_cast<int>(p));
  }
}

// apply_self_collisions (contacts.cpp): every pair of surface voxels i < j not near each
// other in the bond graph (with self-collision off, those with an object voxel j), in (i, j)
// order, as the engine adds the pairs its candidate lists find (they miss no contact, and
// the exact test is this one). A free object's contacts are object_contact's.
void CollisionReplica::apply(const Model& m, const State& s, Workspace& w, Adj dt,
                             uint64_t* events) {
  if (!m.def.self_collision && m.robot_n == m.n) return;
  const double half_d = 0.5 * m.def.contact_diameter;
  const double half_d_object = 0.5 * std::min(1.0, m.def.contact_diameter);
  if (!paired_) {  // every pair that may touch, once: (i, j), i < j, in increasing order
    for (int i = 0; i < m.n; ++i) {
      if (!m.surface[i]) continue;
      const std::vector<int>& near = m.near_voxels[i];
      for (int j = i + 1; j < m.n; ++j)
        if (m.surface[j] && !std::binary_search(near.begin(), near.end(), j) &&
            (m.def.self_collision || j >= m.robot_n))
          pair_a_.push_back(i), pair_b_.push_back(j);
    }
    paired_ = true;
  }
  refresh_near_pairs(m, s, half_d);
  const double *size = s.size.data(), *pos = s.pos.front().data();
  for (size_t c = 0; c < near_.size(); ++c) {
    const int i = pair_a_[near_[c]], j = pair_b_[near_[c]];
    const double dx = s.pos[j].x() - s.pos[i].x(), dy = s.pos[j].y() - s.pos[i].y();
    const double dz = s.pos[j].z() - s.pos[i].z();
    const bool object = j >= m.robot_n;
    const double contact = (object ? half_d_object : half_d) * (s.size[i] + s.size[j]);
    const double dist2 = dx * dx + dy * dy + dz * dz;
    if (dist2 >= contact * contact || dist2 == 0) continue;
    if (events) *events = (*events ^ ((uint64_t(i) << 32) + uint64_t(j))) * 1099511628211ull;
    if (object) {
      const Adj cont = half_d_object * (load(size, i, Adj{}) + load(size, j, Adj{}));
      object_contact_adj(m, s, w, i, j, cont, dt, events);
      continue;
    }
    Adj d[3];
    for (int k = 0; k < 3; ++k) d[k] = load(pos, 3 * j + k, Adj{}) - load(pos, 3 * i + k, Adj{});
    const Adj cont = half_d * (load(size, i, Adj{}) + load(size, j, Adj{}));
    const Adj dist = root(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    const Adj ei = load(s.stiffness.data(), i, Adj{}), ej = load(s.stiffness.data(), j, Adj{});
    const Adj k = 2.0 * ei * ej / (ei + ej) * m.size;
    const Adj scale = k * (cont - dist) / dist;
    for (int c3 = 0; c3 < 3; ++c3) {
      const Adj f = d[c3] * scale;
      put(w.force[c3].data(), j, load(w.force[c3].data(), j, Adj{}) + f);
      put(w.force[c3].data(), i, load(w.force[c3].data(), i, Adj{}) - f);
    }
  }
}

}  // namespace plastivox::grad
