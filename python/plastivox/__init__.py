"""plastivox from Python: robots, physics, simulation, evolution, results and rendering.

A thin layer over the C++ library (the compiled ``plastivox._core``): numpy arrays in and
out, the GIL released in every long call, bad arguments as ``ValueError``/``TypeError``
naming the argument, bad files as ``plastivox.InputError`` (a ``ValueError``) with the
command line's one-line message. docs/python.md describes every function.

Robots, results, trajectories, results files and physics dicts pickle, so they cross
processes (multiprocessing, concurrent.futures, Dask); a Robot comes back bit for bit.

Lattice arrays are shaped ``(nx, ny, nz)`` and indexed ``[x, y, z]``; the engine stores
sites x fastest, so they are converted in Fortran order.
"""

import atexit as _atexit
import csv as _csv
import json as _json
import math as _math
import os as _os
import queue as _queue
import threading as _threading
import types as _types
import weakref as _weakref

try:
    import numpy as _np
except ImportError as _e:  # a pyenv, conda or bare venv python3 first on PATH (README)
    import sys as _sys
    raise ImportError(f"plastivox needs numpy, which {_sys.executable} lacks: run the python3 "
                      "the module was built for (build/python/python3 in a build tree; CMake's "
                      "configure names it), or install numpy into this one") from _e

from . import _core
from ._core import InputError, PhysicsDef, RenderError

__version__ = _core.__version__
__all__ = [
    "InputError", "RenderError", "PhysicsDef", "Robot", "Result", "Trajectory", "Simulator", "Results",
    "Study", "load_robot", "demo_walker", "physics", "simulate", "simulate_many",
    "read_results", "read_study", "evolve", "Evolver", "default_config", "render", "sin_cycles",
    "VoxelEnv", "VoxelVecEnv", "controller_weight_count", "analysis", "robustness", "gradient",
    "gradient_of",
]

_TREATMENTS = ("none", "stress", "pressure", "strain", "strain_energy", "contact", "kinetic")


# --- argument checks -------------------------------------------------------------------

def _lattice_array(value, name, shape=None, kinds="biuf"):
    """value as a 3-D numpy array; TypeError/ValueError naming `name` otherwise."""
    if isinstance(value, (str, bytes)) or value is None:
        raise TypeError(f"{name}: expected a numpy array shaped (nx, ny, nz), got {type(value).__name__}")
    try:
        a = _np.asarray(value)
    except Exception as e:  # ragged nested lists and the like
        raise ValueError(f"{name}: not an array: {e}") from None
    if a.dtype.kind not in kinds:
        raise TypeError(f"{name}: expected a {'bool or integer' if kinds == 'biu' else 'numeric'} "
                        f"array, got dtype {a.dtype}")
    if a.ndim != 3:
        raise ValueError(f"{name}: expected shape (nx, ny, nz), got shape {a.shape}")
    if 0 in a.shape:
        raise ValueError(f"{name}: the lattice is empty (shape {a.shape})")
    if shape is not None and a.shape != shape:
        raise ValueError(f"{name}: shape {a.shape} disagrees with geometry's shape {shape}")
    return a


def _flat(a, dtype):
    """The engine's site order: x fastest (Fortran order), contiguous, of dtype."""
    return _np.ascontiguousarray(_np.ravel(a, order="F").astype(dtype, copy=False))


def _check_treatment(treatment):
    if treatment is None:
        return None
    if treatment not in _TREATMENTS:
        raise ValueError(f"treatment: expected one of {', '.join(_TREATMENTS)}, got {treatment!r}")
    return treatment


def _physics(physics):
    """A physics argument as the C++ layer takes it: None, a PhysicsDef, or a dict of fields
    (resolved with the robot's own physics there, by the engine's one rule: docs/robot-format.md,
    "Resolving a run's physics")."""
    if physics is None or isinstance(physics, (PhysicsDef, dict)):
        return physics
    raise TypeError(f"physics: expected a PhysicsDef or a dict of its fields (see "
                    f"plastivox.physics()), got {type(physics).__name__}")


def _check_task(task):
    """A task argument as the C++ layer takes it: None or a task's name (which wins over the
    physics' task there, keeping its parameters when it names the same task)."""
    if task is not None and not isinstance(task, str):
        raise TypeError("task: expected a task name (walk, jump, turn, rough, climb, slope, "
                        f"obstacles, carry, push), got {type(task).__name__}")
    return task


def _as_robot(source, name="robot"):
    """source as a Robot: a Robot itself, or a file path read as render reads it (a robot
    file, a results file's last champion, a recorded life's robot; each with its physics)."""
    if isinstance(source, Robot):
        return source
    if isinstance(source, (str, _os.PathLike)):
        return Robot(_core.load_source(_os.fspath(source)))
    raise TypeError(f"{name}: expected a plastivox.Robot or a .json/.vxa/.h5 file path, "
                    f"got {type(source).__name__}")


# --- robots ----------------------------------------------------------------------------

