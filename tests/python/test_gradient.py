"""plastivox.gradient (docs/gradients.md): simulate()'s fitness bit for bit, derivatives shaped
like the robot's arrays, agreeing with central differences of simulate(); bad names refused."""

import json

import numpy as np
import pytest

import plastivox

SHORT = {"duration": 0.2, "settle_time": 0.05}


def cube3(phase_shift=0.0, site=None, stiffer=1.0):
    """A 3x3x3 body with distinct stiffness and phases (tests/grad_gradient_test.cpp's)."""
    s = np.arange(27, dtype=np.float64).reshape((3, 3, 3), order="F")
    stiffness = stiffer * 1e8 * (1.5 + np.sin(1.7 * s + 0.3))
    phase = 0.37 * np.sin(0.9 * s) + 0.05 * s
    if site is not None:
        phase[site] += phase_shift
    return plastivox.Robot.from_arrays(np.ones((3, 3, 3), dtype=np.uint8), stiffness, phase)


def test_fitness_is_simulates_and_arrays_are_shaped_like_the_robots():
    robot = cube3()
    fitness, grads = plastivox.gradient(robot, wrt=["stiffness", "phase", "dev_rate", "amplitude"],
                                        physics=SHORT)
    assert fitness == plastivox.simulate(robot, physics=SHORT).fitness
    for name in ("stiffness", "phase", "dev_rate"):
        assert grads[name].shape == robot.shape
    assert isinstance(grads["amplitude"], float)
    assert np.all(grads["dev_rate"] == 0)  # no development under treatment none
    assert np.any(grads["phase"] != 0) and np.any(grads["stiffness"] != 0)


def test_phase_derivative_agrees_with_central_differences():
    site = (1, 0, 0)  # voxel 1 of tests/grad_gradient_test.cpp's 3x3x3 body: a smooth one
    _, grads = plastivox.gradient(cube3(), wrt="phase", physics=SHORT)

    def f(h):
        return plastivox.simulate(cube3(h, site), physics=SHORT).fitness

    h = 1e-4
    d1 = (f(h) - f(-h)) / (2 * h)
    d2 = (f(h / 2) - f(-h / 2)) / h
    difference = (4 * d2 - d1) / 3  # Richardson: error O(h^4)
    assert grads["phase"][site] == pytest.approx(difference, rel=1e-6)


def test_controller_weights_agree_with_central_differences():
    # A distributed network (no hidden layer: 105 weights) on the 3x3x3 body, rate limit off.
    count = plastivox.controller_weight_count("distributed", 0)
    weights = 0.8 * np.sin(1.3 * np.arange(count) + 0.7)
    physics = dict(SHORT, act_max_rate=0.0)

    def robot(w):
        return cube3().with_controller("distributed", hidden=0, every=1, weights=w)

    fitness, grads = plastivox.gradient(robot(weights), wrt=["controller"], physics=physics)
    assert fitness == plastivox.simulate(robot(weights), physics=physics).fitness
    assert grads["controller"].shape == robot(weights).controller["weights"].shape
    k = 2  # the touch input's weight of the actuation unit: a smooth one
    def f(h):
        w = weights.copy()
        w[k] += h
        return plastivox.simulate(robot(w), physics=physics).fitness

    h = 3e-4 * abs(weights[k])
    d1 = (f(h) - f(-h)) / (2 * h)
    d2 = (f(h / 2) - f(-h / 2)) / h
    assert grads["controller"][k] == pytest.approx((4 * d2 - d1) / 3, rel=1e-6)
    with pytest.raises(ValueError, match="^wrt: 'controller': the robot's controller is the sine"):
        plastivox.gradient(cube3(), wrt=["controller"], physics=SHORT)


def test_the_documented_ascent_loop_raises_the_fitness():
    # docs/python.md's loop over plastivox.gradient, on the 3x3x3 body.
    robot = cube3().with_physics(SHORT, treatment="stress")
    seen = []
    for _ in range(3):
        fitness, g = plastivox.gradient(robot, wrt=["phase"])
        seen.append(fitness)
        phase = robot.phase + 0.02 * g["phase"] / np.abs(g["phase"]).max()
        phase -= np.round(phase)
        robot = plastivox.Robot.from_arrays(robot.geometry, robot.stiffness, phase, robot.dev_rate,
                                            controller=robot.controller).with_physics(
                                                robot.physics, treatment=robot.treatment)
    assert robot.treatment == "stress" and np.all(np.abs(robot.phase) <= 0.5)
    assert plastivox.simulate(robot).fitness > seen[-1] > seen[0], seen


