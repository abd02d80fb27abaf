// VXA import. Semantics follow the authors' simulator (notes/authors-physics.md): which tags it
// reads, its defaults for missing tags, palette materials numbered by position, per-voxel
// blocks listing a value for every lattice site.
#include <tinyxml2.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include "plastivox/base/error.hpp"  // InputError
#include "plastivox/io/atomic_file.hpp"
#include "plastivox/io/limits.hpp"
#include "plastivox/io/vxa.hpp"
#include "vxa_internal.hpp"

namespace plastivox {
namespace {

using tinyxml2::XMLElement;
using namespace vxa_detail;

struct Thermal {
  const XMLElement* at = nullptr;
  bool enabled = true, vary = false;
  double amplitude_temp = 0;  // TempAmplitude
  bool legacy = false;        // from TempAmp
  double temp_amp = 0, temp_base = kTempBase, period = 0.1;
};

void read_simulator(Reader& r, const XMLElement* vxa, PhysicsDef& p) {
  const XMLElement* sim = r.need(vxa, "Simulator");
  const XMLElement* integ = r.section(sim, "Integration");
  p.dt_frac = integ ? r.opt(integ, "DtFrac", 0.9) : 0.9;
  const XMLElement* damp = r.section(sim, "Damping");  // constructor vs ReadXML defaults
  p.bond_damping = damp ? r.opt(damp, "BondDampingZ", 0.1) : 0.1;
  p.collision_damping = damp ? r.opt(damp, "ColDampingZ", 1.0) : 1.0;
  p.global_damping = damp ? r.opt(damp, "SlowDampingZ", 1.0) : 0.001;
  const XMLElement* col = r.section(sim, "Collisions");
  p.self_collision = col && r.flag(col, "SelfColEnabled", false);
  const double horizon = col ? r.opt(col, "CollisionHorizon", kCollisionHorizon) : 3.0;
  if (!(horizon > 0) || horizon > 100) r.fail(col, "CollisionHorizon must be in (0, 100]");
  p.collision_exclude_hops = static_cast<int>(1.5 * horizon);
  if (horizon != kCollisionHorizon)
    r.warn(col, "CollisionHorizon " + format_double(horizon) + ": collisions skip voxels within " +
                    std::to_string(p.collision_exclude_hops) +
                    " bonds, but the contact-list horizon itself is not modelled");
  if (const XMLElement* f = Reader::child(sim, "Features")) {
    r.expect(f, "VolumeEffectsEnabled", 0, true, "volume effects are not modelled");
    r.expect(f, "MaxVelLimitEnabled", 0, true, "no velocity limit is modelled");
    r.expect(f, "BlendingEnabled", 0, true, "material blending is not modelled");
    const std::string unread = "the authors' simulator does not read it";
    r.expect(f, "FluidDampEnabled", 0, false, unread);
    r.expect(f, "PoissonKickBackEnabled", 0, false, unread);
    r.expect(f, "EnforceLatticeEnabled", 0, false, unread);
  }
  const XMLElement* stop = r.need(sim, "StopCondition");
  if (!Reader::child(stop, "StopConditionType") && Reader::child(stop, "StopConditionFormula"))
    r.fail(stop,
           "missing <StopConditionType> (a <StopConditionFormula> is voxcraft-sim's dialect: "
           "plastivox simulate BASE.vxa --vxd ROBOT.vxd reads it)");
  const XMLElement* type = r.need(stop, "StopConditionType");
  if (r.number(type) != 2)
    r.fail(type, format_double(r.number(type)) + " is not supported (only 2, simulated time)");
  p.duration = r.required(stop, "StopConditionValue");
  p.settle_time = r.required(stop, "InitCmTime");
  if (const XMLElement* eq = Reader::child(sim, "EquilibriumMode"))
    r.expect(eq, "EquilibriumModeEnabled", 0, true, "equilibrium mode is not modelled");
}

Thermal read_environment(Reader& r, const XMLElement* vxa, PhysicsDef& p) {
  const XMLElement* env = r.need(vxa, "Environment");
  const std::string no_bc = "boundary conditions are not modelled";
  if (const XMLElement* bc = Reader::child(env, "Boundary_Conditions"))
    r.expect(bc, "NumBCs", 0, true, no_bc);
  if (const XMLElement* fx = Reader::child(env, "Fixed_Regions"))
    r.expect(fx, "NumFixed", 0, true, no_bc);
  if (const XMLElement* fo = Reader::child(env, "Forced_Regions"))
    r.expect(fo, "NumForced", 0, true, no_bc);
  const XMLElement* grav = r.section(env, "Gravity");
  const bool grav_on = grav ? r.flag(grav, "GravEnabled", false) : true;
  const double g = grav ? r.opt(grav, "GravAcc", -9.81) : -9.81;
  p.gravity = grav_on ? g : 0.0;
  p.floor = grav ? r.flag(grav, "FloorEnabled", false) : true;
  r.expect(grav, "FloorSlope", 0, true, "only a flat floor is modelled");
  r.expect(grav, "AlterGravityHalfway", 1, true, "gravity is constant");
  r.expect(env, "FluidEnvironment", 0, true, "no fluid is modelled");
  r.expect(env, "AggregateDragCoefficient", 0, true, "no drag is modelled");
  r.expect(env, "StickyFloor", 0, false, "the authors' simulator does not read it");

  Thermal t;
  t.at = r.section(env, "Thermal");
  if (!t.at) return t;
  t.enabled = r.flag(t.at, "TempEnabled", false);
  t.temp_base = r.opt(t.at, "TempBase", kTempBase);
  if (Reader::child(t.at, "TempAmplitude")) {
    t.amplitude_temp = r.required(t.at, "TempAmplitude");
  } else if (Reader::child(t.at, "TempAmp")) {
    t.legacy = true;
    t.temp_amp = r.required(t.at, "TempAmp");
  } else {
    r.warn(t.at, "no <TempAmplitude> or <TempAmp>: no actuation");
  }
  t.vary = r.flag(t.at, "VaryTempEnabled", false);
  t.period = r.opt(t.at, "TempPeriod", 0.1);
  if (!(t.period > 0)) r.fail(r.need(t.at, "TempPeriod"), "must be > 0 s");
  return t;
}

struct Palette {
  std::vector<VxaMaterial> materials;
  std::vector<const XMLElement*> elements;
};

Palette read_palette(Reader& r, const XMLElement* vxc) {
  Palette pal;
  const XMLElement* el = r.need(vxc, "Palette");
  for (const XMLElement* m = el->FirstChildElement("Material"); m;
       m = m->NextSiblingElement("Material")) {
    VxaMaterial mat;
    mat.index = static_cast<int>(pal.materials.size()) + 1;
    if (const char* id = m->Attribute("ID")) {
      double v = 0;
      if (!parse_double(id, &v) || v != mat.index)
        r.fail(m, "is palette entry " + std::to_string(mat.index) +
                      "; the authors' simulator numbers materials by position, so ID " +
                      quoted(id) + " would be misread");
    }
    const XMLElement* name = Reader::child(m, "Name");
    mat.name = name && name->GetText() ? name->GetText() : "Default";
    const XMLElement* type = Reader::child(m, "MatType");
    mat.mat_type = type ? r.whole(type, r.number(type), 0, 3) : 0;
    if (const XMLElement* mech = Reader::child(m, "Mechanical")) {
      auto get = [&](const char* tag) {
        const XMLElement* e = Reader::child(mech, tag);
        return e ? r.number(e) : 0.0;  // the authors' default for every one of these
      };
      const XMLElement* model = Reader::child(mech, "MatModel");
      mat.mat_model = model ? r.whole(model, r.number(model), 0, 10) : 0;
      mat.elastic_mod = get("Elastic_Mod");
      mat.density = get("Density");
      mat.poisson = get("Poissons_Ratio");
      mat.cte = get("CTE");
      mat.mu_static = get("uStatic");
      mat.mu_kinetic = get("uDynamic");
    }
    pal.materials.push_back(mat);
    pal.elements.push_back(m);
  }
  if (pal.materials.empty()) r.fail(el, "has no <Material>");
  if (pal.materials.size() > 200) r.fail(el, "has more than 200 materials");
  return pal;
}

// The uniform material of the robot: every used material must agree (the engine has one).
const VxaMaterial& used_material(Reader& r, const Palette& pal) {
  const VxaMaterial* first = nullptr;
  for (size_t i = 0; i < pal.materials.size(); ++i) {
    const VxaMaterial& m = pal.materials[i];
    if (m.voxels == 0) continue;
    const XMLElement* at = pal.elements[i];
    if (m.mat_type != 0)
      r.fail(at, "<MatType> " + std::to_string(m.mat_type) +
                     " is not supported (only 0, a single material)");
    if (m.mat_model != 0)
      r.fail(at,
             "<MatModel> " + std::to_string(m.mat_model) + " is not supported (only 0, linear)");
    if (!first) {
      first = &m;
      continue;
    }
    auto same = [&](const char* tag, double a, double b) {
      if (a != b)
        r.fail(at, std::string("<") + tag + "> " + format_double(a) + " differs from material " +
                       std::to_string(first->index) + "'s " + format_double(b) +
                       "; the engine has one uniform material");
    };
    same("Density", m.density, first->density);
    same("Poissons_Ratio", m.poisson, first->poisson);
    same("uStatic", m.mu_static, first->mu_static);
    same("uDynamic", m.mu_kinetic, first->mu_kinetic);
    same("CTE", m.cte, first->cte);
    r.warn(at,
           "a second material is used: bonds between different materials use a "
           "different stress model in the authors' simulator");
  }
  return *first;
}

// Every tag of the authors' VXA dialect this reader knows: the ones it reads, and the ones
// their files carry that have no effect on a simulation (display, GA bookkeeping, failure
// and plasticity models of unused materials, controller gains). Any other tag is warned of.
// Sorted (byte order), for the binary search below; the static_assert keeps it so.
constexpr std::string_view kKnownTags[] = {
    "AfterlifeTime",
    "AggregateDragCoefficient",
    "Alpha",
    "AlterGravityHalfway",
    "BlendingEnabled",
    "Blue",
    "BondDampingZ",
    "Boundary_Conditions",
    "CMesh",
    "CTE",
    "ColDampingZ",
    "ColSystem",
    "CollisionHorizon",
    "Collisions",
    "CurvaturesTmpFile",
    "Damping",
    "Data",
    "Density",
    "Display",
    "DrawSmooth",
    "DtFrac",
    "Elastic_Mod",
    "EnforceLatticeEnabled",
    "Environment",
    "EquilibriumMode",
    "EquilibriumModeEnabled",
    "ErrorThreshold",
    "Facets",
    "FailModel",
    "Fail_Strain",
    "Fail_Stress",
    "Features",
    "FitnessFileName",
    "Fixed_Regions",
    "FloorEnabled",
    "FloorSlope",
    "FluidDampEnabled",
    "FluidEnvironment",
    "Forced_Regions",
    "GA",
    "GravAcc",
    "GravEnabled",
    "Gravity",
    "Green",
    "GrowthModel",
    "InitCmTime",
    "Integration",
    "Integrator",
    "Lattice",
    "Lattice_Dim",
    "Layer",
    "Lines",
    "MatModel",
    "MatType",
    "Material",
    "MaxANTIWINDUP",
    "MaxAdaptationRate",
    "MaxElasticMod",
    "MaxKI",
    "MaxKP",
    "MaxStiffnessChange",
    "MaxTempFactChange",
    "MaxVelLimitEnabled",
    "Mechanical",
    "MidLifeFreezeTime",
    "MinDevo",
    "MinElasticMod",
    "MinTempFact",
    "Name",
    "NumBCs",
    "NumFixed",
    "NumForced",
    "Palette",
    "PhaseOffset",
    "Plastic_Mod",
    "PoissonKickBackEnabled",
    "Poissons_Ratio",
    "PressureAdaptationRate",
    "QhullTmpFile",
    "Red",
    "SelfColEnabled",
    "Simulator",
    "SlowDampingZ",
    "StickyFloor",
    "Stiffness",
    "StopCondition",
    "StopConditionType",
    "StopConditionValue",
    "StressAdaptationRate",
    "Structure",
    "SurfMesh",
    "TempAmp",
    "TempAmplitude",
    "TempBase",
    "TempEnabled",
    "TempPeriod",
    "Thermal",
    "ThresholdTime",
    "TimeBetweenTraces",
    "VXA",
    "VXC",
    "VaryTempEnabled",
    "Vertices",
    "VolumeEffectsEnabled",
    "Vox_Name",
    "Voxel",
    "WriteFitnessFile",
    "X_Dim_Adj",
    "X_Layer_Offset",
    "X_Line_Offset",
    "X_Squeeze",
    "X_Voxels",
    "Y_Dim_Adj",
    "Y_Layer_Offset",
    "Y_Line_Offset",
    "Y_Squeeze",
    "Y_Voxels",
    "Yield_Stress",
    "Z_Dim_Adj",
    "Z_Squeeze",
    "Z_Voxels",
    "uDynamic",
    "uStatic",
};
static_assert(std::ranges::is_sorted(kKnownTags));

bool known_tag(std::string_view name) {
  return std::binary_search(std::begin(kKnownTags), std::end(kKnownTags), name);
}

// One warning per unknown tag name, at its first occurrence (document order).
void warn_unknown_tags(Reader& r, const XMLElement* e, std::set<std::string>& seen) {
  for (const XMLElement* c = e->FirstChildElement(); c; c = c->NextSiblingElement()) {
    const std::string name = c->Name();
    if (!known_tag(name) && seen.insert(name).second) r.warn(c, "unknown tag: ignored");
    warn_unknown_tags(r, c, seen);
  }
}

// The most attributes any element of the text has, counted without parsing (tinyxml2 checks
// each new attribute against the element's earlier ones: quadratic in their number). Skips
// comments, CDATA and quoted values; a count, not a validation.
int most_attributes(const std::string& xml) {
  int most = 0;
  for (size_t i = 0; i < xml.size(); ++i) {
    if (xml[i] != '<') continue;
    if (xml.compare(i, 4, "<!--") == 0) {
      i = std::min(xml.find("-->", i), xml.size());
      continue;
    }
    if (xml.compare(i, 9, "<![CDATA[") == 0) {
      i = std::min(xml.find("]]>", i), xml.size());
      continue;
    }
    int n = 0;
    char quote = 0;
    for (++i; i < xml.size() && (quote || xml[i] != '>'); ++i) {
      if (quote) {
        if (xml[i] == quote) quote = 0;
      } else if (xml[i] == '"' || xml[i] == '\'') {
        quote = xml[i];
      } else if (xml[i] == '=') {
        ++n;
      }
    }
    most = std::max(most, n);
  }
  return most;
}

// The first element named `name` at or below `e`, depth first.
const XMLElement* find_tag(const XMLElement* e, const std::string& name) {
  if (!e) return nullptr;
  if (name == e->Name()) return e;
  for (const XMLElement* c = e->FirstChildElement(); c; c = c->NextSiblingElement())
    if (const XMLElement* f = find_tag(c, name)) return f;
  return nullptr;
}

// A validate() message ("physics.density: ...", "robot.stiffness[112]: ...") in the file's
// own terms: the tag a field was read from, and for a per-voxel value its layer and position.
std::string in_file_terms(const std::string& what, const XMLElement* vxa,
                          const XMLElement* material, const XMLElement* structure,
                          const XMLElement* rate_block, const RobotDef& robot) {
  const size_t colon = what.find(": ");
  if (colon == std::string::npos) return what;
  const std::string field = what.substr(0, colon), rest = what.substr(colon + 2);
  struct Tag {
    const char* field;
    const char* tag;
    bool in_material;
  };
  static const Tag kTags[] = {
      {"physics.density", "Density", true},
      {"physics.poisson", "Poissons_Ratio", true},
      {"physics.mu_static", "uStatic", true},
      {"physics.mu_kinetic", "uDynamic", true},
      {"physics.e_min", "MinElasticMod", false},
      {"physics.e_max", "MaxElasticMod", false},
      {"physics.bond_damping", "BondDampingZ", false},
      {"physics.collision_damping", "ColDampingZ", false},
      {"physics.global_damping", "SlowDampingZ", false},
      {"physics.gravity", "GravAcc", false},
      {"physics.dt_frac", "DtFrac", false},
      {"physics.act_frequency", "TempPeriod", false},
      {"physics.act_amplitude", "TempAmplitude", false},
      {"physics.settle_time", "InitCmTime", false},
      {"physics.duration", "StopConditionValue", false},
      {"physics.max_change_per_step", "MaxStiffnessChange", false},
      {"physics.min_devo_factor", "MinDevo", false},
      {"robot.voxel_size", "Lattice_Dim", false},
      {"robot.present", "Data", false},
  };
  for (const Tag& t : kTags) {
    if (field != t.field) continue;
    const XMLElement* e = find_tag(t.in_material ? material : vxa, t.tag);
    return (e ? tag_path(e) : std::string("<") + t.tag + "> (absent: the default)") + ": " + rest;
  }
  // Per-voxel values: robot.stiffness[site] and the like.
  struct Block {
    const char* prefix;
    const XMLElement* block;
  };
  const Block blocks[] = {{"robot.stiffness[", Reader::child(structure, "Stiffness")},
                          {"robot.phase[", Reader::child(structure, "PhaseOffset")},
                          {"robot.dev_rate[", rate_block}};
  for (const Block& b : blocks) {
    const std::string prefix = b.prefix;
    if (field.rfind(prefix, 0) != 0 || field.back() != ']') continue;
    const long site = std::strtol(field.c_str() + prefix.size(), nullptr, 10);
    const long per_layer = static_cast<long>(robot.nx) * robot.ny;
    const std::string where = b.block ? tag_path(b.block) : "<Material>/<Elastic_Mod>";
    return where + ": layer " + std::to_string(site / per_layer + 1) +
           ", x=" + std::to_string(site % robot.nx) +
           " y=" + std::to_string((site % per_layer) / robot.nx) + ": " + rest;
  }
  return what;
}

}  // namespace

namespace vxa_detail {

void parse_xml_document(tinyxml2::XMLDocument& doc, const std::string& text,
                        const std::string& source_name) {
  if (const int n = most_attributes(text); n > kMaxVxaAttributes)
    throw VxaError(source_name + ": an element has " + std::to_string(n) +
                   " attributes, more than the " + std::to_string(kMaxVxaAttributes) +
                   " a VXA file can need");
  if (doc.Parse(text.data(), text.size()) != tinyxml2::XML_SUCCESS)
    throw VxaError(one_line(source_name + ": " + open_elements(text, doc.ErrorLineNum()) +
                            ": malformed XML at line " + std::to_string(doc.ErrorLineNum()) + " (" +
                            doc.ErrorName() + "; truncated file?)"));
}

}  // namespace vxa_detail

VxaRobot parse_vxa(const std::string& xml_text, const std::string& source_name) {
  Reader r(source_name);
  tinyxml2::XMLDocument doc;
  parse_xml_document(doc, xml_text, source_name);
  const XMLElement* vxa = doc.RootElement();
  if (!vxa || std::strcmp(vxa->Name(), "VXA") != 0)
    throw VxaError(source_name + ": <VXA>: missing (the root element is not <VXA>)");

  double vxa_version = 0;
  if (const char* v = vxa->Attribute("Version");
      v && parse_double(v, &vxa_version) && vxa_version > 1.1)
    r.warn(vxa, std::string("Version=\"") + v + "\" is newer than the authors' simulator (1.1)");

  std::set<std::string> unknown;
  warn_unknown_tags(r, vxa, unknown);

  VxaRobot out;
  PhysicsDef& p = out.physics;
  // Bond mechanics stay plastivox's defaults (harmonic-mean axial modulus, exact bond
  // frame): against the authors' published results for tests/data/vxa they agree at least as
  // well as imitating Voxelyze 0.9's bond details (docs/vxa.md has the comparison).
  p.act_min_factor = kMinTempFactor;
  read_simulator(r, vxa, p);
  const Thermal thermal = read_environment(r, vxa, p);

  const XMLElement* vxc = r.need(vxa, "VXC");
  const char* version = vxc->Attribute("Version");
  if (version && std::strcmp(version, "0.93") != 0 && std::strcmp(version, "0.94") != 0)
    r.fail(vxc, std::string("Version=\"") + version + "\" is not supported (only 0.93, 0.94)");
  const XMLElement* lat = r.need(vxc, "Lattice");
  const double dim = r.required(lat, "Lattice_Dim");
  const std::string square = "only a cubic lattice is modelled";
  for (const char* tag : {"X_Dim_Adj", "Y_Dim_Adj", "Z_Dim_Adj"})
    r.expect(lat, tag, 1, true, square);
  for (const char* tag : {"X_Line_Offset", "Y_Line_Offset", "X_Layer_Offset", "Y_Layer_Offset"})
    r.expect(lat, tag, 0, true, square);
  Palette pal = read_palette(r, vxc);

  const XMLElement* st = r.need(vxc, "Structure");
  const char* comp = st->Attribute("Compression");
  if (!comp || std::strcmp(comp, "ASCII_READABLE") != 0)
    r.fail(st, std::string("Compression=\"") + (comp ? comp : "") +
                   "\" is not supported (only ASCII_READABLE)");
  auto extent = [&](const char* tag) {
    const XMLElement* e = Reader::child(st, tag);
    return e ? r.whole(e, r.number(e), 1, 1000) : static_cast<int>(r.opt(st, tag, 1));
  };
  const int nx = extent("X_Voxels"), ny = extent("Y_Voxels"), nz = extent("Z_Voxels");
  if (!(dim >= kMinVoxelSize && dim <= kMaxVoxelSize))
    r.fail(r.need(lat, "Lattice_Dim"), format_double(dim) + " is not in [1e-4, 10] m");
  const Limits limits = limits_from_environment();
  try {
    check_lattice_size(nx, ny, nz, limits);
  } catch (const std::invalid_argument& e) {
    r.fail(st, "<X_Voxels>*<Y_Voxels>*<Z_Voxels>: " +
                   std::string(e.what()).substr(std::strlen("robot.size: ")));
  }
  // The declared extents must match the data before the lattice is allocated.
  const XMLElement* data = r.need(st, "Data");
  const auto data_layers = r.layers(data, nz);
  const size_t per_layer = static_cast<size_t>(nx) * ny;
  for (int z = 0; z < nz; ++z) {
    const char* raw = data_layers[z]->GetText();
    const size_t size = raw ? std::strlen(raw) : 0;
    if (size != per_layer)
      r.fail(data_layers[z], "layer " + std::to_string(z + 1) + " has " + std::to_string(size) +
                                 " characters, expected " + std::to_string(per_layer) +
                                 " (X_Voxels*Y_Voxels)");
  }
  RobotDef& robot = out.robot;
  robot = make_empty_robot(nx, ny, nz, dim, limits);
  robot.name = std::filesystem::path(source_name).stem().string();
  out.material.assign(robot.sites(), 0);

  for (int z = 0; z < nz; ++z) {
    const char* raw = data_layers[z]->GetText();
    const std::string_view text = raw ? raw : "";
    for (size_t k = 0; k < per_layer; ++k) {
      const int id = static_cast<unsigned char>(text[k]) - '0';
      if (id == 0) continue;
      if (id < 0 || id > static_cast<int>(pal.materials.size()))
        r.fail(data_layers[z], "layer " + std::to_string(z + 1) + ", x=" + std::to_string(k % nx) +
                                   " y=" + std::to_string(k / nx) + ": character '" + text[k] +
                                   "' has no palette <Material>");
      const size_t site = z * per_layer + k;
      out.material[site] = static_cast<uint8_t>(id);
      robot.present[site] = 1;
      ++pal.materials[id - 1].voxels;
    }
  }
  if (robot.voxel_count() == 0) r.fail(data, "the robot has no voxels");
  const VxaMaterial& mat = used_material(r, pal);
  p.density = mat.density;
  p.poisson = mat.poisson;
  p.mu_static = mat.mu_static;
  p.mu_kinetic = mat.mu_kinetic;

  // Actuation: the authors' simulator only checks TempEnabled (VaryTempEnabled drives the
  // material temperatures, which its actuation does not use).
  p.act_amplitude = !thermal.enabled ? 0.0
                    : thermal.legacy
                        ? amplitude_from_temp_amp(thermal.temp_amp, thermal.temp_base, mat.cte)
                        : thermal.amplitude_temp * mat.cte;
  if (p.act_amplitude < 0)
    r.fail(thermal.at, "actuation amplitude (TempAmp - TempBase) * CTE = " +
                           format_double(p.act_amplitude) + " is negative; not supported");
  if (thermal.enabled && !thermal.vary && p.act_amplitude != 0)
    r.warn(thermal.at,
           "VaryTempEnabled 0: the authors' simulator actuates anyway (it only "
           "checks TempEnabled), so the robot is imported actuated");
  p.act_frequency = frequency_from_period(thermal.period);

  if (const XMLElement* ph = Reader::child(st, "PhaseOffset"))
    robot.phase = r.site_values(ph, nx, ny, nz);
  else
    r.warn(st, "no <PhaseOffset>: every voxel actuates in phase (offset 0)");
  const XMLElement* stiff = Reader::child(st, "Stiffness");
  if (stiff) {
    p.e_min = r.required(stiff, "MinElasticMod");
    p.e_max = r.required(stiff, "MaxElasticMod");
    robot.stiffness = r.site_values(stiff, nx, ny, nz);
  } else {
    r.warn(st,
           "no <Stiffness>: E from each material's Elastic_Mod, e_min/e_max keep their "
           "defaults (the authors' simulator needs this block for its actuation)");
    for (int s = 0; s < robot.sites(); ++s)
      if (out.material[s]) robot.stiffness[s] = pal.materials[out.material[s] - 1].elastic_mod;
  }

  const XMLElement* sb = Reader::child(st, "StressAdaptationRate");
  const XMLElement* pb = Reader::child(st, "PressureAdaptationRate");
  if (sb && pb)
    r.fail(pb,
           "both StressAdaptationRate and PressureAdaptationRate are present; "
           "the engine develops under one treatment");
  if (const XMLElement* ab = sb ? sb : pb) {
    p.treatment = sb ? Treatment::kStress : Treatment::kPressure;
    if (Reader::child(ab, "MinElasticMod")) p.e_min = r.required(ab, "MinElasticMod");
    if (Reader::child(ab, "MaxElasticMod")) p.e_max = r.required(ab, "MaxElasticMod");
    const XMLElement* cap = r.need(ab, "MaxStiffnessChange");
    p.max_change_per_step = r.number(cap);
    if (!(p.max_change_per_step > 0)) r.fail(cap, "must be > 0 Pa");
    const XMLElement* growth = r.need(ab, "GrowthModel");
    const double gm = r.number(growth);
    if (gm != 1)
      r.fail(growth, format_double(gm) +
                         " is not supported: only 1 (E = E0 + rate * integral); "
                         "0 adds the integral to E every step");
    p.growth = GrowthModel::kIntegral;
    p.min_devo_factor = r.required(ab, "MinDevo");
    robot.dev_rate = r.site_values(ab, nx, ny, nz);
  } else {
    r.warn(st,
           "no <StressAdaptationRate> or <PressureAdaptationRate>: the robot does not "
           "develop (treatment none)");
  }

  try {
    validate(robot, limits);
    validate(p);
  } catch (const std::invalid_argument& e) {
    const XMLElement* material = pal.elements[static_cast<size_t>(mat.index - 1)];
    const XMLElement* rate = sb ? sb : pb;
    throw VxaError(
        one_line(source_name + ": " + in_file_terms(e.what(), vxa, material, st, rate, robot)));
  }
  out.palette = std::move(pal.materials);
  out.warnings = std::move(r.warnings);
  return out;
}

VxaRobot read_vxa_file(const std::string& path) {
  std::string text;
  try {
    text = read_file_bytes(path);
  } catch (const InputError& e) {
    throw VxaError(one_line(e.what()));
  }
  return parse_vxa(text, path);
}

}  // namespace plastivox
