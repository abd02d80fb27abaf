"""simulate / simulate_many / Simulator give the bits of `plastivox simulate --json`."""

import json
import os
import threading
import time
import warnings

import numpy as np
import pytest

import plastivox
from conftest import QUICK_LIFE, SOURCE, cli_json, main_thread_turns, run_cli, vxa

# The summary keys that are science (the rest are wall time and speed).
TIMING = {"wall_seconds", "voxel_steps_per_second"}


def same_science(result, cli):
    d = result.to_dict()
    assert set(d) == set(cli), set(d) ^ set(cli)
    for key in cli:
        if key in TIMING or key == "source":
            continue
        assert d[key] == cli[key], key


@pytest.mark.parametrize("treatment", ["none", "stress", "pressure", "strain", "strain_energy",
                                       "contact", "kinetic"])
def test_demo_walker_matches_cli(treatment):
    cli = cli_json("simulate", "--treatment", treatment, "--json", "--physics",
                   json.dumps(QUICK_LIFE))
    r = plastivox.simulate(plastivox.demo_walker(), treatment=treatment, physics=QUICK_LIFE)
    same_science(r, cli)
    assert r.source == cli["source"]
    assert r.status == "finished" and r.fitness > 0
    assert r.final_state_hash == cli["final_state_hash"]


def test_treatment_object_in_physics_is_stimulus_plus_growth():
    walker = plastivox.demo_walker()
    quick = {"duration": 0.5}
    a = plastivox.simulate(walker, physics={**quick, "treatment": {"stimulus": "contact",
                                                                   "law": "rate"}})
    b = plastivox.simulate(walker, physics={**quick, "growth": "rate"}, treatment="contact")
    assert a.final_state_hash == b.final_state_hash
    c = plastivox.simulate(walker, physics=quick, treatment="contact")
    assert c.final_state_hash != a.final_state_hash  # the default law is integral
    with pytest.raises(Exception, match="physics.treatment.law"):
        plastivox.simulate(walker, physics={"treatment": {"stimulus": "contact", "law": "fast"}})


@pytest.mark.parametrize("name", ["walker-none.vxa", "walker-stress.vxa", "walker-pressure.vxa",
                                  "settle-cube-1e9.vxa"])
def test_vxa_samples_match_cli(name):
    path = vxa(name)
    cli = cli_json("simulate", path, "--json", "--physics", json.dumps(QUICK_LIFE))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the CLI prints the same tag warnings
        r = plastivox.simulate(plastivox.load_robot(path), physics=QUICK_LIFE)
    same_science(r, cli)
    assert r.source == path


def short_walker(duration=0.3):
    return plastivox.demo_walker().with_physics({"duration": duration, "settle_time": 0.1})


def test_from_arrays_simulates_like_the_json_robot(tmp_path):
    src = plastivox.demo_walker()
    path = tmp_path / "walker.json"
    src.save(path)
    loaded = plastivox.load_robot(path)
    built = plastivox.Robot.from_arrays(loaded.geometry, loaded.stiffness, loaded.phase,
                                        dev_rate=loaded.dev_rate, treatment="stress",
                                        voxel_size=loaded.voxel_size)
    phys = {"duration": 0.4, "settle_time": 0.1}
    a = plastivox.simulate(loaded, physics=phys)
    b = plastivox.simulate(built, physics=phys)
    assert a.final_state_hash == b.final_state_hash
    assert a.fitness == b.fitness
    assert np.array_equal(a.final_stiffness, b.final_stiffness)
    # and the same as the CLI on that JSON file with the same physics
    cli = cli_json("simulate", str(path), "--physics", json.dumps(phys), "--json")
    assert cli["final_state_hash"] == a.final_state_hash


