"""plastivox.analysis: each measure and statistic of `plastivox analyze`, from Python, gives
analyze's numbers bit for bit (robustness, canalization, Hausdorff, body plans, bootstrap CIs
and tests), on the champions of a small study of six runs (none, stress, pressure, two seeds
each) that analyze has analysed; and bad arguments are refused in one line naming them."""

import json
import os
import pathlib

import numpy as np
import pytest

import plastivox
from plastivox import analysis

from conftest import main_thread_turns, run_cli, tiny_config

SEED, DRAWS, RESAMPLES = 7, 2, 200  # analyze's --seed, --robustness-draws, --resamples
# PLASTIVOX_STUDY=DIR: the same comparisons on the champions of a study analyze or experiment
# already wrote in DIR (its options read from its stats.json), e.g. the default study's:
#   plastivox experiment --out DIR     (about 10 min on 2 cores), then this file with it set.
STUDY_DIR = os.environ.get("PLASTIVOX_STUDY")
if STUDY_DIR:
    with open(os.path.join(STUDY_DIR, "stats.json")) as _f:
        _options = json.load(_f)["provenance"]["options"]
    SEED, DRAWS, RESAMPLES = _options["seed"], _options["robustness_draws"], _options["resamples"]


def same_bits(a, b):
    """Equal shapes and, element by element, the same double bits (NaN matches NaN: undefined)."""
    a, b = np.asarray(a, dtype=np.float64), np.asarray(b, dtype=np.float64)
    if a.shape != b.shape:
        return False
    nan = np.isnan(a)
    return bool((nan == np.isnan(b)).all() and (a[~nan].view(np.uint64) == b[~nan].view(np.uint64)).all())


def json_number(x):
    return np.nan if x is None else x


@pytest.fixture(scope="module")
def study(tmp_path_factory):
    """(stats.json, analysis.h5 opened, the champions' Results in analyze's order)."""
    h5py = pytest.importorskip("h5py")  # Debian python3-h5py, in .ci/packages.txt
    if STUDY_DIR:
        yield from opened(pathlib.Path(STUDY_DIR), h5py)
        return
    d = tmp_path_factory.mktemp("study")
    files = []
    for treatment in ("none", "stress", "pressure"):
        for seed in (1, 2):
            config = tiny_config(treatment, generations=1)
            config["seed"] = seed
            path = str(d / f"{treatment}-s{seed}.h5")
            plastivox.evolve(config, path, threads=2)
            files.append(path)
    out = d / "out"
    run_cli("analyze", *files, "--out", str(out), "--seed", str(SEED), "--robustness-draws",
            str(DRAWS), "--resamples", str(RESAMPLES), "--threads", "2")
    yield from opened(out, h5py)


def opened(out, h5py):
    """A study folder's (stats.json, analysis.h5 opened, the champions' Results)."""
    stats = json.load(open(out / "stats.json"))
    results = [plastivox.read_results(c["file"]) for c in stats["champions"]]
    with h5py.File(out / "analysis.h5", "r") as h5:
        yield stats, h5, results


def panel(stats, panel_id):
    return next(p for p in stats["panels"] if p["id"] == panel_id)


