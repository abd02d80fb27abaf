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

// Voxels [i, i + width): the stimulus k.stimulus names, from this step's bonds (and, for
// contact and kinetic, the floor force and momenta io points at). Also the sensors' strain,
// stress and pressure (sensors.cpp).
template <class T>
inline T stimulus_lanes(const DevelopIo& io, int i, const DevelopConstants& k) {
  const T zero = splat(0.0, T{});
  T stim;
  if (k.stimulus == Treatment::kStress) {
    // Largest tensile axial stress among the voxel's bonds (compression counts as 0).
    stim = zero;
    for (int slot = 0; slot < 6; ++slot) {
      const T sigma = load_indexed(io.bond_stress, io.slot_bond[slot], i, T{});
      stim = pick(stim < sigma, sigma, stim);
    }
  } else if (k.stimulus == Treatment::kStrain) {
    // Largest absolute axial strain among the voxel's bonds (a slot without one reads 0).
    stim = zero;
    for (int slot = 0; slot < 6; ++slot) {
      const T eps = load_indexed(io.bond_strain, io.slot_bond[slot], i, T{});
      const T magnitude = pick(eps < 0.0, -eps, eps);
      stim = pick(stim < magnitude, magnitude, stim);
    }
  } else if (k.stimulus == Treatment::kStrainEnergy) {
    // Axial elastic energy per unit volume of the voxel's half of each of its bonds.
    // (The bond stage stores each bond's stress x strain for it: one gather per slot, not two.)
    T sum = zero;
    for (int slot = 0; slot < 6; ++slot)
      sum = sum + load_indexed(io.bond_energy, io.slot_bond[slot], i, T{});
    stim = 0.25 * sum;
  } else if (k.stimulus == Treatment::kContact) {
    // Floor normal force over the voxel's (actuated) face area; 0 off the floor.
    const T side = load(io.size, i, T{});
    stim = load(io.floor_normal, i, T{}) / (side * side);
  } else if (k.stimulus == Treatment::kKinetic) {
    T p[3], h[3];
    load3(io.lin_mom, i, p);
    load3(io.ang_mom, i, h);
    const T p2 = p[0] * p[0] + p[1] * p[1] + p[2] * p[2];
    const T h2 = h[0] * h[0] + h[1] * h[1] + h[2] * h[2];
    stim = (0.5 * k.inv_mass * p2 + 0.5 * k.inv_inertia * h2) * k.inv_volume;
  } else {
    // Per axis, the mean over the voxel's two bonds, or the one bond (the other reads 0).
    const double* per_bond = k.split ? io.bond_stress : io.bond_strain;
    T sum = zero;
    for (int axis = 0; axis < 3; ++axis) {
      const int* neg = io.slot_bond[2 * axis];
      const int* pos = io.slot_bond[2 * axis + 1];
      const T a = load_indexed(per_bond, neg, i, T{}), b = load_indexed(per_bond, pos, i, T{});
      const auto both =
          index_mask_ne(neg, i, io.no_bond, T{}) & index_mask_ne(pos, i, io.no_bond, T{});
      sum = sum + pick(both, 0.5 * (a + b), a + b);
    }
    const T stress_sum = k.split ? sum : load(io.stiffness, i, T{}) * sum;
    stim = -stress_sum / k.pressure_denominator;
  }
  return stim;
}

// Voxels [i, i + width).
template <class T>
inline void develop_lanes(const DevelopIo& io, int i, const DevelopConstants& k) {
  const T stim = stimulus_lanes<T>(io, i, k);
  store(io.stimulus, i, stim);
  if (k.first) store(io.stim_ref, i, stim);

  const T e = load(io.stiffness, i, T{});
  const T alpha = load(io.alpha, i, T{});
  // Soft voxels never develop; a voxel softened to the gate stops for good.
  const auto active = and_not(e > k.gate, alpha == 0.0);
  T target;
  if (k.integral) {
    const T old = load(io.stim_integral, i, T{});
    const T integral = old + stim * k.dt;
    store(io.stim_integral, i, pick(active, integral, old));
    target = load(io.e0, i, T{}) + alpha * integral;
  } else {
    target = load(io.e0, i, T{}) + alpha * (stim - load(io.stim_ref, i, T{}));
  }
  const T change = clamp_lanes(target - e, -k.max_change, k.max_change);
  const T next = clamp_lanes(e + change, k.e_min, k.e_max);
  store(io.stiffness, i, pick(active, next, e));
}

template <class T>
inline void run_develop(const DevelopIo& io, int n, const DevelopConstants& k) {
  over_lanes<T>(n, [&](auto lane, int i) { develop_lanes<decltype(lane)>(io, i, k); });
}

}  // namespace
}  // namespace plastivox
