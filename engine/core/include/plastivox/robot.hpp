// A robot as a researcher defines it: which lattice sites hold a voxel and each voxel's
// congenital stiffness, development rate and actuation phase. Plain data, no physics.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "plastivox/controller_def.hpp"

namespace plastivox {

// Lattice sites are indexed x fastest, then y, then z: site = x + nx*(y + ny*z).
struct RobotDef {
  std::string name;               // free text, carried into results
  int nx = 10, ny = 10, nz = 10;  // lattice extent in sites
  double voxel_size = 0.01;       // edge length of one voxel, m
  std::vector<uint8_t> present;   // 1 where a voxel exists (nx*ny*nz)
  std::vector<double> stiffness;  // congenital Young's modulus E0, Pa (nx*ny*nz)
  std::vector<double> dev_rate;   // development rate alpha, 1/s (nx*ny*nz); 0 = none
  std::vector<double> phase;      // actuation phase offset, cycles in (-1, 1) (nx*ny*nz)
  // Per-voxel linear actuation amplitude, fraction of L in [0, 0.9) (nx*ny*nz), as
  // voxcraft-sim gives it (TempAmplitude x the material's CTE, independent of stiffness).
  // Empty (the default, and every robot of the paper): physics.act_amplitude * xi(E).
  std::vector<double> act_amplitude;
  // Per-voxel actuation scale in [0, 1] (nx*ny*nz): the voxel's amplitude (either rule above)
  // times this; 0 makes passive tissue, which the controller's signal does not move. Empty
  // (the default): 1 everywhere.
  std::vector<double> act_scale;
  // The controller that writes each voxel's actuation signal (docs/control.md); the default
  // is the sine, every step.
  ControllerDef controller;

  // Boundary conditions, for experiments and physics tests (evolved robots have none).
  std::vector<int> fixed_sites;  // sites whose voxel is clamped: no translation, no rotation
  struct Load {
    int site = 0;                   // lattice site of the loaded voxel
    double fx = 0, fy = 0, fz = 0;  // constant external force, N, world axes
  };
  std::vector<Load> loads;

  int sites() const { return nx * ny * nz; }
  int site(int x, int y, int z) const { return x + nx * (y + ny * z); }
  int voxel_count() const;
};

// Voxel edge lengths a robot may have, m (docs/robot-format.md, "Limits").
constexpr double kMinVoxelSize = 1e-4, kMaxVoxelSize = 10.0;

// What one input may ask of the machine (docs/robot-format.md, "Limits"), so that no file
// allocates or runs without bound. The engine reads no environment: the program and the
// Python module let a user raise these with PLASTIVOX_MAX_LATTICE_SITES, PLASTIVOX_MAX_STEPS
// and PLASTIVOX_MAX_RECORDING_MB (limits_from_environment(), plastivox/io/limits.hpp) and
// pass them in.
struct Limits {
  // Most lattice sites (nx*ny*nz) a robot may declare: 2^21 (128^3). A RobotDef's arrays are
  // dense (25 bytes a site; the compiled Model and the simulation hold voxels only), so a
  // damaged or hostile file that declares a huge lattice is refused before anything is
  // allocated.
  int64_t lattice_sites = int64_t{1} << 21;
  // Most time steps one life may take: 1e8 (about 2750 times a default 5.2 s life at e_max).
  int64_t life_steps = 100'000'000;
  // Most memory the recordings held at once may take (one life's, or all of a batch's), MB.
  // Recordings streamed to a renderer (SimOptions::on_frame) hold one frame and are not
  // limited.
  int64_t recording_mb = 1024;
};

// Throws std::invalid_argument ("robot.size: ...") when an extent is outside 1..1000 or
// nx*ny*nz exceeds limits.lattice_sites; the message names the override.
void check_lattice_size(int nx, int ny, int nz, const Limits& limits = {});

// An empty robot of the given extent: every site absent, arrays sized and zeroed. Calls
// check_lattice_size first.
RobotDef make_empty_robot(int nx, int ny, int nz, double voxel_size = 0.01,
                          const Limits& limits = {});

// Throws std::invalid_argument naming the field when arrays are mis-sized or values are
// non-finite or out of range (stiffness must be > 0 where present).
void validate(const RobotDef& robot, const Limits& limits = {});

}  // namespace plastivox