class Robot:
    """A robot (lattice arrays) and the physics it came with.

    Build one with ``Robot.from_arrays`` or ``load_robot``; it is immutable. Properties return
    fresh numpy arrays shaped ``(nx, ny, nz)``; ``controller`` is the controller it runs and
    ``with_controller`` a copy running another (weights from Python). Two robots are equal
    when name, lattice, arrays, controller, boundary conditions and physics are equal bit for
    bit (the file they were read from does not count); equal robots hash alike, in every
    process. A pickle holds all of it, so an unpickled robot simulates to the same bits.
    """

    def __init__(self, core):
        if not isinstance(core, _core.Robot):
            raise TypeError("use Robot.from_arrays(...) or plastivox.load_robot(path)")
        self._core = core

    @classmethod
    def from_arrays(cls, geometry, stiffness, phase, dev_rate=None, treatment="none",
                    voxel_size=0.01, name="robot", controller=None):
        """A robot from (nx, ny, nz) arrays: geometry bool/int (non-zero = voxel), stiffness
        E0 in Pa (> 0 where a voxel is), phase in cycles, dev_rate alpha in 1/s (default 0).
        Simulated under the default preset with `treatment` unless physics is given later.
        controller: None (the sine) or a dict of with_controller's arguments (kind, hidden,
        every, weights), as the controller property gives it."""
        if controller is not None:
            if not isinstance(controller, dict):
                raise TypeError("controller: expected a dict with kind, hidden, every and "
                                f"weights (see Robot.controller), got {type(controller).__name__}")
            unknown = sorted(set(controller) - {"kind", "hidden", "every", "weights"})
            if unknown:
                raise ValueError(f"controller: unknown field {unknown[0]!r} (fields: kind, "
                                 "hidden, every, weights)")
            if "kind" not in controller:
                raise ValueError("controller: kind is missing (sine, distributed or central)")
        g = _lattice_array(geometry, "geometry", kinds="biu")
        try:  # before anything is converted: a 1000^3 broadcast array costs nothing until copied
            _core.check_lattice_size(*(min(n, 2**31 - 1) for n in g.shape))
        except ValueError as e:
            raise ValueError(f"geometry: {str(e).removeprefix('robot.size: ')}") from None
        e = _lattice_array(stiffness, "stiffness", g.shape)
        p = _lattice_array(phase, "phase", g.shape)
        d = _np.zeros(g.shape) if dev_rate is None else _lattice_array(dev_rate, "dev_rate", g.shape)
        present = g != 0
        for label, a in (("stiffness", e), ("phase", p), ("dev_rate", d)):
            bad = ~_np.isfinite(a.astype(_np.float64)) & present
            if bad.any():
                x, y, z = _np.argwhere(bad)[0]
                raise ValueError(f"{label}: not finite at voxel [{x}, {y}, {z}]")
        if not present.any():
            raise ValueError("geometry: no voxel is present")
        if not (e[present] > 0).all():
            x, y, z = _np.argwhere(present & ~(e > 0))[0]
            raise ValueError(f"stiffness: must be > 0 where a voxel is; not at [{x}, {y}, {z}]")
        if not isinstance(voxel_size, (int, float)) or not (0 < voxel_size < _math.inf):
            raise ValueError(f"voxel_size: must be a positive number of metres, got {voxel_size!r}")
        _check_treatment(treatment)
        nx, ny, nz = g.shape
        core = _core.from_flat(nx, ny, nz, _flat(present, _np.uint8), _flat(e, _np.float64),
                               _flat(d, _np.float64), _flat(p, _np.float64), float(voxel_size),
                               treatment, str(name))
        robot = cls(core)
        return robot if controller is None else robot.with_controller(**controller)

    def _lattice(self, flat, dtype=None):
        a = _np.reshape(flat, self.shape, order="F")
        return a if dtype is None else a.astype(dtype)

    shape = property(lambda self: self._core.shape, doc="(nx, ny, nz) lattice sites")
    voxel_size = property(lambda self: self._core.voxel_size, doc="voxel edge length, m")
    name = property(lambda self: self._core.name)
    source = property(lambda self: self._core.source, doc="the file read, or the name")
    voxel_count = property(lambda self: self._core.voxel_count)
    treatment = property(lambda self: self._core.treatment)
    geometry = property(lambda self: self._lattice(self._core.present_flat, bool),
                        doc="(nx, ny, nz) bool: where a voxel is")
    stiffness = property(lambda self: self._lattice(self._core.stiffness_flat),
                         doc="(nx, ny, nz) congenital Young's modulus E0, Pa (0 where empty)")
    phase = property(lambda self: self._lattice(self._core.phase_flat),
                     doc="(nx, ny, nz) actuation phase, cycles")
    dev_rate = property(lambda self: self._lattice(self._core.dev_rate_flat),
                        doc="(nx, ny, nz) development rate alpha, 1/s")

    @property
    def act_amplitude(self):
        """(nx, ny, nz) linear actuation amplitude of each voxel, or None: a voxcraft-sim robot
        carries its own (TempAmplitude x its material's CTE, whatever its stiffness); every
        other robot actuates by physics act_amplitude x xi(E) (docs/method.md §4)."""
        flat = self._core.act_amplitude_flat
        return self._lattice(flat) if len(flat) else None

    @property
    def act_scale(self):
        """(nx, ny, nz) actuation scale of each voxel in [0, 1] (its amplitude, by either rule,
        times this; 0: passive tissue), or None: a robot file without act_scale, every voxel
        at 1 (docs/robot-format.md)."""
        flat = self._core.act_scale_flat
        return self._lattice(flat) if len(flat) else None

    @property
    def physics(self):
        """The robot's own physics, a PhysicsDef (a copy: what simulate uses when given none)."""
        return self._core.physics

    @property
    def controller(self):
        """The controller the robot runs (docs/control.md): a dict of kind ("sine",
        "distributed" or "central"), hidden (units), every (steps between calls) and weights
        (a float64 array, a copy; empty for the sine). with_controller(**robot.controller)
        gives the robot back."""
        return self._core.controller

    def with_controller(self, kind, hidden=0, every=1, weights=None):
        """A copy running another controller: kind "sine", "distributed" or "central" with
        `hidden` units (distributed 0-64, central 1-64; 0 for the sine), acting every `every`
        steps (>= 1), with `weights` (a list or array of
        controller_weight_count(kind, hidden) finite numbers, in docs/control.md's order; none
        for the sine). Wrong arguments raise TypeError or ValueError naming the argument."""
        if not isinstance(kind, str):
            raise TypeError(f"kind: expected sine, distributed or central, got {type(kind).__name__}")
        hidden = _count_argument(hidden, "hidden", 0, "hidden units >= 0")
        every = _count_argument(every, "every", 1, "steps >= 1")
        if weights is None:
            weights = []
        if isinstance(weights, (str, bytes, dict)):
            raise TypeError(f"weights: expected a list or array of numbers, got {type(weights).__name__}")
        try:
            w = _np.asarray(weights)
        except Exception as e:  # ragged nested lists and the like
            raise ValueError(f"weights: not an array of numbers: {e}") from None
        if w.size and w.dtype.kind not in "iuf":
            raise TypeError(f"weights: expected numbers, got dtype {w.dtype}")
        if w.ndim != 1:
            raise ValueError(f"weights: expected a flat list of numbers, got shape {w.shape}")
        return Robot(self._core.with_controller(kind, hidden, every,
                                                _np.ascontiguousarray(w, dtype=_np.float64)))

    def with_physics(self, physics=None, treatment=None, task=None):
        """A copy simulated under `physics` (a PhysicsDef, or a dict of fields applied on top),
        `treatment` and `task`, resolved as simulate resolves them."""
        return Robot(self._core.with_physics(_physics(physics), _check_treatment(treatment),
                                             _check_task(task)))

    def save(self, path):
        """Writes the robot and its physics as .json (plastivox-robot) or .vxa, atomically."""
        self._core.save(_os.fspath(path))

    def __eq__(self, other):
        if not isinstance(other, Robot):
            return NotImplemented
        return self._core == other._core

    def __hash__(self):
        return hash(self._core)

    def __repr__(self):
        c = self.controller
        network = ("" if c["kind"] == "sine" else
                   f", controller={c['kind']!r}, hidden={c['hidden']}, every={c['every']}")
        return (f"Robot({self.name!r}, shape={self.shape}, voxels={self.voxel_count}, "
                f"voxel_size={self.voxel_size}, treatment={self.treatment!r}{network})")


def _count_argument(value, name, least, what):
    """value as an int in [least, 2^30]; TypeError/ValueError naming `name` otherwise."""
    if isinstance(value, bool) or not isinstance(value, (int, _np.integer)):
        raise TypeError(f"{name}: expected a whole number of {what}, got {type(value).__name__}")
    if not least <= value <= 2**30:
        raise ValueError(f"{name}: expected a number of {what}, got {value}")
    return int(value)


def controller_weight_count(kind, hidden=0):
    """How many weights a controller of `kind` ("sine", "distributed", "central") with
    `hidden` units takes (docs/control.md): 0 for the sine, 95 for distributed with 4, 41 for
    central with 4. What Robot.with_controller expects."""
    if not isinstance(kind, str):
        raise TypeError(f"kind: expected sine, distributed or central, got {type(kind).__name__}")
    return _core.controller_weight_count(kind, _count_argument(hidden, "hidden", 0,
                                                               "hidden units >= 0"))