def test_result_attributes_and_trajectory():
    r = plastivox.simulate(short_walker(), record_fps=100)
    d = r.to_dict()
    for key in d:
        if key != "final_stiffness":
            assert getattr(r, key) == d[key]
    t = r.trajectory
    n = r.voxels
    assert t.positions.shape == (len(t.times), n, 3)
    assert t.orientations.shape == (len(t.times), n, 4)
    assert t.sizes.shape == (len(t.times), n) and t.stiffness.shape == (len(t.times), n)
    # frames at 0, 0.01, ... and one at the end of the life
    assert t.times[0] == 0 and np.all(np.diff(t.times) > 0) and t.times[-1] >= 0.3
    assert np.allclose(np.linalg.norm(t.orientations, axis=2), 1)
    assert np.array_equal(t.stiffness[-1], r.final_stiffness)
    # recording does not change the life
    assert plastivox.simulate(short_walker()).final_state_hash == r.final_state_hash
    assert plastivox.simulate(short_walker()).trajectory is None


@pytest.mark.parametrize("threads", [1, 2])
def test_simulate_many_equals_separate_calls(threads):
    base = short_walker(0.25)
    rng = np.random.default_rng(7)
    robots = []
    for _ in range(8):
        e = np.where(base.geometry, 10 ** rng.uniform(6, 8, base.shape), 0)
        robots.append(plastivox.Robot.from_arrays(base.geometry, e, base.phase,
                                                  treatment="stress").with_physics(
                                                      {"duration": 0.25, "settle_time": 0.1}))
    many = plastivox.simulate_many(robots, threads=threads)
    alone = [plastivox.simulate(r) for r in robots]
    assert len(many) == 8
    for m, a in zip(many, alone):
        assert m.final_state_hash == a.final_state_hash
        assert m.fitness == a.fitness
        assert np.array_equal(m.final_stiffness, a.final_stiffness)
    assert len({m.final_state_hash for m in many}) == 8  # really different robots


def test_simulator_steps_to_the_same_hash():
    robot = short_walker()
    whole = plastivox.simulate(robot)
    sim = plastivox.Simulator(robot)
    assert sim.status == "running" and sim.time == 0
    p0 = sim.positions
    assert p0.shape == (whole.voxels, 3) and sim.velocities.shape == (whole.voxels, 3)
    assert sim.stiffness.shape == (whole.voxels,)
    assert sim.step() == 1 and sim.steps == 1 and sim.time > 0
    assert sim.step(10) == 10
    while sim.status == "running":
        sim.step(997)
    assert sim.status == "finished"
    assert sim.steps == whole.steps
    assert sim.state_hash == whole.final_state_hash
    assert np.array_equal(sim.stiffness, whole.final_stiffness)
    assert sim.step(5) == 0  # the life is over
    assert not np.array_equal(sim.positions, p0)


def test_simulator_state_views_are_live_read_only_and_zero_copy():
    sim = plastivox.Simulator(short_walker())
    names = [f["name"] for f in sim.state_fields]
    assert names[:5] == ["time", "steps", "dt", "status", "pos"] and len(set(names)) == len(names)
    state = sim.state
    assert list(state) == names
    n = len(sim.positions)
    pos = state["pos"]
    assert pos.shape == (n, 3) and pos.dtype == np.float64 and state["orient"].shape == (n, 4)
    assert state["stiffness"].shape == (n,) and state["time"].shape == ()
    assert state["static_friction"].dtype == np.uint8 and state["settled"].dtype == np.bool_
    assert state["com_settled"].shape == (3,)
    # Views of the simulator's memory, not copies: they follow the steps, and cannot be written.
    assert not pos.flags.owndata and not pos.flags.writeable
    with pytest.raises(ValueError):
        pos[0, 0] = 1.0
    before = pos.copy()
    sim.step(20)
    assert int(state["steps"]) == 20 and float(state["time"]) == sim.time
    assert not np.array_equal(pos, before)
    assert np.array_equal(pos, sim.positions) and np.array_equal(state["stiffness"], sim.stiffness)
    assert np.array_equal(sim.velocities, state["lin_mom"] * (1.0 / sim._core.voxel_mass))
    # The views keep the memory alive after the Simulator is gone.
    del sim, state
    assert pos.shape == (n, 3) and np.all(np.isfinite(pos))


