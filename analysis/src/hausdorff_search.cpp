// Minimising d_H(A, placed B) over rotations and integer translations of B, exactly.
//
// The search is branch and bound on squared distances (all integers, so every comparison is
// exact):
//   1. Every rotation R is tried at one starting shift: rotate_in_lattice's shift without
//      translation search (then this is all there is), else the shift that centres B's
//      bounding box on A's. The best so far, best2, bounds everything after.
//   2. With translation search, for each rotation the shifts t that could still beat best2 are
//      enumerated: along each axis k, the 1-D Hausdorff distance between the projections of A
//      and of R B + t onto axis k is a lower bound of d_H (projection never increases
//      distances), so shifts whose bound reaches best2 are excluded without looking at them.
//      The rest are visited in increasing order of their bound (ties: lexicographic t), and the
//      visit stops once the bound reaches best2.
//   3. Visiting a placement evaluates both directed distances with early exit: as soon as one
//      voxel is at least sqrt(best2) from the other set, the placement cannot win. That voxel
//      is moved to the front of its query order, because the voxel that refuted one placement
//      usually refutes its neighbours at once.
// Nothing that could be strictly better than the answer is ever skipped, so the minimum is
// exact; the placement reported is the first one that reached it in this visiting order.
#include "hausdorff_search.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <tuple>

namespace plastivox::analysis::detail {

PreparedShape::PreparedShape(const VoxelSet& s, int field_pad)
    : set(s), index(s.voxels, field_pad) {
  for (int k = 0; k < 3; ++k) {
    std::vector<int>& p = projection[k];
    for (const Voxel& v : s.voxels) p.push_back(v[k]);
    std::sort(p.begin(), p.end());
    p.erase(std::unique(p.begin(), p.end()), p.end());
  }
}

namespace {

constexpr int64_t kUnbounded = std::numeric_limits<int64_t>::max();

// One rotation R of B, with everything a placement R b + t needs precomputed: B's voxels
// rotated (for queries against A) and A's voxels taken into B's frame by R^-1 (for queries
// against B), each also as offsets into the other set's distance field, so that a placement
// whose points all fall inside the field costs one addition and one load per voxel.
struct RotatedB {
  Rotation r, r_inv;
  std::vector<Voxel> voxels;                   // R b for every b, in B's order
  Voxel lo{}, hi{};                            // their bounding box
  std::array<std::vector<int>, 3> projection;  // sorted distinct coordinates per axis
  std::vector<int> voxels_in_a_field;          // a.index.linear(R b)
  std::vector<Voxel> a_in_b;                   // R^-1 a for every a, in A's order
  Voxel a_lo{}, a_hi{};                        // their bounding box
  std::vector<int> a_in_b_field;               // b.index.linear(R^-1 a)
};

// Bounding box of points rotated by r, from the box lo..hi of the unrotated points.
void rotated_box(const Rotation& r, const Voxel& lo, const Voxel& hi, Voxel* rlo, Voxel* rhi) {
  const Voxel p = rotate_voxel(r, lo), q = rotate_voxel(r, hi);
  for (int k = 0; k < 3; ++k) {
    (*rlo)[k] = std::min(p[k], q[k]);
    (*rhi)[k] = std::max(p[k], q[k]);
  }
}

RotatedB rotate(const PreparedShape& a, const PreparedShape& b, const Rotation& r) {
  RotatedB out;
  out.r = r;
  out.r_inv = inverse(r);
  out.voxels.reserve(b.set.voxels.size());
  out.voxels_in_a_field.reserve(b.set.voxels.size());
  out.a_in_b.reserve(a.set.voxels.size());
  out.a_in_b_field.reserve(a.set.voxels.size());
  for (const Voxel& v : b.set.voxels) {
    out.voxels.push_back(rotate_voxel(r, v));
    out.voxels_in_a_field.push_back(a.index.linear(out.voxels.back()));
  }
  rotated_box(r, b.index.box_lo(), b.index.box_hi(), &out.lo, &out.hi);
  for (const Voxel& v : a.set.voxels) {
    out.a_in_b.push_back(rotate_voxel(out.r_inv, v));
    out.a_in_b_field.push_back(b.index.linear(out.a_in_b.back()));
  }
  rotated_box(out.r_inv, a.index.box_lo(), a.index.box_hi(), &out.a_lo, &out.a_hi);
  // Row k of r holds one +-1 at column j: the new axis k is +-(old axis j).
  for (int k = 0; k < 3; ++k)
    for (int j = 0; j < 3; ++j) {
      const int sign = r.m[k][j];
      if (sign == 0) continue;
      for (int c : b.projection[j]) out.projection[k].push_back(sign * c);
      if (sign < 0) std::reverse(out.projection[k].begin(), out.projection[k].end());
    }
  return out;
}

// Largest integer d with d*d < x (x >= 1).
int64_t isqrt_below(int64_t x) {
  int64_t d = static_cast<int64_t>(std::sqrt(static_cast<double>(x)));
  while (d > 0 && d * d >= x) --d;
  while ((d + 1) * (d + 1) < x) ++d;
  return d;
}

int floor_half(int v) {
  return v >= 0 ? v / 2 : -((-v + 1) / 2);
}

// Squared 1-D Hausdorff distance between sorted sets p and q + t.
int64_t hausdorff_1d_sq(const std::vector<int>& p, const std::vector<int>& q, int t) {
  auto directed = [](const std::vector<int>& from, const std::vector<int>& to, int shift_to) {
    int worst = 0;
    for (int x : from) {
      // Nearest element of (to + shift_to) to x, by binary search in the sorted set.
      const auto it = std::lower_bound(to.begin(), to.end(), x - shift_to);
      int best = std::numeric_limits<int>::max();
      if (it != to.end()) best = *it + shift_to - x;
      if (it != to.begin()) best = std::min(best, x - (*(it - 1) + shift_to));
      worst = std::max(worst, best);
    }
    return worst;
  };
  const int64_t h = std::max(directed(p, q, t), directed(q, p, -t));
  return h * h;
}

// Evaluates placements of B against A with early exit, keeping the query orders between calls.
class PlacementEvaluator {
 public:
  PlacementEvaluator(const PreparedShape& a, const PreparedShape& b) : a_(a), b_(b) {
    order_a_.resize(a.set.voxels.size());
    order_b_.resize(b.set.voxels.size());
    for (size_t i = 0; i < order_a_.size(); ++i) order_a_[i] = static_cast<int>(i);
    for (size_t i = 0; i < order_b_.size(); ++i) order_b_[i] = static_cast<int>(i);
  }

