// content_digest(): the scientific content of a run, hashed in a fixed order.
#include "plastivox/evo/run_state.hpp"

namespace plastivox::evo {
namespace {

void hash_genome(Hasher& h, const Genome& g) {
  for (const Cppn& net : g.nets) {
    h.u64(net.nodes.size());
    h.vec(net.nodes);
    h.u64(net.links.size());
    for (const CppnLink& l : net.links) {
      h.u64(static_cast<uint64_t>(l.source));
      h.u64(static_cast<uint64_t>(l.target));
      h.f64(l.weight);
    }
  }
  if (!g.controller.empty()) h.vec(g.controller);  // absent under the sine: its digests hold
}

}  // namespace

Hash128 content_digest(const RunState& s) {
  Hasher h;
  h.str("plastivox-evolution-content-v1");
  h.str(s.config.identity_json());
  h.str(resolved_physics_json(s.config.physics));
  h.u64(static_cast<uint64_t>(static_cast<int64_t>(s.generations_done)));
  h.u64(s.next_id);
  h.u64(s.history.size());
  for (const GenerationRecord& g : s.history) {
    h.vec(g.id);
    h.vec(g.parent_id);
    h.vec(g.age);
    h.vec(g.fitness);
    h.vec(g.status);
    h.u64(g.champion_id);
    h.f64(g.best_fitness);
  }
  h.u64(s.births.size());
  for (const BirthRecord& b : s.births) {
    h.u64(b.id);
    h.u64(static_cast<uint64_t>(b.parent_id));
    h.u64(static_cast<uint64_t>(b.generation));
    h.f64(b.fitness);
    h.u64(b.status);
    h.u64(static_cast<uint64_t>(b.voxels));
    h.u64(static_cast<uint64_t>(b.tries));
    h.str(b.failure);
  }
  h.u64(s.champions.size());
  for (const ChampionRecord& c : s.champions) {
    h.u64(static_cast<uint64_t>(c.generation));
    h.u64(c.id);
    h.u64(static_cast<uint64_t>(c.parent_id));
    h.u64(static_cast<uint64_t>(c.age));
    h.f64(c.fitness);
    h.u64(c.status);
    hash_genome(h, c.genome);
    hash_robot(h, c.phenotype);
    h.vec(c.final_stiffness);
  }
  h.u64(s.population.size());
  for (const Individual& ind : s.population) {
    h.u64(ind.id);
    h.u64(static_cast<uint64_t>(ind.parent_id));
    h.u64(static_cast<uint64_t>(ind.age));
    h.u64(static_cast<uint64_t>(ind.born));
    h.f64(ind.fitness);
    h.u64(static_cast<uint8_t>(ind.status));
    hash_genome(h, ind.genome);
  }
  if (s.config.algorithm == Algorithm::kCmaEs) {  // the search distribution the run goes on from
    h.str("cma-es");
    h.vec(s.cma.mean);
    h.vec(s.cma.p_sigma);
    h.vec(s.cma.p_c);
    h.vec(s.cma.cov);
    h.f64(s.cma.sigma);
    h.u64(static_cast<uint64_t>(s.cma.updates));
    h.u64(s.cma.separable ? 1 : 0);
  }
  if (s.config.algorithm == Algorithm::kMapElites) {  // the archive and what led to it
    h.str("map-elites");
    for (const BirthRecord& b : s.births) h.vec(b.descriptors);
    for (const GenerationRecord& g : s.history) {
      h.f64(g.qd_score);
      h.u64(static_cast<uint64_t>(g.filled));
    }
    h.u64(s.archive.size());
    for (const Individual& e : s.archive) {
      h.u64(static_cast<uint64_t>(e.cell));
      h.u64(e.id);
      h.u64(static_cast<uint64_t>(e.parent_id));
      h.u64(static_cast<uint64_t>(e.born));
      h.f64(e.fitness);
      h.vec(e.descriptors);
      hash_genome(h, e.genome);
    }
  }
  return h.finish();
}

}  // namespace plastivox::evo
