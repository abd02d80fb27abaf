"""MAP-Elites runs from Python (docs/evolution.md, "MAP-Elites"): the ask/tell Evolver hands
out the children of the archive's elites, and the engine's own scores give `plastivox
evolve`'s digest (the life's descriptors are measured by the engine whatever scored it)."""

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
