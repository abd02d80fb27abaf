// VXA export in the authors' dialect (VXA 1.0 / VXC 0.93, as their Python scripts write it).
// Every number is written with the shortest text that reads back to the same double, and the
// thermal tags are chosen so that the reader's formulas give back exactly the engine's values.
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <optional>

#include "plastivox/io/atomic_file.hpp"
#include "plastivox/io/vxa.hpp"
#include "plastivox/task.hpp"
#include "vxa_internal.hpp"

namespace plastivox {
namespace {

using namespace vxa_detail;

// Searches the doubles next to guess for one that read(x) maps exactly onto target.
template <class Read>
std::optional<double> exact_inverse(double guess, double target, Read read) {
  double lo = guess, hi = guess;
  for (int i = 0; i <= 64; ++i) {
    if (read(hi) == target) return hi;
    if (read(lo) == target) return lo;
    hi = std::nextafter(hi, HUGE_VAL);
    lo = std::nextafter(lo, -HUGE_VAL);
  }
  return std::nullopt;
}

void material(Xml& x, int id, const char* name, double e, double cte, const PhysicsDef& p) {
  x.open("Material", " ID=\"" + std::to_string(id) + "\"");
  x.tag("MatType", 0);
  x.tag("Name", name);
  x.open("Display");
  x.tag("Red", 1);
  x.tag("Green", 0);
  x.tag("Blue", 0);
  x.tag("Alpha", 1);
  x.close();
  x.open("Mechanical");
  x.tag("MatModel", 0);
  x.tag("Elastic_Mod", e);
  for (const char* zero :
       {"Plastic_Mod", "Yield_Stress", "FailModel", "Fail_Stress", "Fail_Strain"})
    x.tag(zero, 0);
  x.tag("Density", p.density);
  x.tag("Poissons_Ratio", p.poisson);
  x.tag("CTE", cte);
  x.tag("uStatic", p.mu_static);
  x.tag("uDynamic", p.mu_kinetic);
  x.close();
  x.close();
}

// One <Layer> per z with a value for every site, each followed by ", " as the authors write.
void site_layers(Xml& x, const RobotDef& r, const std::vector<double>& v) {
  for (int z = 0; z < r.nz; ++z) {
    std::string line;
    line.reserve(static_cast<size_t>(r.nx) * r.ny * 24);
    for (int y = 0; y < r.ny; ++y)
      for (int xi = 0; xi < r.nx; ++xi) {
        const double value = v[r.site(xi, y, z)];
        line += format_double(std::isfinite(value) ? value : 0.0);
        line += ", ";
      }
    x.layer(line);
  }
}

}  // namespace

std::string write_vxa(const RobotDef& robot, const PhysicsDef& p,
                      std::vector<std::string>* warnings) {
  validate(robot);
  validate(p);
  auto note = [&](const std::string& w) {
    if (warnings) warnings->push_back("write_vxa: " + w);
  };
  if (p.growth != GrowthModel::kIntegral)
    throw VxaError(
        "write_vxa: physics.growth 'rate' cannot be written: <GrowthModel> 1 is the "
        "integral model and 0 adds the integral to E every step");
  if (p.treatment != Treatment::kNone && p.treatment != Treatment::kStress &&
      p.treatment != Treatment::kPressure) {
    std::string msg = "write_vxa: physics.treatment '";
    msg += to_string(p.treatment);
    msg += "' cannot be written: the authors' simulator develops under stress or pressure only";
    throw VxaError(msg);
  }
  if (!(p.act_frequency > 0))
    throw VxaError(
        "write_vxa: physics.act_frequency 0 cannot be written (<TempPeriod> would be "
        "infinite)");
  if (!p.act_expansion)
    throw VxaError(
        "write_vxa: physics.act_expansion false (contraction only) cannot be written: the "
        "authors' simulator swells and shrinks every voxel");
  if (!robot.act_amplitude.empty())
    throw VxaError(
        "write_vxa: robot.act_amplitude (per-voxel actuation amplitudes, as voxcraft-sim's "
        "materials give them) cannot be written: the authors' dialect actuates every voxel by "
        "physics.act_amplitude and its stiffness; write voxcraft files or .json");
  if (!robot.act_scale.empty())
    throw VxaError(
        "write_vxa: robot.act_scale (per-voxel actuation scales, passive tissue) cannot be "
        "written: the authors' dialect actuates every voxel alike; write .json");
  if (p.environment.active())
    throw VxaError(
        "write_vxa: physics.environment (a ground or obstacles beyond the flat floor) cannot be "
        "written: the authors' dialect has the floor z = 0 only; write .json");
  if (p.task != Task::kWalk)
    throw VxaError(std::string("write_vxa: physics.task '") + to_string(p.task) +
                   "' cannot be written: the authors' simulator scores displacement only "
                   "(walk); write .json");
  if (!robot.controller.is_default())
    throw VxaError(std::string("write_vxa: robot.controller (") + to_string(robot.controller.kind) +
                   ") cannot be written: the authors' dialect actuates by the sine alone; write "
                   ".json");
  if (!robot.fixed_sites.empty() || !robot.loads.empty())
    throw VxaError(
        "write_vxa: robot.fixed_sites and robot.loads cannot be written (VXA "
        "boundary conditions are regions, not supported here)");
  if (p.axial_modulus != AxialModulus::kHarmonicMean)
    note("physics.axial_modulus is not carried; VXA import uses the harmonic mean");
  if (p.bond_model != BondModel::kExact)
    note("physics.bond_model is not carried; VXA import uses the exact bond model");
  if (p.global_damping_rot_factor != 10.0)
    note("physics.global_damping_rot_factor is not carried (the authors' simulator uses 10)");
  if (p.contact_diameter != 1.5)
    note("physics.contact_diameter is not carried (the authors' simulator uses 1.5)");
  if (p.act_min_factor != kMinTempFactor)
    note("physics.act_min_factor is not carried (the authors' simulator uses 0.1)");
  if (p.fitness != FitnessMode::k3D)
    note("physics.fitness is not carried (the authors' simulator reports 3-D displacement)");
  // plastivox's own rules, which VXA import sets to its defaults: a life judged under other
  // values is judged differently once exported and simulated again.
  const PhysicsDef imported;
  if (p.sinking_invalid != imported.sinking_invalid)
    note(std::string("physics.sinking_invalid ") + (p.sinking_invalid ? "true" : "false") +
         " is not carried; VXA import uses " + (imported.sinking_invalid ? "true" : "false") +
         " (a life that sinks through the floor is " +
         (imported.sinking_invalid ? "invalid" : "scored") + ")");
  if (p.max_speed != imported.max_speed)
    note("physics.max_speed " + format_double(p.max_speed) + " is not carried; VXA import uses " +
         format_double(imported.max_speed) + " m/s");
  if (p.act_max_rate != imported.act_max_rate)
    note("physics.act_max_rate " + format_double(p.act_max_rate) +
         " is not carried; VXA import uses " + format_double(imported.act_max_rate) +
         " per second");
  if (p.treatment == Treatment::kNone)
    for (int s = 0; s < robot.sites(); ++s)
      if (robot.present[s] && robot.dev_rate[s] != 0) {
        note("treatment none: robot.dev_rate is not written");
        break;
      }

  // Thermal tags: TempBase 25 and CTE 0.01 as the authors write them when some TempAmp reads
  // back exactly; otherwise TempAmp = TempBase + 1 and CTE = amplitude (exact by construction).
  double cte = kCte;
  std::optional<double> temp_amp =
      exact_inverse(kTempBase + p.act_amplitude / kCte, p.act_amplitude,
                    [](double t) { return amplitude_from_temp_amp(t, kTempBase, kCte); });
  if (!temp_amp) {
    cte = p.act_amplitude;
    temp_amp = kTempBase + 1.0;
  }
  const std::optional<double> exact_period =
      exact_inverse(1.0 / p.act_frequency, p.act_frequency, frequency_from_period);
  const double period = exact_period.value_or(1.0 / p.act_frequency);
  if (!exact_period)
    note("physics.act_frequency " + format_double(p.act_frequency) + " reads back as " +
         format_double(frequency_from_period(period)) + " (1/TempPeriod)");
  const int hops = p.collision_exclude_hops;
  const double horizon = hops == 3 ? kCollisionHorizon : (hops + 0.5) / 1.5;

  Xml x(static_cast<size_t>(robot.sites()) * 80 + 8192);
  x.text() += "<?xml version=\"1.0\" encoding=\"ISO-8859-1\"?>\n";
  x.open("VXA", " Version=\"1.0\"");
  x.open("Simulator");
  x.open("Integration");
  x.tag("Integrator", 0);
  x.tag("DtFrac", p.dt_frac);
  x.close();
  write_damping(x, p);
  x.open("Collisions");
  x.tag("SelfColEnabled", p.self_collision ? 1 : 0);
  x.tag("ColSystem", 3);
  x.tag("CollisionHorizon", horizon);
  x.close();
  x.open("Features");
  for (const char* off : {"FluidDampEnabled", "PoissonKickBackEnabled", "EnforceLatticeEnabled"})
    x.tag(off, 0);
  x.close();
  x.open("StopCondition");
  x.tag("StopConditionType", 2);
  x.tag("StopConditionValue", p.duration);
  x.tag("AfterlifeTime", 0);
  x.tag("MidLifeFreezeTime", 0);
  x.tag("InitCmTime", p.settle_time);
  x.close();
  x.block("EquilibriumMode", "EquilibriumModeEnabled", 0);
  x.open("GA");
  x.tag("WriteFitnessFile", 1);
  x.tag("FitnessFileName", "fitness.xml");
  x.tag("QhullTmpFile", "qhullInput.txt");
  x.tag("CurvaturesTmpFile", "curvatures.txt");
  x.close();
  x.close();  // Simulator

  x.open("Environment");
  x.block("Fixed_Regions", "NumFixed", 0);
  x.block("Forced_Regions", "NumForced", 0);
  x.open("Gravity");
  x.tag("GravEnabled", 1);
  x.tag("GravAcc", p.gravity);
  x.tag("FloorEnabled", p.floor ? 1 : 0);
  x.tag("FloorSlope", 0);
  x.close();
  x.open("Thermal");
  x.tag("TempEnabled", 1);
  x.tag("TempAmp", *temp_amp);
  x.tag("TempBase", kTempBase);
  x.tag("VaryTempEnabled", 1);
  x.tag("TempPeriod", period);
  x.close();
  x.tag("TimeBetweenTraces", 0);
  x.tag("StickyFloor", 0);
  x.close();  // Environment

  x.open("VXC", " Version=\"0.93\"");
  x.open("Lattice");
  x.tag("Lattice_Dim", robot.voxel_size);
  for (const char* one : {"X_Dim_Adj", "Y_Dim_Adj", "Z_Dim_Adj"}) x.tag(one, 1);
  for (const char* zero : {"X_Line_Offset", "Y_Line_Offset", "X_Layer_Offset", "Y_Layer_Offset"})
    x.tag(zero, 0);
  x.close();
  x.open("Voxel");
  x.tag("Vox_Name", "BOX");
  for (const char* one : {"X_Squeeze", "Y_Squeeze", "Z_Squeeze"}) x.tag(one, 1);
  x.close();
  // The authors' simulator numbers materials by position, so entries 1 and 2 must exist for
  // the robot's material 3 to be found; they are unused.
  x.open("Palette");
  material(x, 1, "Passive_Soft", 5e6, 0.0, p);
  material(x, 2, "Passive_Hard", 5e8, 0.0, p);
  material(x, kActiveMaterial, "Active_+", 5e6, cte, p);
  x.close();

  x.open("Structure", " Compression=\"ASCII_READABLE\"");
  x.tag("X_Voxels", robot.nx);
  x.tag("Y_Voxels", robot.ny);
  x.tag("Z_Voxels", robot.nz);
  x.open("Data");
  for (int z = 0; z < robot.nz; ++z) {
    std::string line(static_cast<size_t>(robot.nx) * robot.ny, '0');
    for (int y = 0; y < robot.ny; ++y)
      for (int xi = 0; xi < robot.nx; ++xi)
        if (robot.present[robot.site(xi, y, z)]) line[xi + robot.nx * y] = '0' + kActiveMaterial;
    x.layer(line);
  }
  x.close();
  x.open("PhaseOffset");
  site_layers(x, robot, robot.phase);
  x.close();
  x.open("Stiffness");
  x.tag("MinElasticMod", p.e_min);
  x.tag("MaxElasticMod", p.e_max);
  site_layers(x, robot, robot.stiffness);
  x.close();
  if (p.treatment != Treatment::kNone) {
    double max_rate = 10.0;  // GUI colouring only; the authors write 10
    for (int s = 0; s < robot.sites(); ++s)
      if (robot.present[s]) max_rate = std::max(max_rate, std::abs(robot.dev_rate[s]));
    x.open(p.treatment == Treatment::kStress ? "StressAdaptationRate" : "PressureAdaptationRate");
    x.tag("MinElasticMod", p.e_min);
    x.tag("MaxElasticMod", p.e_max);
    x.tag("MaxStiffnessChange", p.max_change_per_step);
    x.tag("MaxAdaptationRate", max_rate);
    x.tag("GrowthModel", 1);
    x.tag("MinDevo", p.min_devo_factor);
    site_layers(x, robot, robot.dev_rate);
    x.close();
  }
  x.close();  // Structure
  x.close();  // VXC
  x.close();  // VXA
  return std::move(x.text());
}

void write_vxa_file(const std::string& path, const RobotDef& robot, const PhysicsDef& physics,
                    std::vector<std::string>* warnings) {
  const std::string text = write_vxa(robot, physics, warnings);
  try {
    write_file_atomic(path, text);
  } catch (const InputError& e) {
    throw VxaError(e.what());
  }
}

}  // namespace plastivox
