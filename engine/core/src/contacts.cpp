// Self-collision between surface voxels that are not close in the bond graph.
//
// Contact is a linear spring between voxel centres that engages when they come closer
// than contact_diameter times their mean actuated size; its stiffness is the harmonic-mean
// axial bond constant E_b L.
//
// Candidate pairs are cached per voxel and refreshed voxel by voxel. Positions are taken
// relative to the mean of the surface voxels (Y = X - mean), which changes no distance, so a
// body that walks keeps its lists. When a voxel is refreshed, its partners become exactly the
// voxels within the search radius R = (largest contact distance) + margin at that moment; a
// voxel is refreshed as soon as its Y has moved by delta = margin / 3 (a little less) from
// where it was at its own last refresh. Then no pair can reach contact unseen: a pair that is
// not listed was at least R apart at the later of its two voxels' refreshes, since when the
// later-refreshed voxel moved by less than delta and the other by less than 2 delta (its
// drift is measured from its own, earlier, refresh), so they are still more than
// R - 3 delta >= contact distance apart. Only the voxels that move refresh: a floppy limb
// does not make the whole body rebuild. A refresh compares the voxel with every surface
// voxel (vectorised), or when many refresh at once bins the surface in a uniform grid (cells
// at least as large as R) and looks in the 27 cells around each.
//
// Forces are added pair by pair in (i, j) order, i < j. Pairs that do not touch add
// nothing, so the results do not depend on the margin or on when lists are refreshed: any
// candidate list holding every touching pair, in that order, gives the same bits.
//
// Free objects (Model::robot_n) meet the robot, and each other, through the same lists, as
// the floor meets a voxel (docs/environments.md, "Free objects"): at their mean actuated
// size (faces touching; contact_diameter when that is smaller), with the spring above, the
// floor's normal damping and kinetic friction (collision_body.hpp's pair_contact, which the
// gradient's replica records on the candidates this file finds). Their contacts run even when
// self_collision is off; the robot's own pairs then are left out.
#include <algorithm>
#include <cmath>

#include "collision_body.hpp"
#include "kernels.hpp"
#include "workspace.hpp"

