#include "test_support.hpp"

#include <cfenv>

namespace plastivox::testing {

RobotDef block(int nx, int ny, int nz, double E, double voxel_size) {
  RobotDef r = make_empty_robot(nx, ny, nz, voxel_size);
  for (int s = 0; s < r.sites(); ++s) {
    r.present[s] = 1;
    r.stiffness[s] = E;
  }
  return r;
}

PhysicsDef passive_physics() {
  PhysicsDef d;
  d.act_amplitude = 0;
  d.self_collision = false;
  d.e_min = 1e4;
  d.e_max = 1e12;
  return d;
}

void run_until(Simulator& sim, double t) {
  while (sim.state().time < t && sim.state().status == SimStatus::kRunning) sim.step();
}

std::string shared_dir() {
  return PLASTIVOX_SHARED_DIR;
}

namespace {
// Trap invalid operations (NaN production) in every test binary.
struct TrapFpe {
  TrapFpe() { feenableexcept(FE_INVALID); }
} trap_fpe;
}  // namespace

}  // namespace plastivox::testing
