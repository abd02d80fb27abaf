// One AFPO generation: make, express, deduplicate, evaluate, select, record.
#include "plastivox/evo/evolver.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <utility>

#include "plastivox/base/clock.hpp"
#include "plastivox/base/names.hpp"
#include "plastivox/base/parallel.hpp"
#include "plastivox/evo/afpo.hpp"
#include "plastivox/evo/cma.hpp"
#include "plastivox/evo/cma_body.hpp"
#include "plastivox/evo/map_elites.hpp"
#include "plastivox/evo/variation.hpp"
#include "plastivox/io/limits.hpp"
#include "plastivox/rules/life_rules.hpp"
#include "plastivox/simulator.hpp"

namespace plastivox::evo {
namespace {

// Index of the champion: highest fitness, ties to the lowest id (population is by id).
// The fitness selection sees: a failed life (invalid, unstable, sunk) ranks below every
// scored one, whatever the scores' range. The engine's fitness is >= 0 and a failure's
// kWorstFitness is -1, so for it this changes no order; an outside fitness (Python's) may
// score below -1.
double ranked_fitness(const Individual& ind) {
  return ind.status == EvalStatus::kOk ? ind.fitness : -std::numeric_limits<double>::infinity();
}

// What a champion is chosen by (docs/evolution.md, "Flagged lives"): a life that counts (ok,
// not flagged by the vertical rule) by its fitness, above every flagged life (ok, but scored by
// rising or falling: Evaluation::vertical), above every failed one. Selection still sees
// ranked_fitness; without a flagged life the two order alike, so runs without one keep their
// champions and digests.
using ChampionRank = std::pair<int, double>;
ChampionRank champion_rank(EvalStatus status, bool vertical, double fitness) {
  if (status != EvalStatus::kOk) return {0, 0.0};
  return {vertical ? 1 : 2, fitness};
}
ChampionRank champion_rank(const Individual& ind) {
  return champion_rank(ind.status, ind.vertical, ind.fitness);
}
// The recorded champion's rank: its flag is its birth's.
ChampionRank champion_rank(const RunState& s, const ChampionRecord& c) {
  return champion_rank(static_cast<EvalStatus>(c.status), s.births.at(c.id).vertical != 0,
                       c.fitness);
}

// The best of a population (by id) by champion_rank, ties to the lowest id.
size_t champion_index(const std::vector<Individual>& pop) {
  size_t best = 0;
  for (size_t i = 1; i < pop.size(); ++i)
    if (champion_rank(pop[i]) > champion_rank(pop[best])) best = i;
  return best;
}

// A random individual of generation `gen` (AFPO's newcomer, MAP-Elites' start): the first
// kBodyPlanSeedCount of generation 0 (spawn index `index`) of the body plans when the config
// asks for them.
Offspring newcomer(const Expresser& ex, const EvolveConfig& cfg, int gen, uint64_t id,
                   size_t index) {
  Rng rng = Rng::stream(cfg.seed, StreamPurpose::kNewcomer, gen, id);
  const bool seeded = gen == 0 && cfg.initial_population == InitialPopulation::kBodyPlans &&
                      index < static_cast<size_t>(kBodyPlanSeedCount);
  return seeded ? body_plan_individual(ex, rng, static_cast<int>(index), cfg.max_mutation_tries)
                : random_individual(ex, rng, cfg.max_mutation_tries);
}

}  // namespace

const char* to_string(EvalStatus s) {
  static constexpr Named<EvalStatus> kNames[] = {{EvalStatus::kOk, "ok"},
                                                 {EvalStatus::kInvalid, "invalid"},
                                                 {EvalStatus::kUnstable, "unstable"}};
  return name_in(kNames, s);
}

Evaluation evaluate_phenotype(const Phenotype& p, const PhysicsDef& physics) {
  const auto t0 = std::chrono::steady_clock::now();
  Evaluation e;
  const Model model = compile(p.robot, physics, limits_from_environment());
  // simulate()'s loop, with the life watched for MAP-Elites' descriptors (reading the states
  // only: the life and its result are simulate()'s, bit for bit; Simulator::result()).
  Simulator sim(model);
  DescriptorWatch watch(model);
  watch.see(sim.state());
  while (sim.state().status == SimStatus::kRunning) {
    sim.step();
    watch.see(sim.state());
  }
  SimResult r = sim.result();
  e.measures = watch.finish(r.stiffness_change_abs_mean);
  judge_life(physics, r);  // a sunk life is invalid under physics.sinking_invalid
  e.sank = r.sank;
  e.vertical = vertical_exploit(physics, r);
  e.final_stiffness.assign(p.robot.sites(), 0.0);
  for (int v = 0; v < model.n && v < static_cast<int>(r.final_stiffness.size()); ++v)
    e.final_stiffness[model.site[v]] = r.final_stiffness[v];
  if (r.status == SimStatus::kFinished && std::isfinite(r.fitness)) {
    e.status = EvalStatus::kOk;
    e.fitness = r.fitness;
  } else {
    e.status = EvalStatus::kUnstable;
    e.failure = r.failure.empty() ? "non-finite fitness" : r.failure;
  }
  e.wall_seconds = seconds_since(t0);
  return e;
}

double expected_steps(const Phenotype& p, const PhysicsDef& physics) {
  double e_top = 0;
  for (size_t i = 0; i < p.robot.present.size(); ++i)
    if (p.robot.present[i]) e_top = std::max(e_top, p.robot.stiffness[i]);
  if (!(e_top > 0)) return 0;
  return physics.duration / time_step_at(physics, p.robot.voxel_size, e_top);
}

RunState Evolver::new_run(const EvolveConfig& config) {
  RunState s;
  s.config = config;
  return s;
}

std::vector<Evaluation> simulate_on_threads(const std::vector<const Phenotype*>& batch,
                                            const PhysicsDef& physics, int threads) {
  // Largest bodies first: better load balance; the order does not affect any result.
  std::vector<size_t> schedule(batch.size());
  std::iota(schedule.begin(), schedule.end(), size_t{0});
  std::stable_sort(schedule.begin(), schedule.end(),
                   [&](size_t a, size_t b) { return batch[a]->voxels > batch[b]->voxels; });
  std::vector<Evaluation> out(batch.size());
  parallel_for(schedule.size(), threads, [&](size_t k) {
    out[schedule[k]] = evaluate_phenotype(*batch[schedule[k]], physics);
  });
  return out;
}

Evolver::Evolver(RunState state, int threads, Simulations* simulations)
    : state_(std::move(state)),
      expresser_(state_.config.expression()),
      threads_(threads > 0 ? threads : hardware_threads()),
      simulations_(simulations) {
  // Re-express the population (derived data is not stored in checkpoints).
  std::vector<Individual>& pop = state_.population;
  const bool cma = state_.config.algorithm == Algorithm::kCmaEs;
  parallel_for(pop.size(), threads_, [&](size_t i) {
    if (cma) {  // no networks: the vector on the fixed body
      pop[i].phenotype = express_vector(state_.config, pop[i].genome.controller);
      return;
    }
    pop[i].outputs = expresser_.evaluate(pop[i].genome);
    pop[i].phenotype = expresser_.express(pop[i].outputs);
  });
  std::vector<Individual>& elites = state_.archive;  // MAP-Elites' parents
  parallel_for(elites.size(), threads_, [&](size_t i) {
    elites[i].outputs = expresser_.evaluate(elites[i].genome);
    elites[i].phenotype = expresser_.express(elites[i].outputs);
  });
  // Each life's vertical flag is its birth's (the checkpoint keeps it there once).
  for (std::vector<Individual>* members : {&pop, &elites})
    for (Individual& ind : *members)
      ind.vertical = ind.id < state_.births.size() && state_.births[ind.id].vertical != 0;
}

struct Evolver::Evaluated {
  std::vector<uint64_t> sim_id;   // ids of the individuals simulated this generation
  std::vector<Evaluation> evals;  // their results, in the same order
  std::vector<size_t> edited;     // indices into fresh whose genome the caller set
};

GenerationStats Evolver::step() {
  const auto t0 = std::chrono::steady_clock::now();
  GenerationStats st;
  st.generation = state_.generations_done + 1;
  switch (state_.config.algorithm) {
    case Algorithm::kAfpo:
      step_afpo(st, t0);
      break;
    case Algorithm::kCmaEs:
      step_cma(st, t0);
      break;
    case Algorithm::kMapElites:
      step_map_elites(st, t0);
      break;
  }
  return st;
}

void Evolver::step_afpo(GenerationStats& st, std::chrono::steady_clock::time_point t0) {
  RunState& s = state_;
  const EvolveConfig& cfg = s.config;
  const int gen = st.generation;

  // --- 1-3: who is created: children of the survivors (ascending id), then one newcomer;
  // at generation 0, `population` random individuals (the first three of the body plans
  // when the config asks for them).
  struct Spawn {
    uint64_t id;
    int parent;  // index into the population, -1 for a random individual
  };
  std::vector<Spawn> spawns;
  if (gen == 0) {
    for (int i = 0; i < cfg.population; ++i) spawns.push_back({s.next_id++, -1});
  } else {
    for (Individual& ind : s.population) ++ind.age;
    for (size_t p = 0; p < s.population.size(); ++p)
      spawns.push_back({s.next_id++, static_cast<int>(p)});
    spawns.push_back({s.next_id++, -1});
  }

  // --- 4a: make and express, in parallel; each spawn draws from its own stream.
  std::vector<Offspring> made(spawns.size());
  parallel_for(spawns.size(), threads_, [&](size_t i) {
    const Spawn& t = spawns[i];
    if (t.parent < 0) {
      made[i] = newcomer(expresser_, cfg, gen, t.id, i);
    } else {
      const Individual& parent = s.population[t.parent];
      Rng rng = Rng::stream(cfg.seed, StreamPurpose::kMutation, gen, t.id);
      made[i] = mutate_child(expresser_, parent.genome, parent.outputs, parent.phenotype, rng,
                             cfg.max_mutation_tries);
    }
  });
  std::vector<Individual> fresh(spawns.size());
  std::vector<BirthRecord> births(spawns.size());
  for (size_t i = 0; i < spawns.size(); ++i) {
    Individual& ind = fresh[i];
    ind.id = spawns[i].id;
    ind.born = gen;
    if (spawns[i].parent >= 0) {
      ind.parent_id = static_cast<int64_t>(s.population[spawns[i].parent].id);
      ind.age = s.population[spawns[i].parent].age;
    }
    ind.genome = std::move(made[i].genome);
    ind.outputs = std::move(made[i].outputs);
    ind.phenotype = std::move(made[i].phenotype);
    births[i].id = ind.id;
    births[i].parent_id = ind.parent_id;
    births[i].generation = gen;
    births[i].voxels = ind.phenotype.voxels;
    births[i].tries = made[i].tries;
  }
  made.clear();

  Evaluated ev;
  evaluate_new(fresh, births, st, ev);

  // --- 5: selection over survivors and new individuals.
  std::vector<Individual> candidates = std::move(s.population);
  for (Individual& ind : fresh) candidates.push_back(std::move(ind));
  std::vector<Objectives> objectives;
  for (const Individual& ind : candidates)
    objectives.push_back({ind.id, ranked_fitness(ind), ind.age});
  std::vector<size_t> keep = afpo_select(objectives, static_cast<size_t>(cfg.population));
  std::sort(keep.begin(), keep.end(),
            [&](size_t a, size_t b) { return candidates[a].id < candidates[b].id; });
  s.population.clear();
  for (size_t k : keep) s.population.push_back(std::move(candidates[k]));

  // --- records: births, champion, history. The champion is the population's best by
  // champion_rank; a champion dropped by selection for a flagged life stays champion until a
  // life that counts beats it (without flagged lives AFPO always keeps its fittest, so this is
  // the population's best).
  for (BirthRecord& b : births) s.births.push_back(std::move(b));
  const Individual& champ = s.population[champion_index(s.population)];
  const bool changed =
      s.champions.empty() || (s.champions.back().id != champ.id &&
                              !(champion_rank(champ) < champion_rank(s, s.champions.back())));
  record(gen, changed ? &champ : nullptr, ev, st, t0);
}

// CMA-ES (cma.hpp): `population` samples of the search distribution, evaluated as AFPO's new
// individuals are; the population is this generation's samples; the distribution moves
// toward the best half. The champion is the best individual ever sampled by champion_rank (the
// search is not elitist; a flagged life is crowned only while none counts), ties to the earlier.
// The update still ranks by ranked_fitness: a flagged life pulls the distribution as its
// fitness says.
void Evolver::step_cma(GenerationStats& st, std::chrono::steady_clock::time_point t0) {
  RunState& s = state_;
  const EvolveConfig& cfg = s.config;
  const int gen = st.generation;
  if (gen == 0) s.cma = cma_start(genome_start(cfg), cfg.cma.sigma, cfg.cma.separable);
  const CmaBasis basis = cma_basis(s.cma);

  // --- 4a: sample and express, in parallel; each sample draws from its own stream.
  const size_t lambda = static_cast<size_t>(cfg.population);
  std::vector<Individual> fresh(lambda);
  std::vector<BirthRecord> births(lambda);
  for (size_t i = 0; i < lambda; ++i) fresh[i].id = s.next_id++;
  parallel_for(lambda, threads_, [&](size_t i) {
    Individual& ind = fresh[i];
    Rng rng = Rng::stream(cfg.seed, StreamPurpose::kCmaSample, gen, ind.id);
    ind.genome.nets.fill(minimal_cppn());  // no networks: the genome is the vector alone
    ind.genome.controller = cma_sample(s.cma, basis, rng);
    ind.phenotype = express_vector(cfg, ind.genome.controller);
  });
  for (size_t i = 0; i < lambda; ++i) {
    Individual& ind = fresh[i];
    ind.born = gen;
    births[i].id = ind.id;
    births[i].generation = gen;
    births[i].voxels = ind.phenotype.voxels;
    births[i].tries = 1;
  }

  Evaluated ev;
  evaluate_new(fresh, births, st, ev);

  // --- 5: rank (failed lives last, ties to the lower id) and update from the best half.
  std::vector<size_t> order(lambda);
  std::iota(order.begin(), order.end(), size_t{0});
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) {
    const double fa = ranked_fitness(fresh[a]), fb = ranked_fitness(fresh[b]);
    return fa != fb ? fa > fb : fresh[a].id < fresh[b].id;
  });
  std::vector<const std::vector<double>*> best;
  for (size_t k = 0; k < lambda / 2; ++k) best.push_back(&fresh[order[k]].genome.controller);
  cma_update(s.cma, basis, best, static_cast<int>(lambda));
  s.population = std::move(fresh);  // ascending id

  // --- records: births, champion (the best ever), history.
  for (BirthRecord& b : births) s.births.push_back(std::move(b));
  const Individual& top = s.population[champion_index(s.population)];
  const bool better =
      s.champions.empty() || champion_rank(top) > champion_rank(s, s.champions.back());
  record(gen, better ? &top : nullptr, ev, st, t0);
}

