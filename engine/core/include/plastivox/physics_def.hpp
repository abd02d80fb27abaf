// Every physical and protocol parameter of one simulation, with the GECCO-2018 defaults.
// Units are SI throughout. docs/method.md §1-§5 says where each comes from; its §11 tables them.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "plastivox/environment.hpp"

namespace plastivox {

// The stimulus development follows (docs/plasticity.md has each formula, its units and its
// size on the paper's bodies). none, stress and pressure are the paper's three treatments;
// the others are new developmental feedback loops, per voxel, in Pa (= J/m^3):
// - kStrain: the largest absolute axial strain among the voxel's bonds (dimensionless,
//   scaled by 1 Pa so that alpha keeps its units of Pa per stimulus-second);
// - kStrainEnergy: the axial elastic energy density of the voxel's share of its bonds,
//   sum of sigma * eps / 4 (each bond's energy sigma eps / 2 per unit volume, half to each end);
// - kContact: the floor's normal force on the voxel per face area (size^2), 0 off the floor:
//   the paper's "calluses in response to pressure on its feet";
// - kKinetic: kinetic energy density, (|p|^2 / 2m + |h|^2 / 2I) / L^3.
// Adding one: the enum and its name here, its formula in engine/core/src/develop_body.hpp (the one
// place that computes a stimulus), a test in tests/engine_stimuli_test.cpp.
enum class Treatment { kNone, kStress, kPressure, kStrain, kStrainEnergy, kContact, kKinetic };
// kIntegral: E = E0 + alpha * integral(stimulus dt)   (the authors' code, default)
// kRate:     E = E0 + alpha * (stimulus(t) - stimulus(settle))  (the paper's equations)
enum class GrowthModel { kIntegral, kRate };
enum class FitnessMode { k3D, kXY };
// What a life is scored on: the task (plastivox/task.hpp, docs/tasks.md, one file per task
// in engine/core/src/task_*.cpp). kWalk, the paper's locomotion, is the default.
enum class Task { kWalk, kJump, kTurn, kRough, kClimb, kSlope, kObstacles, kCarry, kPush };
// A task's parameters as given, by name (each task's table in task_<name>.cpp says its
// names, units, defaults and ranges; docs/tasks.md). A parameter not given takes its default.
using TaskParams = std::map<std::string, double>;
// Which modulus a bond's *axial* stiffness uses. Bending, torsion, damping and dt always use
// the harmonic mean. Voxelyze 0.9 (the authors' simulator) used the negative-side voxel's
// own E for the axial stress of bonds between voxels of one palette material.
enum class AxialModulus { kHarmonicMean, kNegativeVoxel };
// How bond deformation is measured. kExact: always in the chord-aligned frame, with shear
// forces that are the exact gradient of the bending energy (conserves energy and angular
// momentum). kVoxelyze09: what the authors' simulator (their Voxelyze 0.9 fork) did, rules
// and defects alike: the switch between a voxel-aligned small-angle axes and the
// chord-aligned frame, with hysteresis; its first-order turn that resets turns below ~3e-8
// rad; its rotation vectors and chord frame; its time step (docs/vxa.md).
enum class BondModel { kExact, kVoxelyze09 };

// A treatment as configs write it: a stimulus name ("contact", the shorthand) or
// {"stimulus": "contact", "law": "integral"}. The law is PhysicsDef::growth, set only when the
// object names it, so that a law equal to the physics' own leaves a config's identity alone.
struct TreatmentSpec {
  Treatment stimulus = Treatment::kNone;
  std::optional<GrowthModel> law;
};

struct PhysicsDef {
  // --- material (uniform; only E varies per voxel) ---
  double density = 1e9;     // kg/m^3 ("heavy materials": a 1 cm voxel weighs 1000 kg)
  double poisson = 0.35;    // Poisson's ratio, dimensionless
  double mu_static = 1.0;   // floor static friction coefficient
  double mu_kinetic = 0.5;  // floor kinetic friction coefficient
  double e_min = 1e5;       // lower stiffness bound, Pa
  double e_max = 1e11;      // upper stiffness bound, Pa

  // --- damping ratios (fraction of critical) ---
  double bond_damping = 1.0;       // internal, per bond
  double collision_damping = 0.8;  // floor contact (self-contact is undamped)
  double global_damping = 0.01;    // "slow" damping against absolute motion
  // Voxelyze 0.9 applies rotational slow damping ten times stronger than translational.
  double global_damping_rot_factor = 10.0;

  // --- environment ---
  double gravity = -9.81;      // m/s^2 along z
  bool floor = true;           // flat floor at z = 0
  bool self_collision = true;  // contact between voxels that are not bonded
  // Ground and obstacles beyond the flat floor (environment.hpp, docs/environments.md); the
  // default is the floor alone. A ground needs `floor` on. Not in kPhysicsFields: the robot
  // file reads and writes it as the object "environment", only when active().
  Environment environment;

