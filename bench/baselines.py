"""Algorithms compared: AFPO, MAP-Elites and CMA-ES on tasks x seeds at one budget of lives.

    build/python/python3 bench/baselines.py --out out/algorithms            # run + summarise
    build/python/python3 bench/baselines.py --out out/algorithms --summarise-only
    build/python/python3 bench/baselines.py --out out/plans --tasks walk \
        --algorithms afpo,map-elites --seeds 1,2 --population 6 --lives 90 --duration 0 \
        --treatment stress --axes plans --body-plans 5       # the body-plan question

(docs/tasks.md, "Algorithms compared"; not a test.) For every task x algorithm x seed it
writes one evolution config (DIR/configs/LABEL.json), runs `nice -n 10 plastivox evolve`
on it (DIR/runs/LABEL.h5; each child one thread, --jobs of them at once) and records the
child's CPU seconds (getrusage, DIR/runs/LABEL.cpu.json). Rerunning continues where it
stopped: a finished run is skipped, a killed one resumed by the evolver from its last
checkpoint. SIGTERM or Ctrl-C stops every running child at its next checkpoint (their CPU
time recorded); a session killed harder (kill -9) loses its CPU record, and the summary then
says the CPU time is incomplete.

The budget is one number of lives (individuals created, simulated or cached) per run:
AFPO's population P makes P + G (P + 1) in G generations, MAP-Elites' batch P and CMA-ES'
lambda P make P (G + 1); with --lives L each gets the generations that give exactly L
(refused when one cannot). The default L = P (P + 2) fits all three.

What is compared. AFPO and MAP-Elites evolve the body and its phases (four CPPNs) from
random bodies on the --lattice. CMA-ES cannot evolve a body: it searches the actuation
phases of one fixed body, the task's example robot (examples/tasks/TASK.json, the best
body known for the task, found by a larger AFPO search), under the same physics. Its row
is therefore how far a fixed good body's gait can be tuned in the same lives, not a search
from scratch; its starting fitness (the body's own) is reported beside it.

Every run is judged here, whatever its file says: its candidates (every champion it
recorded and the last population for AFPO and CMA-ES, every elite of the archive for
MAP-Elites) are simulated again, from the highest recorded fitness down, under the run's
physics, and the first that is not an artifact (unstable, sank, or a 3-D walk owing its
score to vertical motion: the study's audit, docs/analysis.md) is the run's champion, with
its fitness and `success` from that replay.
"""

import argparse
import json
import os
import signal
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
ALGORITHMS = ("afpo", "map-elites", "cma-es")
BOOT_RESAMPLES, BOOT_SEED = 10000, 1


# --------------------------------------------------------------------------- budget

def generations_for(algorithm, population, lives):
    """Generations after generation 0 that make exactly `lives` individuals."""
    if algorithm == "afpo":
        g, r = divmod(lives - population, population + 1)
    else:
        g, r = divmod(lives, population)
        g -= 1
    if r or g < 0:
        raise ValueError(f"--lives {lives}: {algorithm} with population {population} cannot make "
                         f"exactly that many (AFPO makes P + G(P+1), the others P(G+1))")
    return g


def lives_to_reach(records, lives, target, replay, fallback=None):
    """Lives made (lives[g]: cumulative, per generation) when the run first held an
    unflagged individual of fitness >= target. records: (generation, id, recorded fitness)
    of each champion in order; replay(id) -> (flag, fitness) of its life simulated again
    (flag '' when it counts). The first record at or above the target whose replay is
    unflagged and still at or above it counts; when every such record is flagged, the
    generation `fallback` (the judged champion's birth) does; None when there is none."""
    for g, cid, fit in records:
        if fit >= target:
            flag, again = replay(cid)
            if not flag and again >= target:
                return int(lives[g])
    return None if fallback is None else int(lives[fallback])


def start_target(start, margin):
    """The fitness a CMA-ES run must reach to have improved its fixed body's own (start) by
    the fraction `margin`; None when the start is not positive (a margin of nothing)."""
    if start is None or start <= 0:
        return None
    return start * (1 + margin)


