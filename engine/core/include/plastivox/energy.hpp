// Energy bookkeeping, for conservation checks and diagnostics (not used by the step).
#pragma once

#include <vector>

#include "plastivox/model.hpp"
#include "plastivox/state.hpp"

namespace plastivox {

// Translational plus rotational kinetic energy, J.
double kinetic_energy(const Model& model, const State& state);
// Strain energy stored in all bonds (axial, torsion, bending), J, measured from the actuated
// rest lengths (state.size).
double elastic_energy(const Model& model, const State& state);
// Gravitational potential energy relative to z = 0, J.
double gravity_energy(const Model& model, const State& state);

}  // namespace plastivox
