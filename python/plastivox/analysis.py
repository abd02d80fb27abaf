"""The paper's analysis of champions from Python, for robots from anywhere (docs/python.md,
"Analysis from Python"; the measures in docs/analysis.md).

Each function calls the C++ function `plastivox analyze` calls, with the arguments it passes,
so the same robots, stiffness and seeds give the same numbers, bit for bit:

- ``robustness``: R = F_test / F_train under random stiffness (panel C), per draw and the mean;
- ``canalization``: M_body, V_body and V_gain (panels D, E, F);
- ``hausdorff``: the pairwise Hausdorff distance matrix (panel B);
- ``body_plan``: the Π / Γ / Υ template scores and the class;
- ``bootstrap_ci``, ``bootstrap_test``, ``bootstrap_tests``, ``bonferroni``: the statistics;
- ``panel_seed``, ``ci_seed``, ``robustness_seed``, ``mix64``: the seeds analyze derives
  from its ``--seed``, to reproduce its numbers.

Wherever robots are taken, each may be a ``plastivox.Robot``, a robot or results file path, or
a ``plastivox.Results`` (its last champion, under the run's physics, with the final stiffness
the run stored: what analyze reads). Results are numpy arrays, plain floats and dicts.
"""

import os as _os

import numpy as _np

from . import _core

__all__ = ["robustness", "robustness_battery", "canalization", "hausdorff", "body_plan", "bootstrap_ci",
           "bootstrap_test", "bootstrap_tests", "bonferroni", "robustness_seed", "panel_seed",
           "ci_seed", "mix64", "PANELS"]

# analyze's panels, in order: panel_seed(seed, PANELS.index(id) + 1).
PANELS = ("A", "B", "C", "D", "E", "F")

_U64 = 2**64


# --- arguments -------------------------------------------------------------------------

class _Champion:
    """One robot to analyse: the Robot, and for a results file's champion the final stiffness
    the run stored (per voxel) and its own evaluation ("ok", "invalid", "unstable")."""

    def __init__(self, robot, final_stiffness=None, evaluation=None):
        self.robot, self.final_stiffness, self.evaluation = robot, final_stiffness, evaluation


def _champion(item, name):
    import plastivox
    if isinstance(item, plastivox.Results):
        core, lattice_final, evaluation, _, digest = _core.analysis_results_champion(item.path, -1)
        if digest != item.content_digest:
            raise plastivox.InputError(f"{item.path}: content_digest: the file changed since it "
                                       f"was read ({item.content_digest} then, {digest} now)")
        robot = plastivox.Robot(core)
        present = _np.asarray(core.present_flat) != 0
        return _Champion(robot, _np.asarray(lattice_final)[present], evaluation)
    if isinstance(item, (str, _os.PathLike)) and _os.fspath(item).endswith(".h5"):
        try:
            results = plastivox.read_results(item)
        except plastivox.InputError:  # a recorded life (its robot), or a bad file: render's way
            return _Champion(plastivox._as_robot(item, name))
        return _champion(results, name)
    if isinstance(item, (plastivox.Robot, str, _os.PathLike)):
        return _Champion(plastivox._as_robot(item, name))
    raise TypeError(f"{name}: expected a plastivox.Robot, a plastivox.Results or a robot or "
                    f"results file path, got {type(item).__name__}")


def _champions(robots, name="robots"):
    """(list of _Champion, whether one robot was given rather than a list)."""
    import plastivox
    if isinstance(robots, (plastivox.Robot, plastivox.Results, str, _os.PathLike)):
        return [_champion(robots, name)], True
    try:
        items = list(robots)
    except TypeError:
        raise TypeError(f"{name}: expected a robot, a results file or a list of them, got "
                        f"{type(robots).__name__}") from None
    if not items:
        raise ValueError(f"{name}: the list is empty")
    return [_champion(r, f"{name}[{i}]") for i, r in enumerate(items)], False


def _int(value, name, least, most=2**30):
    if isinstance(value, bool) or not isinstance(value, (int, _np.integer)):
        raise TypeError(f"{name}: expected a whole number, got {type(value).__name__}")
    if not least <= value <= most:
        raise ValueError(f"{name}: expected a whole number in [{least}, {most}], got {value}")
    return int(value)


