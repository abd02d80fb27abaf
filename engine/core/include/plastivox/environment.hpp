// The world a robot lives in beyond the flat floor (docs/environments.md): a ground given as a
// height field (an array of heights, or generated: flat, ramp, step, stairs, gap, rough) and
// static obstacles (axis-aligned boxes), and free objects (passive voxel boxes the robot can
// push and carry, simulated with it: compile.cpp). Plain data, in metres, read by the physics
// (contacts: terrain.cpp), the floor health and anyone who draws the world. The default,
// an empty Environment, is the flat floor z = 0 of PhysicsDef::floor, simulated by the
// batched floor kernel with the paper's bits; any other environment takes the terrain path.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace plastivox {

// How the ground is given. kNone: the flat floor z = 0 (the default). kFlat: a level plane at
// `height`, through the terrain path (a flat ground at height 0 behaves as the floor). kHeights:
// node heights on a grid. The generators make node heights from a few numbers: kRamp, kStep,
// kStairs and kGap are profiles along +x (constant in y) sampled every `edge` metres from
// x = `at`; kRough draws each node's height from a seeded uniform distribution.
enum class GroundKind { kNone, kFlat, kHeights, kRamp, kStep, kStairs, kGap, kRough };

// A ground as a user defines it. Only the fields of its kind are read (and written to files).
struct GroundDef {
  GroundKind kind = GroundKind::kNone;
  // kHeights, kRough: node (i, j) lies at (origin[0] + i cell, origin[1] + j cell), m; the
  // height between nodes is bilinear, and past the grid the edge heights continue.
  double cell = 0;                     // node spacing, m (> 0)
  std::array<double, 2> origin{0, 0};  // node (0, 0), m
  int nx = 0, ny = 0;                  // nodes along x and y (kHeights: from the array)
  std::vector<double> heights;         // kHeights: nx * ny heights, m, x fastest
  // kFlat: the level, m. kStep: the step's height, m (negative: a step down).
  double height = 0;
  // Profiles along +x: they start at x = at (m) and are sampled every `edge` m, so a riser
  // rises over one edge.
  double at = 0;
  double edge = 0.001;
  double angle_deg = 0;  // kRamp: slope, degrees in (-80, 80), rising along +x for > 0
  double length = 0;     // kRamp: horizontal run of the slope, m; flat beyond it
  double rise = 0;       // kStairs: height of each step, m
  double run = 0;        // kStairs: tread depth, m
  int count = 0;         // kStairs: number of steps
  double width = 0;      // kGap: width at the top, m
  double depth = 0;      // kGap: depth, m
  // kRough: heights uniform in [-amplitude, 0] (a body placed at z = 0 starts on or above
  // the ground), drawn from `seed`; nx x ny nodes from `origin` every `cell`.
  double amplitude = 0;  // m
  uint64_t seed = 0;

  bool operator==(const GroundDef&) const = default;
};

// A static box of the world, m, world axes (min < max on every axis).
struct ObstacleBox {
  std::array<double, 3> min{0, 0, 0};
  std::array<double, 3> max{0, 0, 0};

  bool operator==(const ObstacleBox&) const = default;
};

// A free object: a passive box of voxels of the robot's own size and density, bonded among
// themselves, that lies in the world (docs/environments.md, "Free objects"). compile()
// appends its voxels to the model after the robot's; they are not actuated, do not develop
// and are no part of the robot's centre of mass or fitness.
struct ObjectDef {
  std::array<int, 3> voxels{1, 1, 1};  // extent along x, y, z, in voxels (each >= 1)
  std::array<double, 3> at{0, 0, 0};   // the box's lowest corner (min x, y, z), m, world axes
  // Young's modulus of its voxels, Pa; 0 (the default): the robot's stiffest congenital
  // modulus, so the object does not shorten the time step at birth.
  double stiffness = 0;

  bool operator==(const ObjectDef&) const = default;
};

struct Environment {
  GroundDef ground;
  std::vector<ObstacleBox> obstacles;
  std::vector<ObjectDef> objects;
  // False for the default (the plain floor): nothing is written to files.
  bool active() const { return terrain() || !objects.empty(); }
  // A ground or obstacles: contact then takes the terrain path (terrain.cpp) instead of the
  // floor kernel. Free objects alone keep the floor kernel.
  bool terrain() const { return ground.kind != GroundKind::kNone || !obstacles.empty(); }
  bool operator==(const Environment&) const = default;
};

// Bounds on one environment, so no file allocates without bound.
constexpr int64_t kMaxGroundNodes = int64_t{1} << 22;  // 4 Mi heights, 32 MB
constexpr int kMaxObstacles = 4096;
constexpr int kMaxObjects = 256;
constexpr int64_t kMaxObjectVoxels = int64_t{1} << 18;  // all objects together

// The ground as the contact reads it: node heights on a grid, bilinear between nodes, the
// edge heights continued past the grid (one node along an axis: constant along it).
struct HeightField {
  double x0 = 0, y0 = 0, cell = 1;  // node (0, 0) and node spacing, m
  int nx = 1, ny = 1;
  std::vector<double> h{0.0};  // nx * ny, m, x fastest

  // Height at (x, y), m, and its slope dh/dx, dh/dy (0 past the grid and along an axis of
  // one node).
  double height(double x, double y, double* gx = nullptr, double* gy = nullptr) const;
  // How far a voxel of half size r centred at (x, y, z) presses into the ground, m (> 0 in
  // contact): r less the distance from its centre to the ground's tangent plane under the
  // centre (tilt ignored, as on the floor: r - z on the plane z = 0, bit for bit). `normal`,
  // when given, receives that plane's upward unit normal (exactly (0, 0, 1) where level).
  double penetration(double x, double y, double z, double r, double* normal = nullptr) const;
};

// The height field of a ground (kNone: z = 0). Call validate first.
HeightField make_height_field(const GroundDef& ground);

// Nodes make_height_field will allocate for a ground (checked against kMaxGroundNodes before
// anything is allocated); -1 when its numbers are not valid.
int64_t ground_nodes(const GroundDef& ground);

// Voxels of the environment's free objects, all together (0 without objects).
int64_t object_voxels(const Environment& env);

// Throws std::invalid_argument naming the field ("physics.environment.ground.cell: must be
// > 0 m", "physics.environment.objects[0].voxels: ...") for a wrong or out-of-bounds
// definition.
void validate(const Environment& env);

const char* to_string(GroundKind kind);  // "none", "flat", "heightfield", "ramp", ...
GroundKind parse_ground_kind(const std::string& name);  // throws std::invalid_argument
std::string ground_kind_names();  // "flat, heightfield, ramp, step, stairs, gap or rough"

}  // namespace plastivox
