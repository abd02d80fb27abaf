// Sensors (computed on request from what step1 left and the state) and the sine controller.
#include "plastivox/control.hpp"

#include <algorithm>
#include <cmath>

#include "develop_body.hpp"  // stimulus_lanes: the development stimuli, as sensors
#include "elementary.hpp"
#include "kernels.hpp"
#include "workspace.hpp"

namespace plastivox {

const std::array<SensorField, kSensorCount> kSensorFields = {{
    {Sensor::kTouch, "touch", "n", "-", "-",
     "1 while the voxel touches the floor, ground or a box (its actuated half-size reaches into "
     "it), else 0",
     true, 1},
    {Sensor::kFloorForce, "floor_force", "n", "N", "contact normal",
     "the elastic normal force of the floor (or the ground and boxes) on the voxel this step "
     "(2 E L times its penetration, summed over its contacts; 0 off them)",
     true, 1},
    {Sensor::kStrain, "strain", "n", "1", "bond",
     "largest absolute axial strain of the voxel's bonds this step (the strain stimulus)", true, 1},
    {Sensor::kStress, "stress", "n", "Pa", "bond",
     "largest tensile axial stress of the voxel's bonds this step (the stress stimulus)", true, 1},
    {Sensor::kPressure, "pressure", "n", "Pa", "-",
     "the voxel's pressure from its bonds' strains, > 0 in compression (the pressure stimulus)",
     true, 1},
    {Sensor::kVelocity, "velocity", "n x 3", "m/s", "world", "the voxel centre's velocity", true,
     3},
    {Sensor::kUp, "up", "n x 3", "1", "world",
     "the voxel's own +z axis (unit vector; (0, 0, 1) upright)", true, 3},
    {Sensor::kComVelocity, "com_velocity", "3", "m/s", "world",
     "velocity of the robot's centre of mass (mean velocity of its voxels)", false, 3},
    {Sensor::kTime, "time", "1", "s", "-", "simulated time at the start of the step", false, 1},
    {Sensor::kPhase, "phase", "1", "cycles", "-",
     "the sine's phase, f t modulo 1, in [0, 1) (0 when act_frequency is 0)", false, 1},
}};

namespace {

// Fills out (sized for the sensor) with sensor `id` of the present step.
void compute(Sensor id, const Model& m, const State& s, const Workspace& w,
             std::vector<double>& out) {
  const int n = m.n;
  switch (id) {
    case Sensor::kTouch:
    case Sensor::kFloorForce:
      // The contact the integrate stage applies this step: on the floor (voxel_body.hpp,
      // update_lanes) the penetration of the actuated half-size below z = 0, tilt ignored; in
      // an environment the summed penetrations into the ground and boxes (terrain.cpp).
      for (int i = 0; i < n; ++i) {
        const double pen = m.def.environment.terrain()
                               ? terrain_penetration(m, s.pos[i], 0.5 * s.size[i])
                               : 0.5 * s.size[i] - s.pos[i].z();
        const bool touch = (m.def.floor || m.def.environment.terrain()) && pen > 0;
        out[i] = id == Sensor::kTouch ? (touch ? 1.0 : 0.0)
                                      : (touch ? 2.0 * s.stiffness[i] * m.size * pen : 0.0);
      }
      return;
    case Sensor::kStrain:
    case Sensor::kStress:
    case Sensor::kPressure: {
      // The development stimulus of that name, of this step's bonds (the bond stage's strains
      // and stresses), by the development kernel's own formula.
      const Treatment which = id == Sensor::kStrain   ? Treatment::kStrain
                              : id == Sensor::kStress ? Treatment::kStress
                                                      : Treatment::kPressure;
      for (int i = 0; i < n; ++i) out[i] = stimulus_lanes<double>(w.views.develop, i, m, which);
      return;
    }
    case Sensor::kVelocity:
      for (int i = 0; i < n; ++i)
        for (int c = 0; c < 3; ++c) out[3 * i + c] = s.lin_mom[i][c] / m.mass;
      return;
    case Sensor::kUp:
      for (int i = 0; i < n; ++i) {
        const Vec3 up = s.orient[i] * Vec3::UnitZ();
        for (int c = 0; c < 3; ++c) out[3 * i + c] = up[c];
      }
      return;
    case Sensor::kComVelocity: {
      const int body = m.robot_n;  // the free objects that follow are not the robot
      Vec3 p = Vec3::Zero();
      for (int i = 0; i < body; ++i) p += s.lin_mom[i];
      const Vec3 v = body > 0 ? Vec3(p / (body * m.mass)) : p;
      for (int c = 0; c < 3; ++c) out[c] = v[c];
      return;
    }
    case Sensor::kTime:
      out[0] = s.time;
      return;
    case Sensor::kPhase: {
      const double cycles = m.def.act_frequency * s.time;
      out[0] = cycles - std::floor(cycles);
      return;
    }
  }
}

}  // namespace

std::span<const double> Sensors::read(Sensor id) const {
  const auto k = static_cast<size_t>(id);
  const SensorField& f = kSensorFields[k];
  std::vector<double>& v = cache_.values[k];
  if (!cache_.fresh[k]) {
    v.resize(static_cast<size_t>(f.per_voxel ? model_.n * f.width : f.width));
    compute(id, model_, state_, ws_, v);
    cache_.fresh[k] = true;
  }
  return v;
}

void SineController::act(const Sensors& sensors, std::span<double> actuation, std::span<double>) {
  const Model& m = sensors.model();
  const State& s = sensors.state();
  if (s.time < m.def.settle_time) return;  // not actuated yet: the signal is not read
  if (m.def.act_frequency == 0) {
    std::fill(actuation.begin(), actuation.end(), 0.0);
    return;
  }
  // The robot's voxels: a free object does not actuate (its signal, a row of the State, stays
  // 0, as a caller that drives the robot writes it).
  kernels().sine(m.phase.data(), actuation.data(), m.robot_n, m.def.act_frequency * s.time);
}

double sin_cycles_of(double u) {
  return sin_cycles(u);
}

void sin_cycles_of(std::span<const double> u, std::span<double> out) {
  kernels().sine(u.data(), out.data(), static_cast<int>(u.size()), 0.0);  // sin(0 + u)
}

}  // namespace plastivox
