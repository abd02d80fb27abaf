"""evolve, read_results and read_study: the same runs and files as the command line."""

import json
import os
import signal
import warnings

import numpy as np
import pytest

import plastivox
from conftest import run_cli, tiny_config


def test_read_results_champion_is_what_export_writes(tiny_run, tmp_path):
    path, config = tiny_run
    res = plastivox.read_results(path)
    assert res.treatment == "pressure" and res.seed == config["seed"]
    assert res.generations_done == 2 and res.generations == 2 and res.finished
    assert res.config["population"] == 4
    assert res.provenance["plastivox_version"] == plastivox.__version__
    assert set(res.provenance) == {  # the file's provenance attributes, by the same names
        "plastivox_version", "git_commit", "compiler", "compiler_flags", "build_type",
        "date_created", "date_updated", "host", "threads", "wall_seconds", "fitness_function"}
    assert res.provenance["fitness_function"] == "built-in"
    assert isinstance(res.provenance["threads"], int)
    assert isinstance(res.provenance["wall_seconds"], float)
    assert res.best_fitness.shape == (3,) and res.mean_fitness.shape == (3,)
    assert np.all(np.diff(res.best_fitness) >= 0)  # AFPO keeps its best
    assert np.all(res.mean_fitness <= res.best_fitness)
    for generation in (-1, 0, 2):
        exported = tmp_path / f"champion{generation}.json"
        args = ["export", path, "--out", str(exported)]
        if generation >= 0:
            args += ["--generation", str(generation)]
        run_cli(*args)
        want = plastivox.load_robot(exported)
        got = res.champion(generation)
        for field in ("geometry", "stiffness", "phase", "dev_rate"):
            assert np.array_equal(getattr(got, field), getattr(want, field)), field
        assert got.physics == want.physics and got.name == want.name
    # the champion simulates to its recorded fitness
    assert plastivox.simulate(res.champion()).fitness == res.best_fitness[-1]
    with pytest.raises(plastivox.InputError, match="generation"):
        res.champion(7)


def test_bad_results_files(tmp_path):
    with pytest.raises(plastivox.InputError, match="nothing.h5"):
        plastivox.read_results(tmp_path / "nothing.h5")
    junk = tmp_path / "junk.h5"
    junk.write_bytes(b"not hdf5 at all" * 10)
    with pytest.raises(plastivox.InputError, match="junk.h5"):
        plastivox.read_results(junk)
    # A recorded life is named as one, not "not HDF5, or its header is damaged".
    walker = tmp_path / "walker.json"
    plastivox.demo_walker().with_physics({"duration": 0.05, "settle_time": 0}).save(walker)
    life = tmp_path / "life.h5"
    run_cli("simulate", str(walker), "--record", str(life))
    with pytest.raises(plastivox.InputError,
                       match="life.h5: a recorded life, not an evolution results file"):
        plastivox.read_results(life)
    with pytest.raises(plastivox.InputError, match="population"):
        plastivox.evolve({**tiny_config(), "population": 0}, str(tmp_path / "x.h5"))
    with pytest.raises(TypeError, match="config"):
        plastivox.evolve(42, str(tmp_path / "x.h5"))


def test_evolve_matches_the_cli_and_resumes(tmp_path, tiny_run):
    path, config = tiny_run
    import json
    cfg = tmp_path / "tiny.json"
    cfg.write_text(json.dumps(config))
    cli_out = tmp_path / "cli.h5"
    run_cli("evolve", "--config", str(cfg), "--out", str(cli_out), "--threads", "1")
    digest = plastivox.read_results(cli_out).content_digest
    assert plastivox.read_results(path).content_digest == digest
    # stopped after generation 1, then resumed from the file path config: same science
    out = str(tmp_path / "resumed.h5")
    seen = []
    stopped = plastivox.evolve(str(cfg), out, threads=2, stop_after=1,
                               on_generation=lambda p: seen.append(p["generation"]))
    assert stopped["outcome"] == "stopped" and stopped["generations_done"] == 1
    assert seen == [0, 1]
    messages = []
    done = plastivox.evolve(str(cfg), out, threads=1, on_message=messages.append)
    assert done["outcome"] == "finished" and done["resumed_from"] == 1
    assert any("resuming" in m for m in messages)
    assert plastivox.read_results(out).content_digest == digest
    again = plastivox.evolve(str(cfg), out)
    assert again["outcome"] == "already-finished"