def load_robot(path, vxd=None):
    """Reads a robot file: .json (plastivox-robot) or .vxa (the authors' format). With vxd,
    path is voxcraft-sim's base.vxa and vxd its robot .vxd, merged as voxcraft-sim merges them
    (docs/vxa.md, "voxcraft-sim")."""
    return Robot(_core.load_robot(_os.fspath(path), "" if vxd is None else _os.fspath(vxd)))


def demo_walker():
    """The built-in demo walker under the stress treatment (`plastivox simulate`'s robot)."""
    return Robot(_core.demo_walker())


def physics(preset="gecco2018-code", **overrides):
    """Every physics field of `preset` with `overrides` applied: a PhysicsDef (also read as a
    mapping: physics()["duration"], dict(physics()), to_dict()). Without a "treatment" (a
    "task") among the overrides its treatment (task) is None: passed to simulate, Simulator or
    with_physics it keeps the robot's, as a preset and a dict without one do
    (docs/robot-format.md, "Resolving a run's physics"). Unknown fields and bad
    values raise plastivox.InputError / ValueError naming the field."""
    return PhysicsDef(preset, **overrides)


# --- simulation ------------------------------------------------------------------------

class Trajectory:
    """A recorded life: times[T] (s), positions[T, n, 3] (m, world axes),
    orientations[T, n, 4] (unit quaternions w, x, y, z), sizes[T, n] (m),
    stiffness[T, n] (Pa), stimulus[T, n] (the treatment's stimulus, Pa): the engine's frame
    channels (kFrameFields), as a recorded life file holds them.

    Recorded with record_control=True it also carries the control channels
    (kControlFrameFields; else they are None): actuation[T, n] (the signal behind each
    frame's sizes, in [-1, 1]) and the sensors a controller reads at each frame
    (docs/control.md): touch, floor_force, strain, stress, pressure [T, n], velocity and
    up [T, n, 3]."""

    _FIELDS = ("times", "positions", "orientations", "sizes", "stiffness", "stimulus")
    CONTROL_FIELDS = ("actuation", "touch", "floor_force", "strain", "stress", "pressure",
                      "velocity", "up")

    def __init__(self, arrays):
        for name in self._FIELDS:
            setattr(self, name, arrays[name])
        for name in self.CONTROL_FIELDS:
            setattr(self, name, arrays.get(name))

    def __len__(self):
        return len(self.times)

    def __eq__(self, other):
        if not isinstance(other, Trajectory):
            return NotImplemented
        return all(_np.array_equal(getattr(self, k), getattr(other, k), equal_nan=True)
                   for k in self._FIELDS) and \
            all((getattr(self, k) is None) == (getattr(other, k) is None) and
                (getattr(self, k) is None or
                 _np.array_equal(getattr(self, k), getattr(other, k), equal_nan=True))
                for k in self.CONTROL_FIELDS)

    def __repr__(self):
        return (f"Trajectory({len(self)} frames, {self.positions.shape[1]} voxels, "
                f"t = {self.times[0]:g}..{self.times[-1]:g} s)")


class Result:
    """One simulated life: every key of `plastivox simulate --json` as an attribute (and
    in to_dict()), the fields of the engine's summary (sim_summary_fields); `status` is
    "finished" or "unstable" (then `failure` says why, else it is ""); `success` whether the
    life met its task's criterion (docs/tasks.md, "Success"); `trajectory` is a
    Trajectory when recorded (record_fps > 0), else None."""

    def __init__(self, summary, trajectory, robot):
        # summary: the fields as the C++ module hands them over (final_stiffness an array).
        self._keys = tuple(summary)
        self.failure = ""
        for key, value in summary.items():
            setattr(self, key, value)
        self.trajectory = None if trajectory is None else Trajectory(trajectory)
        self.robot = robot

    def to_dict(self):
        """The summary as `simulate --json` prints it (final_stiffness as a list)."""
        d = {key: getattr(self, key) for key in self._keys}
        d["final_stiffness"] = d["final_stiffness"].tolist()
        return d

    def keys(self):
        return self._keys

    def __eq__(self, other):
        """Equal summaries (wall time included), trajectories and robots."""
        if not isinstance(other, Result):
            return NotImplemented
        return (self._keys == other._keys
                and all(_np.array_equal(getattr(self, k), getattr(other, k), equal_nan=True)
                        if k == "final_stiffness" else getattr(self, k) == getattr(other, k)
                        for k in self._keys)
                and self.trajectory == other.trajectory and self.robot == other.robot)

    def __repr__(self):
        return (f"Result(status={self.status!r}, fitness={self.fitness!r}, "
                f"success={self.success!r}, voxels={self.voxels}, steps={self.steps})")


def _record_fps(record_fps):
    if isinstance(record_fps, bool) or not isinstance(record_fps, (int, float)) or \
            not (0 <= record_fps <= 1e6):
        raise ValueError(f"record_fps: expected frames per simulated second in [0, 1e6], got {record_fps!r}")
    return float(record_fps)


def simulate(robot, physics=None, treatment=None, record_fps=0, task=None, record_control=False):
    """Simulates one whole life (GIL released) and returns a Result.
    robot: a Robot or a file path, as render takes (.json, .vxa, or .h5: a results file's
    last champion, a recorded life's robot). physics: a dict of fields applied on top of the
    robot's own physics; treatment (overrides both): "none", "stress", "pressure",
    "strain", "strain_energy", "contact" or "kinetic"; record_fps > 0 records a
    Trajectory; task (overrides physics["task"]): what fitness measures, "walk" (the
    default), "jump", "turn", "rough", "climb", "slope", "obstacles", "carry" or "push"
    (docs/tasks.md; a task's parameters go in physics["task"] = {"name": ..., ...});
    record_control: the Trajectory also carries the actuation signal and the sensors (needs
    record_fps > 0; the life's bits are unchanged)."""
    robot = _as_robot(robot)
    summary, traj, cxx_seconds = _core.simulate(robot._core, _physics(physics),
                                                _check_treatment(treatment), _check_task(task),
                                                _record_fps(record_fps), bool(record_control))
    if physics is not None or treatment is not None or task is not None:
        robot = robot.with_physics(physics, treatment, task)  # what render(result) shows
    result = Result(summary, traj, robot)
    result._cxx_seconds = cxx_seconds  # the C++ part of this call (bench/python_bench.py)
    return result


def simulate_many(robots, physics=None, threads=0, treatment=None, record_fps=0, task=None,
                  record_control=False):
    """Simulates every robot (Robots or file paths, as simulate takes) on C++ threads
    (0: all cores), results in input order, each bit-identical to simulate() of that robot
    alone; physics, treatment, record_fps, task and record_control as simulate takes them."""
    if isinstance(robots, (str, _os.PathLike, Robot)):
        raise TypeError(f"robots: expected a list of robots or paths, got one {type(robots).__name__}")
    robots = [_as_robot(r, f"robots[{i}]") for i, r in enumerate(robots)]
    cores = [r._core for r in robots]
    if isinstance(threads, bool) or not isinstance(threads, int) or threads < 0:
        raise ValueError(f"threads: expected an integer >= 0 (0: all cores), got {threads!r}")
    lives = _core.simulate_many(cores, _physics(physics), _check_treatment(treatment),
                                _check_task(task), _record_fps(record_fps), bool(record_control),
                                threads)
    return [Result(s, t, r) for (s, t), r in zip(lives, robots)]