def _seed(value, name="seed"):
    return _int(value, name, 0, _U64 - 1)


def _fraction(value, name):
    if isinstance(value, bool) or not isinstance(value, (int, float, _np.floating)) or \
            not 0 < value < 1:
        raise ValueError(f"{name}: expected a number in (0, 1), got {value!r}")
    return float(value)


def _choice(value, name, choices):
    if value not in choices:
        raise ValueError(f"{name}: expected one of {', '.join(choices)}, got {value!r}")
    return value


def _sample(values, name, least=1):
    """values as a 1-D float64 array of at least `least` finite numbers."""
    if isinstance(values, (str, bytes, dict)):
        raise TypeError(f"{name}: expected a list or array of numbers, got {type(values).__name__}")
    try:
        a = _np.asarray(values, dtype=_np.float64)
    except (TypeError, ValueError) as e:
        raise ValueError(f"{name}: not an array of numbers: {e}") from None
    if a.ndim != 1:
        raise ValueError(f"{name}: expected a flat list of numbers, got shape {a.shape}")
    if a.size < least:
        raise ValueError(f"{name}: expected at least {least} values, got {a.size}")
    if not _np.isfinite(a).all():
        raise ValueError(f"{name}: value {int(_np.flatnonzero(~_np.isfinite(a))[0])} is not finite")
    return _np.ascontiguousarray(a)


def _threads(threads):
    return _int(threads, "threads", 0, 4096)


def _body(robot, lattice_flat):
    """A lattice-sized flat array's values at the robot's voxels, in increasing site order
    (body_values, as the study reads E0 and alpha)."""
    return _np.asarray(lattice_flat)[_np.asarray(robot._core.present_flat) != 0]


def _one(result, single):
    """A result over robots, or its only element when one robot was given."""
    return {k: (v[0] if single and isinstance(v, (_np.ndarray, list)) else v)
            for k, v in result.items()}


# --- seeds -----------------------------------------------------------------------------

def robustness_seed(robot, seed=1):
    """The seed of `robot`'s robustness draws in a study run with ``--seed seed``: a hash of
    the seed and the robot's phenotype digest (its lattice, voxel size and arrays; not its
    name), so it depends on the robot, not on its place among the champions. analysis.h5
    stores it per champion (champions/robustness_seed)."""
    (c,), _ = _champions([robot], "robot")
    return _core.analysis_robustness_seed(_seed(seed), c.robot._core)


def mix64(x):
    """SplitMix64's finaliser of a 64-bit integer: how analyze derives one seed from another
    (docs/analysis.md, "Random numbers"); pair k of ``bootstrap_tests`` uses
    mix64(seed + k)."""
    return _core.analysis_mix64(_seed(x, "x"))


def panel_seed(seed, panel):
    """The seed analyze (``--seed seed``) resamples panel `panel` ("A" ... "F") with:
    mix64(seed ^ mix64(p)), p = 1 for A ... 6 for F. Its tests are
    ``bootstrap_tests(samples, seed=panel_seed(...))``; stats.json records it as the panel's
    ``seed``."""
    return _core.analysis_panel_seed(_seed(seed), PANELS.index(_choice(panel, "panel", PANELS)) + 1)


def ci_seed(seed, panel, treatment):
    """The seed of treatment `treatment`'s confidence interval in panel `panel` of a study run
    with ``--seed seed``: mix64(panel_seed + 1 + t), t = 0 for none, 1 stress, 2 pressure."""
    import plastivox
    plastivox._check_treatment(treatment)
    if treatment is None:
        raise ValueError("treatment: expected a treatment name, got None")
    return _core.analysis_group_ci_seed(panel_seed(seed, panel), treatment)


# --- the measures ----------------------------------------------------------------------

