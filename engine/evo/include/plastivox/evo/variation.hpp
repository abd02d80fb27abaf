// New individuals: mutated children and random newcomers (docs/method.md §6-7).
#pragma once

#include "plastivox/evo/genome.hpp"
#include "plastivox/evo/phenotype.hpp"
#include "plastivox/evo/rng.hpp"

namespace plastivox::evo {

struct Offspring {
  Genome genome;
  NetworkOutputs outputs;
  Phenotype phenotype;
  int tries = 0;         // mutation attempts (child) or draws (newcomer) used
  bool success = false;  // child: phenotype changed and valid; newcomer: valid
};

// A child of parent. One attempt: each network is picked with probability 1/4 (drawn
// again until at least one is picked); each picked network gets one operator chosen
// uniformly from the six. A run that evolves a controller picks its weights as a fifth part,
// alike, and mutates them with mutate_controller(). The attempt succeeds when the phenotype differs
// from the parent's and is valid; otherwise the next attempt starts again from the parent. After
// max_tries failures the child is an unchanged copy of the parent (success = false).
// Networks the phenotype ignores (C3 under treatment none) never make a change by
// themselves, because the phenotype does not contain their output.
Offspring mutate_child(const Expresser& ex, const Genome& parent,
                       const NetworkOutputs& parent_outputs, const Phenotype& parent_phenotype,
                       Rng& rng, int max_tries);

// A random individual: random_genome() drawn until its phenotype is valid, at most
// max_draws times; after that the last (invalid) draw is returned (success = false).
Offspring random_individual(const Expresser& ex, Rng& rng, int max_draws);

// The same with the geometry network replaced by body_plan_geometry(plan) after each draw: a
// body of that plan with random stiffness, development and phase networks.
Offspring body_plan_individual(const Expresser& ex, Rng& rng, int plan, int max_draws);

}  // namespace plastivox::evo
