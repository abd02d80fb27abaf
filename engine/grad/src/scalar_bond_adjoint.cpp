// The scalar bond path and Voxelyze 0.9's time step in the replica (scalar_bond_adjoint.hpp).
#include "scalar_bond_adjoint.hpp"

#include <cmath>

namespace plastivox::grad {

// The C library's functions the Voxelyze 0.9 model takes (scalar_bond_body.hpp): their
// values, and their derivatives. acos's is infinite at +-1; there it is taken as 0, as root's
// at 0 (adj.hpp): the model reaches acos(+-1) only where the result is not used (a chord
// within 1e-7 rad of backwards takes a constant frame).
inline Adj acos_of(Adj a) {
  const double s = 1.0 - a.v * a.v;
  return {std::acos(a.v), record(a.id, s > 0 ? -1.0 / std::sqrt(s) : 0.0, -1, 0.0)};
}
inline Adj sin_of(Adj a) {
  return {std::sin(a.v), record(a.id, std::cos(a.v), -1, 0.0)};
}
inline Adj cos_of(Adj a) {
  return {std::cos(a.v), record(a.id, -std::sin(a.v), -1, 0.0)};
}
template <class F>
inline Adj with_slope(double v, Adj x, F&& slope) {
  return {v, record(x.id, slope(), -1, 0.0)};
}

}  // namespace plastivox::grad

// After the recording type's vocabulary: the template finds it by argument-dependent lookup.
#include "adj_elementary.hpp"
#include "scalar_bond_body.hpp"

namespace plastivox::grad {

void scalar_bonds(const Model& m, KernelViews& v, Adj damp, const int* bonds, int count) {
  const int n = bonds ? count : m.bond_count();
  for (int r = 0; r < n; ++r)
    scalar_bond_lanes<Adj>(v.bond, v.small_angle_in_state, v.small_angle_next, bonds ? bonds[r] : r,
                           m, damp);
}

void scalar_bond_forward(const BondKernelIo& io, const uint8_t* small_in, uint8_t* small_out,
                         const ModelConstants& k, Adj damp) {
  scalar_bond_lanes<Adj>(io, small_in, small_out, 0, k, damp);
}

Adj voxelyze_dt_adj(const Model& m, const double* E, std::vector<int>* near) {
  const int32_t* ids = g_tape ? g_tape->ids_of(E) : nullptr;
  const auto at = [&](int i) { return Adj(E[i], ids ? ids[i] : -1); };
  const double area = m.size * m.size;
  // The maximum on doubles (the same bits as on the recording type), then recorded for the bond
  // that std::max keeps: the first to reach it.
  const auto stiffness = [&](const auto& e1, const auto& e2) {
    return (e1 * e2 / (e1 + e2)) * 2.0 * area / m.size;
  };
  double k = 0;
  int top = -1;
  for (int b = 0; b < m.bond_count(); ++b) {
    const double kb = stiffness(E[m.bond_a[b]], E[m.bond_b[b]]);
    if (k < kb) k = kb, top = b;
  }
  Adj k_adj = k;
  if (top >= 0) {
    k_adj = stiffness(at(m.bond_a[top]), at(m.bond_b[top]));
    if (near)
      for (int b = 0; b < m.bond_count(); ++b)
        if (stiffness(E[m.bond_a[b]], E[m.bond_b[b]]) >= k * (1.0 - 1e-9)) near->push_back(b);
  }
  if (m.bond_count() == 0) {
    for (int i = 0; i < m.n; ++i)
      if (k < E[i]) k = E[i], k_adj = at(i);
  }
  return m.def.dt_frac * (1.0 / (root(k_adj / m.mass) * 2.0 * 3.1415926));
}

}  // namespace plastivox::grad
