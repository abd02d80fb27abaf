// Beam theory: voxel cantilevers against Euler-Bernoulli. Long-running (fine lattices of
// stiff beams need many small steps), so labelled "slow": the sanitizer job skips them.
#include <cmath>

#include "test_support.hpp"

namespace plastivox {
namespace {

using testing::RelNear;

// A horizontal beam of `spans`+1 voxels along x, clamped at x = 0, lifted off the floor.
RobotDef cantilever(int spans, double E) {
  RobotDef r = testing::block(spans + 1, 1, 1, E);
  r.fixed_sites = {0};
  return r;
}

// First bending-mode angular frequency of a clamped beam, rad/s.
double first_mode(double E, double density, int spans) {
  const double L = 0.01, l = spans * L, I = L * L * L * L / 12.0;
  return 3.516 * std::sqrt(E * I / (density * L * L * l * l * l * l));
}

PhysicsDef beam_physics(double E, double density, int spans) {
  PhysicsDef d = testing::passive_physics();
  d.floor = false;
  d.density = density;
  // Global damping near critical for the first bending mode (c = 2 m omega), so it settles
  // within a few periods; statics do not depend on damping.
  const double m = density * 1e-6, L = 0.01;
  d.global_damping = first_mode(E, density, spans) * std::sqrt(m / (E * L));
  return d;
}

// Tip deflection of a clamped beam under its own weight: delta = w l^4 / (8 E I).
class SelfWeightCantilever : public ::testing::TestWithParam<std::tuple<int, double>> {};

TEST_P(SelfWeightCantilever, SagMatchesEulerBernoulli) {
  const auto [spans, E] = GetParam();
  const double L = 0.01, density = 1000.0;
  const Model m = compile(cantilever(spans, E), beam_physics(E, density, spans));
  Simulator sim(m);
  const double l = spans * L, I = L * L * L * L / 12.0, A = L * L;
  testing::run_until(sim, 4 * 2 * M_PI / first_mode(E, density, spans));
  ASSERT_EQ(sim.state().status, SimStatus::kRunning) << sim.state().failure;
  const double w = density * A * 9.81;  // N/m
  const double expected = w * l * l * l * l / (8 * E * I);
  const double sag = m.rest_pos.back().z() - sim.state().pos.back().z();
  // Lumped voxel masses overestimate the continuum sag by ~4/(3 n) (n spans): 3.4 % at
  // n = 40, 2.2 % at n = 60; 5 % is the tolerance.
  EXPECT_TRUE(RelNear(sag, expected, 0.05));
}

INSTANTIATE_TEST_SUITE_P(LengthsAndModuli, SelfWeightCantilever,
                         ::testing::Combine(::testing::Values(40, 60),
                                            ::testing::Values(1e9, 1e10)));

// Tip deflection under an end load: delta = P l^3 / (3 E I), exact for beam elements.
class EndLoadedCantilever : public ::testing::TestWithParam<std::tuple<int, double>> {};

TEST_P(EndLoadedCantilever, TipDeflectionMatchesEulerBernoulli) {
  const auto [spans, E] = GetParam();
  const double L = 0.01, I = L * L * L * L / 12.0, l = spans * L;
  RobotDef r = cantilever(spans, E);
  const double P = 1e-3 * 3 * E * I / (l * l * l) * l;  // tip deflection of 0.1 % of l
  r.loads.push_back({spans, 0, 0, -P});
  PhysicsDef d = beam_physics(E, 1000.0, spans);
  d.gravity = 0;
  const Model m = compile(r, d);
  Simulator sim(m);
  testing::run_until(sim, 4 * 2 * M_PI / first_mode(E, 1000.0, spans));
  ASSERT_EQ(sim.state().status, SimStatus::kRunning) << sim.state().failure;
  const double deflection = m.rest_pos.back().z() - sim.state().pos.back().z();
  EXPECT_TRUE(RelNear(deflection, P * l * l * l / (3 * E * I), 0.02));
}

INSTANTIATE_TEST_SUITE_P(LengthsAndModuli, EndLoadedCantilever,
                         ::testing::Combine(::testing::Values(5, 12), ::testing::Values(1e6, 1e9)));

}  // namespace
}  // namespace plastivox
