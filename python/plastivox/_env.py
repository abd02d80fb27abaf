"""plastivox.VoxelEnv: one robot's life as an environment with the Gymnasium API; and
plastivox.VoxelVecEnv, N of them stepped together on threads (Gymnasium's vector API).

    env = plastivox.VoxelEnv(plastivox.demo_walker(), task="walk")
    obs, info = env.reset(seed=0)
    while True:
        obs, reward, terminated, truncated, info = env.step(env.action_space.sample())
        if terminated or truncated:
            break

It needs no gymnasium: when gymnasium is importable the class is a gymnasium.Env, its spaces
are gymnasium.spaces.Box and it is registered as "plastivox/Voxel-v0"; otherwise the spaces
are the Box below, with the same shape, dtype, low, high, sample(), contains() and seed().
docs/python.md, "Reinforcement learning", says what the observation, action and reward are.
"""

import numpy as _np

from . import _core

try:  # optional: only to be a gymnasium.Env with gymnasium's spaces
    import gymnasium as _gym
except ImportError:
    _gym = None

ENV_ID = "plastivox/Voxel-v0"

# The range of each sensor's values where it has one exactly (docs/control.md, "Sensors"); the
# others are unbounded (`up` too: a unit vector's components may round past 1).
_SENSOR_RANGE = {"touch": (0.0, 1.0), "phase": (0.0, 1.0), "time": (0.0, _np.inf)}


class Box:
    """A box of float arrays, as gymnasium.spaces.Box describes one: shape, dtype, low and
    high (arrays of that shape; +-inf where unbounded), sample() (uniform where bounded,
    normal where unbounded on both sides, exponential on a half-open side) and contains()."""

    def __init__(self, low, high, shape, dtype=_np.float64):
        self.shape = tuple(shape)
        self.dtype = _np.dtype(dtype)
        self.low = _np.broadcast_to(_np.asarray(low, dtype=self.dtype), self.shape).copy()
        self.high = _np.broadcast_to(_np.asarray(high, dtype=self.dtype), self.shape).copy()
        self._rng = _np.random.default_rng()

    def seed(self, seed=None):
        """Seeds sample(); returns [seed]."""
        self._rng = _np.random.default_rng(seed)
        return [seed]

    def sample(self):
        lo_ok, hi_ok = _np.isfinite(self.low), _np.isfinite(self.high)
        out = self._rng.normal(size=self.shape)
        both = lo_ok & hi_ok
        out[both] = self._rng.uniform(self.low[both], self.high[both])
        only_lo, only_hi = lo_ok & ~hi_ok, hi_ok & ~lo_ok
        out[only_lo] = self.low[only_lo] + self._rng.exponential(size=int(only_lo.sum()))
        out[only_hi] = self.high[only_hi] - self._rng.exponential(size=int(only_hi.sum()))
        return out.astype(self.dtype)

    def contains(self, x):
        a = _np.asarray(x)
        return (a.shape == self.shape and a.dtype.kind == "f" and
                bool(_np.all((a >= self.low) & (a <= self.high))))

    __contains__ = contains

    def __repr__(self):
        return f"Box({self.low.min()}, {self.high.max()}, {self.shape}, {self.dtype})"


def _box(low, high, shape):
    if _gym is not None:
        return _gym.spaces.Box(low=_np.broadcast_to(_np.asarray(low, dtype=_np.float64), shape),
                               high=_np.broadcast_to(_np.asarray(high, dtype=_np.float64), shape),
                               shape=shape, dtype=_np.float64)
    return Box(low, high, shape)


