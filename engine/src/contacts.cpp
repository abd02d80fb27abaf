// Self-collision between surface voxels that are not close in the bond graph.
//
// Contact is a linear spring between voxel centres that engages when they come closer
// than contact_diameter times their mean actuated size; its stiffness is the harmonic-mean
// axial bond constant E_b L. Candidate pairs are cached and rebuilt only after the fastest
// voxel could have travelled half a voxel, with a search radius one voxel wider than the
// contact distance, so no pair can reach contact unseen between rebuilds.
#include <algorithm>
#include <cmath>

#include "workspace.hpp"

namespace plastivox {
namespace {

bool is_near(const Model& m, int i, int j) {
  const std::vector<int>& near = m.near_voxels[i];
  return std::binary_search(near.begin(), near.end(), j);
}

void rebuild_candidates(const Model& m, const State& s, Workspace& w) {
  const double L = m.size;
  const double contact_max = m.def.contact_diameter * L * (1.0 + m.def.act_amplitude);
  const double radius = contact_max + L;  // one voxel of travel margin (see accumulator)
  const double r2 = radius * radius;
  w.contact_pairs.clear();
  for (int i = 0; i < m.n; ++i) {
    if (!m.surface[i]) continue;
    for (int j = i + 1; j < m.n; ++j) {
      if (!m.surface[j]) continue;
      if ((s.pos[j] - s.pos[i]).squaredNorm() >= r2) continue;
      if (is_near(m, i, j)) continue;
      w.contact_pairs.emplace_back(i, j);
    }
  }
  w.travel_since_rebuild = 0;
  w.contacts_valid = true;
}

}  // namespace

void apply_self_collisions(const Model& m, const State& s, Workspace& w) {
  if (!m.def.self_collision) return;
  if (!w.contacts_valid || w.travel_since_rebuild > 0.5 * m.size) rebuild_candidates(m, s, w);
  const double L = m.size;
  const double half_d = 0.5 * m.def.contact_diameter;
  for (const auto& [i, j] : w.contact_pairs) {
    const Vec3 d = s.pos[j] - s.pos[i];
    const double contact = half_d * (w.size[i] + w.size[j]);
    const double dist2 = d.squaredNorm();
    if (dist2 >= contact * contact) continue;
    const double dist = std::sqrt(dist2);
    if (dist == 0) continue;  // coincident centres: no direction to push along
    const double ei = s.stiffness[i], ej = s.stiffness[j];
    const double k = 2.0 * ei * ej / (ei + ej) * L;
    const Vec3 f = d * (k * (contact - dist) / dist);  // pushes j away from i
    w.force[j] += f;
    w.force[i] -= f;
  }
}

}  // namespace plastivox
