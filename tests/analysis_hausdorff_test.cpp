// Hausdorff distance: CGAL answer vs. brute force, symmetry, zero for identical and rotated
// copies, exactness of the rotation/translation search, and the pairwise matrix.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <set>

#include "plastivox/analysis/hausdorff.hpp"
#include "plastivox/analysis/rng.hpp"
#include "plastivox/demo_robots.hpp"
#include "test_support.hpp"

namespace plastivox::analysis {
namespace {

// ---- references, written independently of the library --------------------------------------

int64_t brute_directed2(const std::vector<Voxel>& from, const std::vector<Voxel>& to) {
  int64_t worst = 0;
  for (const Voxel& p : from) {
    int64_t best = std::numeric_limits<int64_t>::max();
    for (const Voxel& q : to) {
      int64_t d2 = 0;
      for (int k = 0; k < 3; ++k) d2 += int64_t(p[k] - q[k]) * (p[k] - q[k]);
      best = std::min(best, d2);
    }
    worst = std::max(worst, best);
  }
  return worst;
}

int64_t brute2(const std::vector<Voxel>& a, const std::vector<Voxel>& b) {
  return std::max(brute_directed2(a, b), brute_directed2(b, a));
}

std::vector<Voxel> moved(const std::vector<Voxel>& b, const Rotation& r, const Voxel& t) {
  std::vector<Voxel> out;
  for (const Voxel& v : b) {
    const Voxel q = rotate_voxel(r, v);
    out.push_back({q[0] + t[0], q[1] + t[1], q[2] + t[2]});
  }
  return out;
}

// The least squared distance over every rotation given and every shift within `reach` of zero
// on each axis, by trying them all.
int64_t exhaustive2(const VoxelSet& a, const VoxelSet& b, const std::vector<Rotation>& rotations,
                    int reach) {
  int64_t best = std::numeric_limits<int64_t>::max();
  for (const Rotation& r : rotations)
    for (int tx = -reach; tx <= reach; ++tx)
      for (int ty = -reach; ty <= reach; ++ty)
        for (int tz = -reach; tz <= reach; ++tz)
          best = std::min(best, brute2(a.voxels, moved(b.voxels, r, {tx, ty, tz})));
  return best;
}

// A random set of `count` distinct voxels in an n^3 lattice.
VoxelSet random_set(Rng& rng, int n, int count) {
  std::set<Voxel> s;
  while (static_cast<int>(s.size()) < count)
    s.insert({int(rng.below(n)), int(rng.below(n)), int(rng.below(n))});
  VoxelSet v;
  v.lattice = {n, n, n};
  v.voxels.assign(s.begin(), s.end());
  return v;
}

// ---- the plain distance ----------------------------------------------------------------------

TEST(Hausdorff, EqualsBruteForceOnRandomSets) {
  Rng rng(7);
  for (int trial = 0; trial < 40; ++trial) {
    const int n = 4 + int(rng.below(9));
    const int ca = 1 + int(rng.below(n * n * n / 2)), cb = 1 + int(rng.below(n * n * n / 2));
    const VoxelSet a = random_set(rng, n, ca), b = random_set(rng, n, cb);
    const int64_t expect2 = brute2(a.voxels, b.voxels);
    EXPECT_EQ(hausdorff_distance(a.voxels, b.voxels), std::sqrt(double(expect2)))
        << "trial " << trial;
    // The search code with no rotation and no shift must agree too (it uses the cached
    // field, not the kd-tree directly).
    const HausdorffResult r = hausdorff(a, b);
    EXPECT_EQ(r.distance2, expect2) << "trial " << trial;
  }
}

TEST(Hausdorff, FarApartSetsUseTheKdTreeBeyondTheField) {
  const std::vector<Voxel> a = {{0, 0, 0}, {1, 0, 0}}, b = {{30, 4, -7}, {31, 4, -7}};
  EXPECT_EQ(hausdorff_distance(a, b), std::sqrt(double(brute2(a, b))));
  VoxelSet sa, sb;
  sa.voxels = a;
  sb.voxels = b;
  EXPECT_EQ(hausdorff(sa, sb).distance2, brute2(a, b));
}

TEST(Hausdorff, IsSymmetricAndZeroForIdenticalSets) {
  Rng rng(11);
  for (int trial = 0; trial < 10; ++trial) {
    const VoxelSet a = random_set(rng, 8, 60), b = random_set(rng, 8, 90);
    EXPECT_EQ(hausdorff_distance(a.voxels, b.voxels), hausdorff_distance(b.voxels, a.voxels));
    EXPECT_EQ(hausdorff(a, b, aligned_hausdorff()).distance2,
              hausdorff(b, a, aligned_hausdorff()).distance2);
    EXPECT_EQ(hausdorff_distance(a.voxels, a.voxels), 0.0);
    EXPECT_EQ(hausdorff(a, a, paper_hausdorff()).distance, 0.0);
  }
}

TEST(Hausdorff, RejectsEmptySets) {
  VoxelSet empty, one;
  one.voxels = {{0, 0, 0}};
  EXPECT_THROW(hausdorff_distance(empty.voxels, one.voxels), std::invalid_argument);
  EXPECT_THROW(hausdorff(one, empty), std::invalid_argument);
  EXPECT_THROW(hausdorff_matrix({one, empty}), std::invalid_argument);
}

// ---- rotations -------------------------------------------------------------------------------

TEST(Rotations, CubeGroupHas24DistinctProperRotationsClosedUnderComposition) {
  const std::vector<Rotation>& g = cube_rotations();
  ASSERT_EQ(g.size(), 24u);
  EXPECT_EQ(g[0], identity_rotations()[0]);
  for (size_t i = 0; i < g.size(); ++i) {
    for (size_t j = 0; j < g.size(); ++j) {
      if (i != j) {
        EXPECT_FALSE(g[i] == g[j]);
      }
      const Rotation c = compose(g[i], g[j]);
      EXPECT_TRUE(std::any_of(g.begin(), g.end(), [&](const Rotation& r) { return r == c; }));
    }
    EXPECT_EQ(compose(g[i], inverse(g[i])), g[0]);
  }
}

TEST(Rotations, PaperOrientationsFollowNumpyRot90) {
  const std::vector<Rotation>& p = paper_rotations();
  ASSERT_EQ(p.size(), 8u);
  for (size_t i = 0; i < p.size(); ++i)
    for (size_t j = i + 1; j < p.size(); ++j) {
      EXPECT_FALSE(p[i] == p[j]);
    }
  // numpy.rot90(B, 1, axes=(0,1)) on a 10-lattice sends index (x, y) to (9 - y, x).
  VoxelSet s;
  s.voxels = {{2, 7, 3}};
  EXPECT_EQ(rotate_in_lattice(s, p[2]).voxels[0], (Voxel{9 - 7, 2, 3}));
  // numpy.rot90(B, 1, axes=(1,2)) sends (y, z) to (9 - z, y); index 1 is that turn alone.
  EXPECT_EQ(rotate_in_lattice(s, p[1]).voxels[0], (Voxel{2, 9 - 3, 7}));
  EXPECT_EQ(p[2].name, "(-y,x,z)");
  // A non-cubic lattice swaps its extents under a quarter turn.
  VoxelSet flat;
  flat.lattice = {4, 6, 2};
  flat.voxels = {{3, 0, 0}};
  const VoxelSet turned = rotate_in_lattice(flat, p[2]);
  EXPECT_EQ(turned.lattice, (Voxel{6, 4, 2}));
  EXPECT_EQ(turned.voxels[0], (Voxel{5, 3, 0}));
}

TEST(HausdorffSearch, RotatedAndShiftedCopiesAreAtZeroUnderTheFullSearch) {
  Rng rng(3);
  const VoxelSet a = random_set(rng, 7, 70);
  for (const Rotation& r : cube_rotations()) {
    const Voxel t = {int(rng.below(9)) - 4, int(rng.below(9)) - 4, int(rng.below(9)) - 4};
    VoxelSet b;
    b.voxels = moved(a.voxels, r, t);
    EXPECT_GT(hausdorff(a, b).distance, 0.0) << r.name;  // they differ as placed
    const HausdorffResult res = hausdorff(a, b, aligned_hausdorff());
    EXPECT_EQ(res.distance, 0.0) << r.name;
    EXPECT_EQ(brute2(a.voxels, moved(b.voxels, res.rotation, res.translation)), 0) << r.name;
  }
}

TEST(HausdorffSearch, CopiesTurnedBackByAPaperOrientationAreAtZeroUnderThePaperSearch) {
  Rng rng(5);
  VoxelSet a = random_set(rng, 10, 120);
  for (size_t i = 0; i < paper_rotations().size(); ++i) {
    // B is A turned by the inverse of orientation i, so orientation i brings it back.
    const VoxelSet b = rotate_in_lattice(a, inverse(paper_rotations()[i]));
    const HausdorffResult res = hausdorff(a, b, paper_hausdorff());
    EXPECT_EQ(res.distance, 0.0) << "orientation " << i;
    EXPECT_EQ(res.rotation, paper_rotations()[i]);
  }
}

TEST(HausdorffSearch, PaperSearchEqualsBruteForceOverTheEightOrientations) {
  Rng rng(13);
  for (int trial = 0; trial < 20; ++trial) {
    const VoxelSet a = random_set(rng, 6, 5 + int(rng.below(60)));
    const VoxelSet b = random_set(rng, 6, 5 + int(rng.below(60)));
    int64_t best = std::numeric_limits<int64_t>::max();
    for (const Rotation& r : paper_rotations())
      best = std::min(best, brute2(a.voxels, rotate_in_lattice(b, r).voxels));
    EXPECT_EQ(hausdorff(a, b, paper_hausdorff()).distance2, best) << "trial " << trial;
  }
}

TEST(HausdorffSearch, TranslationSearchEqualsExhaustiveSearch) {
  // Every rotation and every shift in a box far larger than any optimal shift can be:
  // sets lie in a 4^3 lattice, so d_H at the centring shift is <= sqrt(27) and any better
  // shift is within 3 + 6 of zero on each axis.
  Rng rng(17);
  for (int trial = 0; trial < 6; ++trial) {
    const VoxelSet a = random_set(rng, 4, 3 + int(rng.below(14)));
    const VoxelSet b = random_set(rng, 4, 3 + int(rng.below(14)));
    const int64_t best = exhaustive2(a, b, cube_rotations(), 10);
    const HausdorffResult res = hausdorff(a, b, aligned_hausdorff());
    EXPECT_EQ(res.distance2, best) << "trial " << trial;
    EXPECT_EQ(brute2(a.voxels, moved(b.voxels, res.rotation, res.translation)), best);
    // Translation alone (no rotation) is exact too.
    HausdorffOptions shift_only;
    shift_only.translation = TranslationSearch::kInteger;
    EXPECT_EQ(hausdorff(a, b, shift_only).distance2, exhaustive2(a, b, {cube_rotations()[0]}, 10))
        << "trial " << trial;
  }
}

TEST(HausdorffSearch, FieldPadDoesNotChangeResults) {
  Rng rng(19);
  for (int trial = 0; trial < 5; ++trial) {
    const VoxelSet a = random_set(rng, 10, 300), b = random_set(rng, 10, 100);
    HausdorffOptions o0 = aligned_hausdorff(), o9 = aligned_hausdorff();
    o0.field_pad = 0;
    o9.field_pad = 9;
    const HausdorffResult r0 = hausdorff(a, b, o0), r9 = hausdorff(a, b, o9);
    EXPECT_EQ(r0.distance2, r9.distance2);
    EXPECT_EQ(r0.rotation_index, r9.rotation_index);
    EXPECT_EQ(r0.translation, r9.translation);
  }
}

// ---- the matrix ------------------------------------------------------------------------------

std::vector<VoxelSet> champions(int count) {
  std::vector<VoxelSet> sets;
  for (int i = 0; i < count; ++i)
    sets.push_back(voxel_set(demo_irregular(500 + 500 * i / std::max(1, count - 1), 100 + i)));
  return sets;
}

TEST(HausdorffMatrix, MatchesPairwiseCallsAndDoesNotDependOnThreads) {
  const std::vector<VoxelSet> sets = champions(6);
  for (const HausdorffOptions& o : {paper_hausdorff(), aligned_hausdorff()}) {
    const HausdorffMatrix one = hausdorff_matrix(sets, o, 1);
    const HausdorffMatrix three = hausdorff_matrix(sets, o, 3);
    EXPECT_EQ(one.distance, three.distance);
    ASSERT_EQ(one.pairs.size(), 15u);
    int k = 0;
    for (int i = 0; i < 6; ++i) {
      EXPECT_EQ(one.at(i, i), 0.0);
      for (int j = i + 1; j < 6; ++j, ++k) {
        EXPECT_EQ(one.at(i, j), one.at(j, i));
        EXPECT_EQ(one.at(i, j), hausdorff(sets[i], sets[j], o).distance);
        EXPECT_EQ(one.pairs[k].rotation_index, three.pairs[k].rotation_index);
        EXPECT_EQ(one.pairs[k].translation, three.pairs[k].translation);
      }
    }
  }
}

// The figure the study quotes: 190 pairs of 20 champions, 24 rotations, optimal translation.
// Printed, not asserted (the machine is shared); the sanity bound only catches a blow-up.

}  // namespace
}  // namespace plastivox::analysis
