"""Every example under examples/python runs, on small inputs, and its robot stands and walks
(dask_sweep.py runs in test_dask.py, on that suite's cluster)."""

import os
import subprocess
import sys

import plastivox
from conftest import SOURCE, assert_stands_and_walks, deepest_below_floor

EXAMPLES = os.path.join(SOURCE, "examples", "python")


def run_example(name, *args, env=None):
    p = subprocess.run([sys.executable, os.path.join(EXAMPLES, name), *args],
                       capture_output=True, text=True, env={**os.environ, **(env or {})})
    assert p.returncode == 0, p.stdout + p.stderr
    return p.stdout


def assert_saved_robot_stands(label, path, record_fps=100):
    """Simulates the robot file an example wrote, under the physics saved with it."""
    robot = plastivox.load_robot(path)
    r = plastivox.simulate(robot, record_fps=record_fps)
    t = r.trajectory
    assert_stands_and_walks(label, r.to_dict(),
                            deepest_below_floor(t.positions, t.sizes, robot.voxel_size))
    return r


def test_random_search(tmp_path):
    best = tmp_path / "best.json"
    out = run_example("random_search.py", "--robots", "8", "--size", "4", "--duration", "1.0",
                      "--threads", "2", "--out", str(best))
    assert "best is #" in out and best.exists()
    r = assert_saved_robot_stands("random_search.py's best robot", best)
    assert f"hash {r.final_state_hash}" in out


def test_results_report(tiny_run, tmp_path):
    path, _ = tiny_run
    out = run_example("results_report.py", path, "--out-dir", str(tmp_path), "--size", "64x48")
    assert (tmp_path / "champion.png").exists()
    assert "best fitness" in out
    try:
        import matplotlib  # noqa: F401
        assert (tmp_path / "fitness.png").exists()
    except ImportError:
        assert "matplotlib is not installed" in out


def test_walkthrough(tmp_path):
    folder = tmp_path / "not" / "made" / "yet"  # the walkthrough makes it
    out = run_example("walkthrough.py", env={"WALKTHROUGH_DURATION": "1.0",
                                             "WALKTHROUGH_OUT": str(folder)})
    assert (folder / "walker.png").exists() and "frame (240, 320, 3)" in out
    assert_saved_robot_stands("walkthrough.py's robot", folder / "walker.json")
