// The compiled, immutable description of one simulation: voxels, bonds, materials and the
// parameters they run under. Built once by compile(); every stage reads it as const Model&.
#pragma once

#include <cstdint>

#include <array>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "plastivox/model_constants.hpp"
#include "plastivox/physics_def.hpp"
#include "plastivox/robot.hpp"

namespace plastivox {

using Vec3 = Eigen::Vector3d;

// The model's constants (model_constants.hpp: def, size, mass, inertia and the factors
// derived from them, which the kernels read as they are), then its arrays.
struct Model : ModelConstants {
  int n = 0;  // number of voxels: the robot's, then the free objects'
  // Voxels [0, robot_n) are the robot's; [robot_n, n) belong to the free objects
  // (def.environment.objects, or the task's default ones: task.hpp), object k holding
  // [object_begin[k], object_begin[k + 1]). Object voxels have site -1, alpha 0, phase 0,
  // act_gain 0 and bonds of their own only. Without objects robot_n == n. Everything that
  // speaks of "the robot" (centre of mass, fitness, SimResult::voxels, stiffness change)
  // reads the first robot_n voxels; the physics and the floor health read all n.
  int robot_n = 0;
  std::vector<int> object_begin;  // object count + 1 entries ({robot_n} without objects)

  // Per voxel (n entries), in voxel order = increasing lattice site.
  std::vector<int> site;       // lattice site index of the voxel
  std::vector<Vec3> rest_pos;  // initial centre, m, world axes; resting on the ground (z = 0)
  std::vector<double> e0;      // congenital Young's modulus, Pa
  std::vector<double> alpha;   // development rate, 1/s (0 everywhere under kNone)
  std::vector<double> phase;   // actuation phase, cycles
  // Actuation amplitude per voxel: under the paper's rule (act_per_voxel false) every gain is
  // 1 and the amplitude is def.act_amplitude * xi(E); with the robot's own amplitudes
  // (RobotDef::act_amplitude, voxcraft's rule) the gain is the amplitude and xi is not used.
  // Either way it is then multiplied by the robot's act_scale (0 for passive tissue).
  std::vector<double> act_gain;
  bool act_per_voxel = false;
  ControllerDef controller;      // the robot's, validated (Simulator runs it: make_controller)
  double act_amplitude_max = 0;  // the largest linear amplitude any voxel can reach
  // Bond slots of each voxel: [axis*2 + 0] the bond towards -axis, [axis*2 + 1] towards +axis;
  // -1 where there is no neighbour.
  std::vector<std::array<int, 6>> voxel_bonds;
  std::vector<uint8_t> fixed;    // 1 if clamped (boundary condition)
  std::vector<Vec3> load;        // constant external force, N, world axes
  std::vector<uint8_t> surface;  // 1 if some face has no neighbour (collision-eligible)
  // For each voxel, the sorted ids of voxels within def.collision_exclude_hops bonds
  // (never collide with each other: their bonds already keep them apart).
  std::vector<std::vector<int>> near_voxels;

  // Per bond (one per face-adjacent pair); a is the voxel on the negative side of b.
  std::vector<int> bond_a, bond_b;
  std::vector<uint8_t> bond_axis;  // 0 = x, 1 = y, 2 = z

  // The environment (def.environment: the given one, or the task's default that compile()
  // laid out around the body, task.hpp) when active: contact then takes the terrain path
  // (terrain.cpp) with this ground (z = 0 when none is given; unused when def.floor is off)
  // instead of the floor kernel.
  bool terrain = false;
  HeightField ground;

  int bond_count() const { return static_cast<int>(bond_a.size()); }
  int object_count() const { return static_cast<int>(object_begin.size()) - 1; }
};

// Validates robot and physics (std::invalid_argument naming the field) and builds the model.
// Under Treatment::kNone every alpha is forced to 0 so development cannot run.
Model compile(const RobotDef& robot, const PhysicsDef& def, const Limits& limits = {});

// Stable time step for the given per-voxel stiffness: dt_frac / (2 pi sqrt(k_max / m)),
// k_max the largest axial stiffness E * L over bonds (harmonic-mean E) and over single voxels
// (their own E: a stiff voxel among soft ones still meets the floor and global damping
// with its own stiffness; for bodies whose stiffest voxel has an equally stiff neighbour
// this is exactly Voxelyze's rule).
double stable_dt(const Model& model, const std::vector<double>& stiffness);

// ---- Bounds on one life (docs/robot-format.md, "Limits"), so no input runs for ever ----

// The time step of a body whose stiffest voxel has modulus e_top (Pa): the same formula as
// stable_dt, dt_frac / (2 pi sqrt(e_top L / (density L^3))).
double time_step_at(const PhysicsDef& def, double voxel_size, double e_top);
// Throws std::invalid_argument naming the field when a life cannot run in bounded time:
//   - duration / time_step_at(e_top) > limits.life_steps ("physics.duration: ... steps");
//     e_top bounds the stiffness the life can reach (compile: the stiffest voxel, or e_max
//     when it develops), so the estimate is an upper bound;
//   - an actuation period shorter than 2 time steps even at e_max (the smallest dt any
//     body of this physics reaches): "physics.act_frequency".
// compile() calls it; an evolution config calls it with e_max, so no body it makes fails.
void check_life_bounds(const PhysicsDef& def, double voxel_size, double e_top,
                       const Limits& limits = {});

}  // namespace plastivox
