"""Scale-out on Dask: robots pickled to a 2-process LocalCluster, each batch simulated there
with simulate_many, give the hashes simulate_many gives here; examples/python/dask_sweep.py
runs against the same cluster. Registered only when the interpreter has dask.distributed
(Debian python3-distributed; python/CMakeLists.txt)."""

import operator
import os
import subprocess
import sys

import numpy as np
import pytest
from dask.distributed import Client, LocalCluster

import plastivox
from conftest import SOURCE

PHYSICS = {"duration": 0.2, "settle_time": 0.1}
# Debian's tornado under distributed 2022.12; nothing of ours.
pytestmark = pytest.mark.filterwarnings("ignore:make_current is deprecated:DeprecationWarning")


@pytest.fixture(scope="module")
def client():
    # Two worker processes, one Dask thread each, no dashboard (no port to clash over).
    cluster = LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                           dashboard_address=None)
    c = Client(cluster)
    yield c
    c.close()
    cluster.close()


def small_robots(count, seed=5):
    rng = np.random.default_rng(seed)
    robots = []
    for i in range(count):
        g = rng.random((3, 3, 2)) < 0.7
        g[:, :, 0] = True
        robots.append(plastivox.Robot.from_arrays(
            g, 10 ** rng.uniform(6, 8, g.shape), rng.uniform(-0.9, 0.9, g.shape),
            treatment="stress", name=f"r{i}"))
    return robots


def test_cluster_gives_the_hashes_of_simulate_many(client):
    workers = sorted(client.scheduler_info()["workers"])
    pids = client.run(os.getpid)
    assert len(workers) == 2 and len(set(pids.values()) | {os.getpid()}) == 3
    robots = small_robots(8)
    # batches of 2, pinned alternately to each worker so both processes simulate
    futures = [client.submit(plastivox.simulate_many, robots[i:i + 2], physics=PHYSICS,
                             threads=1, workers=[workers[i // 2 % 2]], pure=False)
               for i in range(0, len(robots), 2)]
    remote = [r for batch in client.gather(futures) for r in batch]
    here = plastivox.simulate_many(robots, physics=PHYSICS, threads=2)
    assert [r.final_state_hash for r in remote] == [r.final_state_hash for r in here]
    assert len({r.final_state_hash for r in here}) == len(robots)  # really different lives
    for a, b, robot in zip(remote, here, robots):
        assert a.fitness == b.fitness and np.array_equal(a.final_stiffness, b.final_stiffness)
        assert a.robot == robot  # the robot went there and back bit for bit


def test_a_robot_file_path_works_on_a_worker(client, tmp_path):
    robot = small_robots(1, seed=9)[0].with_physics(PHYSICS)
    path = str(tmp_path / "robot.json")
    robot.save(path)
    remote = client.submit(plastivox.simulate, path, pure=False).result()
    assert remote.final_state_hash == plastivox.simulate(robot).final_state_hash
    assert remote.robot == robot
    # a Result made on a worker, sent back there, gives its robot back unchanged
    assert client.submit(operator.attrgetter("robot"), remote, pure=False).result() == robot


def test_dask_sweep_example(client):
    p = subprocess.run([sys.executable, os.path.join(SOURCE, "examples", "python", "dask_sweep.py"),
                        "--scheduler", client.scheduler.address, "--robots", "6", "--size", "3",
                        "--duration", "0.2", "--batch", "2", "--check"],
                       capture_output=True, text=True)
    assert p.returncode == 0, p.stdout + p.stderr
    assert "6 robots in 3 tasks on 2 workers" in p.stdout
    assert "the same final_state_hash as simulate_many here for all 6 robots" in p.stdout