class VoxelEnv(_gym.Env if _gym is not None else object):
    """One robot's life, stepped by actions (the Gymnasium API; docs/python.md).

    robot: a Robot or a file path (as simulate takes; default the demo walker); task: any of
    simulate's, "walk", "jump", "turn", "rough", "climb", "slope", "obstacles", "carry" or
    "push" (overrides physics["task"], as simulate's task= does); physics, treatment: as
    simulate takes them; sensors: the names of the sensors observed (default all, in
    Simulator.sensor_fields order); every: engine steps each action is held for (>= 1);
    render_mode: None or "rgb_array" (render() returns the present state as an (h, w, 3)
    uint8 array of render_size = (width, height) pixels).

    Observation: the observed sensors of the step about to be taken, one after another, each
    flat in voxel order (float64; with a free object, carry and push, its voxels follow the
    robot's). Action: each of the robot's voxels' actuation signal, shape (robot voxels,),
    float64 (float32 is taken) in [-1, 1] (a free object has none). Reward: the change of
    the task's fitness over the step (fitness so far: the task's score as though the life
    ended there), so an episode's rewards sum to the life's fitness. An episode is one life:
    truncated when time passes physics.duration, terminated when the life goes unstable or
    sinks (under physics.sinking_invalid, the moment it is certain to be graded sunk); the
    last reward then brings the sum to 0, the fitness simulate() gives such a life. The
    physics has no randomness: every reset starts the same life; reset(seed=...) seeds
    np_random."""

    metadata = {"render_modes": ["rgb_array"]}

    def __init__(self, robot=None, task=None, physics=None, treatment=None, sensors=None,
                 every=1, render_mode=None, render_size=(640, 480)):
        from . import (_as_robot, _check_task, _check_treatment, _physics, demo_walker)
        if isinstance(every, bool) or not isinstance(every, (int, _np.integer)) or every < 1:
            raise ValueError(f"every: expected a number of steps >= 1, got {every!r}")
        if render_mode is not None and render_mode not in self.metadata["render_modes"]:
            raise ValueError(f"render_mode: expected None or \"rgb_array\" (an (h, w, 3) uint8 "
                             f"array of the present state), got {render_mode!r}")
        try:
            width, height = (int(v) for v in render_size)
        except (TypeError, ValueError):
            raise TypeError(f"render_size: expected (width, height) in pixels, got "
                            f"{render_size!r}") from None
        if not (1 <= width <= 16384 and 1 <= height <= 16384):
            raise ValueError(f"render_size: each side must be 1..16384 pixels, got {render_size!r}")
        fields = {f["name"]: f for f in _core.Simulator.sensor_fields()}
        if sensors is None:
            sensors = list(fields)
        elif isinstance(sensors, str):
            sensors = [sensors]
        else:
            sensors = list(sensors)
        robot = demo_walker() if robot is None else _as_robot(robot)
        self._episode = _core.Episode(robot._core, _physics(physics), _check_treatment(treatment),
                                      _check_task(task), sensors, int(every))
        self.robot = robot
        self.sensors = tuple(sensors)
        self.every = int(every)
        n = self._episode.voxels
        low, high = [], []
        for name in sensors:
            f = fields[name]
            size = (n if f["shape"].startswith("n") else 1) * (3 if "3" in f["shape"] else 1)
            lo, hi = _SENSOR_RANGE.get(name, (-_np.inf, _np.inf))
            low += [lo] * size
            high += [hi] * size
        self.observation_space = _box(_np.array(low), _np.array(high), (self._episode.obs_size,))
        self.action_space = _box(-1.0, 1.0, (self._episode.robot_voxels,))
        self.render_mode = render_mode
        self.render_size = (width, height)
        self._fitness = 0.0
        self._started = False

    @property
    def task(self):
        return self._episode.task

    @property
    def np_random(self):
        """The environment's random generator (numpy Generator), seeded by reset(seed=...)."""
        if getattr(self, "_np_random", None) is None:
            self._np_random = _np.random.default_rng()
        return self._np_random

    @np_random.setter
    def np_random(self, value):
        self._np_random = value

    def reset(self, *, seed=None, options=None):
        """Back to t = 0: (observation, info). seed (an int) seeds np_random; options is
        accepted and unused."""
        if seed is not None:
            self._np_random = _np.random.default_rng(seed)
        obs = self._episode.reset()
        self._fitness = 0.0
        self._started = True
        return obs, self._info("running")

    def step(self, action):
        """Holds `action` for `every` engine steps: (observation, reward, terminated,
        truncated, info). A wrong action raises TypeError or ValueError naming `action`."""
        if not self._started:
            raise RuntimeError("step: call reset() first")
        obs, fitness, status = self._episode.step(action)
        reward = fitness - self._fitness
        self._fitness = fitness
        terminated = status in ("unstable", "sank")
        truncated = status == "finished"
        return obs, reward, terminated, truncated, self._info(status)

    def _info(self, status):
        e = self._episode
        info = {"time": e.time, "steps": e.steps, "fitness": e.fitness, "status": status}
        if status != "running":
            info["state_hash"] = e.state_hash
            if e.failure:
                info["failure"] = e.failure
        return info

    def render(self):
        """render_mode "rgb_array": the present state (after the last reset or step) as an
        (h, w, 3) uint8 array of render_size, drawn off-screen as plastivox.render draws a
        frame, the camera following the body; render_mode None: None."""
        if self.render_mode is None:
            return None
        if not self._started:
            raise RuntimeError("render: call reset() first")
        return self._episode.render(*self.render_size)

    def close(self):
        pass

    # What a controller that replays the built-in sine needs (docs/control.md).
    act_frequency = property(lambda self: self._episode.act_frequency,
                             doc="the sine's frequency, Hz (physics.act_frequency)")
    voxel_phase = property(lambda self: self._episode.voxel_phase,
                           doc="each of the robot's voxels' sine phase, cycles (voxel order; "
                               "the action's shape)")
    duration = property(lambda self: self._episode.duration, doc="length of the life, s")

    def __repr__(self):
        return (f"VoxelEnv({self.robot.name!r}, task={self.task!r}, "
                f"voxels={self._episode.robot_voxels}, "
                f"obs={self._episode.obs_size}, every={self.every})")


