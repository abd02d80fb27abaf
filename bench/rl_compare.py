"""PPO against CMA-ES for a fixed body's controller at equal cost (docs/control.md,
"Learning a controller: CMA-ES, gradient ascent and PPO"); not a test.

    PYTHONPATH=build/python python3 bench/rl_compare.py --method cma --seed 1 --steps 1000000 \\
        --out /tmp/cmp [--treatment none] [--duration 1] [--every 10] [--task walk] [--robot F]
    PYTHONPATH=build/python python3 bench/rl_compare.py --method ppo --seed 1 --steps 1000000 \\
        --out /tmp/cmp [...]

The body is the demo walker (512 voxels), or --robot's, with the given treatment ("none": no
development; "stress": the walker's own), a life of --duration s after a 0.2 s settle, on
--task (default walk; climb and the other tasks with their default environments). Both
methods run on one thread and stop once the engine steps of every life they simulated
(counted the same way: each life's own steps, PPO's evaluation lives and partial lives
included) reach --steps.

  cma  the evolver's CMA-ES (full covariance) on the weights of a distributed controller of
       4 hidden units acting every --every steps (95 weights, from 0, sigma 0.5, the default
       population of 17), through plastivox.Evolver with each generation simulated by
       simulate_many and told as Results (the engine's scoring). The champion is the
       evolver's: the best life sampled, a life the vertical rule flags (walk's 3-D fitness
       owed to rising or falling) counting only while no other has been seen; the best life
       sampled whatever the flag is printed too ("best_sampled"; until 2026-12-06 it was the
       champion).
  ppo  plastivox.ppo: a per-voxel Gaussian MLP policy acting every --every steps on 8
       environments of a VoxelVecEnv; the champion is the best mean-action life, replayed
       (plastivox.ppo.replay) for its Result.

Prints one JSON line: the champion's fitness, whether it met the task's criterion
(`success`, docs/tasks.md), the engine steps and process CPU seconds when it was found, and
the totals. The CPU seconds include everything in the process after start-up (for PPO,
torch's forward and backward passes; for CMA-ES, the strategy's update). evolve_cma() is also
bench/grad_body.py's CMA-ES.
"""

import argparse
import json
import math
import os
import time

import numpy as np

import plastivox


def body(args):
    robot = plastivox.load_robot(args.robot) if args.robot else plastivox.demo_walker()
    if getattr(args, "dev_rate", None) is not None:  # every voxel's rate, the rest as it was
        rates = np.where(robot.geometry != 0, args.dev_rate, 0.0)
        robot = plastivox.Robot.from_arrays(
            robot.geometry, robot.stiffness, robot.phase, rates, voxel_size=robot.voxel_size,
            name=robot.name).with_physics(robot.physics)
    if args.treatment:
        robot = robot.with_physics({}, treatment=args.treatment)
    return robot


def evolve_cma(config, path, budget, quiet=False):
    """Runs the evolver's CMA-ES of `config` (results to PATH.h5, started afresh) until the
    engine steps of its lives reach `budget`. Each generation is asked, simulated by
    simulate_many on one thread and told as Results. Returns the champion as the evolver keeps
    it (docs/evolution.md, "Flagged lives": the best finished life, where a life that scored
    by rising or falling under walk's 3-D fitness, Result.vertical_exploit, counts only while
    no other has been seen; its fitness, success, engine steps and CPU seconds when found),
    the best life sampled whatever the flag ("best_sampled"), the totals and the curve
    [(steps, cpu_seconds, champion fitness)] after each generation."""
    if os.path.exists(path + ".h5"):
        os.remove(path + ".h5")  # a fresh run: the counters below are not checkpointed
    start = time.process_time()
    steps, curve = 0, []
    best = {False: {"fitness": -math.inf}, True: {"fitness": -math.inf}}  # by the flag
    flagged = 0
    with plastivox.Evolver(config, path + ".h5", threads=1, name="rl_compare") as ev:
        while not ev.finished and steps < budget:
            robots = ev.ask()
            lives = plastivox.simulate_many(robots, threads=1)
            ev.tell(lives)
            for life in lives:
                steps += life.steps
                flag = bool(life.vertical_exploit)
                flagged += flag
                if life.status == "finished" and life.fitness > best[flag]["fitness"]:
                    best[flag] = {"fitness": life.fitness, "success": life.success,
                                  "steps": steps, "cpu_seconds": time.process_time() - start}
            cpu = time.process_time() - start
            champion = best[False] if best[False]["fitness"] > -math.inf else best[True]
            curve.append((steps, round(cpu, 3), champion["fitness"]))
            if not quiet:
                print(f"gen {len(curve):4d}  steps {steps:9d}  cpu {cpu:7.1f} s  "
                      f"best {best['fitness']:.4f}", flush=True)
    return {"steps": steps, "cpu_seconds": round(time.process_time() - start, 2),
            "best": champion, "best_sampled": max(best.values(), key=lambda b: b["fitness"]),
            "flagged_lives": flagged, "curve": curve}


