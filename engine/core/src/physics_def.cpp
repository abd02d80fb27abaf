#include "plastivox/physics_def.hpp"

#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "plastivox/base/names.hpp"
#include "plastivox/task.hpp"

namespace plastivox {

PhysicsDef preset_gecco2018_code() {
  return PhysicsDef{};
}

PhysicsDef preset_gecco2018_paper() {
  PhysicsDef d;
  d.e_min = 1e4;
  d.e_max = 1e10;
  d.growth = GrowthModel::kRate;
  d.fitness = FitnessMode::kXY;
  return d;
}

PhysicsDef physics_preset(const std::string& name) {
  if (name == "gecco2018-code") return preset_gecco2018_code();
  if (name == "gecco2018-paper") return preset_gecco2018_paper();
  throw std::invalid_argument("physics preset '" + name +
                              "' is unknown (use gecco2018-code or gecco2018-paper)");
}

void validate(const PhysicsDef& d) {
  auto need = [](bool ok, const char* field, const char* what) {
    if (!ok) throw std::invalid_argument(std::string("physics.") + field + ": " + what);
  };
  auto fin = [](double v) { return std::isfinite(v); };
  need(d.density > 0 && fin(d.density), "density", "must be > 0 kg/m^3");
  need(d.poisson >= 0 && d.poisson < 0.5, "poisson", "must be in [0, 0.5)");
  need(d.mu_static >= 0 && fin(d.mu_static), "mu_static", "must be >= 0");
  need(d.mu_kinetic >= 0 && fin(d.mu_kinetic), "mu_kinetic", "must be >= 0");
  need(d.e_min > 0 && fin(d.e_min), "e_min", "must be > 0 Pa");
  need(d.e_max > d.e_min && fin(d.e_max), "e_max", "must be finite and > e_min");
  need(d.bond_damping >= 0 && fin(d.bond_damping), "bond_damping", "must be >= 0");
  need(d.collision_damping >= 0 && fin(d.collision_damping), "collision_damping", "must be >= 0");
  need(d.global_damping >= 0 && fin(d.global_damping), "global_damping", "must be >= 0");
  need(d.global_damping_rot_factor >= 0 && fin(d.global_damping_rot_factor),
       "global_damping_rot_factor", "must be >= 0");
  need(d.collision_exclude_hops >= 0 && d.collision_exclude_hops <= 1000, "collision_exclude_hops",
       "must be in [0, 1000] bonds");
  need(d.contact_diameter > 0 && d.contact_diameter <= 10, "contact_diameter",
       "must be in (0, 10] voxel sizes");
  // Gravity is the acceleration along z: a positive value lifts every body off the floor,
  // and the climb would be scored as locomotion.
  need(fin(d.gravity) && d.gravity <= 0, "gravity",
       "must be finite and <= 0 m/s^2 (the acceleration along z; -9.81 is Earth's)");
  need(d.dt_frac >= 1e-3 && d.dt_frac <= 1.5, "dt_frac", "must be in [0.001, 1.5]");
  need(d.act_frequency >= 0 && fin(d.act_frequency), "act_frequency", "must be >= 0 Hz");
  need(d.act_amplitude >= 0 && d.act_amplitude < 0.9, "act_amplitude", "must be in [0, 0.9)");
  need(d.act_min_factor >= 0 && d.act_min_factor <= 1, "act_min_factor", "must be in [0, 1]");
  need(d.act_max_rate >= 0 && fin(d.act_max_rate), "act_max_rate",
       "must be >= 0 per second (0: no limit)");
  need(d.settle_time >= 0 && fin(d.settle_time), "settle_time", "must be >= 0 s");
  need(d.duration >= 0 && fin(d.duration), "duration",
       "must be a number of seconds >= 0 (the life's length, at least settle_time)");
  need(d.duration >= d.settle_time && d.duration <= 1e4, "duration",
       "must be a number of seconds from settle_time (the settling before the walk is "
       "measured) to 1e4");
  need(d.max_change_per_step > 0, "max_change_per_step", "must be > 0 Pa");
  need(d.min_devo_factor >= 0 && fin(d.min_devo_factor), "min_devo_factor", "must be >= 0");
  need(d.max_speed > 0, "max_speed", "must be > 0 m/s");
  validate(d.environment);
  need(d.floor || d.environment.ground.kind == GroundKind::kNone, "environment.ground",
       "a ground needs physics.floor true (floor false: no ground at all)");
  validate_task(d);
}

namespace {

constexpr Named<Treatment> kTreatmentNames[] = {{Treatment::kNone, "none"},
                                                {Treatment::kStress, "stress"},
                                                {Treatment::kPressure, "pressure"},
                                                {Treatment::kStrain, "strain"},
                                                {Treatment::kStrainEnergy, "strain_energy"},
                                                {Treatment::kContact, "contact"},
                                                {Treatment::kKinetic, "kinetic"}};
constexpr Named<GrowthModel> kGrowthNames[] = {{GrowthModel::kIntegral, "integral"},
                                               {GrowthModel::kRate, "rate"}};
constexpr Named<FitnessMode> kFitnessNames[] = {{FitnessMode::k3D, "3d"}, {FitnessMode::kXY, "xy"}};
constexpr Named<AxialModulus> kAxialModulusNames[] = {
    {AxialModulus::kHarmonicMean, "harmonic"}, {AxialModulus::kNegativeVoxel, "negative-voxel"}};
constexpr Named<BondModel> kBondModelNames[] = {{BondModel::kExact, "exact"},
                                                {BondModel::kVoxelyze09, "voxelyze09"}};

}  // namespace

const char* to_string(Treatment t) {
  return name_in(kTreatmentNames, t);
}

const std::vector<Treatment>& all_treatments() {
  static const std::vector<Treatment> all = [] {
    std::vector<Treatment> v;
    for (const Named<Treatment>& row : kTreatmentNames) v.push_back(row.value);
    return v;
  }();
  return all;
}

std::string treatment_names() {
  return choices_in(kTreatmentNames);
}

const char* to_string(GrowthModel g) {
  return name_in(kGrowthNames, g);
}

Treatment parse_treatment(const std::string& s) {
  if (const auto t = value_in(kTreatmentNames, s)) return *t;
  throw std::invalid_argument("treatment '" + s + "' is unknown (use " + treatment_names() + ")");
}

GrowthModel parse_growth(const std::string& s) {
  if (const auto g = value_in(kGrowthNames, s)) return *g;
  throw std::invalid_argument("growth model '" + s + "' is unknown (use " +
                              choices_in(kGrowthNames) + ")");
}

namespace {

using K = PhysicsField::Kind;

PhysicsField number(const char* name, double PhysicsDef::*m,
                    bool written_when_not_default = false) {
  PhysicsField f{name, K::kNumber};
  f.number = m;
  f.written_when_not_default = written_when_not_default;
  return f;
}
PhysicsField flag(const char* name, bool PhysicsDef::*m, bool written_when_not_default = false) {
  PhysicsField f{name, K::kFlag};
  f.flag = m;
  f.written_when_not_default = written_when_not_default;
  return f;
}
PhysicsField whole(const char* name, int PhysicsDef::*m) {
  PhysicsField f{name, K::kWhole};
  f.whole = m;
  return f;
}
PhysicsField choice(const char* name, const char* (*get)(const PhysicsDef&),
                    void (*set)(PhysicsDef&, const std::string&),
                    bool written_when_not_default = false) {
  PhysicsField f{name, K::kChoice};
  f.get = get;
  f.set = set;
  f.written_when_not_default = written_when_not_default;
  return f;
}

// A choice whose names are a table's: member printed by name, parsed from one.
template <auto member, const auto& names>
PhysicsField named(const char* name) {
  return choice(
      name, [](const PhysicsDef& d) { return name_in(names, d.*member); },
      [](PhysicsDef& d, const std::string& v) {
        const auto value = value_in(names, v);
        if (!value) throw std::invalid_argument("expected " + choices_in(names, true));
        d.*member = *value;
      });
}

}  // namespace

const std::vector<PhysicsField> kPhysicsFields = {
    number("density", &PhysicsDef::density),
    number("poisson", &PhysicsDef::poisson),
    number("mu_static", &PhysicsDef::mu_static),
    number("mu_kinetic", &PhysicsDef::mu_kinetic),
    number("e_min", &PhysicsDef::e_min),
    number("e_max", &PhysicsDef::e_max),
    number("bond_damping", &PhysicsDef::bond_damping),
    number("collision_damping", &PhysicsDef::collision_damping),
    number("global_damping", &PhysicsDef::global_damping),
    number("global_damping_rot_factor", &PhysicsDef::global_damping_rot_factor),
    number("gravity", &PhysicsDef::gravity),
    flag("floor", &PhysicsDef::floor),
    flag("self_collision", &PhysicsDef::self_collision),
    whole("collision_exclude_hops", &PhysicsDef::collision_exclude_hops),
    number("contact_diameter", &PhysicsDef::contact_diameter),
    number("dt_frac", &PhysicsDef::dt_frac),
    number("act_frequency", &PhysicsDef::act_frequency),
    number("act_amplitude", &PhysicsDef::act_amplitude),
    number("act_min_factor", &PhysicsDef::act_min_factor),
    flag("act_expansion", &PhysicsDef::act_expansion, true),
    number("act_max_rate", &PhysicsDef::act_max_rate, true),
    number("settle_time", &PhysicsDef::settle_time),
    number("duration", &PhysicsDef::duration),
    choice(
        "treatment", [](const PhysicsDef& d) { return to_string(d.treatment); },
        [](PhysicsDef& d, const std::string& v) { d.treatment = parse_treatment(v); }),
    choice(
        "growth", [](const PhysicsDef& d) { return to_string(d.growth); },
        [](PhysicsDef& d, const std::string& v) { d.growth = parse_growth(v); }),
    number("max_change_per_step", &PhysicsDef::max_change_per_step),
    number("min_devo_factor", &PhysicsDef::min_devo_factor),
    named<&PhysicsDef::fitness, kFitnessNames>("fitness"),
    choice(
        "task", [](const PhysicsDef& d) { return to_string(d.task); },
        [](PhysicsDef& d, const std::string& v) { d.task = parse_task(v); }, true),
    named<&PhysicsDef::axial_modulus, kAxialModulusNames>("axial_modulus"),
    named<&PhysicsDef::bond_model, kBondModelNames>("bond_model"),
    number("max_speed", &PhysicsDef::max_speed),
    flag("sinking_invalid", &PhysicsDef::sinking_invalid, true),
};

}  // namespace plastivox
