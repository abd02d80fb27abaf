// Contact with an environment, recorded (terrain_adjoint.hpp). The ground's height and
// penetration, a box's nearest face and a contact's forces and friction are the engine's own
// templates (terrain_body.hpp) on Adj; the loops below are terrain.cpp's, operation for
// operation: a change there must be made here too (gradient() checks the replica against the
// engine's life at every snapshot, and throws where they part).
#include "terrain_adjoint.hpp"

#include "terrain_body.hpp"

namespace plastivox::grad {
namespace {

// A branch taken, folded into the event signature.
void note(uint64_t* events, uint64_t v) {
  if (events) *events = (*events ^ v) * 1099511628211ull;
}

Adj pos_of(const State& s, int i, int k) {
  return load(s.pos.front().data(), 3 * i + k, Adj{});
}

using Normal = ContactNormal<Adj>;

}  // namespace

// terrain_contacts. Every box is tested (the engine tests those boxes_near finds, a superset
// of those any centre lies in: the same contacts in the same order).
void TerrainReplica::contacts(const Model& m, State& s, Workspace& w, Adj dt, uint64_t* events) {
  const ModelConstants& k = m;
  const std::vector<ObstacleBox>& boxes = m.def.environment.obstacles;
  prev_.resize(3 * size_t(m.n));
  normal_.resize(size_t(m.n));
  held_.resize(size_t(m.n));
  double* mom = s.lin_mom.front().data();
  for (int i = 0; i < m.n; ++i) {
    Adj x[3] = {pos_of(s, i, 0), pos_of(s, i, 1), pos_of(s, i, 2)};
    const Adj r = 0.5 * load(s.size.data(), i, Adj{});
    const Adj E = load(s.stiffness.data(), i, Adj{}), se = load(w.sqrt_e.data(), i, Adj{});
    const bool was_held = s.static_friction[i];
    Adj f[3], p[3];
    for (int a = 0; a < 3; ++a) f[a] = load(w.force[a].data(), i, Adj{});
    for (int a = 0; a < 3; ++a) p[a] = load(mom, 3 * i + a, Adj{});
    bool held = false;
    Adj normal = 0.0;
    // One contact (the engine's apply_contact), its friction regime noted.
    const auto contact = [&](const Normal& c, Adj pen) {
      int regime = 0;
      const Adj n = apply_contact(c, pen, E, se, was_held, k, dt, f, p, held, &regime);
      note(events, 0xc0 + uint64_t(regime));
      return n;
    };
    if (m.def.floor) {
      // Recorded only in contact (the engine's own function decides, on the same values).
      if (m.ground.penetration(x[0].v, x[1].v, x[2].v, r.v) > 0) {
        Normal c;
        int cell[2];
        const Adj pen = ground_penetration(m.ground, x[0], x[1], x[2], r, c.n, cell);
        // touching, and the cell it touches in (a node between cells: a kink)
        note(events, 0x9000 + uint64_t(i));
        note(events, (uint64_t(uint32_t(cell[0])) << 32) + uint32_t(cell[1]));
        if (c.n[0].v == 0 && c.n[1].v == 0) c.axis = 2;
        normal = normal + contact(c, pen);
      }
    }
    for (size_t b = 0; b < boxes.size(); ++b) {
      // Recorded only inside (decided on the values, as the engine does).
      double lo[3], hi[3];
      const double centre[3] = {x[0].v, x[1].v, x[2].v};
      grown_box(boxes[b], r.v, lo, hi);
      if (!inside_box(lo, hi, centre)) continue;
      Adj glo[3], ghi[3], pen;
      grown_box(boxes[b], r, glo, ghi);
      const Normal c = nearest_face(glo, ghi, x, pen);
      note(events, 0xb0000 + 8 * b + 2 * size_t(c.axis) + (c.sign > 0 ? 1 : 0));
      normal = normal + contact(c, pen);
    }
    for (int a = 0; a < 3; ++a) put(w.force[a].data(), i, f[a]);
    for (int a = 0; a < 3; ++a) put(mom, 3 * size_t(i) + a, p[a]);
    held_[i] = held;
    normal_[i] = normal;
    for (int a = 0; a < 3; ++a) prev_[3 * size_t(i) + a] = x[a];
  }
}

// terrain_after_update, every box tested (as in contacts: the engine's boxes near the paths
// are a superset of those a path can be stopped by).
void TerrainReplica::after_update(const Model& m, State& s, Workspace& w, uint64_t* events) {
  const std::vector<ObstacleBox>& boxes = m.def.environment.obstacles;
  double* mom = s.lin_mom.front().data();
  double* pos = s.pos.front().data();
  for (int i = 0; i < m.n; ++i) {
    if (m.fixed[i]) continue;
    s.static_friction[i] = held_[i];
    const Adj r = 0.5 * load(s.size.data(), i, Adj{});
    for (size_t b = 0; b < boxes.size(); ++b) {
      double lo[3], hi[3], x0[3], x1[3];
      grown_box(boxes[b], r.v, lo, hi);
      for (int a = 0; a < 3; ++a)
        x0[a] = prev_[3 * size_t(i) + a].v, x1[a] = pos[3 * size_t(i) + a];
      int where = 0;
      const int a = crossing_stop(lo, hi, x0, x1, where);
      if (a < 0) continue;
      note(events, 0x5700 + 4 * size_t(a) + size_t(where) + (uint64_t(b) << 16));
      const Adj stop = where == 0   ? Adj(boxes[b].min[a]) - r
                       : where == 1 ? Adj(boxes[b].max[a]) + r
                                    : prev_[3 * size_t(i) + a];
      put(pos, 3 * size_t(i) + a, stop);
      put(mom, 3 * size_t(i) + a, Adj(0.0));
    }
  }
  if (!w.floor_normal.empty())
    for (int i = 0; i < m.n; ++i) put(w.floor_normal.data(), i, normal_[i]);
}

}  // namespace plastivox::grad