def test_robustness_draws_seeds_and_means_equal_analyze(study):
    stats, h5, results = study
    champions = h5["champions"]
    measured = [c["excluded"] is None for c in stats["champions"]]  # artifacts: not measured
    assert sum(measured) >= 4, stats["champions"]  # most tiny champions stand
    rob = analysis.robustness([r for r, m in zip(results, measured) if m], draws=DRAWS, seed=SEED)
    keep = np.flatnonzero(measured)
    assert rob["r"].shape == (len(keep), DRAWS) and np.isfinite(rob["r"]).all()
    assert (rob["seed"] == champions["robustness_seed"][:][keep].astype(np.uint64)).all()
    assert same_bits(rob["r"], champions["r_draws"][:][keep])
    assert same_bits(rob["f_test"], champions["f_test"][:][keep])
    assert same_bits(rob["f_train"], champions["f_train"][:][keep])
    assert same_bits(rob["r_mean"], champions["r_mean"][:][keep])
    for i, k in enumerate(keep):  # stats.json prints round-trippable doubles: the same bits
        r = stats["champions"][k]["robustness"]
        assert same_bits(rob["r"][i], [json_number(x) for x in r["draws"]])
        assert same_bits(rob["r_mean"][i], json_number(r["R_mean"]))
        assert rob["seed"][i] == r["seed"]
    # One robot gives its own values; the stream seed may be given directly.
    one = analysis.robustness(results[keep[0]], draws=DRAWS, seed=SEED)
    assert same_bits(one["r"], rob["r"][0]) and same_bits(one["r_mean"], rob["r_mean"][0])
    again = analysis.robustness(results[keep[0]].champion(), draws=DRAWS,
                                stream_seed=int(rob["seed"][0]))
    assert same_bits(again["r"], rob["r"][0])
    assert analysis.robustness_seed(results[keep[0]], SEED) == rob["seed"][0]
    serial = analysis.robustness([results[i] for i in keep], draws=DRAWS, seed=SEED, threads=1)
    assert same_bits(serial["r"], rob["r"])  # robots in parallel or one by one: the same bits
    other = analysis.robustness(results[keep[0]], draws=DRAWS, seed=SEED + 1)
    assert not same_bits(other["r"], rob["r"][0])  # another seed, other draws


def test_canalization_equals_analyze(study):
    stats, h5, results = study
    k = analysis.canalization(results)
    assert np.isfinite(k["m_body"]).all() and np.isfinite(k["v_gain"][2:]).all()
    champions = h5["champions"]
    for name in ("m_body", "v_body", "v_gain"):
        assert same_bits(k[name], champions[name][:]), name
        assert same_bits(k[name], [json_number(c[name]) for c in stats["champions"]]), name
    assert k["alpha_ranges"] == {t: (r["min"], r["max"]) for t, r in stats["alpha_ranges"].items()}
    assert np.isnan(k["v_gain"][0]) and stats["champions"][0]["treatment"] == "none"
    # A robot from elsewhere: its life simulated under its own physics gives the final stiffness
    # the run stored, so the same numbers; or pass its final stiffness yourself.
    robots = [r.champion() for r in results]
    assert same_bits(analysis.canalization(robots)["m_body"], k["m_body"])
    lives = plastivox.simulate_many(robots, threads=2)
    given = analysis.canalization(robots, final_stiffness=[life.final_stiffness for life in lives])
    assert same_bits(given["v_body"], k["v_body"]) and same_bits(given["v_gain"], k["v_gain"])
    # The range analyze would use, given: the same V_gain; another range, another V_gain.
    stress = [r for r, c in zip(results, stats["champions"]) if c["treatment"] == "stress"]
    lo, hi = k["alpha_ranges"]["stress"]
    assert same_bits(analysis.canalization(stress, alpha_range=(lo, hi))["v_gain"],
                     [k["v_gain"][i] for i, c in enumerate(stats["champions"])
                      if c["treatment"] == "stress"])
    wider = analysis.canalization(stress, alpha_range=(lo - 1, hi + 1))["v_gain"]
    base = analysis.canalization(stress)["v_gain"]
    assert (wider <= base).all() and (wider < base).any()


