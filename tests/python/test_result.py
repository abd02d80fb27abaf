"""Simulator.result(): a life stepped from Python says what it scored, so far and at the end,
as simulate() does; a snapshot resumes the score, the task given in the physics dict; every
row of the engine's state table, the rows added for the score included, is a state view."""

import numpy as np
import pytest

import plastivox

# The summary keys that are not the life's bits.
TIMING = {"wall_seconds", "voxel_steps_per_second"}


def walker():
    return plastivox.demo_walker().with_physics({"duration": 0.6, "settle_time": 0.2})


def same_summary(a, b):
    da, db = a.to_dict(), b.to_dict()
    assert set(da) == set(db), set(da) ^ set(db)
    for key in da:
        if key not in TIMING:
            assert da[key] == db[key], key


@pytest.mark.parametrize("task", ["walk", "jump", "turn", "climb", "carry"])
def test_a_restored_life_finishes_with_simulates_fitness_and_floor_health(task):
    robot, physics = walker(), {"task": task, "treatment": "stress"}
    whole = plastivox.simulate(robot, physics)
    assert whole.status == "finished" and whole.fitness > 0
    first = plastivox.Simulator(robot, physics)
    first.step(900)  # 0.4 s of 0.6, past settling: the watches are under way
    assert first.status == "running"
    snapshot = first.save_state()
    second = plastivox.Simulator(robot, physics)
    second.step(200)  # a life of its own, replaced by the snapshot
    second.restore_state(snapshot)
    second.run()
    r = second.result()
    assert r.fitness == whole.fitness and r.health == whole.health
    assert r.floor_depth == whole.floor_depth
    same_summary(r, whole)


def test_result_mid_life_is_the_score_so_far_and_at_the_end_simulates():
    robot, physics = walker(), {"task": "jump", "treatment": "stress"}
    sim = plastivox.Simulator(robot, physics)
    assert sim.result().status == "running" and sim.result().fitness == 0  # not settled
    sim.step(900)
    so_far = sim.result()
    assert so_far.status == "running" and so_far.fitness > 0
    assert so_far.steps == 900 and so_far.final_state_hash == sim.state_hash
    sim.run()
    end = sim.result()
    assert end.status == "finished" and end.fitness >= so_far.fitness
    same_summary(end, plastivox.simulate(robot, physics))
    assert end.robot == plastivox.simulate(robot, physics).robot


def test_every_row_of_the_state_table_is_a_view_the_score_rows_included():
    sim = plastivox.Simulator(walker(), {"task": "jump"})
    names = [f["name"] for f in sim.state_fields]
    assert list(sim.state) == names
    for row in ("actuation", "control_memory", "floor_deepest", "floor_deep_most",
                "task_values", "task_layout"):
        assert row in names, row
    sim.step(900)
    state = sim.state
    n = len(sim.positions)
    assert state["actuation"].shape == (n,)
    assert np.array_equal(state["actuation"][:sim.robot_voxels], sim.actuation)
    assert state["control_memory"].shape == (0,)  # the sine remembers nothing
    assert float(state["floor_deepest"]) > 0 and state["floor_deep_most"].dtype == np.int32
    assert state["task_values"].shape == (10,) and float(state["task_values"][0]) > 0
    assert state["task_layout"].shape == (n, 2)


def test_the_model_table_is_read_whole_from_python():
    sim = plastivox.Simulator(walker(), {"task": "push"})  # a free box: objects + 1 rows
    names = [f["name"] for f in sim.model_fields]
    model = sim.model
    assert list(model) == names and len(names) > 30
    n = len(sim.positions)
    assert int(model["n"]) == n and int(model["robot_n"]) == sim.robot_voxels < n
    assert np.array_equal(model["object_begin"], [sim.robot_voxels, n])
    assert model["rest_pos"].shape == (n, 3) and model["voxel_bonds"].shape == (n, 6)
    assert float(model["mass"]) == sim._core.voxel_mass
    assert np.array_equal(model["phase"][:sim.robot_voxels], sim.voxel_phase)
    bonds = model["bond_a"].shape[0]
    assert model["bond_b"].shape == (bonds,) and model["bond_axis"].dtype == np.uint8
    assert not model["e0"].flags.writeable
    # Before the first step the state's stiffness is the model's E0.
    assert np.array_equal(sim.state["stiffness"], model["e0"])
