"""One life of the demo walker (512 voxels, stress development) stepped one way, for
whole-process timing of plastivox.VoxelEnv against the built-in loop (docs/control.md, "What
a step costs from Python"); not a test.

    PYTHONPATH=build/python python3 bench/env_bench.py --mode env [--duration 2] [--every 1]

Modes:
  builtin  Simulator.run(): the built-in sine, the loop in C++;
  env      VoxelEnv observing "time", the sine replayed from it with sin_cycles: the same
           life as builtin, bit for bit (the printed hash), one env.step per `every` steps;
  env-all  VoxelEnv observing every sensor (n x 11 + 5 numbers), the same replayed sine;
  loop     --num-envs VoxelEnvs observing "time", stepped one after another by a Python loop,
           each the same life as env;
  vec      one VoxelVecEnv of --num-envs environments on --threads threads, observing
           "time": the same lives as loop, bit for bit, one call per step for all of them.
Prints the steps taken and the final state hash (loop and vec: of every environment). Time
two modes as whole processes in alternation; (A - B) / steps is the cost per step of the
difference, and loop against vec the batch's speed-up.
"""

import argparse

import numpy as np

import plastivox


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--mode", choices=["builtin", "env", "env-all", "loop", "vec"], required=True)
    ap.add_argument("--duration", type=float, default=2.0)
    ap.add_argument("--every", type=int, default=1)
    ap.add_argument("--num-envs", type=int, default=8)
    ap.add_argument("--threads", type=int, default=0)
    args = ap.parse_args()
    robot = plastivox.demo_walker().with_physics({"duration": args.duration})
    if args.mode in ("loop", "vec"):
        many(robot, args)
        return
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


def many(robot, args):
    """N lives of the replayed sine, batched (vec) or in a Python loop (loop)."""
    n = args.num_envs
    if args.mode == "vec":
        vec = plastivox.VoxelVecEnv(robot, num_envs=n, sensors=["time"], every=args.every,
                                    threads=args.threads)
        env = vec.single_env
        obs, _ = vec.reset(seed=0)
        done = np.zeros(n, dtype=bool)
        while not done.all():
            # every life has the same length, so all end at the same step
            obs, _, terminated, truncated, infos = vec.step(
                plastivox.sin_cycles(env.act_frequency * obs[:, -1:] + env.voxel_phase))
            done = terminated | truncated
        print(int(infos["steps"].sum()), *(vec.state_hash(i) for i in range(n)))
        return
    envs = [plastivox.VoxelEnv(robot, sensors=["time"], every=args.every) for _ in range(n)]
    f, phase = envs[0].act_frequency, envs[0].voxel_phase
    obs = [env.reset(seed=i)[0] for i, env in enumerate(envs)]
    infos = [None] * n
    running = True
    while running:
        for i, env in enumerate(envs):
            obs[i], _, terminated, truncated, infos[i] = env.step(
                plastivox.sin_cycles(f * obs[i][-1] + phase))
            running = not (terminated or truncated)
    print(sum(info["steps"] for info in infos), *(info["state_hash"] for info in infos))


if __name__ == "__main__":
    main()
