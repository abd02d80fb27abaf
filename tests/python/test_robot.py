"""Robots and physics: arrays in and out, lossless files, errors that name the argument."""

import itertools
import json
import math
import os
import pickle
import warnings

import numpy as np
import pytest

import plastivox
from conftest import DATA, run_cli, vxa


def small_arrays(shape=(3, 2, 2)):
    rng = np.random.default_rng(1)
    g = np.ones(shape, dtype=bool)
    g[0, 0, 1] = False
    e = np.where(g, rng.uniform(1e6, 1e8, shape), 0.0)
    p = np.where(g, rng.uniform(-0.9, 0.9, shape), 0.0)
    a = np.where(g, rng.uniform(-1e6, 1e6, shape), 0.0)
    return g, e, p, a


def test_arrays_come_back_with_lattice_indexing():
    g, e, p, a = small_arrays()
    r = plastivox.Robot.from_arrays(g, e, p, dev_rate=a, treatment="stress", voxel_size=0.02)
    assert r.shape == (3, 2, 2) and r.voxel_size == 0.02 and r.treatment == "stress"
    assert r.voxel_count == g.sum()
    assert r.geometry.dtype == bool and np.array_equal(r.geometry, g)
    for got, want in ((r.stiffness, e), (r.phase, p), (r.dev_rate, a)):
        assert got.shape == g.shape and got.dtype == np.float64
        assert np.array_equal(got, want)
    # integer geometry works too, and [x, y, z] is lattice site x + nx*(y + ny*z)
    r2 = plastivox.Robot.from_arrays(g.astype(np.int32), e, p, dev_rate=a)
    assert np.array_equal(r2.geometry, g)
    assert r.physics["treatment"] == "stress"


@pytest.mark.parametrize("ext", ["json", "vxa"])
def test_save_and_load_are_lossless(tmp_path, ext):
    g, e, p, a = small_arrays()
    r = plastivox.Robot.from_arrays(g, e, p, dev_rate=a, treatment="pressure")
    path = tmp_path / f"r.{ext}"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # VXA cannot hold every field: warned, not silent
        r.save(path)
        back = plastivox.load_robot(path)
    for name in ("geometry", "stiffness", "phase", "dev_rate"):
        assert np.array_equal(getattr(back, name), getattr(r, name)), name
    assert back.shape == r.shape and back.voxel_size == r.voxel_size
    assert back.treatment == "pressure"
    if ext == "json":
        assert back.physics == r.physics
        # every physics field survives a robot file, the bond model included
        other = r.with_physics({"bond_model": "voxelyze09", "axial_modulus": "negative-voxel",
                                "fitness": "xy", "growth": "rate", "floor": False})
        other.save(path)
        assert plastivox.load_robot(path).physics == other.physics


@pytest.mark.parametrize("name", ["walker-stress.vxa", "walker-pressure.vxa"])
def test_vxa_sample_roundtrip(tmp_path, name):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        r = plastivox.load_robot(vxa(name))
        for ext in ("vxa", "json"):
            path = tmp_path / f"copy.{ext}"
            r.save(path)
            back = plastivox.load_robot(path)
            assert back.physics == r.physics, ext
            for field in ("geometry", "stiffness", "phase", "dev_rate"):
                assert np.array_equal(getattr(back, field)[r.geometry], getattr(r, field)[r.geometry])


