// The AFPO loop in memory: bookkeeping, elitism, determinism across thread counts, and
// continuing from a copied state.
#include <set>

#include "plastivox/base/error.hpp"
#include "plastivox/evo/evolver.hpp"
#include "test_support.hpp"

namespace plastivox::evo {
namespace {

// Tiny and quick: 4x4x4 lattice, population 6, 0.2 s lives.
EvolveConfig tiny(Treatment t, uint64_t seed = 11) {
  EvolveConfig c = parse_config(R"({"format": "plastivox-evolve-config", "version": 1,
      "population": 6, "generations": 3, "lattice": {"nx": 4, "ny": 4, "nz": 4},
      "physics": {"duration": 0.2, "settle_time": 0.1}})",
                                "tiny");
  c.treatment = t;
  c.physics.treatment = t;
  c.seed = seed;
  return c;
}

RunState run(const EvolveConfig& c, int threads) {
  Evolver ev(Evolver::new_run(c), threads);
  while (!ev.finished()) ev.step();
  return ev.state();
}

TEST(EvoEvolver, InitialPopulationIsRandomAndAgeZero) {
  Evolver ev(Evolver::new_run(tiny(Treatment::kNone)), 2);
  const GenerationStats st = ev.step();
  EXPECT_EQ(st.generation, 0);
  EXPECT_EQ(st.created, 6);
  const RunState& s = ev.state();
  ASSERT_EQ(s.population.size(), 6u);
  for (size_t i = 0; i < 6; ++i) {
    EXPECT_EQ(s.population[i].id, i);
    EXPECT_EQ(s.population[i].age, 0);
    EXPECT_EQ(s.population[i].parent_id, -1);
    EXPECT_TRUE(s.population[i].phenotype.valid);  // newcomers are drawn until valid
  }
  EXPECT_EQ(s.next_id, 6u);
  EXPECT_EQ(s.births.size(), 6u);
  EXPECT_EQ(s.champions.size(), 1u);
}

TEST(EvoEvolver, AgesChildrenAndNewcomers) {
  Evolver ev(Evolver::new_run(tiny(Treatment::kStress)), 2);
  ev.step();
  for (int g = 1; g <= 3; ++g) {
    const RunState before = ev.state();
    const GenerationStats st = ev.step();
    const RunState& s = ev.state();
    EXPECT_EQ(st.created, 7);  // one child per survivor and one newcomer
    ASSERT_EQ(s.births.size(), before.births.size() + 7);
    // Ids: children of the survivors in ascending parent id, then the newcomer.
    for (size_t k = 0; k < 6; ++k) {
      const BirthRecord& b = s.births[before.births.size() + k];
      EXPECT_EQ(b.id, before.next_id + k);
      EXPECT_EQ(b.parent_id, static_cast<int64_t>(before.population[k].id));
      EXPECT_EQ(b.generation, g);
    }
    const BirthRecord& newcomer = s.births.back();
    EXPECT_EQ(newcomer.id, before.next_id + 6);
    EXPECT_EQ(newcomer.parent_id, -1);
    // Survivors: old ones aged by one; children carry the parent's (incremented) age;
    // the newcomer is 0.
    for (const Individual& ind : s.population) {
      if (ind.id < before.next_id) {
        const auto it = std::find_if(before.population.begin(), before.population.end(),
                                     [&](const Individual& o) { return o.id == ind.id; });
        ASSERT_NE(it, before.population.end());
        EXPECT_EQ(ind.age, it->age + 1);
      } else if (ind.parent_id < 0) {
        EXPECT_EQ(ind.age, 0);
      } else {
        const auto it = std::find_if(
            before.population.begin(), before.population.end(),
            [&](const Individual& o) { return static_cast<int64_t>(o.id) == ind.parent_id; });
        ASSERT_NE(it, before.population.end());
        EXPECT_EQ(ind.age, it->age + 1);
      }
    }
    // The newcomer, alone at age 0, is never dominated: it always survives.
    EXPECT_TRUE(std::any_of(s.population.begin(), s.population.end(),
                            [&](const Individual& i) { return i.id == newcomer.id; }));
    EXPECT_TRUE(
        std::is_sorted(s.population.begin(), s.population.end(),
                       [](const Individual& a, const Individual& b) { return a.id < b.id; }));
  }
}

TEST(EvoEvolver, BestFitnessNeverDecreases) {
  const RunState s = run(tiny(Treatment::kPressure, 3), 2);
  ASSERT_EQ(s.history.size(), 4u);
  for (size_t g = 1; g < s.history.size(); ++g)
    EXPECT_GE(s.history[g].best_fitness, s.history[g - 1].best_fitness);
  EXPECT_EQ(s.champions.back().id, s.history.back().champion_id);
  EXPECT_EQ(s.champions.back().fitness, s.history.back().best_fitness);
  // The champion's recorded final stiffness lies in the physics range where present.
  const ChampionRecord& c = s.champions.back();
  for (int site = 0; site < c.phenotype.sites(); ++site) {
    if (!c.phenotype.present[site]) continue;
    EXPECT_GE(c.final_stiffness[site], 1e5);
    EXPECT_LE(c.final_stiffness[site], 1e11);
  }
}

TEST(EvoEvolver, SameSeedSameDigestWithOneAndTwoThreads) {
  const EvolveConfig c = tiny(Treatment::kStress, 5);
  const RunState one = run(c, 1), two = run(c, 2);
  EXPECT_EQ(content_digest(one).hex(), content_digest(two).hex());
  EvolveConfig other = c;
  other.seed = 6;
  EXPECT_NE(content_digest(one).hex(), content_digest(run(other, 2)).hex());
}

