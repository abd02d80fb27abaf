"""MAP-Elites runs from Python (docs/evolution.md, "MAP-Elites"): the ask/tell Evolver hands
out the children of the archive's elites, and the engine's own scores give `plastivox
evolve`'s digest (the life's descriptors are measured by the engine whatever scored it)."""

import pytest

import plastivox


def me_config(generations=3):
    return {"format": "plastivox-evolve-config", "version": 1, "seed": 6,
            "generations": generations, "population": 5, "treatment": "stress", "threads": 1,
            "lattice": {"nx": 4, "ny": 4, "nz": 4}, "algorithm": "map-elites",
            "map_elites": {"descriptors": [
                {"name": "fill", "bounds": [0.2, 1], "bins": 4},
                {"name": "floor_contact", "bounds": [0, 1], "bins": 4}]},
            "physics": {"preset": "gecco2018-code", "duration": 0.2, "settle_time": 0.1}}


def test_ask_tell_with_the_engines_scores_gives_evolves_digest(tmp_path):
    config = me_config()
    ref = str(tmp_path / "ref.h5")
    assert plastivox.evolve(config, ref, threads=1)["outcome"] == "finished"
    for name, score in (("simulate", lambda robots: plastivox.simulate_many(robots, threads=1)),
                        ("numbers", lambda robots: [plastivox.simulate(r).fitness
                                                    for r in robots])):
        out = str(tmp_path / f"{name}.h5")
        asked = 0
        with plastivox.Evolver(config, out, threads=1, name=name) as ev:
            while not ev.finished:
                robots = ev.ask()
                asked += len(robots)
                ev.tell(score(robots))
        assert asked > 5
        # Numbers alone: the descriptors come from the engine's own simulation of each life,
        # so only the recorded fitness function differs from evolve's run.
        got = plastivox.read_results(out)
        champion = plastivox.simulate(got.champion()).fitness
        assert champion == plastivox.simulate(plastivox.read_results(ref).champion()).fitness
        if name == "simulate":
            assert got.content_digest == plastivox.read_results(ref).content_digest


def test_results_give_the_archive_and_its_qd_curves(tmp_path):
    out = str(tmp_path / "run.h5")
    plastivox.evolve(me_config(generations=4), out, threads=1)
    a = plastivox.read_results(out).archive()
    assert [d["name"] for d in a["descriptors"]] == ["fill", "floor_contact"]
    assert a["cells"] == 16 and len(a["elites"]) >= 2
    assert [e["cell"] for e in a["elites"]] == sorted(e["cell"] for e in a["elites"])
    best = max(a["elites"], key=lambda e: (e["fitness"], -e["id"]))
    # The best elite is the champion, and each elite's robot replays its fitness.
    champion = plastivox.read_results(out).champion()
    assert best["robot"].voxel_count == champion.voxel_count
    for e in a["elites"]:
        assert plastivox.simulate(e["robot"]).fitness == e["fitness"]
        assert e["bins"][0] * 4 + e["bins"][1] == e["cell"]
    assert len(a["qd_score"]) == 5 and a["qd_score"][-1] == sum(e["fitness"] for e in a["elites"])
    assert list(a["evaluations"]) == [5, 10, 15, 20, 25]
    assert a["coverage"][-1] == len(a["elites"]) / 16
    assert all(x <= y for x, y in zip(a["qd_score"], a["qd_score"][1:]))
    with pytest.raises(ValueError, match="algorithm afpo keeps no archive"):
        c = me_config(generations=0)
        del c["algorithm"], c["map_elites"]
        plastivox.evolve(c, str(tmp_path / "afpo.h5"), threads=1)
        plastivox.read_results(str(tmp_path / "afpo.h5")).archive()
