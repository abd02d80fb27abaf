// plastivox beside Voxelyze (jonhiller/Voxelyze, the rewrite this project calls Voxelyze 2.0)
// on the same bodies, the same settings as far as both models express them and the same
// number of steps, one thread each, in one process. Prints CPU time per voxel-step of each and
// their ratio, pair by pair (A B A B ...), so the machine's drift cancels.
//
// Built only when CMake is given a copy of Voxelyze's repository that lives outside this
// project (never committed): -DPLASTIVOX_VOXELYZE_DIR=/path/to/Voxelyze (its src/ and
// include/). docs/benchmarks.md ("Side by side with Voxelyze") says how to run it.
//
// The settings both sides get: the body's voxels and stiffness (a continuous field is put on
// 16 levels first, since Voxelyze makes a material per value), voxel size 1 cm, density
// 1e9 kg/m^3, Poisson's ratio 0 (Voxelyze's volume effects off), bond damping 1, global damping
// 0.01, collision damping 0.8, friction 1 / 0.5, gravity, the floor, self-collision as the
// case says, and a 5 Hz actuation of 14.47 % (Voxelyze: every voxel's temperature through a
// CTE of 0.01; plastivox: its sine). Voxelyze steps at its recommended time step, taken once;
// plastivox at its own. Neither side develops stiffness.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "plastivox/demo_robots.hpp"
#include "plastivox/model.hpp"
#include "plastivox/simulator.hpp"
#include "voxelyze_runner.hpp"

namespace {

using plastivox::RobotDef;

struct Case {
  std::string name;
  RobotDef robot;
  bool self_collision;
};

// A continuous stiffness field on 16 log-spaced levels between its extremes.
RobotDef on_levels(RobotDef r) {
  double lo = INFINITY, hi = 0;
  for (int s = 0; s < r.sites(); ++s)
    if (r.present[s]) lo = std::min(lo, r.stiffness[s]), hi = std::max(hi, r.stiffness[s]);
  if (!(hi > lo)) return r;
  const double step = std::log(hi / lo) / 15.0;
  for (int s = 0; s < r.sites(); ++s)
    if (r.present[s])
      r.stiffness[s] = lo * std::exp(step * std::round(std::log(r.stiffness[s] / lo) / step));
  return r;
}

plastivox::PhysicsDef physics(bool self_collision) {
  plastivox::PhysicsDef d = plastivox::preset_gecco2018_code();
  d.poisson = 0;
  d.self_collision = self_collision;
  d.duration = 1e4;  // never the limit here
  d.settle_time = 0;
  d.max_speed = 1e9;  // both sides run the same steps whatever the body does
  return d;
}

// A run's cost: CPU seconds per voxel-step over the steps it took.
struct Run {
  double seconds = 0;
  int steps = 0;
};

// Up to `steps` steps of plastivox on the case (fewer if the life goes unstable).
Run run_plastivox(const Case& c, int steps) {
  const plastivox::Model m = plastivox::compile(c.robot, physics(c.self_collision));
  plastivox::Simulator sim(m);
  Run run;
  const double t0 = cpu_seconds();
  for (; run.steps < steps && sim.state().status == plastivox::SimStatus::kRunning; ++run.steps)
    sim.step();
  run.seconds = cpu_seconds() - t0;
  if (run.steps < steps)
    std::fprintf(stderr, "note: plastivox's %s went %s at step %d\n", c.name.c_str(),
                 plastivox::to_string(sim.state().status), run.steps);
  return run;
}

// Up to `steps` steps of Voxelyze on the case (fewer if it reports divergence).
Run run_voxelyze(const Case& c, int steps) {
  const plastivox::PhysicsDef p = physics(c.self_collision);
  const RobotDef& r = c.robot;
  VoxelyzeBody body;
  body.voxel_size = r.voxel_size;
  for (int s = 0; s < r.sites(); ++s)
    if (r.present[s])
      body.voxels.push_back({s % r.nx, (s / r.nx) % r.ny, s / (r.nx * r.ny), r.stiffness[s]});
  body.density = p.density;
  body.bond_damping = p.bond_damping;
  body.global_damping = p.global_damping;
  body.collision_damping = p.collision_damping;
  body.mu_static = p.mu_static;
  body.mu_kinetic = p.mu_kinetic;
  body.self_collision = c.self_collision;
  body.act_amplitude = p.act_amplitude;
  body.act_frequency = p.act_frequency;
  Run run;
  run.steps = voxelyze_steps(body, steps, &run.seconds);
  if (run.steps < steps)
    std::fprintf(stderr, "note: Voxelyze's %s diverged at step %d\n", c.name.c_str(), run.steps);
  return run;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

}  // namespace

int main(int argc, char** argv) {
  const int pairs = argc > 1 ? std::max(1, std::atoi(argv[1])) : 5;
  const double voxel_steps = argc > 2 ? std::atof(argv[2]) : 1e7;  // per run
  std::vector<Case> cases;
  for (int n : {5, 8, 10, 16, 20})
    cases.push_back({"cube " + std::to_string(n) + "^3", plastivox::demo_cube(n, 1e9), false});
  cases.push_back({"cube 10^3, self-collision", plastivox::demo_cube(10, 1e9), true});
  cases.push_back({"walker, 16 stiffness levels", on_levels(plastivox::demo_walker()), true});
  cases.push_back({"mixture (soft and stiff blocks)", plastivox::demo_example("mixture"), true});

  std::printf("%d pairs per case, about %.3g voxel-steps per run, one thread\n", pairs,
              voxel_steps);
  std::printf("%-32s %6s %6s %12s %12s %24s\n", "case", "voxels", "steps", "plastivox", "Voxelyze",
              "ratio: median (min-max)");
  std::printf("%-32s %6s %6s %12s %12s\n", "", "", "", "ns/vox-step", "ns/vox-step");
  for (const Case& c : cases) {
    const int n = c.robot.voxel_count();
    const int steps = std::max(100, static_cast<int>(voxel_steps / n));
    std::vector<double> ours, theirs, ratio;  // CPU seconds per voxel-step
    for (int k = 0; k < pairs; ++k) {
      const Run a = run_plastivox(c, steps), b = run_voxelyze(c, steps);
      ours.push_back(a.seconds / (static_cast<double>(n) * std::max(1, a.steps)));
      theirs.push_back(b.seconds / (static_cast<double>(n) * std::max(1, b.steps)));
      ratio.push_back(theirs.back() / ours.back());
    }
    std::printf("%-32s %6d %6d %12.1f %12.1f %10.2fx (%.2f-%.2f)\n", c.name.c_str(), n, steps,
                1e9 * median(ours), 1e9 * median(theirs), median(ratio),
                *std::min_element(ratio.begin(), ratio.end()),
                *std::max_element(ratio.begin(), ratio.end()));
    std::fflush(stdout);
  }
  return 0;
}
