#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>

#include "plastivox/model.hpp"
#include "tasks.hpp"  // task_objects

namespace plastivox {
namespace {

// Appends the free objects' voxels and bonds after the robot's (Model::robot_n): each a box
// of voxels of the robot's size, x fastest, then y, then z, bonded to its face neighbours,
// passive and undeveloping; its stiffness is its own or the robot's stiffest congenital one.
void add_objects(Model& m, const std::vector<ObjectDef>& objects) {
  m.object_begin.assign(1, m.n);
  if (objects.empty()) return;
  double e_robot = 0;
  for (int i = 0; i < m.robot_n; ++i) e_robot = std::max(e_robot, m.e0[i]);
  const double L = m.size;
  for (const ObjectDef& o : objects) {
    const int first = m.n;
    const int nx = o.voxels[0], ny = o.voxels[1], nz = o.voxels[2];
    for (int z = 0; z < nz; ++z)
      for (int y = 0; y < ny; ++y)
        for (int x = 0; x < nx; ++x) {
          m.site.push_back(-1);
          m.rest_pos.emplace_back(o.at[0] + (x + 0.5) * L, o.at[1] + (y + 0.5) * L,
                                  o.at[2] + (z + 0.5) * L);
          m.e0.push_back(o.stiffness > 0 ? o.stiffness : e_robot);
          m.alpha.push_back(0.0);
          m.phase.push_back(0.0);
          m.act_gain.push_back(0.0);
          m.voxel_bonds.push_back({-1, -1, -1, -1, -1, -1});
          m.fixed.push_back(0);
          m.load.push_back(Vec3::Zero());
          m.n += 1;
        }
    const int step[3] = {1, nx, nx * ny};
    for (int z = 0; z < nz; ++z)
      for (int y = 0; y < ny; ++y)
        for (int x = 0; x < nx; ++x) {
          const int c[3] = {x, y, z};
          const int i = first + x + nx * (y + ny * z);
          for (int axis = 0; axis < 3; ++axis) {
            if (c[axis] + 1 >= o.voxels[axis]) continue;
            const int j = i + step[axis], b = m.bond_count();
            m.bond_a.push_back(i);
            m.bond_b.push_back(j);
            m.bond_axis.push_back(static_cast<uint8_t>(axis));
            m.voxel_bonds[i][axis * 2 + 1] = b;
            m.voxel_bonds[j][axis * 2 + 0] = b;
          }
        }
    m.object_begin.push_back(m.n);
  }
}

}  // namespace

namespace {

// The environment of the life (the given one, or the task's default laid out around the
// body's footprint: task.hpp) and the body placed on its ground: the lattice is moved up or
// down, as a whole, until its lowest voxel (as the contact sees it: a ball of half the voxel
// size under its centre) just touches the ground under it and no voxel presses into it
// (docs/environments.md, "Where the robot starts"). Boxes are not considered. Without an
// environment nothing changes: the bottom layer stays on z = 0.
void place_in_environment(Model& m) {
  const double L = m.size;
  TaskSite site;
  site.L = L;
  if (m.n > 0) {
    Vec3 lo = m.rest_pos[0], hi = m.rest_pos[0];
    for (const Vec3& p : m.rest_pos) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
    site.cx = 0.5 * (lo.x() + hi.x()), site.cy = 0.5 * (lo.y() + hi.y());
    site.hx = 0.5 * (hi.x() - lo.x() + L), site.hy = 0.5 * (hi.y() - lo.y() + L);
  }
  if (!m.def.environment.terrain() && task_info(m.def.task).environment) {
    m.def.environment = task_environment(m.def, site);  // keeps the free objects given
    validate(m.def.environment);
  }
  m.terrain = m.def.environment.terrain();
  if (!m.terrain) return;
  m.ground = make_height_field(m.def.environment.ground);
  if (!m.def.floor || m.n == 0) return;
  // The lift that makes voxel i's penetration r - (z - h) n_z zero is pen / n_z.
  double lift = -std::numeric_limits<double>::infinity();
  for (const Vec3& p : m.rest_pos) {
    double normal[3];
    const double pen = m.ground.penetration(p.x(), p.y(), p.z(), 0.5 * L, normal);
    lift = std::max(lift, pen / normal[2]);
  }
  if (lift != 0)
    for (Vec3& p : m.rest_pos) p.z() += lift;
}

}  // namespace

// Floor of the chord in the exact model's shear coupling 3 b3 / chord (bond_forces.cpp), in
// nominal lengths. Below it the coupling's stiffness, ~3 b3 / chord^2, exceeds what the step
// integrates: at a tenth of L it is 50 E L, within the ~195x headroom of dt's 0.9 / (2 pi)
// over the stiffest bond even for a bond of that stiffness. Only a bond crushed to a tenth of
// its length sees it.
constexpr double kMinShearChord = 0.1;

Model compile(const RobotDef& robot, const PhysicsDef& def, const Limits& limits) {
  validate(robot, limits);
  validate(def);
  Model m;
  m.def = def;
  const double L = robot.voxel_size;
  m.size = L;
  m.mass = def.density * L * L * L;
  m.inertia = m.mass * L * L / 6.0;
  m.inv_mass = 1.0 / m.mass;
  m.inv_inertia = 1.0 / m.inertia;
  m.inv_volume = 1.0 / (L * L * L);
  ModelConstants& k = m;
  const double nu = def.poisson;
  k.area = L * L;
  k.inv_L = 1.0 / L;
  k.ka2 = L * L * L / (12.0 * (1.0 + nu));
  k.kb1 = L;
  k.kb2 = L * L / 2.0;
  k.kb3 = L * L * L / 6.0;
  k.bond_damp = 2.0 * std::sqrt(m.mass) * def.bond_damping;
  k.damp_a1 = std::sqrt(L);
  k.damp_b2 = std::sqrt(L * L * L / 4.0);
  k.damp_a2 = std::sqrt(L * L * L * L * L / (72.0 * (1.0 + nu)));
  k.damp_b3 = std::sqrt(L * L * L * L * L / 36.0);
  k.axial_own = def.axial_modulus == AxialModulus::kNegativeVoxel;
  k.min_shear_chord = kMinShearChord * L;
  k.c_lin_unit = 2.0 * std::sqrt(m.mass * L);
  k.c_rot_unit = 2.0 * std::sqrt(m.inertia * L * L * L);
  k.c_col_unit = def.collision_damping * k.c_lin_unit;
  k.rot_damp = def.global_damping_rot_factor * def.global_damping;
  k.weight[2] = m.mass * def.gravity;
  k.pressure_denominator = 3.0 * (1.0 - 2.0 * nu);
  k.gate = def.min_devo_factor * def.e_min;

  // Voxels in increasing site order. The site -> voxel lookup for bonding searches that
  // sorted list, so the model costs memory per voxel, not per lattice site.
  m.site.reserve(static_cast<size_t>(robot.voxel_count()));
  for (int s = 0; s < robot.sites(); ++s)
    if (robot.present[s]) m.site.push_back(s);
  m.n = static_cast<int>(m.site.size());
  const auto voxel_of = [&m](int s) {
    const auto at = std::lower_bound(m.site.begin(), m.site.end(), s);
    return at != m.site.end() && *at == s ? static_cast<int>(at - m.site.begin()) : -1;
  };
  m.rest_pos.resize(m.n);
  m.e0.resize(m.n);
  m.alpha.resize(m.n);
  m.phase.resize(m.n);
  m.act_gain.assign(m.n, 1.0);
  m.act_per_voxel = !robot.act_amplitude.empty();
  m.controller = robot.controller;  // validated with the robot
  m.act_amplitude_max = m.act_per_voxel ? 0.0 : def.act_amplitude;
  m.act_amplitude_xi = m.act_per_voxel ? 1.0 : def.act_amplitude;
  m.xi_e_max = m.act_per_voxel ? 0.0 : def.e_max;
  m.xi_inv_range = m.act_per_voxel ? 0.0 : 1.0 / (def.e_max - def.e_min);
  m.xi_base = m.act_per_voxel ? 1.0 : 0.0;
  m.act_wave_max = def.act_expansion ? HUGE_VAL : 0.0;
  m.voxel_bonds.assign(m.n, {-1, -1, -1, -1, -1, -1});
  const bool develops = def.treatment != Treatment::kNone;
  for (int i = 0; i < m.n; ++i) {
    const int s = m.site[i];
    const int x = s % robot.nx, y = (s / robot.nx) % robot.ny, z = s / (robot.nx * robot.ny);
    m.rest_pos[i] = Vec3((x + 0.5) * L, (y + 0.5) * L, (z + 0.5) * L);
    // Congenital stiffness is held to the admissible range, as the encoding maps it there.
    m.e0[i] = std::clamp(robot.stiffness[s], def.e_min, def.e_max);
    m.alpha[i] = develops ? robot.dev_rate[s] : 0.0;
    m.phase[i] = robot.phase[s];
    if (m.act_per_voxel) {
      m.act_gain[i] = robot.act_amplitude[s];
      m.act_amplitude_max = std::max(m.act_amplitude_max, m.act_gain[i]);
    }
    if (!robot.act_scale.empty()) m.act_gain[i] *= robot.act_scale[s];  // 0: passive
  }
  place_in_environment(m);
  m.flat_floor = def.floor && !m.terrain;  // an environment's ground: terrain.cpp
  // Bounded in time before anything runs: the stiffest voxel, or e_max if E can grow.
  double e_top = 0;
  for (double e : m.e0) e_top = std::max(e_top, e);
  m.robot_n = m.n;
  const std::vector<ObjectDef> objects =
      def.environment.objects.empty() ? task_objects(def.task, robot) : def.environment.objects;
  for (const ObjectDef& o : objects)
    if (o.stiffness > 0) e_top = std::max(e_top, o.stiffness);
  check_life_bounds(def, L, develops ? def.e_max : e_top, limits);
  m.fixed.assign(m.n, 0);
  m.load.assign(m.n, Vec3::Zero());
  for (int site : robot.fixed_sites) m.fixed[voxel_of(site)] = 1;
  for (const RobotDef::Load& l : robot.loads) m.load[voxel_of(l.site)] += Vec3(l.fx, l.fy, l.fz);
  // Bonds in voxel order, +x then +y then +z neighbour: a fixed, documented order.
  const int stride[3] = {1, robot.nx, robot.nx * robot.ny};
  for (int i = 0; i < m.n; ++i) {
    const int s = m.site[i];
    const int c[3] = {s % robot.nx, (s / robot.nx) % robot.ny, s / (robot.nx * robot.ny)};
    const int extent[3] = {robot.nx, robot.ny, robot.nz};
    for (int axis = 0; axis < 3; ++axis) {
      if (c[axis] + 1 >= extent[axis]) continue;
      const int j = voxel_of(s + stride[axis]);
      if (j < 0) continue;
      const int b = m.bond_count();
      m.bond_a.push_back(i);
      m.bond_b.push_back(j);
      m.bond_axis.push_back(static_cast<uint8_t>(axis));
      m.voxel_bonds[i][axis * 2 + 1] = b;
      m.voxel_bonds[j][axis * 2 + 0] = b;
    }
  }
  add_objects(m, objects);
  // Surface voxels and the bond-hop neighbourhoods that self-collision skips.
  m.surface.assign(m.n, 0);
  m.near_voxels.assign(m.n, {});
  std::vector<int> depth(m.n, -1);
  std::vector<int> frontier, next, seen;
  for (int i = 0; i < m.n; ++i) {
    for (int b : m.voxel_bonds[i]) m.surface[i] |= (b < 0) ? 1 : 0;
    if (!m.surface[i] || !(def.self_collision || m.robot_n < m.n)) continue;
    frontier.assign(1, i);
    seen.assign(1, i);
    depth[i] = 0;
    for (int hop = 1; hop <= def.collision_exclude_hops && !frontier.empty(); ++hop) {
      next.clear();
      for (int v : frontier) {
        for (int b : m.voxel_bonds[v]) {
          if (b < 0) continue;
          const int u = m.bond_a[b] == v ? m.bond_b[b] : m.bond_a[b];
          if (depth[u] >= 0) continue;
          depth[u] = hop;
          next.push_back(u);
          seen.push_back(u);
        }
      }
      frontier.swap(next);
    }
    for (int v : seen) depth[v] = -1;
    std::sort(seen.begin(), seen.end());
    m.near_voxels[i] = seen;
  }
  // What the kernels index without checks: every bond joins two voxels, a before b along
  // its axis; every voxel slot names a bond of that voxel or none.
  for (int b = 0; b < m.bond_count(); ++b)
    assert(m.bond_a[b] >= 0 && m.bond_a[b] < m.bond_b[b] && m.bond_b[b] < m.n &&
           m.bond_axis[b] < 3 && "compile() built an inconsistent bond list");
  for (int i = 0; i < m.n; ++i)
    for (int slot = 0; slot < 6; ++slot)
      assert((m.voxel_bonds[i][slot] < 0 ||
              (slot & 1 ? m.bond_a : m.bond_b)[m.voxel_bonds[i][slot]] == i) &&
             "compile() built an inconsistent slot table");
  return m;
}

double time_step_at(const PhysicsDef& def, double voxel_size, double e_top) {
  const double mass = def.density * voxel_size * voxel_size * voxel_size;
  return def.dt_frac / (2.0 * std::numbers::pi * std::sqrt(e_top * voxel_size / mass));
}

void check_life_bounds(const PhysicsDef& def, double voxel_size, double e_top,
                       const Limits& limits) {
  auto num = [](double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.3g", v);
    return std::string(buf);
  };
  const double dt = time_step_at(def, voxel_size, e_top);
  const double steps = def.duration / dt;
  const int64_t limit = limits.life_steps;
  if (!(steps <= static_cast<double>(limit)))
    throw std::invalid_argument(
        "physics.duration: a life of " + num(def.duration) + " s at time step " + num(dt) +
        " s takes about " + num(steps) + " steps, more than the limit of " + std::to_string(limit) +
        " (dt_frac, voxel_size, density and the stiffness set the step; the environment "
        "variable PLASTIVOX_MAX_STEPS raises the limit)");
  const double dt_min = time_step_at(def, voxel_size, def.e_max);
  if (def.act_frequency > 0 && !(1.0 / def.act_frequency >= 2.0 * dt_min))
    throw std::invalid_argument("physics.act_frequency: " + num(def.act_frequency) +
                                " Hz is faster than the time step resolves (dt " + num(dt_min) +
                                " s at e_max; at most " + num(0.5 / dt_min) + " Hz)");
}

namespace {

// Voxelyze 0.9's CVX_Sim::CalcMaxDt: the largest a1 / m = E_bond (L L) / L / m over all bonds
// (no single-voxel term unless there are no bonds, then E / m as written there), and pi as
// the literal 3.1415926, in its order of operations (dt 1.7e-8 longer than with pi).
double voxelyze_dt(const Model& m, const std::vector<double>& E) {
  // Dividing by the one mass after taking the maximum gives the same double (rounding is
  // monotonic), so the loop does no division but the harmonic mean's.
  double k = 0;
  const double area = m.size * m.size;
  for (int b = 0; b < m.bond_count(); ++b) {
    const double e1 = E[m.bond_a[b]], e2 = E[m.bond_b[b]];
    k = std::max(k, (e1 * e2 / (e1 + e2)) * 2 * area / m.size);
  }
  if (m.bond_count() == 0)
    for (int i = 0; i < m.n; ++i) k = std::max(k, E[i]);
  return m.def.dt_frac * (1.0 / (std::sqrt(k / m.mass) * 2 * 3.1415926));
}

}  // namespace

double stable_dt(const Model& m, const std::vector<double>& E) {
  if (m.def.bond_model == BondModel::kVoxelyze09) return voxelyze_dt(m, E);
  // A bond's harmonic mean never exceeds the larger of its two moduli, so a bond can only
  // set k_max (by rounding up) when both its voxels are within a relative 1e-9 of the
  // stiffest voxel: below that, 2ab/(a+b) < E_top (1 - 5e-10) even after rounding. Only
  // those bonds are evaluated, found from their a ends; the result is the same maximum, bit
  // for bit, as over all bonds. The single voxels' term max_i E_i L is E_top L (rounding is
  // monotonic).
  double e_top = 0;
  for (int i = 0; i < m.n; ++i) e_top = E[i] > e_top ? E[i] : e_top;
  const double near_top = e_top * (1.0 - 1e-9);
  double k_max = e_top * m.size;
  for (int i = 0; i < m.n; ++i) {
    if (!(E[i] >= near_top)) continue;
    for (int axis = 0; axis < 3; ++axis) {
      const int b = m.voxel_bonds[i][2 * axis + 1];  // i is this bond's a end
      if (b < 0) continue;
      const double ea = E[i], eb = E[m.bond_b[b]];
      if (eb >= near_top) k_max = std::max(k_max, 2.0 * ea * eb / (ea + eb) * m.size);
    }
  }
  return m.def.dt_frac / (2.0 * std::numbers::pi * std::sqrt(k_max / m.mass));
}

}  // namespace plastivox
