// Self-collision between surface voxels that are not close in the bond graph.
//
// Contact is a linear spring between voxel centres that engages when they come closer
// than contact_diameter times their mean actuated size; its stiffness is the harmonic-mean
// axial bond constant E_b L. Candidate pairs are cached: the list holds every pair within
// the largest contact distance plus a margin, and is rebuilt once some surface voxel has
// moved by half the margin relative to the mean motion of the surface since the last
// rebuild. Two voxels then approach by at most twice that (|D_j - D_i| <= |D_j - U| +
// |D_i - U| for any U), so no pair can reach contact unseen; and a body that walks or
// oscillates in place keeps its list. A rebuild bins the surface voxels in a uniform grid
// (cells at least as large as the search radius, kept in the workspace), so it costs about
// as much as a few steps of the pair loop rather than a sweep over all pairs.
//
// Forces are added pair by pair in (i, j) order, i < j. Pairs that do not touch add
// nothing, so the results do not depend on the margin: any candidate list holding every
// touching pair, in that order, gives the same bits.
#include <algorithm>
#include <cmath>

#include "workspace.hpp"

namespace plastivox {
namespace {

// Search margin beyond the largest contact distance, in voxel lengths: a rebuild once a
// surface voxel has drifted 0.45 of it (a little under half, far beyond any rounding).
// Smaller margins mean shorter lists but more frequent rebuilds.
constexpr double kMargin = 0.5;
constexpr double kDriftLimit = 0.45 * kMargin;

// Largest squared displacement of a surface voxel since the last rebuild, relative to the
// surface's mean displacement, m^2.
double drift2(const State& s, const Workspace& w) {
  const ContactGrid& g = w.contact_grid;
  const size_t n = g.voxels.size();
  if (n == 0) return 0;
  Vec3 mean = Vec3::Zero();
  for (size_t k = 0; k < n; ++k) mean += s.pos[g.voxels[k]] - w.contact_ref_pos[k];
  mean /= static_cast<double>(n);
  double max2 = 0;
  for (size_t k = 0; k < n; ++k)
    max2 = std::max(max2, (s.pos[g.voxels[k]] - w.contact_ref_pos[k] - mean).squaredNorm());
  return max2;
}

void rebuild_candidates(const Model& m, const State& s, Workspace& w) {
  const double L = m.size;
  const double contact_max = m.def.contact_diameter * L * (1.0 + m.def.act_amplitude);
  const double radius = contact_max + kMargin * L;
  const double r2 = radius * radius;
  ContactGrid& g = w.contact_grid;
  w.contact_pairs.clear();
  w.contacts_valid = true;

  // Surface voxels in increasing order and their bounding box.
  g.voxels.clear();
  double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  for (int i = 0; i < m.n; ++i) {
    if (!m.surface[i]) continue;
    g.voxels.push_back(i);
    for (int a = 0; a < 3; ++a)
      lo[a] = std::min(lo[a], s.pos[i][a]), hi[a] = std::max(hi[a], s.pos[i][a]);
  }
  w.contact_ref_pos.resize(g.voxels.size());
  for (size_t k = 0; k < g.voxels.size(); ++k) w.contact_ref_pos[k] = s.pos[g.voxels[k]];
  if (g.voxels.size() < 2) return;
  // Cells a little larger than the radius (so rounding in the cell index can never split
  // two voxels within the radius by more than one cell), at most ~8 per surface voxel:
  // a body scattered far (an unstable run) gets coarser cells, never a huge grid.
  double cell = 1.001 * radius;
  const double max_cells = 8.0 * static_cast<double>(g.voxels.size()) + 64.0;
  for (;;) {
    double cells = 1;
    for (int a = 0; a < 3; ++a) cells *= std::floor((hi[a] - lo[a]) / cell) + 1;
    if (cells <= max_cells) break;
    cell *= 2;
  }
  for (int a = 0; a < 3; ++a) g.dim[a] = static_cast<int>(std::floor((hi[a] - lo[a]) / cell)) + 1;
  const int n_cells = g.dim[0] * g.dim[1] * g.dim[2];
  // Counting sort of the surface voxels by cell; within a cell, in increasing voxel order.
  // Members' centres are copied alongside, so a row of cells along x is one
  // contiguous run of coordinates.
  const size_t ns = g.voxels.size();
  g.cell_of.resize(ns);
  g.start.assign(n_cells + 1, 0);
  for (size_t k = 0; k < ns; ++k) {
    const Vec3& p = s.pos[g.voxels[k]];
    int c[3];
    for (int a = 0; a < 3; ++a)
      c[a] = std::min(g.dim[a] - 1, static_cast<int>(std::floor((p[a] - lo[a]) / cell)));
    g.cell_of[k] = (c[2] * g.dim[1] + c[1]) * g.dim[0] + c[0];
    ++g.start[g.cell_of[k] + 1];
  }
  for (int c = 0; c < n_cells; ++c) g.start[c + 1] += g.start[c];
  g.members.resize(ns);
  for (auto& coordinate : g.member_pos) coordinate.resize(ns);
  g.fill.assign(g.start.begin(), g.start.end() - 1);
  for (size_t k = 0; k < ns; ++k) {
    const int e = g.fill[g.cell_of[k]]++;
    g.members[e] = g.voxels[k];
    for (int a = 0; a < 3; ++a) g.member_pos[a][e] = s.pos[g.voxels[k]][a];
  }

  // For each voxel i, the voxels j > i in the 27 cells around it that are not near it in
  // the bond graph, sorted: the same list, in the same order, as testing every pair (i, j)
  // with i < j. near_mark[v] == i marks v as near i.
  g.near_mark.assign(m.n, -1);
  const double* px = g.member_pos[0].data();
  const double* py = g.member_pos[1].data();
  const double* pz = g.member_pos[2].data();
  for (size_t k = 0; k < ns; ++k) {
    const int i = g.voxels[k];
    for (int v : m.near_voxels[i]) g.near_mark[v] = i;
    const double xi = s.pos[i].x(), yi = s.pos[i].y(), zi = s.pos[i].z();
    const int ci = g.cell_of[k];
    const int cx = ci % g.dim[0], cy = (ci / g.dim[0]) % g.dim[1], cz = ci / (g.dim[0] * g.dim[1]);
    const int x0 = std::max(cx - 1, 0), x1 = std::min(cx + 1, g.dim[0] - 1);
    g.found.clear();
    for (int z = std::max(cz - 1, 0); z <= std::min(cz + 1, g.dim[2] - 1); ++z) {
      for (int y = std::max(cy - 1, 0); y <= std::min(cy + 1, g.dim[1] - 1); ++y) {
        const int row = (z * g.dim[1] + y) * g.dim[0];
        const int end = g.start[row + x1 + 1];
        for (int e = g.start[row + x0]; e < end; ++e) {
          const double dx = px[e] - xi, dy = py[e] - yi, dz = pz[e] - zi;
          if (dx * dx + dy * dy + dz * dz >= r2) continue;
          const int j = g.members[e];
          if (j > i && g.near_mark[j] != i) g.found.push_back(j);
        }
      }
    }
    std::sort(g.found.begin(), g.found.end());
    for (int j : g.found) w.contact_pairs.emplace_back(i, j);
  }
}

}  // namespace

void apply_self_collisions(const Model& m, const State& s, Workspace& w) {
  if (!m.def.self_collision) return;
  const double limit = kDriftLimit * m.size;
  if (!w.contacts_valid || drift2(s, w) > limit * limit) rebuild_candidates(m, s, w);
  const double L = m.size;
  const double half_d = 0.5 * m.def.contact_diameter;
  for (const auto& [i, j] : w.contact_pairs) {
    const Vec3 d = s.pos[j] - s.pos[i];
    const double contact = half_d * (w.size[i] + w.size[j]);
    const double dist2 = d.squaredNorm();
    if (dist2 >= contact * contact) continue;
    const double dist = std::sqrt(dist2);
    if (dist == 0) continue;  // coincident centres: no direction to push along
    const double ei = s.stiffness[i], ej = s.stiffness[j];
    const double k = 2.0 * ei * ej / (ei + ej) * L;
    const Vec3 f = d * (k * (contact - dist) / dist);  // pushes j away from i
    for (int c = 0; c < 3; ++c) {
      w.force[c][j] += f[c];
      w.force[c][i] -= f[c];
    }
  }
}

}  // namespace plastivox