def test_simulator_save_restore_continues_bit_identically():
    robot = short_walker()
    sim = plastivox.Simulator(robot)
    sim.step(300)
    snapshot = sim.save_state()
    assert isinstance(snapshot, bytes)
    saved_hash = sim.state_hash
    view = sim.state["pos"]
    sim.step(200)
    after = sim.state_hash
    sim.restore_state(snapshot)
    assert sim.state_hash == saved_hash and sim.steps == 300
    assert np.array_equal(view, sim.positions)  # the views stay valid across a restore
    sim.step(200)
    assert sim.state_hash == after
    fresh = plastivox.Simulator(robot)
    fresh.restore_state(snapshot)
    fresh.step(200)
    assert fresh.state_hash == after
    other = plastivox.Simulator(plastivox.Robot.from_arrays(
        np.ones((2, 2, 2), dtype=bool), np.full((2, 2, 2), 1e7), np.zeros((2, 2, 2))))
    with pytest.raises(ValueError, match="field 'pos' holds"):
        other.restore_state(snapshot)
    with pytest.raises(TypeError, match="snapshot"):
        other.restore_state("not bytes")


def test_unstable_simulation_reports_status_not_exception():
    # A speed limit every falling voxel exceeds: the engine's instability guard fires.
    r = plastivox.simulate(short_walker(), physics={"max_speed": 1e-6})
    assert r.status == "unstable"
    assert r.failure
    assert r.fitness == 0
    sim = plastivox.Simulator(short_walker(), physics={"max_speed": 1e-6})
    sim.run()
    assert sim.status == "unstable" and sim.failure


@pytest.mark.parametrize("call", ["simulate", "simulate_many", "step"])
def test_long_calls_release_the_gil(call):
    """While a life runs in C++ another Python thread keeps running: with the GIL held it
    could run only in the few bytecodes before and after the call."""
    robot = short_walker(1.0)

    def work():
        if call == "simulate":
            plastivox.simulate(robot)
        elif call == "simulate_many":
            plastivox.simulate_many([robot, robot], threads=2)
        else:
            plastivox.Simulator(robot).step(1 << 30)

    turns = main_thread_turns(work)
    assert turns >= 20, f"{call}: the main thread ran {turns} times during the call"


def test_a_sunk_life_is_invalid_by_default_in_simulate_and_simulate_many():
    # A 2x2x2 block of soft (1e5 Pa), heavy voxels falls through the floor; a stiff one stands.
    shape = (2, 2, 2)
    geometry = np.ones(shape, dtype=bool)
    soft = plastivox.Robot.from_arrays(geometry, np.full(shape, 1e5), np.zeros(shape))
    stiff = plastivox.Robot.from_arrays(geometry, np.full(shape, 1e10), np.zeros(shape))
    sunk, stood = plastivox.simulate_many([soft, stiff], physics={"duration": 1.0}, threads=2)
    assert sunk.status == "unstable" and sunk.fitness == 0 and sunk.health == "sank"
    assert "sank through the floor" in sunk.failure and sunk.floor_depth > 100
    assert stood.status == "finished" and stood.health == "ok" and stood.floor_depth < 0.5
    # The authors' rule scores the same life, bit for bit the same.
    authors = plastivox.simulate(soft, physics={"duration": 1.0, "sinking_invalid": False})
    assert authors.status == "finished" and authors.health == "sank" and authors.fitness > 100
    assert authors.final_state_hash == sunk.final_state_hash


