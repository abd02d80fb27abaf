"""Objects that cross processes: pickles, equality, paths for robots, the module's namespace
and the classes' reprs."""

import json
import pathlib
import pickle

import numpy as np
import pytest

import plastivox
from plastivox import _core

QUICK = {"duration": 0.25, "settle_time": 0.1}


def quick_walker():
    return plastivox.demo_walker().with_physics(QUICK)


def roundtrip(obj):
    return pickle.loads(pickle.dumps(obj))


def clamped_robot_file(path):
    """A robot file with every part a RobotDef holds: fixed voxels, loads and physics."""
    path.write_text(json.dumps({
        "format": "plastivox-robot", "version": 1, "name": "clamped",
        "lattice": {"nx": 3, "ny": 1, "nz": 2, "voxel_size": 0.02},
        "voxels": [[0, 0, 0, 1e6, 0, 0], [1, 0, 0, 2e6, 50, 0.25], [2, 0, 0, 3e6, 0, -0.5],
                   [2, 0, 1, 1e6, -20, 0.1]],
        "fixed": [[0, 0, 0]],
        "loads": [{"at": [2, 0, 1], "force": [0.5, 0, -3]}],
        "physics": {"duration": 0.05, "settle_time": 0.01, "treatment": "stress"}}))
    return path


# --- pickles -----------------------------------------------------------------------------

def robots_of_every_kind(tmp_path):
    rng = np.random.default_rng(3)
    g = rng.random((4, 3, 2)) < 0.7
    g[0, 0, 0] = True
    built = plastivox.Robot.from_arrays(g, np.where(g, 10 ** rng.uniform(5, 8, g.shape), 0),
                                        np.where(g, rng.uniform(-0.9, 0.9, g.shape), 0),
                                        dev_rate=np.where(g, rng.normal(0, 1e3, g.shape), 0),
                                        treatment="kinetic", voxel_size=0.015, name="built")
    clamped = plastivox.load_robot(clamped_robot_file(tmp_path / "clamped.json"))
    return [quick_walker(), built.with_physics(QUICK), clamped]


def test_robot_pickles_bit_for_bit_and_simulates_alike(tmp_path):
    for robot in robots_of_every_kind(tmp_path):
        back = roundtrip(robot)
        assert type(back) is plastivox.Robot and back == robot and hash(back) == hash(robot)
        # every field of the state, arrays as raw bytes, the source included
        assert back._core.__getstate__() == robot._core.__getstate__()
        for field in ("geometry", "stiffness", "phase", "dev_rate"):
            assert getattr(back, field).tobytes() == getattr(robot, field).tobytes(), field
        assert back.physics == robot.physics and back.source == robot.source
        a, b = plastivox.simulate(robot), plastivox.simulate(back)
        assert a.final_state_hash == b.final_state_hash and a.fitness == b.fitness


def test_robot_pickle_keeps_fixed_voxels_and_loads(tmp_path):
    path = clamped_robot_file(tmp_path / "clamped.json")
    robot = plastivox.load_robot(path)
    roundtrip(robot).save(tmp_path / "again.json")
    robot.save(tmp_path / "direct.json")
    saved = json.loads((tmp_path / "again.json").read_text())
    assert saved["fixed"] == [[0, 0, 0]] and saved["loads"] == [{"at": [2, 0, 1],
                                                                  "force": [0.5, 0, -3]}]
    assert (tmp_path / "again.json").read_bytes() == (tmp_path / "direct.json").read_bytes()


def bad_state(state, index, value):
    return state[:index] + (value,) + state[index + 1:]


