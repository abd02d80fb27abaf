// Self-collision, recorded (collision_adjoint.hpp).
#include "collision_adjoint.hpp"

#include "collision_body.hpp"

namespace plastivox::grad {

void CollisionReplica::apply(const Model& m, const State& s, Workspace& w, Adj dt,
                             uint64_t* events) {
  // The candidate lists are kept from segment to segment, though a restored snapshot moves the
  // centres back (Simulator::restore_state starts them afresh instead): whatever came before,
  // every voxel that moved too far from where its list was made is refreshed first, so every
  // pair that can touch is listed (contacts.cpp), and the candidates are then exactly the pairs
  // within a hair of their contact distance, in (i, j) order: the engine's, on 1 or 2 threads.
  const int n = self_collision_candidates(m, s, w);
  const ContactGrid& g = w.contact_grid;
  for (int c = 0; c < n; ++c) {
    const int p = g.touching[c];
    const int i = g.pair_a[p], j = g.pair_b[p];
    const PairContact what = pair_contact(m, s, w, i, j, dt);
    if (what == PairContact::kApart) continue;
    note(events, (uint64_t(i) << 32) + uint64_t(j));
    if (what == PairContact::kObjectSliding || what == PairContact::kObjectStopped)
      note(events, what == PairContact::kObjectStopped ? 0x0b1 : 0x0b0);
  }
}

}  // namespace plastivox::grad
