"""plastivox.VoxelEnv, the Gymnasium-style environment (docs/python.md, "Reinforcement
learning"), checked without gymnasium: seeded resets, spaces, where episodes end, rewards
summing to simulate()'s fitness, wrong actions; and the registration hook with a stand-in
gymnasium module. Also the control channels of a recorded life (record_control)."""

import os
import subprocess
import sys
import textwrap

import numpy as np
import pytest

import plastivox

from conftest import expect_signals_refused, run_cli


def short_walker(duration=0.4):
    return plastivox.demo_walker().with_physics({"duration": duration, "settle_time": 0.1},
                                                treatment="stress")


def sine_action(env, obs):
    """The built-in sine's signal for the step about to be taken; `time` is obs's last entry
    when the env observes ["time"] last."""
    return plastivox.sin_cycles(env.act_frequency * obs[-1] + env.voxel_phase)


def random_episode(env, seed, steps):
    obs, _ = env.reset(seed=seed)
    seen, rewards = [obs], []
    for _ in range(steps):
        action = env.np_random.uniform(-1, 1, env.action_space.shape)
        obs, reward, terminated, truncated, _ = env.step(action)
        seen.append(obs)
        rewards.append(reward)
        if terminated or truncated:
            break
    return np.array(seen), np.array(rewards)


def test_reset_with_a_seed_is_deterministic():
    env = plastivox.VoxelEnv(short_walker())
    obs_a, rewards_a = random_episode(env, 3, 400)
    obs_b, rewards_b = random_episode(env, 3, 400)
    other = plastivox.VoxelEnv(short_walker())
    obs_c, rewards_c = random_episode(other, 3, 400)
    assert np.array_equal(obs_a, obs_b) and np.array_equal(rewards_a, rewards_b)
    assert np.array_equal(obs_a, obs_c) and np.array_equal(rewards_a, rewards_c)
    # Another seed draws other actions, and the body moves otherwise.
    obs_d, _ = random_episode(env, 4, 400)
    assert np.array_equal(obs_d[0], obs_a[0])  # every life starts alike
    assert not np.array_equal(obs_d, obs_a)
    assert np.any(rewards_a != 0)


def test_observation_and_action_match_their_spaces():
    env = plastivox.VoxelEnv(short_walker())
    n = plastivox.demo_walker().voxel_count
    widths = {"n": n, "n x 3": 3 * n, "3": 3, "1": 1}
    size = sum(widths[f["shape"]] for f in plastivox.Simulator.sensor_fields)
    assert env.observation_space.shape == (size,)
    assert env.action_space.shape == (n,)
    assert env.observation_space.dtype == np.float64 and env.action_space.dtype == np.float64
    assert np.all(env.action_space.low == -1) and np.all(env.action_space.high == 1)
    obs, info = env.reset(seed=0)
    assert obs.shape == env.observation_space.shape and obs.dtype == env.observation_space.dtype
    assert env.observation_space.contains(obs)
    assert info["time"] == 0 and info["fitness"] == 0 and info["status"] == "running"
    env.action_space.seed(1)
    for _ in range(20):
        action = env.action_space.sample()
        assert action.shape == (n,) and action.dtype == np.float64
        assert env.action_space.contains(action)
        obs, reward, terminated, truncated, info = env.step(action)
        assert obs.shape == env.observation_space.shape and obs.dtype == np.float64
        assert env.observation_space.contains(obs)
        assert isinstance(reward, float) and not terminated and not truncated
    assert not env.action_space.contains(np.full(n, 1.5))
    assert not env.action_space.contains(np.zeros(n + 1))
    # Fewer sensors, fewer numbers: touch per voxel, then the time.
    small = plastivox.VoxelEnv(short_walker(), sensors=["touch", "time"])
    obs, _ = small.reset()
    assert small.observation_space.shape == (n + 1,) and obs.shape == (n + 1,)
    assert np.all(small.observation_space.low[:n] == 0) and np.all(small.observation_space.high[:n] == 1)
    assert obs[-1] == 0.0