def robustness(robots, draws=10, seed=1, sampling="linear", e_range=None, physics=None,
               threads=0, stream_seed=None):
    """R = F_test / F_train (the paper's Eq. 2, panel C) of each robot, as analyze measures
    it: development removed (every alpha 0, treatment none), F_train its fitness with its own
    stiffness, F_test that of draw k with every voxel's stiffness drawn from [E_lo, E_hi]
    (``sampling`` "linear": uniform, as the authors; "log": log-uniform). ``e_range`` (lo, hi)
    in Pa, default the physics' [e_min, e_max]; ``physics`` as simulate takes it (default each
    robot's own: a results file's champion runs under the run's physics).

    Draw k of a robot comes from the stream (stream seed, robustness, k): the stream seed is
    ``robustness_seed(robot, seed)``, as analyze ``--seed seed`` derives it for the champion,
    so ``seed`` and ``draws`` equal to analyze's ``--seed`` and ``--robustness-draws`` give its
    numbers. ``stream_seed`` sets the stream seed itself instead. Robots run in parallel on
    ``threads`` threads (0: all cores), each one's 1 + draws lives on the spare ones, as analyze
    runs them; the numbers do not depend on it.

    Returns a dict of numpy arrays over the robots (for one robot, its own values): ``r`` and
    ``f_test`` (robots, draws), NaN where a draw went unstable; ``valid`` (bool, same shape);
    ``f_train`` (NaN when the training life was unstable or F_train = 0: no R then); ``r_mean``
    (the mean over valid draws, NaN when none); ``valid_draws``; ``seed`` (the stream seeds,
    uint64); ``failures`` (per robot, per draw, "" or why the draw is invalid); and the
    ``distribution``, ``e_lo``, ``e_hi`` used."""
    champions, single = _champions(robots)
    draws = _int(draws, "draws", 1, 1_000_000)
    seed = _seed(seed)
    _choice(sampling, "sampling", ("linear", "log"))
    e_lo = e_hi = 0.0
    if e_range is not None:
        try:
            e_lo, e_hi = (float(x) for x in e_range)
        except (TypeError, ValueError):
            raise ValueError(f"e_range: expected (lo, hi) in Pa, got {e_range!r}") from None
        if not (0 < e_lo <= e_hi < _np.inf):
            raise ValueError(f"e_range: expected 0 < lo <= hi, finite, got ({e_lo}, {e_hi})")
    import plastivox
    physics = plastivox._physics(physics)
    threads = _threads(threads)
    if stream_seed is not None:
        stream_seed = _seed(stream_seed, "stream_seed")
    out = {"r": [], "f_test": [], "valid": [], "f_train": [], "r_mean": [], "valid_draws": [],
           "seed": [], "failures": []}
    seeds = [stream_seed if stream_seed is not None else
             _core.analysis_robustness_seed(seed, c.robot._core) for c in champions]
    lives = _core.analysis_robustness([c.robot._core for c in champions], physics, seeds, draws,
                                      sampling, e_lo, e_hi, threads)
    for d in lives:
        valid = _np.asarray(d["valid"], bool)  # a draw is valid only with a valid F_train
        out["r"].append(_np.where(valid, d["r"], _np.nan))
        out["f_test"].append(_np.where(valid, d["f_test"], _np.nan))
        out["valid"].append(valid)
        out["f_train"].append(d["f_train"] if d["train_valid"] else _np.nan)
        out["r_mean"].append(d["mean_r"] if d["valid_draws"] > 0 else _np.nan)
        out["valid_draws"].append(d["valid_draws"])
        out["seed"].append(d["seed"])
        out["failures"].append(list(d["failures"]))
        for k in ("distribution", "e_lo", "e_hi"):
            out[k] = d[k]
    dtypes = {"r": float, "f_test": float, "valid": bool, "f_train": float, "r_mean": float,
              "valid_draws": int, "seed": _np.uint64}
    for k, t in dtypes.items():
        out[k] = _np.array(out[k], dtype=t)
    return _one(out, single)


_BATTERY_COLUMNS = ("robot", "perturbation", "kind", "severity", "severity_unit", "seed",
                    "fitness", "kept", "status", "failure", "f_reference", "mean_kept", "sd_kept",
                    "auc")


