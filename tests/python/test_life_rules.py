"""Whether a sunk life counts is decided by one function outside the core (judge_life,
plastivox/rules/life_rules.hpp; docs/engine.md, "Floor contact and sinking"): the champion of
tests/data/results/old-rule-sinker.h5, which falls through the floor, gets the same verdict
from `plastivox simulate` (exit status and JSON), Python's simulate and simulate_many, and
VoxelEnv's early end; with sinking_invalid false every one scores it alike. (Evolution's
evaluation gets the same verdict in tests/life_rules_test.cpp.)"""

import json
import os

import pytest

import plastivox
from conftest import DATA, run_cli

SINKER = os.path.join(DATA, "results", "old-rule-sinker.h5")


@pytest.mark.parametrize("invalid", [True, False])
def test_a_sunk_life_gets_one_verdict_from_the_cli_python_and_the_env(tmp_path, invalid):
    champion = plastivox.read_results(SINKER).champion().with_physics(
        {"sinking_invalid": invalid})
    path = str(tmp_path / "sinker.json")
    champion.save(path)
    code, out, err = run_cli("simulate", path, "--json", check=False)
    cli = json.loads(out)
    assert code == (3 if invalid else 0), err
    assert ("life invalid: sank through the floor" in err) == invalid, err
    life = plastivox.simulate(champion)
    [many] = plastivox.simulate_many([champion], threads=1)
    for r in (life, many):
        assert r.status == cli["status"] == ("unstable" if invalid else "finished")
        assert r.health == cli["health"] == "sank"
        assert r.fitness == cli["fitness"] and r.failure == cli.get("failure", "")
    assert (life.fitness == 0) == invalid
    # VoxelEnv replaying the built-in sine lives the same life: under the rule it ends as
    # soon as the body is certain to be judged sunk, with fitness 0; under the authors' rule
    # it runs to the end with simulate's fitness.
    env = plastivox.VoxelEnv(champion, sensors="time")
    obs, _ = env.reset()
    total = 0.0
    while True:
        action = plastivox.sin_cycles(env.act_frequency * obs[-1] + env.voxel_phase)
        obs, reward, terminated, truncated, info = env.step(action)
        total += reward
        if terminated or truncated:
            break
    if invalid:
        assert terminated and info["status"] == "sank" and info["steps"] < life.steps
        assert info["fitness"] == 0 and total == pytest.approx(0, abs=1e-12)
    else:
        assert truncated and info["status"] == "finished" and info["steps"] == life.steps
        assert info["state_hash"] == life.final_state_hash and info["fitness"] == life.fitness
