// Self-collision on the recording type (docs/gradients.md): contacts.cpp's
// apply_self_collisions with the engine's own pieces, its candidate pairs
// (self_collision_candidates, on the replica's own Workspace from the same centres: the same
// pairs) and each pair's contact (collision_body.hpp's pair_contact on Adj), in the engine's
// order of summation, so that the replica computes the engine's bits and the tape records their
// derivatives. A free object's contacts with the robot (and with each other) are among these
// pairs.
#pragma once

#include <cstdint>

#include "adj.hpp"
#include "plastivox/model.hpp"
#include "plastivox/state.hpp"
#include "workspace.hpp"

namespace plastivox::grad {

class CollisionReplica {
 public:
  // One step's self-collision and object contacts, their forces added to the Workspace's. dt is
  // this step's. `events`, when given, receives each touching pair and an object pair's
  // friction regime: where they change the gradient has a kink.
  void apply(const Model& m, const State& s, Workspace& w, Adj dt, uint64_t* events);
};

}  // namespace plastivox::grad