def robustness_battery(robots, battery="default", seed=1, draws=10, physics=None, threads=0,
                       pandas=None):
    """The robustness battery (docs/analysis.md, "Robustness battery") on each robot, as
    ``plastivox robustness`` and ``analyze --battery`` run it: every perturbation of the battery
    at each of its severities and seeds, one life each; fitness kept = F_perturbed /
    F_unperturbed (for ``paper``: F_train without development, as R). ``battery`` is
    "default", "paper" (Eq. 2 alone, ``draws`` seeds: its kept values are ``robustness``'s R,
    bit for bit), "small" or a battery file. ``seed`` as analyze's ``--seed`` (each robot's
    stream seed is ``robustness_seed(robot, seed)``). Also ``plastivox.robustness``.

    Returns a table with one row per life: robot (index), perturbation, kind, severity,
    severity_unit, seed, fitness (NaN for an unstable or sunk life), kept (NaN unless valid),
    status ("ok", "unstable", "sank" or "no-reference"), failure, f_reference, and the
    perturbation-level mean_kept, sd_kept (over valid lives at that severity) and auc. A
    pandas DataFrame when pandas is importable (``pandas=False``: always a dict of numpy arrays;
    ``pandas=True``: pandas required). A bad battery raises ValueError naming the file and field
    before any life is simulated."""
    champions, _ = _champions(robots)
    if not isinstance(battery, (str, _os.PathLike)):
        raise TypeError(f"battery: expected default, paper, small or a file path, got "
                        f"{type(battery).__name__}")
    seed = _seed(seed)
    draws = _int(draws, "draws", 1, 1_000_000)
    import plastivox
    physics = plastivox._physics(physics)
    threads = _threads(threads)
    seeds = [_core.analysis_robustness_seed(seed, c.robot._core) for c in champions]
    profiles = _core.analysis_battery([c.robot._core for c in champions], physics, seeds,
                                      _os.fspath(battery), draws, threads)
    table = {k: [] for k in _BATTERY_COLUMNS}
    for i, p in enumerate(profiles):
        table["robot"].append(_np.full(len(p["severity"]), i, dtype=int))
        for k in _BATTERY_COLUMNS[1:]:
            table[k].append(_np.asarray(p[k], dtype=object if isinstance(p[k], list) else None))
    out = {k: _np.concatenate(v) for k, v in table.items()}
    for k in ("perturbation", "kind", "severity_unit", "status", "failure"):
        out[k] = out[k].astype(str)
    if pandas is False:
        return out
    try:
        import pandas as _pandas
    except ImportError:
        if pandas:
            raise
        return out
    return _pandas.DataFrame(out)


def _final_stiffness(champions, final_stiffness, threads):
    """Per champion its final stiffness per voxel: given, stored by the run, or simulated."""
    import plastivox
    n = len(champions)
    if final_stiffness is None:
        given = [None] * n
    else:
        if isinstance(final_stiffness, (_np.ndarray, plastivox.Result)) and n == 1:
            final_stiffness = [final_stiffness]
        given = list(final_stiffness)
        if len(given) != n:
            raise ValueError(f"final_stiffness: {len(given)} entries for {n} robots")
    missing = [i for i, (c, f) in enumerate(zip(champions, given))
               if f is None and c.final_stiffness is None]
    if missing:  # robots from elsewhere: their lives, simulated under their own physics
        lives = plastivox.simulate_many([champions[i].robot for i in missing], threads=threads)
        for i, life in zip(missing, lives):
            given[i] = life
    out = []
    for i, (c, f) in enumerate(zip(champions, given)):
        if f is None:
            out.append(c.final_stiffness)
            continue
        if isinstance(f, plastivox.Result):
            f = f.final_stiffness
        a = _np.asarray(f, dtype=_np.float64)
        if a.shape == c.robot.shape:
            a = _np.ravel(a, order="F")[_np.asarray(c.robot._core.present_flat) != 0]
        if a.shape != (c.robot.voxel_count,):
            raise ValueError(f"final_stiffness[{i}]: expected {c.robot.voxel_count} values (one "
                             f"per voxel) or shape {c.robot.shape}, got shape {a.shape}")
        out.append(_np.ascontiguousarray(a))
    return out


