// The hand-written adjoints of the bond stage and the voxel update (engine/grad/src/
// bond_adjoint.hpp, voxel_adjoint.hpp) against the same kernels recorded on a tape (the
// reference): bonds along each axis, with and without damping, with either stress rule and
// with the shear chord floored; voxels in the air and on the floor sliding, stopping, held by
// static friction and slipping from rest. Every input's adjoint agrees to 1e-12 of the largest
// of its kind. And whole gradients with the stages' adjoints (the gather's too) against the
// same gradients recorded operation by operation.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>

#include "adj.hpp"
#include "bond_adjoint.hpp"
#include "plastivox/demo_robots.hpp"
#include "plastivox/grad/gradient.hpp"
#include "plastivox/model.hpp"
#include "plastivox/simd.hpp"
#include "plastivox/simulator.hpp"
#include "scalar_bond_adjoint.hpp"
#include "voxel_adjoint.hpp"

namespace plastivox::grad {
namespace {

// A unit quaternion (x, y, z, w) turned from the identity by about `angle` radians.
void turned(double* q, double angle, double seed) {
  const double ax[3] = {std::sin(seed), std::cos(1.3 * seed), std::sin(2.1 * seed + 1)};
  const double n = std::sqrt(ax[0] * ax[0] + ax[1] * ax[1] + ax[2] * ax[2]);
  for (int c = 0; c < 3; ++c) q[c] = std::sin(angle / 2) * ax[c] / n;
  q[3] = std::cos(angle / 2);
}

// Bond from voxel a to voxel b along `axis`, nominal length L, with small offsets, turns and a
// previous deformation; every input a tape node (ids 0..27).
BondArgs bond(const ModelConstants& k, int axis, double angle, double seed, bool valid) {
  BondArgs a;
  for (int c = 0; c < 3; ++c) {
    a.v[kCentreA + c] = 0.01 * std::sin(seed + c);
    a.v[kCentreB + c] =
        a.v[kCentreA + c] + (c == axis ? k.size : 0.0) + 0.03 * k.size * std::cos(3 * seed + c);
  }
  a.v[kCentreA + 3] = k.size * (1 + 0.05 * std::sin(seed));
  a.v[kCentreB + 3] = k.size * (1 - 0.04 * std::cos(seed));
  turned(a.v + kQuatA, angle, seed);
  turned(a.v + kQuatB, 0.7 * angle, seed + 2);
  a.v[kStiffA] = 1e6 * (1 + 0.3 * std::sin(seed));
  a.v[kStiffB] = 2e6 * (1 + 0.2 * std::cos(seed));
  for (int j = 0; j < 9; ++j) a.v[kPrev + j] = 1e-3 * std::sin(seed + 0.7 * j);
  a.v[kDamp] = 3e3;
  for (int j = 0; j < kBondInputs; ++j) a.id[j] = j;
  a.axis = axis;
  a.valid = valid ? 1 : 0;
  return a;
}

// hand[j] against tape[j] for j in [from, from + count), to 1e-12 of the largest |tape[j]|.
void within(const double* hand, const double* tape, int from, int count) {
  double top = 0;
  for (int j = from; j < from + count; ++j) top = std::max(top, std::abs(tape[j]));
  for (int j = from; j < from + count; ++j)
    EXPECT_LE(std::abs(hand[j] - tape[j]), 1e-12 * top)
        << "input " << j << " hand " << hand[j] << " tape " << tape[j];
}

// The two reverses of one bond for a spread of output adjoints; returns whether the hand path
// took it.
bool agree(const BondArgs& a, const ModelConstants& k, double seed) {
  double out[kBondOutputs];
  for (int o = 0; o < kBondOutputs; ++o) out[o] = std::sin(seed + 1.9 * o) * (o < 9 ? 1 : 1e-3);
  double hand[kBondInputs] = {}, tape[kBondInputs] = {};
  if (!bond_reverse(a, k, out, hand)) return false;
  bond_reverse_tape(a, k, out, tape);
  // Compare each input's adjoint within its kind (positions, sizes, orientations, moduli,
  // deformations, damping: their scales differ by orders of magnitude).
  const int kinds[][2] = {{kCentreA, 3}, {kCentreB, 3}, {kCentreA + 3, 1}, {kCentreB + 3, 1},
                          {kQuatA, 8},   {kStiffA, 2},  {kPrev, 9},        {kDamp, 1}};
  for (const auto& [from, count] : kinds) within(hand, tape, from, count);
  return true;
}

TEST(BondAdjoint, HandWrittenReverseEqualsTheTapes) {
  const Model m = compile(demo_walker(), PhysicsDef{});
  int taken = 0;
  for (int axis = 0; axis < 3; ++axis)
    for (int valid = 0; valid < 2; ++valid)
      for (double angle : {0.0, 1e-3, 0.05, 0.3})
        for (double seed : {0.4, 1.7, 2.9}) {
          ModelConstants k = m;
          k.axial_own = seed > 2;
          taken += agree(bond(k, axis, angle, seed, valid), k, seed + axis) ? 1 : 0;
        }
  EXPECT_EQ(taken, 3 * 2 * 4 * 3);  // every one of these rotations is on the hand path
}

TEST(BondAdjoint, FlooredShearChordEqualsTheTapes) {
  ModelConstants k = compile(demo_walker(), PhysicsDef{});
  k.min_shear_chord = 2 * k.size;  // every chord below the floor
  EXPECT_TRUE(agree(bond(k, 1, 0.05, 0.8, true), k, 0.3));
}

TEST(BondAdjoint, LargeRotationsAreLeftToTheTape) {
  const Model m = compile(demo_walker(), PhysicsDef{});
  // Past pi/16 of relative turn the arctangent takes its wide branch: the hand path declines.
  double out[kBondOutputs] = {1}, in[kBondInputs] = {};
  EXPECT_FALSE(bond_reverse(bond(m, 0, 1.2, 0.4, true), m, out, in));
  for (double g : in) EXPECT_EQ(g, 0.0);
}

// Under Voxelyze 0.9 a bond's scalar path reversed by hand (scalar_bond_reverse.cpp) against
// the same path recorded on a small tape: in either frame as the bond enters the step (small),
// so with the switch of frames both ways, damping on and off, turns from none to a radian (both
// forms of its rotation vectors), chords along the axis (the first-order frame) and turned from
// it (the arccosine's frame).
TEST(BondAdjoint, Voxelyze09HandWrittenReverseEqualsTheTapes) {
  PhysicsDef def;
  def.bond_model = BondModel::kVoxelyze09;
  const Model m = compile(demo_walker(), def);
  int taken = 0, cases = 0;
  BondTape tape;
  for (int axis = 0; axis < 3; ++axis)
    for (int valid = 0; valid < 2; ++valid)
      for (int small = 0; small < 2; ++small)
        for (double angle : {0.0, 1e-3, 0.012, 0.05, 0.3, 1.0})
          for (double seed : {0.4, 1.7, 2.9}) {
            ModelConstants k = m;
            k.axial_own = seed > 2;
            BondArgs a = bond(k, axis, angle, seed, valid);
            if (seed < 1) {  // a unturned, the chord along its axis: the first-order frame
              turned(a.v + kQuatA, 0.0, seed);
              for (int c = 0; c < 3; ++c)
                a.v[kCentreB + c] = a.v[kCentreA + c] + (c == axis ? 1.05 * k.size : 0.0);
            }
            double out[kBondOutputs];
            for (int o = 0; o < kBondOutputs; ++o)
              out[o] = std::sin(seed + angle + 1.9 * o) * (o < 9 ? 1 : 1e-3);
            double hand[kBondInputs] = {}, taped[kBondInputs] = {};
            ++cases;
            if (!voxelyze_bond_reverse(a, small, k, out, hand)) continue;
            ++taken;
            tape.reverse(&scalar_bond_forward, a, small, k, out, taped);
            const int kinds[][2] = {{kCentreA, 3},     {kCentreB, 3}, {kCentreA + 3, 1},
                                    {kCentreB + 3, 1}, {kQuatA, 8},   {kStiffA, 2},
                                    {kPrev, 9},        {kDamp, 1}};
            for (const auto& [from, count] : kinds) within(hand, taped, from, count);
          }
  EXPECT_EQ(taken, cases);
  // A chord of zero length takes a constant frame: left to the tape.
  BondArgs crushed = bond(m, 0, 0.05, 0.4, true);
  for (int c = 0; c < 3; ++c) crushed.v[kCentreB + c] = crushed.v[kCentreA + c];
  double out[kBondOutputs] = {1}, in[kBondInputs] = {};
  EXPECT_FALSE(voxelyze_bond_reverse(crushed, false, m, out, in));
  for (double g : in) EXPECT_EQ(g, 0.0);
}

// A voxel of the walker's model at height z (m) with momentum p (kg m/s), lateral force f (N),
// turning at omega (rad/s); every input a tape node.
VoxelArgs voxel(const ModelConstants& k, double z, const double* p, double f, double omega) {
  VoxelArgs a;
  a.v[kVE] = 1e6;
  a.v[kVSqrtE] = std::sqrt(a.v[kVE]);
  const double force[3] = {f, -0.6 * f, -0.3};
  const double pos[3] = {0.02, -0.01, z};
  for (int c = 0; c < 3; ++c) {
    a.v[kVForce + c] = force[c];
    a.v[kVLinMom + c] = p[c];
    a.v[kVPos + c] = pos[c];
    a.v[kVAngMom + c] = k.inertia * omega * (c + 1) / 3;
    a.v[kVMoment + c] = 1e-6 * (c - 1);
  }
  a.v[kVSize] = k.size * 1.02;
  turned(a.v + kVQuat, 0.1, 0.5);
  a.v[kVDt] = 1e-4;
  for (int j = 0; j < kVoxelInputs; ++j) a.id[j] = j;
  a.fixed = 0;
  a.was_held = 0;
  return a;
}

bool voxel_agree(const VoxelArgs& a, const ModelConstants& k) {
  double out[kVoxelOutputs];
  for (int o = 0; o < kVoxelOutputs; ++o) out[o] = std::cos(0.7 + 2.3 * o);
  double hand[kVoxelInputs] = {}, tape[kVoxelInputs] = {};
  if (!voxel_reverse(a, k, out, hand)) return false;
  voxel_reverse_tape(a, k, out, tape);
  const int kinds[][2] = {{kVE, 1},    {kVSqrtE, 1},  {kVForce, 3},  {kVLinMom, 3}, {kVPos, 3},
                          {kVSize, 1}, {kVAngMom, 3}, {kVMoment, 3}, {kVQuat, 4},   {kVDt, 1}};
  for (const auto& [from, count] : kinds) within(hand, tape, from, count);
  return true;
}

TEST(VoxelAdjoint, HandWrittenReverseEqualsTheTapesOnAndOffTheFloor) {
  const Model m = compile(demo_walker(), PhysicsDef{});
  ASSERT_TRUE(m.flat_floor);
  const double L = m.size, mass = m.mass;
  const double still[3] = {0, 0, 0}, sliding[3] = {0.1 * mass, 0.05 * mass, -0.01 * mass};
  const double creeping[3] = {1e-12 * mass, 0, 0};
  EXPECT_TRUE(voxel_agree(voxel(m, 2 * L, sliding, 0.01, 1.0), m));     // in the air
  EXPECT_TRUE(voxel_agree(voxel(m, 0.4 * L, sliding, 0.01, 1.0), m));   // slides
  EXPECT_TRUE(voxel_agree(voxel(m, 0.4 * L, creeping, 0.01, 1.0), m));  // stops
  EXPECT_TRUE(voxel_agree(voxel(m, 0.4 * L, still, 1e-9, 1.0), m));     // held
  EXPECT_TRUE(voxel_agree(voxel(m, 0.4 * L, still, 1e9, 1.0), m));      // slips from rest
}

// Under Voxelyze 0.9 the update turns a voxel by its first-order step, normalised, and a
// voxel left within about 3e-8 rad of the lattice not at all: the hand-written reverse takes
// both, large turns too, on and off the floor.
TEST(VoxelAdjoint, Voxelyze09HandWrittenReverseEqualsTheTapes) {
  PhysicsDef def;
  def.bond_model = BondModel::kVoxelyze09;
  const Model m = compile(demo_walker(), def);
  const double L = m.size, mass = m.mass;
  const double still[3] = {0, 0, 0}, sliding[3] = {0.1 * mass, 0.05 * mass, -0.01 * mass};
  EXPECT_TRUE(voxel_agree(voxel(m, 2 * L, sliding, 0.01, 1.0), m));    // in the air
  EXPECT_TRUE(voxel_agree(voxel(m, 0.4 * L, sliding, 0.01, 1.0), m));  // slides
  EXPECT_TRUE(voxel_agree(voxel(m, 0.4 * L, still, 1e9, 1.0), m));     // slips from rest
  EXPECT_TRUE(voxel_agree(voxel(m, 2 * L, sliding, 0.01, 1e4), m));    // 0.5 rad a step
  VoxelArgs unturned = voxel(m, 2 * L, sliding, 0.01, 1e-6);           // stays unturned
  for (int c = 0; c < 4; ++c) unturned.v[kVQuat + c] = c == 3 ? 1.0 : 0.0;
  EXPECT_TRUE(voxel_agree(unturned, m));
  VoxelArgs clamped = voxel(m, 2 * L, sliding, 0.01, 1.0);
  clamped.fixed = 1;
  double out[kVoxelOutputs] = {1}, in[kVoxelInputs] = {};
  EXPECT_FALSE(voxel_reverse(clamped, m, out, in));
}

TEST(VoxelAdjoint, ClampedVoxelsAndLargeTurnsAreLeftToTheTape) {
  const Model m = compile(demo_walker(), PhysicsDef{});
  const double p[3] = {0, 0, 0};
  double out[kVoxelOutputs] = {1}, in[kVoxelInputs] = {};
  EXPECT_FALSE(voxel_reverse(voxel(m, 2 * m.size, p, 0, 1e4), m, out, in));  // 0.5 rad a step
  VoxelArgs clamped = voxel(m, 2 * m.size, p, 0, 1.0);
  clamped.fixed = 1;
  EXPECT_FALSE(voxel_reverse(clamped, m, out, in));
  for (double g : in) EXPECT_EQ(g, 0.0);
}

// a against b, kind by kind, to `tol` of b's largest.
void same_vector(const std::vector<double>& a, const std::vector<double>& b, double tol,
                 const char* what) {
  ASSERT_EQ(a.size(), b.size()) << what;
  double top = 0;
  for (double v : b) top = std::max(top, std::abs(v));
  EXPECT_GT(top, 0.0) << what;
  for (size_t j = 0; j < a.size(); ++j)
    EXPECT_LE(std::abs(a[j] - b[j]), tol * top) << what << "[" << j << "]";
}

void same_gradient(const Model& m) {
  const Gradient fast = gradient(m);
  g_reference_tape = true;
  const Gradient reference = gradient(m);
  g_reference_tape = false;
  EXPECT_EQ(fast.fitness, reference.fitness);
  // The blocks were used: a step of tape is a fraction of the reference's.
  EXPECT_LT(4.0 * fast.peak_tape_nodes / fast.checkpoint_every,
            1.0 * reference.peak_tape_nodes / reference.checkpoint_every);
  same_vector(fast.stiffness, reference.stiffness, 1e-12, "stiffness");
  same_vector(fast.phase, reference.phase, 1e-12, "phase");
  same_vector(fast.initial_position, reference.initial_position, 1e-12, "initial_position");
  same_vector(fast.initial_velocity, reference.initial_velocity, 1e-12, "initial_velocity");
  EXPECT_NEAR(fast.amplitude, reference.amplitude, 1e-12 * std::abs(reference.amplitude));
  if (m.def.treatment != Treatment::kNone)
    same_vector(fast.dev_rate, reference.dev_rate, 1e-12, "dev_rate");
}

TEST(StageAdjoints, WholeGradientEqualsTheOperationByOperationTapes) {
  PhysicsDef walk;  // the walker on the floor, actuated from 0.02 s
  walk.duration = 0.04;
  walk.settle_time = 0.02;
  same_gradient(compile(demo_walker(), walk));
  // Actuation's clamps: the signal clipped at 0 (contraction only) and the size factor at its
  // floor for the softer voxels' deeper contractions (the recorded actuation's constant sizes).
  PhysicsDef clamped = walk;
  clamped.act_expansion = false;
  clamped.act_min_factor = 0.97;
  same_gradient(compile(demo_walker(), clamped));
  // Clamped voxels, whose update's reverse is the small tape's: it reads their centres, sizes,
  // orientations and moduli from the bond stage's record, as the hand path does.
  RobotDef held = demo_walker();
  for (int v = 0, k = 0; v < held.sites() && k < 3; ++v)
    if (held.present[v]) held.fixed_sites.push_back(v), v += 40, ++k;
  same_gradient(compile(held, walk));
  PhysicsDef develop = walk;  // a developing cube under stress
  develop.duration = 0.1;
  develop.treatment = Treatment::kStress;
  RobotDef cube = demo_cube(3, 1e8);
  for (int v = 0; v < cube.sites(); ++v) {
    cube.stiffness[v] *= 1.5 + std::sin(1.7 * v + 0.3);
    cube.phase[v] = 0.37 * std::sin(0.9 * v);
    cube.dev_rate[v] = 2.0 + std::cos(1.3 * v);
  }
  same_gradient(compile(cube, develop));
}

// Development on doubles, kept as a block whose reverse applies each voxel's rule's partial
// derivatives (Replica::record_development, develop_stage_reverse), against the kernel recorded
// operation by operation: every stimulus under both laws, pressure under both axial moduli,
// and the clamps on a step's change and on the modulus holding for some voxels.
TEST(StageAdjoints, DevelopmentByItsRuleEqualsTheOperationByOperationTape) {
  RobotDef cube = demo_cube(3, 1e8);
  for (int v = 0; v < cube.sites(); ++v) {
    cube.stiffness[v] *= 1.5 + std::sin(1.7 * v + 0.3);
    cube.phase[v] = 0.37 * std::sin(0.9 * v);
    cube.dev_rate[v] = (v % 5 == 0 ? 0.0 : 2.0 + std::cos(1.3 * v)) * (v % 2 ? 1.0 : -1.0);
  }
  PhysicsDef base;
  base.duration = 0.08;
  base.settle_time = 0.02;
  for (Treatment t : {Treatment::kStress, Treatment::kStrain, Treatment::kStrainEnergy,
                      Treatment::kContact, Treatment::kKinetic, Treatment::kPressure}) {
    for (GrowthModel law : {GrowthModel::kIntegral, GrowthModel::kRate}) {
      SCOPED_TRACE(std::string(to_string(t)) + " " + to_string(law));
      PhysicsDef def = base;
      def.treatment = t;
      def.growth = law;
      same_gradient(compile(cube, def));
    }
  }
  PhysicsDef voxel = base;
  voxel.treatment = Treatment::kPressure;
  voxel.axial_modulus = AxialModulus::kNegativeVoxel;
  same_gradient(compile(cube, voxel));
  // A step's change held for the voxels that develop fastest, the modulus for the stiffest
  // (each clamp changes the life, so it holds somewhere; d/d dev_rate is not zero, so not
  // everywhere).
  PhysicsDef held = base;
  held.treatment = Treatment::kStress;
  held.growth = GrowthModel::kRate;
  PhysicsDef change = held, modulus = held;
  change.max_change_per_step = 1e4;
  modulus.e_max = 2.2e8;
  const uint64_t free = simulate(compile(cube, held)).final_state_hash;
  ASSERT_NE(simulate(compile(cube, change)).final_state_hash, free);
  ASSERT_NE(simulate(compile(cube, modulus)).final_state_hash, free);
  same_gradient(compile(cube, change));
  same_gradient(compile(cube, modulus));
  held.max_change_per_step = change.max_change_per_step;
  held.e_max = modulus.e_max;
  same_gradient(compile(cube, held));
}

// Over the engine's life of m: the bond-steps in Voxelyze 0.9's small-angle frame and in its
// chord-aligned frame, and the switches between them.
struct Frames {
  int64_t small = 0, chord = 0, switches = 0;
};
Frames frames(const Model& m) {
  Frames f;
  Simulator sim(m);
  std::vector<uint8_t> last = sim.state().bond_small_angle;
  while (sim.state().status == SimStatus::kRunning) {
    sim.step();
    const std::vector<uint8_t>& now = sim.state().bond_small_angle;
    for (size_t b = 0; b < now.size(); ++b) {
      (now[b] ? f.small : f.chord) += 1;
      f.switches += now[b] != last[b];
    }
    last = now;
  }
  return f;
}

// Under Voxelyze 0.9 every bond takes the scalar path: kept as a block on doubles, its reverse
// the scalar path recorded bond by bond on a small tape of its own. Its gradient equals the one
// recorded operation by operation on the walker, whose actuated bonds bend past the small-angle
// limit (both frames and the switch between them, checked on the engine's life), and on a
// developing cube; and under the exact model, on a body whose bonds bend near half a turn, so
// that the batched kernel hands bonds back to the scalar path (kept in its block too).
TEST(StageAdjoints, ScalarPathBlocksEqualTheOperationByOperationTapes) {
  PhysicsDef walk;
  walk.duration = 0.06;
  walk.settle_time = 0.02;
  walk.bond_model = BondModel::kVoxelyze09;
  const Model walker = compile(demo_walker(), walk);
  const Frames f = frames(walker);
  std::printf("voxelyze09 walker: %lld bond-steps small-angle, %lld chord-aligned, %lld switches\n",
              static_cast<long long>(f.small), static_cast<long long>(f.chord),
              static_cast<long long>(f.switches));
  EXPECT_GT(f.small, 0);
  EXPECT_GT(f.chord, 0);
  EXPECT_GT(f.switches, 0);
  same_gradient(walker);
  PhysicsDef develop = walk;
  develop.duration = 0.1;
  develop.treatment = Treatment::kStress;
  RobotDef cube = demo_cube(3, 1e8);
  for (int v = 0; v < cube.sites(); ++v) {
    cube.stiffness[v] *= 1.5 + std::sin(1.7 * v + 0.3);
    cube.dev_rate[v] = 2.0 + std::cos(1.3 * v);
  }
  same_gradient(compile(cube, develop));
  PhysicsDef sinks;
  sinks.duration = 0.06;
  sinks.settle_time = 0.02;
  sinks.sinking_invalid = false;
  same_gradient(compile(demo_irregular(150, 1), sinks));
}

// The bits of a vector of doubles.
bool same_bits(const std::vector<double>& a, const std::vector<double>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0;
}

// The bond stage's reverse runs as many bonds at once as the engine's SIMD level
// (bond_reverse_body.hpp): the whole gradient is the same bits at every level, on the walker
// (1296 bonds, whole lane groups) and a developing 3x3x3 cube (54 bonds, a tail of 2 or 6 at
// four and eight lanes); the same cube under bond_model voxelyze09 and an irregular body whose
// bonds bend near half a turn, whose bonds take the scalar path (scalar_bond_adjoint.hpp).
TEST(StageAdjoints, GradientIsTheSameBitsAtEverySimdLevel) {
  PhysicsDef walk;
  walk.duration = 0.04;
  walk.settle_time = 0.02;
  PhysicsDef develop = walk;
  develop.treatment = Treatment::kStress;
  RobotDef cube = demo_cube(3, 1e8);
  for (int v = 0; v < cube.sites(); ++v) cube.stiffness[v] *= 1.5 + std::sin(1.7 * v + 0.3);
  PhysicsDef voxelyze = develop;
  voxelyze.bond_model = BondModel::kVoxelyze09;
  PhysicsDef sinks = walk;
  sinks.duration = 0.06;
  sinks.sinking_invalid = false;
  const SimdLevel best = simd_level();
  for (const Model& m : {compile(demo_walker(), walk), compile(cube, develop),
                         compile(cube, voxelyze), compile(demo_irregular(150, 1), sinks)}) {
    set_simd_level(SimdLevel::kScalar);
    const Gradient scalar = gradient(m);
    for (int level = 1; level <= static_cast<int>(best); ++level) {
      set_simd_level(static_cast<SimdLevel>(level));
      const Gradient g = gradient(m);
      const char* name = to_string(static_cast<SimdLevel>(level));
      EXPECT_TRUE(same_bits(g.stiffness, scalar.stiffness)) << name;
      EXPECT_TRUE(same_bits(g.phase, scalar.phase)) << name;
      EXPECT_TRUE(same_bits(g.dev_rate, scalar.dev_rate)) << name;
      EXPECT_TRUE(same_bits(g.initial_position, scalar.initial_position)) << name;
      EXPECT_TRUE(same_bits(g.initial_velocity, scalar.initial_velocity)) << name;
    }
  }
  set_simd_level(best);
}

}  // namespace
}  // namespace plastivox::grad