  // Squared d_H of A and {R b + t}: exact when below bound2, else some value >= bound2.
  int64_t operator()(const RotatedB& rb, const Voxel& t, int64_t bound2) {
    // A -> placed B, asked in B's frame: R^-1 (a - t) = R^-1 a - s.
    const Voxel s = rotate_voxel(rb.r_inv, t);
    int64_t worst = directed(b_.index, rb.a_in_b, rb.a_in_b_field, rb.a_lo, rb.a_hi,
                             {-s[0], -s[1], -s[2]}, bound2, order_a_);
    if (worst >= bound2) return worst;
    // Placed B -> A: R b + t.
    return std::max(worst, directed(a_.index, rb.voxels, rb.voxels_in_a_field, rb.lo, rb.hi, t,
                                    bound2, order_b_));
  }

 private:
  // max over i of the squared distance from points[i] + shift to `to`, with early exit at
  // bound2 (the refuting point then moves to the front of `order`).
  static int64_t directed(const NearestVoxel& to, const std::vector<Voxel>& points,
                          const std::vector<int>& field_offsets, const Voxel& lo, const Voxel& hi,
                          const Voxel& shift, int64_t bound2, std::vector<int>& order) {
    int64_t worst = 0;
    const Voxel slo = {lo[0] + shift[0], lo[1] + shift[1], lo[2] + shift[2]};
    const Voxel shi = {hi[0] + shift[0], hi[1] + shift[1], hi[2] + shift[2]};
    if (to.in_field(slo, shi)) {
      // Fast path: every shifted point is inside the field.
      const Voxel& dims = to.field_dims();
      const int off = shift[0] + dims[0] * (shift[1] + dims[1] * shift[2]);
      const int32_t* field = to.field();
      for (size_t k = 0; k < order.size(); ++k) {
        const int64_t d2 = field[field_offsets[order[k]] + off];
        if (d2 >= bound2) return refuted(order, k, d2);
        worst = std::max(worst, d2);
      }
      return worst;
    }
    for (size_t k = 0; k < order.size(); ++k) {
      const Voxel& p = points[order[k]];
      const int64_t d2 =
          to.dist2_below({p[0] + shift[0], p[1] + shift[1], p[2] + shift[2]}, bound2);
      if (d2 >= bound2) return refuted(order, k, d2);
      worst = std::max(worst, d2);
    }
    return worst;
  }

