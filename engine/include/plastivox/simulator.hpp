// Running a simulation: one step at a time (Simulator) or a whole life (simulate()).
//
// A Simulator owns the mutable State and a scratch workspace; the Model it reads is shared
// and immutable, so many Simulators (one per thread) may run the same or different models
// at once. A single simulation runs on one thread, which keeps every reduction in a fixed
// order: results are bit-identical whatever the number of threads evaluating robots.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "plastivox/model.hpp"
#include "plastivox/recording.hpp"
#include "plastivox/state.hpp"

namespace plastivox {

struct Workspace;  // per-step scratch arrays (engine/src/workspace.hpp)

class Simulator {
 public:
  explicit Simulator(const Model& model);  // model must outlive the simulator
  ~Simulator();
  Simulator(Simulator&&) noexcept;
  Simulator& operator=(Simulator&&) = delete;

  const Model& model() const { return *model_; }
  const State& state() const { return state_; }
  // The state may be replaced by one saved from another Simulator of the same model: the
  // life then continues bit-identically (State holds everything that carries over).
  State& mutable_state() { return state_; }

  // Advances one time step. Sets status to kUnstable (with a reason) instead of producing
  // non-finite numbers; further calls then do nothing.
  void step();

 private:
  const Model* model_;
  State state_;
  std::unique_ptr<Workspace> ws_;
};

struct SimResult {
  SimStatus status = SimStatus::kRunning;
  std::string failure;               // why the run went unstable; empty when it finished
  double fitness = 0;                // centre-of-mass displacement settle..end, voxel lengths
  Vec3 displacement = Vec3::Zero();  // same, per axis, voxel lengths
  Vec3 com_settled = Vec3::Zero();   // m
  Vec3 com_final = Vec3::Zero();     // m
  int voxels = 0;
  int64_t steps = 0;
  double dt_initial = 0;  // s
  double dt_final = 0;    // s
  double sim_time = 0;    // s reached
  double wall_seconds = 0;
  // Lifetime stiffness change, relative: (E_final - E0) / E0 per voxel.
  std::vector<double> final_stiffness;   // Pa, per voxel
  double stiffness_change_mean = 0;      // signed mean
  double stiffness_change_abs_mean = 0;  // mean of absolute values
  double stiffness_change_var = 0;       // variance of the signed values
  uint64_t final_state_hash = 0;
  Recording recording;  // empty unless def.record_fps > 0
  // Health: with the floor on, the body ended below it (its centre of mass, or a whole
  // voxel, under z = 0). Heavy, soft bodies do this: their time step is long enough for
  // them to pass through the floor in one step (docs/physics.md, "Sinking through the
  // floor"). Reported, not acted on, unless def.sinking_invalid (then status is kUnstable).
  bool sank = false;
  int voxels_below_floor = 0;         // voxels whose top face ends below z = 0
  std::vector<std::string> warnings;  // one line each, e.g. what sank and by how much
};

// Simulates a whole life (def.duration) and summarises it.
SimResult simulate(const Model& model);

const char* to_string(SimStatus s);

}  // namespace plastivox
