#include "plastivox/energy.hpp"

namespace plastivox {

double kinetic_energy(const Model& m, const State& s) {
  double k = 0;
  for (int i = 0; i < m.n; ++i)
    k += 0.5 * s.lin_mom[i].squaredNorm() / m.mass + 0.5 * s.ang_mom[i].squaredNorm() / m.inertia;
  return k;
}

double gravity_energy(const Model& m, const State& s) {
  double u = 0;
  for (int i = 0; i < m.n; ++i) u -= m.mass * m.def.gravity * s.pos[i].z();
  return u;
}

}  // namespace plastivox
