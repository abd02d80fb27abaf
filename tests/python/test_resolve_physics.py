"""One precedence rule (docs/robot-format.md, "Resolving a run's physics"): the same inputs
resolve to the same physics from the command line (plastivox simulate, the physics a recorded
life stores), Python (simulate's result's robot) and an evolution config (the run's champion's
physics)."""

import json

import numpy as np
import pytest

import plastivox
from conftest import run_cli

QUICK = {"duration": 0.3, "settle_time": 0.1, "sinking_invalid": False}


def block_file(tmp_path, physics=None):
    """A 2x2x2 block of 1e8 Pa as a robot file, with `physics` as its own (else the default)."""
    robot = plastivox.Robot.from_arrays(np.ones((2, 2, 2), bool), np.full((2, 2, 2), 1e8),
                                        np.zeros((2, 2, 2)))
    if physics is not None:
        robot = robot.with_physics(physics)
    path = str(tmp_path / "block.json")
    robot.save(path)
    return path


def by_cli(tmp_path, robot_file, *args):
    """The physics `plastivox simulate` resolved, as its recorded life stores it."""
    life = str(tmp_path / "life.h5")
    code, _, err = run_cli("simulate", robot_file, "--record", life, "--json", *args, check=False)
    assert code in (0, 3), err  # a life that went unstable or sank still records its physics
    return plastivox._as_robot(life).physics.to_dict()


def by_config(tmp_path, treatment, task, physics):
    """The physics an evolution config resolved, as its run's champion carries it."""
    config = {"format": "plastivox-evolve-config", "version": 1, "seed": 1, "threads": 1,
              "treatment": treatment, "task": task, "population": 1, "generations": 0,
              "lattice": {"nx": 3, "ny": 3, "nz": 3, "voxel_size": 0.01}, "physics": physics}
    out = str(tmp_path / "run.h5")
    plastivox.evolve(config, out)
    return plastivox.read_results(out).champion().physics.to_dict()


def test_a_preset_a_physics_object_and_single_fields_resolve_alike_everywhere(tmp_path):
    robot = block_file(tmp_path)
    fields = {"preset": "gecco2018-paper", **QUICK, "mu_static": 0.8}
    cli = by_cli(tmp_path, robot, "--physics", json.dumps(fields), "--treatment", "pressure",
                 "--task", "jump")
    python = plastivox.simulate(robot, physics=fields, treatment="pressure",
                                task="jump").robot.physics.to_dict()
    config = by_config(tmp_path, "pressure", "jump", fields)
    assert cli == python == config
    assert cli["growth"] == "rate" and cli["treatment"] == "pressure" and cli["task"] == "jump"
    assert cli["mu_static"] == 0.8 and cli["duration"] == 0.3


def test_a_preset_keeps_the_robots_task_from_the_command_line_and_from_python(tmp_path):
    # The CLI's --preset kept the robot's task where a Python PhysicsDef (a preset's whole
    # physics) replaced it with walk; both keep it now, as a config's top-level task does.
    climb = {"name": "climb", "rise": 0.5}
    robot = block_file(tmp_path, {"task": climb})
    cli = by_cli(tmp_path, robot, "--preset", "gecco2018-paper", "--physics", json.dumps(QUICK))
    preset = plastivox.physics("gecco2018-paper", **QUICK)
    assert preset.task is None  # names none: the robot's stays
    python = plastivox.simulate(robot, physics=preset).robot.physics.to_dict()
    config = by_config(tmp_path, "none", climb, {"preset": "gecco2018-paper", **QUICK})
    assert cli == python == config
    assert cli["task"] == {"name": "climb", "rise": 0.5} and cli["growth"] == "rate"
    # Named, the PhysicsDef's task wins over the robot's, as a physics object's does.
    named = plastivox.simulate(robot, physics=preset.replace(task="jump")).robot.physics
    assert named.task == "jump"
    assert by_cli(tmp_path, robot, "--preset", "gecco2018-paper", "--physics",
                  json.dumps({**QUICK, "task": "jump"})) == named.to_dict()


def test_the_single_fields_win_and_errors_name_the_field(tmp_path):
    robot = block_file(tmp_path, {"task": {"name": "climb", "rise": 0.5}})
    # --duration wins over the physics object, validated once at the end.
    long = {"settle_time": 1.0, "sinking_invalid": False}
    cli = by_cli(tmp_path, robot, "--physics", json.dumps(long), "--duration", "1.1",
                 "--task", "climb")
    python = plastivox.Robot(plastivox._core.load_source(robot)).with_physics(
        {**long, "duration": 1.1}, task="climb").physics.to_dict()
    assert cli == python and cli["task"] == {"name": "climb", "rise": 0.5}  # same task: kept
    code, _, err = run_cli("simulate", robot, "--physics", '{"settle_time": 9}', check=False)
    assert code == 1 and "--physics: physics.duration: must be a number of seconds from " \
        "settle_time" in err, err
    with pytest.raises(ValueError, match=r"^physics.duration: must be a number of seconds from"):
        plastivox.simulate(robot, physics={"settle_time": 9})
