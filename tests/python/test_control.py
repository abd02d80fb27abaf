"""Per-step control from Python (docs/control.md): sensors, set_actuation, reset, snapshots."""

import json
import pickle

import numpy as np
import pytest

import plastivox

from conftest import expect_signals_refused, run_cli


def short_walker(duration=0.4):
    return plastivox.demo_walker().with_physics({"duration": duration, "settle_time": 0.1},
                                                treatment="stress")


def run_builtin(robot):
    sim = plastivox.Simulator(robot)
    sim.run()
    assert sim.status == "finished"
    return sim.state_hash


def sine_of(sim):
    """The built-in sine's signal for the present step, computed in Python."""
    t = float(sim.sensors("time")["time"])
    return plastivox.sin_cycles(sim.act_frequency * t + sim.voxel_phase)


def test_python_sine_replay_gives_the_builtin_bits():
    robot = short_walker()
    sim = plastivox.Simulator(robot)
    assert sim.controller == "sine"
    while sim.status == "running":
        sim.set_actuation(sine_of(sim))
        sim.step()
    assert sim.controller is None
    assert sim.status == "finished"
    assert sim.state_hash == run_builtin(robot)
    assert sim.state_hash == plastivox.simulate(robot).final_state_hash


def test_sin_cycles_stays_in_range():
    quarters = np.arange(-12, 13) / 4.0  # the peaks and zeros, and their neighbours
    u = np.concatenate([np.linspace(-3, 3, 200001), quarters, np.nextafter(quarters, 9),
                        np.nextafter(quarters, -9), [1e6 + 0.25, -1e6 - 0.25]])
    s = plastivox.sin_cycles(u)
    assert s.dtype == np.float64 and s.shape == u.shape
    # Within 1e-15 of [-1, 1] (-1 - 2.2e-16 at 0.75 cycles), which set_actuation takes.
    assert np.all(np.abs(s) <= 1.0 + 1e-15)
    assert np.max(np.abs(s - np.sin(2 * np.pi * u))) < 1e-14
    sim = plastivox.Simulator(short_walker())
    sim.set_actuation(plastivox.sin_cycles(np.full(len(sim.voxel_phase), 0.75)))


def test_wrong_action_arrays_raise_a_clear_error():
    sim = plastivox.Simulator(short_walker())
    n = len(sim.voxel_phase)
    with pytest.raises(ValueError, match=r"actuation: expected shape .* got \(1, %d\)" % n):
        sim.set_actuation(np.zeros((1, n)))
    with pytest.raises(ValueError, match=r"actuation\[0\] is nan"):
        sim.set_actuation(np.full(n, np.nan))
    assert sim.controller == "sine"  # nothing was taken: the sine still drives
    expect_signals_refused(sim.set_actuation, "actuation", n)  # and float32 arrays are fine
    assert np.array_equal(sim.actuation, np.full(n, 0.5))
    with pytest.raises(ValueError, match="every"):
        sim.set_controller("sine", every=0)
    with pytest.raises(ValueError, match="controller"):
        sim.set_controller("neural")


def test_sensors_match_their_table():
    sim = plastivox.Simulator(short_walker())
    sim.step(200)
    n = len(sim.voxel_phase)
    sensors = sim.sensors()
    assert list(sensors) == [f["name"] for f in plastivox.Simulator.sensor_fields]
    shapes = {"n": (n,), "n x 3": (n, 3), "3": (3,), "1": ()}
    for f in plastivox.Simulator.sensor_fields:
        assert sensors[f["name"]].shape == shapes[f["shape"]], f
        assert sensors[f["name"]].dtype == np.float64 and f["unit"]
    assert np.allclose(sensors["velocity"], sim.velocities, rtol=1e-14, atol=0)
    assert float(sensors["time"]) == sim.time
    assert set(np.unique(sensors["touch"])) <= {0.0, 1.0} and sensors["touch"].sum() > 0
    assert np.allclose(np.linalg.norm(sensors["up"], axis=1), 1.0)
    with pytest.raises(ValueError, match="no sensor named 'smell'.*touch"):
        sim.sensors(["smell"])
    # Reading is half of a step (step1), which changes no state: a snapshot taken now is the
    # state before the step.
    sim.step()
    before = sim.save_state()
    sim.sensors()
    assert sim.save_state() == before


def reverse_on_touch(sim):
    """A closed loop: the sine, reversed where the voxel touches the floor."""
    u = sine_of(sim)
    return np.where(sim.sensors("touch")["touch"] == 1.0, -u, u)


