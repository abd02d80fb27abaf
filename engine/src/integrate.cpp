// Force gathering and the semi-implicit Euler update of every voxel, with floor contact
// and Coulomb friction. Per-voxel loops in index order; bond contributions are summed in
// slot order, so the result does not depend on anything but the model and the state.
#include <algorithm>
#include <cmath>
#include <sstream>

#include "workspace.hpp"

namespace plastivox {
namespace {

// Rotation by the rotation vector v (axis * angle, rad).
// Per step a voxel turns by far less than 1e-2 rad, so the common case uses the series
// cos(h) = 1 - h^2/2 + h^4/24 - h^6/720 + h^8/40320, sin(h)/h = 1 - h^2/6 + h^4/120 -
// h^6/5040 + h^8/362880 (truncation error below 1e-20 for h < 5e-3).
inline Quat quat_from_rotation_vector(const Vec3& v) {
  const double a2 = v.squaredNorm();
  const double h2 = 0.25 * a2;  // (angle / 2)^2
  if (h2 < 2.5e-5) {
    const double c = 1.0 - h2 * (0.5 - h2 * (1.0 / 24 - h2 * (1.0 / 720 - h2 * (1.0 / 40320))));
    const double sinc =
        1.0 - h2 * (1.0 / 6 - h2 * (1.0 / 120 - h2 * (1.0 / 5040 - h2 * (1.0 / 362880))));
    const Vec3 u = 0.5 * sinc * v;
    return Quat(c, u.x(), u.y(), u.z());
  }
  const double angle = std::sqrt(a2);
  const Vec3 axis = v / angle;
  const double h = 0.5 * angle, sh = std::sin(h);
  return Quat(std::cos(h), axis.x() * sh, axis.y() * sh, axis.z() * sh);
}

}  // namespace

void gather_voxel_forces(const Model& m, const State& s, Workspace& w) {
  const double L = m.size;
  const Vec3 weight(0.0, 0.0, m.mass * m.def.gravity);
  const double zeta = m.def.global_damping;
  for (int i = 0; i < m.n; ++i) {
    Vec3 f = Vec3::Zero(), mo = Vec3::Zero();
    const std::array<int, 6>& slots = m.voxel_bonds[i];
    for (int k = 0; k < 6; ++k) {
      const int b = slots[k];
      if (b < 0) continue;
      const auto& o = w.bond_out;
      const Vec3 fa(o[0][b], o[1][b], o[2][b]);
      if (k & 1) {  // bond towards +axis: this voxel is its a end
        f += fa;
        mo += Vec3(o[3][b], o[4][b], o[5][b]);
      } else {
        f -= fa;
        mo += Vec3(o[6][b], o[7][b], o[8][b]);
      }
    }
    // Slow (global) damping: a small fraction of the critical damping of the voxel's own
    // axial spring, against absolute velocity.
    w.sqrt_e[i] = std::sqrt(s.stiffness[i]);
    const double c_lin = 2.0 * std::sqrt(m.mass * L) * w.sqrt_e[i];
    f -= (zeta * c_lin / m.mass) * s.lin_mom[i];
    w.force[i] = f + weight + m.load[i];
    w.moment[i] = mo;
  }
}

void integrate(const Model& m, State& s, Workspace& w) {
  const PhysicsDef& d = m.def;
  const double L = m.size, dt = s.dt;
  const double inv_mass = 1.0 / m.mass, inv_inertia = 1.0 / m.inertia;
  // 2 sqrt(m E L) and 2 sqrt(I E L^3) are these times sqrt(E) (cached by gather).
  const double c_lin_unit = 2.0 * std::sqrt(m.mass * L);
  const double c_rot_unit = 2.0 * std::sqrt(m.inertia * L * L * L);
  double max_speed2 = 0;
  int fastest = -1;
  bool finite = true;
  for (int i = 0; i < m.n; ++i) {
    const double E = s.stiffness[i];
    if (m.fixed[i]) {  // clamped: held in place, its reaction is not tracked
      s.lin_mom[i].setZero();
      s.ang_mom[i].setZero();
      continue;
    }
    Vec3 f = w.force[i];
    Vec3& p = s.lin_mom[i];
    bool held = false;  // static friction holds the voxel this step

    if (d.floor) {
      // Penetration of the voxel's (actuated) half-size below the floor plane z = 0; the
      // voxel's tilt is ignored, as in Voxelyze.
      const double pen = 0.5 * w.size[i] - s.pos[i].z();
      if (pen > 0) {
        const double normal = 2.0 * E * L * pen;
        const double vz = p.z() * inv_mass;
        const double c_col = d.collision_damping * c_lin_unit * w.sqrt_e[i];
        const double vx = p.x() * inv_mass, vy = p.y() * inv_mass;
        if (vx == 0 && vy == 0) {
          // At rest: stick unless the lateral load exceeds the static limit.
          held = std::sqrt(f.x() * f.x() + f.y() * f.y()) < d.mu_static * normal;
        } else {
          const double speed = std::sqrt(vx * vx + vy * vy);
          const double fric = d.mu_kinetic * normal;
          if (fric * dt < m.mass * speed) {
            f.x() -= fric * vx / speed;
            f.y() -= fric * vy / speed;
          } else {
            held = true;  // friction would reverse the motion within this step: stop
            p.x() = p.y() = 0;
          }
        }
        f.z() += normal - c_col * vz;
      }
    }
    if (held) f.x() = f.y() = 0;
    s.static_friction[i] = held ? 1 : 0;

    p += f * dt;
    s.pos[i] += p * (dt * inv_mass);

    // Rotation: moment, then slow rotational damping as a per-step decay of the angular
    // momentum, then the orientation advanced by the rotation vector omega * dt.
    Vec3& h = s.ang_mom[i];
    h += w.moment[i] * dt;
    const double c_rot = c_rot_unit * w.sqrt_e[i];
    h *= 1.0 - d.global_damping_rot_factor * d.global_damping * c_rot * inv_inertia * dt;
    Quat& q = s.orient[i];
    q = quat_from_rotation_vector(h * (dt * inv_inertia)) * q;
    q.normalize();

    const double v2 = p.squaredNorm() * inv_mass * inv_mass;
    if (v2 > max_speed2) {
      max_speed2 = v2;
      fastest = i;
    }
    finite = finite && std::isfinite(v2) && std::isfinite(h.squaredNorm());
  }

  if (!finite || max_speed2 > d.max_speed * d.max_speed) {
    std::ostringstream why;
    why.precision(4);
    if (!finite) {
      why << "non-finite momentum at t=" << s.time << " s";
    } else {
      why << "voxel " << fastest << " moves at " << std::sqrt(max_speed2)
          << " m/s (limit max_speed=" << d.max_speed << ") at t=" << s.time << " s";
    }
    s.status = SimStatus::kUnstable;
    s.failure = why.str();
  }
}

}  // namespace plastivox
