"""Sweep: evaluate many random robots on a Dask cluster and print the best.

    PYTHONPATH=build/python python3 examples/python/dask_sweep.py [--robots 64] [--size 4]
        [--duration 0.5] [--treatment stress] [--batch 8] [--threads 1] [--workers 2]
        [--scheduler ADDRESS | --scheduler-file FILE] [--check]

The robots are made here and sent to the workers in batches (a Robot pickles). Each Dask
task is one plastivox.simulate_many call: the worker simulates its batch on `--threads` of
the module's own C++ threads, with the GIL released, and the Results come back pickled, in
input order. Every life is bit-identical to simulate() of that robot alone, wherever it ran;
--check proves it by running simulate_many here too and comparing final_state_hash.

Without --scheduler this starts a LocalCluster of `--workers` processes, one Dask thread each
(the parallelism inside a worker is simulate_many's). With --scheduler (tcp://host:8786) or
--scheduler-file it joins a cluster started elsewhere, e.g. by a Slurm batch script
(docs/python.md, "Scale-out on Dask"); then give --threads the cores of one worker.
"""

import argparse
import time

import numpy as np
from dask.distributed import Client, LocalCluster

import plastivox
from random_search import random_robot  # this folder's random bodies


def batches(items, size):
    return [items[i:i + size] for i in range(0, len(items), size)]


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--robots", type=int, default=64)
    ap.add_argument("--size", type=int, default=4, help="lattice sites per side")
    ap.add_argument("--duration", type=float, default=0.5, help="simulated seconds per life")
    ap.add_argument("--treatment", default="stress")
    ap.add_argument("--batch", type=int, default=8, help="robots per Dask task")
    ap.add_argument("--threads", type=int, default=1,
                    help="simulate_many threads in each task (0: all cores of the worker's machine)")
    ap.add_argument("--workers", type=int, default=2, help="LocalCluster worker processes")
    ap.add_argument("--scheduler", help="address of a running Dask scheduler")
    ap.add_argument("--scheduler-file", help="the file `dask scheduler --scheduler-file` wrote")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--check", action="store_true",
                    help="also run simulate_many here and compare the hashes")
    args = ap.parse_args()
    if args.batch < 1:
        raise SystemExit("--batch: must be >= 1")

    rng = np.random.default_rng(args.seed)
    robots = [random_robot(rng, args.size) for _ in range(args.robots)]
    physics = {"duration": args.duration, "settle_time": min(0.2, args.duration / 2)}

    if args.scheduler or args.scheduler_file:
        cluster = None
        client = Client(args.scheduler, scheduler_file=args.scheduler_file)
    else:
        cluster = LocalCluster(n_workers=args.workers, threads_per_worker=1, processes=True,
                               dashboard_address=None)
        client = Client(cluster)
    try:
        start = time.perf_counter()
        futures = [client.submit(plastivox.simulate_many, batch, physics=physics,
                                 treatment=args.treatment, threads=args.threads, pure=False)
                   for batch in batches(robots, args.batch)]
        results = [r for batch in client.gather(futures) for r in batch]
        seconds = time.perf_counter() - start
        workers = len(client.scheduler_info()["workers"])
    finally:
        client.close()
        if cluster is not None:
            cluster.close()

    ok = [i for i, r in enumerate(results) if r.status == "finished"]
    print(f"{len(results)} robots in {len(futures)} tasks on {workers} workers, "
          f"{seconds:.2f} s; {len(results) - len(ok)} unstable")
    for i in sorted(ok, key=lambda i: results[i].fitness, reverse=True)[:5]:
        r = results[i]
        print(f"  #{i}: fitness {r.fitness:.4f} voxel lengths, {r.voxels} voxels, "
              f"hash {r.final_state_hash}")
    if args.check:
        here = plastivox.simulate_many(robots, physics=physics, treatment=args.treatment)
        same = [a.final_state_hash == b.final_state_hash for a, b in zip(here, results)]
        if not all(same):
            raise SystemExit(f"robot #{same.index(False)}: a different hash on the cluster")
        print(f"the same final_state_hash as simulate_many here for all {len(results)} robots")


if __name__ == "__main__":
    main()
