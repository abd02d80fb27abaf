// Everything an evolutionary run knows, defined in one place: the checkpoint writes
// exactly this and a resumed run continues from it bit-identically. No random-generator
// state is needed: every draw derives from (seed, purpose, generation, id) (rng.hpp).
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "plastivox/base/hash.hpp"
#include "plastivox/evo/cma.hpp"
#include "plastivox/evo/config.hpp"
#include "plastivox/evo/genome.hpp"
#include "plastivox/evo/map_elites.hpp"
#include "plastivox/evo/phenotype.hpp"

namespace plastivox::evo {

enum class EvalStatus : uint8_t {
  kOk = 0,        // simulated to the end; fitness is the distance walked
  kInvalid = 1,   // phenotype invalid (too few voxels or NaN): not simulated
  kUnstable = 2,  // the simulation went unstable (reason recorded)
};
const char* to_string(EvalStatus s);

// Fitness given to invalid and unstable individuals: below every real fitness (distances
// are >= 0), so they lose every comparison.
constexpr double kWorstFitness = -1.0;

struct Individual {
  uint64_t id = 0;         // unique in the run, in order of creation
  int64_t parent_id = -1;  // -1 for random individuals
  int age = 0;             // AFPO age, generations
  int born = 0;            // generation of creation (0 = initial population)
  Genome genome;
  double fitness = kWorstFitness;  // voxel lengths
  EvalStatus status = EvalStatus::kInvalid;
  // Algorithm map-elites, an elite of the archive: its cell and descriptor values.
  int64_t cell = -1;
  std::vector<double> descriptors;
  // Its life scored by vertical motion (Evaluation::vertical); kept in /individuals, restored
  // on resume from the births.
  bool vertical = false;
  // Derived from the genome (recomputed on resume, never stored):
  NetworkOutputs outputs;
  Phenotype phenotype;
};

// The population after selection at the end of one generation, ascending id.
struct GenerationRecord {
  std::vector<uint64_t> id;
  std::vector<int64_t> parent_id;
  std::vector<int32_t> age;
  std::vector<double> fitness;
  std::vector<uint8_t> status;  // EvalStatus
  uint64_t champion_id = 0;
  double best_fitness = kWorstFitness;
  // Bookkeeping and provenance (not part of the content digest):
  int32_t simulated = 0;    // new individuals simulated this generation
  int32_t cache_hits = 0;   // new individuals whose phenotype was already evaluated
  double wall_seconds = 0;  // wall time of the generation, s
  // Algorithm map-elites: the archive after the generation (content).
  double qd_score = 0;  // sum over filled cells of fitness - qd_offset
  int64_t filled = 0;   // cells holding an elite
};

// One row per individual ever created, in id order.
struct BirthRecord {
  uint64_t id = 0;
  int64_t parent_id = -1;
  int32_t generation = 0;
  double fitness = kWorstFitness;
  uint8_t status = 0;     // EvalStatus
  int32_t voxels = 0;     // voxels of the phenotype
  int32_t tries = 0;      // mutation attempts (child) or draws (random individual)
  uint8_t simulated = 0;  // 1 if simulated, 0 if cached or invalid (bookkeeping)
  std::string failure;    // why the phenotype was invalid or the simulation unstable
  uint8_t sank = 0;       // 1 if its life sank through the floor (SimResult::sank); a
                          // health flag, not part of content_digest
  uint8_t vertical = 0;   // 1 if its life scored by vertical motion (Evaluation::vertical); a
                          // flag like sank, not part of content_digest
  // Algorithm map-elites: its descriptor values (NaN where not measured: an invalid body, a
  // failed life); empty otherwise.
  std::vector<double> descriptors;
};

// A new best individual: recorded when the champion changes (and at generation 0).
struct ChampionRecord {
  int32_t generation = 0;  // generation at whose end it became champion
  uint64_t id = 0;
  int64_t parent_id = -1;
  int32_t age = 0;
  double fitness = kWorstFitness;
  uint8_t status = 0;
  Genome genome;
  RobotDef phenotype;                   // present, E0, alpha, phase (lattice arrays)
  std::vector<double> final_stiffness;  // E at the end of life, Pa, lattice-sized, 0 = absent
};

// The phenotype cache: what an identical body scored before.
struct CacheEntry {
  double fitness = kWorstFitness;
  EvalStatus status = EvalStatus::kOk;
  std::string failure;
  bool sank = false;            // SimResult::sank
  DescriptorMeasures measures;  // what the life gave the MAP-Elites descriptors
  bool vertical = false;        // Evaluation::vertical (absent in older files: false)
};

struct RunState {
  EvolveConfig config;
  int generations_done = -1;              // -1: nothing yet; 0: initial population evaluated
  uint64_t next_id = 0;                   // id of the next individual created
  std::vector<Individual> population;     // ascending id
  std::vector<GenerationRecord> history;  // one per generation done, from 0
  std::vector<BirthRecord> births;        // every individual, ascending id
  std::vector<ChampionRecord> champions;  // in order of appearance
  std::map<Hash128, CacheEntry> cache;    // by phenotype hash
  CmaState cma;  // algorithm cma-es: the search distribution after the last generation
  // Algorithm map-elites: one elite per filled cell, ascending cell (Individual::cell).
  std::vector<Individual> archive;

  bool finished() const { return generations_done >= config.generations; }
};

// A 128-bit hash of all scientific content: config identity and resolved physics,
// history, births, champions, population and genomes. Excludes bookkeeping and provenance
// (cache contents, simulated/cache-hit counts, wall times, threads, dates, hosts).
Hash128 content_digest(const RunState& s);

}  // namespace plastivox::evo
