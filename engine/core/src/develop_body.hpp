// The development kernel (KernelSet::develop, kernels.hpp) for any lane type (lanes.hpp).
// develop.cpp says what the rule is and why.
#pragma once

#include "kernels.hpp"
#include "lanes.hpp"

namespace plastivox {
namespace {

// std::clamp(v, lo, hi), lane by lane.
template <class T>
inline T clamp_lanes(T v, double lo, double hi) {
  return pick(v < lo, splat(lo, T{}), pick(hi < v, splat(hi, T{}), v));
}

// Voxels [i, i + width): the stimulus `which` names (never kNone), from this step's bonds
// (and, for contact and kinetic, the floor force and momenta io points at). Also the sensors'
// strain, stress and pressure (control.cpp).
template <class T>
inline T stimulus_lanes(const DevelopIo& io, int i, const ModelConstants& k, Treatment which) {
  const T zero = splat(0.0, T{});
  T stim;
  if (which == Treatment::kStress) {
    // Largest tensile axial stress among the voxel's bonds (compression counts as 0).
    stim = zero;
    for (int slot = 0; slot < 6; ++slot) {
      const T sigma = load_indexed(io.bond_stress, io.slot_bond[slot], i, T{});
      stim = pick(stim < sigma, sigma, stim);
    }
  } else if (which == Treatment::kStrain) {
    // Largest absolute axial strain among the voxel's bonds (a slot without one reads 0).
    stim = zero;
    for (int slot = 0; slot < 6; ++slot) {
      const T eps = load_indexed(io.bond_strain, io.slot_bond[slot], i, T{});
      const T magnitude = pick(eps < 0.0, -eps, eps);
      stim = pick(stim < magnitude, magnitude, stim);
    }
  } else if (which == Treatment::kStrainEnergy) {
    // Axial elastic energy per unit volume of the voxel's half of each of its bonds.
    // (The bond stage stores each bond's stress x strain for it: one gather per slot, not two.)
    T sum = zero;
    for (int slot = 0; slot < 6; ++slot)
      sum = sum + load_indexed(io.bond_energy, io.slot_bond[slot], i, T{});
    stim = 0.25 * sum;
  } else if (which == Treatment::kContact) {
    // Floor normal force over the voxel's (actuated) face area; 0 off the floor.
    const T side = load(io.size, i, T{});
    stim = load(io.floor_normal, i, T{}) / (side * side);
  } else if (which == Treatment::kKinetic) {
    T p[3], h[3];
    load3(io.lin_mom, i, p);
    load3(io.ang_mom, i, h);
    const T p2 = p[0] * p[0] + p[1] * p[1] + p[2] * p[2];
    const T h2 = h[0] * h[0] + h[1] * h[1] + h[2] * h[2];
    stim = (0.5 * k.inv_mass * p2 + 0.5 * k.inv_inertia * h2) * k.inv_volume;
  } else {
    // Per axis, the mean over the voxel's two bonds, or the one bond (the other reads 0).
    // Pressure from bond stresses (each voxel's share of the strain), or E_i x strain.
    const bool split = k.def.axial_modulus == AxialModulus::kHarmonicMean;
    const double* per_bond = split ? io.bond_stress : io.bond_strain;
    T sum = zero;
    for (int axis = 0; axis < 3; ++axis) {
      const int* neg = io.slot_bond[2 * axis];
      const int* pos = io.slot_bond[2 * axis + 1];
      const T a = load_indexed(per_bond, neg, i, T{}), b = load_indexed(per_bond, pos, i, T{});
      const auto both =
          index_mask_ne(neg, i, io.no_bond, T{}) & index_mask_ne(pos, i, io.no_bond, T{});
      sum = sum + pick(both, 0.5 * (a + b), a + b);
    }
    const T stress_sum = split ? sum : load(io.stiffness, i, T{}) * sum;
    stim = -stress_sum / k.pressure_denominator;
  }
  return stim;
}

// Voxels [i, i + width), a step of dt; first: the first developing step (the rate model's
// reference is taken now).
// S: the type of dt, double here (engine/grad runs the same body with its recording type).
template <class T, class S = double>
inline void develop_lanes(const DevelopIo& io, int i, const ModelConstants& k, S dt, bool first) {
  const T stim = stimulus_lanes<T>(io, i, k, k.def.treatment);
  store(io.stimulus, i, stim);
  if (first) store(io.stim_ref, i, stim);

  const T e = load(io.stiffness, i, T{});
  const T alpha = load(io.alpha, i, T{});
  // Soft voxels never develop; a voxel softened to the gate stops for good.
  const auto active = and_not(e > k.gate, alpha == 0.0);
  T target;
  if (k.def.growth == GrowthModel::kIntegral) {  // E = E0 + alpha * integral; else the rate
    const T old = load(io.stim_integral, i, T{});
    const T integral = old + stim * dt;
    store(io.stim_integral, i, pick(active, integral, old));
    target = load(io.e0, i, T{}) + alpha * integral;
  } else {
    target = load(io.e0, i, T{}) + alpha * (stim - load(io.stim_ref, i, T{}));
  }
  const double most = k.def.max_change_per_step;
  const T change = clamp_lanes(target - e, -most, most);
  const T next = clamp_lanes(e + change, k.def.e_min, k.def.e_max);
  store(io.stiffness, i, pick(active, next, e));
}

template <class T>
inline void run_develop(const DevelopIo& io, int n, const ModelConstants& k, double dt,
                        bool first) {
  over_lanes<T>(n, [&](auto lane, int i) { develop_lanes<decltype(lane)>(io, i, k, dt, first); });
}

}  // namespace
}  // namespace plastivox
