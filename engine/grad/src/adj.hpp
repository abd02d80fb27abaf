// The recording number type of the gradient (docs/gradients.md, "Method"): a double and the
// tape node that made it. The engine's kernel templates (engine/core/src/*_body.hpp) run with
// it as their lane type: every operation computes the same IEEE double as the `double` lane
// does (so the same bits as every instruction set), and appends to the tape the partial
// derivatives of its result with respect to its operands. Reverse accumulation over the tape
// then gives the adjoint of every input.
//
// The kernels read and write raw arrays of doubles (kernels.hpp's views). A loaded value
// finds its node through a shadow array of node ids registered for that array's base address
// (a State row, a Workspace array, a parameter array of the Model); an array with no shadow is
// a constant. A store of a recorded value into an array with no shadow is an error (the
// derivative would be lost), never silent.
//
// Internal linkage for what the kernels call (they are compiled into this library's own
// translation unit): see engine/core/src/lanes.hpp.
#pragma once

#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <vector>

namespace plastivox::grad {

// One node per recorded operation: up to two operands (-1: none) and the partial derivative
// of the result with respect to each.
struct Node {
  int32_t a, b;
  double da, db;
  // Left unwritten by default: the block stages' output leaves (Tape::unswept_leaves) are made
  // by the tens of thousands a step and only their adjoints are ever read.
  Node() {}  // NOLINT(modernize-use-equals-default): = default would zero them in resize
  Node(int32_t a_, int32_t b_, double da_, double db_) : a(a_), b(b_), da(da_), db(db_) {}
};

struct Tape {
  std::vector<Node> nodes;
  // Shadows: for each registered array, its base address and the node of each element (-1:
  // constant), in an open-addressed table (a load looks its array up; a few dozen arrays).
  struct Shadow {
    const double* base = nullptr;
    int32_t* ids = nullptr;
  };
  static constexpr size_t kSlots = 256;
  std::vector<Shadow> table = std::vector<Shadow>(kSlots);
  size_t shadow_count = 0;

