// The configuration of one evolutionary run: JSON, format "plastivox-evolve-config",
// version 1 (docs/evolution.md). Every field has a default; every field present is
// validated, and an error names it ("run.json: population: must be an integer >= 1").
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "plastivox/evo/phenotype.hpp"
#include "plastivox/physics_def.hpp"

namespace plastivox::evo {

constexpr int kConfigVersion = 1;

// How generation 0 is made: all random (the paper), or random apart from one individual of
// each body plan Π, Γ, Υ whose geometry network is hand-built (genome.hpp,
// body_plan_geometry) and whose other three networks are random.
enum class InitialPopulation { kRandom, kBodyPlans };
const char* to_string(InitialPopulation p);  // "random", "body-plans"

// The search (docs/evolution.md, "Algorithms"): AFPO over CPPN genomes (the paper), CMA-ES
// over a vector that sets one part of a fixed body, or MAP-Elites over CPPN genomes in a grid
// of descriptors. Adding one: a value here, its name in to_string/parse_config, and its step in
// Evolver::step().
enum class Algorithm { kAfpo, kCmaEs, kMapElites };
const char* to_string(Algorithm a);  // "afpo", "cma-es", "map-elites"

// What a CMA-ES vector sets on the fixed body (cma_body.hpp).
enum class GenomeKind { kController, kPhase, kMaterials };
const char* to_string(GenomeKind g);  // "controller", "phase", "materials"

// A CMA-ES run's own fields (algorithm cma-es; config "body", "genome", "cma").
struct CmaSettings {
  GenomeKind genome = GenomeKind::kController;
  RobotDef body;                    // the fixed body; its own values are where the search starts
  std::string body_json;            // the body as a robot file's JSON: the identity holds it whole
  double sigma = 0;                 // initial step size (0 until parsed: the genome's default)
  bool separable = false;           // sep-CMA-ES (diagonal C): by the dimension rule, or as asked
  std::string covariance = "auto";  // as given: auto | full | separable
};

// What a MAP-Elites archive is a grid over (docs/evolution.md, "MAP-Elites"): of the body
// (voxels, fill, the Π/Γ/Υ template scores, mean congenital stiffness) or of its life
// (development, floor contact, centre-of-mass height). map_elites.hpp computes them.
enum class Descriptor {
  kVoxels,
  kFill,
  kPi,
  kGamma,
  kUpsilon,
  kStiffness,
  kDevelopment,
  kFloorContact,
  kComHeight
};
const char* to_string(Descriptor d);  // "voxels", "fill", "pi", ..., "com_height"

// One axis of the grid: `bins` equal bins over [lo, hi]; values outside go to the end bins.
struct DescriptorAxis {
  Descriptor what = Descriptor::kFill;
  double lo = 0, hi = 1;
  int bins = 1;
};

// A MAP-Elites run's own fields (algorithm map-elites; config "map_elites").
struct MapElitesSettings {
  std::vector<DescriptorAxis> axes;  // 2 or more, the first varying slowest in a cell index
  double qd_offset = 0;              // QD score: sum over filled cells of fitness - qd_offset
  int64_t cells() const;             // product of the bins
};

struct EvolveConfig {
  Algorithm algorithm = Algorithm::kAfpo;
  CmaSettings cma;               // algorithm cma-es only
  MapElitesSettings map_elites;  // algorithm map-elites only
  uint64_t seed = 1;             // run seed; every random draw derives from it
  Treatment treatment = Treatment::kNone;
  Task task = Task::kWalk;        // what lives are scored on (plastivox/task.hpp); physics.task
  TaskParams task_params;         // its parameters as given (physics.task_params)
  int population = 24;            // survivors per generation
  int generations = 5000;         // AFPO generations after the initial population
  int nx = 10, ny = 10, nz = 10;  // lattice extent, sites
  double voxel_size = 0.01;       // m
  GeometryRule geometry = GeometryRule::kLargestComponent;
  double min_fill = 0.2;  // fraction of sites a valid body fills
  InitialPopulation initial_population = InitialPopulation::kRandom;
  int max_mutation_tries = 1500;  // attempts per child (and draws per newcomer)
  // The robots' controller (its weights come from each genome; docs/evolution.md, "Evolving a
  // controller") and the draws and mutation of those weights (count set from the controller).
  ControllerDef controller;
  ControllerGenes controller_genes;
  int checkpoint_every = 1;  // generations between checkpoints (and at the end)
  int threads = 0;           // evaluation threads; 0 = all cores
  std::string physics_json = R"({"preset":"gecco2018-code"})";  // as given, canonical
  PhysicsDef physics;  // resolved from physics_json, treatment and task applied

  ExpressionDef expression() const;  // lattice, geometry rule, mapping range, C3 use
  // Canonical JSON of every field (sorted keys, no comment).
  std::string canonical_json() const;
  // canonical_json() without the fields that cannot change results (threads,
  // checkpoint_every): two runs with equal identity produce identical science.
  std::string identity_json() const;
};

// Parses and validates; throws plastivox::InputError ("<source>: <field>: <problem>").
EvolveConfig parse_config(const std::string& text, const std::string& source);
EvolveConfig read_config_file(const std::string& path);

// The complete default configuration as JSON with a "_comment" block explaining each
// field; parse_config() accepts it unchanged.
std::string default_config_text();

// A treatment's law folded into a physics override object (JSON text), so that a law is
// part of the physics like any other field: adds "growth" only when the law differs from what
// the object resolves to (a law equal to the physics' own leaves the text, and so every
// identity and digest, as it was). Throws InputError "<source>: <field>: ..." when the object
// sets a different growth itself.
std::string fold_law(const std::string& physics_json, GrowthModel law, const std::string& source,
                     const std::string& field);

// Sets the task of a parsed config (its identity and its physics alike), as evolve --task;
// another task than the config's drops the config's task parameters.
void set_task(EvolveConfig& config, Task task);

// All physics fields of def as a canonical JSON object (provenance: what was simulated).
std::string resolved_physics_json(const PhysicsDef& def);
// The rule for sunk lives that text (a JSON object resolved_physics_json wrote) spells:
// "sinking_invalid": true, or absent for the authors' rule, the only rule of files written
// before the other became the default.
bool sinking_invalid_in(const std::string& resolved_physics);

}  // namespace plastivox::evo