// MAP-Elites (map_elites.hpp; docs/evolution.md, "MAP-Elites"): `population` children, each of
// an elite drawn uniformly from the archive (its own stream) and mutated as AFPO mutates;
// while the archive is empty (generation 0), random individuals instead. They are evaluated as
// AFPO's new individuals are, then offered to their cells serially by id: a child whose life
// counts (ok, not sunk, not flagged by the vertical rule) takes its cell when the cell is empty or
// its fitness is strictly higher than the elite's (the elite keeps ties). The population is this
// generation's children; the champion is the best elite (ties to the lower id).
void Evolver::step_map_elites(GenerationStats& st, std::chrono::steady_clock::time_point t0) {
  RunState& s = state_;
  const EvolveConfig& cfg = s.config;
  const MapElitesSettings& me = cfg.map_elites;
  const int gen = st.generation;

  // --- 1-4a: who is created, made and expressed in parallel; each draws from its own streams.
  const size_t n = static_cast<size_t>(cfg.population);
  std::vector<Individual> fresh(n);
  std::vector<BirthRecord> births(n);
  for (size_t i = 0; i < n; ++i) fresh[i].id = s.next_id++;
  parallel_for(n, threads_, [&](size_t i) {
    Individual& ind = fresh[i];
    Offspring made;
    if (s.archive.empty()) {
      made = newcomer(expresser_, cfg, gen, ind.id, i);
    } else {
      Rng pick = Rng::stream(cfg.seed, StreamPurpose::kParent, gen, ind.id);
      const Individual& parent = s.archive[pick.index(static_cast<int>(s.archive.size()))];
      Rng rng = Rng::stream(cfg.seed, StreamPurpose::kMutation, gen, ind.id);
      made = mutate_child(expresser_, parent.genome, parent.outputs, parent.phenotype, rng,
                          cfg.max_mutation_tries);
      ind.parent_id = static_cast<int64_t>(parent.id);
    }
    ind.born = gen;
    ind.genome = std::move(made.genome);
    ind.outputs = std::move(made.outputs);
    ind.phenotype = std::move(made.phenotype);
    ind.descriptors = body_descriptors(me, ind.phenotype);
    births[i].tries = made.tries;
  });
  for (size_t i = 0; i < n; ++i) {
    births[i].id = fresh[i].id;
    births[i].parent_id = fresh[i].parent_id;
    births[i].generation = gen;
    births[i].voxels = fresh[i].phenotype.voxels;
  }

  Evaluated ev;
  evaluate_new(fresh, births, st, ev);
  for (size_t i : ev.edited) fresh[i].descriptors = body_descriptors(me, fresh[i].phenotype);

  // --- 4e: the life's descriptors, from the cache (every life evaluated is in it). An outside
  // fitness gives no measures: those lives are simulated again here (deterministic).
  std::vector<size_t> again;
  std::map<Hash128, size_t> queued;
  for (size_t i = 0; i < n; ++i) {
    const Individual& ind = fresh[i];
    if (!needs_life(me) || ind.status != EvalStatus::kOk) continue;
    if (!s.cache.at(ind.phenotype.hash).measures.measured && !queued.count(ind.phenotype.hash)) {
      queued[ind.phenotype.hash] = again.size();
      again.push_back(i);
    }
  }
  std::vector<DescriptorMeasures> measured(again.size());
  parallel_for(again.size(), threads_, [&](size_t k) {
    measured[k] = evaluate_phenotype(fresh[again[k]].phenotype, cfg.physics).measures;
  });
  for (size_t k = 0; k < again.size(); ++k)
    s.cache.at(fresh[again[k]].phenotype.hash).measures = measured[k];

  // --- 5: each child offered to its cell, by id.
  for (size_t i = 0; i < n; ++i) {
    Individual& ind = fresh[i];
    const bool counts = ind.status == EvalStatus::kOk && births[i].sank == 0 && !ind.vertical;
    if (counts) life_descriptors(me, s.cache.at(ind.phenotype.hash).measures, ind.descriptors);
    births[i].descriptors = ind.descriptors;
    const int64_t cell = counts ? cell_of(me, ind.descriptors) : -1;
    if (cell < 0) continue;
    const auto at = std::lower_bound(s.archive.begin(), s.archive.end(), cell,
                                     [](const Individual& e, int64_t c) { return e.cell < c; });
    if (at != s.archive.end() && at->cell == cell && !(ind.fitness > at->fitness)) continue;
    Individual elite = ind;
    elite.cell = cell;
    if (at != s.archive.end() && at->cell == cell)
      *at = std::move(elite);
    else
      s.archive.insert(at, std::move(elite));
  }
  s.population = std::move(fresh);  // ascending id

  // --- records: births, champion (the best elite), history with the archive's QD score.
  for (BirthRecord& b : births) s.births.push_back(std::move(b));
  const Individual* champ = nullptr;
  for (const Individual& e : s.archive)
    if (!champ || e.fitness > champ->fitness || (e.fitness == champ->fitness && e.id < champ->id))
      champ = &e;
  // Nothing counts yet: the generation's best by champion_rank.
  if (!champ && s.champions.empty()) champ = &s.population[champion_index(s.population)];
  const bool changed = champ && (s.champions.empty() || s.champions.back().id != champ->id);
  record(gen, changed ? champ : nullptr, ev, st, t0);
  GenerationRecord& rec = s.history.back();
  rec.filled = static_cast<int64_t>(s.archive.size());
  rec.qd_score = 0;
  for (const Individual& e : s.archive) rec.qd_score += std::max(0.0, e.fitness - me.qd_offset);
}

