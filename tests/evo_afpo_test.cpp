// Age-Fitness Pareto selection on hand-made populations.
#include "plastivox/evo/afpo.hpp"
#include "test_support.hpp"

namespace plastivox::evo {
namespace {

TEST(EvoAfpo, Dominance) {
  const Objectives fit_young{1, 5.0, 1}, fit_old{2, 5.0, 3}, weak_young{3, 1.0, 1},
      weak_old{4, 1.0, 3};
  EXPECT_TRUE(dominates(fit_young, fit_old));
  EXPECT_TRUE(dominates(fit_young, weak_young));
  EXPECT_TRUE(dominates(fit_young, weak_old));
  EXPECT_FALSE(dominates(fit_old, weak_young));  // a trade-off
  EXPECT_FALSE(dominates(weak_young, fit_old));
  EXPECT_FALSE(dominates(fit_young, fit_young));  // equal: neither dominates
}

TEST(EvoAfpo, ParetoRanksOfAHandMadePopulation) {
  //  id fitness age   rank
  //   0   9.0    5     0   (fittest)
  //   1   7.0    2     0
  //   2   3.0    0     0   (youngest)
  //   3   6.0    5     2   (dominated by 0, 1, 6 and also 4)
  //   4   6.0    2     1   (by 1 and 6)
  //   5   2.0    5     3   (by 3 and everything above)
  //   6   7.0    2     0   (equal to 1: neither dominates)
  const std::vector<Objectives> pop = {{0, 9.0, 5}, {1, 7.0, 2}, {2, 3.0, 0}, {3, 6.0, 5},
                                       {4, 6.0, 2}, {5, 2.0, 5}, {6, 7.0, 2}};
  EXPECT_EQ(pareto_ranks(pop), (std::vector<int>{0, 0, 0, 2, 1, 3, 0}));
}

TEST(EvoAfpo, SelectionKeepsFrontsThenFitnessThenAgeThenNewest) {
  const std::vector<Objectives> pop = {{0, 9.0, 5}, {1, 7.0, 2}, {2, 3.0, 0}, {3, 6.0, 5},
                                       {4, 6.0, 2}, {5, 2.0, 5}, {6, 7.0, 2}};
  // Rank 0 in fitness order: 0 (9.0), then 1 and 6 tie (7.0, age 2): newer id 6 first.
  EXPECT_EQ(afpo_select(pop, 7), (std::vector<size_t>{0, 6, 1, 2, 4, 3, 5}));
  EXPECT_EQ(afpo_select(pop, 3), (std::vector<size_t>{0, 6, 1}));
  EXPECT_EQ(afpo_select(pop, 5), (std::vector<size_t>{0, 6, 1, 2, 4}));
  EXPECT_EQ(afpo_select(pop, 100).size(), 7u);
}

TEST(EvoAfpo, SelectionDoesNotDependOnInputOrder) {
  std::vector<Objectives> pop;
  for (uint64_t i = 0; i < 49; ++i)
    pop.push_back({i * 7919 % 1000, static_cast<double>((i * 37) % 11), static_cast<int>(i % 6)});
  std::vector<Objectives> rev(pop.rbegin(), pop.rend());
  std::vector<uint64_t> a, b;
  for (size_t k : afpo_select(pop, 24)) a.push_back(pop[k].id);
  for (size_t k : afpo_select(rev, 24)) b.push_back(rev[k].id);
  EXPECT_EQ(a, b);
}

TEST(EvoAfpo, TheFittestAndTheNewcomerSurvive) {
  // 24 old parents, 24 children with their ages, 1 newcomer of age 0 and no fitness.
  std::vector<Objectives> pop;
  for (uint64_t i = 0; i < 24; ++i) pop.push_back({i, 1.0 + i * 0.1, 3 + static_cast<int>(i % 4)});
  for (uint64_t i = 0; i < 24; ++i) pop.push_back({24 + i, 0.5 + i * 0.13, pop[i].age});
  pop.push_back({48, -1.0, 0});
  const std::vector<size_t> kept = afpo_select(pop, 24);
  ASSERT_EQ(kept.size(), 24u);
  double best = -1e9;
  size_t best_i = 0;
  for (size_t i = 0; i < pop.size(); ++i)
    if (pop[i].fitness > best) best = pop[i].fitness, best_i = i;
  EXPECT_EQ(kept[0], best_i);
  EXPECT_NE(std::find(kept.begin(), kept.end(), size_t{48}), kept.end());
}

}  // namespace
}  // namespace plastivox::evo