def gradient(robot, wrt=("stiffness", "phase"), physics=None, treatment=None, threads=0):
    """The fitness of the robot's life and its derivative with respect to each name in wrt
    (docs/gradients.md), by reverse accumulation through the engine's own discrete life.
    Returns (fitness, grads): fitness is simulate()'s, bit for bit; grads maps each name to
    numpy arrays shaped like the Robot's own ((nx, ny, nz), 0 where no voxel is): "stiffness"
    (per Pa of congenital stiffness), "phase" (per cycle), "dev_rate" (per 1/s),
    "act_amplitude" (per unit of the robot's own amplitude, Robot.act_amplitude; ValueError for
    a robot without them), "act_scale" (per unit of the voxel's actuation scale,
    Robot.act_scale; for a robot without one, the derivative at 1, every voxel's scale); to a
    float, "amplitude" (per unit of physics act_amplitude; 0 for a
    robot with its own amplitudes, which do not read it); or "controller": a flat array shaped
    like robot.controller["weights"], the derivative with respect to each weight of a neural
    controller (biases included, docs/control.md's order); "initial_position",
    "initial_velocity" and "initial_angular_velocity": (robot_voxels, 3) arrays in voxel order,
    per m, per m/s and per rad/s (world axes) of each voxel's starting centre, velocity and
    spin; "initial_orientation": (robot_voxels, 4), per unit of each component of the voxel's
    starting quaternion (x, y, z, w), projected onto the unit quaternions' tangent space at the
    start (w's column is 0; x, y, z are twice the derivative per rad of a small turn about the
    world's x, y, z). An unknown name is a ValueError. robot, physics and treatment as simulate
    takes them.
    The fitness is the physics' task's, any task, with its environment and free objects, under
    either bond model.
    threads: for the backward pass (0: all cores; it uses at most 2), the same bits on any
    number."""
    robot = _as_robot(robot)
    if isinstance(wrt, str):
        wrt = (wrt,)
    names = [str(w) for w in wrt]
    if isinstance(threads, bool) or not isinstance(threads, int) or threads < 0:
        raise ValueError(f"threads: expected an integer >= 0 (0: all cores), got {threads!r}")
    fitness, flat = _core.gradient(robot._core, _physics(physics), _check_treatment(treatment),
                                   names, threads)
    return fitness, _shaped_gradients(robot, flat)


def _shaped_gradients(robot, flat):
    """The derivatives per site shaped like the robot's arrays; the others as they come."""
    per_site = ("stiffness", "phase", "dev_rate", "act_amplitude", "act_scale")
    return {k: (_np.reshape(v, robot.shape, order="F") if k in per_site else v)
            for k, v in flat.items()}


def gradient_of(robot, loss, steps=None, fields=("pos",), wrt=("stiffness", "phase"),
                physics=None, treatment=None):
    """The backward pass for a loss of your own over the states the robot's life passes through
    (docs/python.md, "Gradients of your own loss"). The life runs once with the states' rows
    `fields` (names of Simulator.state_fields with float values: "pos", "orient", "lin_mom",
    "size", "stiffness", "time", "com_settled", ...) recorded at `steps` (state indices: 0 the
    initial state, k the state after k steps, negative from the end, -1 the last; None: every
    state). Then loss(states) is called once: states maps each field to a float64 array
    (len(steps), *shape of Simulator.state[field]) and "steps" to the indices recorded, in
    increasing order; it returns (value, derivatives): the loss's value and a dict mapping any
    of the fields to d value / d states[field], shaped alike (a field left out: 0). Returns
    (value, grads), grads as gradient() gives them for each name in wrt (the initial state's
    among them: "initial_position", "initial_velocity", "initial_orientation",
    "initial_angular_velocity"). The life is simulated once, as the gradient's own forward pass
    (the states counted from the end are kept from the last ones as it runs); a step outside
    the life's states is a ValueError once it is over. robot, physics and treatment as simulate
    takes them."""
    robot = _as_robot(robot)
    if not callable(loss):
        raise TypeError(f"loss: expected a function of the recorded states, got {type(loss).__name__}")
    if isinstance(wrt, str):
        wrt = (wrt,)
    if isinstance(fields, str):
        fields = (fields,)
    if steps is not None:
        if isinstance(steps, (int, _np.integer)):
            steps = (steps,)
        steps = [int(k) for k in steps]
    value, flat = _core.gradient_of(robot._core, _physics(physics), _check_treatment(treatment),
                                    loss, steps, [str(f) for f in fields], [str(w) for w in wrt])
    return value, _shaped_gradients(robot, flat)


def sin_cycles(u):
    """sin(2 pi u) element by element, as the engine computes it (its own series: the same
    bits on every machine; -0 gives +0), so a Python controller can replay the built-in sine
    exactly."""
    return _core.sin_cycles(_np.asarray(u, dtype=_np.float64))