def test_hausdorff_matrix_equals_analyze(study):
    stats, h5, results = study
    m = analysis.hausdorff(results, rotations=stats["hausdorff"]["rotations"])
    assert m.shape == (len(results), len(results))
    assert same_bits(m, h5["hausdorff"]["matrix"][:])
    assert same_bits(m, stats["hausdorff"]["matrix"])
    m2, placements = analysis.hausdorff(results, placements=True)
    assert same_bits(m2, m)
    assert (placements["rotation_index"] == h5["hausdorff"]["pair_rotation_index"][:]).all()
    assert (placements["translation"] == h5["hausdorff"]["pair_translation"][:]).all()
    assert placements["pairs"].shape == (len(results) * (len(results) - 1) // 2, 2)
    # Every rotation and shift can only bring bodies closer than the paper's placements.
    aligned = analysis.hausdorff(results, rotations="all")
    assert (aligned <= m).all() and (np.diag(aligned) == 0).all()


def test_body_plans_equal_analyze(study):
    stats, h5, results = study
    plans = analysis.body_plan(results)
    assert len(plans) == len(results)
    for p, c in zip(plans, stats["champions"]):
        f = c["body_plan_features"]
        assert p["plan"] == c["body_plan"]
        assert same_bits(p["confidence"], c["body_plan_confidence"])
        assert same_bits(p["margin"], f["margin"]) and same_bits(p["box_fill"], f["box_fill"])
        assert same_bits(p["scores"], [m["score"] for m in f["matches"]])
        assert [m["parameters"] for m in p["matches"]] == [m["parameters"] for m in f["matches"]]
        assert list(p["extent"]) == f["extent"] and p["voxels"] == f["voxels"] == c["voxels"]
    assert same_bits([p["confidence"] for p in plans], h5["champions"]["body_plan_confidence"][:])
    one = analysis.body_plan(results[0].champion())
    assert one["plan"] == plans[0]["plan"] and same_bits(one["scores"], plans[0]["scores"])


def test_every_panel_statistic_equals_analyze(study):
    """The CI of every group and every comparison of every panel, recomputed from the groups'
    values with the seeds analyze derives."""
    stats, _, _ = study
    compared = 0
    for p in stats["panels"]:
        assert p["seed"] == analysis.panel_seed(SEED, p["id"])
        samples = {}
        for g in p["groups"]:
            if g["n"] < 2:
                continue
            ci = analysis.bootstrap_ci(g["values"], resamples=RESAMPLES,
                                       seed=analysis.ci_seed(SEED, p["id"], g["treatment"]))
            assert same_bits([ci["mean"], ci["low"], ci["high"]],
                             [g["mean"], g["ci_low"], g["ci_high"]]), (p["id"], g["treatment"])
            samples[g["treatment"]] = g["values"]
        if len(samples) < 2:
            continue
        tests = analysis.bootstrap_tests(samples, resamples=RESAMPLES, seed=p["seed"])
        assert len(tests) == len(p["comparisons"])
        for k, (t, c) in enumerate(zip(tests, p["comparisons"])):
            assert (t["a"], t["b"]) == (c["a"], c["b"])
            for mine, theirs in (("p", "p"), ("p_corrected", "p_corrected"),
                                 ("difference", "mean_diff"), ("hedges_g", "effect_size"),
                                 ("cohens_d", "cohens_d")):
                assert same_bits(t[mine], json_number(c[theirs])), (p["id"], k, mine)
            assert t["comparisons"] == c["comparisons"] == len(tests)
            # One test with pair k's seed and Bonferroni's factor: the same numbers.
            single = analysis.bootstrap_test(samples[c["a"]], samples[c["b"]], resamples=RESAMPLES,
                                             seed=analysis.mix64(p["seed"] + k),
                                             comparisons=len(tests))
            assert same_bits([single["p"], single["p_corrected"]], [t["p"], t["p_corrected"]])
            assert analysis.bonferroni(single["p"], len(tests)) == single["p_corrected"]
            compared += 1
    assert compared >= 4  # panels A and C (3 pairs each), D-F (1 each) as far as n allows


def test_panels_from_python_measures(study):
    """Panel C's and D's samples from the Python measures: analyze's group values."""
    stats, _, results = study
    rob = analysis.robustness(results, draws=DRAWS, seed=SEED)
    k = analysis.canalization(results)
    for panel_id, values in (("C", rob["r_mean"]), ("D", k["m_body"])):
        for g in panel(stats, panel_id)["groups"]:
            mine = {c["label"]: v for c, v in zip(stats["champions"], values)}
            assert same_bits([mine[label] for label in g["value_labels"]], g["values"])


def test_bad_arguments_are_refused_naming_them(study, tmp_path):
    _, _, results = study
    robot = results[0].champion()
    cases = [
        (lambda: analysis.robustness([]), ValueError, "robots: the list is empty"),
        (lambda: analysis.robustness(robot, draws=0), ValueError, "draws: expected"),
        (lambda: analysis.robustness(robot, seed=-1), ValueError, "seed: expected"),
        (lambda: analysis.robustness(robot, sampling="cubic"), ValueError, "sampling: expected"),
        (lambda: analysis.robustness(robot, e_range=(2, 1)), ValueError, "e_range: expected"),
        (lambda: analysis.robustness(3.5), TypeError, "robots: expected"),
        (lambda: analysis.robustness([robot, 3.5]), TypeError, r"robots\[1\]: expected"),
        (lambda: analysis.canalization([robot], final_stiffness=[np.ones(3)]), ValueError,
         r"final_stiffness\[0\]: expected"),
        (lambda: analysis.canalization([robot, robot], final_stiffness=[np.ones(3)]), ValueError,
         "final_stiffness: 1 entries for 2 robots"),
        (lambda: analysis.canalization([robot], alpha_range=(1, 1)), ValueError,
         "alpha_range: expected finite lo < hi"),
        (lambda: analysis.hausdorff([]), ValueError, "robots: the list is empty"),
        (lambda: analysis.hausdorff([robot], rotations="some"), ValueError, "rotations: expected"),
        (lambda: analysis.body_plan(robot, threshold=2), ValueError, "threshold: expected"),
        (lambda: analysis.bootstrap_ci([]), ValueError, "values: expected at least 1"),
        (lambda: analysis.bootstrap_ci([1, np.nan]), ValueError, "values: value 1 is not finite"),
        (lambda: analysis.bootstrap_ci([[1, 2]]), ValueError, "values: expected a flat list"),
        (lambda: analysis.bootstrap_ci([1, 2], level=1), ValueError, "level: expected"),
        (lambda: analysis.bootstrap_test([1], [1, 2]), ValueError, "a: expected at least 2"),
        (lambda: analysis.bootstrap_test([1, 2], [1, 2], comparisons=0), ValueError,
         "comparisons: expected"),
        (lambda: analysis.bootstrap_tests({"a": [1, 2]}), ValueError, "samples: expected at least two"),
        (lambda: analysis.bootstrap_tests([[1, 2], [3, 4]]), TypeError, "samples: expected a dict"),
        (lambda: analysis.bonferroni(1.5, 3), ValueError, "p: expected"),
        (lambda: analysis.panel_seed(1, "G"), ValueError, "panel: expected"),
        (lambda: analysis.ci_seed(1, "A", "sideways"), ValueError, "treatment: expected"),
    ]
    for call, error, message in cases:
        with pytest.raises(error, match=message) as info:
            call()
        assert "\n" not in str(info.value), str(info.value)
    # Robot files and recorded lives are robots too (read as render reads them).
    robot.save(str(tmp_path / "champion.json"))
    run_cli("simulate", str(tmp_path / "champion.json"), "--record", str(tmp_path / "life.h5"),
            "--fps", "10")
    m = analysis.hausdorff([results[0], str(tmp_path / "champion.json"), tmp_path / "life.h5"])
    assert (m == 0).all()
    # A file that is not a results file is refused as a bad file, naming it.
    bad = tmp_path / "bad.h5"
    bad.write_bytes(b"not hdf5")
    with pytest.raises(plastivox.InputError, match="bad.h5"):
        analysis.hausdorff([robot, str(bad)])


@pytest.mark.parametrize("call", ["robustness", "hausdorff"])
def test_long_calls_release_the_gil(call):
    """While robustness's lives or the Hausdorff search run in C++, other Python threads run."""
    import time
    walker = plastivox.demo_walker().with_physics({"duration": 0.5})
    rng = np.random.default_rng(1)
    shape = (14, 14, 14)
    bodies = [walker] + [plastivox.Robot.from_arrays(rng.random(shape) < 0.3, np.full(shape, 1e9),
                                                     np.zeros(shape)) for _ in range(20)]

    def work():
        if call == "robustness":
            analysis.robustness(walker, draws=2, threads=1)
        else:
            analysis.hausdorff(bodies, rotations="all", threads=1)

    start = time.monotonic()
    turns = main_thread_turns(work)
    print(f"{call}: {time.monotonic() - start:.2f} s, {turns} turns")
    assert turns >= 20, f"{call}: the main thread ran {turns} times during the call"


def test_robustness_battery_equals_the_command_and_paper_is_r(study, tmp_path):
    stats, h5, results = study
    measured = [c["excluded"] is None for c in stats["champions"]]
    keep = [r for r, m in zip(results, measured) if m]
    # The paper battery is R: the same draws, the same bits.
    table = plastivox.robustness(keep, battery="paper", draws=DRAWS, seed=SEED, pandas=False)
    rob = analysis.robustness(keep, draws=DRAWS, seed=SEED)
    assert same_bits(table["kept"].reshape(len(keep), DRAWS), rob["r"])
    assert same_bits(table["f_reference"][::DRAWS], rob["f_train"])
    assert (table["status"] == "ok").all() and (table["kind"] == "paper").all()
    # The small battery gives the numbers plastivox robustness writes, life by life.
    out = tmp_path / "rb"
    run_cli("robustness", *[c["file"] for c in stats["champions"]], "--battery", "small",
            "--seed", str(SEED), "--resamples", str(RESAMPLES), "--threads", "2", "--out", str(out))
    written = json.load(open(out / "robustness.json"))
    small = plastivox.robustness(keep, battery="small", seed=SEED, pandas=False, threads=1)
    profiles = [c["profile"] for c in written["champions"] if "profile" in c]
    assert len(profiles) == len(keep)
    expected = [json_number(x) for p in profiles for q in p["perturbations"]
                for level in q["levels"] for x in level["kept"]]
    assert same_bits(small["kept"], expected)
    assert set(small["perturbation"]) == {"paper", "voxel-loss", "friction", "gravity"}
    if stats.get("robustness_battery") and stats["robustness_battery"]["name"] == "small":
        # A study analysed with the small battery (the default study's): its own stats.json.
        mine = [c["profile"] for c in stats["robustness_battery"]["champions"] if "profile" in c]
        assert same_bits(small["kept"], [json_number(x) for p in mine for q in p["perturbations"]
                                         for level in q["levels"] for x in level["kept"]])
    # A table: a pandas frame when pandas is there, else the same columns as numpy arrays.
    default = plastivox.robustness(keep[0], battery="small", seed=SEED)
    try:
        import pandas
        assert isinstance(default, pandas.DataFrame)
        assert same_bits(default["kept"].to_numpy(), small["kept"][small["robot"] == 0])
    except ImportError:
        assert isinstance(default, dict)
        assert same_bits(default["kept"], small["kept"][small["robot"] == 0])


def test_bad_battery_is_refused_naming_file_and_field(study, tmp_path):
    _, _, results = study
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps({"format": "plastivox-battery", "version": 1,
                               "perturbations": [{"kind": "friction", "severities": [1]}]}))
    with pytest.raises(ValueError, match=r"bad.json: perturbations\[0\].seeds: missing"):
        plastivox.robustness(results[0], battery=str(bad))
    with pytest.raises(ValueError, match="unknown built-in battery 'huge'|huge: cannot read"):
        plastivox.robustness(results[0], battery="huge")
