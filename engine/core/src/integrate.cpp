// Force gathering and the semi-implicit Euler update of every voxel, with floor contact
// and Coulomb friction: the batched voxel kernels (voxel_body.hpp) over the model, state
// and workspace, and the stability check on what they report. Per-voxel work in index
// order; bond contributions are summed in slot order, so the result does not depend on
// anything but the model and the state.
#include <cmath>
#include <sstream>

#include "kernels.hpp"
#include "workspace.hpp"

namespace plastivox {
static_assert(sizeof(Vec3) == 3 * sizeof(double) && sizeof(Quat) == 4 * sizeof(double));

void bind_voxel_views(const Model& m, Workspace& w) {
  VoxelKernelIo& io = w.views.voxel;
  for (int k = 0; k < 6; ++k) io.slot_bond[k] = w.slot_bond[k].data();
  io.fixed = m.fixed.data();
  io.load = fields::data_of(m.load);
  for (int v = 0; v < 3; ++v) io.bond_out[v] = w.bond_out[v].data();
  for (int c = 0; c < 3; ++c) {
    io.force[c] = w.force[c].data();
    io.moment[c] = w.moment[c].data();
  }
  io.sqrt_e = w.sqrt_e.data();
  io.floor_normal = w.floor_normal.empty() ? nullptr : w.floor_normal.data();
}

// Reads the State through the views (positions, momenta, stiffness); the gather takes no dt.
void gather_voxel_forces(const Model& m, const State&, Workspace& w) {
  if (m.n == 0) return;
  kernels().gather(w.views.voxel, m.n, m);
}

void integrate(const Model& m, State& s, Workspace& w) {
  if (m.n == 0) return;
  if (m.terrain) terrain_contacts(m, s, w);
  const VoxelUpdateSummary r = kernels().update(w.views.voxel, w.views.voxel_out, m.n, m, s.dt);
  if (m.terrain) terrain_after_update(m, s, w);
  const double limit = m.def.max_speed;
  if (!r.non_finite && !(r.max_speed2 > limit * limit)) return;

  // Unstable: name the fastest free voxel (the first of equals) from the updated momenta.
  const double inv_mass = m.inv_mass;
  double max_speed2 = 0;
  int fastest = -1;
  for (int i = 0; i < m.n; ++i) {
    if (m.fixed[i]) continue;
    const Vec3& p = s.lin_mom[i];
    const double v2 = (p.x() * p.x() + p.y() * p.y() + p.z() * p.z()) * inv_mass * inv_mass;
    if (v2 > max_speed2) max_speed2 = v2, fastest = i;
  }
  std::ostringstream why;
  why.precision(4);
  if (r.non_finite) {
    why << "non-finite momentum at t=" << s.time << " s";
  } else {
    why << "voxel " << fastest << " moves at " << std::sqrt(max_speed2)
        << " m/s (limit max_speed=" << limit << ") at t=" << s.time << " s";
  }
  s.status = SimStatus::kUnstable;
  s.failure = why.str();
}

}  // namespace plastivox