def test_bad_input_is_refused_in_one_line():
    with pytest.raises(ValueError, match=r"^wrt: no parameter is called 'mass' \(stiffness"):
        plastivox.gradient(cube3(), wrt=["mass"], physics=SHORT)


def test_a_life_that_does_not_count_has_no_gradient():
    # A soft block falls through the floor: sunk, invalid under sinking_invalid (on in every
    # preset), fitness 0 whatever its parameters.
    soft = plastivox.Robot.from_arrays(np.ones((2, 2, 2), dtype=np.uint8), np.full((2, 2, 2), 1e5),
                                       np.zeros((2, 2, 2)))
    with pytest.raises(ValueError, match="^gradient: the life does not count.*sank"):
        plastivox.gradient(soft, physics={"duration": 1.0, "sinking_invalid": True})


def test_one_and_two_threads_give_the_same_bits():
    # A developing body (stress): the backward pass on one thread, and on two (the sweep of a
    # segment beside the recomputation of the one before), gives every array bit for bit.
    base = cube3()
    rate = 2.0 + np.cos(1.3 * np.arange(27.0)).reshape((3, 3, 3), order="F")
    robot = plastivox.Robot.from_arrays(base.geometry, base.stiffness, base.phase, rate)
    robot = robot.with_physics(dict(SHORT, duration=0.15), treatment="stress")
    wrt = ["stiffness", "phase", "dev_rate", "amplitude"]
    f1, g1 = plastivox.gradient(robot, wrt=wrt, threads=1)
    f2, g2 = plastivox.gradient(robot, wrt=wrt, threads=2)
    assert f1 == f2 == plastivox.simulate(robot).fitness
    for name in ("stiffness", "phase", "dev_rate"):
        assert g1[name].tobytes() == g2[name].tobytes(), name
    assert g1["amplitude"] == g2["amplitude"]
    assert np.any(g1["dev_rate"] != 0)
    with pytest.raises(ValueError, match=r"^threads: expected an integer >= 0"):
        plastivox.gradient(robot, wrt="phase", threads=-1)


def test_any_tasks_fitness_is_simulates_and_the_initial_state_has_its_gradient():
    # jump on a cube a hundred times stiffer: the softer one never rises above its settled height
    # in so short a life (fitness 0).
    for task, robot in (("jump", cube3(stiffer=100)), ("turn", cube3())):
        physics = dict(SHORT, task=task)
        fitness, g = plastivox.gradient(robot, wrt=["phase", "initial_position", "initial_velocity"],
                                        physics=physics)
        assert fitness == plastivox.simulate(robot, physics=physics).fitness > 0, task
        assert g["initial_position"].shape == (27, 3) and g["initial_velocity"].shape == (27, 3)
        assert np.any(g["phase"] != 0)
        site = (1, 0, 0)

        def f(h):
            shifted = cube3(h, site, stiffer=100 if task == "jump" else 1)
            return plastivox.simulate(shifted, physics=physics).fitness

        h = 1e-4
        d1 = (f(h) - f(-h)) / (2 * h)
        d2 = (f(h / 2) - f(-h / 2)) / h
        assert g["phase"][site] == pytest.approx((4 * d2 - d1) / 3, rel=1e-6), task


def life_of(robot, physics):
    """Every state's positions and the last state's, stepping a Simulator."""
    sim = plastivox.Simulator(robot, physics=physics)
    pos = [sim.state["pos"].copy()]
    while sim.status == "running":
        sim.step()
        pos.append(sim.state["pos"].copy())
    return np.array(pos)


