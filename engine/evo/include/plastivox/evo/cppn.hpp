// Compositional pattern-producing networks (CPPNs): the genome of one robot property.
//
// A network is a feed-forward DAG kept in topological order: nodes [0, 5) are the inputs
// x, y, z, d, bias; then hidden nodes; the last node is the single output. A link always
// goes from a lower to a higher node index, so evaluating nodes in index order is a valid
// schedule and no cycle can ever form. Links are kept sorted by (target, source): each
// node sums its inputs in that fixed order, so evaluation is bit-reproducible.
//
// Non-finite values never propagate through arithmetic: a node whose input sum or
// activation is not finite becomes NaN (quiet, assigned, never computed), which marks the
// phenotype invalid. No floating-point exception is raised on any path.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "plastivox/evo/rng.hpp"

namespace plastivox::evo {

// Node activations. The seven hidden ones are docs/method.md §6's; kIdentity is used by
// the inputs (which pass their value through) and the output (a plain weighted sum; the
// output mapping applies the logistic, see phenotype.hpp).
enum class Activation : uint8_t {
  kSin = 0,
  kAbs = 1,
  kNegAbs = 2,
  kSquare = 3,
  kNegSquare = 4,
  kSqrtAbs = 5,
  kNegSqrtAbs = 6,
  kIdentity = 7,
};
constexpr int kHiddenActivationCount = 7;  // codes 0..6
const char* to_string(Activation a);
double activate(Activation a, double x);  // x finite; result may overflow to +-inf

constexpr int kInputCount = 5;  // x, y, z, d, bias (in that node order)

struct CppnLink {
  int source = 0;     // node index, < target
  int target = 0;     // node index, >= kInputCount
  double weight = 0;  // in [-1, 1]
};

struct Cppn {
  std::vector<Activation> nodes;  // topological order: inputs, hidden..., output (last)
  std::vector<CppnLink> links;    // sorted by (target, source); at most one per pair

  int node_count() const { return static_cast<int>(nodes.size()); }
  int output() const { return node_count() - 1; }
  int hidden_count() const { return node_count() - kInputCount - 1; }
  bool operator==(const Cppn&) const;
};

// Throws std::invalid_argument describing the first broken invariant (node layout,
// activation codes, link order, ranges, duplicates, weights outside [-1, 1] or non-finite).
void validate(const Cppn& net);

// The per-site input values of a lattice: x, y, z rescaled to [-1, 1] (0 for an axis of
// extent 1), d the Euclidean norm of (x, y, z) min-max rescaled to [-1, 1] over the
// lattice, and bias 1. Sites in RobotDef order (x fastest).
struct CppnInputs {
  int sites = 0;
  std::array<std::vector<double>, kInputCount> values;  // [input][site]
};
CppnInputs lattice_inputs(int nx, int ny, int nz);

// Evaluates net at every site: out[site] = output value (NaN where non-finite arose).
// scratch is resized as needed; pass the same vector to avoid reallocating.
void evaluate(const Cppn& net, const CppnInputs& in, std::vector<double>& out,
              std::vector<double>& scratch);
std::vector<double> evaluate(const Cppn& net, const CppnInputs& in);

// ---- Mutation (docs/method.md §6) ----
enum class MutationOp : uint8_t {
  kAddNode = 0,           // split a random link a->b into a->h (old weight), h->b (weight 1)
  kRemoveNode = 1,        // delete a random hidden node and its links
  kAddLink = 2,           // link a random unlinked forward pair, weight +0.1 or -0.1
  kRemoveLink = 3,        // delete a random link
  kChangeActivation = 4,  // give a random hidden node a different hidden activation
  kChangeWeight = 5,      // add N(0, 0.5^2) to a random link's weight, clipped to [-1, 1]
};
constexpr int kMutationOpCount = 6;
const char* to_string(MutationOp op);

// Applies op in place, drawing from rng. Returns false (net unchanged) when the operator
// cannot apply: no link to split/remove/change, no hidden node, no free pair to link.
bool mutate(Cppn& net, MutationOp op, Rng& rng);

// Every input linked to the output with weight 0, no hidden nodes.
Cppn minimal_cppn();

// A new random network: minimal_cppn(), then 5 node additions, 10 link additions, 5 link
// removals, 100 activation changes and 100 weight changes (operators that cannot apply
// at that moment are skipped).
Cppn random_cppn(Rng& rng);

}  // namespace plastivox::evo
