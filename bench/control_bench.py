"""Per-step cost of control from Python (docs/benchmarks.md, "Control and sensors (issue 37)");
not a test.

    PYTHONPATH=build/python python3 bench/control_bench.py [--steps 4000] [--repeats 7]

The same steps of the demo walker (stress development) taken four ways, in rotation, each
from a reset() Simulator past settling:
  builtin   sim.step(steps): one call, the built-in sine, the loop in C++;
  step      sim.step() once per step from Python (the crossing alone);
  replay    sensors("time"), the sine computed in Python with sin_cycles, set_actuation,
            step(): the same life as builtin, bit for bit, so the difference is the Python
            loop's cost alone;
  closed    as replay, reading touch too and reversing the sine where a voxel touches: a
            closed loop (another life, so its physics may cost a little more or less).
Prints the median steps per second of each and the Python cost per step against builtin, in
microseconds; then the cost of single calls (set_actuation, sensors). The machine should be
otherwise idle.
"""

import argparse
import statistics
import time

import numpy as np

import plastivox


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--steps", type=int, default=4000)
    ap.add_argument("--repeats", type=int, default=7)
    args = ap.parse_args()
    robot = plastivox.demo_walker().with_physics({"duration": 100.0, "settle_time": 0.1},
                                                 treatment="stress")
    sim = plastivox.Simulator(robot)
    n = len(sim.voxel_phase)
    fixed = np.full(n, 0.5)
    f, phase = sim.act_frequency, sim.voxel_phase

    def builtin():
        sim.set_controller("sine")
        sim.step(args.steps)

    def step():
        sim.set_controller("sine")
        for _ in range(args.steps):
            sim.step()

    def replay():
        for _ in range(args.steps):
            t = float(sim.sensors("time")["time"])
            sim.set_actuation(plastivox.sin_cycles(f * t + phase))
            sim.step()

    def closed():
        for _ in range(args.steps):
            s = sim.sensors(["touch", "time"])
            u = plastivox.sin_cycles(f * float(s["time"]) + phase)
            sim.set_actuation(np.where(s["touch"] == 1.0, -u, u))
            sim.step()

    ways = {"builtin": builtin, "step": step, "replay": replay, "closed": closed}
    rates = {k: [] for k in ways}
    for _ in range(args.repeats):
        for name, way in ways.items():
            sim.reset()
            sim.step(400)  # past settling: actuated and developing
            t0 = time.perf_counter()
            way()
            rates[name].append(args.steps / (time.perf_counter() - t0))
    base = statistics.median(rates["builtin"])
    print(f"demo walker, {n} voxels, {args.steps} steps x {args.repeats} repeats (medians)")
    for name in ways:
        r = statistics.median(rates[name])
        extra = (1 / r - 1 / base) * 1e6
        print(f"  {name:8s} {r:9.0f} steps/s   {extra:+7.1f} us/step vs builtin")

    # Single calls, between the halves of one step (sensors are then cached).
    calls = 20000
    for name, call in (("set_actuation((n,) float64)", lambda: sim.set_actuation(fixed)),
                       ('sensors("touch")', lambda: sim.sensors("touch")),
                       ("sensors() (all 10)", lambda: sim.sensors()),
                       ("sin_cycles((n,))", lambda: plastivox.sin_cycles(phase))):
        times = []
        for _ in range(5):
            t0 = time.perf_counter()
            for _ in range(calls):
                call()
            times.append((time.perf_counter() - t0) / calls * 1e6)
        print(f"  {name:28s} {statistics.median(times):6.2f} us/call")


if __name__ == "__main__":
    main()
