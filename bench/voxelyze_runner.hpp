// The Voxelyze side of bench/voxelyze_side_by_side.cpp, behind plain data: Voxelyze's
// headers compile as C++17, not as this project's C++20, so only voxelyze_runner.cpp sees them.
#pragma once

#include <vector>

struct VoxelyzeBody {
  struct Voxel {
    int x, y, z;
    double stiffness;  // Pa
  };
  std::vector<Voxel> voxels;
  double voxel_size = 0.01;  // m
  double density = 1e9;      // kg/m^3
  double bond_damping = 1, global_damping = 0.01, collision_damping = 0.8;
  double mu_static = 1, mu_kinetic = 0.5;
  bool self_collision = false;
  double act_amplitude = 0.1447;  // linear, fraction of the voxel size
  double act_frequency = 5;       // Hz
};

// CPU seconds of this process so far (both sides of the bench time with it).
double cpu_seconds();

// Builds the body in Voxelyze (a material per distinct stiffness, Poisson's ratio 0, the
// floor, gravity) and takes up to `steps` steps at its recommended time step, actuating every
// voxel through its temperature. Stores the CPU seconds of the stepping alone in *seconds and
// returns the steps taken (fewer if Voxelyze reported divergence).
int voxelyze_steps(const VoxelyzeBody& body, int steps, double* seconds);