def test_render_rgb_array_draws_the_present_state():
    robot = short_walker()
    env = plastivox.VoxelEnv(robot, sensors="time", render_mode="rgb_array",
                             render_size=(160, 120))
    assert env.metadata["render_modes"] == ["rgb_array"] and env.render_mode == "rgb_array"
    obs, _ = env.reset(seed=0)
    first = env.render()
    assert first.shape == (120, 160, 3) and first.dtype == np.uint8
    assert first.std() > 5  # a robot, a floor and an overlay, not a blank frame
    frames = [first]
    for until in (0.15, 0.3):  # past settling (0.1 s): the body moves
        while obs[-1] < until:
            obs, _, terminated, truncated, info = env.step(sine_action(env, obs))
            assert not (terminated or truncated)
        frames.append(env.render())
    later = frames[-1]
    assert later.shape == first.shape and later.dtype == np.uint8
    assert not np.array_equal(frames[1], first) and not np.array_equal(later, frames[1])
    # The picture plastivox.render draws of the same life at that time, pixel for pixel.
    assert np.array_equal(later, plastivox.render(robot, time=info["time"], size=(160, 120)))
    # A new episode starts from the first picture again.
    env.reset()
    assert np.array_equal(env.render(), first)
    # No render_mode (the default): render() gives None.
    plain = plastivox.VoxelEnv(robot, sensors="time")
    plain.reset()
    assert plain.render_mode is None and plain.render() is None


def test_bad_render_arguments_raise_a_clear_error():
    with pytest.raises(ValueError, match=r"render_mode: expected None or \"rgb_array\".*'human'"):
        plastivox.VoxelEnv(short_walker(), render_mode="human")
    with pytest.raises(ValueError, match="render_size: each side must be 1..16384 pixels"):
        plastivox.VoxelEnv(short_walker(), render_mode="rgb_array", render_size=(0, 10))
    with pytest.raises(TypeError, match="render_size: expected \\(width, height\\)"):
        plastivox.VoxelEnv(short_walker(), render_mode="rgb_array", render_size=100)
    env = plastivox.VoxelEnv(short_walker(), render_mode="rgb_array")
    with pytest.raises(RuntimeError, match=r"render: call reset\(\) first"):
        env.render()