  AxialModulus axial_modulus = AxialModulus::kHarmonicMean;
  BondModel bond_model = BondModel::kExact;
  // Self-collision acts between surface voxels more than this many bonds apart, when their
  // centres are closer than contact_diameter * (mean actuated size) (Voxelyze 0.9: 3, 1.5).
  int collision_exclude_hops = 3;
  double contact_diameter = 1.5;

  // --- integration ---
  double dt_frac = 0.9;  // dt = dt_frac / (2 pi sqrt(k_max / m))

  // --- actuation (docs/method.md §4) ---
  double act_frequency = 5.0;     // Hz
  double act_amplitude = 0.1447;  // linear, fraction of voxel size
  double act_min_factor = 0.1;    // floor on the size factor 1 + A xi(E) sin(...)
  // false: contraction only, the wave's positive half clipped to 0 (voxcraft-sim without
  // EnableExpansion, docs/vxa.md); true, every preset: the voxel swells and shrinks.
  bool act_expansion = true;
  // The fastest a neural controller's signal may change, per second of simulated time (0: no
  // limit). Each control call moves a voxel's signal at most act_max_rate * every * dt from
  // the one it held. The default, 2 pi 5 /s, is the steepest slope of the paper's 5 Hz sine:
  // a network may do what the sine does, no faster, so it cannot vibrate the body at the
  // step rate, which carries bodies far in simulation and in no real actuator
  // (docs/control.md, "How fast a network may act"). The sine and Python's own signals are
  // not limited.
  double act_max_rate = 31.415926535897931;

  // --- timeline ---
  double settle_time = 0.2;  // s without actuation or development; fitness starts here
  double duration = 5.2;     // s, total simulated time

  // --- development (docs/method.md §5) ---
  Treatment treatment = Treatment::kNone;
  GrowthModel growth = GrowthModel::kIntegral;
  double max_change_per_step = 1e9;  // Pa, cap on |dE| in one step
  double min_devo_factor = 1000.0;   // develop only while E > min_devo_factor * e_min

  FitnessMode fitness = FitnessMode::k3D;  // walk's distance: 3-D or horizontal only
  Task task = Task::kWalk;                 // what fitness measures (docs/tasks.md)
  // The task's parameters (in robot files: "task": {"name": ..., parameters}); empty: every
  // default. Not in kPhysicsFields' text: read and written with "task".
  TaskParams task_params;

  // --- safety --- (recording is an output option: SimOptions in simulator.hpp)
  double max_speed = 100.0;  // m/s; a voxel faster than this means the run went unstable
  // A finished life that sank through the floor (SimResult::sank) counts as unstable
  // (fitness 0), so selection never rewards sinking. On in every preset; false restores the
  // authors' rule, which scores such a life like any other (docs/engine.md, "Floor contact
  // and sinking"), for reproduction studies.
  bool sinking_invalid = true;
};

// Named presets. "gecco2018-code" (the default) is what produced the published results;
// "gecco2018-paper" uses the paper's text (E in [1e4, 1e10] Pa, rate model, xy fitness).
PhysicsDef preset_gecco2018_code();
PhysicsDef preset_gecco2018_paper();
// Throws std::invalid_argument for an unknown name.
PhysicsDef physics_preset(const std::string& name);

// Throws std::invalid_argument naming the field for impossible values.
void validate(const PhysicsDef& def);

const char* to_string(Treatment t);
const char* to_string(GrowthModel g);
Treatment parse_treatment(const std::string& s);  // throws std::invalid_argument
const std::vector<Treatment>& all_treatments();   // in the enum's order
std::string treatment_names();                    // "none, stress, pressure, ..."
GrowthModel parse_growth(const std::string& s);   // throws std::invalid_argument

// Every field of PhysicsDef, described once: its name (in robot files, evolution configs and
// the Python module's physics dicts), its kind and where it is. The robot-file reader and
// writer (plastivox/io/robot_file.hpp) go through this table, so a field added here is read
// and written everywhere. A choice field is text: get() names the value, set() parses it
// (std::invalid_argument "expected ..." otherwise).
struct PhysicsField {
  enum class Kind { kNumber, kFlag, kWhole, kChoice };
  const char* name;
  Kind kind;
  double PhysicsDef::*number = nullptr;                          // kNumber
  bool PhysicsDef::*flag = nullptr;                              // kFlag
  int PhysicsDef::*whole = nullptr;                              // kWhole
  const char* (*get)(const PhysicsDef&) = nullptr;               // kChoice
  void (*set)(PhysicsDef&, const std::string& value) = nullptr;  // kChoice
  // Written only when not the default (sinking_invalid, act_expansion: false; task: not
  // walk; act_max_rate): added after files were made with the default, which stay
  // byte-identical.
  bool written_when_not_default = false;
};
extern const std::vector<PhysicsField> kPhysicsFields;

}  // namespace plastivox
