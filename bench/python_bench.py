"""Benchmarks of the Python module (docs/benchmarks.md, "Python module"); not a test.

    PYTHONPATH=build/python python3 bench/python_bench.py [--repeats 15]

1. Python overhead of plastivox.simulate on a 0.2 s life of the demo walker, as a ratio
   within each call: the wall time of the Python call against the wall time of the same work
   in C++ inside it (resolve the physics, compile the model, simulate, build the summary:
   what `plastivox simulate --json` does; Result._cxx_seconds). What is left is the module's
   own cost: argument checks, crossing into C++ and back, parsing the summary into a Result.
   Also shown against the simulation alone (Result.wall_seconds, timed inside the C++
   simulate()), which counts compiling and the summary as overhead too.
2. simulate_many on 2 threads against 1: 16 different bodies (the demo walker with random
   stiffness), 1 s lives each (thread start-up is microseconds against seconds of work), in
   alternating pairs; with the process CPU time of each, which shows whether 2 threads really
   ran at once (CPU/wall near 2 with the GIL released), and the load average.
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
    module, engine, total, cxx = [], [], [], []
    for _ in range(repeats):
        t0 = time.perf_counter()
        r = plastivox.simulate(walker)
        t = time.perf_counter() - t0
        total.append(t)
        cxx.append(r._cxx_seconds)
        engine.append(r.wall_seconds)
        module.append((t - r._cxx_seconds) / r._cxx_seconds)
    against_engine = [(t - e) / e for t, e in zip(total, engine)]
    return (statistics.median(total), statistics.median(cxx), statistics.median(engine),
            statistics.median(module), statistics.median(against_engine))


def speedup(repeats):
    rng = np.random.default_rng(5)
    base = plastivox.demo_walker()
    robots = [plastivox.Robot.from_arrays(base.geometry,
                                          np.where(base.geometry, 10 ** rng.uniform(6, 8, base.shape), 0),
                                          base.phase, treatment="stress")
              for _ in range(16)]
    physics = {"duration": 1.0, "settle_time": 0.1}
    ratios, cpu = [], {1: [], 2: []}
    for _ in range(repeats):
        pair = {}
        for threads in (1, 2):
            c0, t0 = time.process_time(), time.perf_counter()
            plastivox.simulate_many(robots, physics=physics, threads=threads)
            pair[threads] = time.perf_counter() - t0
            cpu[threads].append((time.process_time() - c0) / pair[threads])
        ratios.append(pair[1] / pair[2])
        print(f"  pair: 1 thread {pair[1]:.3f} s, 2 threads {pair[2]:.3f} s, {ratios[-1]:.2f}x "
              f"(CPU/wall {cpu[1][-1]:.2f}, {cpu[2][-1]:.2f}; load {os.getloadavg()[0]:.1f})")
    return statistics.median(ratios), statistics.median(cpu[1]), statistics.median(cpu[2])


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=15)
    args = ap.parse_args()
    print(f"plastivox {plastivox.__version__}, {os.cpu_count()} hardware threads")
    load = os.getloadavg()[0]
    total, cxx, engine, module, against_engine = overhead(args.repeats)
    print(f"simulate, demo walker, 0.2 s life: Python call {total * 1e3:.2f} ms, the same work "
          f"in C++ {cxx * 1e3:.2f} ms (simulation alone {engine * 1e3:.2f} ms): module overhead "
          f"{100 * module:.2f} % (against the simulation alone {100 * against_engine:.2f} %), "
          f"median of {args.repeats}, load {load:.1f} -> {os.getloadavg()[0]:.1f}")
    ratio, cpu1, cpu2 = speedup(max(3, args.repeats // 5))
    print(f"simulate_many, 16 bodies x 1 s, alternating pairs: speed-up {ratio:.2f}x (median), "
          f"CPU/wall {cpu1:.2f} on 1 thread, {cpu2:.2f} on 2")


if __name__ == "__main__":
    main()
