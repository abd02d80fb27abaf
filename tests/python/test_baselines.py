"""The summary logic of bench/baselines.py (docs/tasks.md, "Algorithms compared") on tiny
synthetic inputs: the budget, lives to reach a target with flagged champions skipped, and the
group's mean and bootstrap interval. No evolution runs here."""

import importlib.util
import os

import pytest

SOURCE = os.environ.get("PLASTIVOX_SOURCE_DIR",
                        os.path.join(os.path.dirname(__file__), "..", ".."))
spec = importlib.util.spec_from_file_location("baselines",
                                              os.path.join(SOURCE, "bench", "baselines.py"))
baselines = importlib.util.module_from_spec(spec)
spec.loader.exec_module(baselines)


def test_every_algorithm_gets_the_same_lives():
    for p in (3, 6, 16):
        lives = p * (p + 2)
        afpo = baselines.generations_for("afpo", p, lives)
        assert p + afpo * (p + 1) == lives
        for alg in ("map-elites", "cma-es"):
            assert p * (baselines.generations_for(alg, p, lives) + 1) == lives
    # the main job's budget: AFPO 6 + 12 x 7 = 90 lives, MAP-Elites 6 x 15
    assert baselines.generations_for("afpo", 6, 90) == 12
    assert baselines.generations_for("map-elites", 6, 90) == 14
    with pytest.raises(ValueError, match="cannot make exactly"):
        baselines.generations_for("afpo", 6, 91)


def test_lives_to_reach_skips_flagged_champions():
    lives = [10, 21, 32, 43, 54]
    records = [(0, 1, 0.5), (2, 7, 3.0), (3, 9, 2.5), (4, 12, 4.0)]
    replays = {1: ("", 0.5), 7: ("vertical", 3.0), 9: ("", 2.5), 12: ("", 4.0)}
    reach = baselines.lives_to_reach
    # the first record at 2.0 or more is flagged: the next unflagged one counts
    assert reach(records, lives, 2.0, replays.get) == 43
    assert reach(records, lives, 0.5, replays.get) == 10
    assert reach(records, lives, 3.5, replays.get) == 54
    # a replay below the target does not count, though its record is above it
    assert reach(records, lives, 2.5, {**replays, 9: ("", 2.4)}.get) == 54
    assert reach(records, lives, 5.0, replays.get) is None
    # every record at the target flagged: the judged champion's birth generation
    assert reach(records[:2], lives, 2.0, replays.get, fallback=1) == 21
    assert reach(records[:2], lives, 2.0, replays.get) is None


def test_reach_summary_counts_and_takes_the_median_of_those_reached():
    s = baselines.reach_summary([30, None, 10])
    assert (s["reached"], s["runs"], s["median"]) == (2, 3, 20)
    assert s["text"] == "20 (2/3 reached)"
    assert baselines.reach_summary([None, None])["text"] == "not reached"
    assert baselines.reach_summary([5, 7, 100])["median"] == 7


def test_group_mean_and_bootstrap_interval():
    values = [1.0, 1.4, 0.9, 1.2]
    s = baselines.summarise_group(values, baselines.plastivox_ci)
    assert s["n"] == 4 and s["mean"] == pytest.approx(1.125)
    assert min(values) <= s["low"] < s["mean"] < s["high"] <= max(values)
    from plastivox import analysis
    c = analysis.bootstrap_ci(values, resamples=baselines.BOOT_RESAMPLES, seed=baselines.BOOT_SEED)
    assert (s["low"], s["high"]) == (c["low"], c["high"])
    one = baselines.summarise_group([2.0], baselines.plastivox_ci)
    assert (one["mean"], one["low"], one["high"]) == (2.0, None, None)
    assert baselines.summarise_group([], baselines.plastivox_ci)["mean"] is None


def test_markdown_row():
    row = {"task": "walk", "algorithm": "map-elites", "runs": 3, "success": 1, "lives": 288,
           "fitness": {"mean": 1.5, "low": 1.0, "high": 2.0}, "cpu_seconds_mean": 30.4,
           "cpu_complete": True, "qd_score_mean": 12.34, "coverage_mean": 0.25,
           "lives_to_target": {"text": "96 (2/3 reached)"}}
    line = baselines.markdown([row]).splitlines()[2]
    assert line == ("| `walk` | map-elites | 1.50 [1.00, 2.00] | 1/3 | 12.3 (25 %) | 288 | 30 | "
                    "96 (2/3 reached) |")


def test_plan_counts_leave_out_flagged_and_slow_bodies():
    rows = [("Pi", 6.0, ""), ("Pi", 7.5, ""), ("Gamma", 9.0, "vertical"), ("Gamma", 2.0, ""),
            ("Upsilon", 5.0, ""), ("other", 12.0, "")]
    table, distinct = baselines.plan_counts(rows, 5.0)
    assert {p: table[p]["count"] for p in baselines.PLANS} == \
        {"Pi": 2, "Gamma": 0, "Upsilon": 1, "other": 1}
    assert table["Pi"]["best"] == 7.5 and table["Gamma"]["best"] is None
    assert distinct == ["Pi", "Upsilon"]  # "other" is no plan


def test_start_target_is_the_fixed_bodys_own_fitness_plus_a_margin():
    assert baselines.start_target(5.0, 0.1) == pytest.approx(5.5)
    assert baselines.start_target(2.0, 0.0) == 2.0
    # a start of nothing (slope's body not yet on a ramp) has no margin to beat
    assert baselines.start_target(0.0, 0.1) is None
    assert baselines.start_target(-0.3, 0.1) is None
    assert baselines.start_target(None, 0.1) is None


def test_markdown_cma_row_gives_lives_to_the_start_and_margin():
    row = {"task": "climb", "algorithm": "cma-es", "runs": 3, "success": 3, "lives": 288,
           "fitness": {"mean": 6.0, "low": 5.8, "high": 6.2}, "cpu_seconds_mean": 41.0,
           "cpu_complete": True, "start_fitness": 5.43, "start_margin": 0.1,
           "lives_to_target": {"text": "16 (3/3 reached)"},
           "lives_to_start_target": {"text": "48 (2/3 reached)"}}
    line = baselines.markdown([row]).splitlines()[2]
    assert line == ("| `climb` | cma-es | 6.00 [5.80, 6.20] (start 5.43) | 3/3 |  | 288 | 41 | "
                    "16 (3/3 reached); to start + 10 %: 48 (2/3 reached) |")


def test_start_margin_is_refused_below_zero():
    assert baselines.parse(["--out", "x"]).start_margin == 0.1
    assert baselines.parse(["--out", "x", "--start-margin", "0.2"]).start_margin == 0.2
    with pytest.raises(SystemExit):
        baselines.parse(["--out", "x", "--start-margin", "-0.1"])
