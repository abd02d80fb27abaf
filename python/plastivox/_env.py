"""plastivox.VoxelEnv: one robot's life as an environment with the Gymnasium API.

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


def _register():
    """Registers VoxelEnv with gymnasium when it is importable (gymnasium.make(ENV_ID, ...))."""
    if _gym is None:
        return
    if ENV_ID not in getattr(_gym, "registry", {}):
        _gym.register(id=ENV_ID, entry_point="plastivox:VoxelEnv")


_register()