def test_save_restore_reproduces_the_same_future_bit_for_bit():
    robot = short_walker(0.6)
    sim = plastivox.Simulator(robot)
    for _ in range(400):
        sim.set_actuation(reverse_on_touch(sim))
        sim.step()
    snapshot = sim.save_state()

    def future(s):
        hashes = []
        for _ in range(300):
            s.set_actuation(reverse_on_touch(s))
            s.step()
            hashes.append(s.state_hash)
        return hashes

    first = future(sim)
    sim.restore_state(snapshot)
    assert future(sim) == first
    fresh = plastivox.Simulator(robot)
    fresh.restore_state(snapshot)
    assert future(fresh) == first
    # The closed loop is another gait than the sine's.
    builtin = plastivox.Simulator(robot)
    builtin.step(700)
    assert builtin.state_hash != first[-1]


def test_reset_starts_the_life_again():
    robot = short_walker()
    sim = plastivox.Simulator(robot)
    sim.step(300)
    sim.reset()
    assert sim.steps == 0 and sim.time == 0
    sim.run()
    assert sim.state_hash == run_builtin(robot)
    # The held signal of a Python controller is in the snapshot, and reset zeroes it.
    n = len(sim.voxel_phase)
    sim.reset()
    sim.set_actuation(np.full(n, -0.25))
    assert np.array_equal(sim.actuation, np.full(n, -0.25))
    sim.reset()
    assert sim.controller is None and np.array_equal(sim.actuation, np.zeros(n))
    sim.set_controller("sine")
    sim.run()
    assert sim.state_hash == run_builtin(robot)