class Simulator:
    """Step-wise control of one life: step(n) advances up to n steps (GIL released) and stops
    when the life is over; positions (n, 3) m, velocities (n, 3) m/s and stiffness (n,) Pa are
    numpy copies of the current state, in voxel order (increasing lattice site). state is
    every field of the engine's state (state_fields describes them) as read-only numpy views
    of the simulator's own memory, which follow it as it steps. save_state() gives the state
    as bytes, restore_state(snapshot) returns to it (the life then continues bit-identically,
    its score included); result() is the life's Result so far, or final once it is over.
    robot is a Robot or a file path, as simulate takes. A Simulator does not pickle: pickle
    its robot and physics and step a new one. With free objects in the environment
    (docs/environments.md) every per-voxel array holds the robot's robot_voxels rows first,
    then the objects' voxels; the actuation (set_actuation, actuation, voxel_phase) is the
    robot's alone: a free object does not actuate.

    Per-step control (docs/control.md): sensors() gives the sensors of the present step,
    set_actuation(u) sets each voxel's signal in [-1, 1] (held until set again), step()
    advances (or its two halves, step1() then step2(), as the engine's C++ Simulator and
    MuJoCo's mj_step1/mj_step2 split it); reset() returns to t = 0. The robot's controller (the sine unless its file names
    a neural one) drives it until set_actuation is first called (or set_controller(None))."""

    # Each sensor: name, shape ("n", "n x 3", "3", "1"), unit, axes and meaning, in the
    # engine's order (docs/control.md, "Sensors").
    sensor_fields = tuple(_core.Simulator.sensor_fields())

    # Each field of the state: name, shape ("1", "3", "n", "n x 3", "n x 4", "bonds"), unit,
    # axes and meaning, in the engine's order (docs/engine.md, "State").
    state_fields = tuple(_core.Simulator.state_fields())

    # Each number and array of the compiled model: name, shape, unit, axes and meaning, in
    # the engine's order (docs/engine.md, "Model").
    model_fields = tuple(_core.Simulator.model_fields())

    def __init__(self, robot, physics=None, treatment=None):
        robot = _as_robot(robot)
        self._core = _core.Simulator(robot._core, _physics(physics), _check_treatment(treatment))
        self._views = None
        self._model_views = None
        # The robot a Result of this life names, as simulate() makes it.
        self._robot = (robot if physics is None and treatment is None
                       else robot.with_physics(physics, treatment))

    def result(self):
        """The life's Result at this point: so far while it runs (status "running", fitness
        the task's score as though the life ended now), final once it is over; the same
        fields and bits as simulate() gives for the same life (a life simulate() ends at the
        same time, or the whole life), its wall time aside, without a trajectory. A snapshot
        (save_state) holds what the score is made of, so a restored life reports the score of
        the whole life."""
        return Result(self._core.result(), None, self._robot)

    @property
    def state(self):
        """{field name: read-only numpy view} of the live state (no copy; the views keep the
        simulator's memory alive and show its state whenever read). Copy to keep a value."""
        if self._views is None:
            self._views = _types.MappingProxyType(self._core.state_views())
        return self._views

    @property
    def model(self):
        """{field name: read-only numpy view} of the compiled model (model_fields describes
        them: voxel count, size, mass, rest positions, E0, development rates, phases, bonds,
        derived constants, ...); it never changes during a life."""
        if self._model_views is None:
            self._model_views = _types.MappingProxyType(self._core.model_views())
        return self._model_views

    def save_state(self):
        """The state as bytes (every field, in state_fields order)."""
        return self._core.save_state()

    def restore_state(self, snapshot):
        """Returns to a state save_state() gave, of this Simulator or another of the same robot
        and physics; a snapshot of another model's state raises ValueError naming the field."""
        if not isinstance(snapshot, (bytes, bytearray, memoryview)):
            raise TypeError(f"snapshot: expected the bytes save_state() returns, got "
                            f"{type(snapshot).__name__}")
        self._core.restore_state(bytes(snapshot))

    def backward(self, derivatives, steps=None, wrt=("stiffness", "phase")):
        """The backward pass for a loss of your own over the states this Simulator's life has
        passed through (docs/python.md, "A Simulator's backward pass"): derivatives maps
        fields of state_fields with float values ("pos", "orient", "lin_mom", "size", ...) to
        d loss / d state[field] at `steps` (state indices: 0 the initial state, k the state
        after k steps, negative from the present one, -1 it; increasing; None: every state
        0..steps), each an array (len(steps), *state[field].shape). Returns {name: d loss /
        d name} for each name in wrt, as gradient() gives them. The life is recomputed from its
        start (the forward pass and the backward pass of gradient_of, over the steps taken so
        far), which must reach the present state bit for bit: a life steered by
        set_actuation, set_controller or restore_state is refused (ValueError), as is one that
        went unstable; the life is not judged (result() says whether it counts)."""
        if isinstance(wrt, str):
            wrt = (wrt,)
        if not isinstance(derivatives, dict):
            raise TypeError(f"derivatives: expected a dict {{field: array}}, got "
                            f"{type(derivatives).__name__}")
        if steps is not None:
            if isinstance(steps, (int, _np.integer)):
                steps = (steps,)
            steps = [int(k) for k in steps]
        flat = self._core.backward(self._robot._core, derivatives, steps, [str(w) for w in wrt])
        return _shaped_gradients(self._robot, flat)

    def sensors(self, names=None):
        """{name: numpy array} of the sensors of the present step (all, or those named: a name
        or a list of names), as copies: shape (n,) or (n, 3) per voxel, (3,) or () for the
        whole body. Reading runs the first half of the step, step1() (the sensors come from its
        bond strains and contacts), which changes no state; step() or step2() finishes it."""
        if isinstance(names, str):
            names = [names]
        return self._core.sensors(None if names is None else list(names))

    def set_actuation(self, actuation):
        """Sets each of the robot's voxels' actuation signal: a float array of shape
        (robot_voxels,) (n without free objects), voxel order, every value in [-1, 1] (times
        the voxel's amplitude: how far it swells, > 0, or shrinks). Held until set again; the
        built-in controller stops driving the robot. A wrong array raises TypeError or
        ValueError naming `actuation`."""
        self._core.set_actuation(actuation)

    def set_controller(self, controller, every=1):
        """The built-in controller: "sine", the robot's own neural controller by its kind's
        name ("distributed" or "central", with the robot's weights: a robot file names it, or
        Robot.with_controller; docs/control.md), or None (the signal set_actuation sets, held), acting every `every`
        steps (an integer >= 1). A new Simulator runs the robot's own, at its own rate."""
        if isinstance(every, bool) or not isinstance(every, (int, _np.integer)) or every < 1:
            raise ValueError(f"every: expected a number of steps >= 1, got {every!r}")
        self._core.set_controller(controller, int(every))

    def reset(self):
        """Back to the state at t = 0 (as a new Simulator starts), the controller kept and the
        signal 0."""
        self._core.reset()

    actuation = property(lambda self: self._core.actuation(),
                         doc="each of the robot's voxels' present actuation signal, in "
                             "[-1, 1] (a copy, robot_voxels values)")
    controller = property(lambda self: self._core.controller(),
                          doc='the built-in controller: "sine", or None (set_actuation)')
    act_frequency = property(lambda self: self._core.act_frequency(),
                             doc="the sine's frequency, Hz (physics.act_frequency)")
    voxel_phase = property(lambda self: self._core.voxel_phase(),
                           doc="each of the robot's voxels' sine phase, cycles (voxel "
                               "order, robot_voxels values)")

    def step(self, n=1):
        if isinstance(n, bool) or not isinstance(n, (int, _np.integer)) or n < 0:
            raise ValueError(f"n: expected a number of steps >= 0, got {n!r}")
        return self._core.step(int(n))

    def step1(self):
        """The first half of a step, from the present state: every bond's strain, stress and
        forces, the time step, each voxel's forces and the self-contacts (what sensors() reads).
        It changes no state: state, state_hash and save_state() are as before it (a snapshot
        taken now is the state before the step), and calling it again gives the same. Does
        nothing once the life is over."""
        self._core.step1()

    def step2(self):
        """The second half of a step: the controller (when one is set), then integration,
        actuation and development, and time advances by dt; runs step1() first when it has
        not run since the last step. step1() then step2() is step(), bit for bit. Does nothing
        once the life is over."""
        self._core.step2()

    def run(self):
        """Steps to the end of the life; returns the steps taken."""
        taken = 0
        while self.status == "running":
            taken += self._core.step(1 << 20)
        return taken

    time = property(lambda self: self._core.time, doc="simulated time, s")
    steps = property(lambda self: self._core.steps)
    dt = property(lambda self: self._core.dt, doc="current time step, s")
    duration = property(lambda self: self._core.duration, doc="length of the life, s")
    status = property(lambda self: self._core.status, doc='"running", "finished" or "unstable"')
    failure = property(lambda self: self._core.failure, doc="why it went unstable")
    state_hash = property(lambda self: self._core.state_hash,
                          doc="the state's hash (final_state_hash at the end of a life)")
    positions = property(lambda self: self._core.state_copy("pos"))
    velocities = property(lambda self: self._core.state_copy("lin_mom") *
                          (1.0 / self._core.voxel_mass))
    stiffness = property(lambda self: self._core.state_copy("stiffness"))
    robot_voxels = property(lambda self: self._core.robot_voxels,
                            doc="the robot's voxels: the first rows of every per-voxel array; "
                                "the rest are the free objects' (docs/environments.md)")

    def __reduce__(self):
        raise TypeError("a plastivox.Simulator does not pickle (its state lives in C++); "
                        "pickle the Robot and physics and make a new Simulator")

    def __repr__(self):
        return (f"Simulator(status={self.status!r}, time={self.time:g} of {self.duration:g} s, "
                f"steps={self.steps})")


