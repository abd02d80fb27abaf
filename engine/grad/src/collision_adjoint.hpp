// Self-collision on the recording type (docs/gradients.md): contacts.cpp's
// apply_self_collisions, the pairs of surface voxels not near in the bond graph that touch, in
// the engine's order of summation, so that the replica computes the engine's bits and the tape
// records their derivatives. A free object's contacts with the robot (and with each other) are
// among these pairs (object_contact_adj, terrain_adjoint.hpp).
#pragma once

#include <cstdint>
#include <vector>

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

 private:
  void refresh_near_pairs(const Model& m, const State& s, double half_d);

  // The surface pairs self-collision tests (built on the first step), and those that may touch.
  std::vector<int> pair_a_, pair_b_, near_;
  bool paired_ = false;
  std::vector<double> anchor_;  // refresh_near_pairs'
  double size_top_ = 0;
};

}  // namespace plastivox::grad