def test_ctrl_c_stops_at_a_checkpoint(tmp_path):
    config = tiny_config(generations=4)
    out = str(tmp_path / "interrupted.h5")
    def interrupt(progress):
        if progress["generation"] == 1:
            os.kill(os.getpid(), signal.SIGINT)  # what Ctrl-C does
    with pytest.raises(KeyboardInterrupt):
        plastivox.evolve(config, out, threads=1, on_generation=interrupt)
    partial = plastivox.read_results(out)
    assert 1 <= partial.generations_done < 4 and not partial.finished
    done = plastivox.evolve(config, out, threads=1)
    assert done["outcome"] == "finished" and done["resumed_from"] == partial.generations_done
    whole = str(tmp_path / "whole.h5")
    plastivox.evolve(config, whole, threads=1)
    assert plastivox.read_results(out).content_digest == plastivox.read_results(whole).content_digest


def test_callback_error_stops_and_propagates(tmp_path):
    out = str(tmp_path / "cb.h5")
    def fail(progress):
        raise RuntimeError("my optimiser broke")
    with pytest.raises(RuntimeError, match="my optimiser broke"):
        plastivox.evolve(tiny_config(generations=4), out, threads=1, on_generation=fail)
    assert not plastivox.read_results(out).finished


def test_read_study(tiny_run, tmp_path):
    path, _ = tiny_run
    study_dir = tmp_path / "study"
    run_cli("analyze", path, "--out", str(study_dir), "--robustness-draws", "1",
            "--resamples", "100", "--threads", "1")
    study = plastivox.read_study(study_dir)
    assert study.stats["format"] == "plastivox-analysis"
    assert len(study.champions) == 1
    champ = study.champions[0]
    assert champ["treatment"] == "pressure"
    assert champ["fitness"] == plastivox.read_results(path).best_fitness[-1]
    assert isinstance(champ["voxels"], int)
    assert champ["vertical_exploit"] is (champ["status"] == "vertical")  # a bool, not "false"
    assert study.statistics and all("kind" in row for row in study.statistics)
    with pytest.raises(plastivox.InputError, match="stats.json"):
        plastivox.read_study(tmp_path)
    # Damaged tables are refused, naming the file, not read as rows of nonsense.
    import shutil
    for name, text, expect in [
            ("champions.csv", "damaged\n" * 7, "not a plastivox table: no column 'label'"),
            ("champions.csv", None, "2 rows where stats.json lists 1"),
            ("statistics.csv", "a,b\n1,2\n", "not a plastivox table: no column 'kind'"),
            ("champions.csv", "\x00\xff\n", None)]:
        damaged = tmp_path / f"damaged-{name}-{len(text or '')}"
        shutil.copytree(study_dir, damaged)
        table = damaged / name
        if text is None:  # one row too many
            lines = table.read_text().splitlines(keepends=True)
            table.write_text("".join(lines + lines[1:]))
        else:
            table.write_bytes(text.encode("latin-1"))
        with pytest.raises(plastivox.InputError, match=name + (": " + expect if expect else "")):
            plastivox.read_study(damaged)


def test_ctrl_c_from_outside_during_a_long_run(tmp_path):
    """A real SIGINT arriving while the run is in C++ (GIL released): the process ends with
    KeyboardInterrupt after a checkpoint, and the file resumes."""
    import json
    import subprocess
    import sys
    import time
    config = tiny_config(generations=100000)
    cfg = tmp_path / "long.json"
    cfg.write_text(json.dumps(config))
    out = tmp_path / "long.h5"
    script = ("import sys, plastivox\n"
              "plastivox.evolve(sys.argv[1], sys.argv[2], threads=1)\n")
    p = subprocess.Popen([sys.executable, "-c", script, str(cfg), str(out)],
                         stderr=subprocess.PIPE, text=True)
    deadline = time.time() + 120
    while not out.exists() and time.time() < deadline:  # the first checkpoint is written
        time.sleep(0.05)
    assert out.exists()
    p.send_signal(signal.SIGINT)
    _, err = p.communicate(timeout=120)
    assert p.returncode != 0 and "KeyboardInterrupt" in err
    partial = plastivox.read_results(out)
    assert 0 <= partial.generations_done < 100000
    again = plastivox.evolve(str(cfg), str(out), threads=1,
                             stop_after=partial.generations_done + 1)
    assert again["outcome"] == "stopped" and again["resumed_from"] == partial.generations_done


