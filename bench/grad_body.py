"""A fixed body's phases and stiffness, by gradient ascent against CMA-ES at equal cost
(docs/gradients.md, "A fixed body's phases and stiffness: gradient against CMA-ES"); not a test.

    build/python/python3 bench/grad_body.py --method gradient --wrt phase,stiffness --lr 0.01 \\
        --steps 500000 --out DIR [--robot examples/walker.json] [--treatment none] [--duration 1]
    build/python/python3 bench/grad_body.py --method cma --genome phase --seed 1 \\
        --steps 500000 --out DIR [...]

The problem: --robot (default the demo walker's file, 512 voxels) under --treatment (default
none: the body does not develop), a life of --duration s after a 0.2 s settle, on --task
(walk), driven by its own sine. Both methods start from the body's own values and stop once
the engine steps of the lives they simulated reach --steps.

  gradient  `plastivox optimize BODY --wrt WRT --method adam --lr LR --steps N` (one
            process, one thread; N = --steps / (3 x the starting life's engine steps),
            rounded up). Each step judges the life and takes its gradient (the forward life
            and its recomputation), so a step costs three lives' engine steps, counted from
            the log's `life_steps` (a stiffer body takes more steps); the last robot costs one
            life and the replay of the written file one more. CPU seconds: the log's
            `cpu_seconds` per step, and getrusage of the child for the whole process. The
            gradient is deterministic from its start: runs differ by --lr.
  cma       the evolver's CMA-ES on "genome": --genome (phase: every voxel's phase, sigma
            0.25; materials: every voxel's stiffness on a log scale, sigma 1, and its
            development rate unless the treatment is none; --sigma overrides), the default
            population and covariance (separable above 200 numbers), seeded by --seed; run by
            rl_compare.evolve_cma (one thread, each generation simulated by simulate_many).

Writes DIR/LABEL.json (the method's own output: the optimised robot, or the CMA-ES results
file LABEL.h5) and prints one JSON line: the champion (fitness, engine steps and CPU seconds
when found), the totals and the curve [(engine steps, CPU seconds, best fitness)].
"""

import argparse
import json
import math
import os
import resource
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)

import plastivox  # noqa: E402
from rl_compare import evolve_cma  # noqa: E402 (bench/ is on the path above)

CLI = os.environ.get("PLASTIVOX_CLI", os.path.join(os.path.dirname(HERE), "build", "apps",
                                                   "plastivox"))


def physics_of(args):
    return {"duration": args.duration, "settle_time": 0.2}


def write_body(args):
    """The body with the run's physics, as both methods read it: DIR/body.json."""
    robot = plastivox.load_robot(args.robot).with_physics(
        physics_of(args), treatment=args.treatment, task=args.task)
    path = os.path.join(args.out, "body.json")
    robot.save(path)
    return robot, path


def gradient(args, robot, path):
    life_steps = plastivox.simulate(robot).steps
    n = max(1, math.ceil(args.steps / (3 * life_steps)))
    label = f"grad-{args.wrt.replace(',', '+')}-lr{args.lr:g}"
    out = os.path.join(args.out, label + ".json")
    log = os.path.join(args.out, label + ".log.jsonl")
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    subprocess.run([CLI, "optimize", path, "--wrt", args.wrt, "--method", "adam",
                    "--lr", str(args.lr), "--steps", str(n), "--out", out, "--log", log],
                   check=True, stderr=None if not args.quiet else subprocess.DEVNULL)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu_process = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    lines = [json.loads(x) for x in open(log)]
    steps, cpu, best, curve = 0, 0.0, {"fitness": -math.inf}, []
    for line in lines[1:]:
        if "written" in line or "failure" in line:
            continue
        lives = 3 if "gradient_norm" in line else 1  # the last robot is only judged
        steps += lives * line["life_steps"]
        cpu += line["cpu_seconds"]
        if line["fitness"] > best["fitness"]:
            best = {"fitness": line["fitness"], "step": line["step"], "steps": steps,
                    "cpu_seconds": round(cpu, 2), "life_steps": line["life_steps"]}
        curve.append((steps, round(cpu, 3), line["fitness"]))
    written = lines[-1]
    if written.get("fitness") != best["fitness"]:
        raise SystemExit(f"{out} replays to {written.get('fitness')}, not {best['fitness']}")
    # optimize judges as simulate does; the evolver would also not count a 3-D walk owed to
    # rising or falling (docs/evolution.md, "Flagged lives"): say whether the champion is one.
    best["vertical_exploit"] = plastivox.simulate(plastivox.load_robot(out)).vertical_exploit
    return {"method": "gradient-adam", "wrt": args.wrt, "lr": args.lr, "gradient_steps": n,
            "start": curve[0][2], "steps": steps + best["life_steps"],  # + the replay
            "cpu_seconds": round(cpu_process, 2), "best": best, "curve": curve,
            "stopped": written.get("stopped")}


def cma(args, robot, path):
    label = f"cma-{args.genome}-{args.seed}"
    config = {"format": "plastivox-evolve-config", "version": 1, "seed": args.seed,
              "generations": 100000, "algorithm": "cma-es", "body": path,
              "genome": args.genome, "treatment": robot.treatment, "threads": 1,
              "task": args.task, "physics": physics_of(args)}
    if args.sigma:
        config["cma"] = {"sigma": args.sigma}
        label += f"-sigma{args.sigma:g}"
    out = evolve_cma(config, os.path.join(args.out, label), args.steps, args.quiet)
    out["sigma"] = args.sigma or "default"
    start = plastivox.simulate(robot).fitness
    return {"method": "cma-es", "genome": args.genome, "sigma": out["sigma"], "seed": args.seed,
            "start": start, "best_sampled": out["best_sampled"],
            "flagged_lives": out["flagged_lives"],
            "steps": out["steps"], "cpu_seconds": out["cpu_seconds"], "best": out["best"],
            "curve": out["curve"]}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--method", choices=["gradient", "cma"], required=True)
    ap.add_argument("--wrt", default="phase,stiffness", help="gradient: what optimize moves")
    ap.add_argument("--lr", type=float, default=0.01, help="gradient: Adam's step")
    ap.add_argument("--genome", choices=["phase", "materials"], default="phase",
                    help="cma: the vector searched")
    ap.add_argument("--seed", type=int, default=1, help="cma: the search's seed")
    ap.add_argument("--sigma", type=float, help="cma: sigma0 (default the evolver's)")
    ap.add_argument("--steps", type=int, default=500_000, help="engine steps budget")
    ap.add_argument("--robot", default=os.path.join(os.path.dirname(HERE), "examples",
                                                    "walker.json"))
    ap.add_argument("--treatment", default="none")
    ap.add_argument("--task", default="walk")
    ap.add_argument("--duration", type=float, default=1.0)
    ap.add_argument("--out", required=True)
    ap.add_argument("--quiet", action="store_true")
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    robot, path = write_body(args)
    started = time.process_time()
    out = gradient(args, robot, path) if args.method == "gradient" else cma(args, robot, path)
    out["driver_cpu_seconds"] = round(time.process_time() - started, 2)
    print(json.dumps(out))


if __name__ == "__main__":
    main()