@pytest.mark.parametrize("task", ["walk", "jump", "turn"])
def test_rewards_sum_to_the_fitness_and_the_episode_ends_where_the_life_ends(task):
    robot = short_walker()
    life = plastivox.simulate(robot, task=task)
    assert life.status == "finished" and life.fitness > 0
    env = plastivox.VoxelEnv(robot, task=task, sensors=["touch", "time"])
    obs, info = env.reset(seed=0)
    rewards, steps = [], 0
    while True:
        obs, reward, terminated, truncated, info = env.step(sine_action(env, obs))
        assert env.observation_space.contains(obs)
        rewards.append(reward)
        steps += 1
        if terminated or truncated:
            break
    # The built-in sine replayed: the same life, bit for bit, ending at the same step.
    assert truncated and not terminated and info["status"] == "finished"
    assert steps == info["steps"] == life.steps
    assert info["state_hash"] == life.final_state_hash
    assert info["fitness"] == life.fitness
    assert sum(rewards) == pytest.approx(life.fitness, rel=1e-12, abs=1e-12)
    with pytest.raises(RuntimeError, match=r"step: the episode is over \(finished\); call reset\(\)"):
        env.step(sine_action(env, obs))
    # Holding each action for 4 steps is the life of sending it every step, in fewer calls.
    ends = {}
    for every in (1, 4):
        held = plastivox.VoxelEnv(robot, task=task, every=every, sensors="time")
        held.reset()
        calls, total = 0, 0.0
        while True:
            _, reward, terminated, truncated, info = held.step(np.full(held.action_space.shape, 0.5))
            calls += 1
            total += reward
            if terminated or truncated:
                break
        assert truncated and calls == -(-info["steps"] // every)
        assert total == pytest.approx(info["fitness"], rel=1e-12, abs=1e-12)
        ends[every] = (info["steps"], info["state_hash"], info["fitness"])
    assert ends[1] == ends[4]


def test_a_sinking_life_terminates_with_the_fitness_simulate_gives():
    # A soft, heavy 3x3x3 block falls through the floor: sunk lives are invalid (fitness 0).
    block = plastivox.Robot.from_arrays(np.ones((3, 3, 3), bool), np.full((3, 3, 3), 1e5),
                                        np.zeros((3, 3, 3)))
    robot = block.with_physics({"duration": 0.5, "act_amplitude": 0.0, "gravity": -9.81})
    life = plastivox.simulate(robot)
    assert life.health == "sank" and life.fitness == 0
    env = plastivox.VoxelEnv(robot)
    env.reset()
    total, steps = 0.0, 0
    while True:
        _, reward, terminated, truncated, info = env.step(np.zeros(env.action_space.shape))
        total += reward
        steps += 1
        if terminated or truncated:
            break
    assert terminated and not truncated and info["status"] == "sank"
    assert steps < life.steps  # ended when certain to be graded sunk
    assert info["fitness"] == 0 and total == pytest.approx(0, abs=1e-12)


def test_wrong_actions_raise_a_clear_error_naming_the_argument():
    env = plastivox.VoxelEnv(short_walker())
    n = env.action_space.shape[0]
    with pytest.raises(RuntimeError, match="call reset"):
        env.step(np.zeros(n))
    env.reset()
    with pytest.raises(ValueError, match=r"action: expected shape \(%d,\), one value per voxel, got \(%d,\)" % (n, n - 1)):
        env.step(np.zeros(n - 1))
    expect_signals_refused(env.step, "action", n)
    with pytest.raises(ValueError, match=r"sensors: no sensor named 'smell'"):
        plastivox.VoxelEnv(short_walker(), sensors=["smell"])
    with pytest.raises(ValueError, match=r"every: expected a number of steps >= 1, got 0"):
        plastivox.VoxelEnv(short_walker(), every=0)
    with pytest.raises(TypeError, match=r"task: expected a task name"):
        plastivox.VoxelEnv(short_walker(), task=3)


def test_it_registers_with_gymnasium_when_importable(tmp_path):
    # A stand-in gymnasium records what plastivox asks of it.
    fake = tmp_path / "gymnasium"
    (fake / "spaces").mkdir(parents=True)
    (fake / "__init__.py").write_text(textwrap.dedent("""
        from . import spaces
        registry = {}
        class Env:
            pass
        def register(id, entry_point):
            registry[id] = entry_point
    """))
    (fake / "spaces" / "__init__.py").write_text(textwrap.dedent("""
        class Box:
            def __init__(self, low, high, shape, dtype):
                self.low, self.high, self.shape, self.dtype = low, high, shape, dtype
    """))
    probe = textwrap.dedent("""
        import gymnasium, plastivox
        env = plastivox.VoxelEnv(plastivox.demo_walker(), sensors=["time"])
        print(gymnasium.registry, isinstance(env, gymnasium.Env),
              type(env.action_space).__module__, env.action_space.shape)
    """)
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join([str(tmp_path), env.get("PYTHONPATH", "")])
    out = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, env=env)
    assert out.returncode == 0, out.stderr
    n = plastivox.demo_walker().voxel_count
    assert out.stdout.strip() == ("{'plastivox/Voxel-v0': 'plastivox:VoxelEnv'} True "
                                  f"gymnasium.spaces ({n},)")
    # Without gymnasium, the built-in Box.
    space = plastivox.VoxelEnv(short_walker()).action_space
    assert type(space).__name__ == "Box" and type(space).__module__ == "plastivox._env"


def test_a_recorded_life_carries_the_control_channels_on_request(tmp_path):
    robot = short_walker()
    plain = plastivox.simulate(robot, record_fps=50)
    life = plastivox.simulate(robot, record_fps=50, record_control=True)
    assert life.final_state_hash == plain.final_state_hash
    assert plain.trajectory.actuation is None and plain.trajectory.touch is None
    t = life.trajectory
    frames, n = t.positions.shape[:2]
    for name in plastivox.Trajectory.CONTROL_FIELDS:
        shape = (frames, n, 3) if name in ("velocity", "up") else (frames, n)
        assert getattr(t, name).shape == shape, name
    assert np.all(np.abs(t.actuation) <= 1 + 1e-15)
    assert np.all(t.actuation[t.times < 0.1] == 0)  # still while settling
    assert np.any(t.actuation[-1] != 0)
    assert np.allclose(np.linalg.norm(t.up, axis=2), 1)
    assert set(np.unique(t.touch)) <= {0.0, 1.0} and t.touch[-1].sum() > 0
    assert t != plain.trajectory

    # The command line writes the same channels into the life file, and only when asked.
    h5py = pytest.importorskip("h5py")
    path = str(tmp_path / "walker.json")
    robot.save(path)
    run_cli("simulate", path, "--record", str(tmp_path / "control.h5"), "--fps", "50",
            "--record-control")
    run_cli("simulate", path, "--record", str(tmp_path / "plain.h5"), "--fps", "50")
    with h5py.File(tmp_path / "control.h5", "r") as f:
        assert f.attrs["control"] == 1
        for name in plastivox.Trajectory.CONTROL_FIELDS:
            assert np.array_equal(f[name][()], getattr(t, name)), name
        assert f["actuation"].attrs["units"] in ("1", b"1")
    with h5py.File(tmp_path / "plain.h5", "r") as f:
        assert "control" not in f.attrs and "actuation" not in f
    # Drawn by its signal from the file; a life recorded without it is refused in one line.
    run_cli("render", str(tmp_path / "control.h5"), "--color", "actuation", "--time", "0.3",
            "--size", "64x48", "--out", str(tmp_path / "a.png"))
    status, _, err = run_cli("render", str(tmp_path / "plain.h5"), "--color", "actuation",
                             "--out", str(tmp_path / "b.png"), check=False)
    assert status == 1 and "plain.h5: --color actuation needs the actuation signal" in err
    status, _, err = run_cli("simulate", path, "--record-control", check=False)
    assert status == 2 and "--record-control adds the actuation signal" in err
    with pytest.raises(ValueError, match="record_control: .* give record_fps > 0"):
        plastivox.simulate(robot, record_control=True)


