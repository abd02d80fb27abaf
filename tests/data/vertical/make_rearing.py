#!/usr/bin/env python3
"""Makes the vertical rule's test robots (README.md beside this file): CMA-ES (Debian's
python3-cmaes) on the 95 weights of a distributed controller (4 hidden units, every step) of
a fixed body, each candidate simulated with plastivox.simulate_many under the body's own
physics (gecco2018-code: walk scored in 3-D). Not run by the tests, which replay its output.

  PYTHONPATH=build/python /usr/bin/python3 tests/data/vertical/make_rearing.py \\
      --objective fitness --out rearing.json
  ... --objective rise --out riser.json

--objective fitness maximises walk's 3-D fitness, as a user's optimiser would (the search
finds a rise as early as a stride); --objective rise maximises dist_z less the horizontal
distance, for a life whose fitness is mostly rise. Prints each generation's best, its
dist_z and vertical_share.
"""
import argparse
import json

import numpy as np
import plastivox
from cmaes import CMA


def small_walker():
    """A 96-voxel walker: a 6 x 4 x 2 slab on two 2 x 4 legs three voxels high, 5e9 Pa, under
    stress development and the gecco2018-code physics (5.2 s lives, walk scored in 3-D)."""
    g = np.zeros((6, 4, 5), bool)
    g[:, :, 3:] = True
    g[0:2, :, :3] = g[4:6, :, :3] = True
    return plastivox.Robot.from_arrays(g, stiffness=np.full(g.shape, 5e9), phase=np.zeros(g.shape),
                                       treatment="stress", name="small-walker")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--robot", help="body to start from (default: small_walker() below)")
    ap.add_argument("--objective", choices=["fitness", "rise"], default="fitness")
    ap.add_argument("--generations", type=int, default=4)
    ap.add_argument("--popsize", type=int, default=0, help="0: CMA-ES's default")
    ap.add_argument("--sigma", type=float, default=0.5)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--physics", default="{}", help="JSON applied on top of the body's physics")
    ap.add_argument("--threads", type=int, default=0)
    ap.add_argument("--out", required=True)
    a = ap.parse_args()

    body = plastivox.load_robot(a.robot) if a.robot else small_walker()
    body = body.with_physics(json.loads(a.physics))
    n = plastivox.controller_weight_count("distributed", 4)
    opt = CMA(mean=np.zeros(n), sigma=a.sigma, seed=a.seed,
              population_size=a.popsize or None)

    def score(r):
        if r.status != "finished":
            return -1e9
        if a.objective == "fitness":
            return r.fitness
        return r.dist_z - np.hypot(r.dist_x, r.dist_y)  # rise, less any walk

    best = None
    for g in range(a.generations):
        xs = [opt.ask() for _ in range(opt.population_size)]
        robots = [body.with_controller("distributed", hidden=4, every=1, weights=x) for x in xs]
        results = plastivox.simulate_many(robots, threads=a.threads)
        scores = [score(r) for r in results]
        opt.tell([(x, -s) for x, s in zip(xs, scores)])
        k = int(np.argmax(scores))
        if best is None or scores[k] > best[0]:
            best = (scores[k], robots[k], results[k])
        r = results[k]
        print(f"generation {g}: best {scores[k]:.3f} (fitness {r.fitness:.3f}, "
              f"dist_xy {np.hypot(r.dist_x, r.dist_y):.3f}, dist_z {r.dist_z:.3f}, "
              f"vertical_share {r.vertical_share:.3f}, health {r.health})", flush=True)
    _, robot, r = best
    robot.save(a.out)
    print(f"{a.out}: fitness {r.fitness:.3f}, dist_z {r.dist_z:.3f}, "
          f"vertical_share {r.vertical_share:.3f}")


if __name__ == "__main__":
    main()
