// The gradient's cost against a forward life (docs/gradients.md, "Cost"), one process per run
// so that farm-bench pairs whole processes and /usr/bin/time -v reads the peak memory:
//   grad_bench forward|gradient walker|walker09|cube10[:TREATMENT] DURATION [CHECKPOINT_EVERY]
//              [THREADS]
// (walker09: the walker under bond_model voxelyze09; ROBOT.json or .vxa: a robot file, with its
// own physics but the duration; :stress, :pressure, ...: the body develops under that stimulus)
//   grad_bench check BODY DURATION [STRIDE] [TASK] [unclassified]
// forward: simulate() of the life; gradient: plastivox::grad::gradient of the same life. The
// physics are the defaults (a robot file's own) but the duration (settling 0.2 s, as in every
// preset). Prints the fitness, the wall time and, for the gradient, its snapshots and largest
// tape. THREADS: the gradient's backward pass (GradientOptions::threads; default 0, all cores).
// check: the gradient against central differences of simulate() (h = 1e-4 of E0, 1e-4 cycles)
// on every STRIDE-th voxel's E0 and phase (16 unless given): each parameter's relative error,
// whether the nudged lives took the life's branches, and per kind the cosine between the two
// vectors (the measured agreement over a whole life, docs/gradients.md). TASK: the task whose
// fitness is taken (walk unless given: jump, turn, ...). unclassified: check without telling
// which nudged lives took the life's branches (replicate_life of every nudged life costs far
// more than the lives themselves: a whole life's check takes minutes instead of an hour).
// GRAD_BENCH_SIMD=scalar|avx2|avx512 in the environment lowers the kernels' instruction set
// (set_simd_level), to see how the ratio moves with the lanes' width: the bits do not.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "plastivox/demo_robots.hpp"
#include "plastivox/grad/gradient.hpp"
#include "plastivox/io/robot_io.hpp"
#include "plastivox/simd.hpp"
#include "plastivox/simulator.hpp"
#include "plastivox/task.hpp"

