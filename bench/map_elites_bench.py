"""MAP-Elites against AFPO (docs/evolution.md, "MAP-Elites"; docs/benchmarks.md); not a test.

    PYTHONPATH=build/python python3 bench/map_elites_bench.py [--generations 6] [--duration 1]

Runs, one thread each, one after the other: AFPO (10x10x10, population 16: 17 lives a
generation) and MAP-Elites (17 children a generation) over the same genomes and physics, the
archive on fill, the Π template score and floor contact (so the body-plan rule and the life's
watch are both in the cost). For each, as bench/cma_bench.py reports it: the CPU time of a
life, the cost of a voxel-step outside the search (the last population's bodies simulated
again) and, for MAP-Elites, inside it (its population is the last generation's children: the
same lives, simulated with the descriptors' watch), and the search's own overhead per
generation (a generation's wall time less its simulation's: making, expressing,
descriptors, offering to the archive, records; not the checkpoint).
"""

import argparse
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from cma_bench import run  # noqa: E402  (the same measures, one definition)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--generations", type=int, default=6)
    ap.add_argument("--duration", type=float, default=1.0)
    a = ap.parse_args()
    physics = {"preset": "gecco2018-code", "duration": a.duration, "settle_time": 0.2}
    base = {"format": "plastivox-evolve-config", "version": 1, "seed": 1,
            "generations": a.generations, "treatment": "stress", "threads": 1,
            "physics": physics}
    run(dict(base, population=16), "afpo")
    axes = [{"name": "fill", "bounds": [0.2, 1], "bins": 8},
            {"name": "pi", "bounds": [0, 1], "bins": 5},
            {"name": "floor_contact", "bounds": [0, 1], "bins": 8}]
    run(dict(base, population=17, algorithm="map-elites", map_elites={"descriptors": axes}),
        "map-elites, fill x pi x floor")


if __name__ == "__main__":
    main()
