"""Shared fixtures of the Python suites: the CLI to compare against, the sample robots, and
a tiny evolved run. ctest sets PYTHONPATH (build/python), PLASTIVOX_CLI and
PLASTIVOX_TEST_DATA_DIR (python/CMakeLists.txt)."""

import json
import os
import subprocess
import threading
import time

import numpy as np
import pytest

import plastivox

CLI = os.environ.get("PLASTIVOX_CLI", "")
DATA = os.environ.get("PLASTIVOX_TEST_DATA_DIR", os.path.join(os.path.dirname(__file__), "../data"))
SOURCE = os.environ.get("PLASTIVOX_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "../.."))


def run_cli(*args, check=True):
    """Runs the plastivox program; returns (exit status, stdout, stderr)."""
    assert CLI and os.path.exists(CLI), "PLASTIVOX_CLI must name the built plastivox program"
    p = subprocess.run([CLI, *args], capture_output=True, text=True)
    if check:
        assert p.returncode == 0, p.stderr
    return p.returncode, p.stdout, p.stderr


def cli_json(*args):
    return json.loads(run_cli(*args)[1])


def main_thread_turns(call):
    """Runs call() in another thread and counts how often this thread wakes (every
    millisecond) from the call's start to its end. A call that releases the GIL lets it wake
    about once a millisecond; one that holds it, only in the few bytecodes around the call."""
    inside = threading.Event()
    done = threading.Event()

    def work():
        inside.set()
        try:
            call()
        finally:
            done.set()

    worker = threading.Thread(target=work)
    worker.start()
    inside.wait()
    turns = 0
    while not done.is_set():
        turns += 1
        time.sleep(0.001)
    worker.join()
    return turns


def expect_signals_refused(take, name, n):
    """take(signal), which takes one value per voxel in [-1, 1] (Simulator.set_actuation,
    VoxelEnv.step), refuses a wrong shape, an integer or object array and a value out of range,
    each in one line naming the argument `name`, and takes float32."""
    with pytest.raises(ValueError, match=r"%s: expected shape \(%d,\).*got \(%d,\)" % (name, n, n + 1)):
        take(np.zeros(n + 1))
    with pytest.raises(TypeError, match=r"%s: expected a float array .*int64" % name):
        take(np.zeros(n, dtype=np.int64))
    with pytest.raises(TypeError, match=r"%s: expected a float array .* got dtype object" % name):
        take(None)
    u = np.zeros(n)
    u[2] = 1.5
    with pytest.raises(ValueError, match=r"%s: every value must be in \[-1, 1\]; %s\[2\] is 1.5" % (name, name)):
        take(u)
    take(np.full(n, 0.5, dtype=np.float32))


# Under the sanitizers (python/CMakeLists.txt sets PLASTIVOX_SANITIZED) a whole life costs
# tens of seconds: the suites that compare whole lives with the command line's shorten them
# there to QUICK_LIFE's physics (the Release suite runs them whole; the engine's own code is
# the same at any length).
SANITIZED = os.environ.get("PLASTIVOX_SANITIZED") == "1"
QUICK_LIFE = {"duration": 1.0} if SANITIZED else {}


def vxa(name):
    return os.path.join(DATA, "vxa", name)


def tiny_config(treatment="pressure", generations=2):
    """5x5x5 lattice, population 4, 0.3 s lives: an evolution of a few seconds."""
    c = plastivox.default_config()
    c.update(generations=generations, population=4, treatment=treatment, threads=1,
             lattice={"nx": 5, "ny": 5, "nz": 5, "voxel_size": 0.01},
             physics={"preset": "gecco2018-code", "duration": 0.3, "settle_time": 0.1})
    return c


@pytest.fixture(scope="session")
def tiny_run(tmp_path_factory):
    """A finished tiny evolution: (results path, config dict)."""
    d = tmp_path_factory.mktemp("tiny")
    config = tiny_config()
    out = str(d / "tiny.h5")
    report = plastivox.evolve(config, out, threads=1)
    assert report["outcome"] == "finished" and report["generations_done"] == 2
    return out, config


# Standing and walking, in voxel lengths. A life stands when it finished, did not sink
# (simulate's "sank through the floor" warning) and no voxel's bottom face went deeper than
# FLOOR_TOLERANCE below z = 0 in any frame of the life: the bound of the engine's `ok` grade
# (docs/engine.md, "Floor contact and sinking"; feet pressed a little into the floor are
# normal, a body that cannot carry itself goes a voxel or more under). It walks when its
# centre of mass moved more than MIN_STRIDE in the xy-plane.
FLOOR_TOLERANCE = 0.5
MIN_STRIDE = 0.1


def deepest_below_floor(positions, sizes, voxel_size):
    """The deepest any voxel's bottom face went below z = 0 over the frames, voxel lengths
    (negative when every voxel stayed above it): positions (F, n, 3) m, sizes (F, n) m."""
    positions, sizes = np.asarray(positions), np.asarray(sizes)
    return float(-(positions[:, :, 2] - sizes / 2).min() / voxel_size)


def assert_stands_and_walks(label, summary, deepest):
    """summary: `simulate --json`'s object (or Result.to_dict()); deepest: deepest_below_floor
    of its recorded life, an independent check of the engine's own floor grade (`health`)."""
    assert summary["status"] == "finished", f"{label}: {summary.get('failure', '')}"
    assert summary["health"] == "ok", f"{label}: health {summary['health']}, {summary['warnings']}"
    sank = [w for w in summary.get("warnings", []) if "sank" in w]
    assert not sank and deepest <= FLOOR_TOLERANCE, \
        f"{label}: voxels {deepest:.3f} voxel lengths below the floor; {sank}"
    stride = float(np.hypot(summary["dist_x"], summary["dist_y"]))
    assert stride > MIN_STRIDE, f"{label}: moved {stride:.3f} voxel lengths in the xy-plane"
