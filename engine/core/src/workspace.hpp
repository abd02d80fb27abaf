// Scratch arrays one step fills and consumes. Not part of State: nothing here carries
// information from one step to the next. step1 reads the State and writes only here,
// including what it computes for the next state (the *_next fields), which step2 commits to
// the State. The self-collision candidates persist as a cache (rebuilt from positions when
// stale; a fresh workspace finds the same contacts), and the model's index tables in the
// layout the kernels read are built once here.
#pragma once

#include <array>
#include <cmath>
#include <vector>

#include "kernels.hpp"
#include "plastivox/model.hpp"
#include "plastivox/state.hpp"

namespace plastivox {

// Self-collision candidates (contacts.cpp): per surface voxel its partner list and where it
// was at its last refresh, and the scratch of a refresh, kept to reuse its memory.
struct ContactGrid {
  std::vector<int> voxels;                    // surface voxels, increasing
  std::vector<Vec3> ref_rel;                  // voxels[k]'s centre minus the surface mean at its
                                              // last refresh, m
  std::vector<std::vector<int>> partners;     // per voxel: candidate partners, increasing
  std::vector<int> stale;                     // surface voxels (indices k) to refresh this step
  std::array<std::vector<double>, 3> centre;  // voxels[k]'s centre this step (x, y, z), m
  std::vector<int> within;                    // scratch: indices k found by a scan
  // The grid of a refresh.
  std::vector<int> cell_of;  // cell of voxels[k]
  std::vector<int> start;    // members of cell c: members[start[c] .. start[c + 1])
  std::vector<int> fill;
  std::vector<int> members;  // surface voxels by cell, increasing within a cell
  std::array<std::vector<double>, 3> member_pos;  // their centres (x, y, z), m
  std::vector<int> near_mark;                     // per voxel: last voxel it was near
  std::vector<int> found;                         // partners of one voxel
  // Every candidate pair (i, j), i < j, in increasing order, rebuilt after a refresh that
  // changed some partners, and scratch for the pairs that may touch this step.
  std::vector<int> pair_a, pair_b, touching;
  bool pairs_stale = true;
  int dim[3] = {0, 0, 0};  // cells per axis
};

// What the stages hand the kernels (kernels.hpp), built once by bind_views.
struct KernelViews {
  BondKernelIo bond;  // prev_next: where this step1 writes (compute_bond_forces)
  // The State's own arrays of each bond's previous deformation and frame (the frame's only
  // under the Voxelyze 0.9 model), where step() has the bond stage write the next values,
  // and where the scalar path writes the frame this step (one or the other's).
  double* prev_in_state[9] = {};
  uint8_t* small_angle_in_state = nullptr;
  uint8_t* small_angle_next = nullptr;
  VoxelKernelIo voxel;
  VoxelStateOut voxel_out;
  DevelopIo develop;
};

struct Workspace {
  // Per voxel.
  // Total force (N) and moment (N m), world axes, one array per component.
  std::array<std::vector<double>, 3> force, moment;
  std::vector<double> sqrt_e;  // sqrt of the current stiffness, sqrt(Pa)
  // Per voxel, 4 doubles: centre (m) and actuated size (m), copied from the state at the
  // start of the bond stage. Not a second layout kept for its own sake: the bond kernel and
  // the contact test gather two voxels per bond (pair) by index, and a 4-double record is one
  // aligned 256-bit load per voxel and lane (lanes.hpp, load_records); State::pos has 3
  // doubles per voxel and the size is a separate array, which would take two loads each
  // (and a 4-wide load of a 3-double record reads past the last voxel).
  std::vector<double> centre_size;
  // Model::voxel_bonds by slot (one array per slot), for the gather; a slot without a bond
  // names the extra zero entry of bond_out (index bond_count()).
  std::array<std::vector<int>, 6> slot_bond;
  // Per bond (plus one zero record), filled by the bond stage, gathered per voxel in a fixed
  // order; world axes, records of 4 doubles (x, y, z, 0) so a voxel reads a bond's vector in
  // one load: [0] force on voxel a (N; the force on b is its negative), [1] moment on a,
  // [2] moment on b (N m).
  std::array<std::vector<double>, 3> bond_out;
  // Per bond, plus the zero entry past the last one (for slots without a bond).
  std::vector<double> bond_strain;  // axial engineering strain vs. actuated rest length
  std::vector<double> bond_stress;  // axial stress, Pa (tension > 0)
  // Per bond (and the zero entry), stress times strain, Pa; filled only for the strain_energy
  // stimulus, which would otherwise gather both arrays.
  std::vector<double> bond_energy;
  // Per voxel: the floor's normal force this step, N; filled only for the contact stimulus.
  std::vector<double> floor_normal;
  // Per voxel, only with an environment (Model::terrain; terrain.cpp): whether a contact
  // held the voxel this step, the normal force of its contacts (N), and its centre before
  // the update (m, world axes).
  std::vector<uint8_t> terrain_held;
  std::vector<double> terrain_normal;
  std::vector<Vec3> terrain_prev;
  std::vector<int> terrain_boxes;  // the boxes near the body this step (indices)
  // Self-collision candidates: unbonded voxel pairs near enough to touch soon.
  ContactGrid contact_grid;
  bool contacts_valid = false;
  // What step1 computes for the next state and step2 commits to it (so between them the
  // State is still the state before the step): the time step (s, follow_stiffness), each
  // bond's deformation this step, which the next step damps against (State::bond_prev's next
  // value; every bond then has one, bond_prev_valid), and under the Voxelyze 0.9 model each
  // bond's frame (State::bond_small_angle's; empty otherwise).
  // step() runs both halves with nothing between them, so there the bond stage writes the
  // deformations and frames into the State itself (bonds_next_in_state) and the commit has
  // nothing to copy: copying 9 doubles per bond each step made whole lives 5-9 % slower.
  double dt_next = 0;
  std::array<std::vector<double>, 9> bond_prev_next;
  std::vector<uint8_t> bond_small_angle_next;
  bool bonds_next_in_state = false;
  std::vector<int> redo;                // bonds the batched kernel left to the scalar path
  std::vector<int64_t> bond_axis_wide;  // Model::bond_axis as 64-bit integers (bond kernel)
  // The kernels' views of the Model's, State's and this Workspace's arrays (bind_views); the
  // stages set only what changes with each step (whether every bond has a previous
  // deformation, where the next ones go). The kernels read the Model's constants directly.
  KernelViews views;