  int32_t leaf() {
    nodes.push_back({-1, -1, 0.0, 0.0});
    return static_cast<int32_t>(nodes.size() - 1);
  }
  // `count` leaves whose nodes the sweep never reads (a block stage's outputs, whose adjoints
  // its own reverse takes), left unwritten; returns the first.
  int64_t unswept_leaves(size_t count) {
    const size_t first = nodes.size();
    nodes.resize(first + count);
    return static_cast<int64_t>(first);
  }
  static size_t slot_of(const double* base) {
    return static_cast<size_t>((reinterpret_cast<uintptr_t>(base) >> 3) * 0x9e3779b97f4a7c15ull >>
                               56);
  }
  int32_t* ids_of(const double* base) const {
    for (size_t k = slot_of(base);; k = (k + 1) % kSlots) {
      if (table[k].base == base) return table[k].ids;
      if (!table[k].base) return nullptr;
    }
  }
  void add_shadow(const double* base, int32_t* ids) {
    if (ids_of(base)) throw std::logic_error("gradient: an array registered twice");
    if (2 * ++shadow_count > kSlots) throw std::logic_error("gradient: too many arrays");
    size_t k = slot_of(base);
    while (table[k].base) k = (k + 1) % kSlots;
    table[k] = {base, ids};
  }
  void clear_shadows() {
    table.assign(kSlots, Shadow{});
    shadow_count = 0;
  }
};

// Reverse accumulation over nodes [begin, end) of a tape, last to first: each node's adjoint
// times its partials added to its operands'.
inline void sweep_nodes(const Tape& t, std::vector<double>& adj, size_t begin, size_t end) {
  for (size_t n = end; n-- > begin;) {
    const double a = adj[n];
    if (a == 0) continue;
    const Node& nd = t.nodes[n];
    if (nd.a >= 0) adj[nd.a] += nd.da * a;
    if (nd.b >= 0) adj[nd.b] += nd.db * a;
  }
}

// When set, gradient() records every stage operation by operation, without the stages' own
// adjoints (bond_adjoint.hpp, voxel_adjoint.hpp): the reference they are tested against.
inline thread_local bool g_reference_tape = false;

// The tape being recorded on this thread, or none (values only: the replica's forward).
inline thread_local Tape* g_tape = nullptr;

// The node of a value with operands a and b (-1: a constant) and partials da and db: none
// for two constants, the operand's own for one operand with a partial of exactly 1 (x + c,
// x - c, x * 1: the result's adjoint is the operand's), else the node `add` appends.
template <class Add>
[[gnu::always_inline]] inline int32_t node_of(int32_t a, double da, int32_t b, double db, Add add) {
  if (a < 0 && b < 0) return -1;
  if (a < 0) a = b, da = db, b = -1, db = 0.0;
  if (b < 0 && da == 1.0) return a;
  return add(Node{a, b, da, b < 0 ? 0.0 : db});
}

// Inlined everywhere: the call, not the work, was a third of a replica's step without a tape.
[[gnu::always_inline]] inline int32_t record(int32_t a, double da, int32_t b, double db) {
  if (!g_tape) return -1;
  return node_of(a, da, b, db, [](const Node& n) {
    g_tape->nodes.push_back(n);
    return static_cast<int32_t>(g_tape->nodes.size() - 1);
  });
}

struct Adj {
  double v = 0.0;
  int32_t id = -1;
  Adj() = default;
  Adj(double x) : v(x) {}  // NOLINT: a constant, as the kernels mix doubles in
  Adj(double x, int32_t node) : v(x), id(node) {}
};

inline Adj operator+(Adj a, Adj b) {
  return {a.v + b.v, record(a.id, 1.0, b.id, 1.0)};
}
inline Adj operator-(Adj a, Adj b) {
  return {a.v - b.v, record(a.id, 1.0, b.id, -1.0)};
}
inline Adj operator*(Adj a, Adj b) {
  return {a.v * b.v, record(a.id, b.v, b.id, a.v)};
}
inline Adj operator/(Adj a, Adj b) {
  const double r = a.v / b.v;
  return {r, record(a.id, 1.0 / b.v, b.id, -r / b.v)};
}
inline Adj operator-(Adj a) {
  return {-a.v, record(a.id, -1.0, -1, 0.0)};
}
// A branch taken, folded into an event signature (the replica's; none when null).
inline void note(uint64_t* events, uint64_t v) {
  if (events) *events = (*events ^ v) * 1099511628211ull;
}
// When set, every comparison folds its outcome into *g_branches (the replica's event
// signature, over the stages whose comparisons are all kinks: actuation and development).
inline thread_local uint64_t* g_branches = nullptr;
inline bool branch(bool outcome) {
  note(g_branches, outcome ? 0x9e37u : 0x7f4au);
  return outcome;
}
inline bool operator<(Adj a, Adj b) {
  return branch(a.v < b.v);
}
inline bool operator>(Adj a, Adj b) {
  return branch(a.v > b.v);
}
inline bool operator<=(Adj a, Adj b) {
  return branch(a.v <= b.v);
}
inline bool operator>=(Adj a, Adj b) {
  return branch(a.v >= b.v);
}
inline bool operator==(Adj a, Adj b) {
  return branch(a.v == b.v);
}

// ---- The lane vocabulary (lanes.hpp) for Adj: one element per lane group, masks are bool.
// Found by argument-dependent lookup from the kernel templates.

inline Adj splat(double v, Adj) {
  return Adj(v);
}
inline int32_t node_at(const double* p, size_t i) {
  if (!g_tape) return -1;
  const int32_t* ids = g_tape->ids_of(p);
  return ids ? ids[i] : -1;
}
inline void put(double* p, size_t i, Adj v) {
  p[i] = v.v;
  if (!g_tape) return;
  int32_t* ids = g_tape->ids_of(p);
  if (ids)
    ids[i] = v.id;
  else if (v.id >= 0)
    throw std::logic_error("gradient: a recorded value stored into an array without a shadow");
}
inline Adj load(const double* p, int i, Adj) {
  return {p[i], node_at(p, i)};
}
inline void store(double* p, int i, Adj v) {
  put(p, i, v);
}
inline void load3(const double* p, int i, Adj* c) {
  for (int k = 0; k < 3; ++k) c[k] = Adj(p[3 * i + k], node_at(p, 3 * static_cast<size_t>(i) + k));
}
inline void store3(double* p, int i, const Adj* c) {
  for (int k = 0; k < 3; ++k) put(p, 3 * static_cast<size_t>(i) + k, c[k]);
}
inline void load4(const double* p, int i, Adj* c) {
  for (int k = 0; k < 4; ++k) c[k] = Adj(p[4 * i + k], node_at(p, 4 * static_cast<size_t>(i) + k));
}
inline void store4(double* p, int i, const Adj* c) {
  for (int k = 0; k < 4; ++k) put(p, 4 * static_cast<size_t>(i) + k, c[k]);
}
inline void load_records(const double* records, const int* idx, Adj* c) {
  load4(records, idx[0], c);
}
inline Adj load_indexed(const double* p, const int* idx, int i, Adj) {
  return {p[idx[i]], node_at(p, static_cast<size_t>(idx[i]))};
}
inline bool index_mask_ne(const int* idx, int i, int value, Adj) {
  return idx[i] != value;
}
inline bool mask_eq(const int64_t* p, int i, int64_t value, Adj) {
  return p[i] == value;
}
inline bool load_flag(const uint8_t* p, int i, Adj) {
  return p[i] != 0;
}
// sqrt; at 0 (a norm of a zero vector) the derivative is taken as 0, the subgradient of |x|
// at its kink, rather than the infinite slope of sqrt.
inline Adj root(Adj a) {
  const double r = std::sqrt(a.v);
  return {r, record(a.id, r > 0 ? 0.5 / r : 0.0, -1, 0.0)};
}
// The branch the life took: the derivative of the selected operand (docs/gradients.md,
// "Where a stage has no derivative").
inline Adj pick(bool c, Adj a, Adj b) {
  return c ? a : b;
}
// The value, without its node (terrain_body.hpp's value_of for double: a cell's index).
inline double value_of(Adj a) {
  return a.v;
}
// One lane of a group: the element itself (the update's rotation of more than 0.01 rad in one
// step takes its lanes one by one).
inline Adj lane_get(Adj v, int) {
  return v;
}
inline void lane_set(Adj& v, int, Adj x) {
  v = x;
}

}  // namespace plastivox::grad
