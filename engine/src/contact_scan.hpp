// The search of a self-collision candidate refresh (contacts.cpp): which of a run of points
// lie within a radius of a centre. Lane-generic like the bond and voxel kernels
// (contact_scan_body.hpp), chosen by plastivox/simd.hpp's level; every level finds the same
// points.
#pragma once

namespace plastivox {

// Writes to out, increasing, every e in [begin, end) with
// (px[e] - x)^2 + (py[e] - y)^2 + (pz[e] - z)^2 < r2 (a plain comparison of those rounded
// sums); returns how many. out has room for end - begin entries.
int scan_within(const double* px, const double* py, const double* pz, int begin, int end, double x,
                double y, double z, double r2, int* out);
int scan_within_avx2(const double* px, const double* py, const double* pz, int begin, int end,
                     double x, double y, double z, double r2, int* out);
int scan_within_avx512(const double* px, const double* py, const double* pz, int begin, int end,
                       double x, double y, double z, double r2, int* out);

}  // namespace plastivox
