// Import of voxcraft-sim's input: the .vxd's replacing elements are merged into the base VXA
// as voxcraft-sim merges them, then the VXA is read with voxcraft-sim's tags and defaults
// (its VXA reader, environment and kernel; docs/vxa.md, "voxcraft-sim").
#include <tinyxml2.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <numbers>
#include <string>
#include <vector>

#include "plastivox/io/atomic_file.hpp"
#include "plastivox/io/limits.hpp"
#include "plastivox/io/voxcraft.hpp"
#include "voxcraft_internal.hpp"
#include "vxa_internal.hpp"

namespace plastivox {
namespace {

using tinyxml2::XMLElement;
using namespace vxa_detail;

// The value of parent/<name>, or def when absent (voxcraft-sim's default for it).
double value(const Reader& r, const XMLElement* parent, const char* name, double def) {
  const XMLElement* e = Reader::child(parent, name);
  return e ? r.number(e) : def;
}

// Each child of <VXD> with replace="VXA.A.B" becomes the element at that path of the base
// (created if missing), under the path's last name, as voxcraft-sim's ptree merge does.
void merge(tinyxml2::XMLDocument& base, const XMLElement* vxd, const Reader& r) {
  for (const XMLElement* c = vxd->FirstChildElement(); c; c = c->NextSiblingElement()) {
    const char* replace = c->Attribute("replace");
    if (!replace) continue;  // voxcraft-sim ignores it too (e.g. a genotype)
    std::vector<std::string> path;
    std::string part;
    for (const char* p = replace;; ++p) {
      if (*p == '.' || *p == 0) {
        path.push_back(part);
        part.clear();
        if (*p == 0) break;
      } else {
        part += *p;
      }
    }
    if (path.size() < 2 || path[0] != "VXA" ||
        std::any_of(path.begin(), path.end(), [](const std::string& s) { return s.empty(); }))
      r.fail(c, std::string("replace=\"") + replace + "\" is not a path below VXA (VXA.A.B)");
    XMLElement* at = base.RootElement();
    for (size_t i = 1; i + 1 < path.size(); ++i) {
      XMLElement* next = at->FirstChildElement(path[i].c_str());
      at = next ? next : at->InsertNewChildElement(path[i].c_str());
    }
    XMLElement* copy = c->DeepClone(&base)->ToElement();
    copy->SetName(path.back().c_str());
    if (XMLElement* old = at->FirstChildElement(path.back().c_str())) {
      at->InsertAfterChild(old, copy);
      at->DeleteChild(old);
    } else {
      at->InsertEndChild(copy);
    }
  }
}

// A constant MathTree expression (no variables), as voxcraft-sim evaluates it.
double constant(const Reader& r, const XMLElement* e) {
  const std::string op = e->Name();
  if (op == "mtCONST") return r.number(e);
  if (op == "mtPI") return std::numbers::pi;
  if (op == "mtE") return std::numbers::e;
  std::vector<double> arg;
  for (const XMLElement* a = e->FirstChildElement(); a; a = a->NextSiblingElement())
    arg.push_back(constant(r, a));
  if (arg.size() == 2) {
    if (op == "mtADD") return arg[0] + arg[1];
    if (op == "mtSUB") return arg[0] - arg[1];
    if (op == "mtMUL") return arg[0] * arg[1];
    if (op == "mtDIV") return arg[0] / arg[1];
  }
  if (op == "mtVAR")
    r.fail(e, "the stop condition reads the variable '" +
                  std::string(e->GetText() ? e->GetText() : "") +
                  "': only t - T (or t > T) is supported, plastivox runs for a fixed time");
  r.fail(e, "not supported in a stop time (only mtCONST, mtPI, mtE, mtADD, mtSUB, mtMUL, mtDIV)");
}

bool is_time(const XMLElement* e);

// Fails naming the first variable other than t in the tree at e, if there is one.
void name_variables(const Reader& r, const XMLElement* e) {
  if (std::strcmp(e->Name(), "mtVAR") == 0 && !is_time(e)) constant(r, e);
  for (const XMLElement* c = e->FirstChildElement(); c; c = c->NextSiblingElement())
    name_variables(r, c);
}

bool is_time(const XMLElement* e) {
  return std::strcmp(e->Name(), "mtVAR") == 0 && e->GetText() &&
         std::string(trim(e->GetText())) == "t";
}

// The time at which <StopConditionFormula> first becomes > 0: it must be t - T, t > T or
// T < t (voxcraft-sim stops before the step at which the formula is positive).
double stop_time(const Reader& r, const XMLElement* formula) {
  const XMLElement* f = formula->FirstChildElement();
  const XMLElement* a = f ? f->FirstChildElement() : nullptr;
  const XMLElement* b = a ? a->NextSiblingElement() : nullptr;
  if (f && a && b && !b->NextSiblingElement() && !f->NextSiblingElement()) {
    const std::string op = f->Name();
    if ((op == "mtSUB" || op == "mtGREATERTHAN") && is_time(a)) return constant(r, b);
    if (op == "mtLESSTHAN" && is_time(b)) return constant(r, a);
  }
  if (f) name_variables(r, f);
  r.fail(formula, "only t - T, t > T or T < t is supported (plastivox runs for a fixed time)");
}

struct UsedMaterial {
  const XMLElement* at = nullptr;
  double e = 0, density = 0, cte = 0, mu_static = 0, mu_kinetic = 0, start = 0;
};

}  // namespace

VxaRobot parse_voxcraft(const std::string& base_text, const std::string& base_name,
                        const std::string& vxd_text, const std::string& vxd_name) {
  tinyxml2::XMLDocument doc, vxd;
  parse_xml_document(doc, base_text, base_name);
  parse_xml_document(vxd, vxd_text, vxd_name);
  if (!doc.RootElement() || std::strcmp(doc.RootElement()->Name(), "VXA") != 0)
    throw VxaError(base_name + ": <VXA>: missing (the root element is not <VXA>)");
  if (!vxd.RootElement() || std::strcmp(vxd.RootElement()->Name(), "VXD") != 0)
    throw VxaError(vxd_name + ": <VXD>: missing (the root element is not <VXD>)");
  merge(doc, vxd.RootElement(), Reader(vxd_name));
  // Errors name both files: a tag may come from either.
  Reader r(base_name + " + " + vxd_name);
  const XMLElement* vxa = doc.RootElement();
  const XMLElement* sim = Reader::child(vxa, "Simulator");
  const XMLElement* env = Reader::child(vxa, "Environment");
  const XMLElement* vxc = r.need(vxa, "VXC");

  // Features plastivox does not model: all of them in one line.
  std::vector<std::string> unsupported;
  auto feature = [&](const XMLElement* parent, const char* tag, const char* what) {
    const XMLElement* e = Reader::child(parent, tag);
    if (e && r.number(e) != 0) unsupported.push_back(std::string(what) + " (" + tag_path(e) + ")");
  };
  const XMLElement* attach = Reader::child(sim, "AttachDetach");
  feature(sim, "EnableCilia", "cilia");
  feature(sim, "EnableSignals", "signals");
  feature(sim, "SecondaryExperiment", "secondary experiment");
  feature(attach, "EnableAttach", "attachment");
  feature(attach, "EnableDetach", "detachment");
  feature(Reader::child(sim, "Features"), "VolumeEffectsEnabled", "volume effects");
  feature(Reader::child(sim, "Features"), "BlendingEnabled", "material blending");
  feature(Reader::child(sim, "EquilibriumMode"), "EquilibriumModeEnabled", "equilibrium mode");
  feature(Reader::child(env, "Boundary_Conditions"), "NumBCs", "boundary conditions");
  feature(Reader::child(env, "Fixed_Regions"), "NumFixed", "fixed regions");
  feature(Reader::child(env, "Forced_Regions"), "NumForced", "forced regions");
  if (const XMLElement* ff = Reader::child(sim, "ForceField"); ff && ff->FirstChildElement())
    unsupported.push_back("force field (" + tag_path(ff) + ")");

  // Palette: materials by position, 1-based.
  const XMLElement* pal = r.need(vxc, "Palette");
  std::vector<const XMLElement*> materials;
  for (const XMLElement* m = pal->FirstChildElement("Material"); m;
       m = m->NextSiblingElement("Material"))
    materials.push_back(m);

  // Structure: one character per site, id = char - 48, layers z bottom first, x fastest.
  const XMLElement* st = r.need(vxc, "Structure");
  const char* compression = st->Attribute("Compression");
  if (!compression || std::strcmp(compression, "ASCII_READABLE") != 0)
    r.fail(st, std::string("Compression=\"") + (compression ? compression : "") +
                   "\" is not supported (only ASCII_READABLE)");
  if (const char* v = vxc->Attribute("Version");
      v && std::strcmp(v, "0.93") != 0 && std::strcmp(v, "0.94") != 0)
    r.fail(vxc, std::string("Version=\"") + v + "\" is not supported (only 0.93, 0.94)");
  const double dim_x = value(r, st, "X_Voxels", 1), dim_y = value(r, st, "Y_Voxels", 1),
               dim_z = value(r, st, "Z_Voxels", 1);
  const int nx = r.whole(Reader::child(st, "X_Voxels"), dim_x, 1, 1000);
  const int ny = r.whole(Reader::child(st, "Y_Voxels"), dim_y, 1, 1000);
  const int nz = r.whole(Reader::child(st, "Z_Voxels"), dim_z, 1, 1000);
  const Limits limits = limits_from_environment();
  try {
    check_lattice_size(nx, ny, nz, limits);
  } catch (const std::invalid_argument& e) {
    r.fail(st, e.what());
  }
  const XMLElement* lat = r.need(vxc, "Lattice");
  const double size = r.required(lat, "Lattice_Dim");
  for (const char* one : {"X_Dim_Adj", "Y_Dim_Adj", "Z_Dim_Adj"})
    if (value(r, lat, one, 1) != 1)
      unsupported.push_back(std::string("a non-cubic lattice (") + one + ")");
  for (const char* zero : {"X_Line_Offset", "Y_Line_Offset", "X_Layer_Offset", "Y_Layer_Offset"})
    if (value(r, lat, zero, 0) != 0)
      unsupported.push_back(std::string("a non-cubic lattice (") + zero + ")");

  VxaRobot out;
  RobotDef& robot = out.robot;
  robot = make_empty_robot(nx, ny, nz, size, limits);  // size is checked by validate() below
  robot.name = std::filesystem::path(vxd_name).stem().string();
  out.material.assign(robot.sites(), 0);
  const std::vector<const XMLElement*> layers = r.layers(r.need(st, "Data"), nz);
  const size_t per_layer = static_cast<size_t>(nx) * ny;
  for (int z = 0; z < nz; ++z) {
    const char* raw = layers[z]->GetText();
    const std::string_view text = trim(raw ? raw : "");
    if (text.size() != per_layer)
      r.fail(layers[z], "layer " + std::to_string(z + 1) + " has " + std::to_string(text.size()) +
                            " characters, expected " + std::to_string(per_layer) +
                            " (X_Voxels*Y_Voxels)");
    for (size_t k = 0; k < per_layer; ++k) {
      const int id = static_cast<unsigned char>(text[k]) - 48;
      if (id < 0 || id > static_cast<int>(materials.size()))
        r.fail(layers[z], "layer " + std::to_string(z + 1) + ", site " + std::to_string(k + 1) +
                              ": material " + std::to_string(id) + " is not in the palette (1.." +
                              std::to_string(materials.size()) + ")");
      out.material[z * per_layer + k] = static_cast<uint8_t>(id);
    }
  }

  // The materials the robot uses: voxcraft-sim's tags and defaults, uniform where plastivox's
  // physics holds one value.
  std::vector<UsedMaterial> used(materials.size());
  std::vector<int> count(materials.size() + 1, 0);
  for (uint8_t id : out.material) count[id] += 1;
  const UsedMaterial* first = nullptr;
  for (size_t i = 0; i < materials.size(); ++i) {
    const XMLElement* m = materials[i];
    VxaMaterial vm;
    vm.index = static_cast<int>(i + 1);
    vm.name = Reader::child(m, "Name") && Reader::child(m, "Name")->GetText()
                  ? Reader::child(m, "Name")->GetText()
                  : "Default";
    vm.voxels = count[i + 1];
    const XMLElement* mech = Reader::child(m, "Mechanical");
    UsedMaterial u;
    u.at = m;
    u.e = value(r, mech, "Elastic_Mod", 0);
    u.density = value(r, mech, "Density", 0);
    u.cte = value(r, mech, "CTE", 0);
    u.mu_static = value(r, mech, "uStatic", 0);
    u.mu_kinetic = value(r, mech, "uDynamic", 0);
    u.start = value(r, mech, "TurnOnThermalExpansionAfterThisManySeconds", 0);
    vm.mat_type = static_cast<int>(value(r, m, "MatType", 0));
    vm.mat_model = static_cast<int>(value(r, mech, "MatModel", 0));
    vm.elastic_mod = u.e;
    vm.density = u.density;
    vm.poisson = value(r, mech, "Poissons_Ratio", 0);
    vm.cte = u.cte;
    vm.mu_static = u.mu_static;
    vm.mu_kinetic = u.mu_kinetic;
    out.palette.push_back(vm);
    used[i] = u;
    if (vm.voxels == 0) continue;
    if (vm.mat_type != 0 || Reader::child(m, "RandIndex1") || Reader::child(m, "Structure"))
      unsupported.push_back("a compound material (" + tag_path(m) + ")");
    feature(mech, "MatModel", "a nonlinear material model");
    feature(mech, "Fixed", "fixed materials");
    feature(mech, "Sticky", "sticky materials");
    feature(mech, "Cilia", "cilia");
    feature(mech, "RemoveFromSimulationAfterThisManySeconds", "voxel removal");
    if (value(r, mech, "MaterialTempPhase", 0) != 0)
      r.warn(Reader::child(mech, "MaterialTempPhase"),
             "ignored, as voxcraft-sim's kernel ignores it (phase comes from <PhaseOffset>)");
    if (!(u.e > 0)) r.fail(mech ? mech : m, "<Elastic_Mod> must be > 0 Pa for a material in use");
    if (!(u.density > 0)) r.fail(mech ? mech : m, "<Density> must be > 0 for a material in use");
    if (!first) {
      first = &used[i];
      continue;
    }
    auto same = [&](double a, double b, const char* tag) {
      if (a != b)
        r.fail(m, std::string("<") + tag + "> " + format_double(b) + " differs from " +
                      format_double(a) + " of " + tag_path(first->at) +
                      ": plastivox's physics holds one value for every voxel");
    };
    same(first->density, u.density, "Density");
    same(first->mu_static, u.mu_static, "uStatic");
    same(first->mu_kinetic, u.mu_kinetic, "uDynamic");
    same(first->start, u.start, "TurnOnThermalExpansionAfterThisManySeconds");
  }
  if (const XMLElement* fit = Reader::child(sim, "FitnessFunction");
      fit && fit->FirstChildElement())
    r.warn(fit, "not evaluated: plastivox reports its own fitness (docs/vxa.md)");
  if (!unsupported.empty()) {
    std::string all;
    for (const std::string& u : unsupported) all += (all.empty() ? "" : ", ") + u;
    throw VxaError(one_line(base_name + " + " + vxd_name +
                            ": voxcraft-sim features plastivox does not model: " + all));
  }
  if (!first) r.fail(st, "the robot has no voxels");

  // Environment: voxcraft-sim's defaults without <Environment>, its reader's with it.
  PhysicsDef& p = out.physics;
  const XMLElement* grav = Reader::child(env, "Gravity");
  p.gravity = grav ? value(r, grav, "GravAcc", -9.81) : -9.81;
  p.floor = grav ? value(r, grav, "FloorEnabled", 0) != 0 : true;
  if (grav && value(r, grav, "GravEnabled", 0) == 0 && p.gravity != 0)
    r.warn(Reader::child(grav, "GravEnabled") ? Reader::child(grav, "GravEnabled") : grav,
           "GravEnabled 0 has no effect in voxcraft-sim: gravity is GravAcc " +
               format_double(p.gravity) + " m/s^2 (set GravAcc 0 for none)");
  const XMLElement* thermal = Reader::child(env, "Thermal");
  double temp_amplitude = 0, period = 0.1;
  bool vary = false;
  if (thermal) {
    const double base = value(r, thermal, "TempBase", 25);
    temp_amplitude = Reader::child(thermal, "TempAmplitude")
                         ? value(r, thermal, "TempAmplitude", 0)
                         : value(r, thermal, "TempAmp", base) - base;
    vary = value(r, thermal, "VaryTempEnabled", 0) != 0;
    period = value(r, thermal, "TempPeriod", 0.1);
  }
  const bool actuated = vary && period > 0;  // voxcraft-sim's kernel updates temperature then
  for (size_t i = 0; i < used.size(); ++i) {
    const double a = actuated ? temp_amplitude * used[i].cte : 0.0;
    if (out.palette[i].voxels > 0 && !(a >= 0 && a < 0.9))
      r.fail(used[i].at, "TempAmplitude x <CTE> = " + format_double(a) +
                             " is not a linear actuation amplitude in [0, 0.9)");
  }

  // Simulator settings.
  const XMLElement* stop =
      Reader::child(Reader::child(sim, "StopCondition"), "StopConditionFormula");
  if (!stop)
    r.fail(sim ? sim : vxa,
           "no <StopCondition>/<StopConditionFormula>: voxcraft-sim would run 1e6 steps");
  p.duration = stop_time(r, stop);
  p.settle_time = first->start;
  if (!(p.duration >= p.settle_time && p.duration <= 1e4))
    r.fail(stop, "stop time " + format_double(p.duration) + " s must be in [" +
                     format_double(p.settle_time) +
                     " (TurnOnThermalExpansionAfterThisManySeconds), 1e4]");
  const XMLElement* damp = Reader::child(sim, "Damping");
  if (!damp)
    r.warn(sim ? sim : vxa,
           "no <Damping>: voxcraft-sim leaves its damping ratios uninitialised; using its "
           "<Damping> defaults 0.1 (bond), 1 (collision), 1 (slow)");
  p.bond_damping = value(r, damp, "BondDampingZ", 0.1);
  p.collision_damping = value(r, damp, "ColDampingZ", 1.0);
  p.global_damping = value(r, damp, "SlowDampingZ", 1.0);
  p.global_damping_rot_factor = 1.0;  // voxcraft-sim damps rotation with the same ratio
  p.self_collision = value(r, attach, "EnableCollision", 1) != 0;
  p.act_expansion = value(r, sim, "EnableExpansion", 0) != 0;
  p.density = first->density;
  p.poisson = 0;  // voxcraft-sim zeroes it without volume effects
  p.mu_static = first->mu_static;
  p.mu_kinetic = first->mu_kinetic;
  p.act_frequency = actuated ? 1.0 / period : 0.0;
  p.act_min_factor = 0;  // voxcraft-sim has no floor on the size
  p.treatment = Treatment::kNone;

  // Voxels: the material's E and amplitude; phases per site where given.
  robot.act_amplitude.assign(robot.sites(), 0.0);
  double e_lo = HUGE_VAL, e_hi = 0, amplitude_max = 0;
  for (int s = 0; s < robot.sites(); ++s) {
    const int id = out.material[s];
    if (id == 0) continue;
    const UsedMaterial& u = used[id - 1];
    robot.present[s] = 1;
    robot.stiffness[s] = u.e;
    robot.act_amplitude[s] = actuated ? temp_amplitude * u.cte : 0.0;
    e_lo = std::min(e_lo, u.e);
    e_hi = std::max(e_hi, u.e);
    amplitude_max = std::max(amplitude_max, robot.act_amplitude[s]);
  }
  if (const XMLElement* ph = Reader::child(st, "PhaseOffset")) {
    const std::vector<double> phase = r.site_values(ph, nx, ny, nz);
    for (int s = 0; s < robot.sites(); ++s) robot.phase[s] = robot.present[s] ? phase[s] : 0.0;
  }
  // The bounds only clamp E in compile() (there is no development): they hold every voxel.
  p.e_min = std::min(p.e_min, e_lo);
  p.e_max = std::max(p.e_max, e_hi);
  p.act_amplitude = amplitude_max;
  // voxcraft-sim's dt takes the stiffest bond; plastivox's the stiffest voxel.
  const XMLElement* integ = Reader::child(sim, "Integration");
  const double dt_frac = value(r, integ, "DtFrac", 0.9);
  p.dt_frac = dt_frac / voxcraft_dt_ratio(robot, robot.stiffness);
  try {
    validate(p);
  } catch (const std::invalid_argument& e) {
    r.fail(integ && std::strstr(e.what(), "dt_frac") ? Reader::child(integ, "DtFrac") : vxa,
           e.what());
  }
  try {
    validate(robot, limits);
  } catch (const std::invalid_argument& e) {
    r.fail(std::strstr(e.what(), "voxel_size") ? Reader::child(lat, "Lattice_Dim") : st, e.what());
  }
  out.warnings = std::move(r.warnings);
  return out;
}

VxaRobot read_voxcraft(const std::string& base_path, const std::string& vxd_path) {
  std::string base, vxd;
  try {
    base = read_file_bytes(base_path);
    vxd = read_file_bytes(vxd_path);
  } catch (const InputError& e) {
    throw VxaError(one_line(e.what()));
  }
  return parse_voxcraft(base, base_path, vxd, vxd_path);
}

}  // namespace plastivox