def mean_height_and_final_x(states):
    """A loss of every recorded state: voxel 13's mean height over the life plus voxel 0's last
    x, in voxel lengths; and its derivative with respect to states["pos"]."""
    pos = states["pos"]
    value = (pos[:, 13, 2].mean() + pos[-1, 0, 0]) / 0.01
    d = np.zeros_like(pos)
    d[:, 13, 2] = 1 / len(pos) / 0.01
    d[-1, 0, 0] += 1 / 0.01
    return value, {"pos": d}


def test_gradient_of_a_loss_over_every_state_agrees_with_central_differences():
    value, g = plastivox.gradient_of(cube3(), mean_height_and_final_x, wrt=["phase", "stiffness"],
                                     physics=SHORT)
    assert value == mean_height_and_final_x({"pos": life_of(cube3(), SHORT)})[0]
    assert g["phase"].shape == (3, 3, 3)
    site = (1, 0, 0)

    def f(h):
        return mean_height_and_final_x({"pos": life_of(cube3(h, site), SHORT)})[0]

    h = 1e-4
    d1 = (f(h) - f(-h)) / (2 * h)
    d2 = (f(h / 2) - f(-h / 2)) / h
    assert g["phase"][site] == pytest.approx((4 * d2 - d1) / 3, rel=1e-6)


def test_gradient_of_reads_the_steps_asked_for():
    # A loss of the initial state alone: its derivative is the initial state's gradient, as given.
    w = np.arange(27 * 3, dtype=np.float64).reshape(1, 27, 3)
    seen = {}

    def loss(states):
        seen.update(states)
        return float((w * states["pos"]).sum()), {"pos": w, "lin_mom": 2 * w}

    value, g = plastivox.gradient_of(cube3(), loss, steps=[0], fields=["pos", "lin_mom"],
                                     wrt=["initial_position", "initial_velocity", "phase"],
                                     physics=SHORT)
    assert list(seen["steps"]) == [0] and seen["pos"].shape == (1, 27, 3)
    np.testing.assert_array_equal(g["initial_position"], w[0])
    mass = float(plastivox.Simulator(cube3(), physics=SHORT).model["mass"])
    np.testing.assert_allclose(g["initial_velocity"], 2 * w[0] * mass, rtol=1e-15)
    assert np.all(g["phase"] == 0)
    # Steps counted from the end, in increasing order, each once.
    steps = plastivox.simulate(cube3(), physics=SHORT).steps
    plastivox.gradient_of(cube3(), loss_of_nothing(seen), steps=[-1, 5, 5, 0], physics=SHORT)
    assert list(seen["steps"]) == [0, 5, steps]


def stepped(robot, steps, physics=SHORT):
    """A Simulator stepped `steps` times, and its positions at every state it passed through."""
    sim = plastivox.Simulator(robot, physics=physics)
    pos = [sim.state["pos"].copy()]
    for _ in range(steps):
        sim.step()
        pos.append(sim.state["pos"].copy())
    return sim, np.array(pos)


def test_simulator_backward_is_gradient_ofs_for_the_life_so_far_and_central_differences():
    # A Simulator stopped part way (past settling, so the phases act), a loss of the states it
    # recorded: backward gives gradient_of's derivatives of the same loss of the same states,
    # bit for bit, and they agree with central differences of Simulators stepped as far.
    n = 50  # of the life's 70
    sim, pos = stepped(cube3(), n)
    assert sim.status == "running" and sim.time > SHORT["settle_time"]
    value, d = mean_height_and_final_x({"pos": pos})
    wrt = ["phase", "stiffness", "initial_velocity"]
    g = sim.backward(d, wrt=wrt)
    v2, g2 = plastivox.gradient_of(cube3(), mean_height_and_final_x, steps=range(n + 1),
                                   wrt=wrt, physics=SHORT)
    assert v2 == value
    for name in wrt:
        np.testing.assert_array_equal(g[name], g2[name])
    assert sim.steps == n and sim.status == "running"  # the Simulator itself did not move
    site = (1, 0, 0)

    def f(h):
        return mean_height_and_final_x({"pos": stepped(cube3(h, site), n)[1]})[0]

    h = 1e-4
    d1 = (f(h) - f(-h)) / (2 * h)
    d2 = (f(h / 2) - f(-h / 2)) / h
    assert g["phase"][site] != 0
    assert g["phase"][site] == pytest.approx((4 * d2 - d1) / 3, rel=1e-6)
    # Some states only, one counted from the present; step1 and step2 make the same life.
    sim.step1()
    sim.step2()
    w = np.zeros((2,) + pos.shape[1:])
    w[0, 4, 1] = 1.0
    w[1, 13, 2] = 2.0
    g3 = sim.backward({"pos": w}, steps=[30, -1], wrt="phase")
    v4, g4 = plastivox.gradient_of(
        cube3(), lambda s: (0.0, {"pos": w}), steps=[30, n + 1], wrt="phase", physics=SHORT)
    np.testing.assert_array_equal(g3["phase"], g4["phase"])