def test_physics_presets_and_overrides():
    code = plastivox.physics()
    paper = plastivox.physics("gecco2018-paper")
    assert code["growth"] == "integral" and paper["growth"] == "rate"
    assert plastivox.physics(duration=1.5, treatment="stress")["duration"] == 1.5
    assert plastivox.physics(floor=False)["floor"] is False
    with pytest.raises(plastivox.InputError, match="physics.not_a_field"):
        plastivox.physics(not_a_field=1)
    with pytest.raises(ValueError, match="physics.poisson"):
        plastivox.physics(poisson="a lot")
    with pytest.raises(ValueError, match="physics.density"):
        plastivox.physics(density=math.nan)
    with pytest.raises(ValueError, match="dt_frac"):
        plastivox.physics(dt_frac=7.0)
    with pytest.raises(ValueError, match="preset"):
        plastivox.physics("no-such-preset")
    r = plastivox.demo_walker()
    with pytest.raises(plastivox.InputError, match="physics.bogus"):
        plastivox.simulate(r, physics={"bogus": 1})
    with pytest.raises(ValueError, match="treatment"):
        plastivox.simulate(r, treatment="sunlight")
    with pytest.raises(TypeError, match="physics"):
        plastivox.simulate(r, physics="fast")


def test_bad_files_raise_input_error_with_the_cli_message(tmp_path):
    bad = tmp_path / "bad.json"
    bad.write_text('{"format": "plastivox-robot", "version": 1, "lattice": {"nx": 2}}')
    with pytest.raises(plastivox.InputError) as err:
        plastivox.load_robot(bad)
    status, _, cli_err = run_cli("simulate", str(bad), check=False)
    assert status == 1
    assert str(err.value) in cli_err  # the same one-line message
    assert str(bad) in str(err.value)
    broken = tmp_path / "broken.vxa"
    broken.write_text("<VXA><not closed")
    with pytest.raises(plastivox.InputError, match="broken.vxa"):
        plastivox.load_robot(broken)
    with pytest.raises(plastivox.InputError, match="missing.json"):
        plastivox.load_robot(tmp_path / "missing.json")
    with pytest.raises(plastivox.InputError, match=".json or .vxa"):
        plastivox.load_robot(tmp_path / "robot.txt")
    with pytest.raises(ValueError, match="path"):
        plastivox.demo_walker().save(tmp_path / "robot.txt")
    assert issubclass(plastivox.InputError, ValueError)


def test_bad_arrays_name_the_argument():
    g, e, p, a = small_arrays()
    R = plastivox.Robot.from_arrays
    with pytest.raises(ValueError, match="stiffness.*disagrees"):
        R(g, e[:2], p)
    with pytest.raises(ValueError, match="phase.*disagrees"):
        R(g, e, p[:, :1])
    with pytest.raises(ValueError, match="dev_rate"):
        R(g, e, p, dev_rate=a[..., :1])
    with pytest.raises(ValueError, match="geometry.*shape"):
        R(g[0], e[0], p[0])
    with pytest.raises(TypeError, match="geometry"):
        R(g.astype(float), e, p)
    with pytest.raises(TypeError, match="stiffness"):
        R(g, e.astype(str), p)
    with pytest.raises(TypeError, match="stiffness"):
        R(g, "stiff", p)
    bad = e.copy()
    bad[1, 1, 1] = np.nan
    with pytest.raises(ValueError, match=r"stiffness: not finite at voxel \[1, 1, 1\]"):
        R(g, bad, p)
    bad[1, 1, 1] = -5
    with pytest.raises(ValueError, match="stiffness: must be > 0"):
        R(g, bad, p)
    with pytest.raises(ValueError, match="geometry: no voxel"):
        R(np.zeros_like(g), e, p)
    with pytest.raises(ValueError, match="empty"):
        R(np.zeros((0, 2, 2), bool), np.zeros((0, 2, 2)), np.zeros((0, 2, 2)))
    with pytest.raises(ValueError, match="voxel_size"):
        R(g, e, p, voxel_size=-1)
    with pytest.raises(ValueError, match="treatment"):
        R(g, e, p, treatment="sun")


