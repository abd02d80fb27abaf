"""CMA-ES against AFPO (docs/evolution.md, "CMA-ES: cost"); not a test.

    PYTHONPATH=build/python python3 bench/cma_bench.py [--generations 6] [--duration 1]

Runs, one thread each, one after the other: AFPO evolving bodies with a distributed
controller (10x10x10, population 16: 17 lives a generation), and CMA-ES on the 512-voxel
riser body (tests/data/vertical) for each genome: its controller's 95 weights (full
covariance, 17 samples), its 512 phases and its 1024 stiffnesses and development rates
(separable). From every generation's progress: the CPU time of a life (the lives' own times, summed,
over lives simulated), and the search's own overhead: the generation's wall time less its
simulation's (sampling or mutating, expressing, selecting or updating, records; checkpoints
are not in it), per generation and as a share. The cost of a voxel-step: the last
population's bodies simulated again outside the search; for CMA-ES (whose population is
the last generation's samples) also of those very lives inside the run.
"""

import argparse
import os
import statistics
import tempfile

import plastivox

HERE = os.path.dirname(os.path.abspath(__file__))
RISER = os.path.join(HERE, "..", "tests", "data", "vertical", "riser.json")


def run(config, label):
    seen = []
    with tempfile.TemporaryDirectory() as d:
        out = os.path.join(d, "r.h5")
        plastivox.evolve(config, out, threads=1, on_generation=seen.append)
        people = [p for p in plastivox.read_results(out).population() if p["robot"] is not None]
    lives = sum(g["simulated"] for g in seen)
    cpu = sum(g["sim_cpu_seconds"] for g in seen)
    over = [g["wall_seconds"] - g["sim_wall_seconds"] for g in seen]
    share = sum(over) / sum(g["wall_seconds"] for g in seen)
    # The last population's bodies simulated again, outside the search, one after another.
    again = plastivox.simulate_many([p["robot"] for p in people], threads=1)
    voxel_steps = sum(r.voxels * r.steps for r in again)
    outside = 1e9 * sum(r.wall_seconds for r in again) / voxel_steps
    line = (f"{label:30s} {lives:4d} lives {1e3 * cpu / lives:7.1f} ms CPU/life; "
            f"outside the search {outside:6.1f} ns/voxel-step")
    last = seen[-1]
    if config.get("algorithm") in ("cma-es", "map-elites") and last["simulated"] == len(people):
        # a CMA-ES or MAP-Elites population is the last generation's samples or children: the
        # same lives, in the run
        line += f", in it {1e9 * last['sim_cpu_seconds'] / voxel_steps:6.1f}"
    print(line + f"; search overhead {1e3 * statistics.median(over):6.2f} ms/generation "
                 f"(median), {100 * share:5.3f} % of wall")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--generations", type=int, default=6)
    ap.add_argument("--duration", type=float, default=1.0)
    a = ap.parse_args()
    physics = {"preset": "gecco2018-code", "duration": a.duration, "settle_time": 0.2}
    base = {"format": "plastivox-evolve-config", "version": 1, "seed": 1,
            "generations": a.generations, "treatment": "stress", "threads": 1,
            "physics": physics}
    run(dict(base, population=16,
             controller={"kind": "distributed", "hidden": 4, "every": 1}),
        "afpo, distributed controller")
    for genome in ("controller", "phase", "materials"):
        c = dict(base, algorithm="cma-es", genome=genome, body=RISER)
        if genome != "controller":
            c["population"] = 17
        run(c, f"cma-es, riser {genome}")


if __name__ == "__main__":
    main()
