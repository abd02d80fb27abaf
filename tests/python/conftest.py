"""Shared fixtures of the Python suites: the CLI to compare against, the sample robots, and
a tiny evolved run. ctest sets PYTHONPATH (build/python), PLASTIVOX_CLI and
PLASTIVOX_TEST_DATA_DIR (python/CMakeLists.txt)."""

import json
import os
import subprocess

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