  // Moves order[k] to the front, keeping the others in order (recent refuters first).
  static int64_t refuted(std::vector<int>& order, size_t k, int64_t d2) {
    std::rotate(order.begin(), order.begin() + k, order.begin() + k + 1);
    return d2;
  }

  const PreparedShape& a_;
  const PreparedShape& b_;
  std::vector<int> order_a_, order_b_;
};

struct Candidate {
  int64_t bound2;  // lower bound of the squared d_H at this shift
  Voxel t;
  bool operator<(const Candidate& o) const { return std::tie(bound2, t) < std::tie(o.bound2, o.t); }
};

// Shifts of rb whose projection bound is below best2, in visiting order.
std::vector<Candidate> candidate_shifts(const PreparedShape& a, const RotatedB& rb, int64_t best2) {
  const int64_t d = isqrt_below(best2);
  std::array<std::vector<std::pair<int, int64_t>>, 3> axis;  // (shift, squared 1-D bound)
  for (int k = 0; k < 3; ++k) {
    // The bounding-box extremes already bound the shift: |amin - rbmin - t| <= d and
    // |amax - rbmax - t| <= d.
    const int c1 = a.index.box_lo()[k] - rb.lo[k], c2 = a.index.box_hi()[k] - rb.hi[k];
    const int lo = static_cast<int>(std::max(c1, c2) - d);
    const int hi = static_cast<int>(std::min(c1, c2) + d);
    for (int t = lo; t <= hi; ++t) {
      const int64_t h2 = hausdorff_1d_sq(a.projection[k], rb.projection[k], t);
      if (h2 < best2) axis[k].push_back({t, h2});
    }
  }
  std::vector<Candidate> out;
  for (const auto& [tx, hx] : axis[0])
    for (const auto& [ty, hy] : axis[1])
      for (const auto& [tz, hz] : axis[2]) {
        const int64_t b2 = std::max({hx, hy, hz});
        if (b2 < best2) out.push_back({b2, {tx, ty, tz}});
      }
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace

HausdorffResult search_placements(const PreparedShape& a, const PreparedShape& b,
                                  const HausdorffOptions& options) {
  const std::vector<Rotation>& rotations = rotation_set(options.rotations);
  const bool shift_search = options.translation == TranslationSearch::kInteger;
  PlacementEvaluator evaluate(a, b);

  int64_t best2 = kUnbounded;
  int best_r = 0;
  Voxel best_t{};
  auto consider = [&](int r, const RotatedB& rb, const Voxel& t) {
    const int64_t d2 = evaluate(rb, t, best2);
    if (d2 < best2) {
      best2 = d2;
      best_r = r;
      best_t = t;
    }
  };

  // 1. One starting shift per rotation.
  std::vector<RotatedB> rotated;
  std::vector<Voxel> start(rotations.size());
  for (size_t r = 0; r < rotations.size(); ++r) {
    rotated.push_back(rotate(a, b, rotations[r]));
    const RotatedB& rb = rotated.back();
    if (shift_search) {
      for (int k = 0; k < 3; ++k)
        start[r][k] = floor_half(a.index.box_lo()[k] - rb.lo[k] + a.index.box_hi()[k] - rb.hi[k]);
    } else {
      start[r] = lattice_shift(b.set.lattice, rotations[r]);
    }
    consider(static_cast<int>(r), rb, start[r]);
  }

  // 2. Every other shift that might still win.
  if (shift_search) {
    for (size_t r = 0; r < rotations.size() && best2 > 0; ++r) {
      for (const Candidate& c : candidate_shifts(a, rotated[r], best2)) {
        if (c.bound2 >= best2) break;
        if (c.t == start[r]) continue;
        consider(static_cast<int>(r), rotated[r], c.t);
      }
    }
  }

  HausdorffResult res;
  res.distance2 = best2;
  res.distance = std::sqrt(static_cast<double>(best2));
  res.rotation_index = best_r;
  res.rotation = rotations[best_r];
  res.translation = best_t;
  res.rotations = options.rotations;
  res.translation_search = options.translation;
  return res;
}

}  // namespace plastivox::analysis::detail