def test_simulator_used_from_two_threads_at_once_raises_and_keeps_its_state():
    """step() runs without the GIL; four threads stepping one Simulator crashed or ended in a
    state no sequential run gives. A second user gets a clear RuntimeError instead, and the
    life the Simulator runs is the sequential one."""
    robot = short_walker(1.0)
    sim = plastivox.Simulator(robot)
    errors, taken = [], []
    stepping = threading.Event()

    def work():
        try:
            stepping.set()
            taken.append(sim.step(1 << 30))
        except RuntimeError as e:
            errors.append(str(e))

    workers = [threading.Thread(target=work) for _ in range(4)]
    for w in workers:
        w.start()
    stepping.wait()
    refused_reads = 0
    while any(w.is_alive() for w in workers):
        try:
            sim.time  # noqa: B018 - a read of the state while another thread may step
        except RuntimeError as e:
            assert "in use by another thread" in str(e)
            refused_reads += 1
    for w in workers:
        w.join()
    assert all("in use by another thread" in e for e in errors)
    assert len(taken) + len(errors) == 4 and sum(taken) == sim.steps
    assert refused_reads + len(errors) > 0, "no thread ever met another one stepping"
    assert sim.state_hash == plastivox.simulate(robot).final_state_hash


def test_recordings_too_large_for_memory_are_refused_before_simulating(monkeypatch):
    # 10,000 frames per second of the walker's 5.2 s life is over the 1 GiB default, and 8 of
    # a recording the limit admits alone are refused together (all are held until returned).
    t0 = time.monotonic()
    with pytest.raises(ValueError, match=r"record_fps: the recording would need about .* "
                                         r"PLASTIVOX_MAX_RECORDING_MB"):
        plastivox.simulate(plastivox.demo_walker(), record_fps=10000)
    walker = plastivox.demo_walker()
    plastivox.simulate(walker, record_fps=1000)  # ~0.4 GB: admitted
    with pytest.raises(ValueError, match="more than the limit of 1024 MB"):
        plastivox.simulate_many([walker] * 8, record_fps=1000)
    assert time.monotonic() - t0 < 20
    monkeypatch.setenv("PLASTIVOX_MAX_RECORDING_MB", "1")
    with pytest.raises(ValueError, match="more than the limit of 1 MB"):
        plastivox.simulate(walker, record_fps=1000)


def test_task_is_the_clis_and_leaves_the_life_alone():
    # docs/tasks.md: the task changes what fitness measures, never the life.
    walker = plastivox.demo_walker()
    quick = {"duration": 0.6}
    walk = plastivox.simulate(walker, physics=quick)
    assert walk.to_dict()["task"] == "walk"
    for task, unit in (("jump", "voxel lengths"), ("turn", "rad")):
        cli = cli_json("simulate", "--task", task, "--duration", "0.6", "--json")
        r = plastivox.simulate(walker, physics=quick, task=task)
        same_science(r, cli)
        assert r.to_dict()["fitness_unit"] == unit
        # The same life: the state's hash differs only by the task's running values it covers.
        for key in ("dist_x", "dist_y", "dist_z", "steps", "floor_depth"):
            assert getattr(r, key) == getattr(walk, key), key
        assert np.array_equal(r.final_stiffness, walk.final_stiffness)
        assert r.final_state_hash != walk.final_state_hash and r.fitness != walk.fitness
        assert plastivox.simulate(walker, physics={**quick, "task": task}).fitness == r.fitness
        many = plastivox.simulate_many([walker], physics=quick, task=task, threads=1)
        assert many[0].fitness == r.fitness
    with pytest.raises(Exception, match="physics.task: unknown task 'fly'"):
        plastivox.simulate(walker, task="fly")


def test_terrain_task_with_parameters_is_the_clis():
    # docs/tasks.md: a task's parameters go in physics["task"]; its default ground is made
    # from them, as on the command line.
    walker = plastivox.demo_walker()
    climb = {"name": "climb", "rise": 1, "count": 3}
    physics = {"duration": 0.6, "task": climb}
    r = plastivox.simulate(walker, physics=physics)
    cli = cli_json("simulate", "--duration", "0.6", "--json", "--physics",
                   json.dumps({"task": climb}))
    same_science(r, cli)
    assert r.to_dict()["task"] == "climb"
    assert plastivox.simulate(walker, physics={"duration": 0.6, "task": "rough"}).fitness == \
        plastivox.simulate(walker, physics={"duration": 0.6, "task": {"name": "rough"}}).fitness
    with pytest.raises(Exception, match=r"physics.task.rise: must be in \[0.05, 5\] voxel lengths"):
        plastivox.simulate(walker, physics={"task": {"name": "climb", "rise": 9}})
    # A PhysicsDef carries the parameters (as files write them) through a pickle; another
    # task drops them.
    import pickle
    p = plastivox.PhysicsDef(task=climb)
    assert p.to_dict()["task"] == {"name": "climb", "rise": 1.0, "count": 3.0}
    assert pickle.loads(pickle.dumps(p)) == p
    assert p != plastivox.PhysicsDef(task="climb")
    assert p.replace(task="rough").to_dict()["task"] == "rough"
    q = plastivox.PhysicsDef(task=climb)
    q.task = "slope"
    assert q.to_dict()["task"] == "slope"