def cma(args):
    hidden = 4
    n = plastivox.controller_weight_count("distributed", hidden)
    robot = body(args).with_controller("distributed", hidden=hidden, every=args.every,
                                       weights=np.zeros(n))
    os.makedirs(args.out, exist_ok=True)
    path = os.path.join(args.out, f"cma-{args.seed}")
    robot.save(path + ".json")
    config = {"format": "plastivox-evolve-config", "version": 1, "seed": args.seed,
              "generations": 100000, "algorithm": "cma-es", "body": path + ".json",
              "genome": "controller", "treatment": robot.treatment, "threads": 1,
              "task": args.task,
              "physics": {"duration": args.duration, "settle_time": 0.2},
              "cma": {"sigma": 0.5, "covariance": "full"}}
    out = evolve_cma(config, path, args.steps, args.quiet)
    return {"method": "cma-es", "seed": args.seed, "task": args.task, "steps": out["steps"],
            "cpu_seconds": out["cpu_seconds"], "best": out["best"],
            "best_sampled": out["best_sampled"], "flagged_lives": out["flagged_lives"]}


def ppo(args):
    from plastivox import ppo as p  # torch only here
    os.makedirs(args.out, exist_ok=True)
    checkpoint = os.path.join(args.out, f"ppo-{args.seed}.pt")
    argv = ["--checkpoint", checkpoint, "--steps", str(args.steps), "--seed", str(args.seed),
            "--duration", str(args.duration), "--every", str(args.every)]
    if args.treatment:
        argv += ["--treatment", args.treatment]
    if args.robot:
        argv += ["--robot", args.robot]
    argv += ["--task", args.task]
    if args.quiet:
        argv.append("--quiet")
    ppo_args = p.parser().parse_args(argv)
    state = p.train(ppo_args)
    best = {k: v for k, v in state["best"].items() if k != "actions"}
    life = p.replay(ppo_args, state["best"]["actions"])
    if life.fitness != best["fitness"]:
        raise SystemExit(f"the champion's replay scored {life.fitness!r}, not {best['fitness']!r}")
    best["success"] = life.success
    best["vertical_exploit"] = life.vertical_exploit  # the evolver would not count it
    return {"method": "ppo", "seed": args.seed, "task": args.task, "steps": state["steps"],
            "cpu_seconds": round(state["cpu_seconds"], 2), "best": best}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--method", choices=["cma", "ppo"], required=True)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--steps", type=int, default=1_000_000)
    ap.add_argument("--duration", type=float, default=1.0)
    ap.add_argument("--every", type=int, default=10)
    ap.add_argument("--treatment", help="none: no development; default the walker's (stress)")
    ap.add_argument("--task", default="walk")
    ap.add_argument("--robot", help="robot file (default: the demo walker)")
    ap.add_argument("--dev-rate", type=float,
                    help="set every voxel's development rate (1/s); for a body evolved "
                         "without development, whose rates are 0")
    ap.add_argument("--out", required=True)
    ap.add_argument("--quiet", action="store_true")
    args = ap.parse_args()
    if args.dev_rate is not None:  # both methods read the body from a file
        os.makedirs(args.out, exist_ok=True)
        path = os.path.join(args.out, "body.json")
        body(args).save(path)
        args.robot, args.dev_rate = path, None
    out = cma(args) if args.method == "cma" else ppo(args)
    print(json.dumps(out))


if __name__ == "__main__":
    main()