def test_simulator_backward_refuses_a_steered_life_and_bad_input_in_one_line():
    sim, pos = stepped(cube3(), 40)
    d = {"pos": np.zeros_like(pos)}
    with pytest.raises(ValueError, match=r"^derivatives: 'pos' must be shaped \(2, 27, 3\)"):
        sim.backward(d, steps=[0, 5])
    with pytest.raises(ValueError, match=r"^steps: the states must increase"):
        sim.backward({"pos": np.zeros((2, 27, 3))}, steps=[5, 5])
    with pytest.raises(ValueError, match=r"^steps: 41 is outside the life's states 0\.\.40"):
        sim.backward({"pos": np.zeros((1, 27, 3))}, steps=[41])
    with pytest.raises(ValueError, match=r"^derivatives: 'steps' is not a floating-point row"):
        sim.backward({"steps": np.zeros(41)})
    with pytest.raises(ValueError, match=r"^derivatives: 'floor_deepest' is not a floating-point"):
        sim.backward({"floor_deepest": np.zeros(41)})  # a watch: the replica does not keep it
    with pytest.raises(ValueError, match=r"^wrt: no parameter is called 'mass'"):
        sim.backward(d, wrt="mass")
    with pytest.raises(ValueError, match=r"^backward: the Simulator has not stepped yet"):
        plastivox.Simulator(cube3(), physics=SHORT).backward({})
    # A life another signal drove, or restored from another life's state, is not the one the
    # backward pass recomputes from t = 0.
    sim.set_actuation(np.full(27, 0.5))
    sim.step(5)
    with pytest.raises(ValueError, match=r"^backward: this Simulator's life is not its robot's"):
        sim.backward({"pos": np.zeros((46, 27, 3))})
    other, _ = stepped(cube3(0.1, (1, 0, 0)), 40)
    sim2, _ = stepped(cube3(), 10)
    sim2.restore_state(other.save_state())
    with pytest.raises(ValueError, match=r"^backward: this Simulator's life is not its robot's"):
        sim2.backward({"pos": np.zeros((1, 27, 3))}, steps=[-1])


def loss_of_nothing(seen):
    def loss(states):
        seen.clear()
        seen.update(states)
        return 0.0, {}
    return loss


def test_gradient_of_refuses_bad_input_in_one_line():
    nothing = loss_of_nothing({})
    with pytest.raises(ValueError, match=r"^fields: 'steps' is not a floating-point row"):
        plastivox.gradient_of(cube3(), nothing, fields=["steps"], physics=SHORT)
    with pytest.raises(ValueError, match=r"^fields: 'mass' is not a floating-point row"):
        plastivox.gradient_of(cube3(), nothing, fields=["mass"], physics=SHORT)
    with pytest.raises(ValueError, match=r"^steps: 100000 is outside the life's states 0\.\."):
        plastivox.gradient_of(cube3(), nothing, steps=[100000], physics=SHORT)
    with pytest.raises(ValueError, match=r"^loss: the derivative of 'pos' must be shaped like"):
        plastivox.gradient_of(cube3(), lambda s: (0.0, {"pos": np.zeros(3)}), physics=SHORT)
    with pytest.raises(ValueError, match=r"^loss: a derivative of 'size', which is not among"):
        plastivox.gradient_of(cube3(), lambda s: (0.0, {"size": 0}), physics=SHORT)
    with pytest.raises(TypeError, match=r"^loss: must return \(value, \{field: derivative\}\)"):
        plastivox.gradient_of(cube3(), lambda s: 0.0, physics=SHORT)
    with pytest.raises(ZeroDivisionError):  # the loss's own error comes through
        plastivox.gradient_of(cube3(), lambda s: 1 / 0, physics=SHORT)
    with pytest.raises(ValueError, match=r"^wrt: no parameter is called 'mass'"):
        plastivox.gradient_of(cube3(), nothing, wrt=["mass"], physics=SHORT)