// A backend that simulates the batch backwards on one thread, as another rank might.
class Backwards : public Simulations {
 public:
  std::vector<Evaluation> run(const std::vector<const Phenotype*>& batch, const PhysicsDef& physics,
                              int) override {
    std::vector<Evaluation> out(batch.size());
    for (size_t k = batch.size(); k-- > 0;) out[k] = evaluate_phenotype(*batch[k], physics);
    calls += 1;
    return out;
  }
  int calls = 0;
};

TEST(EvoEvolver, SimulationBackendDoesNotChangeResults) {
  const EvolveConfig c = tiny(Treatment::kStress, 12);
  Backwards backend;
  Evolver ev(Evolver::new_run(c), 2, &backend);
  while (!ev.finished()) ev.step();
  EXPECT_EQ(backend.calls, 4);
  EXPECT_EQ(content_digest(ev.state()).hex(), content_digest(run(c, 2)).hex());
}

TEST(EvoEvolver, ContinuingFromACopiedStateEqualsUninterrupted) {
  const EvolveConfig c = tiny(Treatment::kNone, 8);
  const RunState full = run(c, 2);
  Evolver first(Evolver::new_run(c), 2);
  first.step();
  first.step();
  RunState saved = first.state();
  for (Individual& ind : saved.population) {  // what a checkpoint does not store
    ind.outputs = {};
    ind.phenotype = {};
  }
  Evolver second(saved, 1);
  while (!second.finished()) second.step();
  EXPECT_EQ(content_digest(second.state()).hex(), content_digest(full).hex());
}

TEST(EvoEvolver, CacheServesIdenticalBodies) {
  const RunState s = run(tiny(Treatment::kNone, 2), 2);
  int simulated = 0, cached = 0;
  for (const GenerationRecord& g : s.history) {
    simulated += g.simulated;
    cached += g.cache_hits;
  }
  int valid = 0;
  for (const BirthRecord& b : s.births)
    valid += b.status != static_cast<uint8_t>(EvalStatus::kInvalid);
  EXPECT_EQ(simulated + cached, valid);
  EXPECT_EQ(static_cast<size_t>(simulated), s.cache.size());
}

// initial_population: body-plans puts one hand-built body of each plan first in generation 0
// (random stiffness, development and phase networks from the same draws) and leaves every
// other individual as the random start makes it; the default stays out of the canonical
// config, so runs that do not ask for it keep their identities and digests.
TEST(EvoEvolver, BodyPlanStartSeedsTheFirstThreeAndNothingElse) {
  EvolveConfig random = tiny(Treatment::kStress);
  random.nx = random.ny = random.nz = 6;  // the bodies need 6 sites a side
  EXPECT_EQ(random.canonical_json().find("initial_population"), std::string::npos);
  EvolveConfig seeded = random;
  seeded.initial_population = InitialPopulation::kBodyPlans;
  EXPECT_NE(seeded.identity_json(), random.identity_json());
  EXPECT_EQ(parse_config(seeded.canonical_json(), "x").canonical_json(), seeded.canonical_json());

  Evolver a(Evolver::new_run(random), 2), b(Evolver::new_run(seeded), 2);
  a.step();
  b.step();
  const RunState &ra = a.state(), &rb = b.state();
  ASSERT_EQ(ra.population.size(), 6u);
  ASSERT_EQ(rb.population.size(), 6u);
  const auto by_id = [](const RunState& s, uint64_t id) -> const Individual& {
    for (const Individual& i : s.population)
      if (i.id == id) return i;
    throw std::runtime_error("no individual " + std::to_string(id));
  };
  for (uint64_t id = 0; id < 6; ++id) {
    const Individual &x = by_id(ra, id), &y = by_id(rb, id);
    EXPECT_EQ(y.parent_id, -1);
    EXPECT_TRUE(y.phenotype.valid);
    if (id < kBodyPlanSeedCount) {
      // The plan's geometry with the other three networks of the stream's first draw.
      Rng rng = Rng::stream(seeded.seed, StreamPurpose::kNewcomer, 0, id);
      Genome first = random_genome(rng);
      first.nets[static_cast<int>(Network::kGeometry)] = body_plan_geometry(static_cast<int>(id));
      EXPECT_EQ(y.genome, first) << id;
    } else {
      EXPECT_EQ(x.genome, y.genome) << id;
    }
  }
  // Threads do not change a seeded run either.
  EXPECT_EQ(content_digest(run(seeded, 1)).hex(), content_digest(run(seeded, 2)).hex());
}

TEST(EvoEvolver, BodyPlanStartRefusesALatticeTooSmallForTheBodies) {
  const auto error = [](const std::string& lattice) {
    try {
      parse_config(R"({"format": "plastivox-evolve-config", "version": 1,
                       "initial_population": "body-plans", "lattice": )" +
                       lattice + "}",
                   "c.json");
    } catch (const plastivox::InputError& e) {
      return std::string(e.what());
    }
    return std::string("(accepted)");
  };
  EXPECT_EQ(error(R"({"nx": 6, "ny": 6, "nz": 6})"), "(accepted)");
  EXPECT_EQ(error(R"({"nx": 10, "ny": 10, "nz": 5})"),
            "c.json: initial_population: body-plans needs a lattice of at least 6 sites on each "
            "axis, not 10x10x5");
  try {
    parse_config(R"({"format": "plastivox-evolve-config", "version": 1,
                     "initial_population": "planned"})",
                 "c.json");
    ADD_FAILURE() << "accepted";
  } catch (const plastivox::InputError& e) {
    EXPECT_EQ(std::string(e.what()),
              "c.json: initial_population: 'planned' is unknown (use random or body-plans)");
  }
}

}  // namespace
}  // namespace plastivox::evo
