// Actuation (docs/method.md §4, docs/control.md): every voxel's rest size for the next step,
// from its signal (the controller's, in [-1, 1]) and its amplitude, damped by stiffness. The
// per-voxel formula is the batched voxel kernel's (voxel_body.hpp, actuate_lanes).
#include <algorithm>

#include "kernels.hpp"
#include "workspace.hpp"  // the stage declarations

namespace plastivox {

void actuate(const Model& m, State& s, const double* signal) {
  const PhysicsDef& d = m.def;
  if (s.time < d.settle_time || m.act_amplitude_max == 0) {
    std::fill(s.size.begin(), s.size.end(), m.size);
    return;
  }
  // The constants compile() derived: the voxel's own amplitude (its gain) whatever its
  // stiffness when the robot gives one (act_per_voxel), else the paper's xi(E).
  kernels().actuate(s.stiffness.data(), signal, m.act_gain.data(), s.size.data(), m.n, m);
}

}  // namespace plastivox