namespace plastivox {
namespace {

// Search margin beyond the largest contact distance, in voxel lengths, and the drift that
// refreshes a voxel's list (a little under a third of it, far beyond any rounding).
constexpr double kMargin = 0.5;
constexpr double kDriftLimit = 0.32 * kMargin;
// Up to this many voxels to refresh in a step, each is compared with every surface voxel (a
// vectorised pass over their centres); more, and the surface is binned in a grid first.
constexpr size_t kDirectRefreshes = 48;

// Bins the surface voxels' current centres in a uniform grid of cells at least `radius`
// wide (coarser if the body is scattered far: at most ~8 cells per surface voxel).
void bin_surface(const State& s, ContactGrid& g, double radius) {
  const size_t ns = g.voxels.size();
  double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  for (int i : g.voxels)
    for (int a = 0; a < 3; ++a)
      lo[a] = std::min(lo[a], s.pos[i][a]), hi[a] = std::max(hi[a], s.pos[i][a]);
  // Cells a little larger than the radius, so rounding in the cell index can never split
  // two voxels within the radius by more than one cell.
  double cell = 1.001 * radius;
  const double max_cells = 8.0 * static_cast<double>(ns) + 64.0;
  for (;;) {
    double cells = 1;
    for (int a = 0; a < 3; ++a) cells *= std::floor((hi[a] - lo[a]) / cell) + 1;
    if (cells <= max_cells) break;
    cell *= 2;
  }
  for (int a = 0; a < 3; ++a) g.dim[a] = static_cast<int>(std::floor((hi[a] - lo[a]) / cell)) + 1;
  const int n_cells = g.dim[0] * g.dim[1] * g.dim[2];
  const double inv_cell = 1.0 / cell;
  // Counting sort by cell; within a cell, in increasing voxel order. Members' centres are
  // copied alongside, so a row of cells along x is one contiguous run of coordinates.
  g.cell_of.resize(ns);
  g.start.assign(n_cells + 1, 0);
  for (size_t k = 0; k < ns; ++k) {
    const Vec3& p = s.pos[g.voxels[k]];
    int c[3];
    for (int a = 0; a < 3; ++a)
      c[a] = std::min(g.dim[a] - 1, static_cast<int>((p[a] - lo[a]) * inv_cell));
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
}

// The surface voxels within `radius` of surface voxel k = g.voxels[k] that are not near it
// in the bond graph, increasing, into g.found: from the grid of bin_surface ...
void find_partners_binned(const Model& m, const State& s, ContactGrid& g, size_t k, double radius) {
  const int i = g.voxels[k];
  const double r2 = radius * radius;
  for (int v : m.near_voxels[i]) g.near_mark[v] = i;  // near_mark[v] == i: v is near i
  const double xi = s.pos[i].x(), yi = s.pos[i].y(), zi = s.pos[i].z();
  const int ci = g.cell_of[k];
  const int cx = ci % g.dim[0], cy = (ci / g.dim[0]) % g.dim[1], cz = ci / (g.dim[0] * g.dim[1]);
  const int x0 = std::max(cx - 1, 0), x1 = std::min(cx + 1, g.dim[0] - 1);
  const double* px = g.member_pos[0].data();
  const double* py = g.member_pos[1].data();
  const double* pz = g.member_pos[2].data();
  g.found.clear();
  for (int z = std::max(cz - 1, 0); z <= std::min(cz + 1, g.dim[2] - 1); ++z) {
    for (int y = std::max(cy - 1, 0); y <= std::min(cy + 1, g.dim[1] - 1); ++y) {
      const int row = (z * g.dim[1] + y) * g.dim[0];
      const int end = g.start[row + x1 + 1];
      for (int e = g.start[row + x0]; e < end; ++e) {
        const double dx = px[e] - xi, dy = py[e] - yi, dz = pz[e] - zi;
        if (dx * dx + dy * dy + dz * dz >= r2) continue;
        const int j = g.members[e];
        if (j != i && g.near_mark[j] != i) g.found.push_back(j);
      }
    }
  }
  std::sort(g.found.begin(), g.found.end());
}

// ... or by comparing with every surface voxel (same voxels: the same distance test).
void find_partners_direct(const Model& m, ContactGrid& g, size_t k, double radius) {
  const int i = g.voxels[k];
  for (int v : m.near_voxels[i]) g.near_mark[v] = i;
  const int hits =
      kernels().scan_within(g.centre[0].data(), g.centre[1].data(), g.centre[2].data(), 0,
                            static_cast<int>(g.voxels.size()), g.centre[0][k], g.centre[1][k],
                            g.centre[2][k], radius * radius, g.within.data());
  g.found.clear();
  for (int h = 0; h < hits; ++h) {
    const int j = g.voxels[g.within[h]];
    if (j != i && g.near_mark[j] != i) g.found.push_back(j);
  }
}

void erase_sorted(std::vector<int>& list, int v) {
  const auto it = std::lower_bound(list.begin(), list.end(), v);
  if (it != list.end() && *it == v) list.erase(it);
}
void insert_sorted(std::vector<int>& list, int v) {
  const auto it = std::lower_bound(list.begin(), list.end(), v);
  if (it == list.end() || *it != v) list.insert(it, v);
}

// Brings every surface voxel's partner list up to date (see the top of this file).
void refresh_partners(const Model& m, const State& s, Workspace& w) {
  const double L = m.size;
  const double radius = m.def.contact_diameter * L * (1.0 + m.act_amplitude_max) + kMargin * L;
  ContactGrid& g = w.contact_grid;
  const bool first = !w.contacts_valid;
  if (first) {
    g.voxels.clear();
    for (int i = 0; i < m.n; ++i)
      if (m.surface[i]) g.voxels.push_back(i);
    g.ref_rel.assign(g.voxels.size(), Vec3::Zero());
    g.partners.assign(m.n, {});
    g.near_mark.assign(m.n, -1);
    w.contacts_valid = true;
  }
  const size_t ns = g.voxels.size();
  if (ns < 2) return;
  for (auto& coordinate : g.centre) coordinate.resize(ns);
  g.within.resize(ns);
  Vec3 mean = Vec3::Zero();
  for (size_t k = 0; k < ns; ++k) {
    const Vec3& p = s.pos[g.voxels[k]];
    mean += p;
    for (int a = 0; a < 3; ++a) g.centre[a][k] = p[a];
  }
  mean /= static_cast<double>(ns);

  const double limit = kDriftLimit * L;
  g.stale.clear();
  for (size_t k = 0; k < ns; ++k) {
    if (first || (s.pos[g.voxels[k]] - mean - g.ref_rel[k]).squaredNorm() > limit * limit)
      g.stale.push_back(static_cast<int>(k));
  }
  if (g.stale.empty()) return;
  const bool direct = g.stale.size() <= kDirectRefreshes;
  if (!direct) bin_surface(s, g, radius);
  for (int k : g.stale) {
    const int i = g.voxels[k];
    if (direct) {
      find_partners_direct(m, g, k, radius);
    } else {
      find_partners_binned(m, s, g, k, radius);
    }
    g.ref_rel[k] = s.pos[i] - mean;
    // i's pairs are now decided by this refresh alone (most refreshes find the same ones).
    if (g.found == g.partners[i]) continue;
    for (int j : g.partners[i]) erase_sorted(g.partners[j], i);
    g.partners[i] = g.found;
    for (int j : g.found) insert_sorted(g.partners[j], i);
    g.pairs_stale = true;
  }
}

// The pairs to test each step, from the partner lists: every (i, j), i < j, of the lists, or
// with self_collision off only those that hold an object voxel (j >= robot_n).
void list_pairs(const Model& m, ContactGrid& g) {
  g.pair_a.clear(), g.pair_b.clear();
  for (int i : g.voxels) {
    const std::vector<int>& list = g.partners[i];
    // Each list is sorted, so i's pairs are the tail of its list past i.
    auto upper = std::upper_bound(list.begin(), list.end(), i);
    if (!m.def.self_collision) upper = std::lower_bound(upper, list.end(), m.robot_n);
    g.pair_a.insert(g.pair_a.end(), static_cast<size_t>(list.end() - upper), i);
    g.pair_b.insert(g.pair_b.end(), upper, list.end());
  }
  g.touching.resize(g.pair_a.size());
  g.pairs_stale = false;
}

}  // namespace

int self_collision_candidates(const Model& m, const State& s, Workspace& w) {
  if (!m.def.self_collision && m.robot_n == m.n) return 0;
  refresh_partners(m, s, w);
  ContactGrid& g = w.contact_grid;
  if (g.pairs_stale) list_pairs(m, g);
  // A vectorised pass keeps the pairs that may touch (nearly all do not), at the robot's
  // contact distance, which is no less than an object's.
  return kernels().touch_candidates(w.centre_size.data(), g.pair_a.data(), g.pair_b.data(),
                                    static_cast<int>(g.pair_a.size()), 0.5 * m.def.contact_diameter,
                                    g.touching.data());
}

// Each candidate is decided exactly, and forces are added pair by pair in (i, j) order, i < j.
void apply_self_collisions(const Model& m, const State& s, Workspace& w) {
  const int n = self_collision_candidates(m, s, w);
  const ContactGrid& g = w.contact_grid;
  for (int c = 0; c < n; ++c) {
    const int p = g.touching[c];
    pair_contact(m, s, w, g.pair_a[p], g.pair_b[p], w.dt_next);
  }
}

}  // namespace plastivox
