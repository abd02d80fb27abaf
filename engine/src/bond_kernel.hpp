// The batched bond kernel: the exact bond model over arrays of bonds, written once as a
// template over the lane type (bond_lanes.hpp): four bonds at a time with AVX2, eight with
// AVX-512, chosen at run time from what the CPU has (plastivox/simd.hpp). It reads the voxels'
// centres, orientations, sizes and moduli directly (no intermediate per-bond copy) and writes each
// bond's forces, strain, stress and deformation in place. Element-wise IEEE arithmetic in the same
// order in every lane type, so vector and scalar builds give identical bits.
#pragma once

#include <cstdint>

namespace plastivox {

// Where the kernel reads and writes; raw views of Model, State and Workspace arrays.
struct BondKernelIo {
  // Per bond (model): voxel on the negative side, voxel on the positive side, lattice axis.
  const int* bond_a = nullptr;
  const int* bond_b = nullptr;
  const uint8_t* axis = nullptr;
  // Per voxel (state): centre (x, y, z; m, world frame), orientation (x, y, z, w: Eigen's
  // storage order of a unit quaternion, body to world), actuated size (m), modulus (Pa).
  const double* pos = nullptr;
  const double* quat = nullptr;
  const double* size = nullptr;
  const double* stiff = nullptr;
  // The same centres and sizes as records of 4 doubles per voxel (x, y, z, size), for the
  // vector lanes' whole-record loads.
  const double* centre_size = nullptr;
  // The lattice axes again, as 64-bit integers for the vector lanes' whole-vector loads.
  const int64_t* axis_wide = nullptr;
  // Per bond: 1 once a previous deformation is recorded (read only; the caller sets it), and
  // whether every bond's is (after the first step, always), so lanes need not read it.
  const uint8_t* prev_valid = nullptr;
  bool all_valid = false;
  // Per bond, in and out: the previous deformation (State::bond_prev); out: the results
  // (Workspace::bond_out: force on a, moment on a, moment on b, each as records of
  // (x, y, z, 0); bond_strain, bond_stress).
  double* prev[9] = {};
  double* out[3] = {};
  double* strain = nullptr;
  double* stress = nullptr;
  // Out when not null: stress times strain (Workspace::bond_energy; the strain_energy stimulus).
  double* energy = nullptr;
  // Out: indices of the bonds the kernel could not compute (degenerate chord, relative
  // rotation near half a turn), in increasing order; room for one per bond. They keep
  // their previous deformation and must be recomputed by the scalar path.
  int* redo = nullptr;
};

struct BondConstants {
  double L, area, inv_L;
  double ka2, kb1, kb2, kb3;          // beam constants per unit modulus
  double damp;                        // 2 sqrt(m) zeta / dt
  double dk_a1, dk_b2, dk_a2, dk_b3;  // damping coefficients per sqrt(E) (Workspace)
  bool axial_own;                     // axial stress from a's own modulus
  double min_shear_chord;             // floor of the chord in the shear coupling, m
};

}  // namespace plastivox