def canalization(robots, final_stiffness=None, alpha_range=None, threads=0):
    """M_body, V_body and V_gain (panels D, E, F) of each robot, as analyze computes them.

    M_body and V_body are the mean and population variance of |E+/E0 - 1| over the body, E0
    the robot's congenital stiffness and E+ its final stiffness: ``final_stiffness`` per robot
    (an array of one value per voxel, in increasing site order, or (nx, ny, nz)-shaped; or a
    plastivox.Result of its life), else the one a results file stored for its champion (what
    analyze reads), else the robot is simulated under its own physics (``threads``).

    V_gain is the population variance of alpha normalised over ``alpha_range`` (lo, hi) in
    1/s; by default, as analyze, the range that evolved in each robot's treatment: the
    smallest and largest alpha over the body voxels of the robots given with that treatment.
    Under treatment none V_gain is undefined.

    Returns a dict: ``m_body``, ``v_body``, ``v_gain`` (numpy arrays over the robots, NaN where
    undefined: V_gain under none or when the range is empty, M_body and V_body of a results
    file's champion whose own evaluation failed, as analyze leaves them; for one robot, its
    own floats) and ``alpha_ranges`` ({treatment: (lo, hi)})."""
    champions, single = _champions(robots)
    threads = _threads(threads)
    finals = _final_stiffness(champions, final_stiffness, threads)
    if alpha_range is not None:
        try:
            lo, hi = (float(x) for x in alpha_range)
        except (TypeError, ValueError):
            raise ValueError(f"alpha_range: expected (lo, hi) in 1/s, got {alpha_range!r}") from None
        if not (_np.isfinite(lo) and _np.isfinite(hi) and lo < hi):
            raise ValueError(f"alpha_range: expected finite lo < hi, got ({lo}, {hi})")
    alphas = [_body(c.robot, c.robot._core.dev_rate_flat) for c in champions]
    ranges = {}
    for c, a in zip(champions, alphas):
        t = c.robot.treatment
        if t != "none":
            ranges.setdefault(t, []).append(a)
    ranges = {t: (lo, hi) if alpha_range is not None else _core.analysis_alpha_range(a)
              for t, a in ranges.items()}
    m_body, v_body, v_gain = [], [], []
    for c, e_final, a in zip(champions, finals, alphas):
        e0 = _body(c.robot, c.robot._core.stiffness_flat)
        if c.evaluation in (None, "ok"):
            m, v = _core.analysis_canalization(e0, e_final)
        else:
            m = v = _np.nan
        m_body.append(m)
        v_body.append(v)
        r = ranges.get(c.robot.treatment)
        v_gain.append(_core.analysis_v_gain(a, *r) if r and r[1] > r[0] else _np.nan)
    out = {"m_body": _np.array(m_body), "v_body": _np.array(v_body), "v_gain": _np.array(v_gain)}
    out = _one(out, single)
    out["alpha_ranges"] = ranges
    return out


def hausdorff(robots, rotations="paper", translation=None, threads=0, placements=False):
    """The Hausdorff distance between every two robots' filled voxels (panel B), in voxel
    lengths: an (n, n) symmetric numpy matrix, zero diagonal, as analyze's matrix. Entry
    (i, j), i < j, is minimised over the placements of robot j: ``rotations`` "none", "paper"
    (the paper's 8 orientations, analyze's default) or "all" (the 24 cube rotations);
    ``translation`` "none" or "integer" (the optimal integer shift), default "integer" with
    "all" and "none" otherwise, as analyze. With ``placements=True`` returns (matrix, dict):
    per pair (0,1), (0,2), ..., (1,2), ... its ``pairs`` (i, j), ``rotation_index``,
    ``rotation`` (the image of (x,y,z)) and ``translation``: robot j's voxel b is placed at
    R b + t."""
    champions, _ = _champions(robots)
    _choice(rotations, "rotations", ("none", "paper", "all"))
    if translation is None:
        translation = "integer" if rotations == "all" else "none"
    _choice(translation, "translation", ("none", "integer"))
    matrix, index, names, shift = _core.analysis_hausdorff_matrix(
        [c.robot._core for c in champions], rotations, translation, _threads(threads))
    if not placements:
        return matrix
    n = len(champions)
    pairs = _np.array([(i, j) for i in range(n) for j in range(i + 1, n)], dtype=int).reshape(-1, 2)
    return matrix, {"pairs": pairs, "rotation_index": _np.asarray(index), "rotation": list(names),
                    "translation": _np.asarray(shift)}