def test_a_physics_def_reads_and_sets_its_task_as_to_dict_and_with_physics_do():
    # dict(p), p["task"], p.task and repr(p) give the task with its parameters, as to_dict()
    # does, so dict(p) is equal to p and simulates alike; and an attribute takes what
    # with_physics takes (a task or treatment object).
    walker = plastivox.demo_walker()
    rough = {"name": "rough", "amplitude": 2.0, "seed": 7}
    p = walker.with_physics({"task": rough, "duration": 0.5}).physics
    assert p["task"] == rough and p.task == rough and dict(p)["task"] == rough
    assert p == dict(p) and plastivox.PhysicsDef(**dict(p)) == p
    assert "task={'name': 'rough', 'amplitude': 2.0, 'seed': 7.0}" in repr(p)
    a, b = plastivox.simulate(walker, physics=p), plastivox.simulate(walker, physics=dict(p))
    assert a.final_state_hash == b.final_state_hash and a.fitness == b.fitness
    assert plastivox.physics(task="walk")["task"] == "walk"  # without parameters: the name
    assert plastivox.physics()["task"] is None  # names none: the robot's (as a preset keeps it)
    q = plastivox.physics()
    q.task = {"name": "climb", "rise": 1}
    assert q.task == {"name": "climb", "rise": 1.0}
    assert q == plastivox.physics(task={"name": "climb", "rise": 1})
    with pytest.raises(ValueError, match=r"physics.task.rise: must be in \[0.05, 5\]"):
        q.task = {"name": "climb", "rise": 9}
    assert q.task == {"name": "climb", "rise": 1.0}  # unchanged by the refused value
    q.treatment = {"stimulus": "stress", "law": "rate"}
    assert q.treatment == "stress" and q.growth == "rate"
    assert q == plastivox.physics(task={"name": "climb", "rise": 1}, treatment="stress",
                                  growth="rate")


def test_the_task_argument_keeps_the_parameters_of_the_same_task():
    # task= naming the task physics["task"] names keeps its parameters; another task comes
    # with its defaults (docs/python.md, "Simulation").
    walker = plastivox.demo_walker()
    rough = {"name": "rough", "amplitude": 2.0, "seed": 7}
    physics = {"duration": 0.5, "task": rough}
    given = plastivox.simulate(walker, physics=physics)
    assert given.final_state_hash != \
        plastivox.simulate(walker, physics={**physics, "task": "rough"}).final_state_hash
    for same in (plastivox.simulate(walker, physics=physics, task="rough"),
                 plastivox.simulate_many([walker], physics=physics, task="rough", threads=1)[0],
                 plastivox.simulate(walker, physics=walker.physics.replace(**physics),
                                    task="rough")):
        assert same.final_state_hash == given.final_state_hash and same.fitness == given.fitness
    env = plastivox.VoxelEnv(walker, physics=physics, task="rough", sensors="time")
    obs, _ = env.reset()
    while True:  # the built-in sine replayed: simulate's life, on the same ground
        action = plastivox.sin_cycles(env.act_frequency * obs[-1] + env.voxel_phase)
        obs, _, terminated, truncated, info = env.step(action)
        if terminated or truncated:
            break
    assert info["state_hash"] == given.final_state_hash and info["fitness"] == given.fitness
    other = plastivox.simulate(walker, physics=physics, task="slope")
    slope = plastivox.simulate(walker, physics={"duration": 0.5, "task": "slope"})
    assert other.final_state_hash == slope.final_state_hash and other.fitness == slope.fitness


