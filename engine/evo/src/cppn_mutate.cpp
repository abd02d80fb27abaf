// The six CPPN mutation operators and the initial-network recipe (docs/method.md §6).
// Every operator keeps the invariants of validate(): topological node order, links sorted
// by (target, source), no duplicate pair, weights in [-1, 1].
#include <algorithm>
#include <iterator>

#include "plastivox/evo/cppn.hpp"

namespace plastivox::evo {
namespace {

void sort_links(Cppn& net) {
  std::sort(net.links.begin(), net.links.end(), [](const CppnLink& a, const CppnLink& b) {
    return a.target != b.target ? a.target < b.target : a.source < b.source;
  });
}

bool linked(const Cppn& net, int source, int target) {
  for (const CppnLink& l : net.links)
    if (l.source == source && l.target == target) return true;
  return false;
}

Activation random_hidden_activation(Rng& rng) {
  return static_cast<Activation>(rng.index(kHiddenActivationCount));
}

bool add_node(Cppn& net, Rng& rng) {
  if (net.links.empty()) return false;
  const CppnLink split = net.links[rng.index(static_cast<int>(net.links.size()))];
  net.links.erase(std::find_if(net.links.begin(), net.links.end(), [&](const CppnLink& l) {
    return l.source == split.source && l.target == split.target;
  }));
  // The new node takes the target's place in the order; everything from there shifts up.
  const int h = split.target;
  for (CppnLink& l : net.links) {
    if (l.source >= h) ++l.source;
    if (l.target >= h) ++l.target;
  }
  net.nodes.insert(net.nodes.begin() + h, random_hidden_activation(rng));
  net.links.push_back({split.source, h, split.weight});
  net.links.push_back({h, split.target + 1, 1.0});
  sort_links(net);
  return true;
}

bool remove_node(Cppn& net, Rng& rng) {
  if (net.hidden_count() == 0) return false;
  const int h = kInputCount + rng.index(net.hidden_count());
  std::erase_if(net.links, [h](const CppnLink& l) { return l.source == h || l.target == h; });
  for (CppnLink& l : net.links) {
    if (l.source > h) --l.source;
    if (l.target > h) --l.target;
  }
  net.nodes.erase(net.nodes.begin() + h);
  return true;  // order is preserved by a monotone renumbering
}

bool add_link(Cppn& net, Rng& rng) {
  // Candidates: source < target, target not an input, pair not yet linked. Enumerated in
  // (target, source) order so the k-th candidate is the same on every platform.
  const int n = net.node_count();
  std::vector<CppnLink> free;
  for (int t = kInputCount; t < n; ++t)
    for (int s = 0; s < t; ++s)
      if (!linked(net, s, t)) free.push_back({s, t, 0.0});
  if (free.empty()) return false;
  CppnLink l = free[rng.index(static_cast<int>(free.size()))];
  l.weight = rng.coin(0.5) ? 0.1 : -0.1;
  net.links.push_back(l);
  sort_links(net);
  return true;
}

bool remove_link(Cppn& net, Rng& rng) {
  if (net.links.empty()) return false;
  net.links.erase(net.links.begin() + rng.index(static_cast<int>(net.links.size())));
  return true;
}

bool change_activation(Cppn& net, Rng& rng) {
  if (net.hidden_count() == 0) return false;
  const int h = kInputCount + rng.index(net.hidden_count());
  // One of the six other hidden activations, uniformly.
  int code = rng.index(kHiddenActivationCount - 1);
  if (code >= static_cast<int>(net.nodes[h])) ++code;
  net.nodes[h] = static_cast<Activation>(code);
  return true;
}

bool change_weight(Cppn& net, Rng& rng) {
  if (net.links.empty()) return false;
  CppnLink& l = net.links[rng.index(static_cast<int>(net.links.size()))];
  l.weight = std::clamp(l.weight + 0.5 * rng.normal(), -1.0, 1.0);
  return true;
}

// Each operator's name and function, in one place: one row per op.
struct Operator {
  MutationOp op;
  const char* name;
  bool (*apply)(Cppn&, Rng&);
};
constexpr Operator kOperators[] = {
    {MutationOp::kAddNode, "add_node", add_node},
    {MutationOp::kRemoveNode, "remove_node", remove_node},
    {MutationOp::kAddLink, "add_link", add_link},
    {MutationOp::kRemoveLink, "remove_link", remove_link},
    {MutationOp::kChangeActivation, "change_activation", change_activation},
    {MutationOp::kChangeWeight, "change_weight", change_weight},
};
static_assert(std::size(kOperators) == kMutationOpCount, "a MutationOp has no row here");

const Operator* operator_of(MutationOp op) {
  for (const Operator& o : kOperators)
    if (o.op == op) return &o;
  return nullptr;
}

}  // namespace

const char* to_string(MutationOp op) {
  const Operator* o = operator_of(op);
  return o ? o->name : "?";
}

bool mutate(Cppn& net, MutationOp op, Rng& rng) {
  const Operator* o = operator_of(op);
  return o && o->apply(net, rng);
}

Cppn minimal_cppn() {
  Cppn net;
  net.nodes.assign(kInputCount + 1, Activation::kIdentity);
  for (int i = 0; i < kInputCount; ++i) net.links.push_back({i, kInputCount, 0.0});
  return net;
}

Cppn random_cppn(Rng& rng) {
  Cppn net = minimal_cppn();
  const struct {
    MutationOp op;
    int times;
  } recipe[] = {{MutationOp::kAddNode, 5},
                {MutationOp::kAddLink, 10},
                {MutationOp::kRemoveLink, 5},
                {MutationOp::kChangeActivation, 100},
                {MutationOp::kChangeWeight, 100}};
  for (const auto& step : recipe)
    for (int i = 0; i < step.times; ++i) mutate(net, step.op, rng);
  return net;
}

}  // namespace plastivox::evo