int main(int argc, char** argv) {
  using namespace plastivox;
  if (argc < 4) {
    std::fprintf(
        stderr,
        "usage: grad_bench forward|gradient|check walker|walker09|cube10[:TREATMENT] DURATION "
        "[CHECKPOINT_EVERY | "
        "STRIDE] [THREADS | TASK] [unclassified] (THREADS for gradient, TASK for check)\n");
    return 2;
  }
  const std::string mode = argv[1], named = argv[2];
  // BODY:TREATMENT develops the body under that stimulus (walker:stress), as the paper's do.
  const size_t colon = named.rfind(':');
  const std::string body = named.substr(0, colon);
  RobotDef robot;
  PhysicsDef def;
  const bool from_file = body.ends_with(".json") || body.ends_with(".vxa");
  try {
    if (from_file) {
      // A robot file (an exported champion) with its own physics, but DURATION, TREATMENT
      // and TASK.
      LoadedRobot file = load_robot(body);
      robot = file.robot;
      def = file.physics;
    }
    if (colon != std::string::npos) def.treatment = parse_treatment(named.substr(colon + 1));
    if (argc > 5 && mode == "check") def.task = parse_task(argv[5]);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "grad_bench: %s\n", e.what());
    return 2;
  }
  def.duration = std::atof(argv[3]);
  if (body == "walker09") def.bond_model = BondModel::kVoxelyze09;  // every bond's scalar path
  if (body == "walker" || body == "walker09") {
    robot = demo_walker();
  } else if (body == "cube10") {
    robot = demo_cube(10, 1e10);
    for (int s = 0; s < robot.sites(); ++s) robot.stiffness[s] *= 1.0 + 1e-3 * (s % 7);
  } else if (!from_file) {
    std::fprintf(stderr,
                 "grad_bench: body must be walker, walker09, cube10 or a robot file, not %s\n",
                 body.c_str());
    return 2;
  }
  if (const char* simd = std::getenv("GRAD_BENCH_SIMD")) {
    const std::string level = simd;
    if (level != "scalar" && level != "avx2" && level != "avx512") {
      std::fprintf(stderr, "grad_bench: GRAD_BENCH_SIMD must be scalar, avx2 or avx512, not %s\n",
                   simd);
      return 2;
    }
    set_simd_level(level == "scalar" ? SimdLevel::kScalar
                   : level == "avx2" ? SimdLevel::kAvx2
                                     : SimdLevel::kAvx512);
  }
  const Model m = compile(robot, def);
  const auto start = std::chrono::steady_clock::now();
  if (mode == "forward") {
    const SimResult r = simulate(m);
    const double s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::printf("forward %s %.3g s: fitness %.17g, %lld steps, %.3f s, %s\n", body.c_str(),
                def.duration, r.fitness, static_cast<long long>(r.steps), s,
                to_string(simd_level()));
  } else if (mode == "gradient") {
    grad::GradientOptions o;
    if (argc > 4) o.checkpoint_every = std::atoi(argv[4]);
    if (argc > 5) o.threads = std::atoi(argv[5]);
    const grad::Gradient g = grad::gradient(m, o);
    const double s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::printf(
        "gradient %s %.3g s: fitness %.17g, %lld steps, %.3f s; %zu snapshots every %d steps "
        "(%.1f MB), largest tape %zu nodes (%.1f MB), %d threads, %s\n",
        body.c_str(), def.duration, g.fitness, static_cast<long long>(g.steps), s, g.checkpoints,
        g.checkpoint_every, g.checkpoint_bytes / 1e6, g.peak_tape_nodes,
        g.peak_tape_nodes * 32.0 / 1e6, g.threads, to_string(simd_level()));
  } else if (mode == "check") {
    const grad::Gradient g = grad::gradient(m);
    const bool classify = !(argc > 6 && std::string(argv[6]) == "unclassified");
    const uint64_t events = classify ? grad::replicate_life(m).events : 0;
    const int stride = argc > 4 ? std::max(1, std::atoi(argv[4])) : 16;
    for (int kind = 0; kind < 2; ++kind) {
      double dot = 0, gg = 0, dd = 0, dot_s = 0, gg_s = 0, dd_s = 0;  // all, smooth only
      std::vector<double> errors;
      int smooth = 0, count = 0;
      for (int i = 0; i < m.n; i += stride) {
        const double h = kind == 0 ? 1e-4 * m.e0[i] : 1e-4;
        double f[2];
        bool same = true;
        for (int k = 0; k < 2; ++k) {
          Model x = m;
          (kind == 0 ? x.e0[i] : x.phase[i]) += k == 0 ? h : -h;
          f[k] = simulate(x).fitness;
          same = same && (!classify || grad::replicate_life(x).events == events);
        }
        const double d = (f[0] - f[1]) / (2 * h), a = kind == 0 ? g.stiffness[i] : g.phase[i];
        const double err = std::abs(a - d) / std::max(std::abs(d), 1e-300);
        std::printf("%s[%d] gradient %.6e difference %.6e relative error %.2e%s\n",
                    kind == 0 ? "stiffness" : "phase", i, a, d, err, same ? "" : " (kink)");
        dot += a * d, gg += a * a, dd += d * d;
        if (same) dot_s += a * d, gg_s += a * a, dd_s += d * d;
        errors.push_back(err);
        smooth += same ? 1 : 0, ++count;
      }
      std::sort(errors.begin(), errors.end());
      std::printf(
          "%s: %d parameters, %d smooth%s; relative error median %.2e, 90th percentile "
          "%.2e, largest %.2e; cosine %.9f (over the smooth ones %.9f)\n",
          kind == 0 ? "stiffness" : "phase", count, smooth,
          classify ? "" : " (unclassified: all taken as smooth)", errors[errors.size() / 2],
          errors[errors.size() * 9 / 10], errors.back(), dot / std::sqrt(gg * dd),
          dot_s / std::sqrt(gg_s * dd_s));
    }
  } else {
    std::fprintf(stderr, "grad_bench: mode must be forward, gradient or check, not %s\n",
                 mode.c_str());
    return 2;
  }
  return 0;
}
