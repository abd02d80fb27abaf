// Evolution config: parsing, validation, canonical forms and the commented default.
#include "plastivox/evo/config.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>

#include <nlohmann/json.hpp>

#include "plastivox/base/names.hpp"
#include "plastivox/evo/cma.hpp"
#include "plastivox/evo/cma_body.hpp"
#include "plastivox/evo/map_elites.hpp"
#include "plastivox/io/atomic_file.hpp"
#include "plastivox/io/json_input.hpp"
#include "plastivox/io/limits.hpp"
#include "plastivox/io/resolve_physics.hpp"
#include "plastivox/io/robot_file.hpp"
#include "plastivox/model.hpp"
#include "plastivox/task.hpp"

namespace plastivox::evo {
namespace {

using nlohmann::json;

using json_field::fail;
using json_field::integer;
using json_field::number;
using json_field::text;

json canonical(const EvolveConfig& c, bool with_run_control) {
  json j;
  j["format"] = "plastivox-evolve-config";
  j["version"] = kConfigVersion;
  j["seed"] = c.seed;
  j["treatment"] = to_string(c.treatment);
  j["population"] = c.population;
  j["generations"] = c.generations;
  j["lattice"] = {{"nx", c.nx}, {"ny", c.ny}, {"nz", c.nz}, {"voxel_size", c.voxel_size}};
  j["geometry"] = to_string(c.geometry);
  j["min_fill"] = c.min_fill;
  // Only when seeded: a field every run had would change every identity and digest.
  if (c.initial_population != InitialPopulation::kRandom)
    j["initial_population"] = to_string(c.initial_population);
  if (c.task != Task::kWalk) {  // likewise
    j["task"] = {{"name", to_string(c.task)}};
    for (const auto& [name, value] : c.task_params) j["task"][name] = value;
  }
  j["max_mutation_tries"] = c.max_mutation_tries;
  if (!c.controller.is_default()) {  // likewise
    json& k = j["controller"] = json_field::controller_json(c.controller);
    k.erase("weights");  // each genome's own
    if (c.controller.kind != ControllerKind::kSine) {
      k["init_sigma"] = c.controller_genes.init_sigma;
      k["mutation_rate"] = c.controller_genes.rate;
      k["mutation_sigma"] = c.controller_genes.sigma;
    }
  }
  if (c.algorithm == Algorithm::kMapElites) {  // only then: every AFPO identity and digest holds
    j["algorithm"] = to_string(c.algorithm);
    json axes = json::array();
    for (const DescriptorAxis& a : c.map_elites.axes)
      axes.push_back({{"name", to_string(a.what)}, {"bounds", {a.lo, a.hi}}, {"bins", a.bins}});
    j["map_elites"] = {{"descriptors", axes}, {"qd_offset", c.map_elites.qd_offset}};
  }
  if (c.algorithm == Algorithm::kCmaEs) {  // only then: every AFPO identity and digest holds
    j["algorithm"] = to_string(c.algorithm);
    j["genome"] = to_string(c.cma.genome);
    j["body"] = json::parse(c.cma.body_json);
    j["cma"] = {{"sigma", c.cma.sigma}, {"covariance", c.cma.covariance}};
    for (const char* afpo_only : {"lattice", "geometry", "min_fill", "max_mutation_tries"})
      j.erase(afpo_only);
  }
  j["physics"] = json::parse(c.physics_json);
  if (with_run_control) {
    j["checkpoint_every"] = c.checkpoint_every;
    j["threads"] = c.threads;
  }
  return j;
}

// The fields one algorithm reads and another would silently ignore: refused instead.
constexpr const char* kCppnOnly[] = {  // the CPPN genomes' (afpo and map-elites)
    "lattice", "geometry", "min_fill", "initial_population", "max_mutation_tries", "controller"};
constexpr const char* kCmaOnly[] = {"body", "genome", "cma"};

// Before any field is read, so a field of another algorithm is named as such.
void check_algorithm_fields(const json& j, const std::string& src) {
  const bool cma = j.contains("algorithm") && j["algorithm"] == "cma-es";
  const bool elites = j.contains("algorithm") && j["algorithm"] == "map-elites";
  if (j.contains("algorithm") && !cma && !elites && j["algorithm"] != "afpo")
    return;  // the loop refuses it
  for (const char* f : kCmaOnly)
    if (!cma && j.contains(f)) fail(src, f, "applies to algorithm cma-es only");
  if (!elites && j.contains("map_elites"))
    fail(src, "map_elites", "applies to algorithm map-elites only");
  if (elites && !j.contains("map_elites"))
    fail(src, "map_elites",
         "missing: map-elites needs its descriptors ({\"descriptors\": [{\"name\": ..., "
         "\"bounds\": [lo, hi], \"bins\": ...}, ...]})");
  for (const char* f : kCppnOnly)
    if (cma && j.contains(f))
      fail(src, f,
           "applies to algorithms afpo and map-elites only (cma-es searches a genome of its "
           "fixed body)");
}

const Descriptor kDescriptors[] = {
    Descriptor::kVoxels,      Descriptor::kFill,         Descriptor::kPi,
    Descriptor::kGamma,       Descriptor::kUpsilon,      Descriptor::kStiffness,
    Descriptor::kDevelopment, Descriptor::kFloorContact, Descriptor::kComHeight};

// "map_elites": {"descriptors": [{"name", "bounds": [lo, hi], "bins"}, ...], "qd_offset"}.
MapElitesSettings parse_map_elites(const json& v, const std::string& src) {
  MapElitesSettings m;
  if (!v.is_object()) fail(src, "map_elites", "expected an object {descriptors, qd_offset}");
  for (auto it = v.begin(); it != v.end(); ++it) {
    const std::string f = "map_elites." + it.key();
    if (it.key() == "qd_offset") {
      m.qd_offset = number(*it, src, f);
      if (!std::isfinite(m.qd_offset)) fail(src, f, "must be finite");
    } else if (it.key() != "descriptors") {
      fail(src, f, "unknown field");
    }
  }
  const std::string f = "map_elites.descriptors";
  if (!v.contains("descriptors")) fail(src, f, "missing: a list of 2 or more descriptors");
  const json& list = v["descriptors"];
  if (!list.is_array() || list.size() < 2) fail(src, f, "expected a list of 2 or more descriptors");
  std::string names;
  for (const Descriptor d : kDescriptors) {
    if (!names.empty()) names += ", ";
    names += to_string(d);
  }
  double cells = 1;
  for (size_t k = 0; k < list.size(); ++k) {
    const std::string at = f + "[" + std::to_string(k) + "]";
    const json& e = list[k];
    if (!e.is_object()) fail(src, at, "expected an object {name, bounds, bins}");
    for (auto it = e.begin(); it != e.end(); ++it)
      if (it.key() != "name" && it.key() != "bounds" && it.key() != "bins")
        fail(src, at + "." + it.key(), "unknown field");
    DescriptorAxis a;
    if (!e.contains("name")) fail(src, at + ".name", "missing (one of " + names + ")");
    const std::string name = text(e["name"], src, at + ".name");
    bool known = false;
    for (const Descriptor d : kDescriptors)
      if (name == to_string(d)) a.what = d, known = true;
    if (!known) fail(src, at + ".name", "'" + name + "' is unknown (use " + names + ")");
    for (const DescriptorAxis& b : m.axes)
      if (b.what == a.what) fail(src, at + ".name", "'" + name + "' is given twice");
    if (!e.contains("bounds"))
      fail(src, at + ".bounds",
           "missing: give [lo, hi] (docs/evolution.md, \"MAP-Elites\", lists each descriptor's "
           "range)");
    const json& b = e["bounds"];
    if (!b.is_array() || b.size() != 2 || !b[0].is_number() || !b[1].is_number())
      fail(src, at + ".bounds", "expected [lo, hi], two numbers");
    a.lo = b[0].get<double>();
    a.hi = b[1].get<double>();
    if (!(std::isfinite(a.lo) && std::isfinite(a.hi) && a.lo < a.hi))
      fail(src, at + ".bounds", "must be finite with lo < hi");
    if (!e.contains("bins")) fail(src, at + ".bins", "missing: the number of bins (>= 1)");
    a.bins = integer(e["bins"], src, at + ".bins", 1, 100000);
    cells *= a.bins;
    m.axes.push_back(a);
  }
  if (cells > kMaxArchiveCells)
    fail(src, f,
         std::to_string(static_cast<int64_t>(cells)) + " cells are too many (at most " +
             std::to_string(kMaxArchiveCells) + ")");
  return m;
}

void resolve_cma(const json& j, const std::string& src, EvolveConfig& c) {
  if (c.algorithm != Algorithm::kCmaEs) return;
  if (!j.contains("body"))
    fail(src, "body", "missing: cma-es needs a fixed body (a robot file or a results file)");
  if (!j.contains("genome")) fail(src, "genome", "missing: controller, phase or materials");
  const json& b = j["body"];
  RobotDef body;
  if (b.is_string())
    body = read_body(b.get<std::string>(), src);
  else if (b.is_object())
    body = parse_robot_json(b.dump(), src + ": body").robot;
  else
    fail(src, "body", "expected a file name or a robot object");
  // As a results file will give it back, so a resumed run sees the very same body.
  c.cma.body_json = robot_to_json(body);
  c.cma.body = parse_robot_json(c.cma.body_json, src + ": body").robot;
  c.nx = c.cma.body.nx;
  c.ny = c.cma.body.ny;
  c.nz = c.cma.body.nz;
  c.voxel_size = c.cma.body.voxel_size;
  if (c.cma.genome == GenomeKind::kController &&
      c.cma.body.controller.kind == ControllerKind::kSine)
    fail(src, "genome",
         "controller needs a body with a distributed or central controller (it runs "
         "the sine)");
  const int n = genome_dimension(c);
  if (n < 1) fail(src, "body", "has no voxels");
  c.controller_genes = ControllerGenes{};
  c.controller_genes.count = n;  // the vector a genome carries (results files store it so)
  if (!j.contains("population"))
    c.population = cma_default_lambda(n);
  else if (c.population < 2)
    fail(src, "population", "cma-es needs at least 2 samples a generation");
  if (c.cma.sigma == 0) c.cma.sigma = default_sigma(c.cma.genome);
  c.cma.separable =
      c.cma.covariance == "separable" || (c.cma.covariance == "auto" && n > kCmaFullMaxDimension);
  if (!c.cma.separable && n > kCmaFullLimit)  // n^2 numbers and an O(n^3) step a generation
    fail(src, "cma.covariance",
         "full covariance for " + std::to_string(n) + " numbers is too large (at most " +
             std::to_string(kCmaFullLimit) + "); use separable");
}

}  // namespace

const char* to_string(Algorithm a) {
  return a == Algorithm::kCmaEs ? "cma-es" : a == Algorithm::kMapElites ? "map-elites" : "afpo";
}

const char* to_string(Descriptor d) {
  static constexpr Named<Descriptor> kNames[] = {{Descriptor::kVoxels, "voxels"},
                                                 {Descriptor::kFill, "fill"},
                                                 {Descriptor::kPi, "pi"},
                                                 {Descriptor::kGamma, "gamma"},
                                                 {Descriptor::kUpsilon, "upsilon"},
                                                 {Descriptor::kStiffness, "stiffness"},
                                                 {Descriptor::kDevelopment, "development"},
                                                 {Descriptor::kFloorContact, "floor_contact"},
                                                 {Descriptor::kComHeight, "com_height"}};
  return name_in(kNames, d);
}

int64_t MapElitesSettings::cells() const {
  int64_t n = 1;
  for (const DescriptorAxis& a : axes) n *= a.bins;
  return n;
}

const char* to_string(GenomeKind g) {
  return g == GenomeKind::kController ? "controller"
         : g == GenomeKind::kPhase    ? "phase"
                                      : "materials";
}

const char* to_string(InitialPopulation p) {
  return p == InitialPopulation::kBodyPlans ? "body-plans" : "random";
}

ExpressionDef EvolveConfig::expression() const {
  ExpressionDef d;
  d.nx = nx;
  d.ny = ny;
  d.nz = nz;
  d.voxel_size = voxel_size;
  d.geometry = geometry;
  d.min_fill = min_fill;
  d.e_min = physics.e_min;
  d.e_max = physics.e_max;
  d.uses_development = treatment != Treatment::kNone;
  d.controller = controller;
  d.controller_genes = controller_genes;
  return d;
}

std::string EvolveConfig::canonical_json() const {
  return canonical(*this, true).dump();
}

std::string EvolveConfig::identity_json() const {
  return canonical(*this, false).dump();
}

EvolveConfig parse_config(const std::string& input, const std::string& src) {
  json j = parse_json_file(input, src, "plastivox-evolve-config");
  if (!j.contains("version")) fail(src, "version", "missing");
  const int version = integer(j["version"], src, "version", 0, 1 << 30);
  if (version != kConfigVersion)
    fail(src, "version",
         "unsupported version " + std::to_string(version) + " (this build reads " +
             std::to_string(kConfigVersion) + ")");

  check_algorithm_fields(j, src);
  EvolveConfig c;
  TreatmentSpec treatment;
  const int kMaxInt = std::numeric_limits<int>::max();
  for (auto it = j.begin(); it != j.end(); ++it) {
    const std::string& k = it.key();
    const json& v = *it;
    if (k == "format" || k == "version" || k == "_comment") {
      continue;
    } else if (k == "algorithm") {
      const std::string a = text(v, src, k);
      if (a == "afpo")
        c.algorithm = Algorithm::kAfpo;
      else if (a == "cma-es")
        c.algorithm = Algorithm::kCmaEs;
      else if (a == "map-elites")
        c.algorithm = Algorithm::kMapElites;
      else
        fail(src, k, "'" + a + "' is unknown (use afpo, cma-es or map-elites)");
    } else if (k == "map_elites") {
      c.map_elites = parse_map_elites(v, src);
    } else if (k == "body") {
      continue;  // read by resolve_cma, once the algorithm is known
    } else if (k == "genome") {
      const std::string g = text(v, src, k);
      if (g == "controller")
        c.cma.genome = GenomeKind::kController;
      else if (g == "phase")
        c.cma.genome = GenomeKind::kPhase;
      else if (g == "materials")
        c.cma.genome = GenomeKind::kMaterials;
      else
        fail(src, k, "'" + g + "' is unknown (use controller, phase or materials)");
    } else if (k == "cma") {
      if (!v.is_object()) fail(src, k, "expected an object {sigma, covariance}");
      for (auto ct = v.begin(); ct != v.end(); ++ct) {
        const std::string f = "cma." + ct.key();
        if (ct.key() == "sigma") {
          c.cma.sigma = number(*ct, src, f);
          if (!(c.cma.sigma > 0 && c.cma.sigma <= 1000)) fail(src, f, "must be in (0, 1000]");
        } else if (ct.key() == "covariance") {
          c.cma.covariance = text(*ct, src, f);
          if (c.cma.covariance != "auto" && c.cma.covariance != "full" &&
              c.cma.covariance != "separable")
            fail(src, f, "'" + c.cma.covariance + "' is unknown (use auto, full or separable)");
        } else {
          fail(src, f, "unknown field");
        }
      }
    } else if (k == "seed") {
      if (!v.is_number_unsigned()) fail(src, k, "expected a non-negative integer");
      c.seed = v.get<uint64_t>();
    } else if (k == "treatment") {
      treatment = json_field::treatment(v, src, k);
      c.treatment = treatment.stimulus;
    } else if (k == "task") {
      const json_field::TaskSpec t = json_field::task(v, src, k);
      c.task = t.task;
      c.task_params = t.params;
    } else if (k == "population") {
      c.population = integer(v, src, k, 1, 100000);
    } else if (k == "generations") {
      c.generations = integer(v, src, k, 0, 100000000);
    } else if (k == "lattice") {
      if (!v.is_object()) fail(src, k, "expected an object {nx, ny, nz, voxel_size}");
      for (auto lt = v.begin(); lt != v.end(); ++lt) {
        const std::string f = "lattice." + lt.key();
        if (lt.key() == "nx")
          c.nx = integer(*lt, src, f, 1, 100);
        else if (lt.key() == "ny")
          c.ny = integer(*lt, src, f, 1, 100);
        else if (lt.key() == "nz")
          c.nz = integer(*lt, src, f, 1, 100);
        else if (lt.key() == "voxel_size") {
          c.voxel_size = number(*lt, src, f);
          if (!(c.voxel_size >= kMinVoxelSize && c.voxel_size <= kMaxVoxelSize))
            fail(src, f, "must be in [1e-4, 10] m");
        } else {
          fail(src, f, "unknown field");
        }
      }
    } else if (k == "geometry") {
      try {
        c.geometry = parse_geometry_rule(text(v, src, k));
      } catch (const std::invalid_argument& e) {
        fail(src, k, e.what());
      }
    } else if (k == "min_fill") {
      c.min_fill = number(v, src, k);
      if (!(c.min_fill >= 0 && c.min_fill <= 1)) fail(src, k, "must be in [0, 1]");
    } else if (k == "initial_population") {
      const std::string p = text(v, src, k);
      if (p == "random")
        c.initial_population = InitialPopulation::kRandom;
      else if (p == "body-plans")
        c.initial_population = InitialPopulation::kBodyPlans;
      else
        fail(src, k, "'" + p + "' is unknown (use random or body-plans)");
    } else if (k == "max_mutation_tries") {
      c.max_mutation_tries = integer(v, src, k, 1, 10000000);
    } else if (k == "controller") {
      // The evolution's own fields first; the rest is a robot file's controller, less weights.
      json def = v;
      if (def.is_object()) {
        const auto take = [&](const char* name, double hi, double& out) {
          if (!def.contains(name)) return;
          const std::string f = std::string("controller.") + name;
          out = number(def[name], src, f);
          if (!(out >= 0 && out <= hi))
            fail(src, f, "must be in [0, " + std::to_string(static_cast<int>(hi)) + "]");
          def.erase(name);
        };
        take("init_sigma", 100, c.controller_genes.init_sigma);
        take("mutation_rate", 1, c.controller_genes.rate);
        take("mutation_sigma", 100, c.controller_genes.sigma);
      }
      c.controller = json_field::controller(def, src, k, false);
      c.controller_genes.count = weight_count(c.controller.kind, c.controller.hidden);
    } else if (k == "checkpoint_every") {
      c.checkpoint_every = integer(v, src, k, 1, kMaxInt);
    } else if (k == "threads") {
      c.threads = integer(v, src, k, 0, 4096);
    } else if (k == "physics") {
      if (!v.is_object()) fail(src, k, "expected an object of physics fields");
      if (v.contains("treatment"))
        fail(src, "physics.treatment", "set the treatment at the top level (\"treatment\")");
      if (v.contains("task"))
        fail(src, "physics.task", "set the task at the top level (\"task\": {\"name\": ...})");
      c.physics_json = v.dump();
    } else {
      fail(src, k, "unknown field");
    }
  }
  resolve_cma(j, src, c);
  // Physics: the preset (default gecco2018-code) with the given overrides, then the run's
  // treatment and task (docs/robot-format.md, "Resolving a run's physics"), errors naming the
  // field.
  if (treatment.law)
    c.physics_json = fold_law(c.physics_json, *treatment.law, src, "treatment.law");
  PhysicsRequest request;  // the one rule (resolve_physics.hpp), over no robot's physics
  request.fields = c.physics_json;
  request.where = src;
  request.treatment = c.treatment;
  request.task = c.task;
  request.task_params = c.task_params;
  try {  // validated with the task's parameters against a given environment (docs/tasks.md)
    c.physics = resolve_physics(preset_gecco2018_code(), request);
  } catch (const InputError& e) {
    // "<src>: physics.task.<name>: ...": a config's task is its top level's "task".
    const std::string what = e.what(), task = src + ": physics.task.";
    if (!what.starts_with(task)) throw;
    throw InputError(src + ": " + what.substr(task.size() - std::string("task.").size()));
  }
  // Evaluations never record frames (a champion can be re-simulated with recording).
  const json given = json::parse(c.physics_json);
  if (given.contains("record_fps") && given["record_fps"] != 0)
    fail(src, "physics.record_fps", "must be 0 during evolution (recording is off)");
  if (c.initial_population == InitialPopulation::kBodyPlans) {
    const std::string lattice =
        std::to_string(c.nx) + "x" + std::to_string(c.ny) + "x" + std::to_string(c.nz);
    if (std::min({c.nx, c.ny, c.nz}) < 6)  // on 5 sites the Π's gap is one site wide
      fail(src, "initial_population",
           "body-plans needs a lattice of at least 6 sites on each axis, not " + lattice);
    const Expresser ex(c.expression());
    const char* names[kBodyPlanSeedCount] = {"Pi", "Gamma", "Upsilon"};
    for (int plan = 0; plan < std::min(c.population, kBodyPlanSeedCount); ++plan) {
      Genome g;  // the other networks do not change which sites hold a voxel
      g.nets.fill(body_plan_geometry(plan));
      g.controller.assign(c.controller_genes.count, 0.0);
      const Phenotype body = ex.express(ex.evaluate(g));
      if (!body.valid)
        fail(src, "initial_population",
             std::string("the ") + names[plan] + " body is not valid on a " + lattice +
                 " lattice (" + body.invalid_reason + "); use random");
    }
  }
  try {  // every body this run makes is bounded by e_max, so none can fail later
    double e_top = c.physics.e_max;  // a cma-es body keeps its own stiffness unless searched
    for (double e : c.cma.body.stiffness) e_top = std::max(e_top, e);
    check_life_bounds(c.physics, c.voxel_size, e_top, limits_from_environment());
  } catch (const std::invalid_argument& e) {
    throw InputError(src + ": " + e.what());
  }
  return c;
}

EvolveConfig read_config_file(const std::string& path) {
  return parse_config(read_file_bytes(path), path);
}

std::string fold_law(const std::string& physics_json, GrowthModel law, const std::string& source,
                     const std::string& field) {
  json p = json::parse(physics_json);
  if (p.contains("growth")) {
    if (!p["growth"].is_string() || p["growth"].get<std::string>() != to_string(law))
      fail(source, field, "contradicts physics.growth (give the law once)");
    return physics_json;
  }
  PhysicsDef resolved = preset_gecco2018_code();
  apply_physics_json(physics_json, source, resolved);
  if (resolved.growth == law) return physics_json;
  p["growth"] = to_string(law);
  return p.dump();
}

void set_task(EvolveConfig& config, Task task) {
  PhysicsRequest request;  // a single field over the resolved physics, by the one rule
  request.task = task;
  config.physics = resolve_physics(config.physics, request);
  config.task = task;
  config.task_params = config.physics.task_params;
}

std::string resolved_physics_json(const PhysicsDef& d) {
  // Reuses the robot format's physics writer so field names match docs/robot-format.md.
  const json robot = json::parse(robot_to_json(make_empty_robot(1, 1, 1), &d));
  json p = robot["physics"];
  p["bond_model"] = d.bond_model == BondModel::kExact ? "exact" : "voxelyze09";
  p["global_damping_rot_factor"] = d.global_damping_rot_factor;
  // Recording left the physics for SimOptions; evolution never recorded, so every identity
  // and digest made before the move said 0 here and still does.
  p["record_fps"] = 0.0;
  // The selection rule for sunk lives, spelled as before it became the default: present
  // when they are invalid, absent under the authors' rule. Every file and digest made
  // before then (the authors' rule, unless it said true) keeps its meaning and its digest.
  if (d.sinking_invalid)
    p["sinking_invalid"] = true;
  else
    p.erase("sinking_invalid");
  return p.dump();
}

bool sinking_invalid_in(const std::string& resolved_physics) {
  const json p = json::parse(resolved_physics);
  return p.contains("sinking_invalid") && p["sinking_invalid"] == true;
}

std::string default_config_text() {
  const EvolveConfig c;
  json j = canonical(c, true);
  j["_comment"] = json::array(
      {"plastivox evolve configuration (docs/evolution.md). JSON has no comments: this",
       "_comment field is ignored. Defaults are the GECCO 2018 study (docs/method.md §6-7).",
       "seed: run seed (non-negative integer); the paper used seeds 1..20.",
       "task: what a life is scored on (docs/tasks.md), e.g. {\"name\": \"climb\", \"rise\": 1}",
       "  (its parameters are optional): walk (the paper's locomotion; the default, so absent",
       "  above) | jump | turn | rough | climb | slope | obstacles | carry | push.",
       "treatment: what development follows: none | stress | pressure (the paper's) | strain |",
       "  strain_energy | contact | kinetic (docs/plasticity.md), or with its law:",
       "  {\"stimulus\": \"contact\", \"law\": \"integral\" | \"rate\"} (the law is "
       "physics.growth).",
       "population: survivors per generation (24). Each generation makes one child per",
       "  survivor plus one random newcomer (49 candidates), then AFPO selects back down.",
       "generations: AFPO generations after the initial random population (5000).",
       "lattice: workspace extent in sites and voxel edge length in m (10x10x10, 0.01).",
       "geometry: largest-component (the paper) | keep-all (the authors' code).",
       "min_fill: a valid body fills at least this fraction of the lattice (0.2).",
       "initial_population: random (the paper) | body-plans: generation 0 also holds one",
       "  hand-built body of each of the paper's plans, Pi, Gamma, Upsilon (docs/evolution.md).",
       "max_mutation_tries: attempts to make a changed, valid child (1500).",
       "controller: the robots' controller, evolved with the body (docs/evolution.md), e.g.",
       "  {\"kind\": \"distributed\", \"hidden\": 4, \"every\": 1, \"init_sigma\": 1,",
       "  \"mutation_rate\": 0.1, \"mutation_sigma\": 0.3}; kind sine | distributed |",
       "  central (docs/control.md). Absent: the sine, every step.",
       "checkpoint_every: generations between checkpoints of the results file (1).",
       "threads: evaluation threads, 0 = all cores (--threads overrides; results do not",
       "  depend on it).",
       "algorithm: afpo (the default, so absent above) | cma-es: CMA-ES on one part of a fixed",
       "  body, with \"body\" (a robot file, or a results file whose champion it takes),",
       "  \"genome\" (controller | phase | materials) and optionally \"cma\": {\"sigma\": ...,",
       "  \"covariance\": auto | full | separable}; population is then the samples a",
       "  generation (default 4 + 3 ln n). docs/evolution.md, \"Algorithms\".",
       "  | map-elites: an archive over descriptors, with \"map_elites\": {\"descriptors\":",
       "  [{\"name\": \"fill\", \"bounds\": [0.2, 1], \"bins\": 8}, {\"name\":",
       "  \"floor_contact\", \"bounds\": [0, 1], \"bins\": 8}], \"qd_offset\": 0};",
       "  population is then the children a generation (docs/evolution.md, \"MAP-Elites\").",
       "physics: a preset (gecco2018-code | gecco2018-paper) plus any PhysicsDef field to",
       "  override, e.g. {\"preset\": \"gecco2018-code\", \"duration\": 5.2}; the",
       "  treatment is set above, not here."});
  return j.dump(2) + "\n";
}

}  // namespace plastivox::evo
