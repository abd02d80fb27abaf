// Actuation (docs/method.md §4, docs/control.md): every voxel's rest size for the next step,
// from its signal (the controller's, in [-1, 1]) and its amplitude, damped by stiffness. The
// per-voxel formula is the batched voxel kernel's (voxel_body.hpp, actuate_lanes).
#include <algorithm>
#include <cmath>

#include "kernels.hpp"
#include "workspace.hpp"  // the stage declarations

namespace plastivox {

void actuate(const Model& m, State& s, const double* signal) {
  const PhysicsDef& d = m.def;
  if (s.time < d.settle_time || m.act_amplitude_max == 0) {
    std::fill(s.size.begin(), s.size.end(), m.size);
    return;
  }
  ActuationConstants k;
  k.L = m.size;
  k.min_factor = d.act_min_factor;
  k.wave_max = d.act_expansion ? HUGE_VAL : 0.0;
  if (m.act_per_voxel) {  // the voxel's own amplitude (its gain), whatever its stiffness
    k.amplitude = 1.0;
    k.e_max = 0.0;
    k.inv_range = 0.0;
    k.xi_base = 1.0;
  } else {
    k.amplitude = d.act_amplitude;
    k.e_max = d.e_max;
    k.inv_range = 1.0 / (d.e_max - d.e_min);
    k.xi_base = 0.0;
  }
  kernels().actuate(s.stiffness.data(), signal, m.act_gain.data(), s.size.data(), m.n, k);
}

}  // namespace plastivox