# --- evolution and results -------------------------------------------------------------

class Results:
    """An evolution results file (.h5): run settings, provenance, champions and curves.
    Two are equal when their content digests are. A Results pickles as a reference to its
    file (absolute path and content digest): unpickling reads the file again, so the path
    must be readable there (a cluster's shared file system), and fails if the content
    changed in between."""

    _STATE_FORMAT, _STATE_VERSION = "plastivox.Results", 1

    def __init__(self, core):
        self._core = core
        self.best_fitness, self.mean_fitness = core.fitness_curves()

    def __getstate__(self):
        return {"format": self._STATE_FORMAT, "version": self._STATE_VERSION,
                "path": _os.path.abspath(self.path), "content_digest": self.content_digest}

    def __setstate__(self, state):
        if not isinstance(state, dict) or state.get("format") != self._STATE_FORMAT:
            raise InputError("Results pickle: not a plastivox results state")
        if state.get("version") != self._STATE_VERSION:
            raise InputError(f"Results pickle: state version {state.get('version')!r}, this "
                             f"plastivox reads version {self._STATE_VERSION}")
        path, digest = state.get("path"), state.get("content_digest")
        if not isinstance(path, str) or not isinstance(digest, str):
            raise InputError("Results pickle: path and content_digest must be strings")
        self.__init__(_core.read_results(path))
        if self.content_digest != digest:
            raise InputError(f"{path}: content_digest: the file changed since it was pickled "
                             f"({digest} then, {self.content_digest} now)")

    def __eq__(self, other):
        if not isinstance(other, Results):
            return NotImplemented
        return self.content_digest == other.content_digest

    def __hash__(self):
        return hash(self.content_digest)

    path = property(lambda self: self._core.path)
    treatment = property(lambda self: self._core.treatment)
    seed = property(lambda self: self._core.seed)
    generations_done = property(lambda self: self._core.generations_done)
    generations = property(lambda self: self._core.generations, doc="planned")
    finished = property(lambda self: self._core.finished)
    content_digest = property(lambda self: self._core.content_digest)
    provenance = property(lambda self: self._core.provenance)

    @property
    def config(self):
        """The run's configuration as a dict (canonical JSON, as the file stores it)."""
        return _json.loads(self._core.config_json)

    def champion(self, generation=-1):
        """The champion at the end of `generation` (-1: the last done) as a Robot under the
        run's physics; what `plastivox export` writes."""
        if isinstance(generation, bool) or not isinstance(generation, (int, _np.integer)) or generation < -1:
            raise ValueError(f"generation: expected a generation number or -1, got {generation!r}")
        return Robot(self._core.champion(int(generation)))

    def population(self):
        """The population at the file's last checkpoint: one dict per individual (ascending
        id) with id, parent_id, age, born, fitness, status ("ok", "invalid", "unstable") and
        robot, its genome decoded into a Robot under the run's physics (None for an invalid
        body); a CMA-ES run's also carry genome, the vector (a list of floats) the robot is
        the fixed body with. With champion(), these are every individual whose genome the file
        stores."""
        people = self._core.population()
        for p in people:
            p["robot"] = None if p["robot"] is None else Robot(p["robot"])
        return people

    def archive(self):
        """A MAP-Elites run's archive at the file's last checkpoint (docs/evolution.md,
        "MAP-Elites"): a dict with descriptors (each axis's name, bounds and bins), cells,
        qd_offset, elites (one dict per filled cell, ascending cell: cell, bins, descriptors,
        fitness, id, parent_id, born and robot, its genome's Robot under the run's physics)
        and, per generation, qd_score, coverage and evaluations (individuals made so far)
        as arrays. ValueError for another algorithm's run."""
        a = self._core.archive()
        for e in a["elites"]:
            e["robot"] = Robot(e["robot"])
        return a

    def __repr__(self):
        return (f"Results({self.path!r}, treatment={self.treatment!r}, seed={self.seed}, "
                f"generations_done={self.generations_done}/{self.generations})")


def read_results(path):
    """Reads and checks an evolution results file."""
    return Results(_core.read_results(_os.fspath(path)))


def default_config():
    """The default evolve configuration as a dict."""
    config = _json.loads(_core.default_config())
    config.pop("_comment", None)
    return config


def _config_args(config):
    """(text, path) for the C++ layer: a config dict as JSON text, or a config file path."""
    if isinstance(config, dict):
        # A PhysicsDef in the config (config["physics"] = plastivox.physics(...)) goes as its fields.
        # Its None fields (an unnamed treatment or task, no environment) are left out.
        text = _json.dumps(config, default=lambda o: {k: v for k, v in o.to_dict().items()
                                                      if v is not None}
                           if isinstance(o, PhysicsDef) else _json.JSONEncoder().default(o))
        return text, ""
    if isinstance(config, (str, _os.PathLike)):
        return "", _os.fspath(config)
    raise TypeError(f"config: expected a dict or a file path, got {type(config).__name__}")


def _run_threads(threads):
    """An evolution's threads as the C++ layer takes them: None (the config's "threads", as
    `plastivox evolve` without --threads) is -1; else an integer >= 0 (0: all cores)."""
    if threads is None:
        return -1
    if isinstance(threads, bool) or not isinstance(threads, int) or threads < 0:
        raise ValueError(f"threads: expected None (the config's) or an integer >= 0 (0: all "
                         f"cores), got {threads!r}")
    return threads


def _score(value, index, what):
    """One life's score as the C++ layer takes it: (ok, fitness, failure, sank,
    final_stiffness or None, vertical). A Result is scored as the engine scores it (a life that
    did not finish, or sank while sinking_invalid is on, fails; its vertical_exploit flag is
    kept, so no MAP-Elites archive admits it); a number is the fitness (not finite: the life
    failed), never flagged."""
    if isinstance(value, Result):
        ok = value.status == "finished"
        return (ok, float(value.fitness), "" if ok else (value.failure or value.status),
                value.health == "sank", _np.asarray(value.final_stiffness, dtype=float),
                bool(value.vertical_exploit))
    if isinstance(value, (bool, _np.bool_)) or not isinstance(value, (int, float, _np.integer,
                                                                      _np.floating)):
        raise TypeError(f"{what}[{index}]: expected a number or a plastivox.Result, "
                        f"got {type(value).__name__}")
    fitness = float(value)
    finite = _math.isfinite(fitness)
    return (finite, fitness if finite else 0.0,
            "" if finite else f"the fitness function gave {fitness}", False, None, False)


def _function_name(fn):
    return f"{getattr(fn, '__module__', '?')}.{getattr(fn, '__qualname__', type(fn).__name__)}"


