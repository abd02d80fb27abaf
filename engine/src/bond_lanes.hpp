// The batched bond kernel, part 1: the scalar lane type and the inputs of a bond. Included,
// in this order, by each bond_kernel*.cpp: this header, that file's own vector lane type
// (its operations must be declared before the template that uses them: vector types have
// no namespace for argument-dependent lookup), then bond_lanes_body.hpp.
//
// Everything here has internal linkage (unnamed namespace): the files are compiled for
// different instruction sets, and no copy of an inline function built for AVX-512 may be
// picked by the linker for code that runs on a CPU without it. For the same reason this
// code calls only C library functions (sqrt, atan) and compiler intrinsics.
#pragma once

#include <cmath>
#include <cstdint>

#include "atan_series.hpp"
#include "bond_kernel.hpp"
#include "lane_ops.hpp"

namespace plastivox {
namespace {

// Inputs of one bond (or of a group of lanes): what the kernel reads from the voxels.
template <class T>
struct BondIn {
  T dx, dy, dz;      // centre of b minus centre of a, m, world frame
  T ax, ay, az, aw;  // orientation of a
  T bx, by, bz, bw;  // orientation of b
  T size_a, size_b;  // actuated sizes, m
  T ea, eb;          // moduli, Pa
  T valid;           // 1 if the previous deformation is recorded, else 0
};

inline void append_redo(bool redo, int i, const BondKernelIo& io, int& count) {
  if (redo) io.redo[count++] = i;
}

// Column/component selection by the bond's lattice axis d: v0 if d = 0, v1 if 1, v2 if 2.
struct Axis1 {
  int d;
  double operator()(double v0, double v1, double v2) const {
    return d == 0 ? v0 : d == 1 ? v1 : v2;
  }
};

inline BondIn<double> gather(const BondKernelIo& io, int b, double) {
  const int ia = io.bond_a[b], ib = io.bond_b[b];
  const double* pa = io.pos + 3 * ia;
  const double* pb = io.pos + 3 * ib;
  const double* qa = io.quat + 4 * ia;
  const double* qb = io.quat + 4 * ib;
  BondIn<double> in;
  in.dx = pb[0] - pa[0], in.dy = pb[1] - pa[1], in.dz = pb[2] - pa[2];
  in.ax = qa[0], in.ay = qa[1], in.az = qa[2], in.aw = qa[3];
  in.bx = qb[0], in.by = qb[1], in.bz = qb[2], in.bw = qb[3];
  in.size_a = io.size[ia], in.size_b = io.size[ib];
  in.ea = io.stiff[ia], in.eb = io.stiff[ib];
  in.valid = io.prev_valid[b] ? 1.0 : 0.0;
  return in;
}

// The 4-double records (x, y, z, w) of the voxels idx[0 .. width), one value per component.
inline void load_records(const double* records, const int* idx, double* c) {
  const double* r = records + 4 * static_cast<size_t>(idx[0]);
  c[0] = r[0], c[1] = r[1], c[2] = r[2], c[3] = r[3];
}

inline Axis1 axis_select(const BondKernelIo& io, int b, double) {
  return Axis1{io.axis[b]};
}

}  // namespace
}  // namespace plastivox
