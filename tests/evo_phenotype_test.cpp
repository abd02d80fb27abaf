// Genome -> robot: output mappings, the geometry rules, validity, and variation.
#include <cmath>

#include "plastivox/evo/phenotype.hpp"
#include "plastivox/evo/variation.hpp"
#include "test_support.hpp"

namespace plastivox::evo {
namespace {

// A network whose output is w_x * x + w_b * bias (no hidden nodes).
Cppn affine(double w_x, double w_b) {
  Cppn n = minimal_cppn();
  n.links[0].weight = w_x;
  n.links[4].weight = w_b;
  return n;
}

Genome genome(Cppn geo, Cppn stiff, Cppn devo, Cppn phase) {
  Genome g;
  g.nets = {geo, stiff, devo, phase};
  return g;
}

ExpressionDef small_lattice() {
  ExpressionDef d;
  d.nx = d.ny = d.nz = 5;
  return d;
}

TEST(EvoPhenotype, LogisticIsStableAndMonotone) {
  EXPECT_EQ(logistic(0.0), 0.5);
  EXPECT_EQ(logistic(1000.0), 1.0);
  EXPECT_EQ(logistic(-1000.0), 0.0);
  EXPECT_LT(logistic(-1.0), logistic(1.0));
  EXPECT_DOUBLE_EQ(logistic(2.0) + logistic(-2.0), 1.0);
}

TEST(EvoPhenotype, MappingsHitTheirRanges) {
  const Expresser ex(small_lattice());
  // Saturated outputs reach the range ends; output 0 gives the midpoints.
  NetworkOutputs out;
  for (auto& r : out.raw) r.assign(125, 0.0);
  out.raw[0].assign(125, 1.0);  // all present
  out.raw[1].assign(125, 800.0);
  out.raw[2].assign(125, -800.0);
  out.raw[3].assign(125, 0.0);
  Phenotype p = ex.express(out);
  ASSERT_TRUE(p.valid) << p.invalid_reason;
  EXPECT_EQ(p.voxels, 125);
  for (int s = 0; s < 125; ++s) {
    EXPECT_EQ(p.robot.stiffness[s], 1e11);
    EXPECT_EQ(p.robot.dev_rate[s], -10.0);
    EXPECT_EQ(p.robot.phase[s], 0.0);
  }
  out.raw[1].assign(125, -800.0);
  out.raw[2].assign(125, 800.0);
  out.raw[3].assign(125, 800.0);
  p = ex.express(out);
  for (int s = 0; s < 125; ++s) {
    EXPECT_EQ(p.robot.stiffness[s], 1e5);
    EXPECT_EQ(p.robot.dev_rate[s], 10.0);
    EXPECT_EQ(p.robot.phase[s], 1.0);
  }
  out.raw[1].assign(125, 0.0);
  out.raw[2].assign(125, 0.0);
  out.raw[3].assign(125, -800.0);
  p = ex.express(out);
  EXPECT_EQ(p.robot.stiffness[0], 1e5 + (1e11 - 1e5) * 0.5);
  EXPECT_EQ(p.robot.dev_rate[0], 0.0);
  EXPECT_EQ(p.robot.phase[0], -1.0);
}

TEST(EvoPhenotype, RandomGenomesStayInRange) {
  const Expresser ex(small_lattice());
  for (uint64_t id = 0; id < 40; ++id) {
    Rng rng = Rng::stream(3, StreamPurpose::kTest, 1, id);
    const Phenotype p = ex.express(random_genome(rng));
    for (int s = 0; s < 125; ++s) {
      if (!p.robot.present[s]) {
        EXPECT_EQ(p.robot.stiffness[s], 0.0);
        continue;
      }
      EXPECT_GE(p.robot.stiffness[s], 1e5);
      EXPECT_LE(p.robot.stiffness[s], 1e11);
      EXPECT_GE(p.robot.dev_rate[s], -10.0);
      EXPECT_LE(p.robot.dev_rate[s], 10.0);
      EXPECT_GE(p.robot.phase[s], -1.0);
      EXPECT_LE(p.robot.phase[s], 1.0);
    }
  }
}

TEST(EvoPhenotype, GeometryFromTheSignOfTheOutput) {
  // present iff 0.5*x + 0 > 0: the half of the lattice with x > 0 (x = 0 is absent).
  const Expresser ex(small_lattice());
  const Phenotype p = ex.express(genome(affine(0.5, 0), affine(0, 0), affine(0, 0), affine(0, 0)));
  for (int s = 0; s < 125; ++s) EXPECT_EQ(p.robot.present[s], s % 5 >= 3 ? 1 : 0) << s;
  EXPECT_EQ(p.voxels, 50);
  EXPECT_TRUE(p.valid);
}

TEST(EvoPhenotype, LargestComponentOnKnownShapes) {
  // 4x3x2 lattice: a 3-voxel bar, a 2-voxel bar, an isolated voxel, and an edge-only
  // (not face) contact that must not join components.
  const int nx = 4, ny = 3, nz = 2;
  std::vector<uint8_t> p(nx * ny * nz, 0);
  auto at = [&](int x, int y, int z) -> uint8_t& { return p[x + nx * (y + ny * z)]; };
  at(0, 0, 0) = at(1, 0, 0) = at(2, 0, 0) = 1;  // bar of 3
  at(3, 1, 1) = 1;                              // touches (2,0,0)? no: differs in y and z
  at(0, 2, 0) = at(0, 2, 1) = 1;                // bar of 2 along z
  at(3, 2, 0) = 1;                              // alone
  const std::vector<uint8_t> keep = largest_component(p, nx, ny, nz);
  int kept = 0;
  for (uint8_t k : keep) kept += k;
  EXPECT_EQ(kept, 3);
  EXPECT_EQ(keep[0], 1);
  EXPECT_EQ(keep[1], 1);
  EXPECT_EQ(keep[2], 1);
  // Two equal components: the one with the lowest site wins.
  std::vector<uint8_t> q(nx * ny * nz, 0);
  q[5] = q[6] = 1;    // (1,1,0),(2,1,0)
  q[12] = q[13] = 1;  // (0,0,1),(1,0,1): not face-adjacent to the first pair
  const std::vector<uint8_t> k2 = largest_component(q, nx, ny, nz);
  EXPECT_EQ(k2[5], 1);
  EXPECT_EQ(k2[6], 1);
  EXPECT_EQ(k2[12], 0);
  EXPECT_EQ(k2[13], 0);
  // A full block is one component; an empty lattice keeps nothing.
  EXPECT_EQ(largest_component(std::vector<uint8_t>(24, 1), nx, ny, nz),
            std::vector<uint8_t>(24, 1));
  EXPECT_EQ(largest_component(std::vector<uint8_t>(24, 0), nx, ny, nz),
            std::vector<uint8_t>(24, 0));
}

TEST(EvoPhenotype, KeepAllKeepsEveryPresentVoxel) {
  // Geometry: |x| > 0.6 (two slabs x = 0 and x = 4, not connected): sin? use a hidden abs.
  Cppn geo = minimal_cppn();
  geo.nodes.insert(geo.nodes.end() - 1, Activation::kAbs);  // node 5 = |x|, output 6
  geo.links = {{0, 5, 1.0}, {4, 6, -0.6}, {5, 6, 1.0}};
  validate(geo);
  ExpressionDef d = small_lattice();
  d.min_fill = 0.1;
  const Genome g = genome(geo, affine(0, 0), affine(0, 0), affine(0, 0));
  d.geometry = GeometryRule::kKeepAll;
  EXPECT_EQ(Expresser(d).express(g).voxels, 50);
  d.geometry = GeometryRule::kLargestComponent;
  const Phenotype lcc = Expresser(d).express(g);
  EXPECT_EQ(lcc.voxels, 25);
  EXPECT_EQ(lcc.robot.present[0], 1);  // the x = 0 slab holds the lowest site
  EXPECT_EQ(lcc.robot.present[4], 0);
}

TEST(EvoPhenotype, ValidityNeedsTwentyPercent) {
  const Expresser ex(small_lattice());  // 125 sites: 25 voxels needed
  EXPECT_EQ(ex.min_voxels(), 25);
  // x > 0.5*... : 0.5*x - 0.3 > 0 means x > 0.6: only x = 1 (25 voxels): valid.
  Phenotype p = ex.express(genome(affine(0.5, -0.3), affine(0, 0), affine(0, 0), affine(0, 0)));
  EXPECT_EQ(p.voxels, 25);
  EXPECT_TRUE(p.valid) << p.invalid_reason;
  // Nothing present: invalid with a reason.
  p = ex.express(genome(affine(0, -1), affine(0, 0), affine(0, 0), affine(0, 0)));
  EXPECT_FALSE(p.valid);
  EXPECT_NE(p.invalid_reason.find("fewer than 25"), std::string::npos) << p.invalid_reason;
  ExpressionDef big;  // 10x10x10: 0.2 * 1000 is exactly 200 voxels
  EXPECT_EQ(Expresser(big).min_voxels(), 200);
}

TEST(EvoPhenotype, NaNOutputsMakeItInvalid) {
  const Expresser ex(small_lattice());
  NetworkOutputs out;
  for (auto& r : out.raw) r.assign(125, 0.5);
  out.raw[3][7] = std::numeric_limits<double>::quiet_NaN();
  Phenotype p = ex.express(out);
  EXPECT_FALSE(p.valid);
  EXPECT_NE(p.invalid_reason.find("phase"), std::string::npos);
  out.raw[3][7] = 0.5;
  out.raw[0][100] = std::numeric_limits<double>::quiet_NaN();
  p = ex.express(out);
  EXPECT_FALSE(p.valid);
  EXPECT_NE(p.invalid_reason.find("geometry"), std::string::npos);
}

TEST(EvoPhenotype, DevelopmentIgnoredUnderNone) {
  ExpressionDef d = small_lattice();
  d.uses_development = false;
  const Expresser ex(d);
  const Genome a = genome(affine(0.5, 0.2), affine(0.3, 0), affine(0.9, 0.1), affine(0, 0.4));
  Genome b = a;
  b.nets[2] = affine(-0.7, 0.5);
  const Phenotype pa = ex.express(a), pb = ex.express(b);
  EXPECT_TRUE(pa.same_as(pb));
  EXPECT_EQ(pa.hash, pb.hash);
  for (double r : pa.robot.dev_rate) EXPECT_EQ(r, 0.0);
  // ... but it matters when development is on.
  d.uses_development = true;
  EXPECT_NE(Expresser(d).express(a).hash, Expresser(d).express(b).hash);
}

TEST(EvoVariation, ChildrenDifferFromTheirParentAndAreValid) {
  const Expresser ex(small_lattice());
  Rng r0 = Rng::stream(9, StreamPurpose::kTest, 0, 0);
  const Offspring parent = random_individual(ex, r0, 1500);
  ASSERT_TRUE(parent.success);
  for (uint64_t id = 0; id < 20; ++id) {
    Rng rng = Rng::stream(9, StreamPurpose::kMutation, 1, id);
    const Offspring child =
        mutate_child(ex, parent.genome, parent.outputs, parent.phenotype, rng, 1500);
    ASSERT_TRUE(child.success);
    EXPECT_TRUE(child.phenotype.valid);
    EXPECT_FALSE(child.phenotype.same_as(parent.phenotype));
    EXPECT_GE(child.tries, 1);
    validate(child.genome);
    // The cached outputs equal a fresh evaluation of the child's genome.
    const NetworkOutputs fresh = ex.evaluate(child.genome);
    for (int n = 0; n < kNetworkCount; ++n)
      EXPECT_EQ(0, std::memcmp(fresh.raw[n].data(), child.outputs.raw[n].data(), 125 * 8));
  }
}

TEST(EvoVariation, OnlyDevelopmentChangesNeverCountUnderNone) {
  // A parent whose geometry, stiffness and phase networks cannot change the phenotype in
  // a single try is impossible to build in general; instead: with a budget of one try
  // per child, every successful child must differ outside dev_rate.
  ExpressionDef d = small_lattice();
  d.uses_development = false;
  const Expresser ex(d);
  Rng r0 = Rng::stream(4, StreamPurpose::kTest, 0, 0);
  const Offspring parent = random_individual(ex, r0, 1500);
  int dev_only = 0;
  for (uint64_t id = 0; id < 200; ++id) {
    Rng rng = Rng::stream(4, StreamPurpose::kMutation, 1, id);
    const Offspring child =
        mutate_child(ex, parent.genome, parent.outputs, parent.phenotype, rng, 1);
    const bool others_same = child.genome.nets[0] == parent.genome.nets[0] &&
                             child.genome.nets[1] == parent.genome.nets[1] &&
                             child.genome.nets[3] == parent.genome.nets[3];
    if (child.success) {
      EXPECT_FALSE(others_same);
    } else {
      EXPECT_TRUE(child.genome == parent.genome);
    }
    dev_only += others_same && !(child.genome == parent.genome);
  }
  EXPECT_EQ(dev_only, 0);
}

TEST(EvoVariation, FailedMutationReturnsTheParentUnchanged) {
  // A parent with an all-zero geometry network is invalid: a child that must be valid
  // after one try will (almost always) fail and come back identical.
  const Expresser ex(small_lattice());
  Genome g;
  for (Cppn& n : g.nets) n = minimal_cppn();
  const NetworkOutputs out = ex.evaluate(g);
  const Phenotype p = ex.express(out);
  Rng rng(77);
  const Offspring child = mutate_child(ex, g, out, p, rng, 1);
  if (!child.success) {
    EXPECT_TRUE(child.genome == g);
    EXPECT_EQ(child.tries, 1);
  }
}

}  // namespace
}  // namespace plastivox::evo
