// Age-Fitness Pareto selection (Schmidt & Lipson 2011; docs/method.md §7).
//
// Objectives: fitness (maximised) and age (minimised). a dominates b when a is at least as
// fit and at least as young, and strictly better in one of the two. Pareto rank 0 is the
// non-dominated set; rank k is non-dominated once ranks < k are removed.
//
// Selection back down to the population size keeps candidates in this total order:
//   1. lower Pareto rank first (whole fronts are kept while they fit);
//   2. then higher fitness;   3. then lower age;
//   4. then the larger id (the newer individual: ties in both objectives favour novelty).
// Ids are unique, so the order is total and selection never depends on input order.
// The fittest candidate is always rank 0 and first within it, so the best fitness of the
// population never decreases.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace plastivox::evo {

struct Objectives {
  uint64_t id = 0;     // unique individual id
  double fitness = 0;  // maximised; never NaN
  int age = 0;         // minimised
};

bool dominates(const Objectives& a, const Objectives& b);

// Pareto rank of each candidate (same order as the input).
std::vector<int> pareto_ranks(const std::vector<Objectives>& candidates);

// Indices of the `keep` candidates selected by the order above, in that order
// (all of them, ordered, when keep >= size).
std::vector<size_t> afpo_select(const std::vector<Objectives>& candidates, size_t keep);

}  // namespace plastivox::evo
