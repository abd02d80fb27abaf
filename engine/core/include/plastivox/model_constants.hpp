// The constants of a model's step: its physics, the voxel's size, mass and inertia, and the
// factors the formulas derive from them, each computed once by compile(). Model (model.hpp)
// is these plus its per-voxel and per-bond arrays, and the kernels (engine/core/src/kernels.hpp)
// read these directly, under these names. Plain numbers only (no Eigen type): the header is
// compiled into every instruction set's kernels.
#pragma once

#include "plastivox/physics_def.hpp"

namespace plastivox {

struct ModelConstants {
  PhysicsDef def;      // parameters, validated
  double size = 0;     // nominal voxel edge length L, m
  double mass = 0;     // per voxel, kg
  double inertia = 0;  // per voxel moment of inertia about any centre axis (m L^2 / 6), kg m^2

  // Derived (compile()), each as the factor the formulas multiply by.
  double inv_mass = 0;     // 1 / mass
  double inv_inertia = 0;  // 1 / inertia
  double inv_volume = 0;   // 1 / L^3
  // Beam stiffness per unit modulus (times E, Pa, gives the stiffness): axial area L^2 (m^2),
  // torsion L^3 / (12 (1 + nu)), shear L, shear-rotation coupling L^2 / 2, bending L^3 / 6.
  double area = 0, inv_L = 0, ka2 = 0, kb1 = 0, kb2 = 0, kb3 = 0;
  // Bond damping: 2 sqrt(m) zeta_bond, over dt per step; the coefficients are sqrt(E) times
  // that times these geometric constants: sqrt(k) per sqrt(E) for k = E L (axial, shear),
  // E L^3 / 4 (shear-rotation coupling), G J / L and 2 E I / L (torsion, bending).
  double bond_damp = 0;
  double damp_a1 = 0, damp_b2 = 0, damp_a2 = 0, damp_b3 = 0;
  bool axial_own = false;      // a bond's axial stress from voxel a's own modulus (kNegativeVoxel)
  double min_shear_chord = 0;  // floor of the chord in the exact model's shear coupling, m
  // Voxel damping per sqrt(E): 2 sqrt(m L) (linear), 2 sqrt(I L^3) (rotation), and the
  // floor's, collision_damping times the linear one.
  double c_lin_unit = 0, c_rot_unit = 0, c_col_unit = 0;
  // Rotational slow damping: its factor over the linear one times that one's ratio,
  // global_damping_rot_factor global_damping.
  double rot_damp = 0;
  double weight[3] = {0, 0, 0};  // m g, N, world axes
  // The floor z = 0 of the update kernel: def.floor without an environment's ground, which
  // the terrain contact handles instead (terrain.cpp).
  bool flat_floor = false;
  // Development: the pressure stimulus's denominator 3 (1 - 2 nu), and the gate
  // min_devo_factor e_min below which a voxel does not develop, Pa.
  double pressure_denominator = 0;
  double gate = 0;
  // Actuation (actuate.cpp): size = L max(1 + act_amplitude_xi xi(E) gain u,
  // def.act_min_factor) with xi(E) = (xi_e_max - E) xi_inv_range + xi_base: the paper's
  // stiffness factor (e_max - E) / (e_max - e_min) with act_amplitude_xi = def.act_amplitude
  // and the voxel's gain 1, or, with the robot's own amplitudes (Model::act_per_voxel), exactly
  // 1 (xi_e_max = xi_inv_range = 0, xi_base = 1) times the gain, its amplitude
  // (act_amplitude_xi = 1). The signal u is clipped to at most act_wave_max: +infinity, or 0
  // without def.act_expansion (contraction only).
  double act_amplitude_xi = 0, xi_e_max = 0, xi_inv_range = 0, xi_base = 0;
  double act_wave_max = 0;
};

}  // namespace plastivox