def test_physics_dicts_take_numpy_and_name_a_number_that_is_not_finite():
    # The environment and a task's parameters take numpy arrays and scalars; NaN and infinity
    # are refused in one line naming the field, as a file's reader names it.
    heights = np.array([[0.0, 0.001], [0.002, 0.0]])
    ground = {"type": "heightfield", "cell": 0.01}
    p = plastivox.physics(environment={"ground": {**ground, "heights": heights}})
    assert p == plastivox.physics(environment={"ground": {**ground, "heights": heights.tolist()}})
    assert p.environment["ground"]["heights"] == heights.tolist()
    assert plastivox.physics(task={"name": "rough", "amplitude": np.float32(0.5),
                                   "seed": np.int64(3)}) == \
        plastivox.physics(task={"name": "rough", "amplitude": 0.5, "seed": 3})
    walker = plastivox.demo_walker()
    with pytest.raises(ValueError, match=r"^physics.environment.ground.height: must be finite$"):
        plastivox.simulate(walker, physics={"environment": {"ground": {"type": "flat",
                                                                       "height": float("nan")}}})
    with pytest.raises(ValueError, match=r"^physics.task.amplitude: must be finite$"):
        plastivox.simulate(walker, physics={"task": {"name": "rough", "amplitude": np.inf}})
    heights[1, 0] = np.nan
    with pytest.raises(ValueError,
                       match=r"^physics.environment.ground.heights\[1\]\[0\]: must be finite$"):
        plastivox.physics(environment={"ground": {**ground, "heights": heights}})
    with pytest.raises(ValueError, match=r"^physics.environment.ground.cell: expected a number, "):
        plastivox.physics(environment={"ground": {**ground, "cell": object()}})


def test_a_treatment_object_without_a_stimulus_is_refused_as_the_cli_refuses_it():
    walker = plastivox.demo_walker()
    for treatment in ({"law": "rate"}, {}):
        code, _, err = run_cli("simulate", "--duration", "0.1", "--physics",
                               json.dumps({"treatment": treatment}), check=False)
        assert code != 0 and "physics.treatment.stimulus: missing" in err
        with pytest.raises(ValueError, match=r"^physics.treatment.stimulus: missing$"):
            plastivox.simulate(walker, physics={"treatment": treatment})
        with pytest.raises(ValueError, match=r"^physics.treatment.stimulus: missing$"):
            plastivox.physics(treatment=treatment)