def test_every_task_of_simulate_is_an_environment():
    # docs/python.md: VoxelEnv takes any of simulate's nine tasks.
    for task in ("walk", "jump", "turn", "rough", "climb", "slope", "obstacles", "carry",
                 "push"):
        env = plastivox.VoxelEnv(short_walker(0.2), task=task, sensors="time")
        assert env.task == task
        env.reset()
        env.step(np.zeros(env.action_space.shape))


@pytest.mark.parametrize("task", ["carry", "push"])
def test_a_free_object_is_observed_and_takes_no_action(task):
    # The action covers the robot's voxels only (a free object does not actuate); the
    # per-voxel sensors cover the object's voxels after the robot's, as a Simulator's do.
    robot = short_walker(0.3)
    n = robot.voxel_count
    sim = plastivox.Simulator(robot, physics={"task": task})
    everything = len(sim.positions)
    assert sim.robot_voxels == n < everything
    env = plastivox.VoxelEnv(robot, task=task, sensors=["touch", "time"])
    assert env.action_space.shape == (n,) and env.voxel_phase.shape == (n,)
    assert repr(env).count(f"voxels={n},") == 1
    obs, _ = env.reset()
    assert obs.shape == env.observation_space.shape == (everything + 1,)
    with pytest.raises(ValueError, match=r"action: expected shape \(%d,\), one value per voxel, "
                                         r"got \(%d,\)" % (n, everything)):
        env.step(np.zeros(everything))
    life = plastivox.simulate(robot, task=task)
    while True:  # the built-in sine replayed on the robot's voxels: simulate's life
        obs, _, terminated, truncated, info = env.step(sine_action(env, obs))
        if terminated or truncated:
            break
    assert info["state_hash"] == life.final_state_hash and info["fitness"] == life.fitness


# --- VoxelVecEnv: N environments stepped in one call (docs/python.md, "Many environments") ---

def vec_actions(rngs, shape):
    return np.stack([rng.uniform(-1, 1, shape) for rng in rngs])


@pytest.mark.parametrize("threads", [1, 2])
def test_vec_env_steps_each_environment_as_it_steps_alone(threads):
    # Three walkers driven by their own seeded random actions over more than one episode
    # (autoreset "next_step"): each row is, bit for bit, what a VoxelEnv gives alone.
    robot, sensors, every, n = short_walker(0.15), ["touch", "time"], 40, 3
    vec = plastivox.VoxelVecEnv(robot, num_envs=n, sensors=sensors, every=every,
                                threads=threads)
    shape = vec.single_action_space.shape
    obs, infos = vec.reset(seed=10)
    singles = [plastivox.VoxelEnv(robot, sensors=sensors, every=every) for _ in range(n)]
    single_obs = [env.reset(seed=10 + i)[0] for i, env in enumerate(singles)]
    np.testing.assert_array_equal(obs, np.stack(single_obs))
    assert list(infos["status"]) == ["running"] * n and infos["_fitness"].all()
    ends, resets = 0, 0
    done = [False] * n
    for _ in range(30):
        actions = vec_actions(vec.np_randoms, shape)
        obs, rewards, terminated, truncated, infos = vec.step(actions)
        for i, env in enumerate(singles):
            if done[i]:  # next_step autoreset: this step restarted environment i
                o, _ = env.reset()
                r, te, tr = 0.0, False, False
                resets += 1
            else:
                o, r, te, tr, info = env.step(actions[i])
                assert infos["fitness"][i] == info["fitness"]
                assert infos["steps"][i] == info["steps"] and infos["status"][i] == info["status"]
            assert np.array_equal(obs[i], o) and rewards[i] == r
            assert terminated[i] == te and truncated[i] == tr
            done[i] = te or tr
            ends += done[i]
    assert ends >= n and resets >= n  # every environment ended and restarted at least once


