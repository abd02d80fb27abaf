// The mutable state of one simulation, defined in one place: everything that evolves with
// time and must be saved to resume bit-identically. One list of fields (PLASTIVOX_STATE_FIELDS)
// generates the struct's members, their values at t = 0 (make_initial_state) and the table
// (kStateFields) that drives save_state/restore_state, state_hash and the Python module's
// state views, the kernels' views of its arrays and the recorded frames' channels
// (plastivox/field_table.hpp says how). Per-voxel fields are structure-of-arrays.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "plastivox/field_table.hpp"
#include "plastivox/model.hpp"

namespace plastivox {

using Quat = Eigen::Quaterniond;
using Vec2 = Eigen::Vector2d;

enum class SimStatus { kRunning, kFinished, kUnstable };

// Per bond, the deformation at the previous step, for the bond's internal damping: one array
// per component (structure-of-arrays for the batched bond kernel): [0..2] position of b
// relative to its rest place (m), [3..5] rotation vector of a, [6..8] rotation vector of b
// (rad); all in the bond axes.
using BondPrev = std::array<std::vector<double>, 9>;

// A task's running values (docs/tasks.md names each task's): what its fitness needs besides
// the last state, kept up after every step (task.hpp, TaskInfo::see).
inline constexpr int kTaskValues = 10;
using TaskValues = std::array<double, kTaskValues>;

// What the list's initial values are made of (m: the model).
namespace state_init {
template <class T>
std::vector<T> per_voxel(const Model& m, T value) {
  return std::vector<T>(static_cast<size_t>(m.n), value);
}
template <class T>
std::vector<T> per_bond(const Model& m, T value) {
  return std::vector<T>(static_cast<size_t>(m.bond_count()), value);
}
inline BondPrev bond_components(const Model& m) {
  BondPrev b;
  for (auto& component : b) component = per_bond(m, 0.0);
  return b;
}
}  // namespace state_init

// Every field of State, in order: FIELD(type, name, initial value, kernel views, shape, unit,
// axes, meaning), RECORDED for the rows every recorded frame copies (with the channel's name in
// a recorded life file and in a Python Trajectory); bond_prev is one member (its views are
// arrays of nine pointers, one per component) of nine rows. The
// kernel views are the kernels' pointers to the row's array (KernelViews, bound by
// bind_views). The size is actuated for the next step's bonds and contacts (none before the
// first step); dt follows stiffness; Voxelyze 0.9 starts every bond in its small-angle axes.
// The last six rows are what the Simulator keeps besides the physics, so that a snapshot
// resumes the score too: the signal and the controller's memory (control.hpp), and the
// watches step2 updates after every step (the floor's deepest penetration, the task's running
// values: simulator.hpp). plastivox/field_table.hpp says what the list generates.
// clang-format off
#define PLASTIVOX_STATE_FIELDS(FIELD, RECORDED, MEMBER, ROW)                                      \
  FIELD(double, time, 0.0, (), "1", "s", "-", "simulated time")                                   \
  FIELD(int64_t, steps, int64_t{0}, (), "1", "1", "-", "steps taken")                             \
  FIELD(double, dt, stable_dt(m, m.e0), (), "1", "s", "-",                                        \
        "the next step's length (follows stiffness)")                                             \
  FIELD(SimStatus, status, SimStatus::kRunning, (), "1", "-", "-",                                \
        "running, finished or unstable (SimStatus)")                                              \
  RECORDED(std::vector<Vec3>, pos, m.rest_pos, (views.voxel.pos, views.voxel_out.pos),            \
           "n x 3", "m", "world", "voxel centre", "position", "positions")                         \
  RECORDED(std::vector<Quat>, orient, state_init::per_voxel(m, Quat::Identity()),                 \
           (views.voxel.quat, views.voxel_out.quat, views.bond.quat), "n x 4", "1",               \
           "body to world", "voxel rotation (x, y, z, w)", "orientation", "orientations")         \
  FIELD(std::vector<Vec3>, lin_mom, state_init::per_voxel(m, Vec3(Vec3::Zero())),                 \
        (views.voxel.lin_mom, views.voxel_out.lin_mom, views.develop.lin_mom), "n x 3",           \
        "kg m/s", "world", "linear momentum")                                                     \
  FIELD(std::vector<Vec3>, ang_mom, state_init::per_voxel(m, Vec3(Vec3::Zero())),                 \
        (views.voxel.ang_mom, views.voxel_out.ang_mom, views.develop.ang_mom), "n x 3",           \
        "kg m^2/s", "world", "angular momentum")                                                  \
  RECORDED(std::vector<double>, stiffness, m.e0,                                                  \
           (views.voxel.stiff, views.bond.stiff, views.develop.stiffness), "n", "Pa", "-",        \
           "current Young's modulus", "stiffness", "stiffness")                                   \
  RECORDED(std::vector<double>, size, state_init::per_voxel(m, m.size),                           \
           (views.voxel.size, views.develop.size), "n", "m", "-",                                 \
           "actuated edge length for the next step", "size", "sizes")                             \
  RECORDED(std::vector<double>, stimulus, state_init::per_voxel(m, 0.0),                          \
           (views.develop.stimulus), "n", "Pa", "-", "the treatment's last stimulus",             \
           "stimulus", "stimulus")                                                                \
  FIELD(std::vector<double>, stim_integral, state_init::per_voxel(m, 0.0),                        \
        (views.develop.stim_integral), "n", "Pa s", "-",                                          \
        "integral of the stimulus since settling")                                                \
  FIELD(std::vector<double>, stim_ref, state_init::per_voxel(m, 0.0), (views.develop.stim_ref),   \
        "n", "Pa", "-", "stimulus at the end of settling (rate model)")                           \
  FIELD(bool, stim_ref_set, false, (), "1", "-", "-", "stim_ref has been taken")                  \
  FIELD(std::vector<uint8_t>, static_friction, state_init::per_voxel(m, uint8_t{0}),              \
        (views.voxel.static_friction, views.voxel_out.static_friction), "n", "-", "-",            \
        "1 while held by floor static friction")                                                  \
  MEMBER(BondPrev, bond_prev, state_init::bond_components(m),                                    \
         (views.bond.prev, views.prev_in_state))                                                  \
  ROW(bond_prev_x, bond_prev[0], "bonds", "m", "bond", "previous deformation: b's offset, x")      \
  ROW(bond_prev_y, bond_prev[1], "bonds", "m", "bond", "previous deformation: b's offset, y")      \
  ROW(bond_prev_z, bond_prev[2], "bonds", "m", "bond", "previous deformation: b's offset, z")      \
  ROW(bond_prev_rot_a_x, bond_prev[3], "bonds", "rad", "bond", "previous rotation vector of a, x") \
  ROW(bond_prev_rot_a_y, bond_prev[4], "bonds", "rad", "bond", "previous rotation vector of a, y") \
  ROW(bond_prev_rot_a_z, bond_prev[5], "bonds", "rad", "bond", "previous rotation vector of a, z") \
  ROW(bond_prev_rot_b_x, bond_prev[6], "bonds", "rad", "bond", "previous rotation vector of b, x") \
  ROW(bond_prev_rot_b_y, bond_prev[7], "bonds", "rad", "bond", "previous rotation vector of b, y") \
  ROW(bond_prev_rot_b_z, bond_prev[8], "bonds", "rad", "bond", "previous rotation vector of b, z") \
  FIELD(std::vector<uint8_t>, bond_prev_valid, state_init::per_bond(m, uint8_t{0}),               \
        (views.bond.prev_valid), "bonds", "-", "-", "1 once the previous deformation is recorded") \
  FIELD(std::vector<uint8_t>, bond_small_angle,                                                   \
        state_init::per_bond(m, static_cast<uint8_t>(m.def.bond_model == BondModel::kVoxelyze09)), \
        (views.small_angle_in_state), "bonds", "-", "-",                                          \
        "1 while the bond uses the small-angle axes")                                             \
  FIELD(Vec3, com_settled, Vec3(Vec3::Zero()), (), "3", "m", "world",                             \
        "centre of mass when settling ended")                                                     \
  FIELD(bool, settled, false, (), "1", "-", "-", "time has passed the settle time")               \
  FIELD(std::vector<double>, actuation, state_init::per_voxel(m, 0.0), (), "n", "1", "-",         \
        "actuation signal: the controller's last output, held until its next call")               \
  FIELD(std::vector<double>, control_memory,                                                      \
        std::vector<double>(controller_memory_size(m.controller, m.n), 0.0), (), "memory", "1",   \
        "-", "what the controller remembers between calls (distributed: the signals in flight)")  \
  FIELD(double, floor_deepest, 0.0, (), "1", "m", "world",                                        \
        "deepest floor penetration of any voxel after any step")                                  \
  FIELD(int32_t, floor_deep_most, int32_t{0}, (), "1", "1", "-",                                  \
        "most voxels at once deeper than half a voxel length")                                    \
  FIELD(TaskValues, task_values, TaskValues{}, (), "10", "-", "-",                                \
        "the task's running values (docs/tasks.md)")                                              \
  FIELD(std::vector<Vec2>, task_layout, state_init::per_voxel(m, Vec2(Vec2::Zero())), (),         \
        "n x 2", "m", "world",                                                                    \
        "turn: horizontal offset from the centre of mass when settling ended")
// clang-format on

struct State {
  PLASTIVOX_MEMBERS(PLASTIVOX_STATE_FIELDS)
  std::string failure;  // why the run went unstable (empty otherwise): text, not a row
};

// The state at t = 0: voxels at rest positions, E = E0, dt from E0.
State make_initial_state(const Model& model);

// The table of State's fields, generated from PLASTIVOX_STATE_FIELDS: what each holds, its
// shape, unit and axes, and where its bytes are (a recorded life's frames keep the RECORDED
// rows: kFrameFields, recording.hpp). `failure` is text that explains `status` and is not a row
// here.
using StateField = FieldRow<State>;
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
