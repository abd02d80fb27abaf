# %% [markdown]
# # plastivox from Python: a walk-through
#
# Run it as a script, or open it as a notebook (Jupyter, VS Code: the `# %%` markers are
# cells). `PYTHONPATH=build/python` must point at the build tree (or install the module).
# Environment: WALKTHROUGH_DURATION (s of life, default 2.0), WALKTHROUGH_OUT (folder, made
# if missing; default a new temporary folder).

# %%
import os
import tempfile

import numpy as np

import plastivox

duration = float(os.environ.get("WALKTHROUGH_DURATION", "2.0"))
out = os.environ.get("WALKTHROUGH_OUT") or tempfile.mkdtemp(prefix="plastivox-")
os.makedirs(out, exist_ok=True)
print("plastivox", plastivox.__version__, "-> files in", out)

# %% [markdown]
# ## A robot from numpy arrays
# Arrays are shaped (nx, ny, nz) and indexed [x, y, z]. Stiffness is Young's modulus in Pa,
# phase is the actuation phase in cycles, dev_rate the development rate in 1/s.

# %%
n = 4
geometry = np.ones((n, n, 2), dtype=bool)
geometry[1:3, 1:3, 1] = False                   # a hollow on top
x = np.arange(n)[:, None, None] * np.ones((n, n, 2))
# 3e9 Pa: under the presets' density (1e9 kg/m^3, a 1 cm voxel weighs 1000 kg) a voxel much
# softer than ~1e9 Pa cannot carry the body, and below ~1e7 Pa it falls through the floor.
stiffness = np.where(geometry, 3e9, 0.0)
phase = x / n                                   # a wave travelling from front to back
robot = plastivox.Robot.from_arrays(geometry, stiffness, phase, treatment="stress",
                                    dev_rate=np.where(geometry, 100.0, 0.0))
print(robot)

# %% [markdown]
# ## Physics: a preset and overrides, as a plain dict

# %%
physics = plastivox.physics(duration=duration, settle_time=min(0.2, duration / 2))
print({k: physics[k] for k in ("duration", "treatment", "growth", "e_min", "e_max")})

# %% [markdown]
# ## One life, with its trajectory

# %%
result = plastivox.simulate(robot, physics=physics, treatment="stress", record_fps=30)
print(result)
print("distance", result.fitness, "voxel lengths; hash", result.final_state_hash)
traj = result.trajectory
com = traj.positions.mean(axis=1)               # centre of mass per frame, m
print(traj, "centre of mass moved", com[-1] - com[0], "m")

# %% [markdown]
# ## Step by step

# %%
sim = plastivox.Simulator(robot, physics=physics)
while sim.time < min(0.1, duration):
    sim.step(100)
print(f"t = {sim.time:.4f} s after {sim.steps} steps; mean speed "
      f"{np.linalg.norm(sim.velocities, axis=1).mean():.4f} m/s")

# %% [markdown]
# ## Many robots on all cores: the stiffness of the whole body scaled

# %%
variants = [plastivox.Robot.from_arrays(geometry, stiffness * s, phase) for s in (0.1, 1, 10)]
for s, r in zip((0.1, 1, 10), plastivox.simulate_many(variants, physics=physics)):
    print(f"E x {s:>4}: {r.status}, fitness {r.fitness:.4f}")

# %% [markdown]
# ## Save, load, render

# %%
path = os.path.join(out, "walker.json")
simulated = robot.with_physics(physics, treatment="stress")  # what was simulated above
simulated.save(path)
again = plastivox.load_robot(path)
assert again == simulated                     # robots compare by value, bit for bit
assert plastivox.simulate(path).final_state_hash == result.final_state_hash  # a path works too
frame = plastivox.render(again, time=min(0.5, duration), size=(320, 240),
                         out=os.path.join(out, "walker.png"))
print("frame", frame.shape, frame.dtype, "->", os.path.join(out, "walker.png"))