def test_fuzzed_array_inputs_never_crash():
    """Odd shapes, dtypes and values for geometry, stiffness and phase: each raises a Python
    error naming an argument or builds a robot that simulates (briefly); none takes the
    interpreter down."""
    rng = np.random.default_rng(3)
    shapes = [(2, 2, 2), (1, 1, 1), (2, 2, 3), (2, 2), (0, 3, 3), (2, 2, 2, 1)]
    values = {
        "bool": lambda s: np.ones(s, dtype=bool),
        "int8": lambda s: np.full(s, 3, dtype=np.int8),
        "uint64": lambda s: np.full(s, 2**63, dtype=np.uint64),
        "float": lambda s: rng.uniform(1e5, 1e9, s),
        "float32": lambda s: rng.uniform(-0.5, 0.5, s).astype(np.float32),
        "nan": lambda s: np.full(s, np.nan),
        "inf": lambda s: np.full(s, np.inf),
        "negative": lambda s: np.full(s, -1.0),
        "huge": lambda s: np.full(s, 1e300),
        "complex": lambda s: np.zeros(s, dtype=np.complex128),
        "str": lambda s: np.full(s, "x"),
        "object": lambda s: np.full(s, None, dtype=object),
        "ragged": lambda s: [[1, 2], [3]],
        "none": lambda s: None,
        "scalar": lambda s: 1.0,
    }
    names = list(values)
    built = raised = 0
    for g_shape, g_kind, e_shape, e_kind in itertools.product(shapes, names, shapes, names):
        if g_kind not in ("bool", "int8", "uint64", "float", "str", "none", "ragged"):
            continue
        try:
            r = plastivox.Robot.from_arrays(values[g_kind](g_shape), values[e_kind](e_shape),
                                            np.zeros(e_shape), treatment="stress")
        except (ValueError, TypeError) as e:
            assert any(arg in str(e) for arg in ("geometry", "stiffness", "phase")), str(e)
            raised += 1
            continue
        built += 1
        res = plastivox.simulate(r, physics={"duration": 0.02, "settle_time": 0.01})
        assert res.status in ("finished", "unstable")
    assert built > 0 and raised > 1000


def test_wrong_argument_types():
    with pytest.raises(TypeError, match="robot"):
        plastivox.simulate(b"walker.json")
    with pytest.raises(plastivox.InputError, match="walker.json: cannot open"):
        plastivox.simulate("walker.json")  # a path is read (tests/python/test_objects.py)
    with pytest.raises(TypeError, match=r"robots\[1\]"):
        plastivox.simulate_many([plastivox.demo_walker(), 3])
    with pytest.raises(ValueError, match="threads"):
        plastivox.simulate_many([], threads=-2)
    with pytest.raises(ValueError, match="record_fps"):
        plastivox.simulate(plastivox.demo_walker(), record_fps=-1)
    with pytest.raises(ValueError, match="n:"):
        plastivox.Simulator(plastivox.demo_walker()).step(-3)
    assert plastivox.simulate_many([]) == []


def test_from_arrays_checks_the_lattice_size_before_copying():
    """Broadcast arrays of 1000^3 sites cost no memory; from_arrays used to convert them (7.45
    GiB) before the engine's lattice limit was checked. The limit is checked on the shape."""
    big = np.broadcast_to(np.ones(1, bool), (1000, 1000, 1000))
    e = np.broadcast_to(np.full(1, 1e9), big.shape)
    with pytest.raises(ValueError, match=r"geometry: a 1000x1000x1000 lattice has 1000000000 sites"):
        plastivox.Robot.from_arrays(big, e, e)


