// The mutable state of one simulation, defined in one place: everything that evolves with
// time and must be saved to resume bit-identically. Per-voxel fields are structure-of-arrays.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "plastivox/model.hpp"

namespace plastivox {

using Quat = Eigen::Quaterniond;

enum class SimStatus { kRunning, kFinished, kUnstable };

struct State {
  double time = 0;    // simulated time, s
  int64_t steps = 0;  // steps taken
  double dt = 0;      // current step, s (follows stiffness)
  SimStatus status = SimStatus::kRunning;
  std::string failure;  // why the run went unstable (empty otherwise)

  // Per voxel (model.n entries).
  std::vector<Vec3> pos;                 // centre, m, world frame
  std::vector<Quat> orient;              // body-to-world rotation
  std::vector<Vec3> lin_mom;             // linear momentum, kg m/s, world frame
  std::vector<Vec3> ang_mom;             // angular momentum, kg m^2/s, world frame
  std::vector<double> stiffness;         // current Young's modulus E, Pa
  std::vector<double> size;              // actuated edge length, m, set by the actuation
                                         // stage for the next step's bonds and contacts
  std::vector<double> stimulus;          // last stimulus of the treatment, Pa (docs/plasticity.md)
  std::vector<double> stim_integral;     // integral of the stimulus since settling, Pa s
  std::vector<double> stim_ref;          // stimulus at the end of settling (rate model), Pa
  bool stim_ref_set = false;             // stim_ref has been taken
  std::vector<uint8_t> static_friction;  // 1 while held by floor static friction

  // Per bond: deformation at the previous step, for the bond's internal damping.
  // Per bond, one array per component (structure-of-arrays for the batched bond kernel):
  // [0..2] position of b relative to its rest place (m), [3..5] rotation vector of a,
  // [6..8] rotation vector of b (rad); all in the bond frame.
  std::array<std::vector<double>, 9> bond_prev;
  std::vector<uint8_t> bond_prev_valid;   // 1 once the previous deformation is recorded
  std::vector<uint8_t> bond_small_angle;  // 1 while the bond uses the small-angle frame

  Vec3 com_settled = Vec3::Zero();  // centre of mass when settling ended, m
  bool settled = false;             // true once time >= settle_time
};

// The state at t = 0: voxels at rest positions, E = E0, dt from E0.
State make_initial_state(const Model& model);

// The fields of State, described once: what each holds, its shape, unit and frame, and
// where its bytes are. The table drives state_hash, save_state/restore_state and the Python
// module's state views (a recorded life's frames keep a subset: capture_frame). Shapes: "1" one
// value, "n" per voxel, "n x 3" a vector per voxel, "n x 4" a quaternion per voxel (x, y, z, w:
// Eigen's order), "bonds" per bond. `failure` is text that explains `status` and is not a field
// here.
struct StateFieldBytes {
  const void* data = nullptr;
  size_t count = 0;        // values (doubles, bytes or integers), all components included
  size_t value_bytes = 0;  // bytes per value
  char kind = 'f';         // what a value is: 'f' floating point, 'i' signed integer (or the
                           // SimStatus enum), 'u' unsigned integer, 'b' bool
  size_t width = 1;        // values per entry: 3 for a vector, 4 for a quaternion, else 1
};
struct StateField {
  const char* name;
  const char* shape;
  const char* unit;
  const char* frame;
  const char* meaning;
  StateFieldBytes (*bytes)(const State&);
};
extern const std::vector<StateField> kStateFields;
// The row of kStateFields called `name`; std::invalid_argument for a name not in it.
const StateField& state_field(std::string_view name);

// The state as bytes, driven by kStateFields: a header, then every field in the table's
// order as its value count, its value size and its bytes, then the failure text. Restoring
// a snapshot into a State made for the same model continues the life bit-identically (the
// bytes are copied into the State's own arrays, which keep their storage). restore_state
// refuses, with std::invalid_argument naming the field and leaving the state unchanged, a
// snapshot whose counts differ from the state's (another model's) or that is damaged.
std::vector<uint8_t> save_state(const State& state);
void restore_state(State& state, const std::vector<uint8_t>& snapshot);

// 64-bit FNV-1a hash of the state, bit for bit: for every field of kStateFields in order,
// its value count and then its bytes. Every field that affects the future is in it; two
// states with the same hash continue the same way.
uint64_t state_hash(const State& state);

// Centre of mass of all voxels, m (equal masses): of a state, or of voxel centres as a
// recorded frame holds them.
Vec3 center_of_mass(const std::vector<Vec3>& pos);
inline Vec3 center_of_mass(const State& state) {
  return center_of_mass(state.pos);
}
// Centre of mass of the first `count` centres, m: of the robot, without the free objects that
// follow it (Model::robot_n), the same bits as center_of_mass(pos) when count is pos.size().
Vec3 center_of_mass(const std::vector<Vec3>& pos, int count);
inline Vec3 body_center_of_mass(const Model& model, const State& state) {
  return center_of_mass(state.pos, model.robot_n);
}

}  // namespace plastivox
