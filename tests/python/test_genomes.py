"""The ask/tell Evolver hands out CPPN genomes as arrays and takes edited ones back
(docs/python.md, "Genomes"): unchanged genomes change nothing, an edited weight changes the
body it was asked about deterministically, and a malformed genome is one ValueError."""
import numpy as np
import pytest

import plastivox
from conftest import tiny_config

NETWORKS = ("geometry", "stiffness", "development", "phase")


def map_elites(config):
    return {**config, "algorithm": "map-elites", "map_elites": {"descriptors": [
        {"name": "fill", "bounds": [0.2, 1], "bins": 4},
        {"name": "stiffness", "bounds": [1e5, 1e11], "bins": 3}]}}


def drive(config, out, edit=None):
    """An ask/tell run scoring each body by simulating it; `edit(genomes)` may change the
    first generation's genomes, whose bodies are then scored. Returns (digest, first
    generation's (robots, genomes) as asked, the robots scored)."""
    first = scored = None
    with plastivox.Evolver(config, out, threads=1) as ev:
        while not ev.finished:
            robots, genomes = ev.ask(genomes=True)
            if first is None:
                first = (robots, [dict(g) for g in genomes])
                if edit is not None:
                    edit(ev, robots, genomes)
                bodies = [ev.robot(g) for g in genomes]
                scored = bodies
                ev.tell(plastivox.simulate_many(bodies), genomes=genomes)
            else:
                ev.tell(plastivox.simulate_many(robots))
    return plastivox.read_results(out).content_digest, first, scored


def same_body(a, b):
    return all(np.array_equal(getattr(a, k), getattr(b, k))
               for k in ("geometry", "stiffness", "dev_rate", "phase"))


@pytest.mark.parametrize("algorithm", ["afpo", "map-elites"])
def test_genomes_read_as_arrays_and_set_unchanged_change_nothing(tmp_path, algorithm):
    config = tiny_config(generations=1)
    if algorithm == "map-elites":
        config = map_elites(config)
    plain = plastivox.evolve(config, str(tmp_path / "plain.h5"), threads=1)["content_digest"]
    digest, (robots, genomes), bodies = drive(config, str(tmp_path / "set.h5"))
    assert digest == plain
    assert robots and len(genomes) == len(robots)
    for robot, body, g in zip(robots, bodies, genomes):
        assert set(g) == set(NETWORKS) | {"controller"}
        assert same_body(robot, body)  # the genome expresses to the body asked about
        for name in NETWORKS:
            net = g[name]
            nodes = len(net["activation"])
            assert net["activation"][:5] == ["identity"] * 5 and net["activation"][-1] == "identity"
            assert net["source"].dtype == np.int32 and net["weight"].dtype == np.float64
            assert len(net["source"]) == len(net["target"]) == len(net["weight"])
            assert (net["source"] < net["target"]).all() and (net["target"] < nodes).all()
            assert (np.abs(net["weight"]) <= 1).all()
        assert len(g["controller"]) == 0  # the sine: no weights


def flip_a_geometry_weight(ev, robots, genomes):
    """The first geometry weight of robot 0 whose change of sign (or, near 0, to 0.9) gives a
    valid body of another shape."""
    net = genomes[0]["geometry"]
    for k in range(len(net["weight"])):
        weight = net["weight"].copy()
        weight[k] = -weight[k] if abs(weight[k]) > 0.05 else 0.9
        body = ev.robot(dict(genomes[0], geometry=dict(net, weight=weight)))
        if body is not None and not np.array_equal(body.geometry, robots[0].geometry):
            genomes[0] = dict(genomes[0], geometry=dict(net, weight=weight))
            return
    raise AssertionError("no single weight changes robot 0's shape")


def test_an_edited_weight_changes_the_body_deterministically(tmp_path):
    config = tiny_config(generations=0)  # generation 0 is the population: every body kept
    plain, (asked, _), _ = drive(config, str(tmp_path / "plain.h5"))
    a, _, bodies_a = drive(config, str(tmp_path / "a.h5"), flip_a_geometry_weight)
    b, _, _ = drive(config, str(tmp_path / "b.h5"), flip_a_geometry_weight)
    assert a == b != plain
    edited = bodies_a[0]
    assert not same_body(edited, asked[0])
    # The run recorded the edited body in place of the one asked about (generation 0 keeps
    # every individual; any other with the asked body took the same genome).
    kept = [p["robot"] for p in plastivox.read_results(str(tmp_path / "a.h5")).population()
            if p["robot"] is not None]
    assert any(same_body(r, edited) for r in kept)
    assert not any(same_body(r, asked[0]) for r in kept)


def test_a_malformed_genome_is_one_error_and_the_generation_waits(tmp_path):
    with plastivox.Evolver(tiny_config(generations=0), str(tmp_path / "bad.h5"), threads=1) as ev:
        robots, genomes = ev.ask(genomes=True)
        bad = dict(genomes[0])
        bad["phase"] = dict(bad["phase"], weight=bad["phase"]["weight"] * 0 + 5.0)
        with pytest.raises(ValueError, match=r"genomes\[0\]\.phase: cppn: link 0: weight must be "
                                             r"finite and in \[-1, 1\]"):
            ev.tell([1.0] * len(robots), genomes=[bad] + [None] * (len(robots) - 1))
        with pytest.raises(ValueError, match=r"genomes\[0\]\.geometry\.activation\[5\]: 'cos' is "
                                             r"unknown"):
            g = dict(genomes[0])
            g["geometry"] = dict(g["geometry"], activation=["identity"] * 5 + ["cos"])
            ev.tell([1.0] * len(robots), genomes=[g] + [None] * (len(robots) - 1))
        with pytest.raises(ValueError, match=r"genomes: expected one per robot"):
            ev.tell([1.0] * len(robots), genomes=[None])
        with pytest.raises(ValueError, match=r"genomes\[0\]: unknown key 'colour'"):
            ev.tell([1.0] * len(robots), genomes=[dict(genomes[0], colour=1)] +
                    [None] * (len(robots) - 1))
        ev.tell([1.0] * len(robots), genomes=genomes)  # still waiting: a good tell goes through
        assert ev.ask() == []