def test_voxcraft_demo_loads_with_its_vxd_and_stands_on_the_floor(tmp_path):
    base = os.path.join(DATA, "voxcraft", "bigbuy", "base.vxa")
    vxd = os.path.join(DATA, "voxcraft", "bigbuy", "robot_0000.vxd")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        robot = plastivox.load_robot(base, vxd=vxd)
    assert any("FitnessFunction" in str(w.message) for w in caught)
    assert robot.voxel_count == 21 and robot.shape == (3, 3, 3)
    assert robot.source == base + " + " + vxd
    amp = robot.act_amplitude
    assert amp[0, 0, 0] == 7.72173 * 0.01 and amp[1, 0, 0] == 0  # muscle, bone
    assert robot.stiffness[0, 0, 0] == 3e7 and robot.phase[0, 0, 0] == 0.437
    assert robot.physics["act_expansion"] is False and robot.physics["duration"] == 2
    # same life as the command line, and a pickle keeps the amplitudes
    r = plastivox.simulate(robot)
    _, out, _ = run_cli("simulate", base, "--vxd", vxd, "--json")
    assert r.final_state_hash == json.loads(out)["final_state_hash"]
    back = pickle.loads(pickle.dumps(robot))
    assert back == robot and np.array_equal(back.act_amplitude, amp)
    assert plastivox.simulate(back).final_state_hash == r.final_state_hash
    assert plastivox.load_robot(vxa("walker-none.vxa")).act_amplitude is None
    with pytest.raises(plastivox.InputError, match="none.vxd"):
        plastivox.load_robot(base, vxd=tmp_path / "none.vxd")


def test_an_environment_rides_with_the_physics_through_pickles_and_equality():
    low = {"ground": {"type": "flat", "height": -0.01}}  # the body drops 1 cm onto it
    d = plastivox.physics(environment=low, duration=0.3)
    assert d.environment["ground"]["type"] == "flat" and d["environment"] == d.environment
    assert "environment" in d.keys() and d.to_dict()["environment"] == d.environment
    flat_floor = plastivox.physics()
    assert flat_floor.environment is None and "environment" not in flat_floor.keys()
    walker = plastivox.demo_walker().with_physics(d)
    back = pickle.loads(pickle.dumps(walker))
    assert back == walker and hash(back) == hash(walker)
    # d names no treatment nor task, so the walker keeps its own (stress, walk); its physics
    # names them.
    assert back.physics == d.replace(treatment="stress", task="walk") and back.physics != d
    assert walker != plastivox.demo_walker().with_physics({"duration": 0.3})
    flat = walker.with_physics({"environment": None})
    assert flat.physics.environment is None
    assert plastivox.simulate(walker).final_state_hash != plastivox.simulate(flat).final_state_hash
    with pytest.raises(plastivox.InputError, match="physics.environment.ground.type"):
        plastivox.physics(environment={"ground": {"type": "moon"}})
    with pytest.raises(ValueError, match="physics.environment: expected a dict"):
        d.environment = 5
    assert d.environment["ground"]["type"] == "flat"  # unchanged by the refused value


def test_free_objects_ride_with_the_physics_and_are_not_the_robot():
    # A 2 x 2 x 2 box one voxel length in front of a 2 x 2 x 1 block: the Simulator's arrays
    # hold the robot's voxels first, then the box's; the result counts the robot alone.
    box = {"objects": [{"voxels": [2, 2, 2], "at": [0.03, 0, 0]}]}
    robot = plastivox.Robot.from_arrays(np.ones((2, 2, 1), bool), np.full((2, 2, 1), 1e7),
                                        np.zeros((2, 2, 1)))
    d = plastivox.physics(environment=box, duration=0.3, task="push")
    assert d.environment == box
    sim = plastivox.Simulator(robot, physics=d)
    assert sim.robot_voxels == 4 and sim.positions.shape == (12, 3)
    assert sim.state["pos"].shape == (12, 3)
    assert abs(sim.positions[4][0] - 0.035) < 1e-12  # the box's first voxel, after the robot's
    r = plastivox.simulate(robot, physics=d, record_fps=30)
    assert r.voxels == 4 and len(r.final_stiffness) == 4 and r.task == "push"
    assert r.trajectory.positions.shape[1] == 12
    with pytest.raises(plastivox.InputError, match=r"physics.environment.objects\[0\].voxels"):
        plastivox.physics(environment={"objects": [{"voxels": [0, 1, 1], "at": [0, 0, 0]}]})
