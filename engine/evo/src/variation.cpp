#include "plastivox/evo/variation.hpp"

namespace plastivox::evo {

Offspring mutate_child(const Expresser& ex, const Genome& parent,
                       const NetworkOutputs& parent_outputs, const Phenotype& parent_phenotype,
                       Rng& rng, int max_tries) {
  const ControllerGenes& genes = ex.def().controller_genes;
  const int parts = kNetworkCount + (genes.count > 0 ? 1 : 0);
  for (int attempt = 1; attempt <= max_tries; ++attempt) {
    // Which parts: each network (and the controller, when the run evolves one) with
    // probability 1/4, drawn again until one is picked.
    bool picked[kNetworkCount + 1] = {false, false, false, false, false};
    bool any = false;
    while (!any)
      for (int i = 0; i < parts; ++i) any |= (picked[i] = rng.coin(0.25));

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
    if (picked[kNetworkCount]) {
      mutate_controller(g.controller, genes, rng);
      out.controller = g.controller;
      applied = true;
    }
    if (!applied) continue;
    Phenotype p = ex.express(out);
    if (!p.valid || p.same_as(parent_phenotype)) continue;
    return {std::move(g), std::move(out), std::move(p), attempt, true};
  }
  return {parent, parent_outputs, parent_phenotype, max_tries, false};  // the parent again
}

namespace {

// random_genome() drawn until its phenotype is valid (see random_individual); `plan` >= 0
// replaces the geometry network of every draw with that body plan's.
Offspring drawn_individual(const Expresser& ex, Rng& rng, int plan, int max_draws) {
  Offspring o;
  for (int draw = 1; draw <= max_draws; ++draw) {
    o.genome = random_genome(rng, ex.def().controller_genes);
    if (plan >= 0) o.genome.nets[static_cast<int>(Network::kGeometry)] = body_plan_geometry(plan);
    o.outputs = ex.evaluate(o.genome);
    o.phenotype = ex.express(o.outputs);
    o.tries = draw;
    o.success = o.phenotype.valid;
    if (o.success) break;
  }
  return o;
}

}  // namespace

Offspring random_individual(const Expresser& ex, Rng& rng, int max_draws) {
  return drawn_individual(ex, rng, -1, max_draws);
}

Offspring body_plan_individual(const Expresser& ex, Rng& rng, int plan, int max_draws) {
  return drawn_individual(ex, rng, plan, max_draws);
}

}  // namespace plastivox::evo
