"""Every example under examples/python runs, on tiny inputs (dask_sweep.py in test_dask.py,
on that suite's cluster)."""

import os
import subprocess
import sys

from conftest import SOURCE

EXAMPLES = os.path.join(SOURCE, "examples", "python")


def run_example(name, *args, env=None):
    p = subprocess.run([sys.executable, os.path.join(EXAMPLES, name), *args],
                       capture_output=True, text=True, env={**os.environ, **(env or {})})
    assert p.returncode == 0, p.stdout + p.stderr
    return p.stdout


def test_random_search(tmp_path):
    best = tmp_path / "best.json"
    out = run_example("random_search.py", "--robots", "6", "--size", "3", "--duration", "0.1",
                      "--threads", "2", "--out", str(best))
    assert "best is #" in out and best.exists()


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
    out = run_example("walkthrough.py", env={"WALKTHROUGH_DURATION": "0.3",
                                             "WALKTHROUGH_OUT": str(folder)})
    assert (folder / "walker.png").exists() and "frame (240, 320, 3)" in out