def test_evolve_treats_a_sunk_life_as_unstable(tmp_path):
    # Every body soft (E <= 2e5 Pa) and heavy: every life sinks through the floor.
    config = tiny_config(generations=1)
    config["physics"] = {**config["physics"], "duration": 1.0, "e_max": 2e5, "act_frequency": 1}
    seen = []
    plastivox.evolve(config, str(tmp_path / "s.h5"), threads=1, on_generation=seen.append)
    assert seen and all(g["sank"] == g["simulated"] > 0 for g in seen)
    assert all(g["unstable"] == g["simulated"] for g in seen)
    assert max(plastivox.read_results(str(tmp_path / "s.h5")).best_fitness) < 0  # none scored
    # The authors' rule scores them.
    config["physics"]["sinking_invalid"] = False
    seen = []
    plastivox.evolve(config, str(tmp_path / "a.h5"), threads=1, on_generation=seen.append)
    assert all(g["sank"] == g["simulated"] and g["unstable"] == 0 for g in seen)


def test_ask_tell_with_the_engines_scores_gives_evolves_digest(tmp_path, tiny_run):
    """Scoring each asked robot with plastivox.simulate is the engine's own evolution."""
    path, config = tiny_run
    out = str(tmp_path / "asked.h5")
    asked = []
    with plastivox.Evolver(config, out, threads=1, name="simulate") as ev:
        while not ev.finished:
            robots = ev.ask()
            assert all(isinstance(r, plastivox.Robot) and r.voxel_count > 0 for r in robots)
            asked.append(len(robots))
            ev.tell(plastivox.simulate_many(robots, threads=1))
        assert ev.ask() == [] and ev.report["outcome"] == "finished"
    assert len(asked) == 3 and asked[0] >= 1  # generations 0, 1 and 2
    mine, theirs = plastivox.read_results(out), plastivox.read_results(path)
    assert mine.content_digest == theirs.content_digest
    assert mine.provenance["fitness_function"] == "python: simulate"
    assert theirs.provenance["fitness_function"] == "built-in"
    # another scorer may not continue a file: the science would change mid-run
    with pytest.raises(plastivox.InputError, match="scored by fitness python: simulate, now by "
                                                   "built-in"):
        plastivox.evolve(config, out, threads=1)


def test_ask_tell_numbers_close_resume_and_bad_scores(tmp_path):
    config = tiny_config(generations=3)
    out = str(tmp_path / "numbers.h5")

    def score(robot):  # a made-up task: fewer voxels is better
        return -float(robot.voxel_count)

    ev = plastivox.Evolver(config, out, threads=1, name="fewest voxels")
    robots = ev.ask()
    with pytest.raises(RuntimeError, match="tell"):
        ev.ask()
    with pytest.raises(ValueError, match=f"scores: expected {len(robots)}"):
        ev.tell([1.0] * (len(robots) + 1))
    with pytest.raises(TypeError, match=r"scores\[0\]: expected a number"):
        ev.tell(["fast"] * len(robots))
    scores = [score(r) for r in robots]
    scores[0] = float("nan")  # a failed life: worst fitness, never a finding
    ev.tell(scores)
    robots = ev.ask()
    ev.tell([score(r) for r in robots])
    ev.close()  # generation 2 asked or not: dropped; the file stands at generation 1
    assert not ev._thread.is_alive()
    res = plastivox.read_results(out)
    assert res.generations_done == 1 and not res.finished
    assert np.all(res.best_fitness < 0)
    with plastivox.Evolver(config, out, threads=1, name="fewest voxels") as again:
        while not again.finished:
            again.tell([score(r) for r in again.ask()])
    done = plastivox.read_results(out)
    assert done.finished and done.provenance["fitness_function"] == "python: fewest voxels"
    # the champion is the smallest valid body scored, and it carries its life's stiffness
    assert done.best_fitness[-1] == -done.champion().voxel_count
    with pytest.raises(plastivox.InputError, match="scored by fitness python: fewest voxels, "
                                                   "now by python: other"):
        with plastivox.Evolver(config, out, threads=1, name="other") as e:
            e.ask()