def test_act_scale_in_a_robot_file_makes_passive_tissue_and_pickles(tmp_path):
    walker = plastivox.demo_walker().with_physics({"duration": 0.4, "settle_time": 0.1})
    walker.save(tmp_path / "walker.json")
    doc = json.loads((tmp_path / "walker.json").read_text())
    n = len(doc["voxels"])
    doc["act_scale"] = [0.0] * (n // 2) + [1.0] * (n - n // 2)  # the first half passive
    (tmp_path / "half.json").write_text(json.dumps(doc))
    half = plastivox.load_robot(tmp_path / "half.json")
    sim = plastivox.Simulator(half)
    sim.step(600)
    sizes = sim.state["size"]
    size0 = 0.01  # the walker's voxel size, m
    assert np.all(sizes[: n // 2] == size0) and np.any(sizes[n // 2:] != size0)
    back = pickle.loads(pickle.dumps(half))
    assert back == half and back != walker
    assert plastivox.simulate(back).final_state_hash == plastivox.simulate(half).final_state_hash
    doc["act_scale"][0] = 2.0
    (tmp_path / "bad.json").write_text(json.dumps(doc))
    with pytest.raises(plastivox.InputError, match=r"bad.json.*act_scale\[0\].*\[0, 1\]"):
        plastivox.load_robot(tmp_path / "bad.json")


def test_a_robot_file_with_a_neural_controller_runs_it_and_pickles_keep_it(tmp_path):
    # The demo walker with a distributed network of 2 hidden units (51 weights), every 3
    # steps: Python runs the file's network, names it, and a pickle keeps every weight.
    path = tmp_path / "walker.json"
    short_walker().save(path)
    data = json.loads(path.read_text())
    weights = [((7 * k) % 11 - 5) / 5 for k in range(51)]
    data["controller"] = {"kind": "distributed", "hidden": 2, "every": 3, "weights": weights}
    path.write_text(json.dumps(data))
    robot = plastivox.load_robot(path)
    sim = plastivox.Simulator(robot)
    assert sim.controller == "distributed"
    own = run_builtin(robot)
    assert own == plastivox.simulate(robot).final_state_hash
    assert own != run_builtin(short_walker())
    back = pickle.loads(pickle.dumps(robot))
    assert back == robot and hash(back) == hash(robot)
    assert run_builtin(back) == own
    # The sine instead, and back to the robot's own network by its name.
    sim = plastivox.Simulator(robot)
    sim.set_controller("sine")
    assert sim.controller == "sine"
    sim.set_controller("distributed", every=3)
    assert sim.controller == "distributed"
    sim.run()
    assert sim.state_hash == own
    with pytest.raises(ValueError, match='"sine", "distributed" \\(the robot\'s own\\) or None'):
        sim.set_controller("central")
    # A snapshot holds the signals in flight: the restored life ends in the same bits.
    first = plastivox.Simulator(robot)
    first.step(300)
    snapshot = first.save_state()
    first.run()
    second = plastivox.Simulator(robot)
    second.restore_state(snapshot)
    second.run()
    assert second.state_hash == first.state_hash == own


def test_weights_trained_in_python_make_a_robot_that_runs_them(tmp_path):
    # A central network of 1 hidden unit, every 2 steps, from a numpy array: the same robot
    # (and life, bit for bit) as a robot file naming it, and it pickles with every weight.
    walker = short_walker()
    n = plastivox.controller_weight_count("central", 1)
    assert n == 17
    assert plastivox.controller_weight_count("distributed", 4) == 95
    assert plastivox.controller_weight_count("central", 4) == 41
    assert plastivox.controller_weight_count("sine") == 0
    weights = np.sin(1.7 * np.arange(n))
    robot = walker.with_controller("central", hidden=1, every=2, weights=weights)
    c = robot.controller
    assert (c["kind"], c["hidden"], c["every"]) == ("central", 1, 2)
    assert c["weights"].dtype == np.float64 and np.array_equal(c["weights"], weights)
    assert walker.controller["kind"] == "sine" and len(walker.controller["weights"]) == 0
    assert robot != walker and walker.with_controller(**robot.controller) == robot

    walker.save(tmp_path / "walker.json")
    doc = json.loads((tmp_path / "walker.json").read_text())
    doc["controller"] = {"kind": "central", "hidden": 1, "every": 2, "weights": weights.tolist()}
    (tmp_path / "central.json").write_text(json.dumps(doc))
    from_file = plastivox.load_robot(tmp_path / "central.json")
    assert from_file == robot
    life = plastivox.simulate(robot)
    assert life.status == "finished"
    assert life.final_state_hash == plastivox.simulate(from_file).final_state_hash
    assert life.final_state_hash != plastivox.simulate(walker).final_state_hash
    sim = plastivox.Simulator(robot)
    assert sim.controller == "central"
    sim.run()
    assert sim.state_hash == life.final_state_hash
    back = pickle.loads(pickle.dumps(robot))
    assert back == robot and np.array_equal(back.controller["weights"], weights)
    assert plastivox.simulate(back).final_state_hash == life.final_state_hash
    # A list works as well as an array; saving writes the file form back.
    as_list = walker.with_controller("central", 1, 2, weights.tolist())
    assert as_list == robot
    as_list.save(tmp_path / "again.json")
    assert plastivox.load_robot(tmp_path / "again.json") == robot
    # from_arrays takes the same dict; back to the sine.
    built = plastivox.Robot.from_arrays(robot.geometry, robot.stiffness, robot.phase,
                                        controller={"kind": "distributed", "hidden": 0,
                                                    "weights": np.zeros(105)})
    assert built.controller["kind"] == "distributed" and built.controller["every"] == 1
    assert robot.with_controller("sine").controller["kind"] == "sine"
    assert robot.with_controller("sine") == walker


def test_wrong_controller_arguments_raise_a_clear_error_naming_them():
    walker = short_walker()
    ok = np.zeros(17)
    cases = [
        (TypeError, "kind: expected sine, distributed or central", dict(kind=3)),
        (ValueError, "kind: 'lstm' is not a controller", dict(kind="lstm")),
        (ValueError, r"hidden: must be in \[1, 64\] for central, got 0",
         dict(kind="central", hidden=0, weights=ok)),
        (ValueError, r"hidden: must be in \[0, 64\] for distributed, got 65",
         dict(kind="distributed", hidden=65)),
        (TypeError, "hidden: expected a whole number", dict(kind="central", hidden=1.5)),
        (ValueError, "hidden: the sine has no network, expected 0, got 2",
         dict(kind="sine", hidden=2)),
        (ValueError, "every: expected a number of steps >= 1, got 0",
         dict(kind="central", hidden=1, every=0, weights=ok)),
        (TypeError, "every: expected a whole number", dict(kind="sine", every=True)),
        (ValueError, "weights: expected 17 numbers for central with hidden 1, got 16",
         dict(kind="central", hidden=1, weights=np.zeros(16))),
        (ValueError, "weights: expected 17 numbers for central with hidden 1, got 0",
         dict(kind="central", hidden=1)),
        (ValueError, "weights: expected 0 numbers for sine with hidden 0, got 2",
         dict(kind="sine", weights=[1.0, 2.0])),
        (ValueError, r"weights\[3\]: not finite",
         dict(kind="central", hidden=1, weights=np.where(np.arange(17) == 3, np.nan, 0.0))),
        (ValueError, r"weights\[0\]: not finite",
         dict(kind="central", hidden=1, weights=[np.inf] + [0.0] * 16)),
        (ValueError, r"weights: expected a flat list of numbers, got shape \(17, 1\)",
         dict(kind="central", hidden=1, weights=np.zeros((17, 1)))),
        (TypeError, "weights: expected numbers, got dtype <U1",
         dict(kind="central", hidden=1, weights=["a"] * 17)),
        (TypeError, "weights: expected a list or array of numbers, got str",
         dict(kind="central", hidden=1, weights="0.5")),
    ]
    for error, message, kwargs in cases:
        with pytest.raises(error, match=message):
            walker.with_controller(**kwargs)
    with pytest.raises(TypeError, match="controller: expected a dict"):
        plastivox.Robot.from_arrays(walker.geometry, walker.stiffness, walker.phase,
                                    controller="central")
    with pytest.raises(ValueError, match="controller: unknown field 'weight'"):
        plastivox.Robot.from_arrays(walker.geometry, walker.stiffness, walker.phase,
                                    controller={"kind": "central", "weight": ok})
    with pytest.raises(ValueError, match="hidden: must be in"):
        plastivox.controller_weight_count("central", 0)
    with pytest.raises(ValueError, match="kind: 'rnn' is not a controller"):
        plastivox.controller_weight_count("rnn", 1)


def test_the_cli_controller_option_is_the_network_python_hands_over(tmp_path):
    # docs/control.md's worked central example: every weight 0 but the head's weight on local
    # input 0 (index 9 for 1 hidden unit), every 2 steps. `simulate --controller JSON` and
    # Robot.with_controller run the same network: the same life, bit for bit.
    walker = short_walker()
    path = tmp_path / "walker.json"
    walker.save(path)
    weights = [0.0] * 17
    weights[9] = 1.0
    spec = {"kind": "central", "hidden": 1, "every": 2, "weights": weights}
    _, out, _ = run_cli("simulate", str(path), "--json", "--controller", json.dumps(spec))
    cli = json.loads(out)
    life = plastivox.simulate(walker.with_controller(**spec))
    assert cli["final_state_hash"] == life.final_state_hash and cli["fitness"] == life.fitness
    assert life.final_state_hash != plastivox.simulate(walker).final_state_hash
    # A wrong definition: one line naming the option and the field, exit status 1.
    spec["weights"] = weights[:16]
    status, out, err = run_cli("simulate", str(path), "--json", "--controller", json.dumps(spec),
                               check=False)
    assert status == 1 and out == ""
    assert err.count("\n") == 1
    assert ("--controller: controller.weights: expected 17 numbers for central with hidden 1, "
            "got 16") in err


def test_with_a_free_object_the_actuation_is_the_robots_alone():
    # A free object (docs/environments.md) does not actuate: set_actuation takes the robot's
    # voxels, and actuation and voxel_phase give as many; the sine replayed so is the life.
    robot = short_walker(0.3)
    n = robot.voxel_count
    sim = plastivox.Simulator(robot, physics={"task": "push"})
    everything = len(sim.positions)
    assert sim.robot_voxels == n < everything
    assert sim.voxel_phase.shape == (n,) and sim.actuation.shape == (n,)
    with pytest.raises(ValueError, match=r"actuation: expected shape \(%d,\)" % n):
        sim.set_actuation(np.zeros(everything))
    while sim.status == "running":
        sim.set_actuation(sine_of(sim))
        sim.step()
    assert sim.state_hash == plastivox.simulate(robot, task="push").final_state_hash


def test_halves_of_a_step_are_step():
    """step1() then step2() is step(); step1 changes no state, so a snapshot between the halves
    is the state before the step and resumes bit-identically."""
    robot = short_walker(0.3)
    whole = plastivox.Simulator(robot)
    whole.run()
    halves = plastivox.Simulator(robot)
    snapshot = None
    while halves.status == "running":
        before = halves.state_hash
        halves.step1()
        assert halves.state_hash == before
        if halves.steps == 150:
            snapshot = halves.save_state()
            halves.step1()  # again: the same first half
        halves.step2()
    assert halves.state_hash == whole.state_hash
    resumed = plastivox.Simulator(robot)
    resumed.restore_state(snapshot)
    assert resumed.steps == 150
    resumed.run()
    assert resumed.state_hash == whole.state_hash
