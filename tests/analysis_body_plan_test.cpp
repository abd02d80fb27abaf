// Body-plan classification on hand-built canonical Π, Γ and Υ bodies, their quarter turns
// about z, and shapes that are none of them.
#include <cmath>
#include <cstdio>
#include <functional>

#include "plastivox/analysis/body_plan.hpp"
#include "plastivox/analysis/rng.hpp"
#include "plastivox/evo/genome.hpp"
#include "plastivox/evo/phenotype.hpp"
#include "test_support.hpp"

namespace plastivox::analysis {
namespace {

// A body on the 10^3 lattice: every site where `filled` says so.
VoxelSet body(const std::function<bool(int, int, int)>& filled) {
  VoxelSet s;
  for (int z = 0; z < 10; ++z)
    for (int y = 0; y < 10; ++y)
      for (int x = 0; x < 10; ++x)
        if (filled(x, y, z)) s.voxels.push_back({x, y, z});
  return s;
}

// Π: front and back legs two voxels thick over the full width, a bridge three voxels thick.
VoxelSet pi_body() {
  return body([](int x, int, int z) { return x < 2 || x >= 8 || z >= 7; });
}
// Γ, side view L: a wall two thick and a floor plate two thick meeting at one end.
VoxelSet gamma_body() {
  return body([](int x, int, int z) { return x < 2 || z < 2; });
}
// Γ, plan view L: two full-height walls meeting at a corner.
VoxelSet gamma_plan_body() {
  return body([](int x, int y, int) { return x < 2 || y < 3; });
}
// Υ: a 10x10 vertical plate two thick and a round leg of radius 2 from its centre.
VoxelSet upsilon_body() {
  return body([](int x, int y, int z) {
    const double dy = y + 0.5 - 5, dz = z + 0.5 - 5;
    return x < 2 || dy * dy + dz * dz <= 4.0;
  });
}

VoxelSet turned(const VoxelSet& s, int quarter_turns) {
  const Rotation z90 = paper_rotations()[2];  // +90 deg about z
  VoxelSet out = s;
  for (int k = 0; k < quarter_turns; ++k) out = rotate_in_lattice(out, z90);
  return out;
}

void expect_plan(const VoxelSet& s, BodyPlan expected, const char* what) {
  const BodyPlanResult first = classify_body_plan(s);
  std::printf("%-10s -> %-7s confidence %.3f margin %.3f | Π %.3f (%s) Γ %.3f (%s) Υ %.3f (%s)\n",
              what, to_string(first.plan), first.confidence, first.margin,
              first.features.matches[0].score, first.features.matches[0].parameters.c_str(),
              first.features.matches[1].score, first.features.matches[1].parameters.c_str(),
              first.features.matches[2].score, first.features.matches[2].parameters.c_str());
  for (int k = 0; k < 4; ++k) {
    const BodyPlanResult r = classify_body_plan(turned(s, k));
    EXPECT_EQ(r.plan, expected) << what << " turned " << k << " times";
    EXPECT_EQ(r.confidence, first.confidence) << what << " turned " << k << " times";
    for (int p = 0; p < 3; ++p)
      EXPECT_EQ(r.features.matches[p].score, first.features.matches[p].score) << what << " " << k;
  }
}

TEST(BodyPlan, CanonicalShapesAndTheirQuarterTurnsClassifyCorrectly) {
  expect_plan(pi_body(), BodyPlan::kPi, "Π");
  expect_plan(gamma_body(), BodyPlan::kGamma, "Γ side");
  expect_plan(gamma_plan_body(), BodyPlan::kGamma, "Γ plan");
  expect_plan(upsilon_body(), BodyPlan::kUpsilon, "Υ");
}

TEST(BodyPlan, CanonicalShapesMatchTheirTemplateExactly) {
  EXPECT_EQ(classify_body_plan(pi_body()).confidence, 1.0);
  EXPECT_EQ(classify_body_plan(pi_body()).features.matches[0].parameters, "legs 2+2, bridge 3");
  EXPECT_EQ(classify_body_plan(gamma_body()).confidence, 1.0);
  EXPECT_EQ(classify_body_plan(upsilon_body()).confidence, 1.0);
}

TEST(BodyPlan, CubesAndSlabsAreOther) {
  expect_plan(body([](int, int, int) { return true; }), BodyPlan::kOther, "10-cube");
  expect_plan(body([](int x, int y, int z) { return x < 6 && y < 6 && z < 6; }), BodyPlan::kOther,
              "6-cube");
  expect_plan(body([](int, int, int z) { return z < 3; }), BodyPlan::kOther, "floor slab");
}

TEST(BodyPlan, ToleratesSomeNoise) {
  // Remove 5 % of a Π's voxels at random: still a Π.
  Rng rng(8);
  VoxelSet noisy;
  for (const Voxel& v : pi_body().voxels)
    if (rng.uniform() >= 0.05) noisy.voxels.push_back(v);
  expect_plan(noisy, BodyPlan::kPi, "noisy Π");
}

TEST(BodyPlan, FeaturesDescribeTheBody) {
  const BodyPlanResult r = classify_body_plan(pi_body());
  EXPECT_EQ(r.features.extent, (Voxel{10, 10, 10}));
  EXPECT_EQ(r.features.voxels, int(pi_body().voxels.size()));
  EXPECT_EQ(r.features.footprint_components, (std::vector<int>{20, 20}));  // two legs
  EXPECT_EQ(classify_body_plan(gamma_body()).features.footprint_components,
            (std::vector<int>{100}));
  EXPECT_STREQ(symbol(BodyPlan::kUpsilon), "Υ");
  EXPECT_THROW(classify_body_plan(VoxelSet{}), std::invalid_argument);
}

// The hand-built geometry networks of a body-plan start (evolution config
// initial_population: body-plans) express bodies that the rule names as their plan with full
// confidence, on the default study's 6^3 lattice and larger ones.
TEST(BodyPlan, HandBuiltGenomesExpressTheirPlanOnSmallAndPaperLattices) {
  const BodyPlan expected[evo::kBodyPlanSeedCount] = {BodyPlan::kPi, BodyPlan::kGamma,
                                                      BodyPlan::kUpsilon};
  for (int n : {6, 8, 10}) {
    evo::ExpressionDef def;
    def.nx = def.ny = def.nz = n;
    const evo::Expresser ex(def);
    for (int plan = 0; plan < evo::kBodyPlanSeedCount; ++plan) {
      const evo::Cppn net = evo::body_plan_geometry(plan);
      ASSERT_NO_THROW(evo::validate(net));
      evo::Genome g;
      g.nets.fill(net);
      const evo::Phenotype p = ex.express(g);
      ASSERT_TRUE(p.valid) << n << " " << plan << ": " << p.invalid_reason;
      VoxelSet b;
      for (int z = 0; z < n; ++z)
        for (int y = 0; y < n; ++y)
          for (int x = 0; x < n; ++x)
            if (p.robot.present[p.robot.site(x, y, z)]) b.voxels.push_back({x, y, z});
      const BodyPlanResult r = classify_body_plan(b);
      EXPECT_EQ(r.plan, expected[plan]) << n << "^3, plan " << plan;
      EXPECT_GE(r.confidence, 0.8) << n << "^3, plan " << plan;
    }
  }
  EXPECT_THROW(evo::body_plan_geometry(3), std::invalid_argument);
}

}  // namespace
}  // namespace plastivox::analysis
