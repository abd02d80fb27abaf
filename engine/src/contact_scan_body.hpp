// KernelSet::scan_within (kernels.hpp) for any lane type: the search of a self-collision
// refresh, which of a run of points lie within a radius of a centre. Included after the lane
// operations of the lane types used (see voxel_lanes_body.hpp).
#pragma once

#include "lane_ops.hpp"

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

template <class T, int W>
inline int run_scan_within(const double* px, const double* py, const double* pz, int begin, int end,
                           double x, double y, double z, double r2, int* out) {
  int count = 0, e = begin;
  for (; e + W <= end; e += W)
    count += scan_within_lanes<T>(px, py, pz, e, x, y, z, r2, out + count);
  for (; e < end; ++e) count += scan_within_lanes<double>(px, py, pz, e, x, y, z, r2, out + count);
  return count;
}

}  // namespace
}  // namespace plastivox
