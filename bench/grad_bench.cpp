// The gradient's cost against a forward life (docs/gradients.md, "Cost"), one process per run
// so that farm-bench pairs whole processes and /usr/bin/time -v reads the peak memory:
//   grad_bench forward|gradient walker|cube10 DURATION [CHECKPOINT_EVERY]
// forward: simulate() of the life; gradient: plastivox::grad::gradient of the same life. The
// physics are the defaults but the duration (settling 0.2 s, as in every preset). Prints the
// fitness, the wall time and, for the gradient, its snapshots and largest tape.
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "plastivox/demo_robots.hpp"
#include "plastivox/grad/gradient.hpp"
#include "plastivox/simulator.hpp"

int main(int argc, char** argv) {
  using namespace plastivox;
  if (argc < 4) {
    std::fprintf(stderr,
                 "usage: grad_bench forward|gradient walker|cube10 DURATION [CHECKPOINT_EVERY]\n");
    return 2;
  }
  const std::string mode = argv[1], body = argv[2];
  PhysicsDef def;
  def.duration = std::atof(argv[3]);
  RobotDef robot;
  if (body == "walker") {
    robot = demo_walker();
  } else if (body == "cube10") {
    robot = demo_cube(10, 1e10);
    for (int s = 0; s < robot.sites(); ++s) robot.stiffness[s] *= 1.0 + 1e-3 * (s % 7);
  } else {
    std::fprintf(stderr, "grad_bench: body must be walker or cube10, not %s\n", body.c_str());
    return 2;
  }
  const Model m = compile(robot, def);
  const auto start = std::chrono::steady_clock::now();
  if (mode == "forward") {
    const SimResult r = simulate(m);
    const double s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::printf("forward %s %.3g s: fitness %.17g, %lld steps, %.3f s\n", body.c_str(),
                def.duration, r.fitness, static_cast<long long>(r.steps), s);
  } else if (mode == "gradient") {
    grad::GradientOptions o;
    if (argc > 4) o.checkpoint_every = std::atoi(argv[4]);
    const grad::Gradient g = grad::gradient(m, o);
    const double s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::printf(
        "gradient %s %.3g s: fitness %.17g, %lld steps, %.3f s; %zu snapshots every %d steps "
        "(%.1f MB), largest tape %zu nodes (%.1f MB)\n",
        body.c_str(), def.duration, g.fitness, static_cast<long long>(g.steps), s, g.checkpoints,
        g.checkpoint_every, g.checkpoint_bytes / 1e6, g.peak_tape_nodes,
        g.peak_tape_nodes * 32.0 / 1e6);
  } else {
    std::fprintf(stderr, "grad_bench: mode must be forward or gradient, not %s\n", mode.c_str());
    return 2;
  }
  return 0;
}
