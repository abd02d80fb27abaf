// The batched bond kernel: the exact bond model over arrays of bonds, written as one
// branch-free loop over structure-of-arrays inputs so the compiler vectorises it (AVX2
// where the build enables it). Element-wise IEEE arithmetic in the same order as the
// scalar code, so vector and scalar builds give identical bits.
#pragma once

#include <vector>

namespace plastivox {

struct BondBatch {
  // Inputs, one entry per bond (gathered by compute_bond_forces).
  std::vector<double> rx, ry, rz;      // chord a->b in a's permuted body frame, m
  std::vector<double> qw, qx, qy, qz;  // rotation of b relative to a, permuted
  std::vector<double> rest;            // actuated rest length, m
  std::vector<double> ea, eb;          // current moduli of a and b, Pa
  std::vector<double> valid;           // 1 if the previous deformation is recorded
  std::vector<double> c[9];            // a's orientation with columns permuted (column-major)
  std::vector<double> redo;            // output, 1: outside the series' range, recompute in scalar
  // Where the kernel reads and writes bond state and results (State::bond_prev, in and out;
  // Workspace::bond_out, bond_strain, bond_stress): set before each call.
  double* prev[9] = {};
  double* out[9] = {};
  double* strain = nullptr;
  double* stress = nullptr;

  void resize(int n);
};

struct BondConstants {
  double L, area, inv_L;
  double ka2, kb1, kb2, kb3;          // beam constants per unit modulus
  double damp;                        // 2 sqrt(m) zeta / dt
  double dk_a1, dk_b2, dk_a2, dk_b3;  // damping coefficients per sqrt(E) (Workspace)
  bool axial_own;                     // axial stress from a's own modulus
};

void bond_kernel_exact(BondBatch& batch, int n, const BondConstants& k);

// atan(t)/t as a function of t^2: nine terms of the alternating series leave an error
// below 1e-19 for t^2 < 1e-2 (rotations under 11 degrees). Shared by the batched kernel
// and the scalar path so both evaluate the same expression.
template <class T>
inline T atan_series(T t2) {
  return 1.0 -
         t2 * (1.0 / 3 -
               t2 * (1.0 / 5 -
                     t2 * (1.0 / 7 -
                           t2 * (1.0 / 9 -
                                 t2 * (1.0 / 11 -
                                       t2 * (1.0 / 13 - t2 * (1.0 / 15 - t2 * (1.0 / 17))))))));
}

}  // namespace plastivox