def body_plan(robots, threshold=0.75):
    """The body plan of each robot by analyze's rule (docs/analysis.md, "Body plans"): a dict
    with ``plan`` ("Pi", "Gamma", "Upsilon" or "other"), ``confidence``, ``margin``,
    ``scores`` (numpy: the best Π, Γ, Υ template scores, in that order), ``matches`` (each
    plan's best template: score, fill, empty, inside, quarter_turns, parameters), ``voxels``,
    ``extent``, ``box_fill`` and ``footprint_components``. A list of robots gives a list."""
    champions, single = _champions(robots)
    if isinstance(threshold, bool) or not isinstance(threshold, (int, float)) or \
            not 0 <= threshold <= 1:
        raise ValueError(f"threshold: expected a score in [0, 1], got {threshold!r}")
    out = []
    for c in champions:
        d = _core.analysis_body_plan(c.robot._core, float(threshold))
        d["scores"] = _np.array([m["score"] for m in d["matches"]])
        out.append(d)
    return out[0] if single else out


# --- statistics ------------------------------------------------------------------------

def bootstrap_ci(values, level=0.95, resamples=10000, seed=1):
    """The percentile bootstrap confidence interval of the mean of `values`, as analyze
    computes each group's (``seed = ci_seed(study seed, panel, treatment)``, ``resamples`` its
    ``--resamples``): `resamples` resampled means, their quantiles at (1 -+ level)/2,
    interpolated as numpy's percentile. Returns a dict of ``mean``, ``low``, ``high`` and
    ``n``, ``level``, ``resamples``, ``seed``, ``method``."""
    x = _sample(values, "values")
    return _core.analysis_bootstrap_ci(x, _fraction(level, "level"),
                                       _int(resamples, "resamples", 2, 10_000_000), _seed(seed))


def _test_args(resamples, seed, null, level, comparisons):
    return (_int(resamples, "resamples", 1, 10_000_000), _seed(seed),
            _choice(null, "null", ("pooled", "shifted-means")), _fraction(level, "level"),
            _int(comparisons, "comparisons", 1))


def bootstrap_test(a, b, resamples=10000, seed=1, null="pooled", level=0.05, comparisons=1):
    """The two-sample bootstrap test of mean(a) - mean(b), two-sided (docs/analysis.md): null
    "pooled" (Efron & Tibshirani's Alg. 16.1, analyze's) or "shifted-means" (16.2);
    ``comparisons`` > 1 applies Bonferroni's correction. Each sample needs at least two values.
    Returns a dict: ``p``, ``p_corrected``, ``significant`` (p_corrected < level), ``stars``,
    ``difference``, ``mean_a``, ``mean_b``, ``n_a``, ``n_b``, ``cohens_d``, ``hedges_g``,
    ``pooled_sd`` and how it was made (test, null_model, correction, comparisons, level,
    resamples, seed)."""
    return _core.analysis_bootstrap_test(_sample(a, "a", 2), _sample(b, "b", 2),
                                         *_test_args(resamples, seed, null, level, comparisons))


def bootstrap_tests(samples, resamples=10000, seed=1, null="pooled", level=0.05,
                    comparisons=None):
    """Every pair of samples tested as analyze tests a panel's treatments: `samples` a dict
    {name: values} (in analyze's order: none, stress, pressure), pairs (0,1), (0,2), ...,
    (1,2), ...; pair k resamples with seed mix64(seed + k) and is Bonferroni-corrected for the
    number of pairs unless ``comparisons`` gives another factor. With ``seed =
    panel_seed(study seed, panel)`` and analyze's ``--resamples`` these are its comparisons
    (analyze then hides the stars of a comparison whose treatments have fewer than 20
    champions; the p-values are these). Returns a list of bootstrap_test's dicts, with ``a``
    and ``b`` the names."""
    if not isinstance(samples, dict):
        raise TypeError(f"samples: expected a dict of name: values, got {type(samples).__name__}")
    if len(samples) < 2:
        raise ValueError(f"samples: expected at least two samples, got {len(samples)}")
    names = [str(k) for k in samples]
    values = [_sample(v, f"samples[{k!r}]", 2) for k, v in samples.items()]
    return _core.analysis_bootstrap_tests(
        names, values, *_test_args(resamples, seed, null, level,
                                   1 if comparisons is None else comparisons))


def bonferroni(p, comparisons):
    """Bonferroni's correction: min(1, p * comparisons)."""
    if isinstance(p, bool) or not isinstance(p, (int, float, _np.floating)) or not 0 <= p <= 1:
        raise ValueError(f"p: expected a probability in [0, 1], got {p!r}")
    return _core.analysis_bonferroni(float(p), _int(comparisons, "comparisons", 1))
