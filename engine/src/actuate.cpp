// Actuation (docs/method.md §4): every voxel's rest size oscillates, damped by stiffness.
// The per-voxel formula is the batched voxel kernel's (voxel_body.hpp, actuate_lanes).
#include <algorithm>

#include "kernels.hpp"
#include "workspace.hpp"  // the stage declarations

namespace plastivox {

void actuate(const Model& m, State& s) {
  const PhysicsDef& d = m.def;
  if (s.time < d.settle_time || d.act_amplitude == 0 || d.act_frequency == 0) {
    std::fill(s.size.begin(), s.size.end(), m.size);
    return;
  }
  ActuationConstants k;
  k.L = m.size;
  k.amplitude = d.act_amplitude;
  k.min_factor = d.act_min_factor;
  k.e_max = d.e_max;
  k.inv_range = 1.0 / (d.e_max - d.e_min);
  k.cycles = d.act_frequency * s.time;
  kernels().actuate(s.stiffness.data(), m.phase.data(), s.size.data(), m.n, k);
}

}  // namespace plastivox
