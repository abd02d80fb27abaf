// How well the gradient of a life in an environment or with a free object agrees with central
// differences over a longer life, and its cost (docs/gradients.md, "Environments and free
// objects"):
//   grad_env_bench check|forward|gradient climb|carry DURATION [STRIDE]
//   grad_env_bench gradient climb|carry DURATION [CHECKPOINT_EVERY [THREADS]]
// The demo walker on the task's default environment (climb: terraces; carry: its payload),
// default physics but the duration. The loss is a final-state one of the bench's own, not the
// task's fitness: the x of the centre (the robot's for climb, the payload's for carry) in voxel
// lengths. For every STRIDE-th robot voxel (16 unless given) the E0 and phase derivatives are
// compared with plain central differences (h = 1e-4 of E0, 1e-4 cycles); a parameter whose
// nudged lives take other branches than the life (replicate_life's signature) is marked as
// crossing a kink. Prints each parameter, then per kind the distribution of relative errors
// and the cosine between the two vectors, over all and over the smooth ones. forward and
// gradient run the life alone, or its gradient alone, for timing as whole processes; gradient
// takes grad_bench's CHECKPOINT_EVERY (0: the default) and THREADS (the backward pass's; 0,
// the default: all cores).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "plastivox/demo_robots.hpp"
#include "plastivox/grad/gradient.hpp"
#include "plastivox/simulator.hpp"

namespace {

using namespace plastivox;

// The mean x of voxels [first, end), in voxel lengths.
struct CentreX {
  int first, end;
  double size;
  double of(const State& s) const {
    double x = 0;
    for (int i = first; i < end; ++i) x += s.pos[i].x();
    return x / (end - first) / size;
  }
};

double final_x(const Model& m, const CentreX& c) {
  Simulator sim(m);
  while (sim.state().status == SimStatus::kRunning) sim.step();
  return c.of(sim.state());
}

uint64_t events_of(Model m) {
  m.def.task = Task::kWalk;  // the physics do not read the task once compiled
  return grad::replicate_life(m).events;
}

// The gradient beside the differences of one kind of parameter, and what they say together.
struct Comparison {
  std::vector<double> gradient, difference;
  std::vector<bool> smooth;
  void print(const char* kind) const {
    const auto summary = [&](bool smooth_only) {
      std::vector<double> errors;
      double dot = 0, gg = 0, dd = 0;
      for (size_t k = 0; k < gradient.size(); ++k) {
        if (smooth_only && !smooth[k]) continue;
        const double a = gradient[k], d = difference[k];
        errors.push_back(std::abs(a - d) / std::max(std::abs(d), 1e-300));
        dot += a * d, gg += a * a, dd += d * d;
      }
      if (errors.empty()) return std::printf("none");
      std::sort(errors.begin(), errors.end());
      return std::printf(
          "%zu: relative error median %.2e, 90th percentile %.2e, largest %.2e, "
          "cosine %.10f",
          errors.size(), errors[errors.size() / 2], errors[errors.size() * 9 / 10], errors.back(),
          dot / std::sqrt(gg * dd));
    };
    std::printf("%s, all ", kind);
    summary(false);
    std::printf("\n%s, smooth ", kind);
    summary(true);
    std::printf("\n");
  }
};

}  // namespace

int main(int argc, char** argv) {
  if (argc < 4) {
    std::fprintf(stderr,
                 "usage: grad_env_bench check|forward|gradient climb|carry DURATION [STRIDE]\n"
                 "       grad_env_bench gradient climb|carry DURATION [CHECKPOINT_EVERY "
                 "[THREADS]]\n");
    return 2;
  }
  const std::string mode = argv[1], task = argv[2];
  if (mode != "check" && mode != "forward" && mode != "gradient") {
    std::fprintf(stderr, "grad_env_bench: the mode must be check, forward or gradient, not %s\n",
                 argv[1]);
    return 2;
  }
  PhysicsDef def;
  def.duration = std::atof(argv[3]);
  if (task == "climb") {
    def.task = Task::kClimb;
  } else if (task == "carry") {
    def.task = Task::kCarry;
  } else {
    std::fprintf(stderr, "grad_env_bench: the task must be climb or carry, not %s\n", argv[2]);
    return 2;
  }
  const int stride = argc > 4 ? std::max(1, std::atoi(argv[4])) : 16;
  const Model m = compile(demo_walker(), def);
  const CentreX centre = task == "climb" ? CentreX{0, m.robot_n, m.size}
                                         : CentreX{m.robot_n, m.object_begin[1], m.size};
  const grad::FinalLoss loss = [&](const State& s, std::vector<std::vector<double>>& d) {
    std::vector<double>& pos = d[&state_field("pos") - kStateFields.data()];
    for (int i = centre.first; i < centre.end; ++i)
      pos[3 * size_t(i)] = 1.0 / (centre.end - centre.first) / centre.size;
    return centre.of(s);
  };
  if (mode == "forward") {
    std::printf("%s, demo walker, %.3g s: loss %.17g\n", task.c_str(), def.duration,
                final_x(m, centre));
    return 0;
  }
  grad::GradientOptions options;
  if (mode == "gradient" && argc > 4) options.checkpoint_every = std::atoi(argv[4]);
  if (mode == "gradient" && argc > 5) options.threads = std::atoi(argv[5]);
  const grad::Gradient g = grad::gradient_of(m, loss, options);
  if (mode == "gradient") {
    std::printf(
        "%s, demo walker, %.3g s: loss %.17g, %zu snapshots, largest tape %zu nodes, %d threads\n",
        task.c_str(), def.duration, g.fitness, g.checkpoints, g.peak_tape_nodes, g.threads);
    return 0;
  }
  const SimResult r = simulate(m);
  std::printf("%s, demo walker, %.3g s: loss %.17g, %lld steps, forward hash %s simulate's\n",
              task.c_str(), def.duration, g.fitness, static_cast<long long>(g.steps),
              g.final_state_hash == r.final_state_hash ? "equals" : "DIFFERS FROM");
  const uint64_t events = events_of(m);
  Comparison kinds[2];
  for (int i = 0; i < m.robot_n; i += stride) {
    for (int kind = 0; kind < 2; ++kind) {
      const double h = kind == 0 ? 1e-4 * m.e0[i] : 1e-4;
      double f[2];
      bool same = true;
      for (int side = 0; side < 2; ++side) {
        Model x = m;
        (kind == 0 ? x.e0[i] : x.phase[i]) += side == 0 ? h : -h;
        f[side] = final_x(x, centre);
        same = same && events_of(x) == events;
      }
      Comparison& c = kinds[kind];
      c.gradient.push_back(kind == 0 ? g.stiffness[i] : g.phase[i]);
      c.difference.push_back((f[0] - f[1]) / (2 * h));
      c.smooth.push_back(same);
      std::printf("%s[%d] gradient %.6e difference %.6e%s\n", kind == 0 ? "stiffness" : "phase", i,
                  c.gradient.back(), c.difference.back(), same ? "" : " (kink)");
      std::fflush(stdout);
    }
  }
  kinds[0].print("stiffness");
  kinds[1].print("phase");
  return 0;
}