def test_a_physics_def_keeps_the_robots_treatment_unless_it_names_one():
    # Issue 54: physics=plastivox.physics(...) used to replace the stress walker's treatment with
    # the preset's none (stiffness change 0.0 against 0.52 with a dict of the same fields).
    walker = plastivox.demo_walker()
    quick = {"duration": 0.6, "settle_time": 0.1}
    p = plastivox.physics(**quick)
    assert p.treatment is None and p["treatment"] is None and dict(p)["treatment"] is None
    assert "treatment=None" in repr(p)
    by_def = plastivox.simulate(walker, physics=p)
    by_dict = plastivox.simulate(walker, physics=quick)
    assert by_def.final_state_hash == by_dict.final_state_hash
    assert np.array_equal(by_def.final_stiffness, by_dict.final_stiffness)
    assert not np.array_equal(by_def.final_stiffness,
                              plastivox.simulate(walker, physics={**quick, "treatment": "none"})
                              .final_stiffness)  # development ran
    assert plastivox.simulate(walker, physics=dict(p)).final_state_hash == by_def.final_state_hash
    sim = plastivox.Simulator(walker, physics=p)
    sim.run()
    assert sim.state_hash == by_dict.final_state_hash
    assert walker.with_physics(p).treatment == "stress"
    assert [r.final_state_hash for r in plastivox.simulate_many([walker], physics=p)] == \
        [by_dict.final_state_hash]
    # Named (as an argument, an attribute or replace), it replaces the robot's, as in a dict.
    none = plastivox.simulate(walker, physics=p.replace(treatment="none"))
    assert none.final_state_hash == plastivox.simulate(
        walker, physics={**quick, "treatment": "none"}).final_state_hash
    named = plastivox.physics(treatment="pressure", **quick)
    assert named.treatment == "pressure"
    assert plastivox.simulate(walker, physics=named).final_state_hash == plastivox.simulate(
        walker, physics={**quick, "treatment": "pressure"}).final_state_hash
    q = p.replace(duration=0.5)
    assert q.treatment is None  # replace keeps "names none"
    q.treatment = "pressure"
    assert q.treatment == "pressure" and q != p.replace(duration=0.5)
    q.treatment = None  # names none again
    assert q == p.replace(duration=0.5)
    # A robot's own physics names its treatment; the flag survives pickling and copying.
    assert walker.physics.treatment == "stress"
    import copy
    import pickle
    for x in (p, named):
        assert pickle.loads(pickle.dumps(x)) == x and copy.deepcopy(x) == x
        assert pickle.loads(pickle.dumps(x)).treatment == x.treatment
    # "preset" in a dict keeps the robot's treatment and task, as the command line's --preset.
    paper = plastivox.simulate(walker, physics={"preset": "gecco2018-paper", **quick})
    assert paper.to_dict()["treatment"] == "stress"


def test_a_vxa_file_pressed_into_the_floor_at_its_own_density_is_warned_as_the_cli_warns():
    # Issue 54: examples/pi.vxa at its own 1e9 kg/m^3 ends penetrating; the warning names the
    # density and the fix, in Python's result as in simulate --json.
    pi = os.path.join(SOURCE, "examples", "pi.vxa")
    quick = {"duration": 2.0, **QUICK_LIFE}
    r = plastivox.simulate(pi, physics=quick)
    cli = cli_json("simulate", pi, "--json", "--physics", json.dumps(quick))
    assert r.to_dict()["health"] == "penetrating"
    assert r.to_dict()["warnings"] == cli["warnings"]
    assert any("at the VXA file's own density, 1e+09 kg/m^3" in w and '"density": 1e7' in w
               for w in r.to_dict()["warnings"])
    [many] = plastivox.simulate_many([pi], physics=quick)
    assert many.to_dict()["warnings"] == cli["warnings"]
    light = plastivox.simulate(pi, physics={**quick, "density": 1e7})
    assert light.to_dict()["health"] == "ok"
    assert not any("own density" in w for w in light.to_dict()["warnings"])


def test_a_bad_duration_states_the_rule():
    # Issue 54: "--duration -1" said "expects a number of seconds"; Python reads the rule too.
    with pytest.raises(ValueError, match=r"^physics.duration: must be a number of seconds >= 0"):
        plastivox.physics(duration=-1)
    with pytest.raises(ValueError, match=r"physics.duration: must be a number of seconds from "
                                         r"settle_time"):
        plastivox.simulate(plastivox.demo_walker(), physics={"duration": 0.1, "settle_time": 0.2})


def test_success_is_the_tasks_criterion_as_the_cli_says():
    # docs/tasks.md, "Success": push's example moves its box more than two voxel lengths.
    path = os.path.join(SOURCE, "examples", "tasks", "push.json")
    robot = plastivox.load_robot(path)
    r = plastivox.simulate(robot)
    cli = cli_json("simulate", path, "--json")
    assert r.task == "push" and r.fitness >= 2
    assert r.success is True and cli["success"] is True
    assert "success=True" in repr(r)
    # Cut short, the same robot has not moved the box far enough yet.
    assert plastivox.simulate(robot, physics={"duration": 0.4}).success is False
    sim = plastivox.Simulator(robot)
    sim.step(50)
    assert sim.result().success is False  # still running: no success claimed
    while sim.status == "running":
        sim.step(997)
    assert sim.result().success is True
