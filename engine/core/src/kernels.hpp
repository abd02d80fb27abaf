// The batched kernels of a step: what each reads and writes, and one set of them per
// instruction set. Each kernel is written once, as a template over the lane type (lanes.hpp),
// in its own body (bond_body.hpp, voxel_body.hpp, develop_body.hpp, contact_body.hpp), and
// compiled three times: for `double` (kernels.cpp: the scalar set, and every set's tails),
// 4-wide AVX2 (kernels_avx2.cpp) and 8-wide AVX-512 (kernels_avx512.cpp). Element-wise IEEE
// arithmetic in the same order in every lane type, so every set gives the same bits;
// kernels() is the one place that chooses, by plastivox/simd.hpp's level.
#pragma once

#include <cstdint>

#include "plastivox/model_constants.hpp"

namespace plastivox {

// ---- Bonds: the exact bond model (bond_forces.cpp says what it is) ----

// Where the kernel reads and writes; raw views of Model, State and Workspace arrays.
struct BondKernelIo {
  // Per bond (model): voxel on the negative side, voxel on the positive side, and the lattice
  // axis as 64-bit integers (whole-vector loads).
  const int* bond_a = nullptr;
  const int* bond_b = nullptr;
  const int64_t* axis_wide = nullptr;
  // Per voxel: centre and actuated size as records of 4 doubles (x, y, z, size; m, world
  // frame; Workspace::centre_size), orientation (x, y, z, w: Eigen's storage order of a unit
  // quaternion, body to world), modulus (Pa).
  const double* centre_size = nullptr;
  const double* quat = nullptr;
  const double* stiff = nullptr;
  // Per bond: 1 once a previous deformation is recorded (read only; the caller sets it), and
  // whether every bond's is (after the first step, always), so lanes need not read it.
  const uint8_t* prev_valid = nullptr;
  bool all_valid = false;
  // Per bond, in: the previous deformation (State::bond_prev, read only); out: this step's
  // deformation, the next step's previous one (Workspace::bond_prev_next, which step2 commits
  // to the State), and the results (Workspace::bond_out: force on a, moment on a, moment on
  // b, each as records of (x, y, z, 0); bond_strain, bond_stress).
  const double* prev[9] = {};
  double* prev_next[9] = {};
  double* out[3] = {};
  double* strain = nullptr;
  double* stress = nullptr;
  // Out when not null: stress times strain (Workspace::bond_energy; the strain_energy stimulus).
  double* energy = nullptr;
  // Out: indices of the bonds the kernel could not compute (degenerate chord, relative
  // rotation near half a turn), in increasing order; room for one per bond. Their
  // prev_next is their previous deformation, and the scalar path must recompute them.
  int* redo = nullptr;
};

// ---- Voxels: gathering bond forces, floor contact, friction and the Euler update ----

// Where the kernels read and write: raw views of Model, State and Workspace arrays.
// "xyz" arrays hold 3 doubles per voxel back to back (Eigen vectors), "quat" 4 (x, y, z, w).
struct VoxelKernelIo {
  // Model, per voxel.
  const int* slot_bond[6] = {};    // bond in each slot (Model::voxel_bonds by slot); a slot
                                   // without one names the zero record of bond_out
  const uint8_t* fixed = nullptr;  // 1 if clamped
  const double* load = nullptr;    // xyz: constant external force, N
  // Workspace, per bond and one zero record (gather input): force on a, moment on a, moment
  // on b (bond_out: records of x, y, z, 0).
  const double* bond_out[3] = {};
  // State, per voxel (read; the update stage writes through VoxelStateOut).
  const double* pos = nullptr;      // xyz, m
  const double* quat = nullptr;     // quat
  const double* lin_mom = nullptr;  // xyz, kg m/s
  const double* ang_mom = nullptr;  // xyz, kg m^2/s
  const double* stiff = nullptr;    // E, Pa
  const uint8_t* static_friction = nullptr;
  const double* size = nullptr;  // actuated edge length, m
  // Workspace, per voxel: total force and moment (one array per component), sqrt of the
  // modulus.
  double* force[3] = {};
  double* moment[3] = {};
  double* sqrt_e = nullptr;
  // Workspace, per voxel, written by the update stage when not null: the floor's normal
  // force on the voxel, N (0 off the floor). Only the contact stimulus reads it.
  double* floor_normal = nullptr;
};

// What the update stage writes: the same State arrays as VoxelKernelIo's, writable.
struct VoxelStateOut {
  double* pos = nullptr;
  double* quat = nullptr;
  double* lin_mom = nullptr;
  double* ang_mom = nullptr;
  uint8_t* static_friction = nullptr;
};

// What the update stage reports for the stability check: the largest squared speed of a
// free voxel (m^2/s^2) and whether some free voxel's momenta are not finite.
struct VoxelUpdateSummary {
  double max_speed2 = 0;
  bool non_finite = false;
};

// Actuation: size[i] = L max(1 + A xi(E_i) u_i, min_factor) from each voxel's signal u_i in
// [-1, 1] (the sine controller's is sin(2 pi (f t + phase_i))), with
// xi(E) = (e_max - E) / (e_max - e_min).
// (ModelConstants: act_amplitude_xi, xi_e_max, xi_inv_range, xi_base, act_wave_max.)

// ---- Development: the per-voxel rule of develop.cpp (docs/method.md §5) ----

struct DevelopIo {
  // Workspace: the bond in each slot of every voxel (a slot without one names the zero entry
  // past the last bond) and this step's bond stresses and strains (with that zero entry).
  const int* slot_bond[6] = {};
  int no_bond = 0;  // the index of that zero entry (the number of bonds)
  const double* bond_stress = nullptr;
  const double* bond_strain = nullptr;
  const double* bond_energy = nullptr;  // stress x strain (strain_energy only)
  // Read by the contact stimulus: the floor's normal force on each voxel this step, N
  // (Workspace::floor_normal), and the actuated sizes, m.
  const double* floor_normal = nullptr;
  const double* size = nullptr;
  // Read by the kinetic stimulus: momenta after this step's update, xyz per voxel.
  const double* lin_mom = nullptr;
  const double* ang_mom = nullptr;
  // Model.
  const double* e0 = nullptr;
  const double* alpha = nullptr;
  // State, in and out.
  double* stiffness = nullptr;
  double* stimulus = nullptr;
  double* stim_integral = nullptr;
  double* stim_ref = nullptr;
};

// ---- The set ----

// Every kernel reads the model's constants as compile() made them (ModelConstants, which a
// Model is), and is handed only what follows the step: dt, or the bonds' damping factor
// bond_damp / dt.
struct KernelSet {
  // Bonds [0, n); returns how many bond indices it wrote to io.redo.
  int (*bond)(const BondKernelIo& io, int n, const ModelConstants& k, double damp);
  // Voxels [0, n): force[i] = the sum of its bonds' forces in slot order - slow damping +
  // weight + load; moment[i] = the sum of its bonds' moments; sqrt_e[i] = sqrt(E_i).
  void (*gather)(const VoxelKernelIo& io, int n, const ModelConstants& k);
  // Voxels [0, n): floor contact and friction on force[i], then momenta, position and
  // orientation, over a step of dt (bond_model voxelyze09 turns as Voxelyze 0.9 does: a
  // first-order quaternion step, and an orientation within about 3e-8 rad of the lattice's
  // reset to exactly none).
  VoxelUpdateSummary (*update)(const VoxelKernelIo& io, const VoxelStateOut& st, int n,
                               const ModelConstants& k, double dt);
  // Voxels [0, n): signal[i] = sin(2 pi (cycles + phase[i])), the sine controller's.
  void (*sine)(const double* phase, double* signal, int n, double cycles);
  // Voxels [0, n): the actuated sizes from the signals.
  void (*actuate)(const double* stiff, const double* signal, const double* gain, double* size,
                  int n, const ModelConstants& k);
  // Voxels [0, n): stimulus and stiffness update over a step of dt; first: the first
  // developing step (the rate model's reference is taken now).
  void (*develop)(const DevelopIo& io, int n, const ModelConstants& k, double dt, bool first);
  // Writes to out, increasing, every e in [begin, end) with
  // (px[e] - x)^2 + (py[e] - y)^2 + (pz[e] - z)^2 < r2 (a plain comparison of those rounded
  // sums); returns how many. out has room for end - begin entries. (Self-collision refresh.)
  int (*scan_within)(const double* px, const double* py, const double* pz, int begin, int end,
                     double x, double y, double z, double r2, int* out);
  // Writes to out, increasing, every p in [0, n) whose voxels pair_a[p], pair_b[p] (records of
  // centre and size, Workspace::centre_size) may touch: centre distance squared below
  // (half_d (size_a + size_b))^2 (1 + 1e-9); returns how many. (Self-collision, each step.)
  int (*touch_candidates)(const double* records, const int* pair_a, const int* pair_b, int n,
                          double half_d, int* out);
};

// The set for the level in use.
const KernelSet& kernels();

// The set of one instruction set, compiled for it: use only when the CPU has it.
KernelSet kernels_avx2();
KernelSet kernels_avx512();

}  // namespace plastivox
