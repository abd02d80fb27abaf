#include "plastivox/evo/variation.hpp"

namespace plastivox::evo {

Offspring mutate_child(const Expresser& ex, const Genome& parent,
                       const NetworkOutputs& parent_outputs, const Phenotype& parent_phenotype,
                       Rng& rng, int max_tries) {
  Offspring child;
  for (int attempt = 1; attempt <= max_tries; ++attempt) {
    // Which networks: each with probability 1/4, drawn again until one is picked.
    bool picked[kNetworkCount] = {false, false, false, false};
    bool any = false;
    while (!any)
      for (int i = 0; i < kNetworkCount; ++i) any |= (picked[i] = rng.coin(0.25));

    Genome g = parent;
    NetworkOutputs out = parent_outputs;
    bool applied = false;
    for (int i = 0; i < kNetworkCount; ++i) {
      if (!picked[i]) continue;
      const auto op = static_cast<MutationOp>(rng.index(kMutationOpCount));
      if (!mutate(g.nets[i], op, rng)) continue;
      applied = true;
      ex.evaluate(g, static_cast<Network>(i), out);  // only mutated networks are re-run
    }
    if (!applied) continue;
    Phenotype p = ex.express(out);
    if (!p.valid || p.same_as(parent_phenotype)) continue;
    child.genome = std::move(g);
    child.outputs = std::move(out);
    child.phenotype = std::move(p);
    child.tries = attempt;
    child.success = true;
    return child;
  }
  child.genome = parent;
  child.outputs = parent_outputs;
  child.phenotype = parent_phenotype;
  child.tries = max_tries;
  child.success = false;
  return child;
}

Offspring random_individual(const Expresser& ex, Rng& rng, int max_draws) {
  Offspring o;
  for (int draw = 1; draw <= max_draws; ++draw) {
    o.genome = random_genome(rng);
    o.outputs = ex.evaluate(o.genome);
    o.phenotype = ex.express(o.outputs);
    o.tries = draw;
    o.success = o.phenotype.valid;
    if (o.success) break;
  }
  return o;
}

}  // namespace plastivox::evo
