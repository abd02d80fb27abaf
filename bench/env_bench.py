"""One life of the demo walker (512 voxels, stress development) stepped one way, for
whole-process timing of plastivox.VoxelEnv against the built-in loop (docs/control.md, "What
a step costs from Python"); not a test.

    PYTHONPATH=build/python python3 bench/env_bench.py --mode env [--duration 2] [--every 1]

Modes:
  builtin  Simulator.run(): the built-in sine, the loop in C++;
  env      VoxelEnv observing "time", the sine replayed from it with sin_cycles: the same
           life as builtin, bit for bit (the printed hash), one env.step per `every` steps;
  env-all  VoxelEnv observing every sensor (n x 11 + 5 numbers), the same replayed sine.
Prints the steps taken and the final state hash. Time two modes as whole processes in
alternation; (A - B) / steps is the cost per step of the difference.
"""

import argparse

import plastivox


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--mode", choices=["builtin", "env", "env-all"], required=True)
    ap.add_argument("--duration", type=float, default=2.0)
    ap.add_argument("--every", type=int, default=1)
    args = ap.parse_args()
    robot = plastivox.demo_walker().with_physics({"duration": args.duration})
    if args.mode == "builtin":
        sim = plastivox.Simulator(robot)
        sim.run()
        print(sim.steps, sim.state_hash)
        return
    sensors = None if args.mode == "env-all" else ["time"]
    at = -2 if args.mode == "env-all" else -1  # the time: before the phase when all are observed
    env = plastivox.VoxelEnv(robot, sensors=sensors, every=args.every)
    f, phase = env.act_frequency, env.voxel_phase
    obs, info = env.reset(seed=0)
    while True:
        obs, _, terminated, truncated, info = env.step(plastivox.sin_cycles(f * obs[at] + phase))
        if terminated or truncated:
            break
    print(info["steps"], info["state_hash"])


if __name__ == "__main__":
    main()
