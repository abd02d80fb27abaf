// Canalization metrics on hand-made stiffness and alpha arrays (docs/method.md §8, D-F).
#include <cmath>
#include <vector>

#include "plastivox/analysis/canalization.hpp"
#include "test_support.hpp"

namespace plastivox::analysis {
namespace {

TEST(Canalization, MBodyAndVBodyEqualTheFormulas) {
  // Relative changes |E+/E0 - 1|: 0.5, 0.5 (softened by half), 1.0, 0.
  const std::vector<double> e0 = {1e6, 2e6, 1e9, 3e7};
  const std::vector<double> ef = {1.5e6, 1e6, 2e9, 3e7};
  const Canalization c = canalization(e0, ef);
  EXPECT_EQ(c.voxels, 4);
  EXPECT_DOUBLE_EQ(c.m_body, (0.5 + 0.5 + 1.0 + 0.0) / 4);  // 0.5
  // Population variance (divide by n = 4, numpy's default): deviations 0, 0, 0.5, -0.5.
  EXPECT_DOUBLE_EQ(c.v_body, (0.25 + 0.25) / 4);
}

TEST(Canalization, NoChangeGivesZero) {
  const std::vector<double> e = {1e5, 1e7, 1e11};
  const Canalization c = canalization(e, e);
  EXPECT_EQ(c.m_body, 0.0);
  EXPECT_EQ(c.v_body, 0.0);
}

TEST(Canalization, UniformChangeHasNoSpatialVariance) {
  const std::vector<double> e0 = {1e6, 4e8, 2e10}, ef = {3e6, 1.2e9, 6e10};  // all x3
  const Canalization c = canalization(e0, ef);
  EXPECT_DOUBLE_EQ(c.m_body, 2.0);
  EXPECT_NEAR(c.v_body, 0.0, 1e-28);
}

TEST(Canalization, RejectsBadInput) {
  const std::vector<double> two = {1, 2}, three = {1, 2, 3}, none, bad = {1, 0};
  EXPECT_THROW(canalization(none, none), std::invalid_argument);
  EXPECT_THROW(canalization(two, three), std::invalid_argument);
  EXPECT_THROW(canalization(bad, two), std::invalid_argument);
}

TEST(VGain, IsThePopulationVarianceOfMinMaxNormalisedAlpha) {
  // The paper's stress range -10.00 .. 6.42 (width 16.42).
  const AlphaRange stress{-10.0, 6.42};
  const std::vector<double> alpha = {-10.0, 6.42, -1.79};  // normalised: 0, 1, 0.5
  const double w = 16.42;
  const double n0 = 0, n1 = 1, n2 = (-1.79 + 10.0) / w;
  const double m = (n0 + n1 + n2) / 3;
  const double expect = ((n0 - m) * (n0 - m) + (n1 - m) * (n1 - m) + (n2 - m) * (n2 - m)) / 3;
  EXPECT_DOUBLE_EQ(v_gain(alpha, stress), expect);
  // Normalising removes the range's scale: the same pattern over another range gives the same.
  const AlphaRange pressure{-5.36, 5.63};
  const std::vector<double> scaled = {-5.36, 5.63, -5.36 + 10.99 * n2};
  EXPECT_NEAR(v_gain(scaled, pressure), expect, 1e-15);
}

TEST(VGain, RejectsEmptyAlphaAndDegenerateRange) {
  const std::vector<double> none, one = {1.0};
  EXPECT_THROW(v_gain(none, {0, 1}), std::invalid_argument);
  EXPECT_THROW(v_gain(one, {2, 2}), std::invalid_argument);
}

TEST(VGain, EvolvedRangeSpansAllChampions) {
  const AlphaRange r = evolved_alpha_range({{-1.0, 2.0}, {}, {-5.36, 5.63, 0.0}});
  EXPECT_EQ(r.min, -5.36);
  EXPECT_EQ(r.max, 5.63);
  EXPECT_THROW(evolved_alpha_range({{}, {}}), std::invalid_argument);
}

TEST(Canalization, BodyValuesFollowModelVoxelOrder) {
  RobotDef r = make_empty_robot(2, 2, 1);
  r.present = {0, 1, 1, 0};
  r.stiffness = {9, 1e6, 2e6, 9};
  EXPECT_EQ(body_values(r, r.stiffness), (std::vector<double>{1e6, 2e6}));
  // And the order matches the engine's per-voxel arrays.
  const Model m = compile(r, PhysicsDef{});
  EXPECT_EQ(body_values(r, r.stiffness), m.e0);
  EXPECT_THROW(body_values(r, std::vector<double>(3)), std::invalid_argument);
}

}  // namespace
}  // namespace plastivox::analysis
