// The self-collision kernels (KernelSet::scan_within and touch_candidates, kernels.hpp) for
// any lane type (lanes.hpp): the search of a refresh, which of a run of points lie within a
// radius of a centre, and the test of the candidate pairs each step.
#pragma once

#include "lanes.hpp"

namespace plastivox {
namespace {

template <class T>
inline int scan_within_lanes(const double* px, const double* py, const double* pz, int e, double x,
                             double y, double z, double r2, int* out) {
  const T dx = load(px, e, T{}) - x, dy = load(py, e, T{}) - y, dz = load(pz, e, T{}) - z;
  int count = 0;
  for_each_lane(mask_not(dx * dx + dy * dy + dz * dz >= r2), [&](int j) { out[count++] = e + j; });
  return count;
}

template <class T>
inline int run_scan_within(const double* px, const double* py, const double* pz, int begin, int end,
                           double x, double y, double z, double r2, int* out) {
  int count = 0;
  over_lanes<T>(end - begin, [&](auto lane, int i) {
    count += scan_within_lanes<decltype(lane)>(px, py, pz, begin + i, x, y, z, r2, out + count);
  });
  return count;
}

// Pairs [p, p + width): those whose centres are within (a hair over) their contact distance.
template <class T>
inline int touch_candidates_lanes(const double* records, const int* pair_a, const int* pair_b,
                                  int p, double half_d, int* out) {
  T a[4], b[4];
  load_records(records, pair_a + p, a);
  load_records(records, pair_b + p, b);
  const T dx = b[0] - a[0], dy = b[1] - a[1], dz = b[2] - a[2];
  const T contact = half_d * (a[3] + b[3]);
  // A relative slack of 1e-9 on the squared distance: the caller decides each candidate with
  // its own exact test, so rounding here can only add candidates, never lose a contact.
  const T limit = contact * contact * (1.0 + 1e-9);
  int count = 0;
  for_each_lane(dx * dx + dy * dy + dz * dz < limit, [&](int j) { out[count++] = p + j; });
  return count;
}

template <class T>
inline int run_touch_candidates(const double* records, const int* pair_a, const int* pair_b, int n,
                                double half_d, int* out) {
  int count = 0;
  over_lanes<T>(n, [&](auto lane, int p) {
    count +=
        touch_candidates_lanes<decltype(lane)>(records, pair_a, pair_b, p, half_d, out + count);
  });
  return count;
}

}  // namespace
}  // namespace plastivox