void Evolver::evaluate_new(std::vector<Individual>& fresh, std::vector<BirthRecord>& births,
                           GenerationStats& st, Evaluated& out) {
  RunState& s = state_;
  const EvolveConfig& cfg = s.config;
  // --- 4b: serially, by id: invalid, cached, duplicate of an earlier new one, or to simulate.
  std::vector<size_t> to_sim;
  std::vector<size_t> duplicates;
  std::vector<size_t> duplicate_of;    // the index in fresh each duplicate's body is simulated for
  std::map<Hash128, size_t> first_of;  // phenotype hash -> index in fresh
  for (size_t i = 0; i < fresh.size(); ++i) {
    Individual& ind = fresh[i];
    if (!ind.phenotype.valid) {
      ind.status = EvalStatus::kInvalid;
      ind.fitness = kWorstFitness;
      births[i].failure = ind.phenotype.invalid_reason;
      ++st.invalid;
    } else if (auto c = s.cache.find(ind.phenotype.hash); c != s.cache.end()) {
      ind.status = c->second.status;
      ind.fitness = c->second.fitness;
      births[i].failure = c->second.failure;
      births[i].sank = c->second.sank ? 1 : 0;
      ind.vertical = c->second.vertical;
      ++st.cache_hits;
    } else if (first_of.count(ind.phenotype.hash)) {
      duplicates.push_back(i);
      duplicate_of.push_back(first_of[ind.phenotype.hash]);
      ++st.cache_hits;
    } else {
      first_of[ind.phenotype.hash] = i;
      to_sim.push_back(i);
    }
  }

  // --- 4c: simulate (thread pool or MPI ranks); results land by index.
  std::vector<const Phenotype*> batch;
  std::vector<const Genome*> genomes;
  for (size_t i : to_sim) {
    batch.push_back(&fresh[i].phenotype);
    genomes.push_back(&fresh[i].genome);
  }
  if (simulations_) simulations_->genomes(genomes);
  const auto t_sim = std::chrono::steady_clock::now();
  std::vector<Evaluation> results = simulations_
                                        ? simulations_->run(batch, cfg.physics, threads_)
                                        : simulate_on_threads(batch, cfg.physics, threads_);
  st.sim_wall_seconds = seconds_since(t_sim);
  if (results.size() != batch.size()) throw std::logic_error("simulation backend lost results");
  std::vector<Evaluation> evals(fresh.size());
  for (size_t k = 0; k < to_sim.size(); ++k) evals[to_sim[k]] = std::move(results[k]);
  for (size_t i : to_sim)  // genomes the caller set, serially by id
    if (evals[i].edited) {
      if (cfg.algorithm == Algorithm::kCmaEs)
        throw std::invalid_argument("genomes: a CMA-ES run's samples cannot be set");
      Genome g = std::move(*evals[i].edited);
      evals[i].edited.reset();
      if (g == fresh[i].genome) continue;  // set unchanged: nothing to do
      std::vector<size_t> group = {i};     // every new individual with the body asked about
      for (size_t k = 0; k < duplicates.size(); ++k)
        if (duplicate_of[k] == i) group.push_back(duplicates[k]);
      apply_edit(fresh, births, group, g, evals[i]);
      out.edited.insert(out.edited.end(), group.begin(), group.end());
    }

  // --- 4d: record results by id, fill the cache, resolve duplicates.
  for (size_t i : to_sim) {
    Individual& ind = fresh[i];
    const Evaluation& e = evals[i];
    ind.status = e.status;
    ind.fitness = e.fitness;
    births[i].failure = e.failure;
    births[i].simulated = 1;
    births[i].sank = e.sank ? 1 : 0;
    ind.vertical = e.vertical;
    if (!ind.phenotype.valid) {  // a genome the caller set gave an invalid body
      ++st.invalid;
      continue;
    }
    s.cache[ind.phenotype.hash] =
        CacheEntry{e.fitness, e.status, e.failure, e.sank, e.measures, e.vertical};
    st.sim_cpu_seconds += e.wall_seconds;
    if (e.status == EvalStatus::kUnstable) ++st.unstable;
    if (e.sank) ++st.sank;
  }
  for (size_t i : duplicates) {
    if (!fresh[i].phenotype.valid) {  // of a body whose set genome gave an invalid one
      fresh[i].status = EvalStatus::kInvalid;
      fresh[i].fitness = kWorstFitness;
      births[i].failure = fresh[i].phenotype.invalid_reason;
      ++st.invalid;
      continue;
    }
    const CacheEntry& c = s.cache.at(fresh[i].phenotype.hash);
    fresh[i].status = c.status;
    fresh[i].fitness = c.fitness;
    births[i].failure = c.failure;
    births[i].sank = c.sank ? 1 : 0;
    fresh[i].vertical = c.vertical;
  }
  for (size_t i = 0; i < fresh.size(); ++i) {
    births[i].fitness = fresh[i].fitness;
    births[i].status = static_cast<uint8_t>(fresh[i].status);
    births[i].vertical = fresh[i].vertical ? 1 : 0;
  }
  st.created = static_cast<int>(fresh.size());
  st.simulated = static_cast<int>(to_sim.size());
  for (size_t k = 0; k < to_sim.size(); ++k) {
    out.sim_id.push_back(fresh[to_sim[k]].id);
    out.evals.push_back(std::move(evals[to_sim[k]]));
  }
}