# The vector API's names (gymnasium.vector.AutoresetMode); the one mode implemented.
AUTORESET_MODE = "next_step"


class VoxelVecEnv:
    """num_envs lives of one robot stepped together (Gymnasium's vector API; docs/python.md).

    Arguments as VoxelEnv takes them, plus num_envs (>= 1) and threads (the C++ threads a
    step uses; 0: all cores, 1: serially). Each environment is a VoxelEnv's life: reset() and
    step(actions) return arrays stacked over the environments (observations (N, obs),
    rewards, terminated and truncated (N,)) and infos, a dict of (N,) arrays ("time",
    "steps", "fitness", "status"), each with its "_name" mask as gymnasium's vector envs give.
    One step is one call into C++ that steps every environment on threads with the GIL
    released; environment i's observations, rewards and ends are those of a VoxelEnv stepped
    alone with the same actions, bit for bit, on any number of threads.

    Autoreset "next_step" (gymnasium 1.x's default): the step after an environment's episode
    ends resets it, ignores its action and returns its first observation with reward 0 and
    terminated = truncated = False. reset(seed=s) seeds environment i's np_random with s + i
    (a list seeds each); np_randoms holds them."""

    metadata = {"autoreset_mode": AUTORESET_MODE}

    def __init__(self, robot=None, num_envs=1, task=None, physics=None, treatment=None,
                 sensors=None, every=1, threads=0):
        from . import _as_robot, _check_task, _check_treatment, _physics, demo_walker
        for name, value, least in (("num_envs", num_envs, 1), ("threads", threads, 0)):
            if isinstance(value, bool) or not isinstance(value, (int, _np.integer)) or \
                    value < least:
                raise ValueError(f"{name}: expected a whole number >= {least}, got {value!r}")
        # One VoxelEnv checks the arguments and gives the spaces; the batch shares its model.
        robot = demo_walker() if robot is None else _as_robot(robot)
        self.single_env = VoxelEnv(robot, task=task, physics=physics, treatment=treatment,
                                   sensors=sensors, every=every)
        self._batch = _core.EpisodeBatch(robot._core, _physics(physics),
                                         _check_treatment(treatment), _check_task(task),
                                         list(self.single_env.sensors), int(every),
                                         int(num_envs), int(threads))
        self.num_envs = int(num_envs)
        self.threads = int(threads)
        self.robot = robot
        self.single_observation_space = self.single_env.observation_space
        self.single_action_space = self.single_env.action_space
        n = self.num_envs
        self.observation_space = Box(_np.broadcast_to(self.single_observation_space.low,
                                                      (n,) + self.single_observation_space.shape),
                                     _np.broadcast_to(self.single_observation_space.high,
                                                      (n,) + self.single_observation_space.shape),
                                     (n,) + self.single_observation_space.shape)
        self.action_space = Box(-1.0, 1.0, (n,) + self.single_action_space.shape)
        self.np_randoms = [_np.random.default_rng() for _ in range(n)]
        self._fitness = _np.zeros(n)
        self._done = None  # before the first reset: stepping raises

    def reset(self, *, seed=None, options=None):
        """Every environment back to t = 0: (observations (N, obs), infos). seed: an int
        (environment i gets seed + i), a list of N ints or Nones, or None."""
        if seed is not None:
            seeds = ([int(seed) + i for i in range(self.num_envs)]
                     if not isinstance(seed, (list, tuple)) else list(seed))
            if len(seeds) != self.num_envs:
                raise ValueError(f"seed: expected an int or {self.num_envs} seeds, got "
                                 f"{len(seeds)}")
            for i, s in enumerate(seeds):
                if s is not None:
                    self.np_randoms[i] = _np.random.default_rng(s)
        obs, fitness, ends = self._batch.advance(None, None)
        self._fitness = fitness
        self._done = _np.zeros(self.num_envs, dtype=bool)
        return obs, self._infos(fitness, ends)

    def step(self, actions):
        """Steps every environment with its row of actions ((N, robot voxels) floats in
        [-1, 1]); an environment whose episode ended at the last step is reset instead.
        Returns (observations, rewards, terminated, truncated, infos), each stacked."""
        if self._done is None:
            raise RuntimeError("step: call reset() first")
        restart = self._done
        obs, fitness, ends = self._batch.advance(actions, restart)
        rewards = _np.where(restart, 0.0, fitness - self._fitness)
        self._fitness = fitness
        terminated = (ends == 2) | (ends == 3)
        truncated = ends == 1
        self._done = terminated | truncated
        return obs, rewards, terminated, truncated, self._infos(fitness, ends)

    _STATUS = _np.array(["running", "finished", "unstable", "sank"])

    def _infos(self, fitness, ends):
        b, n = self._batch, self.num_envs
        infos = {"time": _np.array([b.time(i) for i in range(n)]),
                 "steps": _np.array([b.steps(i) for i in range(n)], dtype=_np.int64),
                 "fitness": fitness, "status": self._STATUS[ends]}
        for key in list(infos):
            infos["_" + key] = _np.ones(n, dtype=bool)
        return infos

    def state_hash(self, i):
        """Environment i's present state hash (a VoxelEnv's info["state_hash"] at its end)."""
        return self._batch.state_hash(int(i))

    def close(self):
        pass

    def __repr__(self):
        return (f"VoxelVecEnv({self.robot.name!r}, num_envs={self.num_envs}, "
                f"task={self.single_env.task!r}, threads={self.threads})")


def _register():
    """Registers VoxelEnv with gymnasium when it is importable (gymnasium.make(ENV_ID, ...))."""
    if _gym is None:
        return
    if ENV_ID not in getattr(_gym, "registry", {}):
        _gym.register(id=ENV_ID, entry_point="plastivox:VoxelEnv")


_register()
