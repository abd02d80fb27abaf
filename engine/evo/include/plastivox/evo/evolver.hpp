// The generation loop: one call of step() runs one generation of the config's algorithm,
// AFPO (below), CMA-ES (docs/evolution.md; new individuals sampled from the search
// distribution, evaluated by the same steps 4a-4d, the distribution updated from them) or
// MAP-Elites (children of elites drawn from the archive, evaluated by the same steps, each
// offered to its cell).
//
// The AFPO loop (docs/method.md §7):
//
// Generation 0 creates `population` random individuals. Every later generation:
//   1. every survivor's age += 1;
//   2. each survivor (ascending id) makes one mutated child that inherits its age;
//   3. one random newcomer of age 0 is added (ids: children first, then the newcomer);
//   4. new individuals are expressed and evaluated: invalid phenotypes and unstable
//      simulations get kWorstFitness; a phenotype seen before takes its cached result;
//      identical new phenotypes within a generation are simulated once;
//   5. afpo_select() keeps `population` of the survivors and new individuals.
// Steps 2-4 run on a thread pool; everything that orders or reduces runs serially by id,
// so the result is bit-identical for any number of threads.
#pragma once

#include <chrono>
#include <functional>
#include <optional>
#include <vector>

#include "plastivox/evo/run_state.hpp"

namespace plastivox::evo {

struct GenerationStats {
  int generation = 0;
  int created = 0;              // new individuals
  int simulated = 0;            // of which simulated
  int cache_hits = 0;           // of which served by the cache
  int invalid = 0;              // of which invalid phenotypes
  int unstable = 0;             // of which unstable simulations
  int sank = 0;                 // of which simulated lives that sank through the floor
  double wall_seconds = 0;      // whole generation
  double sim_wall_seconds = 0;  // wall time of the parallel simulation phase
  double sim_cpu_seconds = 0;   // summed simulation time over threads
  double best_fitness = kWorstFitness;
  uint64_t champion_id = 0;
};

// Outcome of simulating one phenotype.
struct Evaluation {
  double fitness = kWorstFitness;
  EvalStatus status = EvalStatus::kInvalid;
  std::string failure;
  bool sank = false;  // SimResult::sank: the body ended below the floor
  // The rules' vertical_exploit (plastivox/rules/life_rules.hpp): a finished life that scored
  // by rising or falling under walk's 3-D fitness. No archive admits it, and it is crowned only
  // when no life counts (docs/evolution.md, "Flagged lives").
  bool vertical = false;
  // Pa, lattice-sized, 0 where absent; empty when an outside fitness gave none (the
  // evolver then simulates a champion again for it).
  std::vector<double> final_stiffness;
  // The life's measures for MAP-Elites' descriptors (map_elites.hpp); not measured when an
  // outside fitness gave a number alone (the evolver then simulates the life for them).
  DescriptorMeasures measures;
  double wall_seconds = 0;
  // Python's ask/tell (docs/python.md): the genome the caller set for this body in place of
  // the one it was handed; the evolver expresses it, and this evaluation is its body's
  // (AFPO and MAP-Elites; validated by the caller).
  std::optional<Genome> edited;
};
// Simulates a valid phenotype under physics (thread-safe).
Evaluation evaluate_phenotype(const Phenotype& p, const PhysicsDef& physics);

// Time steps a valid phenotype's life is expected to take: duration over the time step of its
// stiffest voxel at birth (development may change it). With voxels, the cost that schedulers
// order by (longest first); never part of any result.
double expected_steps(const Phenotype& p, const PhysicsDef& physics);

// Where the simulations of a generation run. The default (nullptr in Evolver) is the
// evolver's thread pool; an MPI implementation spreads them over ranks (mpi_cluster.hpp).
// Implementations must return, for every phenotype of the batch, exactly what
// evaluate_phenotype() returns for it, in batch order.
class Simulations {
 public:
  virtual ~Simulations() = default;
  virtual std::vector<Evaluation> run(const std::vector<const Phenotype*>& batch,
                                      const PhysicsDef& physics, int threads) = 0;
  // Before run(): the genome of each body of the batch (its first new individual's), for a
  // backend that hands genomes out (Python's ask/tell). The default ignores them.
  virtual void genomes(const std::vector<const Genome*>& batch) { (void)batch; }
};

// The thread-pool implementation: largest bodies first on `threads` threads.
std::vector<Evaluation> simulate_on_threads(const std::vector<const Phenotype*>& batch,
                                            const PhysicsDef& physics, int threads);

class Evolver {
 public:
  // Starts a new run (generations_done = -1) or continues `state` (phenotypes of the
  // population are re-expressed from their genomes). threads: 0 = all cores.
  // simulations: nullptr for the thread pool; otherwise must outlive the evolver.
  Evolver(RunState state, int threads, Simulations* simulations = nullptr);

  static RunState new_run(const EvolveConfig& config);

  // One generation of the config's algorithm; must not be called when finished().
  GenerationStats step();
  bool finished() const { return state_.finished(); }
  const RunState& state() const { return state_; }
  int threads() const { return threads_; }

 private:
  struct Evaluated;  // what evaluate_new() simulated (evolver.cpp)
  // A genome the caller set (Evaluation::edited) for the new individuals `edited` (one body
  // and its duplicates): re-expressed, and `e` made an invalid body's when it is one.
  void apply_edit(std::vector<Individual>& fresh, std::vector<BirthRecord>& births,
                  const std::vector<size_t>& edited, const Genome& genome, Evaluation& e);
  using Time = std::chrono::steady_clock::time_point;
  void step_afpo(GenerationStats& st, Time t0);
  void step_cma(GenerationStats& st, Time t0);         // docs/evolution.md, "CMA-ES"
  void step_map_elites(GenerationStats& st, Time t0);  // docs/evolution.md, "MAP-Elites"
  // The stages every algorithm shares: 4b-4d above for the generation's new individuals, and
  // the records (new_champion: null when the champion did not change).
  void evaluate_new(std::vector<Individual>& fresh, std::vector<BirthRecord>& births,
                    GenerationStats& st, Evaluated& out);
  void record(int gen, const Individual* new_champion, const Evaluated& ev, GenerationStats& st,
              Time t0);

  RunState state_;
  Expresser expresser_;
  int threads_;
  Simulations* simulations_;
};

}  // namespace plastivox::evo
