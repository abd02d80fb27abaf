// Contact with an environment on the recording type (docs/gradients.md, "Environments and free
// objects"): terrain.cpp's terrain_contacts and terrain_after_update (the ground, the boxes and
// each contact by the engine's own templates, terrain_body.hpp), in the engine's order of
// operations on Adj, so that the replica computes the engine's bits and the tape records their
// derivatives (the ground's height and normal under each voxel, the boxes' faces, the contact
// forces, friction and the stops). The stages are scalar in the engine too; the tape is their
// adjoint. Free objects' contacts are collision_adjoint.hpp's.
#pragma once

#include <cstdint>
#include <vector>

#include "adj.hpp"
#include "plastivox/model.hpp"
#include "plastivox/state.hpp"
#include "workspace.hpp"

namespace plastivox::grad {

// One step's contact with the ground and the boxes (Model::terrain). `events`, when given,
// receives the branches taken (which surface, which cell of the ground, which face of a box,
// the friction regime, a stopped crossing): where they change the gradient has a kink.
class TerrainReplica {
 public:
  // terrain_contacts: before the voxel update, the contact forces into the Workspace's forces
  // and the stops into the State's momenta. dt is this step's.
  void contacts(const Model& m, State& s, Workspace& w, Adj dt, uint64_t* events);
  // terrain_after_update: the static friction flags, the stopped crossings of thin boxes and
  // the normal forces (Workspace::floor_normal, where kept).
  void after_update(const Model& m, State& s, Workspace& w, uint64_t* events);

 private:
  std::vector<Adj> prev_;    // 3 per voxel: each centre before the update
  std::vector<Adj> normal_;  // each voxel's summed normal force
  std::vector<uint8_t> held_;
  std::vector<int> all_boxes_;  // every box's index
};

}  // namespace plastivox::grad