void Evolver::apply_edit(std::vector<Individual>& fresh, std::vector<BirthRecord>& births,
                         const std::vector<size_t>& edited, const Genome& genome, Evaluation& e) {
  NetworkOutputs outputs = expresser_.evaluate(genome);
  Phenotype phenotype = expresser_.express(outputs);
  for (size_t j : edited) {
    fresh[j].genome = genome;
    fresh[j].outputs = outputs;
    fresh[j].phenotype = phenotype;
    births[j].voxels = phenotype.voxels;
  }
  if (!phenotype.valid) {
    e = Evaluation{};
    e.failure = "the genome set gives an invalid body: " + phenotype.invalid_reason;
    for (size_t j : edited) fresh[j].phenotype.invalid_reason = e.failure;
  }
}

void Evolver::record(int gen, const Individual* new_champion, const Evaluated& ev,
                     GenerationStats& st, Time t0) {
  RunState& s = state_;
  const EvolveConfig& cfg = s.config;
  if (new_champion) {
    const Individual& champ = *new_champion;
    ChampionRecord c;
    c.generation = gen;
    c.id = champ.id;
    c.parent_id = champ.parent_id;
    c.age = champ.age;
    c.fitness = champ.fitness;
    c.status = static_cast<uint8_t>(champ.status);
    c.genome = champ.genome;
    c.phenotype = champ.phenotype.robot;
    c.final_stiffness.assign(c.phenotype.sites(), 0.0);
    if (champ.status != EvalStatus::kInvalid) {
      // Its life's final stiffness: from this generation's simulation, or (rarely, for
      // a cached body, or when an outside fitness gave a number alone) simulated again;
      // the simulation is deterministic.
      const auto now = std::find(ev.sim_id.begin(), ev.sim_id.end(), champ.id);
      const size_t k = static_cast<size_t>(now - ev.sim_id.begin());
      c.final_stiffness = now != ev.sim_id.end() && !ev.evals[k].final_stiffness.empty()
                              ? ev.evals[k].final_stiffness
                              : evaluate_phenotype(champ.phenotype, cfg.physics).final_stiffness;
    }
    s.champions.push_back(std::move(c));
  }
  const ChampionRecord& champ = s.champions.back();
  GenerationRecord rec;
  for (const Individual& ind : s.population) {
    rec.id.push_back(ind.id);
    rec.parent_id.push_back(ind.parent_id);
    rec.age.push_back(ind.age);
    rec.fitness.push_back(ind.fitness);
    rec.status.push_back(static_cast<uint8_t>(ind.status));
  }
  rec.champion_id = champ.id;
  rec.best_fitness = champ.fitness;
  rec.simulated = st.simulated;
  rec.cache_hits = st.cache_hits;
  st.best_fitness = champ.fitness;
  st.champion_id = champ.id;
  s.generations_done = gen;
  st.wall_seconds = seconds_since(t0);
  rec.wall_seconds = st.wall_seconds;
  s.history.push_back(std::move(rec));
}

}  // namespace plastivox::evo