  explicit Workspace(const Model& m)
      : sqrt_e(m.n),
        centre_size(4 * static_cast<size_t>(m.n), 0.0),
        bond_strain(m.bond_count() + 1, 0.0),
        bond_stress(m.bond_count() + 1, 0.0),
        bond_energy(m.def.treatment == Treatment::kStrainEnergy ? m.bond_count() + 1 : 0, 0.0),
        floor_normal(m.def.treatment == Treatment::kContact ? m.n : 0, 0.0),
        terrain_held(m.terrain ? m.n : 0, 0),
        terrain_normal(m.terrain ? m.n : 0, 0.0),
        terrain_prev(m.terrain ? m.n : 0, Vec3::Zero()),
        bond_small_angle_next(m.def.bond_model == BondModel::kVoxelyze09 ? m.bond_count() : 0),
        redo(m.bond_count()),
        bond_axis_wide(m.bond_axis.begin(), m.bond_axis.end()) {
    // One more entry than there are bonds, always 0: where a voxel slot has no bond.
    for (auto& vectors : bond_out)
      vectors.assign(4 * (static_cast<size_t>(m.bond_count()) + 1), 0.0);
    for (int c = 0; c < 3; ++c) force[c].assign(m.n, 0.0), moment[c].assign(m.n, 0.0);
    for (auto& component : bond_prev_next) component.assign(m.bond_count(), 0.0);
    if (m.terrain) terrain_boxes.reserve(m.def.environment.obstacles.size());
    for (int k = 0; k < 6; ++k) {
      slot_bond[k].resize(m.n);
      for (int i = 0; i < m.n; ++i) {
        const int b = m.voxel_bonds[i][k];
        slot_bond[k][i] = b >= 0 ? b : m.bond_count();
      }
    }
  }
  // views points into this object's own arrays.
  Workspace(const Workspace&) = delete;
  Workspace& operator=(const Workspace&) = delete;
};

// Points w.views at the arrays of m, s and w (s's as PLASTIVOX_STATE_FIELDS names them). Called
// once when a Simulator is made and again when its State is replaced (restore_state,
// mutable_state): the views stay valid as long as no array is reallocated, and none is
// during a life (every array has its final size from the start; restore copies into them).
void bind_views(const Model& m, State& s, Workspace& w);
// Each stage's part of it for the Model's and the Workspace's arrays (in the stage's file).
void bind_bond_views(const Model& m, Workspace& w);
void bind_voxel_views(const Model& m, Workspace& w);
void bind_develop_views(const Model& m, Workspace& w);
// Whether w.views still point at s's arrays (for assertions).
bool views_bound_to(const State& s, const Workspace& w);

// The stages of one step, in the order Simulator::step() calls them (one file each:
// bond_forces.cpp, simulator.cpp, integrate.cpp, contacts.cpp, actuate.cpp, develop.cpp).
// step1's read the State and write the Workspace only, but for one case: with
// next_into_state (step(), nothing between the halves) the bond stage writes each bond's next
// deformation and frame straight into the State's arrays, as the commit would.
void compute_bond_forces(const Model& m, const State& s, Workspace& w, bool next_into_state);
// Its work on the views as bound (io.all_valid set, damp = bond_damp / dt): Voxelyze 0.9's
// scalar path for every bond, else the batched kernel set and the scalar path for the bonds it
// hands back (listed in io.redo); returns how many it handed back. Also the gradient's replica's
// bond stage.
int run_bond_stage(const Model& m, KernelViews& v, double damp);
// The time step from the stiffness development left, into w.dt_next.
void follow_stiffness(const Model& m, const State& s, Workspace& w);
void gather_voxel_forces(const Model& m, const State& s, Workspace& w);
void apply_self_collisions(const Model& m, const State& s, Workspace& w);
// step2's first: what step1 computed for the next state (each bond's deformation and frame,
// unless already there, and that every bond has one) into the State; Simulator::step2 sets dt
// beside it.
void commit_bond_deformation(const Model& m, State& s, const Workspace& w);
void integrate(const Model& m, State& s, Workspace& w);  // floor, friction, Euler update
// Within integrate, with an environment (terrain.cpp): contact with the ground and boxes
// before the update kernel, and after it the static-friction flags, the contact stimulus's
// normal forces and the stop of paths that would cross a box.
void terrain_contacts(const Model& m, State& s, Workspace& w);
void terrain_after_update(const Model& m, State& s, Workspace& w);
// How far a voxel of half size r centred at x presses into the ground and the boxes, m, summed
// over its contacts as terrain_contacts measures them (for the touch and contact-force sensors).
double terrain_penetration(const Model& m, const Vec3& x, double r);
// Sizes for the next step from each voxel's signal (n values in [-1, 1]).
void actuate(const Model& m, State& s, const double* signal);
void develop(const Model& m, State& s, Workspace& w);

}  // namespace plastivox