def robot_with_own_amplitudes(tmp_path, nudge=0.0, site=None):
    """The 3x3x3 body with amplitudes of its own (voxcraft's rule: a robot file's 7th entry per
    voxel) and an act_scale of 0.5 at every fourth voxel, from a robot file (json keeps every
    double exactly); `nudge` added to the amplitude at `site`."""
    base = cube3()
    voxels, scale = [], []
    for k in range(27):
        x, y, z = k % 3, (k // 3) % 3, k // 9
        amplitude = 0.12 + 0.05 * np.sin(2.3 * k) + (nudge if (x, y, z) == site else 0.0)
        voxels.append([x, y, z, float(base.stiffness[x, y, z]), 0.0, float(base.phase[x, y, z]),
                       float(amplitude)])
        scale.append(0.5 if k % 4 == 0 else 1.0)
    path = tmp_path / f"own-{nudge!r}.json"
    path.write_text(json.dumps({"format": "plastivox-robot", "version": 1,
                                "lattice": {"nx": 3, "ny": 3, "nz": 3, "voxel_size": 0.01},
                                "voxels": voxels, "act_scale": scale}))
    return plastivox.load_robot(str(path))


def central(f, h):
    """Richardson-extrapolated central difference of f at 0 (error O(h^4))."""
    d1 = (f(h) - f(-h)) / (2 * h)
    d2 = (f(h / 2) - f(-h / 2)) / h
    return (4 * d2 - d1) / 3


def test_own_amplitudes_and_the_physics_amplitude_agree_with_central_differences(tmp_path):
    robot = robot_with_own_amplitudes(tmp_path)
    fitness, g = plastivox.gradient(robot, wrt=["act_amplitude", "amplitude"], physics=SHORT)
    assert fitness == plastivox.simulate(robot, physics=SHORT).fitness
    assert g["act_amplitude"].shape == robot.shape
    assert g["amplitude"] == 0.0  # the robot's own amplitudes do not read the physics'
    for site in ((0, 0, 0), (1, 1, 1), (2, 0, 1)):  # act_scale 0.5, 1, 1
        amplitude = robot.act_amplitude[site]

        def f(h):
            nudged = robot_with_own_amplitudes(tmp_path, h, site)
            return plastivox.simulate(nudged, physics=SHORT).fitness

        difference = central(f, 1e-4 * amplitude)
        assert difference != 0
        assert g["act_amplitude"][site] == pytest.approx(difference, rel=1e-6), site
    # The physics' amplitude, for a robot of the paper's rule.
    _, g = plastivox.gradient(cube3(), wrt=["amplitude"], physics=SHORT)
    a = 0.1447

    def f(h):
        return plastivox.simulate(cube3(), physics=dict(SHORT, act_amplitude=a + h)).fitness

    assert g["amplitude"] == pytest.approx(central(f, 1e-4 * a), rel=1e-6)
    with pytest.raises(ValueError, match=r"^wrt: 'act_amplitude': the robot has no amplitudes"):
        plastivox.gradient(cube3(), wrt=["act_amplitude"], physics=SHORT)


def robot_with_scales(tmp_path, own_amplitudes, scales=True, nudge=0.0, site=None):
    """The 3x3x3 body from a robot file, actuated by the paper's rule (physics act_amplitude x
    xi(E)) or, own_amplitudes, by amplitudes of its own (robot_with_own_amplitudes'), with an
    act_scale of 0.5, 0.7 or 0.9 per voxel (none when not scales); `nudge` added to the scale at
    `site`."""
    base = cube3()
    voxels, scale = [], []
    for k in range(27):
        x, y, z = k % 3, (k // 3) % 3, k // 9
        voxel = [x, y, z, float(base.stiffness[x, y, z]), 0.0, float(base.phase[x, y, z])]
        if own_amplitudes:
            voxel.append(float(0.12 + 0.05 * np.sin(2.3 * k)))
        voxels.append(voxel)
        scale.append(0.5 + 0.2 * (k % 3) + (nudge if (x, y, z) == site else 0.0))
    document = {"format": "plastivox-robot", "version": 1,
                "lattice": {"nx": 3, "ny": 3, "nz": 3, "voxel_size": 0.01}, "voxels": voxels}
    if scales is not None:
        document["act_scale"] = scale if scales is True else scales
    path = tmp_path / f"scales-{own_amplitudes}-{scales is True}-{nudge!r}-{site}.json"
    path.write_text(json.dumps(document))
    return plastivox.load_robot(str(path))


@pytest.mark.parametrize("own_amplitudes", [False, True])
def test_act_scale_agrees_with_central_differences(tmp_path, own_amplitudes):
    # d gain / d act_scale is 1 under the paper's rule (the gain is the scale), the voxel's own
    # amplitude under voxcraft's: both against differences of lives from nudged robot files.
    robot = robot_with_scales(tmp_path, own_amplitudes)
    fitness, g = plastivox.gradient(robot, wrt=["act_scale", "stiffness"], physics=SHORT)
    assert fitness == plastivox.simulate(robot, physics=SHORT).fitness
    assert g["act_scale"].shape == robot.shape == robot.act_scale.shape
    for site in ((0, 0, 0), (1, 1, 1), (2, 0, 1)):  # act_scale 0.5, 0.7, 0.9
        scale = robot.act_scale[site]

        def f(h):
            nudged = robot_with_scales(tmp_path, own_amplitudes, nudge=h, site=site)
            return plastivox.simulate(nudged, physics=SHORT).fitness

        difference = central(f, 1e-4 * scale)
        assert difference != 0
        assert g["act_scale"][site] == pytest.approx(difference, rel=1e-6), site
    if own_amplitudes:  # the chain rule's two ends: amplitude x d/d amplitude = scale x d/d scale
        _, h = plastivox.gradient(robot, wrt=["act_amplitude"], physics=SHORT)
        assert np.allclose(robot.act_amplitude * h["act_amplitude"],
                           robot.act_scale * g["act_scale"], rtol=1e-12, atol=0)


def test_act_scale_of_a_robot_without_one_is_the_derivative_at_1(tmp_path):
    # No act_scale array: every voxel's scale is 1, and the derivative is taken there, shaped
    # like the robot; the same bits as for the robot with the array of ones.
    robot = robot_with_scales(tmp_path, own_amplitudes=False, scales=None)
    assert robot.act_scale is None
    fitness, g = plastivox.gradient(robot, wrt="act_scale", physics=SHORT)
    ones = robot_with_scales(tmp_path, own_amplitudes=False, scales=[1.0] * 27)
    fitness1, g1 = plastivox.gradient(ones, wrt="act_scale", physics=SHORT)
    assert g["act_scale"].shape == robot.shape
    assert fitness == fitness1 and g["act_scale"].tobytes() == g1["act_scale"].tobytes()
    # The robot format stops at 1, so the difference is one-sided there (from below),
    # Richardson-extrapolated: (f(1) - f(1 - h)) / h has error O(h), 2 D(h/2) - D(h) O(h^2).
    site = (1, 0, 0)
    scales = np.ones(27)

    def f(h):
        nudged = scales.copy()
        nudged[site[0] + 3 * site[1] + 9 * site[2]] -= h
        return plastivox.simulate(robot_with_scales(tmp_path, False, scales=list(nudged)),
                                  physics=SHORT).fitness

    h = 1e-4
    d1 = (fitness - f(h)) / h
    d2 = (fitness - f(h / 2)) / (h / 2)
    assert g["act_scale"][site] == pytest.approx(2 * d2 - d1, rel=1e-6)


def test_initial_orientation_and_angular_velocity():
    # Through a loss of the initial state: its derivative comes back as the gradient, the
    # orientation's w column projected out (x, y, z, w) and the angular momentum's scaled to
    # per rad/s by the inertia; and the task's fitness, whose derivatives are not all 0
    # (tests/grad_gradient_test.cpp checks them against central differences of nudged lives).
    wq = np.arange(27 * 4, dtype=np.float64).reshape(1, 27, 4) + 1
    wl = np.arange(27 * 3, dtype=np.float64).reshape(1, 27, 3) + 1

    def loss(states):
        return float((wq * states["orient"]).sum()), {"orient": wq, "ang_mom": wl}

    names = ["initial_orientation", "initial_angular_velocity"]
    _, g = plastivox.gradient_of(cube3(), loss, steps=[0], fields=["orient", "ang_mom"], wrt=names,
                                 physics=SHORT)
    assert g["initial_orientation"].shape == (27, 4)
    np.testing.assert_array_equal(g["initial_orientation"][:, :3], wq[0, :, :3])
    assert np.all(g["initial_orientation"][:, 3] == 0)
    inertia = float(plastivox.Simulator(cube3(), physics=SHORT).model["inertia"])
    np.testing.assert_allclose(g["initial_angular_velocity"], wl[0] * inertia, rtol=1e-15)
    fitness, g = plastivox.gradient(cube3(), wrt=names, physics=SHORT)
    assert fitness == plastivox.simulate(cube3(), physics=SHORT).fitness
    assert g["initial_angular_velocity"].shape == (27, 3)
    turn = g["initial_orientation"]
    assert np.any(turn[:, :3] != 0) and np.all(turn[:, 3] == 0)
    assert np.any(g["initial_angular_velocity"] != 0)
    with pytest.raises(ValueError, match=r"^wrt: no parameter is called 'initial_spin'"):
        plastivox.gradient(cube3(), wrt=["initial_spin"], physics=SHORT)


def test_gradient_of_steps_from_the_end_without_a_second_life():
    # The states counted from the end come from the gradient's own life (no life simulated
    # before it): the same states a Simulator passes through, among the ones counted from the
    # start, each once, in increasing order.
    pos = life_of(cube3(), SHORT)
    last = len(pos) - 1
    seen = {}
    plastivox.gradient_of(cube3(), loss_of_nothing(seen), steps=[-3, 2, -1, last - 2, 0],
                          physics=SHORT)
    assert list(seen["steps"]) == [0, 2, last - 2, last]
    np.testing.assert_array_equal(seen["pos"], pos[[0, 2, last - 2, last]])
    outside = rf"^steps: -{last + 2} is outside the life's states 0\.\.{last} "
    with pytest.raises(ValueError, match=outside):
        plastivox.gradient_of(cube3(), loss_of_nothing({}), steps=[-(last + 2)], physics=SHORT)


def test_gradient_of_holds_the_recording_to_its_limit(monkeypatch):
    # 1 MB holds about 800 states of a 27-voxel body's positions and their derivatives. Refused
    # before the life runs, on the steps the initial time step gives (about 1 060 over 3 s), and
    # as it runs when development shortens the step: under pressure at rates of 100/s a 0.5 s
    # life estimated at 177 states takes 1 240.
    monkeypatch.setenv("PLASTIVOX_MAX_RECORDING_MB", "1")
    nothing = loss_of_nothing({})
    with pytest.raises(ValueError, match=r"^steps: the recording would need about 1\.\d+ MB"):
        plastivox.gradient_of(cube3(), nothing, physics=dict(SHORT, duration=3.0))
    fast = plastivox.Robot.from_arrays(np.ones((3, 3, 3), dtype=np.uint8), cube3().stiffness,
                                       cube3().phase, np.full((3, 3, 3), 100.0))
    physics = dict(SHORT, duration=0.5)
    assert plastivox.simulate(fast, physics=physics, treatment="pressure").steps > 900
    over = r"^steps: the recording would need about 1(\.\d+)? MB of memory, more than the limit"
    with pytest.raises(ValueError, match=over):
        plastivox.gradient_of(fast, nothing, physics=physics, treatment="pressure")
    plastivox.gradient_of(fast, nothing, steps=[0, -1], physics=physics, treatment="pressure")
