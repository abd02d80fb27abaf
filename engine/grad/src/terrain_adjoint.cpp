// Contact with an environment, recorded (terrain_adjoint.hpp). A voxel's contacts with the
// ground and the boxes and the stops of its path by thin boxes are the engine's own templates
// (terrain_body.hpp's voxel_terrain_contacts and voxel_box_stops) on Adj; what is left below is
// terrain.cpp's frame around them: a change there must be made here too (gradient() checks the
// replica against the engine's life at every snapshot, and throws where they part).
#include "terrain_adjoint.hpp"

#include "terrain_body.hpp"

namespace plastivox::grad {
namespace {

Adj pos_of(const State& s, int i, int k) {
  return load(s.pos.front().data(), 3 * i + k, Adj{});
}

}  // namespace

// terrain_contacts. Every box is listed (the engine lists those boxes_near finds, a superset of
// those any centre lies in: the same contacts in the same order).
void TerrainReplica::contacts(const Model& m, State& s, Workspace& w, Adj dt, uint64_t* events) {
  all_boxes_.resize(m.def.environment.obstacles.size());
  for (size_t b = 0; b < all_boxes_.size(); ++b) all_boxes_[b] = static_cast<int>(b);
  prev_.resize(3 * size_t(m.n));
  normal_.resize(size_t(m.n));
  held_.resize(size_t(m.n));
  double* mom = s.lin_mom.front().data();
  for (int i = 0; i < m.n; ++i) {
    Adj x[3] = {pos_of(s, i, 0), pos_of(s, i, 1), pos_of(s, i, 2)};
    Adj f[3], p[3];
    for (int a = 0; a < 3; ++a) f[a] = load(w.force[a].data(), i, Adj{});
    for (int a = 0; a < 3; ++a) p[a] = load(mom, 3 * i + a, Adj{});
    bool held = false;
    normal_[i] = voxel_terrain_contacts(m, all_boxes_, i, x, 0.5 * load(s.size.data(), i, Adj{}),
                                        load(s.stiffness.data(), i, Adj{}),
                                        load(w.sqrt_e.data(), i, Adj{}), s.static_friction[i] != 0,
                                        dt, f, p, held, [events](uint64_t v) { note(events, v); });
    for (int a = 0; a < 3; ++a) put(w.force[a].data(), i, f[a]);
    for (int a = 0; a < 3; ++a) put(mom, 3 * size_t(i) + a, p[a]);
    held_[i] = held;
    for (int a = 0; a < 3; ++a) prev_[3 * size_t(i) + a] = x[a];
  }
}

// terrain_after_update, every box listed (as in contacts: the engine's boxes near the paths
// are a superset of those a path can be stopped by).
void TerrainReplica::after_update(const Model& m, State& s, Workspace& w, uint64_t* events) {
  double* mom = s.lin_mom.front().data();
  double* pos = s.pos.front().data();
  for (int i = 0; i < m.n; ++i) {
    if (m.fixed[i]) continue;
    s.static_friction[i] = held_[i];
    if (all_boxes_.empty()) continue;
    Adj x1[3], p[3];
    for (int a = 0; a < 3; ++a) x1[a] = pos_of(s, i, a), p[a] = load(mom, 3 * i + a, Adj{});
    if (!voxel_box_stops(m, all_boxes_, 0.5 * load(s.size.data(), i, Adj{}), &prev_[3 * size_t(i)],
                         x1, p, [events](uint64_t v) { note(events, v); }))
      continue;
    for (int a = 0; a < 3; ++a)
      put(pos, 3 * size_t(i) + a, x1[a]), put(mom, 3 * size_t(i) + a, p[a]);
  }
  if (!w.floor_normal.empty())
    for (int i = 0; i < m.n; ++i) put(w.floor_normal.data(), i, normal_[i]);
}

}  // namespace plastivox::grad
