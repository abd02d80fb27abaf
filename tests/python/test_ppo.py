"""plastivox.ppo, PPO through VoxelVecEnv (docs/control.md, "Learning a controller: PPO vs
CMA-ES"): a smoke test on a small body and a short life. A few updates give finite losses
and move the policy; a run stopped after one iteration and resumed from its checkpoint ends
with the very parameters of a run that was not stopped. Needs python3-torch
(.ci/packages.txt); `import plastivox` itself does not import torch."""

import subprocess
import sys

import numpy as np
import pytest

import plastivox

torch = pytest.importorskip("torch")
from plastivox import ppo  # noqa: E402 (after torch is known to be there)


def small_robot(path):
    shape = (3, 3, 2)
    x = np.indices(shape)[0]
    robot = plastivox.Robot.from_arrays(np.ones(shape, bool), np.full(shape, 5e9), x / 3.0,
                                        name="small")
    robot.save(str(path))
    return str(path)


def args_for(tmp_path, name, extra=()):
    return ppo.parser().parse_args(
        ["--robot", small_robot(tmp_path / "small.json"), "--checkpoint",
         str(tmp_path / name), "--duration", "0.06", "--settle-time", "0.01", "--every", "10",
         "--num-envs", "2", "--eval-every", "1", "--quiet", "--seed", "3", *extra])


def params(state):
    return {k: v.clone() for k, v in state["agent"].items()}


def test_import_plastivox_does_not_import_torch():
    code = "import sys, plastivox; print('torch' in sys.modules)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True)
    assert out.stdout.strip() == "False"


def test_updates_are_finite_and_a_resumed_run_ends_where_an_unbroken_one_does(tmp_path):
    whole = ppo.train(args_for(tmp_path, "whole.pt"), stop_after=2)
    assert whole["iteration"] == 2 and len(whole["log"]) == 2
    for entry in whole["log"]:
        assert np.isfinite(entry["policy_loss"]) and np.isfinite(entry["value_loss"])
        assert np.isfinite(entry["eval_fitness"])
    # whole lives (94 steps each: 2 training, 1 evaluation an iteration), none cut short
    assert whole["steps"] == 2 * 3 * 94 and whole["best"]["fitness"] > 0
    # The champion's actions, replayed in a Simulator, give its life: its fitness bit for
    # bit, and the Result (success by the task's criterion) the comparison reports.
    life = ppo.replay(args_for(tmp_path, "whole.pt"), whole["best"]["actions"])
    assert life.status == "finished" and life.fitness == whole["best"]["fitness"]
    assert life.steps == 94
    torch.manual_seed(3)  # the parameters the run started from
    init = ppo.Agent(16).state_dict()
    assert any(not torch.equal(init[k], v) for k, v in whole["agent"].items())

    broken = args_for(tmp_path, "broken.pt")
    first = ppo.train(broken, stop_after=1)
    assert first["iteration"] == 1
    resumed = ppo.train(broken, stop_after=1)  # a new call: from the checkpoint
    assert resumed["iteration"] == 2 and resumed["steps"] == whole["steps"]
    a, b = params(whole), params(resumed)
    assert a.keys() == b.keys() and all(torch.equal(a[k], b[k]) for k in a)
    assert [e["eval_fitness"] for e in resumed["log"]] == [e["eval_fitness"]
                                                          for e in whole["log"]]


def test_a_checkpoint_of_another_run_is_refused(tmp_path):
    ppo.train(args_for(tmp_path, "run.pt"), stop_after=1)
    with pytest.raises(SystemExit, match=r"run.pt: checkpoint of another run \(lr: 0.0003 "
                                         r"there, 0.001 here\)"):
        ppo.train(args_for(tmp_path, "run.pt", ["--lr", "1e-3"]), stop_after=1)
