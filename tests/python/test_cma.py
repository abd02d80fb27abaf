"""CMA-ES runs from Python (docs/evolution.md, "CMA-ES"): the ask/tell Evolver hands out each
sample's vector beside its body, the engine's own scores give `plastivox evolve`'s digest, a
checkpoint's population carries its vectors, and on a known quadratic the search converges
as an independent implementation (Debian's python3-cmaes) does."""

import numpy as np
import pytest

import plastivox


def block(neural):
    """A 3x2x2 block, 5e9 Pa, phases along x; a distributed controller when neural."""
    g = np.ones((3, 2, 2), bool)
    phase = np.zeros(g.shape)
    phase[1], phase[2] = 0.25, 0.5
    r = plastivox.Robot.from_arrays(g, stiffness=np.full(g.shape, 5e9), phase=phase,
                                    treatment="stress", name="block")
    if neural:
        n = plastivox.controller_weight_count("distributed", 2)
        r = r.with_controller("distributed", hidden=2, weights=np.zeros(n))
    return r


def cma_config(tmp_path, genome, generations=2, **extra):
    body = str(tmp_path / f"body-{genome}.json")
    block(genome == "controller").save(body)
    c = {"format": "plastivox-evolve-config", "version": 1, "seed": 4,
         "generations": generations, "algorithm": "cma-es", "genome": genome, "body": body,
         "treatment": "stress", "threads": 1,
         "physics": {"preset": "gecco2018-code", "duration": 0.4, "settle_time": 0.2}}
    c.update(extra)
    return c


def test_ask_tell_hands_out_vectors_and_the_engines_scores_give_evolves_digest(tmp_path):
    config = cma_config(tmp_path, "controller")
    ref = str(tmp_path / "ref.h5")
    assert plastivox.evolve(config, ref, threads=1)["outcome"] == "finished"
    out = str(tmp_path / "asked.h5")
    with plastivox.Evolver(config, out, threads=1, name="simulate") as ev:
        while not ev.finished:
            robots, vectors = ev.ask(genomes=True)
            assert len(robots) == len(vectors) > 0
            for r, v in zip(robots, vectors):
                assert isinstance(v, np.ndarray) and v.shape == (plastivox.controller_weight_count(
                    "distributed", 2),)
                assert list(r.controller["weights"]) == list(v)  # the body with its genome
            ev.tell(plastivox.simulate_many(robots, threads=1))
    assert plastivox.read_results(out).content_digest == plastivox.read_results(ref).content_digest
    people = plastivox.read_results(out).population()
    for p in people:
        assert list(p["robot"].controller["weights"]) == list(p["genome"])
        assert plastivox.simulate(p["robot"]).fitness == p["fitness"]


def sphere_distance(v):
    return float(np.sum((np.asarray(v) - 0.3) ** 2))


def test_on_a_quadratic_it_converges_as_python3_cmaes_does(tmp_path):
    """Minimise |x - 0.3|^2 over the block's 12 phases, told as numbers (no life is scored
    by the engine): plastivox's CMA-ES and python3-cmaes, same start, step size and samples
    a generation, both reach the optimum within the same budget."""
    cmaes = pytest.importorskip("cmaes")
    generations = 120
    config = cma_config(tmp_path, "phase", generations=generations,
                        cma={"sigma": 0.25, "covariance": "full"})
    best = np.inf
    with plastivox.Evolver(config, str(tmp_path / "q.h5"), threads=1, name="sphere") as ev:
        while not ev.finished:
            _, vectors = ev.ask(genomes=True)
            scores = [-sphere_distance(v) for v in vectors]
            best = min(best, -max(scores))
            ev.tell(scores)
    lam = plastivox.read_results(str(tmp_path / "q.h5")).population().__len__()
    x0 = block(False).phase.transpose(2, 1, 0).ravel()  # the body's phases in site order
    ref = cmaes.CMA(mean=np.array(x0, float), sigma=0.25, population_size=lam, seed=1)
    ref_best = np.inf
    for _ in range(generations + 1):
        told = []
        for _ in range(lam):
            x = ref.ask()
            told.append((x, sphere_distance(x)))
            ref_best = min(ref_best, told[-1][1])
        ref.tell(told)
    print(f"best |x - 0.3|^2 after {generations + 1} generations of {lam}: plastivox {best:.3g}, "
          f"python3-cmaes {ref_best:.3g}")
    assert ref_best < 1e-6  # the reference reaches the optimum in this budget
    assert best < 1e-6  # and so does ours, at a like rate
    assert 1e-2 < best / ref_best < 1e2