def summarise_group(values, ci):
    """Mean and 95 % interval of a group's champion fitness; ci(values) -> (low, high)."""
    if not values:
        return {"n": 0, "mean": None, "low": None, "high": None}
    mean = sum(values) / len(values)
    if len(values) < 2:
        return {"n": len(values), "mean": mean, "low": None, "high": None}
    low, high = ci(values)
    return {"n": len(values), "mean": mean, "low": low, "high": high}


def reach_summary(per_run):
    """per_run: lives to reach (None: not reached) of each seed -> text and numbers."""
    got = sorted(n for n in per_run if n is not None)
    if not got:
        return {"reached": 0, "runs": len(per_run), "median": None, "text": "not reached"}
    k = len(got)
    median = got[k // 2] if k % 2 else (got[k // 2 - 1] + got[k // 2]) / 2
    return {"reached": k, "runs": len(per_run), "median": median,
            "text": f"{median:g} ({k}/{len(per_run)} reached)"}


def plastivox_ci(values):
    from plastivox import analysis
    c = analysis.bootstrap_ci(values, level=0.95, resamples=BOOT_RESAMPLES, seed=BOOT_SEED)
    return c["low"], c["high"]


# --------------------------------------------------------------------------- configs

def map_elites_axes(name):
    if name == "task":   # what the task runs use: body size x time on the floor
        return [{"name": "fill", "bounds": [0.2, 1], "bins": 8},
                {"name": "floor_contact", "bounds": [0, 1], "bins": 8}]
    if name == "plans":  # the body-plan question: the three template scores
        return [{"name": p, "bounds": [0, 1], "bins": 5} for p in ("pi", "gamma", "upsilon")]
    raise ValueError(f"--axes: unknown '{name}' (use task, plans)")


def make_config(a, task, algorithm, seed):
    physics = {"preset": a.preset}
    if a.duration:
        physics["duration"] = a.duration
    c = {"format": "plastivox-evolve-config", "version": 1, "seed": seed,
         "task": task, "treatment": a.treatment, "algorithm": algorithm,
         "population": a.population,
         "generations": generations_for(algorithm, a.population, a.lives),
         "checkpoint_every": 1, "threads": 1, "physics": physics}
    if algorithm == "cma-es":
        c["body"] = os.path.join(ROOT, "examples", "tasks", task + ".json")
        c["genome"] = "phase"
        if a.cma_sigma is not None:
            c["cma"] = {"sigma": a.cma_sigma}
    else:
        n = a.lattice
        c["lattice"] = {"nx": n, "ny": n, "nz": n, "voxel_size": 0.01}
    if algorithm == "map-elites":
        c["map_elites"] = {"descriptors": map_elites_axes(a.axes)}
    return c


# --------------------------------------------------------------------------- running

def cli(a):
    return os.path.abspath(a.plastivox)


def inspect(a, path):
    out = subprocess.run([cli(a), "inspect", path, "--json"], capture_output=True, text=True)
    return json.loads(out.stdout) if out.returncode == 0 else None


def sessions(a, label, update=None):
    """The run's CPU record (DIR/runs/LABEL.cpu.json): one entry a session, written when it
    starts (cpu_seconds null) and completed when it ends; update(list) edits it."""
    path = os.path.join(a.out, "runs", label + ".cpu.json")
    rec = json.load(open(path)) if os.path.exists(path) else {"sessions": []}
    if update:
        update(rec["sessions"])
        with open(path, "w") as f:
            json.dump(rec, f)
    return rec["sessions"]


def start(a, label):
    sessions(a, label, lambda s: s.append({"cpu_seconds": None, "wall_seconds": None,
                                           "exit": None}))
    cfg = os.path.join(a.out, "configs", label + ".json")
    h5 = os.path.join(a.out, "runs", label + ".h5")
    log = open(os.path.join(a.out, "runs", label + ".log"), "a")
    cmd = ["nice", "-n", str(a.nice), cli(a), "evolve", "--config", cfg, "--out", h5, "--threads", "1"]
    return subprocess.Popen(cmd, stdout=log, stderr=subprocess.STDOUT), log


def run_all(a, labels):
    """Runs every unfinished run, --jobs at once; CPU seconds of each child by wait4."""
    todo = []
    for label in labels:
        info = inspect(a, os.path.join(a.out, "runs", label + ".h5"))
        if info and info.get("finished"):
            continue
        todo.append(label)
    print(f"{len(labels) - len(todo)} runs finished, {len(todo)} to run", flush=True)
    running, failed = {}, []
    stopping = []

    def stop(signum, frame):  # SIGTERM or Ctrl-C: each run stops at its next checkpoint
        if not stopping:
            stopping.append(signum)
            for _, proc, _, _ in running.values():
                proc.send_signal(signal.SIGTERM)

    signal.signal(signal.SIGTERM, stop)
    signal.signal(signal.SIGINT, stop)
    while (todo and not stopping) or running:
        while todo and not stopping and len(running) < a.jobs:
            label = todo.pop(0)
            proc, log = start(a, label)
            running[proc.pid] = (label, proc, log, time.time())
        try:
            pid, status, usage = os.wait4(-1, 0)
        except ChildProcessError:
            break
        if pid not in running:
            continue
        label, proc, log, t0 = running.pop(pid)
        proc.returncode = os.waitstatus_to_exitcode(status)
        log.close()
        cpu = usage.ru_utime + usage.ru_stime
        sessions(a, label, lambda s: s[-1].update(cpu_seconds=cpu, wall_seconds=time.time() - t0,
                                                  exit=proc.returncode))
        print(f"{label}: exit {proc.returncode}, {cpu:.1f} CPU s", flush=True)
        if proc.returncode != 0:
            failed.append(label)
    if stopping:
        sys.exit("stopped: rerun the same command to continue")
    if failed:  # the others ran to their end first: no run is left orphaned
        sys.exit(f"plastivox evolve failed on {', '.join(failed)} (see DIR/runs/LABEL.log)")


# --------------------------------------------------------------------------- judging

def flag_of(result):
    """The study's audit of one replayed life: '' when it counts, else why not."""
    if result.status != "finished":
        return "unstable"
    if result.health == "sank":
        return "sank"
    if result.vertical_exploit:
        return "vertical"
    return ""


def champion_records(h5):
    """(generation, id, recorded fitness) of each champion, in order of appearance."""
    import h5py
    with h5py.File(h5, "r") as f:
        return [(int(c.attrs["generation"]), int(c.attrs["id"]), float(c.attrs["fitness"]))
                for c in (f["champions"][k] for k in sorted(f["champions"]))]


def candidates(res, h5):
    """(recorded fitness, id, robot) of every individual whose genome the file holds: every
    champion, and the last population (AFPO, CMA-ES) or the archive (MAP-Elites)."""
    out = [(fit, cid, res.champion(generation=g)) for g, cid, fit in champion_records(h5)]
    if res.config.get("algorithm", "afpo") == "map-elites":
        out += [(e["fitness"], int(e["id"]), e["robot"]) for e in res.archive()["elites"]]
    else:
        out += [(p["fitness"], int(p["id"]), p["robot"]) for p in res.population()
                if p["robot"] is not None and p["status"] == "ok"]
    return out


class Replays:
    """Each individual's life simulated again once, judged by the audit (flag_of)."""

    def __init__(self, h5):
        import plastivox
        self.res = plastivox.read_results(h5)
        self.h5 = h5
        self.robots = {cid: rob for _, cid, rob in candidates(self.res, h5)}
        self.fitness = {cid: fit for fit, cid, _ in candidates(self.res, h5)}
        self.lives = {}

    def life(self, cid):
        if cid not in self.lives:
            import plastivox
            self.lives[cid] = plastivox.simulate(self.robots[cid])
        return self.lives[cid]


def judge(rp):
    """The run's best unflagged individual by replay (ties to the lower id), and what was
    flagged above it."""
    flagged = []
    for cid in sorted(rp.robots, key=lambda c: (-rp.fitness[c], c)):
        r = rp.life(cid)
        why = flag_of(r)
        if why:
            flagged.append({"id": cid, "recorded": rp.fitness[cid], "why": why})
            continue
        return {"id": cid, "fitness": r.fitness, "recorded": rp.fitness[cid],
                "success": bool(r.success), "voxels": int(r.voxels), "health": r.health,
                "flagged_above": flagged}
    return {"id": None, "fitness": 0.0, "recorded": None, "success": False, "voxels": 0,
            "health": None, "flagged_above": flagged}


def born(h5, cid):
    import h5py
    with h5py.File(h5, "r") as f:
        return int(f["individuals/generation"][cid])


def judged_lives_to_reach(rp, judged, lives, target):
    """lives_to_reach for a run; None when its judged champion is below the target."""
    if target is None or judged["id"] is None or judged["fitness"] < target:
        return None
    return lives_to_reach(champion_records(rp.h5), lives, target,
                          lambda c: (flag_of(rp.life(c)), rp.life(c).fitness),
                          born(rp.h5, judged["id"]))


def curves(h5):
    """Per generation: best recorded fitness and lives made so far; QD score if any."""
    import h5py
    import numpy as np
    with h5py.File(h5, "r") as f:
        best = f["generations/best_fitness"][:]
        gen = f["individuals/generation"][:]
        lives = np.cumsum(np.bincount(gen, minlength=len(best)))[:len(best)]
        qd = f["generations/qd_score"][:] if "qd_score" in f["generations"] else None
        cov = f["generations/coverage"][:] if "coverage" in f["generations"] else None
    return best.tolist(), lives.tolist(), qd, cov


def cpu_of(a, label):
    """CPU seconds of the run's sessions, and whether every session was measured (a session
    killed hard has none; one stopped by a signal, exit 130, has its own) and the last ended
    the run."""
    s = sessions(a, label)
    if not s:
        return None, False
    return (sum(x["cpu_seconds"] or 0.0 for x in s),
            all(x["cpu_seconds"] is not None for x in s) and s[-1]["exit"] == 0)


# --------------------------------------------------------------------------- summary

def fmt(x, d=2):
    return "—" if x is None else f"{x:.{d}f}"


def summarise(a, plan):
    import plastivox
    targets = {}  # AFPO's mean champion per task, from another summary when AFPO is not run here
    if a.targets:
        for row in json.load(open(a.targets))["rows"]:
            if row["algorithm"] == "afpo":
                targets[row["task"]] = row["fitness"]["mean"]
    runs = {}
    for task, algorithm, seed, label in plan:
        h5 = os.path.join(a.out, "runs", label + ".h5")
        info = inspect(a, h5)
        if not info or not info.get("finished"):
            print(f"{label}: not finished, left out", flush=True)
            continue
        rp = Replays(h5)
        j = judge(rp)
        best, lives, qd, cov = curves(h5)
        cpu, complete = cpu_of(a, label)
        runs[label] = {"task": task, "algorithm": algorithm, "seed": seed,
                       "digest": info["content_digest"][:12], "lives": lives[-1],
                       "recorded_best": best[-1], "fitness": j["fitness"],
                       "success": j["success"], "voxels": j["voxels"],
                       "flagged_above": len(j["flagged_above"]),
                       "flags": sorted({x["why"] for x in j["flagged_above"]}),
                       "qd_score": None if qd is None else float(qd[-1]),
                       "coverage": None if cov is None else float(cov[-1]),
                       "cpu_seconds": cpu, "cpu_complete": complete,
                       "_rp": rp, "_judged": j, "_lives": lives}
        if algorithm == "cma-es":  # the fixed body as it is, under the run's physics
            body = plastivox.load_robot(os.path.join(ROOT, "examples", "tasks", task + ".json"))
            start_life = plastivox.simulate(body.with_physics(rp.res.champion().physics))
            runs[label]["start_fitness"] = start_life.fitness
            runs[label]["start_flag"] = flag_of(start_life)
        print(f"{label}: judged {j['fitness']:.3f} (recorded {best[-1]:.3f}, "
              f"{len(j['flagged_above'])} flagged above)", flush=True)
    rows = []
    for task in a.tasks:
        group = {alg: [r for r in runs.values() if r["task"] == task and r["algorithm"] == alg]
                 for alg in a.algorithms}
        afpo = group.get("afpo") or []
        target = sum(r["fitness"] for r in afpo) / len(afpo) if afpo else targets.get(task)
        for alg in a.algorithms:
            g = group[alg]
            if not g:
                continue
            s = summarise_group([r["fitness"] for r in g], plastivox_ci)
            reach = [judged_lives_to_reach(r["_rp"], r["_judged"], r["_lives"], target)
                     for r in g]
            cpus = [r["cpu_seconds"] for r in g if r["cpu_seconds"] is not None]
            row = {"task": task, "algorithm": alg, "runs": len(g),
                   "fitness": s, "success": sum(r["success"] for r in g),
                   "lives": g[0]["lives"],
                   "cpu_seconds_mean": sum(cpus) / len(cpus) if cpus else None,
                   "cpu_complete": all(r["cpu_complete"] for r in g) and len(cpus) == len(g),
                   "afpo_target": target, "lives_to_target": reach_summary(reach),
                   "flagged_above": sum(r["flagged_above"] for r in g)}
            if alg == "map-elites":
                row["qd_score_mean"] = sum(r["qd_score"] for r in g) / len(g)
                row["coverage_mean"] = sum(r["coverage"] for r in g) / len(g)
            if alg == "cma-es":  # when the start already beats AFPO's mean, reaching that
                start = g[0]["start_fitness"]  # says nothing of the search: so also the lives
                goal = start_target(start, a.start_margin)  # to beat the start by a margin
                row["start_fitness"] = start
                row["start_margin"] = a.start_margin
                row["start_target"] = goal
                row["lives_to_start_target"] = reach_summary(
                    [judged_lives_to_reach(r["_rp"], r["_judged"], r["_lives"], goal) for r in g])
                if goal is None:
                    row["lives_to_start_target"]["text"] = "start not positive"
            rows.append(row)
    for r in runs.values():
        del r["_rp"], r["_judged"], r["_lives"]
    out = {"format": "plastivox-algorithm-baselines", "version": 1,
           "budget": {"lives": a.lives, "population": a.population, "lattice": a.lattice,
                      "duration": a.duration, "preset": a.preset, "treatment": a.treatment,
                      "map_elites_axes": map_elites_axes(a.axes),
                      "cma_es": "genome phase on examples/tasks/TASK.json",
                      "cma_sigma": a.cma_sigma, "cma_start_margin": a.start_margin},
           "bootstrap": {"method": "percentile bootstrap of the mean (plastivox.analysis.bootstrap_ci)",
                         "resamples": BOOT_RESAMPLES, "seed": BOOT_SEED, "level": 0.95},
           "rows": rows, "runs": dict(sorted(runs.items()))}
    with open(os.path.join(a.out, "summary.json"), "w") as f:
        json.dump(out, f, indent=1, sort_keys=True)
        f.write("\n")
    md = markdown(rows)
    with open(os.path.join(a.out, "summary.md"), "w") as f:
        f.write(md)
    print(md)


def markdown(rows):
    lines = ["| task | algorithm | champion fitness, mean [95 % CI] | success | QD score "
             "(coverage) | lives | CPU s / run | lives to AFPO's mean |",
             "|---|---|---|---|---|---|---|---|"]
    for r in rows:
        f = r["fitness"]
        fit = f"{fmt(f['mean'])} [{fmt(f['low'])}, {fmt(f['high'])}]"
        if r["algorithm"] == "cma-es":
            fit += f" (start {fmt(r['start_fitness'])})"
        qd = "" if "qd_score_mean" not in r else \
            f"{r['qd_score_mean']:.1f} ({100 * r['coverage_mean']:.0f} %)"
        cpu = fmt(r["cpu_seconds_mean"], 0) + ("" if r["cpu_complete"] else " (incomplete)")
        reach = r["lives_to_target"]["text"]
        if "lives_to_start_target" in r:
            reach += (f"; to start + {100 * r['start_margin']:g} %: "
                      f"{r['lives_to_start_target']['text']}")
        lines.append(f"| `{r['task']}` | {r['algorithm']} | {fit} | {r['success']}/{r['runs']} | "
                     f"{qd} | {r['lives']} | {cpu} | {reach} |")
    return "\n".join(lines) + "\n"


# --------------------------------------------------------------------------- body plans

PLANS = ("Pi", "Gamma", "Upsilon", "other")


def plan_counts(rows, least):
    """rows: (plan, fitness, flag) of each individual -> per plan, the unflagged individuals
    walking at least `least` and the best fitness among them; and the distinct plans other
    than "other" among those."""
    table = {p: {"count": 0, "best": None} for p in PLANS}
    for plan, fit, flag in rows:
        if flag or fit < least:
            continue
        t = table[plan]
        t["count"] += 1
        t["best"] = fit if t["best"] is None else max(t["best"], fit)
    distinct = [p for p in PLANS[:3] if table[p]["count"]]
    return table, distinct


def body_plans(a, plan):
    """Every stored individual of each run (AFPO: its champions and last population;
    MAP-Elites: its champions and archive) simulated again, judged by the audit and
    classified by the body-plan rule (analyze's, threshold 0.75)."""
    from plastivox import analysis
    out = {"least_fitness": a.body_plans, "runs": {}}
    for task, algorithm, seed, label in plan:
        h5 = os.path.join(a.out, "runs", label + ".h5")
        if not os.path.exists(h5):
            continue
        rp = Replays(h5)
        ids = sorted(rp.robots)
        plans = analysis.body_plan([rp.robots[c] for c in ids])
        rows = []
        for cid, bp in zip(ids, plans):
            life = rp.life(cid)
            rows.append((bp["plan"], life.fitness, flag_of(life), bp["voxels"]))
        table, distinct = plan_counts([r[:3] for r in rows], a.body_plans)
        every, _ = plan_counts([(p, 0.0, "") for p, _, _, _ in rows], 0.0)
        fills = sorted(r[3] for r in rows)
        j = judge(rp)
        champion_plan = plans[ids.index(j["id"])]["plan"] if j["id"] is not None else None
        out["runs"][label] = {
            "algorithm": algorithm, "seed": seed, "individuals": len(rows),
            "flagged": sum(1 for r in rows if r[2]),
            "plans_all": {p: every[p]["count"] for p in PLANS},
            "walking": table, "distinct_walking_plans": distinct,
            "voxels_median": fills[len(fills) // 2], "champion_plan": champion_plan,
            "best_fitness": j["fitness"],
            "lives": [{"id": cid, "plan": r[0], "fitness": round(r[1], 4), "flag": r[2],
                       "voxels": r[3]} for cid, r in zip(ids, rows)]}
        print(f"{label}: {len(rows)} individuals, plans {out['runs'][label]['plans_all']}, "
              f"walking >= {a.body_plans}: "
              f"{ {p: table[p]['count'] for p in PLANS} }, distinct {distinct}", flush=True)
    with open(os.path.join(a.out, "body_plans.json"), "w") as f:
        json.dump(out, f, indent=1, sort_keys=True)
        f.write("\n")
    lines = [f"| run | stored (flagged) | Π / Γ / Υ / other, all | Π / Γ / Υ / other, walking "
             f">= {a.body_plans:g} | best Π / Γ / Υ / other | distinct walking plans | "
             f"champion | median voxels |", "|---|---|---|---|---|---|---|---|"]
    for label, r in out["runs"].items():
        al = " / ".join(str(r["plans_all"][p]) for p in PLANS)
        wk = " / ".join(str(r["walking"][p]["count"]) for p in PLANS)
        best = {p: max((x["fitness"] for x in r["lives"] if x["plan"] == p and not x["flag"]),
                       default=None) for p in PLANS}
        bs = " / ".join(fmt(best[p], 1) for p in PLANS)
        lines.append(f"| {label} | {r['individuals']} ({r['flagged']}) | {al} | {wk} | {bs} | "
                     f"{len(r['distinct_walking_plans'])} | {r['champion_plan']} "
                     f"{fmt(r['best_fitness'])} | {r['voxels_median']} |")
    text = "\n".join(lines) + "\n"
    with open(os.path.join(a.out, "body_plans.md"), "w") as f:
        f.write(text)
    print(text)


# --------------------------------------------------------------------------- main

def parse(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", required=True, help="folder for configs, runs and the summary")
    ap.add_argument("--tasks", default="walk,jump,push,slope")
    ap.add_argument("--algorithms", default=",".join(ALGORITHMS))
    ap.add_argument("--seeds", default="1,2,3")
    ap.add_argument("--population", type=int, default=16,
                    help="AFPO's population, MAP-Elites' batch, CMA-ES' lambda")
    ap.add_argument("--lives", type=int, default=None, help="per run (default P(P+2))")
    ap.add_argument("--lattice", type=int, default=6)
    ap.add_argument("--duration", type=float, default=2.0, help="life length, s (0: the preset's)")
    ap.add_argument("--preset", default="gecco2018-code")
    ap.add_argument("--treatment", default="none")
    ap.add_argument("--axes", default="task", help="MAP-Elites descriptors: task or plans")
    ap.add_argument("--jobs", type=int, default=2, help="runs at once (one thread each)")
    ap.add_argument("--nice", type=int, default=10)
    ap.add_argument("--plastivox", default=os.path.join(ROOT, "build", "apps", "plastivox"))
    ap.add_argument("--cma-sigma", type=float, default=None,
                    help="CMA-ES' initial step size (default: the evolver's, 0.25 for phases)")
    ap.add_argument("--targets", default=None, metavar="SUMMARY.json",
                    help="AFPO's mean champions from another run's summary, for lives to reach "
                         "when AFPO is not among --algorithms")
    ap.add_argument("--start-margin", type=float, default=0.1, metavar="M",
                    help="CMA-ES rows also give the lives to beat the fixed body's own fitness "
                         "by the fraction M (default 0.1: start + 10 %%)")
    ap.add_argument("--summarise-only", action="store_true")
    ap.add_argument("--body-plans", type=float, default=None, metavar="X",
                    help="also classify every stored individual's body plan and count the "
                         "distinct plans among those walking at least X (body_plans.md)")
    a = ap.parse_args(argv)
    a.tasks = a.tasks.split(",")
    a.algorithms = a.algorithms.split(",")
    for alg in a.algorithms:
        if alg not in ALGORITHMS:
            ap.error(f"--algorithms: unknown '{alg}' (use {', '.join(ALGORITHMS)})")
    try:
        a.seeds = [int(s) for s in a.seeds.split(",")]
        map_elites_axes(a.axes)
    except ValueError as e:
        ap.error(f"--seeds: {e}" if "axes" not in str(e) else str(e))
    if not a.start_margin >= 0:
        ap.error(f"--start-margin: must be at least 0, got {a.start_margin}")
    if a.lives is None:
        a.lives = a.population * (a.population + 2)
    for alg in a.algorithms:
        try:
            generations_for(alg, a.population, a.lives)
        except ValueError as e:
            ap.error(str(e))
    return a


def main(argv=None):
    a = parse(argv)
    os.makedirs(os.path.join(a.out, "configs"), exist_ok=True)
    os.makedirs(os.path.join(a.out, "runs"), exist_ok=True)
    plan = []
    for task in a.tasks:
        for alg in a.algorithms:
            for seed in a.seeds:
                label = f"{task}-{alg}-s{seed}"
                path = os.path.join(a.out, "configs", label + ".json")
                text = json.dumps(make_config(a, task, alg, seed), indent=1, sort_keys=True) + "\n"
                if not os.path.exists(path) or open(path).read() != text:
                    with open(path, "w") as f:
                        f.write(text)
                plan.append((task, alg, seed, label))
    if not a.summarise_only:
        run_all(a, [p[3] for p in plan])
    summarise(a, plan)
    if a.body_plans is not None:
        body_plans(a, plan)


if __name__ == "__main__":
    main()
