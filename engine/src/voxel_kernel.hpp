// The batched voxel kernels: the per-voxel stages of a step (gathering bond forces, and the
// floor contact, friction and Euler update) over arrays of voxels, written once as templates
// over the lane type (voxel_lanes_body.hpp) like the bond kernel: eight voxels at a time with
// AVX-512, four with AVX2, one otherwise, with identical bits on every level.
#pragma once

#include <cstdint>

namespace plastivox {

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

// Constants of the voxel stages, each kept as the factor the formulas multiply by (so every
// product is rounded as in the scalar expressions of integrate.cpp's history).
struct VoxelConstants {
  double weight[3];   // m g, N
  double slow_zeta;   // global (slow) damping ratio
  double c_lin_unit;  // 2 sqrt(m L): critical damping of a voxel's axial spring per sqrt(E)
  double c_rot_unit;  // 2 sqrt(I L^3): the same for rotation
  double c_col_unit;  // floor damping ratio times c_lin_unit
  double rot_damp;    // rotational slow damping: factor over the linear one times zeta
  double mass, inv_mass, inv_inertia, L, dt;
  double mu_static, mu_kinetic;
  bool floor;
  // bond_model voxelyze09: turn as Voxelyze 0.9 does (first-order quaternion step, and an
  // orientation within about 3e-8 rad of the lattice's reset to exactly none).
  bool voxelyze_turns;
};

// What the update stage reports for the stability check: the largest squared speed of a
// free voxel (m^2/s^2) and whether some free voxel's momenta are not finite.
struct VoxelUpdateSummary {
  double max_speed2 = 0;
  bool non_finite = false;
};

// Actuation: size[i] = L max(1 + A xi(E_i) sin(2 pi (f t + phase_i)), min_factor), with
// xi(E) = (e_max - E) / (e_max - e_min); `cycles` = f t.
struct ActuationConstants {
  double L, amplitude, min_factor, e_max, inv_range, cycles;
};

}  // namespace plastivox