def test_vec_env_seeds_each_environment():
    vec = plastivox.VoxelVecEnv(short_walker(), num_envs=2, sensors=["time"])
    vec.reset(seed=[5, 7])
    assert vec.np_randoms[0].random() == np.random.default_rng(5).random()
    assert vec.np_randoms[1].random() == np.random.default_rng(7).random()
    vec.reset(seed=3)
    assert vec.np_randoms[1].random() == np.random.default_rng(4).random()


def test_vec_env_refuses_bad_input():
    robot = short_walker()
    for bad in (0, -1, 1.5, True):
        with pytest.raises(ValueError, match=r"^num_envs: expected a whole number >= 1"):
            plastivox.VoxelVecEnv(robot, num_envs=bad)
    with pytest.raises(ValueError, match=r"^threads: expected a whole number >= 0"):
        plastivox.VoxelVecEnv(robot, num_envs=2, threads=-1)
    vec = plastivox.VoxelVecEnv(robot, num_envs=2, sensors=["time"])
    n = vec.single_action_space.shape[0]
    with pytest.raises(RuntimeError, match="call reset"):
        vec.step(np.zeros((2, n)))
    vec.reset()
    with pytest.raises(ValueError, match=rf"^actions: expected shape \(2, {n}\), one row per "
                                         rf"environment and one value per voxel, got \(3, {n}\)$"):
        vec.step(np.zeros((3, n)))
    with pytest.raises(ValueError, match=rf"^actions: expected shape \(2, {n}\).* got \({n},\)$"):
        vec.step(np.zeros(n))
    with pytest.raises(TypeError, match=r"^actions: expected a float array"):
        vec.step(np.zeros((2, n), dtype=int))
    bad = np.zeros((2, n))
    bad[1, 4] = 1.5
    with pytest.raises(ValueError, match=r"^actions\[1\]: every value must be in \[-1, 1\]; "
                                         r"actions\[1\]\[4\] is 1.5"):
        vec.step(bad)
    # Nothing moved: a good step after the refusals is the first step.
    _, _, _, _, infos = vec.step(np.zeros((2, n)))
    assert list(infos["steps"]) == [1, 1]


def test_vec_env_refuses_a_second_thread_while_it_steps():
    # A step runs without the GIL; another thread's step or read of the same VoxelVecEnv is
    # refused with one line instead of racing, and the stepping thread's life is untouched.
    import threading
    robot = short_walker(0.4)
    vec = plastivox.VoxelVecEnv(robot, num_envs=2, sensors=["time"], every=600, threads=1)
    n = vec.single_action_space.shape[0]
    vec.reset()
    started, results = threading.Event(), []

    def work():
        started.set()
        results.append(vec.step(np.zeros((2, n))))

    worker = threading.Thread(target=work)
    worker.start()
    started.wait()
    message = "VoxelVecEnv: in use by another thread; give each thread its own VoxelVecEnv"
    reads, steps = 0, 0
    while worker.is_alive():
        try:
            vec.state_hash(0)
            continue
        except RuntimeError as e:
            assert str(e) == message
            reads += 1
        try:  # the worker is inside its step (unless it has just left it)
            vec.step(np.zeros((2, n)))
        except RuntimeError as e:
            assert str(e) == message
            steps += 1
    worker.join()
    assert reads > 0 and steps > 0, "no call ever met the step"
    alone = plastivox.VoxelEnv(robot, sensors=["time"], every=600)
    alone.reset()
    obs, *_ = alone.step(np.zeros(n))
    assert len(results) == 1 and np.array_equal(results[0][0][0], obs)
