// The batched development kernel: the per-voxel rule of develop.cpp (METHOD.md section 5)
// over arrays of voxels, lane-generic like the voxel kernels (develop_lanes_body.hpp).
#pragma once

#include "plastivox/physics_def.hpp"

namespace plastivox {

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

struct DevelopConstants {
  Treatment stimulus;  // which stimulus (never kNone here)
  bool split;  // pressure from bond stresses (each voxel's share of the strain); else E_i x strain
  bool integral;  // E = E0 + alpha * integral; else the rate model
  bool first;     // the first developing step: the rate model's reference is taken now
  double pressure_denominator;  // 3 (1 - 2 nu)
  double gate;                  // development only while E > gate
  double dt, max_change, e_min, e_max;
  double inv_mass, inv_inertia, inv_volume;  // kinetic: 1/m, 1/I, 1/L^3
};

}  // namespace plastivox