def evolve(config, out, threads=None, on_generation=None, on_message=None, stop_after=None,
           fitness=None, record_fps=0):
    """Runs (or resumes) an evolution into the results file `out`: the same run as
    `plastivox evolve --config ... --out ...`. `config` is a dict or a config file path.
    threads: None (the config's "threads", as the command without --threads) or the
    evaluation threads to use instead (0: all cores).
    on_generation(progress_dict) is called after every generation; raising from it, or
    Ctrl-C, stops the run at the next checkpoint (resumable: call evolve again). Returns a
    dict with outcome ("finished", "stopped", "already-finished") and generations_done.

    fitness: a callable scoring each new body's life instead of the engine's fitness. It
    receives the Result of the life under the run's physics (with its trajectory when
    record_fps > 0) and returns a number (higher is better; NaN or infinite: the life fails).
    Lives that went unstable or sank (sinking_invalid, the default) fail without being
    scored. The results file names the function (provenance fitness_function) and resumes
    only under the same name; raising from it stops the run at its last checkpoint."""
    text, path = _config_args(config)
    threads = _run_threads(threads)
    for name, fn in (("on_generation", on_generation), ("on_message", on_message),
                     ("fitness", fitness)):
        if fn is not None and not callable(fn):
            raise TypeError(f"{name}: expected a callable")
    stop = -1 if stop_after is None else int(stop_after)
    evaluate, name = None, ""
    if fitness is not None:
        fps = _record_fps(record_fps)
        lives_threads = threads if threads >= 0 else _core.config_threads(text, path)

        def evaluate(robots, vectors):
            lives = simulate_many([Robot(r) for r in robots], threads=lives_threads,
                                  record_fps=fps)
            return [_score(life if life.status != "finished" else fitness(life), i, "fitness")
                    + (None,) for i, life in enumerate(lives)]
        name = _function_name(fitness)
    return _core.evolve(text, path, _os.fspath(out), threads, stop, on_generation, on_message,
                        evaluate, name)


_EVOLVERS = _weakref.WeakSet()  # running ask/tell loops, closed at exit


@_atexit.register
def _close_evolvers():
    """An Evolver left running when Python exits stops at its last checkpoint, as close()
    stops it: its thread must not be inside the library while the interpreter goes away."""
    for ev in list(_EVOLVERS):
        ev.close()


class Evolver:
    """An evolution driven from outside, ask/tell style: the same search (the config's
    algorithm, AFPO, MAP-Elites or CMA-ES), checkpoints, resume and results file as evolve(),
    with the lives scored by the caller (under MAP-Elites the descriptors of a life stay the
    engine's: it simulates a life scored by a number for them).

        ev = plastivox.Evolver(config, "run.h5")
        while not ev.finished:
            robots = ev.ask()                  # the generation's new bodies (Robots)
            ev.tell([score(r) for r in robots])

    ask() gives the bodies the engine would simulate (new, valid, not seen before; the
    others are scored from the run's cache), under the run's physics; ask(genomes=True)
    gives each body's genome beside it, and tell(scores, genomes=...) takes edited ones back
    (docs/python.md, "Genomes"). tell() takes one score
    per robot: a number (higher is better; NaN or infinite: the life failed) or a
    plastivox.Result of simulating it (scored as evolve() scores it, so
    tell(plastivox.simulate_many(robots)) gives the digest `plastivox evolve` gives). The
    results file names the loop (provenance fitness_function "python: <name>"), and a run
    resumes only under the same name. The run goes on in a thread of its own between tell()
    and the next ask(); close() (or leaving a `with` block, or Python exiting) stops it at
    its last checkpoint."""

    _CLOSE = object()

    def __init__(self, config, out, threads=None, name="ask-tell"):
        text, path = _config_args(config)
        threads = _run_threads(threads)
        if not isinstance(name, str) or not name:
            raise ValueError("name: expected a non-empty string")
        self._config = (text, path)
        self._asks = _queue.Queue(maxsize=1)
        self._tells = _queue.Queue(maxsize=1)
        self._next = None        # the next generation's robots, once known; [] at the end
        self._vectors = []       # their genomes: vectors (cma-es) or CPPN genome dicts
        self._pending = None     # robots asked and not yet told
        self._error = None
        self.report = None       # evolve()'s dict once the run has ended
        self.generations_done = -1

        def evaluate(robots, vectors):
            self._asks.put(([Robot(r) for r in robots],
                            [v if v is None or isinstance(v, dict) else _np.asarray(v, dtype=float)
                             for v in vectors]))
            scores = self._tells.get()
            if scores is Evolver._CLOSE:
                raise InterruptedError("the ask/tell loop was closed")
            return scores

        def progress(p):
            self.generations_done = p["generation"]

        def run():
            try:
                self.report = _core.evolve(text, path, _os.fspath(out), threads, -1, progress,
                                           None, evaluate, name)
            except BaseException as e:  # surfaced by ask()/finished in the caller's thread
                self._error = e
            finally:
                self._asks.put(None)

        self._thread = _threading.Thread(target=run, name="plastivox-evolver", daemon=True)
        self._thread.start()
        _EVOLVERS.add(self)

    def _wait(self):
        if self._next is None:
            batch = self._asks.get()
            self._next, self._vectors = ([], []) if batch is None else batch
            if batch is None:
                self._thread.join()
                if self._error is not None and not isinstance(self._error, InterruptedError):
                    raise self._error
        return self._next

    @property
    def finished(self):
        """True once the run has ended (waits for the run to reach its next generation)."""
        return self._pending is None and not self._wait()

    def ask(self, genomes=False):
        """The next generation's new bodies to score, as Robots; [] once the run has ended.
        genomes=True: (robots, genomes) instead, each robot's genome beside it: under
        algorithm cma-es the vector the search sampled (a float array; the robot is the
        fixed body with it applied, docs/evolution.md); under afpo and map-elites its four
        CPPNs, a dict per network ("geometry", "stiffness", "development", "phase") of
        "activation" (a name per node: the five inputs x, y, z, d, bias, the hidden nodes, the
        output), "source", "target" (int32 arrays of node indices) and "weight" (a float
        array), a link each, and "controller", the controller's weights (docs/python.md,
        "Genomes"). Edit a copy and give it back to tell(genomes=...)."""
        if self._pending is not None:
            raise RuntimeError("ask: tell() the scores of the robots asked before")
        robots = self._wait()
        vectors = self._vectors
        if robots:
            self._pending, self._next = robots, None
        return (list(robots), list(vectors)) if genomes else list(robots)

    def tell(self, scores, genomes=None):
        """One score per robot the last ask() gave, in its order. genomes (afpo and
        map-elites): None, or one entry per robot: None (its genome as asked) or a genome as
        ask(genomes=True) gives it, edited; the robot's genome becomes that one, and its score
        must then be the body robot(genome) gives (an invalid body fails whatever its score).
        A malformed genome is a ValueError naming it and its field, and the generation still
        waits for a tell()."""
        if self._pending is None:
            raise RuntimeError("tell: ask() for robots first")
        scores = list(scores)
        if len(scores) != len(self._pending):
            raise ValueError(f"scores: expected {len(self._pending)}, one per robot ask() "
                             f"gave, got {len(scores)}")
        converted = [_score(v, i, "scores") for i, v in enumerate(scores)]
        genomes = [None] * len(scores) if genomes is None else list(genomes)
        if len(genomes) != len(scores):
            raise ValueError(f"genomes: expected one per robot ask() gave ({len(scores)}), "
                             f"got {len(genomes)}")
        for i, (g, asked) in enumerate(zip(genomes, self._vectors)):
            if g is None:
                continue
            if not isinstance(asked, dict):
                raise ValueError(f"genomes[{i}]: only a CPPN genome (afpo, map-elites) can be "
                                 f"set; a CMA-ES run's samples are the search's")
            _core.check_genome(g, len(asked["controller"]), f"genomes[{i}]")
        converted = [c + (g,) for c, g in zip(converted, genomes)]
        self._pending = None
        self._tells.put(converted)

    def robot(self, genome):
        """The body a CPPN genome (as ask(genomes=True) gives it) expresses under the run's
        config, as a Robot under its physics; None when the body is invalid (too few voxels,
        or NaN)."""
        r = _core.express_genome(*self._config, genome)
        return None if r is None else Robot(r)

    def close(self):
        """Stops the run at its last checkpoint (resumable with the same config, out and
        name). Nothing happens once it has ended."""
        while self._next != []:
            if self._pending is None and self._next is None:
                batch = self._asks.get()  # the run's next message: robots, or None at its end
                if batch is None:
                    self._next = []
                    break
            # A generation waits for its scores (asked or not): it is dropped, unscored.
            self._pending = self._next = None
            self._tells.put(Evolver._CLOSE)
        self._thread.join()
        _EVOLVERS.discard(self)

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def __repr__(self):
        state = "finished" if not self._thread.is_alive() else "running"
        return f"Evolver({state}, generations_done={self.generations_done})"


