// Actuation (METHOD.md section 4): every voxel's rest size oscillates, damped by stiffness.
#include <algorithm>
#include <cmath>
#include <numbers>

#include "workspace.hpp"

namespace plastivox {

void actuate(const Model& m, const State& s, Workspace& w) {
  const PhysicsDef& d = m.def;
  if (s.time < d.settle_time || d.act_amplitude == 0 || d.act_frequency == 0) {
    std::fill(w.size.begin(), w.size.end(), m.size);
    return;
  }
  const double two_pi = 2.0 * std::numbers::pi;
  const double inv_range = 1.0 / (d.e_max - d.e_min);
  for (int i = 0; i < m.n; ++i) {
    // Stiff voxels barely move; xi follows the *current* E, so development changes actuation.
    const double xi = (d.e_max - s.stiffness[i]) * inv_range;
    const double wave = std::sin(two_pi * (d.act_frequency * s.time + m.phase[i]));
    // The size factor never drops below act_min_factor (Voxelyze's MIN_TEMP_FACTOR).
    w.size[i] = m.size * std::max(1.0 + d.act_amplitude * xi * wave, d.act_min_factor);
  }
}

}  // namespace plastivox
