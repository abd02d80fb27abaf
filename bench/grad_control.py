"""Gradient ascent on a fixed body's controller, at the budget bench/rl_compare.py gives PPO and
CMA-ES (docs/gradients.md, "Learning a controller by gradient ascent"); not a test.

    PYTHONPATH=build/python python3 bench/grad_control.py --seed 1 --steps 1000000 \\
        [--cpu SECONDS] [--treatment none] [--duration 1] [--every 10] [--lr 0.01] \\
        [--task walk] [--robot FILE]

The problem is rl_compare.py's: the demo walker (512 voxels), or --robot's, with the given
treatment ("none": no development; default the walker's own, stress), a life of --duration s
after a 0.2 s settle, on --task (default walk); a distributed controller of 4 hidden units
acting every --every steps (95 weights).
The initial weights are drawn from N(0, 0.5^2) with --seed: a sample of the distribution CMA-ES
draws its first generation from (mean 0, sigma 0.5). From zero weights a gradient cannot start:
every hidden unit is 0, so only the output bias has a derivative, and that never changes.

Each step is one plastivox.gradient(robot, wrt=["controller"]) call, then an Adam step (beta1
0.9, beta2 0.999, eps 1e-8) of --lr on the weights, on one thread (threads=1). Its cost is
counted in full: the gradient runs the forward life (judged as simulate judges it) and
recomputes every step once for the reverse sweep, so a step counts two lives' engine steps
(three before the gradient's forward life was judged in place of a separate one: the runs in
docs/gradients.md counted three); the CPU seconds are the process's (time.process_time) from
the start of the search, the Python and numpy around the calls included. The fitness a gradient
returns is the life of the weights it was taken at, so every step is also an evaluation; the
champion is the best life seen. A life the gradient refuses (sank, unstable, a bond it cannot
differentiate) counts its forward life, returns to the previous weights and halves the
learning rate.

Runs until the engine steps reach --steps or the CPU seconds --cpu (whichever first). Prints a
line per step and one JSON line at the end: the champion (with `success`, its life's by the
task's criterion, simulated once more outside the budget), when it was found, the best by
250k / 500k / 1M steps, and the totals. A task whose fitness has no gradient yet (climb and
the other tasks with an environment, docs/gradients.md "Not covered yet") is refused at the
first call, in one line, exit 1, with no numbers.
"""

import argparse
import json
import math
import time

import numpy as np

import plastivox
from rl_compare import body as body_of  # bench/ is on the path when this script runs


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--steps", type=int, default=1_000_000)
    ap.add_argument("--cpu", type=float, default=math.inf, help="CPU seconds budget")
    ap.add_argument("--duration", type=float, default=1.0)
    ap.add_argument("--every", type=int, default=10)
    ap.add_argument("--lr", type=float, default=0.01)
    ap.add_argument("--treatment", help="none: no development; default the walker's (stress)")
    ap.add_argument("--task", default="walk")
    ap.add_argument("--robot", help="robot file (default: the demo walker)")
    ap.add_argument("--quiet", action="store_true")
    args = ap.parse_args()

    hidden = 4
    n = plastivox.controller_weight_count("distributed", hidden)
    body = body_of(args)
    physics = {"duration": args.duration, "settle_time": 0.2, "task": args.task}
    w = np.random.default_rng(args.seed).normal(0.0, 0.5, n)

    def robot(weights):
        return body.with_controller("distributed", hidden=hidden, every=args.every,
                                    weights=weights)

    # The life's length in engine steps (outside the budget: the same for every weights
    # unless a life ends early, which the gradient refuses).
    life_steps = plastivox.simulate(robot(w), physics=physics).steps

    start = time.process_time()
    m, v = np.zeros(n), np.zeros(n)
    lr, t, steps = args.lr, 0, 0
    best = {"fitness": -math.inf}
    marks = {250_000: None, 500_000: None, 1_000_000: None}
    curve = []
    while steps < args.steps and time.process_time() - start < args.cpu:
        try:
            fitness, grads = plastivox.gradient(robot(w), wrt=["controller"], physics=physics,
                                                threads=1)
        except (ValueError, RuntimeError) as e:
            steps += life_steps  # the forward life
            if not args.quiet:
                print(f"refused: {e}; back to the previous weights, lr {lr / 2:g}", flush=True)
            if t == 0:
                raise SystemExit(f"grad_control: task {args.task}: the initial controller's "
                                 f"life is refused: {e}")
            w, lr = w_prev, lr / 2
            continue
        steps += 2 * life_steps
        cpu = time.process_time() - start
        if fitness > best["fitness"]:
            best = {"fitness": fitness, "steps": steps, "cpu_seconds": round(cpu, 2),
                    "step": t}
            best_weights = w
        for mark in marks:
            if steps <= mark:
                marks[mark] = best["fitness"]
        g = grads["controller"]
        curve.append((t, steps, round(cpu, 2), fitness))
        if not args.quiet:
            print(f"step {t:4d}  steps {steps:9d}  cpu {cpu:7.1f} s  fitness {fitness:.4f}  "
                  f"best {best['fitness']:.4f}  |g| {np.linalg.norm(g):.3g}", flush=True)
        # Adam ascent.
        t += 1
        m = 0.9 * m + 0.1 * g
        v = 0.999 * v + 0.001 * g * g
        w_prev = w
        w = w + lr * (m / (1 - 0.9**t)) / (np.sqrt(v / (1 - 0.999**t)) + 1e-8)
    champion = plastivox.simulate(robot(best_weights), physics=physics)
    if champion.fitness != best["fitness"]:
        raise SystemExit(f"the champion's life scored {champion.fitness!r}, "
                         f"not {best['fitness']!r}")
    best["success"] = champion.success
    best["vertical_exploit"] = champion.vertical_exploit  # the evolver would not count it
    print(json.dumps({"method": "gradient-adam", "seed": args.seed, "lr": args.lr,
                      "task": args.task, "treatment": args.treatment, "life_steps": life_steps,
                      "gradient_steps": len(curve), "steps": steps,
                      "cpu_seconds": round(time.process_time() - start, 2), "best": best,
                      "best_by_steps": marks, "curve": curve}))


if __name__ == "__main__":
    main()
