"""Random search: evaluate random robots with simulate_many and print the best one.

    PYTHONPATH=build/python python3 examples/python/random_search.py [--robots 50] [--size 5]
        [--duration 1.0] [--threads 0] [--out best.json]
"""

import argparse

import numpy as np

import plastivox


def random_robot(rng, n):
    """A random body on an n^3 lattice: about half the sites filled, log-uniform stiffness,
    random phases; the bottom layer is kept full so every body stands on the floor."""
    geometry = rng.random((n, n, n)) < 0.5
    geometry[:, :, 0] = True
    # 1e10..1e11 Pa: under the presets' density (1e9 kg/m^3, 1000 kg per 1 cm voxel) softer
    # bodies press their feet into the floor (below ~1e7 Pa they fall through it).
    stiffness = 10 ** rng.uniform(10, 11, (n, n, n))
    phase = rng.uniform(-1, 1, (n, n, n)) * 0.999
    return plastivox.Robot.from_arrays(geometry, stiffness, phase, treatment="none")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--robots", type=int, default=50)
    ap.add_argument("--size", type=int, default=5, help="lattice sites per side")
    ap.add_argument("--duration", type=float, default=1.0, help="simulated seconds per life")
    ap.add_argument("--threads", type=int, default=0, help="0: all cores")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--out", help="save the best robot here (.json or .vxa)")
    args = ap.parse_args()

    rng = np.random.default_rng(args.seed)
    robots = [random_robot(rng, args.size) for _ in range(args.robots)]
    physics = {"duration": args.duration, "settle_time": min(0.2, args.duration / 2)}
    results = plastivox.simulate_many(robots, physics=physics, threads=args.threads)
    ok = [i for i, r in enumerate(results) if r.status == "finished"]
    if not ok:
        raise SystemExit("every simulation went unstable or sank through the floor")
    best = max(ok, key=lambda i: results[i].fitness)
    r = results[best]
    print(f"{len(results)} robots, {len(results) - len(ok)} unstable or sunk; best is #{best}: "
          f"fitness {r.fitness:.4f} voxel lengths, {r.voxels} voxels, floor {r.health}, "
          f"hash {r.final_state_hash}")
    if args.out:
        robots[best].with_physics(physics).save(args.out)
        print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