def test_robot_pickle_refuses_garbage_with_one_line():
    state = quick_walker()._core.__getstate__()
    assert state[:2] == ("plastivox.Robot", 4) and len(state) == 16
    physics = state[11]
    assert isinstance(physics, dict) and physics["duration"] == QUICK["duration"]
    cases = [
        ((1, 2, 3), "not a plastivox robot state"),
        (bad_state(state, 0, "something.Else"), "not a plastivox robot state"),
        (bad_state(state, 1, 1), "state version 1 with 16 fields, this plastivox reads versions 1"),
        (bad_state(state, 1, 2 ** 70), "state version 1180591620717411303424"),
        (bad_state(state, 6, b"\0" * 12), "stiffness: expected 8000 bytes"),
        (bad_state(state, 3, "10x10x10"), "wrong type"),
        (bad_state(state, 3, (0, 10, 10)), "robot.size"),
        (bad_state(state, 9, (10 ** 6,)), "fixed_sites: site out of range"),
        (bad_state(state, 11, {**physics, "duration": -1}), "Robot pickle: physics.duration"),
        (bad_state(state, 11, {**physics, "floor": "yes"}), "physics.floor: expected True or False"),
        (bad_state(state, 11, {**physics, "bogus": 1}), "physics.bogus: unknown field"),
        (bad_state(state, 11, '{"duration": 1}'), "Robot pickle: physics: expected a dict"),
        (bad_state(state, 13, b"\0" * 8), "act_amplitude: expected 8000 bytes"),
    ]
    for garbage, message in cases:
        blank = _core.Robot.__new__(_core.Robot)
        with pytest.raises(plastivox.InputError, match=message):
            blank.__setstate__(garbage)


def test_robot_pickles_of_earlier_versions_still_read():
    """Versions 1 and 2 held the physics as JSON text (version 1 without act_amplitude)."""
    robot = quick_walker()
    state = robot._core.__getstate__()
    text = json.dumps(robot.physics.to_dict())
    for old in (state[:1] + (1,) + state[2:11] + (text, state[12]),
                state[:1] + (2,) + state[2:11] + (text, state[12], b"\0" * len(state[6]))):
        blank = _core.Robot.__new__(_core.Robot)
        blank.__setstate__(old)
        back = plastivox.Robot(blank)
        assert back.physics == robot.physics
        assert (back == robot) == (old[1] == 1)  # version 2 carried zero amplitudes of its own
    blank = _core.Robot.__new__(_core.Robot)
    with pytest.raises(plastivox.InputError, match="Robot pickle"):
        blank.__setstate__(state[:1] + (1,) + state[2:11] + ("{not json", state[12]))


def test_result_and_trajectory_pickle_to_equal_objects():
    r = plastivox.simulate(quick_walker(), record_fps=100)
    back = roundtrip(r)
    assert back == r and back.to_dict() == r.to_dict()
    assert back.trajectory == r.trajectory and roundtrip(r.trajectory) == r.trajectory
    assert back.robot == r.robot
    assert np.array_equal(back.final_stiffness, r.final_stiffness)
    # equality sees the content: another life (here another wall time) is not equal
    other = plastivox.simulate(quick_walker(), record_fps=100)
    assert other != r and other.trajectory == r.trajectory
    many = plastivox.simulate_many([quick_walker()], threads=1)[0]
    assert roundtrip(many) == many and many.trajectory is None


def test_results_pickle_as_a_reference_to_their_file(tiny_run, tmp_path):
    path, _ = tiny_run
    res = plastivox.read_results(path)
    back = roundtrip(res)
    assert back == res and hash(back) == hash(res) and back is not res
    assert back.content_digest == res.content_digest and back.config == res.config
    assert np.array_equal(back.best_fitness, res.best_fitness)
    assert back.champion() == res.champion()
    state = res.__getstate__()
    assert state["format"] == "plastivox.Results" and state["version"] == 1
    blank = plastivox.Results.__new__(plastivox.Results)
    with pytest.raises(plastivox.InputError, match="the file changed since it was pickled"):
        blank.__setstate__({**state, "content_digest": "0" * 32})
    with pytest.raises(plastivox.InputError, match="state version 7"):
        blank.__setstate__({**state, "version": 7})
    with pytest.raises(plastivox.InputError, match="not a plastivox results state"):
        blank.__setstate__("garbage")
    with pytest.raises(plastivox.InputError, match="path and content_digest must be strings"):
        blank.__setstate__({"format": "plastivox.Results", "version": 1})
    with pytest.raises(plastivox.InputError, match="gone.h5"):
        blank.__setstate__({**state, "path": str(tmp_path / "gone.h5")})


