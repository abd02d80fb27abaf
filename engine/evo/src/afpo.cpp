#include "plastivox/evo/afpo.hpp"

#include <algorithm>
#include <numeric>

namespace plastivox::evo {

bool dominates(const Objectives& a, const Objectives& b) {
  const bool no_worse = a.fitness >= b.fitness && a.age <= b.age;
  const bool better = a.fitness > b.fitness || a.age < b.age;
  return no_worse && better;
}

std::vector<int> pareto_ranks(const std::vector<Objectives>& c) {
  // Peel fronts: O(n^2) per front, fine for populations of tens.
  const size_t n = c.size();
  std::vector<int> rank(n, -1);
  size_t assigned = 0;
  for (int r = 0; assigned < n; ++r) {
    std::vector<size_t> front;
    for (size_t i = 0; i < n; ++i) {
      if (rank[i] >= 0) continue;
      bool dominated = false;
      for (size_t j = 0; j < n && !dominated; ++j)
        dominated = j != i && rank[j] < 0 && dominates(c[j], c[i]);
      if (!dominated) front.push_back(i);
    }
    for (size_t i : front) rank[i] = r;
    assigned += front.size();
  }
  return rank;
}

std::vector<size_t> afpo_select(const std::vector<Objectives>& c, size_t keep) {
  const std::vector<int> rank = pareto_ranks(c);
  std::vector<size_t> order(c.size());
  std::iota(order.begin(), order.end(), size_t{0});
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) {
    if (rank[a] != rank[b]) return rank[a] < rank[b];
    if (c[a].fitness != c[b].fitness) return c[a].fitness > c[b].fitness;
    if (c[a].age != c[b].age) return c[a].age < c[b].age;
    return c[a].id > c[b].id;
  });
  if (order.size() > keep) order.resize(keep);
  return order;
}

}  // namespace plastivox::evo
