// The two halves of a step (Simulator::step1 and step2, simulator.hpp): step1 reads the State
// and writes only the Workspace, so between the halves the State is the state before the
// step. On every instruction set the tests cover, since each has its own bond kernel. And the
// constants the kernels read: the Model's own, made once by compile().
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <type_traits>
#include <vector>

#include <gtest/gtest.h>

#include "kernels.hpp"
#include "plastivox/demo_robots.hpp"
#include "plastivox/simd.hpp"
#include "plastivox/simulator.hpp"
#include "test_support.hpp"
#include "workspace.hpp"

namespace plastivox {
namespace {

// Runs f at every instruction set this build and CPU have, then restores the best.
void at_every_simd_level(const std::function<void()>& f) {
  const SimdLevel best = best_simd_level();
  for (int level = 0; level <= static_cast<int>(best); ++level) {
    set_simd_level(static_cast<SimdLevel>(level));
    SCOPED_TRACE(to_string(simd_level()));
    f();
  }
  set_simd_level(best);
}

// A short developing life: settling ends early, so dt follows the stiffness for most steps.
PhysicsDef developing(BondModel bonds) {
  PhysicsDef d = preset_gecco2018_code();
  d.treatment = Treatment::kStress;
  d.bond_model = bonds;
  d.settle_time = 0.02;
  d.duration = 0.09;
  return d;
}

// The bodies whose step1 takes each path that writes something for the next state: the
// exact model's batched kernel (and its scalar redo, on the irregular body's bent bonds),
// Voxelyze 0.9's scalar path (which switches bond axes), and free objects (whose contacts
// read this step's dt).
struct Body {
  const char* name;
  Model model;
};
std::vector<Body> bodies() {
  PhysicsDef carry = developing(BondModel::kExact);
  carry.task = Task::kCarry;
  return {{"walker, exact", compile(demo_walker(), developing(BondModel::kExact))},
          {"irregular, exact", compile(demo_irregular(500, 7), developing(BondModel::kExact))},
          {"walker, voxelyze09", compile(demo_walker(), developing(BondModel::kVoxelyze09))},
          {"walker carrying", compile(demo_walker(), carry)}};
}

// What step1 leaves in the workspace: the forces and moments, every bond's results, and what
// it computed for the next state.
struct FirstHalf {
  std::array<std::vector<double>, 3> force, moment, bond_out;
  std::vector<double> strain, stress, sqrt_e;
  std::array<std::vector<double>, 9> prev_next;
  std::vector<uint8_t> small_angle_next;
  double dt_next;
  bool operator==(const FirstHalf&) const = default;
};
FirstHalf first_half(const Workspace& w) {
  return {w.force,       w.moment, w.bond_out,       w.bond_strain,
          w.bond_stress, w.sqrt_e, w.bond_prev_next, w.bond_small_angle_next,
          w.dt_next};
}

TEST(Stages, Step1AndSensorsChangeNoByteOfTheState) {
  for (const Body& body : bodies()) {
    SCOPED_TRACE(body.name);
    at_every_simd_level([&] {
      Simulator sim(body.model);
      int dt_changes = 0;
      while (sim.state().status == SimStatus::kRunning) {
        const std::vector<uint8_t> before = save_state(sim.state());
        const double dt = sim.state().dt;
        sim.step1();
        ASSERT_EQ(save_state(sim.state()), before) << "step1 at step " << sim.state().steps;
        const Sensors sensors = sim.sensors();
        for (const SensorField& f : kSensorFields) (void)sensors.read(f.id);
        ASSERT_EQ(save_state(sim.state()), before) << "sensors at step " << sim.state().steps;
        sim.step2();
        dt_changes += sim.state().dt != dt ? 1 : 0;
      }
      EXPECT_EQ(sim.state().status, SimStatus::kFinished) << sim.state().failure;
      EXPECT_GT(dt_changes, 0) << "the life should develop, so step1 computes a new dt";
    });
  }
}

TEST(Stages, Step1TwiceLeavesTheSameWorkspaceAndTheSameLife) {
  for (const Body& body : bodies()) {
    SCOPED_TRACE(body.name);
    at_every_simd_level([&] {
      const uint64_t whole = simulate(body.model).final_state_hash;
      Simulator sim(body.model);
      while (sim.state().status == SimStatus::kRunning) {
        sim.step1();
        const FirstHalf once = first_half(sim.workspace());
        sim.step1();
        ASSERT_TRUE(first_half(sim.workspace()) == once) << "at step " << sim.state().steps;
        sim.step2();
      }
      EXPECT_EQ(state_hash(sim.state()), whole);
    });
  }
}

// A snapshot between the halves is the snapshot before the step, and restoring it (in this
// Simulator, between the halves again, or in a new one) continues the life bit-identically.
TEST(Stages, SaveBetweenTheHalvesIsTheStateBeforeTheStepAndResumes) {
  for (const Body& body : bodies()) {
    SCOPED_TRACE(body.name);
    at_every_simd_level([&] {
      const Model& m = body.model;
      const uint64_t whole = simulate(m).final_state_hash;
      Simulator sim(m);
      testing::run_until(sim, 0.05);
      const std::vector<uint8_t> before = sim.save_state();
      sim.step1();
      const std::vector<uint8_t> between = sim.save_state();
      EXPECT_EQ(between, before);
      (void)sim.sensors().read(Sensor::kStress);
      EXPECT_EQ(sim.save_state(), before);
      sim.step2();
      testing::run_until(sim, 0.07);
      sim.step1();
      sim.restore_state(between);  // back, from between the halves of a later step
      while (sim.state().status == SimStatus::kRunning) sim.step();
      EXPECT_EQ(state_hash(sim.state()), whole);

      Simulator fresh(m);
      fresh.restore_state(between);
      while (fresh.state().status == SimStatus::kRunning) fresh.step();
      EXPECT_EQ(state_hash(fresh.state()), whole);
    });
  }
}

// Changing the State between the halves drops what step1 computed from it: step2 runs step1
// again, so the step is the one a change made before step1 gives.
TEST(Stages, ChangingTheStateBetweenTheHalvesRedoesStep1) {
  const Model m = compile(demo_walker(), developing(BondModel::kExact));
  const auto push = [&m](State& s) {
    for (int i = 0; i < m.n; ++i) s.lin_mom[i].x() += 0.01 * m.mass;
  };
  Simulator reference(m), between(m);
  testing::run_until(reference, 0.05);
  testing::run_until(between, 0.05);
  push(reference.mutable_state());
  reference.step();
  between.step1();
  push(between.mutable_state());
  between.step2();
  EXPECT_EQ(state_hash(between.state()), state_hash(reference.state()));
}

// Constants once: every kernel that reads constants takes the Model's own (a Model is a
// ModelConstants, model_constants.hpp) and only what follows the step besides, so no copy of
// them under other names stands between compile() and the kernels.
static_assert(std::is_base_of_v<ModelConstants, Model>);
static_assert(std::is_same_v<decltype(KernelSet::bond),
                             int (*)(const BondKernelIo&, int, const ModelConstants&, double)>);
static_assert(std::is_same_v<decltype(KernelSet::gather),
                             void (*)(const VoxelKernelIo&, int, const ModelConstants&)>);
static_assert(std::is_same_v<decltype(KernelSet::update),
                             VoxelUpdateSummary (*)(const VoxelKernelIo&, const VoxelStateOut&, int,
                                                    const ModelConstants&, double)>);
static_assert(std::is_same_v<decltype(KernelSet::actuate),
                             void (*)(const double*, const double*, const double*, double*, int,
                                      const ModelConstants&)>);
static_assert(std::is_same_v<decltype(KernelSet::develop),
                             void (*)(const DevelopIo&, int, const ModelConstants&, double, bool)>);

// compile() derives each constant from the parameters, as the formulas that used to make them
// in each stage did (the golden hashes hold the rest).
TEST(Constants, CompileDerivesEachOnceFromTheParameters) {
  PhysicsDef d = preset_gecco2018_code();
  d.axial_modulus = AxialModulus::kNegativeVoxel;
  const Model m = compile(demo_walker(), d);
  const double L = m.size;
  EXPECT_EQ(m.inv_mass, 1.0 / m.mass);
  EXPECT_EQ(m.inv_inertia, 1.0 / m.inertia);
  EXPECT_EQ(m.inv_volume, 1.0 / (L * L * L));
  EXPECT_EQ(m.inv_L, 1.0 / L);
  EXPECT_EQ(m.bond_damp, 2.0 * std::sqrt(m.mass) * d.bond_damping);
  EXPECT_TRUE(m.axial_own);
  EXPECT_EQ(m.min_shear_chord, 0.1 * L);
  EXPECT_EQ(m.c_col_unit, d.collision_damping * 2.0 * std::sqrt(m.mass * L));
  EXPECT_EQ(m.rot_damp, d.global_damping_rot_factor * d.global_damping);
  EXPECT_EQ(m.weight[0], 0.0);
  EXPECT_EQ(m.weight[1], 0.0);
  EXPECT_EQ(m.weight[2], m.mass * d.gravity);
  EXPECT_EQ(m.pressure_denominator, 3.0 * (1.0 - 2.0 * d.poisson));
  EXPECT_EQ(m.gate, d.min_devo_factor * d.e_min);
  EXPECT_TRUE(m.flat_floor);
  EXPECT_EQ(m.act_amplitude_xi, d.act_amplitude);  // the paper's xi(E)
  EXPECT_EQ(m.xi_e_max, d.e_max);
  EXPECT_EQ(m.xi_inv_range, 1.0 / (d.e_max - d.e_min));
  EXPECT_EQ(m.xi_base, 0.0);
  EXPECT_EQ(m.act_wave_max, d.act_expansion ? HUGE_VAL : 0.0);
  // An environment's ground takes the floor from the update kernel (terrain.cpp).
  const Model rough =
      compile(demo_walker(),
              testing::with_environment(
                  d, R"({"ground": {"type": "ramp", "angle_deg": 10, "at": 0.1, "length": 0.5}})"));
  EXPECT_FALSE(rough.flat_floor);
  EXPECT_FALSE(compile(demo_walker(), preset_gecco2018_code()).axial_own);
}

}  // namespace
}  // namespace plastivox