def test_the_authors_sunk_life_rule_survives_pickles_and_physics_dicts():
    """sinking_invalid False (the authors' rule, scoring sunk lives) must not come back as the
    default True from a pickle, a physics dict or Robot.physics."""
    soft = plastivox.Robot.from_arrays(np.ones((3, 3, 3), bool), np.full((3, 3, 3), 1e5),
                                       np.zeros((3, 3, 3)), treatment="none")
    authors = soft.with_physics({"duration": 0.5, "settle_time": 0.1, "sinking_invalid": False})
    settings = plastivox.physics(sinking_invalid=False)
    assert settings["sinking_invalid"] is False and plastivox.physics()["sinking_invalid"] is True
    assert authors.physics["sinking_invalid"] is False
    for robot in (roundtrip(authors), soft.with_physics(authors.physics)):
        assert robot == authors
        r = plastivox.simulate(robot)
        assert r.status == "finished" and r.health == "sank" and r.fitness > 2, r


def test_physics_settings_and_study_pickle():
    for settings in (plastivox.physics(), plastivox.physics("gecco2018-paper", duration=1.0)):
        back = roundtrip(settings)
        assert back == settings
        assert quick_walker().with_physics(back) == quick_walker().with_physics(settings)
    study = plastivox.Study("study", {"format": "plastivox-analysis", "runs": 2},
                            [{"run": 1, "fitness": 0.5}], [{"measure": "x", "p": None}])
    assert roundtrip(study) == study
    assert study != plastivox.Study("study", study.stats, [], study.statistics)


def test_simulator_says_it_does_not_pickle():
    with pytest.raises(TypeError, match="pickle the Robot and physics"):
        pickle.dumps(plastivox.Simulator(quick_walker()))


# --- equality ----------------------------------------------------------------------------

def test_robot_value_equality(tmp_path):
    walker = quick_walker()
    assert walker == quick_walker() and hash(walker) == hash(quick_walker())
    assert walker is not quick_walker() and len({walker, quick_walker()}) == 1
    # read from a file: equal to the robot saved, though its source differs
    walker.save(tmp_path / "w.json")
    loaded = plastivox.load_robot(tmp_path / "w.json")
    assert loaded.source != walker.source and loaded == walker
    assert plastivox.load_robot(tmp_path / "w.json") == loaded
    # any difference counts: one ulp of one stiffness, the physics, the treatment, the name
    def rebuild(stiffness=walker.stiffness, name=walker.name):
        return plastivox.Robot.from_arrays(walker.geometry, stiffness, walker.phase,
                                           dev_rate=walker.dev_rate, treatment="stress",
                                           name=name).with_physics(QUICK)

    assert rebuild() == walker
    e = walker.stiffness
    site = tuple(np.argwhere(walker.geometry)[0])
    e[site] = np.nextafter(e[site], np.inf)
    assert rebuild(stiffness=e) != walker
    assert rebuild(name="other") != walker
    assert walker.with_physics({"duration": 0.3}) != walker
    assert walker.with_physics(treatment="none") != walker
    assert walker != "walker" and not (walker == 1)


# --- paths wherever render takes them -----------------------------------------------------

def test_simulate_simulate_many_and_simulator_take_paths(tmp_path):
    walker = quick_walker()
    path = tmp_path / "walker.json"
    walker.save(path)
    want = plastivox.simulate(walker)
    for source in (str(path), path):
        r = plastivox.simulate(source)
        assert r.final_state_hash == want.final_state_hash
        assert r.source == str(path) and r.robot == walker
    many = plastivox.simulate_many([str(path), walker, pathlib.Path(path)], threads=2)
    assert [m.final_state_hash for m in many] == [want.final_state_hash] * 3
    sim = plastivox.Simulator(path)
    sim.run()
    assert sim.state_hash == want.final_state_hash
    assert plastivox.simulate(path, treatment="none").final_state_hash == \
        plastivox.simulate(walker, treatment="none").final_state_hash


def test_a_results_path_simulates_its_champion(tiny_run):
    path, _ = tiny_run
    champion = plastivox.read_results(path).champion()
    r = plastivox.simulate(path)
    assert r.robot == champion
    assert r.final_state_hash == plastivox.simulate(champion).final_state_hash


