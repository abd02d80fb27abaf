"""Benchmarks of the Python module (docs/benchmarks.md, "Python module"); not a test.

    PYTHONPATH=build/python python3 bench/python_bench.py [--repeats 15]

1. Python overhead of plastivox.simulate on a 0.2 s life of the demo walker: the wall time
   of the Python call less the engine's own wall time for the life (Result.wall_seconds,
   timed inside the C++ simulate()), as a fraction of the engine time. Compiling the model,
   building the summary and crossing into Python all count as overhead here.
2. simulate_many on 2 threads against 1: 16 different bodies (the demo walker with random
   stiffness), 1 s lives each.
Medians over the repeats; the machine should be otherwise idle.
"""

import argparse
import os
import statistics
import time

import numpy as np

import plastivox


def overhead(repeats):
    walker = plastivox.demo_walker().with_physics({"duration": 0.2, "settle_time": 0.1})
    plastivox.simulate(walker)  # warm up
    fractions, engine, total = [], [], []
    for _ in range(repeats):
        t0 = time.perf_counter()
        r = plastivox.simulate(walker)
        t = time.perf_counter() - t0
        total.append(t)
        engine.append(r.wall_seconds)
        fractions.append((t - r.wall_seconds) / r.wall_seconds)
    return statistics.median(total), statistics.median(engine), statistics.median(fractions)


def speedup(repeats):
    rng = np.random.default_rng(5)
    base = plastivox.demo_walker()
    robots = [plastivox.Robot.from_arrays(base.geometry,
                                          np.where(base.geometry, 10 ** rng.uniform(6, 8, base.shape), 0),
                                          base.phase, treatment="stress")
              for _ in range(16)]
    physics = {"duration": 1.0, "settle_time": 0.1}
    times = {1: [], 2: []}
    for _ in range(repeats):
        for threads in (1, 2):
            t0 = time.perf_counter()
            plastivox.simulate_many(robots, physics=physics, threads=threads)
            times[threads].append(time.perf_counter() - t0)
    one, two = statistics.median(times[1]), statistics.median(times[2])
    return one, two, one / two


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=15)
    args = ap.parse_args()
    print(f"plastivox {plastivox.__version__}, {os.cpu_count()} hardware threads")
    total, engine, fraction = overhead(args.repeats)
    print(f"simulate, demo walker, 0.2 s life: Python call {total * 1e3:.2f} ms, engine "
          f"{engine * 1e3:.2f} ms, overhead {100 * fraction:.2f} % (median of {args.repeats})")
    one, two, ratio = speedup(max(3, args.repeats // 5))
    print(f"simulate_many, 16 bodies x 1 s: 1 thread {one:.3f} s, 2 threads {two:.3f} s, "
          f"speed-up {ratio:.2f}x")


if __name__ == "__main__":
    main()