def test_evolve_with_a_fitness_function_sees_trajectories(tmp_path):
    config = tiny_config(generations=1)
    seen = []

    def height(result):  # the highest any voxel reached: needs the trajectory
        seen.append(result.trajectory.positions.shape)
        return float(result.trajectory.positions[..., 2].max())

    out = str(tmp_path / "height.h5")
    report = plastivox.evolve(config, out, threads=1, fitness=height, record_fps=20)
    assert report["outcome"] == "finished" and seen
    assert all(len(shape) == 3 and shape[2] == 3 for shape in seen)
    res = plastivox.read_results(out)
    assert res.provenance["fitness_function"].startswith("python: ")
    assert res.provenance["fitness_function"].endswith("height")
    champion = plastivox.simulate(res.champion(), record_fps=20)
    assert res.best_fitness[-1] == float(champion.trajectory.positions[..., 2].max())

    def broken(result):
        raise KeyError("no such sensor")

    with pytest.raises(KeyError, match="no such sensor"):
        plastivox.evolve(config, str(tmp_path / "broken.h5"), threads=1, fitness=broken)
    assert not os.path.exists(tmp_path / "broken.h5")  # generation 0 was never scored


def test_the_checkpoint_population_decodes_into_robots_that_score_as_recorded(tiny_run):
    path, config = tiny_run
    res = plastivox.read_results(path)
    people = res.population()
    assert len(people) == config["population"]
    assert [p["id"] for p in people] == sorted(p["id"] for p in people)
    for p in people:
        assert set(p) == {"id", "parent_id", "age", "born", "fitness", "status", "robot"}
        if p["status"] == "invalid":
            assert p["robot"] is None
            continue
        robot = p["robot"]
        assert robot.name == f"individual-{p['id']}" and robot.physics == res.champion().physics
        assert plastivox.simulate(robot).fitness == p["fitness"]  # its life, as evolution scored it
    best = max((p for p in people if p["status"] == "ok"), key=lambda p: p["fitness"])
    champion = res.champion()
    assert best["fitness"] == res.best_fitness[-1]
    assert np.array_equal(best["robot"].geometry, champion.geometry)


def test_an_evolver_left_running_at_exit_stops_at_its_checkpoint(tmp_path):
    """Python exiting while the run works (between tell() and the next ask()) closes it: a
    clean exit, and a results file that resumes."""
    import subprocess
    import sys
    out = tmp_path / "left.h5"
    script = (
        "import plastivox, sys\n"
        "from conftest import tiny_config\n"
        "ev = plastivox.Evolver(tiny_config(generations=20), sys.argv[1], threads=1)\n"
        "ev.tell(plastivox.simulate_many(ev.ask(), threads=1))\n")
    here = os.path.dirname(__file__)
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([here, os.environ.get("PYTHONPATH", "")])}
    for _ in range(3):  # the thread is at a different point each time
        run = subprocess.run([sys.executable, "-c", script, str(out)], env=env,
                             capture_output=True, text=True, timeout=300)
        assert run.returncode == 0, run.stderr
        assert "terminate" not in run.stderr, run.stderr
    res = plastivox.read_results(out)
    assert res.provenance["fitness_function"] == "python: ask-tell" and not res.finished


def test_threads_default_to_the_configs_as_on_the_command_line(tmp_path, monkeypatch):
    # evolve and Evolver without threads= use the config's "threads" (as `plastivox evolve`
    # without --threads); threads=N overrides it.
    config = tiny_config(generations=1)
    assert config["threads"] == 1
    report = plastivox.evolve(config, str(tmp_path / "own.h5"))
    assert report["threads"] == 1
    assert plastivox.read_results(str(tmp_path / "own.h5")).provenance["threads"] == 1
    assert plastivox.evolve(config, str(tmp_path / "two.h5"), threads=2)["threads"] == 2
    with plastivox.Evolver(config, str(tmp_path / "asked.h5")) as ev:
        while not ev.finished:
            ev.tell([0.0] * len(ev.ask()))
    assert ev.report["threads"] == 1
    # A fitness function's lives are simulated on the config's threads too.
    asked = []
    simulate_many = plastivox.simulate_many

    def spy(robots, **kwargs):
        asked.append(kwargs["threads"])
        return simulate_many(robots, **kwargs)
    monkeypatch.setattr(plastivox, "simulate_many", spy)
    cfg = tmp_path / "run.json"
    cfg.write_text(json.dumps(config))
    plastivox.evolve(str(cfg), str(tmp_path / "scored.h5"), fitness=lambda life: life.fitness)
    assert asked and set(asked) == {1}
    with pytest.raises(ValueError, match=r"threads: expected None \(the config's\) or an integer"):
        plastivox.evolve(config, str(tmp_path / "bad.h5"), threads=-1)