class Study:
    """An analysed study (the folder `plastivox analyze` or `experiment` writes):
    stats (stats.json as a dict), champions and statistics (the CSV tables as lists of
    dicts, numbers as float/int, empty cells as None)."""

    def __init__(self, folder, stats, champions, statistics):
        self.folder = folder
        self.stats = stats
        self.champions = champions
        self.statistics = statistics

    def __eq__(self, other):
        if not isinstance(other, Study):
            return NotImplemented
        return (self.folder, self.stats, self.champions, self.statistics) == \
            (other.folder, other.stats, other.champions, other.statistics)

    def __repr__(self):
        return f"Study({self.folder!r}, {len(self.champions)} champions)"


def _cell(text):
    if text == "":
        return None
    if text in ("true", "false"):  # a flag column (vertical_exploit): a bool, as "false" is truthy
        return text == "true"
    for kind in (int, float):
        try:
            return kind(text)
        except ValueError:
            pass
    return text


def _read_table(path, columns, rows=None):
    """The rows of a CSV table plastivox wrote, checked: its header must hold `columns` and,
    when `rows` is given, it must have that many rows (a damaged or foreign table is an
    InputError naming the file, never rows of nonsense)."""
    try:
        with open(path, newline="") as f:
            reader = _csv.DictReader(f)
            header = reader.fieldnames or []
            missing = [c for c in columns if c not in header]
            if missing:
                raise InputError(f"{path}: not a plastivox table: no column {missing[0]!r} "
                                 f"(a damaged file? rerun the analysis)")
            raw = list(reader)
            if any(None in row or None in row.values() for row in raw):  # DictReader's marks
                raise InputError(f"{path}: a row's cells do not match the header (a damaged file?)")
            table = [{k: _cell(v) for k, v in row.items()} for row in raw]
    except OSError as e:
        raise InputError(f"{path}: cannot read: {e.strerror}") from None
    except (_csv.Error, UnicodeDecodeError) as e:
        raise InputError(f"{path}: not a readable CSV table: {e}") from None
    if rows is not None and len(table) != rows:
        raise InputError(f"{path}: {len(table)} rows where stats.json lists {rows} "
                         f"(a damaged file? rerun the analysis)")
    return table


def read_study(folder):
    """Reads an analysed study: stats.json, champions.csv and statistics.csv in `folder`."""
    folder = _os.fspath(folder)
    stats_path = _os.path.join(folder, "stats.json")
    try:
        with open(stats_path) as f:
            stats = _json.load(f)
    except OSError as e:
        raise InputError(f"{stats_path}: cannot read: {e.strerror} (not an analysed study?)") from None
    except ValueError as e:
        raise InputError(f"{stats_path}: not valid JSON: {e}") from None
    if not isinstance(stats, dict) or stats.get("format") != "plastivox-analysis":
        raise InputError(f"{stats_path}: format: expected \"plastivox-analysis\"")
    champions = stats.get("champions")
    return Study(folder, stats,
                 _read_table(_os.path.join(folder, "champions.csv"),
                             ("label", "treatment", "seed", "fitness", "excluded"),
                             len(champions) if isinstance(champions, list) else None),
                 _read_table(_os.path.join(folder, "statistics.csv"),
                             ("kind", "panel", "metric", "treatment", "mean")))


# --- rendering -------------------------------------------------------------------------

def render(source, time=0.2, color="congenital", size=(640, 480), out=None, generation=None,
           overlay=True, zoom=1.0, azimuth=-60.0, elevation=25.0, antialias="msaa"):
    """One frame of a life at simulated `time` (s) as an (h, w, 3) uint8 array, drawn
    off-screen; also written as a PNG when `out` is given. `source` is a Robot, a Result
    (its robot), a Results (its champion at `generation`, None: the last done) or a
    .json/.vxa/.h5 path; `generation` applies to a results file only (ValueError otherwise).
    color:
    congenital, stiffness, change, alpha, phase, stimulus or actuation (the signal, recorded
    while the life is simulated for the picture); the other options are those of
    `plastivox render` (--no-overlay, --zoom, --azimuth, --elevation, --antialias)."""
    try:
        w, h = (int(v) for v in size)
    except (TypeError, ValueError):
        raise TypeError(f"size: expected (width, height), got {size!r}") from None
    args = (float(time), str(color), w, h, bool(overlay), float(zoom), float(azimuth),
            float(elevation), str(antialias), "" if out is None else _os.fspath(out))
    if generation is not None and (isinstance(generation, bool) or
                                   not isinstance(generation, (int, _np.integer)) or
                                   generation < -1):
        raise ValueError(f"generation: expected a generation number or -1 (the last done), "
                         f"got {generation!r}")
    if isinstance(source, (Robot, Result)) and generation is not None:
        raise ValueError(f"generation: applies to a results file (a Results or a .h5 path), "
                         f"not a {type(source).__name__}")
    generation = -1 if generation is None else int(generation)
    if isinstance(source, Result):
        source = source.robot
    if isinstance(source, Robot):
        return _core.render_robot(source._core, *args)
    if isinstance(source, Results):
        return _core.render_file(source.path, generation, *args)
    if isinstance(source, (str, _os.PathLike)):
        return _core.render_file(_os.fspath(source), generation, *args)
    raise TypeError(f"source: expected a Robot, Result, Results or file path, got {type(source).__name__}")


# --- reinforcement learning ----------------------------------------------------------------

from ._env import VoxelEnv, VoxelVecEnv  # noqa: E402 (it uses the helpers above)
from . import analysis  # noqa: E402 (the paper's analysis of champions; it uses the classes above)
from .analysis import robustness_battery as robustness  # noqa: E402 (the battery, by its short name)