def test_path_errors_name_the_argument(tmp_path):
    with pytest.raises(TypeError, match="robot: expected a plastivox.Robot or a .json/.vxa/.h5"):
        plastivox.simulate(42)
    with pytest.raises(TypeError, match=r"robots\[1\]"):
        plastivox.simulate_many([quick_walker(), 3.5])
    with pytest.raises(TypeError, match="robots: expected a list of robots or paths"):
        plastivox.simulate_many(str(tmp_path / "w.json"))
    with pytest.raises(plastivox.InputError, match="robot.txt: expected a robot"):
        plastivox.simulate(str(tmp_path / "robot.txt"))
    with pytest.raises(plastivox.InputError, match="missing.json"):
        plastivox.Simulator(tmp_path / "missing.json")


# --- namespace, reprs, docstrings ---------------------------------------------------------

def test_namespace_holds_only_the_api():
    # plastivox.ppo is a submodule imported on demand (it needs torch), not part of the names
    # `import plastivox` gives; another test may have imported it.
    public = {name for name in dir(plastivox) if not name.startswith("_")} - {"ppo"}
    assert public == set(plastivox.__all__)
    for leaked in ("np", "os", "json", "math", "csv", "numpy"):
        assert not hasattr(plastivox, leaked), leaked
    assert all(hasattr(plastivox, name) for name in plastivox.__all__)


def test_every_public_class_has_a_useful_repr(tiny_run, tmp_path):
    walker = quick_walker()
    result = plastivox.simulate(walker, record_fps=50)
    study = plastivox.Study("study", {"format": "plastivox-analysis"}, [{"run": 1}], [])
    evolver = plastivox.Evolver({**tiny_run[1], "generations": 0}, tmp_path / "e.h5", threads=1)
    evolver.tell(plastivox.simulate_many(evolver.ask(), threads=1))
    assert evolver.finished
    reprs = {
        plastivox.Evolver: (evolver, ["finished"]),
        plastivox.Robot: (walker, ["demo-walker", "(10, 10, 10)", "voxels=512", "stress"]),
        plastivox.Result: (result, ["finished", "fitness=", "voxels=512"]),
        plastivox.Trajectory: (result.trajectory, ["frames", "512 voxels", " s)"]),
        plastivox.Simulator: (plastivox.Simulator(walker), ["running", "0.25 s", "steps=0"]),
        plastivox.Results: (plastivox.read_results(tiny_run[0]), ["tiny.h5", "pressure",
                                                                   "generations_done=2/2"]),
        plastivox.Study: (study, ["study", "1 champions"]),
        plastivox.PhysicsDef: (plastivox.physics(duration=1.5), ["duration=1.5", "treatment=None"]),
        plastivox.VoxelEnv: (plastivox.VoxelEnv(walker, task="jump"),
                             ["demo-walker", "task='jump'", "voxels=512", "every=1"]),
        plastivox.VoxelVecEnv: (plastivox.VoxelVecEnv(walker, num_envs=2, threads=1),
                                ["demo-walker", "num_envs=2", "task='walk'", "threads=1"]),
    }
    classes = {getattr(plastivox, n) for n in plastivox.__all__
               if isinstance(getattr(plastivox, n), type)
               and not issubclass(getattr(plastivox, n), Exception)}
    assert classes == set(reprs)
    for cls, (obj, words) in reprs.items():
        text = repr(obj)
        assert text.startswith(cls.__name__ + "("), text
        for word in words:
            assert word in text, (text, word)
    # A robot's repr names its network, when it runs one instead of the sine.
    assert "controller" not in repr(walker)
    count = plastivox.controller_weight_count("distributed", 2)
    net = walker.with_controller("distributed", hidden=2, every=3, weights=[0.1] * count)
    assert "controller='distributed', hidden=2, every=3" in repr(net), repr(net)


def test_docstrings_name_every_treatment_and_colour():
    treatments = ["none", "stress", "pressure", "strain", "strain_energy", "contact", "kinetic"]
    assert tuple(treatments) == plastivox._TREATMENTS  # the engine's, in its order
    for t in treatments:
        assert f'"{t}"' in plastivox.simulate.__doc__, t
    colours = ["congenital", "stiffness", "change", "alpha", "phase", "stimulus"]
    for colour in colours:
        assert colour in plastivox.render.__doc__, colour
    walker = quick_walker()
    frames = {c: plastivox.render(walker, time=0.2, color=c, size=(48, 36), overlay=False)
              for c in ("congenital", "stimulus")}
    assert not np.array_equal(frames["congenital"], frames["stimulus"])
