// CPPNs: evaluation of hand-built networks, the six mutation operators, the recipe, and
// the generator and hash they rely on.
#include <cmath>
#include <set>

#include "plastivox/base/hash.hpp"
#include "plastivox/evo/cppn.hpp"
#include "plastivox/evo/rng.hpp"
#include "test_support.hpp"

namespace plastivox::evo {
namespace {

// A network with the given hidden activations (nodes 5..) and links.
Cppn net(std::vector<Activation> hidden, std::vector<CppnLink> links) {
  Cppn n;
  n.nodes.assign(kInputCount, Activation::kIdentity);
  for (Activation a : hidden) n.nodes.push_back(a);
  n.nodes.push_back(Activation::kIdentity);
  n.links = std::move(links);
  validate(n);
  return n;
}

TEST(EvoRng, SameKeySameNumbersDifferentKeyDifferent) {
  Rng a = Rng::stream(7, StreamPurpose::kMutation, 3, 42);
  Rng b = Rng::stream(7, StreamPurpose::kMutation, 3, 42);
  Rng c = Rng::stream(7, StreamPurpose::kMutation, 3, 43);
  Rng d = Rng::stream(7, StreamPurpose::kNewcomer, 3, 42);
  for (int i = 0; i < 100; ++i) {
    const uint64_t x = a.next_u64();
    EXPECT_EQ(x, b.next_u64());
    EXPECT_NE(x, c.next_u64());
    EXPECT_NE(x, d.next_u64());
  }
}

TEST(EvoRng, PinnedGoldenValues) {
  // The generator is part of the results' definition: these numbers must never change.
  Rng r(0);
  EXPECT_EQ(r.next_u64(), 0xe220a8397b1dcdafULL);  // SplitMix64 from state 0
  Rng s = Rng::stream(1, StreamPurpose::kTest, 0, 0);
  const uint64_t first = s.next_u64();
  Rng s2 = Rng::stream(1, StreamPurpose::kTest, 0, 0);
  EXPECT_EQ(first, s2.next_u64());
}

TEST(EvoRng, DistributionsHaveTheirMoments) {
  Rng r(123);
  const int n = 200000;
  double sum = 0, sum2 = 0, usum = 0;
  int counts[6] = {0, 0, 0, 0, 0, 0};
  for (int i = 0; i < n; ++i) {
    const double g = r.normal();
    sum += g;
    sum2 += g * g;
    const double u = r.uniform();
    ASSERT_GE(u, 0.0);
    ASSERT_LT(u, 1.0);
    usum += u;
    ++counts[r.index(6)];
  }
  EXPECT_NEAR(sum / n, 0.0, 0.01);
  EXPECT_NEAR(sum2 / n, 1.0, 0.02);
  EXPECT_NEAR(usum / n, 0.5, 0.005);
  for (int c : counts) EXPECT_NEAR(c, n / 6.0, n * 0.005);
}

TEST(EvoHash, LengthAndOrderMatter) {
  Hasher a, b, c;
  a.str("ab");
  a.str("c");
  b.str("a");
  b.str("bc");
  c.str("ab");
  c.str("c");
  EXPECT_NE(a.finish(), b.finish());
  EXPECT_EQ(a.finish(), c.finish());
  EXPECT_EQ(a.finish().hex().size(), 32u);
  Hasher z, nz;
  z.f64(0.0);
  nz.f64(-0.0);
  EXPECT_NE(z.finish(), nz.finish());  // bit-exact
}

TEST(EvoCppn, LatticeInputsSpanMinusOneToOne) {
  const CppnInputs in = lattice_inputs(10, 10, 10);
  ASSERT_EQ(in.sites, 1000);
  EXPECT_EQ(in.values[0][0], -1.0);
  EXPECT_EQ(in.values[0][9], 1.0);
  EXPECT_EQ(in.values[1][90], 1.0);
  EXPECT_EQ(in.values[2][999], 1.0);
  for (int i = 0; i < 4; ++i) {
    EXPECT_EQ(*std::min_element(in.values[i].begin(), in.values[i].end()), -1.0);
    EXPECT_EQ(*std::max_element(in.values[i].begin(), in.values[i].end()), 1.0);
  }
  EXPECT_EQ(in.values[3][0], 1.0);  // a corner is farthest from the centre
  for (double b : in.values[4]) EXPECT_EQ(b, 1.0);
  const CppnInputs flat = lattice_inputs(3, 1, 1);
  EXPECT_EQ(flat.values[1][1], 0.0);  // an axis of extent 1 sits at 0
}

TEST(EvoCppn, HandBuiltNetworksEvaluateAsWritten) {
  const CppnInputs in = lattice_inputs(5, 4, 3);
  // out = 0.5*x - 0.25*bias
  const Cppn linear = net({}, {{0, 5, 0.5}, {4, 5, -0.25}});
  // out = sin(x + y) with a hidden sin node, plus 1.0 * sqrt|z|
  const Cppn deep = net({Activation::kSin, Activation::kSqrtAbs},
                        {{0, 5, 1.0}, {1, 5, 1.0}, {2, 6, 1.0}, {5, 7, 1.0}, {6, 7, 1.0}});
  // out = -(d)^2 through neg_square
  const Cppn sq = net({Activation::kNegSquare}, {{3, 5, 1.0}, {5, 6, 1.0}});
  const std::vector<double> a = evaluate(linear, in), b = evaluate(deep, in), c = evaluate(sq, in);
  for (int s = 0; s < in.sites; ++s) {
    const double x = in.values[0][s], y = in.values[1][s], z = in.values[2][s], d = in.values[3][s];
    EXPECT_EQ(a[s], 0.5 * x + -0.25 * 1.0);
    EXPECT_DOUBLE_EQ(b[s], std::sin(x + y) + std::sqrt(std::fabs(z)));
    EXPECT_DOUBLE_EQ(c[s], -(d * d));
  }
}

TEST(EvoCppn, EveryActivationMatchesItsDefinition) {
  for (double x : {-2.5, -1.0, -0.3, 0.0, 0.7, 3.0}) {
    EXPECT_EQ(activate(Activation::kSin, x), std::sin(x));
    EXPECT_EQ(activate(Activation::kAbs, x), std::fabs(x));
    EXPECT_EQ(activate(Activation::kNegAbs, x), -std::fabs(x));
    EXPECT_EQ(activate(Activation::kSquare, x), x * x);
    EXPECT_EQ(activate(Activation::kNegSquare, x), -x * x);
    EXPECT_EQ(activate(Activation::kSqrtAbs, x), std::sqrt(std::fabs(x)));
    EXPECT_EQ(activate(Activation::kNegSqrtAbs, x), -std::sqrt(std::fabs(x)));
  }
}

TEST(EvoCppn, OverflowBecomesNaNWithoutFloatingPointTraps) {
  // A chain of squares overflows; the test binary traps FE_INVALID, so this also checks
  // that no inf*0 or sin(inf) is ever computed. Node 5 = (1 + d)^2, nodes 6..16 square it
  // again, node 17 = sin, output = 0 * node 17.
  std::vector<Activation> hidden(12, Activation::kSquare);
  hidden.push_back(Activation::kSin);
  std::vector<CppnLink> links = {{3, 5, 1.0}, {4, 5, 1.0}};
  for (int i = 5; i < 17; ++i) links.push_back({i, i + 1, 1.0});
  links.push_back({17, 18, 0.0});
  const Cppn chain = net(hidden, links);
  const std::vector<double> out = evaluate(chain, lattice_inputs(3, 3, 3));
  int nans = 0;
  for (double o : out) nans += std::isnan(o) ? 1 : 0;
  EXPECT_GT(nans, 0);  // where 1 + d > 1, (1 + d)^(2^12) overflows
}

TEST(EvoCppn, MinimalNetworkIsValidAndZero) {
  const Cppn n = minimal_cppn();
  validate(n);
  EXPECT_EQ(n.node_count(), 6);
  EXPECT_EQ(n.links.size(), 5u);
  for (double o : evaluate(n, lattice_inputs(4, 4, 4))) EXPECT_EQ(o, 0.0);
}

TEST(EvoCppn, EachOperatorKeepsTheNetworkValid) {
  Rng rng(2024);
  for (int op = 0; op < kMutationOpCount; ++op) {
    int applied = 0;
    for (int trial = 0; trial < 300; ++trial) {
      Cppn n = random_cppn(rng);
      const Cppn before = n;
      const bool ok = mutate(n, static_cast<MutationOp>(op), rng);
      ASSERT_NO_THROW(validate(n)) << to_string(static_cast<MutationOp>(op));
      if (ok) {
        ++applied;
        // A weight change may be clipped back to the same bound; every other operator
        // changes the network whenever it applies.
        if (static_cast<MutationOp>(op) != MutationOp::kChangeWeight) {
          EXPECT_FALSE(n == before) << to_string(static_cast<MutationOp>(op));
        }
      } else {
        EXPECT_TRUE(n == before);
      }
    }
    EXPECT_GT(applied, 200) << to_string(static_cast<MutationOp>(op));
  }
}

TEST(EvoCppn, OperatorsDoWhatTheySay) {
  Rng rng(5);
  Cppn n = random_cppn(rng);
  const int nodes = n.node_count();
  const size_t links = n.links.size();
  Cppn a = n;
  ASSERT_TRUE(mutate(a, MutationOp::kAddNode, rng));
  EXPECT_EQ(a.node_count(), nodes + 1);
  EXPECT_EQ(a.links.size(), links + 1);  // one link split into two
  Cppn b = n;
  ASSERT_TRUE(mutate(b, MutationOp::kAddLink, rng));
  EXPECT_EQ(b.links.size(), links + 1);
  bool found = false;
  for (const CppnLink& l : b.links) found |= std::fabs(l.weight) == 0.1;
  EXPECT_TRUE(found);
  Cppn c = n;
  ASSERT_TRUE(mutate(c, MutationOp::kRemoveLink, rng));
  EXPECT_EQ(c.links.size(), links - 1);
  Cppn d = n;
  ASSERT_TRUE(mutate(d, MutationOp::kRemoveNode, rng));
  EXPECT_EQ(d.node_count(), nodes - 1);
  Cppn e = n;
  ASSERT_TRUE(mutate(e, MutationOp::kChangeActivation, rng));
  EXPECT_EQ(e.links.size(), links);
  int changed = 0;
  for (int i = 0; i < nodes; ++i) changed += e.nodes[i] != n.nodes[i];
  EXPECT_EQ(changed, 1);
  Cppn f = n;
  ASSERT_TRUE(mutate(f, MutationOp::kChangeWeight, rng));
  int moved = 0;
  for (size_t i = 0; i < links; ++i) {
    moved += f.links[i].weight != n.links[i].weight;
    EXPECT_LE(std::fabs(f.links[i].weight), 1.0);
  }
  EXPECT_LE(moved, 1);
}

TEST(EvoCppn, OperatorsThatCannotApplyReportIt) {
  Rng rng(1);
  Cppn bare = minimal_cppn();
  bare.links.clear();
  EXPECT_FALSE(mutate(bare, MutationOp::kAddNode, rng));
  EXPECT_FALSE(mutate(bare, MutationOp::kRemoveLink, rng));
  EXPECT_FALSE(mutate(bare, MutationOp::kChangeWeight, rng));
  EXPECT_FALSE(mutate(bare, MutationOp::kRemoveNode, rng));
  EXPECT_FALSE(mutate(bare, MutationOp::kChangeActivation, rng));
  Cppn full = minimal_cppn();  // every input already feeds the output
  EXPECT_FALSE(mutate(full, MutationOp::kAddLink, rng));
}

TEST(EvoCppn, RandomNetworksFollowTheRecipeAndVary) {
  std::set<std::string> shapes;
  for (uint64_t id = 0; id < 50; ++id) {
    Rng rng = Rng::stream(1, StreamPurpose::kTest, 0, id);
    const Cppn n = random_cppn(rng);
    validate(n);
    EXPECT_EQ(n.hidden_count(), 5);  // five node additions, never removed
    std::string key;
    for (const CppnLink& l : n.links)
      key += std::to_string(l.source) + ">" + std::to_string(l.target) + " ";
    shapes.insert(key);
  }
  EXPECT_GT(shapes.size(), 40u);
}

TEST(EvoCppn, ValidateRejectsBrokenNetworks) {
  Cppn n = minimal_cppn();
  n.links.push_back({5, 5, 0.1});
  EXPECT_THROW(validate(n), std::invalid_argument);
  n = minimal_cppn();
  n.links[0].weight = 2.0;
  EXPECT_THROW(validate(n), std::invalid_argument);
  n = minimal_cppn();
  std::swap(n.links[0], n.links[1]);
  EXPECT_THROW(validate(n), std::invalid_argument);
  n = minimal_cppn();
  n.nodes.back() = Activation::kSin;
  EXPECT_THROW(validate(n), std::invalid_argument);
}

}  // namespace
}  // namespace plastivox::evo
