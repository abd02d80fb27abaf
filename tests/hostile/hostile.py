#!/usr/bin/env python3
"""Seeded hostile-input run against an installed plastivox (issue 40's closing table).

Generates a few thousand cases (damaged and extreme inputs, bad command lines, kills,
full and read-only disks, Python misuse), runs each under a timeout and an address-space
cap, classifies each outcome and writes:

  OUT/cases.jsonl   one JSON object per case
  OUT/table.md      a table per category and the totals
  OUT/findings.md   every crash, hang, unbounded, wrong and lost case with its reproduction

Not part of ctest: it takes about 20 minutes. See tests/hostile/README.md.
"""

import argparse
import hashlib
import json
import os
import random
import resource
import shlex
import shutil
import signal
import socket
import subprocess
import sys
import time

CATEGORIES = [
    "robot-json",
    "vxa",
    "config-cli",
    "damaged-files",
    "interruption",
    "disk",
    "physics",
    "python",
]
OUTCOMES = ["clean error", "accepted", "crash", "hang", "unbounded", "wrong", "lost"]
DEFECTS = {"crash", "hang", "unbounded", "wrong", "lost"}

CAP_BYTES = 4 << 30
UNBOUNDED_MARKS = ["std::bad_alloc", "MemoryError", "Cannot allocate memory", "out of memory"]
CRASH_MARKS = [
    "terminate called",
    "Segmentation fault",
    "AddressSanitizer",
    "runtime error:",
    "Assertion",
    "HDF5-DIAG",
    "core dumped",
    "Traceback (most recent call last)",
    "Fatal Python error",
]
# Lines on stderr that are progress or warnings, not the error message.
NOISE_PREFIXES = ("[", "generation ", "  ", "wrote ", "resum")


class Harness:
    def __init__(self, args):
        self.args = args
        self.rng = random.Random(args.seed)
        self.work = os.path.abspath(args.work)
        self.out = os.path.abspath(args.out)
        self.exe = os.path.abspath(args.plastivox)
        self.pypath = os.path.abspath(args.pythonpath)
        self.timeout = args.timeout
        self.cases = []
        self.n = 0
        self.mounts = []
        self.t0 = time.time()

    # ---- running -------------------------------------------------------------------

    def env(self, extra=None):
        e = {
            "PATH": "/usr/bin:/bin",
            "HOME": self.work,
            "LANG": "C.UTF-8",
            "PYTHONPATH": self.pypath,
            "OMP_NUM_THREADS": "1",
            "OPENBLAS_NUM_THREADS": "1",
        }
        if extra:
            e.update(extra)
        return e

    def spawn(self, argv, cwd=None, env=None):
        def pre():
            os.setsid()
            resource.setrlimit(resource.RLIMIT_AS, (CAP_BYTES, CAP_BYTES))
            resource.setrlimit(resource.RLIMIT_CORE, (0, 0))

        return subprocess.Popen(
            argv,
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            stdin=subprocess.DEVNULL,
            preexec_fn=pre,
            cwd=cwd or self.scratch,
            env=self.env(env),
        )

    def finish(self, p, start, timeout=None):
        timed_out = False
        try:
            out, err = p.communicate(timeout=timeout or self.timeout)
        except subprocess.TimeoutExpired:
            timed_out = True
            try:
                os.killpg(p.pid, signal.SIGKILL)
            except ProcessLookupError:
                pass
            out, err = p.communicate()
        return {
            "rc": p.returncode,
            "out": out.decode("utf-8", "replace"),
            "err": err.decode("utf-8", "replace"),
            "wall": round(time.time() - start, 3),
            "timed_out": timed_out,
        }

    def run(self, argv, cwd=None, env=None, timeout=None):
        start = time.time()
        return self.finish(self.spawn(argv, cwd, env), start, timeout)

    def interrupt(self, argv, delay, sig):
        """Runs argv and sends it sig after delay seconds (SIGKILL to its whole group)."""
        start = time.time()
        p = self.spawn(argv)
        time.sleep(delay)
        try:
            os.killpg(p.pid, sig) if sig == signal.SIGKILL else p.send_signal(sig)
        except ProcessLookupError:
            pass
        return self.finish(p, start)

    def pv(self, *args, **kw):
        return self.run([self.exe] + [str(a) for a in args], **kw)

    # ---- classification ------------------------------------------------------------

    def classify(self, r, expect, check=None, ok_rcs=(0,)):
        """expect: refuse (must be a clean error), valid (must be accepted), either."""
        if r["timed_out"]:
            return "hang", "no exit within %g s" % self.timeout
        err = r["err"]
        for m in UNBOUNDED_MARKS:
            if m in err:
                return "unbounded", "hit the 4 GB cap: " + m
        if r["rc"] < 0:
            sig = signal.Signals(-r["rc"]).name
            return "crash", "killed by " + sig + ": " + last_line(err)
        for m in CRASH_MARKS:
            if m in err:
                return "crash", "stderr shows '%s': %s" % (m, last_line(err, m))
        if r["rc"] in ok_rcs:
            if expect == "refuse":
                return "wrong", "accepted (exit %d) input that must be refused" % r["rc"]
            if check:
                msg = check(r)
                if msg:
                    return "wrong", msg
            return "accepted", ""
        lines = message_lines(err)
        errors = [l for l in lines if " error: " in l or l.startswith("error: ")]
        if errors:
            lines = errors  # the lines before it were progress reports
        if r["rc"] == 2 and "usage:" in err:
            lines = lines[:1]  # a command-line error, then the usage
        if expect == "valid":
            return "wrong", "refused a valid input (exit %d): %s" % (r["rc"], last_line(err))
        if not lines:
            return "wrong", "exit %d with no message on stderr" % r["rc"]
        if len(lines) > 1:
            return "wrong", "error of %d lines, not one: %s" % (len(lines), " | ".join(lines[:3]))
        return "clean error", ""

    def record(self, category, kind, repro, outcome, reason, r=None, known=None):
        self.n += 1
        case = {
            "id": self.n,
            "category": category,
            "kind": kind,
            "outcome": outcome,
            "reason": reason,
            "repro": repro,
        }
        if r is not None:
            case["rc"] = r["rc"]
            case["wall"] = r["wall"]
            case["stderr"] = last_line(r["err"])[:300]
        if known and outcome in DEFECTS:
            case["known"] = known
        self.cases.append(case)
        with open(os.path.join(self.out, "cases.jsonl"), "a") as f:
            f.write(json.dumps(case) + "\n")
        return case

    def cli_case(self, category, kind, argv, expect, check=None, ok_rcs=(0,), env=None,
                 known=None, setup="", post=None):
        r = self.pv(*argv, env=env)
        outcome, reason = self.classify(r, expect, check, ok_rcs)
        if post and post():
            outcome, reason = "wrong", post()
        envs = " ".join("%s=%s" % (k, shlex.quote(v)) for k, v in (env or {}).items())
        repro = (setup + " && " if setup else "") + "cd %s && %s%s %s" % (
            self.scratch, envs + " " if envs else "", self.exe,
            " ".join(shlex.quote(str(a)) for a in argv))
        return self.record(category, kind, repro, outcome, reason, r, known)

    def py_case(self, category, kind, body, expect, known=None):
        """Runs BODY in a fresh interpreter. The wrapper prints CLEAN/ACCEPTED/WRONG."""
        script = "%s\ndef case():\n%s\n%s" % (PY_PRELUDE.replace("@BASE@", self.base),
                                              indent(body), PY_EPILOGUE)
        path = os.path.join(self.pydir, "case%05d.py" % (self.n + 1))
        with open(path, "w") as f:
            f.write(script)
        r = self.run(["/usr/bin/python3", path], cwd=self.scratch)
        verdict = ""
        for line in r["out"].splitlines():
            if line.startswith("HOSTILE:"):
                verdict = line[len("HOSTILE:"):].strip()
        if r["timed_out"] or r["rc"] != 0 or not verdict:
            outcome, reason = self.classify(r, "refuse")
            if outcome in ("clean error", "wrong"):
                outcome, reason = "crash", "interpreter exit %d without a verdict: %s" % (
                    r["rc"], last_line(r["err"]))
        elif verdict.startswith("CLEAN"):
            outcome, reason = (("wrong", "refused a valid call: " + verdict) if expect == "valid"
                               else ("clean error", verdict[:200]))
        elif verdict.startswith("ACCEPTED"):
            outcome, reason = (("wrong", "accepted a call that must be refused: " + verdict)
                               if expect == "refuse" else ("accepted", verdict[:200]))
        elif verdict.startswith("WRONG"):
            outcome, reason = "wrong", verdict
        elif verdict.startswith("UNBOUNDED"):
            outcome, reason = "unbounded", verdict
        else:
            outcome, reason = "crash", verdict
        repro = "cd %s && PYTHONPATH=%s /usr/bin/python3 %s" % (self.scratch, self.pypath, path)
        return self.record(category, kind, repro, outcome, reason, r, known)

    # ---- set-up --------------------------------------------------------------------

    def setup(self):
        if os.path.exists(self.work):
            self.unmount_all(self.work)
            shutil.rmtree(self.work)
        os.makedirs(self.work)
        os.makedirs(self.out, exist_ok=True)
        open(os.path.join(self.out, "cases.jsonl"), "w").close()
        self.base = os.path.join(self.work, "base")
        self.scratch = os.path.join(self.work, "scratch")
        self.pydir = os.path.join(self.work, "py")
        for d in (self.base, self.scratch, self.pydir):
            os.makedirs(d)
        b = self.base
        write_json(os.path.join(b, "robot.json"), base_robot())
        write_json(os.path.join(b, "evolve.json"), base_evolve())
        write_json(os.path.join(b, "long.json"), dict(base_evolve(), population=6, generations=30))
        write_json(os.path.join(b, "experiment.json"), base_experiment())
        must(self.pv("evolve", "--config", b + "/evolve.json", "--out", b + "/run.h5",
                     "--threads", "1"), "tiny evolve")
        must(self.pv("export", b + "/run.h5", "--out", b + "/champion.vxa"), "export vxa")
        must(self.pv("export", b + "/run.h5", "--out", b + "/champion.json"), "export json")
        must(self.pv("simulate", b + "/robot.json", "--record", b + "/life.h5", "--fps", "30"),
             "record a life")
        must(self.pv("experiment", "--config", b + "/experiment.json", "--out", b + "/study",
                     "--threads", "1"), "tiny study")
        self.robot_text = open(b + "/robot.json").read()
        self.vxa_text = open(b + "/champion.vxa", encoding="latin-1").read()
        self.sim_ref = json.loads(must(self.pv("simulate", b + "/robot.json", "--json"),
                                       "simulate")["out"])
        self.vxa_ref = json.loads(must(self.pv("simulate", b + "/champion.vxa", "--json"),
                                       "simulate vxa")["out"])
        self.run_digest = digest_of(self.pv("inspect", b + "/run.h5", "--json"))
        r = must(self.pv("evolve", "--config", b + "/long.json", "--out", b + "/long.h5",
                         "--threads", "1"), "uninterrupted long evolve")
        self.long_wall = r["wall"]
        self.long_digest = digest_of(self.pv("inspect", b + "/long.h5", "--json"))
        # Baseline outputs of every reader, to compare damaged inputs' outputs against.
        self.baseline = {}
        for name, src in (("run", b + "/run.h5"), ("life", b + "/life.h5")):
            for reader, argv, out in self.readers(src):
                r = self.pv(*argv)
                self.baseline[(name, reader)] = (r["rc"], file_digest(out), strip_inspect(r))
                if os.path.exists(out):
                    os.remove(out)

    def readers(self, src):
        s = self.scratch
        rs = [
            ("render", ["render", src, "--out", s + "/o.png", "--size", "64x48", "--time", "0.1"],
             s + "/o.png"),
            ("view", ["view", src, "--out", s + "/o.html"], s + "/o.html"),
            ("video", ["video", src, "--out", s + "/o.mp4", "--size", "64x48", "--fps", "4"],
             s + "/o.mp4"),
        ]
        if src.endswith("run.h5") or "results" in os.path.basename(src):
            rs += [
                ("inspect", ["inspect", src, "--json"], s + "/none"),
                ("export", ["export", src, "--out", s + "/o.json"], s + "/o.json"),
            ]
        return rs

    # ---- mounts --------------------------------------------------------------------

    def tmpfs(self, name, size):
        d = os.path.join(self.work, "mnt", name)
        os.makedirs(d, exist_ok=True)
        subprocess.run(["mount", "-t", "tmpfs", "-o", "size=%s" % size, "tmpfs", d], check=True)
        self.mounts.append(d)
        return d

    def umount(self, d):
        subprocess.run(["umount", "-l", d], check=False)
        if d in self.mounts:
            self.mounts.remove(d)

    def unmount_all(self, under):
        with open("/proc/mounts") as f:
            for line in f:
                mp = line.split()[1]
                if mp.startswith(under + "/"):
                    subprocess.run(["umount", "-l", mp], check=False)

    # ---- report --------------------------------------------------------------------

    def report(self):
        rows = {c: {o: 0 for o in OUTCOMES} for c in CATEGORIES}
        for c in self.cases:
            rows[c["category"]][c["outcome"]] += 1
        head = "| category | cases | " + " | ".join(OUTCOMES) + " |\n"
        head += "|---" * (len(OUTCOMES) + 2) + "|\n"
        body = ""
        total = {o: 0 for o in OUTCOMES}
        for c in CATEGORIES:
            n = sum(rows[c].values())
            body += "| %s | %d | %s |\n" % (c, n, " | ".join(str(rows[c][o]) for o in OUTCOMES))
            for o in OUTCOMES:
                total[o] += rows[c][o]
        body += "| **total** | **%d** | %s |\n" % (
            len(self.cases), " | ".join("**%d**" % total[o] for o in OUTCOMES))
        meta = "seed %d, %d cases, %.0f s, %s\n\n" % (
            self.args.seed, len(self.cases), time.time() - self.t0, self.exe)
        with open(os.path.join(self.out, "table.md"), "w") as f:
            f.write(meta + head + body)
        with open(os.path.join(self.out, "findings.md"), "w") as f:
            f.write("# Non-clean cases (seed %d)\n\n" % self.args.seed)
            for c in self.cases:
                if c["outcome"] in DEFECTS:
                    f.write("- #%d %s / %s: **%s** %s%s\n  `%s`\n" % (
                        c["id"], c["category"], c["kind"], c["outcome"], c["reason"],
                        " (known: %s)" % c["known"] if c.get("known") else "", c["repro"]))
        print(meta + head + body)


# ---- helpers -----------------------------------------------------------------------

def last_line(text, containing=None):
    lines = [l for l in text.splitlines() if l.strip()]
    if containing:
        hits = [l for l in lines if containing in l]
        if hits:
            return hits[0].strip()
    return lines[-1].strip() if lines else ""


def message_lines(err):
    out = []
    for l in err.splitlines():
        if not l.strip() or "warning" in l or l.startswith(NOISE_PREFIXES):
            continue
        if ": simulating " in l or ": frame " in l or l.startswith(("usage:", "commands:")):
            continue
        out.append(l.strip())
    return out


def indent(text):
    return "\n".join("    " + l for l in text.strip("\n").splitlines())


def must(r, what):
    if r["rc"] not in (0, 3) or r["timed_out"]:
        sys.exit("hostile: set-up step failed (%s): %s" % (what, r["err"][-2000:]))
    return r


def write_json(path, obj):
    with open(path, "w") as f:
        json.dump(obj, f, indent=1)


def file_digest(path):
    if not os.path.isfile(path):
        return None
    with open(path, "rb") as f:
        return hashlib.sha256(f.read()).hexdigest()


def strip_inspect(r):
    try:
        j = json.loads(r["out"])
    except ValueError:
        return None
    for k in ("file", "wall_seconds"):
        j.pop(k, None)
    return j


def digest_of(r):
    try:
        return json.loads(r["out"])["content_digest"]
    except (ValueError, KeyError):
        return None


def base_robot():
    vox = []
    for x in range(3):
        for y in range(3):
            for z in range(2):
                vox.append([x, y, z, 1e9 * (1 + x), 0.5 * y - 0.2, 0.1 * z])
    return {
        "format": "plastivox-robot",
        "version": 1,
        "name": "hostile",
        "lattice": {"nx": 3, "ny": 3, "nz": 2, "voxel_size": 0.01},
        "voxels": vox,
        "physics": {"preset": "gecco2018-code", "duration": 0.3, "treatment": "stress"},
    }


def base_evolve():
    return {
        "format": "plastivox-evolve-config",
        "version": 1,
        "seed": 1,
        "treatment": "stress",
        "population": 4,
        "generations": 3,
        "lattice": {"nx": 3, "ny": 3, "nz": 3, "voxel_size": 0.01},
        "physics": {"preset": "gecco2018-code", "duration": 0.3},
    }


def base_experiment():
    return {
        "format": "plastivox-experiment-config",
        "version": 1,
        "name": "hostile",
        "treatments": ["none", "stress"],
        "seeds": [1],
        "evolution": {
            "population": 3,
            "generations": 2,
            "lattice": {"nx": 3, "ny": 3, "nz": 3, "voxel_size": 0.01},
            "physics": {"preset": "gecco2018-code", "duration": 0.3},
        },
        "analysis": {"robustness_draws": 2, "resamples": 100, "rotations": "paper", "seed": 1},
        "rendering": {"figure_size": "200x200", "gallery_size": "480x270",
                      "video_size": "64x48", "video_fps": 4, "video_color": "change"},
    }


def first_of(*checks):
    def check(r):
        for c in checks:
            msg = c(r)
            if msg:
                return msg
        return ""

    return check


def sane_sim(ref=None):
    """Checks an accepted `simulate --json`: parseable, finite, and equal to REF's life."""

    def check(r):
        try:
            j = json.loads(r["out"], parse_constant=lambda c: float("nan"))
        except ValueError:
            return "accepted, but stdout is not one JSON object"
        for k, v in j.items():
            if isinstance(v, float) and v != v:
                return "accepted with NaN in the result (%s)" % k
        if not isinstance(j.get("fitness"), (int, float)):
            return "accepted without a fitness"
        if ref is not None and j.get("final_state_hash") != ref.get("final_state_hash"):
            return "an equivalent input gave a different life (hash %s, expected %s)" % (
                j.get("final_state_hash"), ref.get("final_state_hash"))
        return ""

    return check


PY_PRELUDE = r'''
import os, sys, threading, pickle, traceback
import numpy as np
import plastivox as pv
CLEAN = (pv.InputError, pv.RenderError, ValueError, TypeError, RuntimeError, OverflowError,
         KeyError, IndexError, OSError)
BASE = "@BASE@"
nan, inf = float("nan"), float("inf")
class Wrong(Exception):
    pass
def require(ok, what):
    if not ok:
        raise Wrong(what)
'''

PY_EPILOGUE = r'''
try:
    v = case()
    print("HOSTILE: ACCEPTED " + ("" if v is None else str(v)[:150]).replace("\n", " "))
except Wrong as e:
    print("HOSTILE: WRONG " + str(e)[:300].replace("\n", " "))
except MemoryError as e:
    print("HOSTILE: UNBOUNDED MemoryError " + str(e)[:200])
except CLEAN as e:
    print("HOSTILE: CLEAN %s: %s" % (type(e).__name__, str(e).replace("\n", " | ")[:200]))
except BaseException as e:
    print("HOSTILE: CRASH %s: %s" % (type(e).__name__, str(e)[:200].replace("\n", " ")))
    traceback.print_exc()
sys.stdout.flush()
'''


# ---- generators: robot JSON ----------------------------------------------------------

BAD_VALUES = [None, True, "x", "", [], {}, -1, 0, 1.5, -0.0, 1e308, -1e308, 2 ** 64, -(2 ** 63),
              "1e400", "NaN", "-Infinity", [1, 2], {"a": 1}, 5e-324]
RAW = {"1e400": "1e400", "NaN": "NaN", "-Infinity": "-Infinity"}


def dump_raw(obj):
    """json.dumps, but the strings named in RAW become raw tokens (invalid JSON numbers)."""
    text = json.dumps(obj)
    for k, v in RAW.items():
        text = text.replace('"%s"' % k, v)
    return text


def is_int(v):
    return isinstance(v, int) and not isinstance(v, bool)


def is_num(v):
    return (isinstance(v, (int, float)) and not isinstance(v, bool) and v == v
            and abs(v) != float("inf"))


def robot_value_valid(path, v):
    """Whether replacing the base robot's field PATH with V leaves a valid robot (None: unsure)."""
    if isinstance(v, str) and v in RAW:
        return False
    if path == "name":
        return isinstance(v, str)
    if path in ("format", "version"):
        return False
    if path == "physics":
        return None if v == {} else False
    if path in ("fixed", "loads"):
        return None if v == [] else False
    if path in ("lattice.nx", "lattice.ny"):
        return is_int(v) and 3 <= v <= 1000
    if path == "lattice.nz":
        return is_int(v) and 2 <= v <= 1000
    if path == "lattice.voxel_size":
        return None if is_num(v) and 1e-4 <= v <= 10 else False
    if path.startswith("voxels.0."):
        i = int(path.split(".")[2])
        if i < 3:
            return v == 0 and is_int(v)
        if i == 3:
            return None if is_num(v) and v > 0 else False
        return None if is_num(v) else False
    return False


def damage_text(h, raw, modes, tail):
    """One random damage to a text file's bytes, at a place at least `tail` bytes from its end:
    (mode, damaged bytes, what a reader must do). Truncation, a NUL byte and trailing bytes
    must be refused; a flipped bit, inserted bytes or a BOM may be read or refused."""
    mode = h.rng.choice(modes)
    b = bytearray(raw)
    pos = h.rng.randrange(len(raw) - tail)
    expect = "either"
    if mode == "truncate":
        b = b[:pos]
        expect = "refuse"
    elif mode == "flip":
        b[pos] ^= 1 << h.rng.randrange(8)
    elif mode == "insert":
        b[pos:pos] = bytes(h.rng.randrange(256) for _ in range(h.rng.randrange(1, 6)))
    elif mode == "nul":
        b[pos:pos] = b"\0"
        expect = "refuse"
    elif mode == "trail":
        b += h.rng.choice([b"\0" * 1000, b"{}", b"x", b"]"])
        expect = "refuse"
    elif mode == "bom":
        b = b"\xef\xbb\xbf" + b
    return mode, bytes(b), expect


def gen_robot_json(h):
    cat = "robot-json"
    base = base_robot()
    d = h.scratch
    paths = ["name", "format", "version", "lattice", "lattice.nx", "lattice.ny", "lattice.nz",
             "lattice.voxel_size", "voxels", "voxels.0", "voxels.0.0", "voxels.0.1", "voxels.0.2",
             "voxels.0.3", "voxels.0.4", "voxels.0.5", "physics", "physics.preset", "fixed",
             "loads"]
    k = 0
    # Value substitutions at every field.
    for path in paths:
        for v in BAD_VALUES:
            r = json.loads(json.dumps(base))
            set_path(r, path, v)
            valid = robot_value_valid(path, v)
            f = "%s/rj%05d.json" % (d, k)
            k += 1
            with open(f, "w") as fh:
                fh.write(dump_raw(r))
            expect = {True: "valid", False: "refuse", None: "either"}[valid]
            h.cli_case(cat, "value %s=%s" % (path, json.dumps(v)[:20]),
                       ["simulate", f, "--json"], expect, sane_sim(), ok_rcs=(0, 3))
    # Unknown keys at every level, duplicate keys, bad voxel lists.
    structural = []
    for where in ("", "lattice", "physics"):
        r = json.loads(json.dumps(base))
        (r if not where else r[where])["surprise"] = 1
        structural.append(("unknown key in " + (where or "top"), dump_raw(r), "refuse"))
    r = json.loads(json.dumps(base))
    r["loads"] = [{"at": [0, 0, 0], "force": [0, 0, -1], "extra": 1}]
    structural.append(("unknown key in loads entry", json.dumps(r), "refuse"))
    r["loads"] = [{"at": [9, 9, 9], "force": [0, 0, -1]}]
    structural.append(("load outside the lattice", json.dumps(r), "refuse"))
    r["loads"] = [{"at": [0, 0, 0], "force": [0, 0, "1e400"]}]
    structural.append(("infinite load", dump_raw(r), "refuse"))
    r = json.loads(json.dumps(base))
    r["fixed"] = [[7, 0, 0]]
    structural.append(("fixed outside the lattice", json.dumps(r), "refuse"))
    r["fixed"] = [[0, 0]]
    structural.append(("fixed entry of 2", json.dumps(r), "refuse"))
    text = json.dumps(base)
    structural.append(("duplicate top key", text[:-1] + ', "name": "again"}', "refuse"))
    structural.append(("duplicate lattice key", text.replace('"nx": 3', '"nx": 3, "nx": 3'),
                       "refuse"))
    for n in (0, 5, 7):
        r = json.loads(json.dumps(base))
        r["voxels"][0] = r["voxels"][0][:n] + [0] * max(0, n - 6)
        structural.append(("voxel entry of %d" % n, json.dumps(r), "refuse"))
    r = json.loads(json.dumps(base))
    r["voxels"].append(list(r["voxels"][0]))
    structural.append(("voxel given twice", json.dumps(r), "refuse"))
    r["voxels"] = []
    structural.append(("no voxels", json.dumps(r), "refuse"))
    for label, mutate in (("permuted voxels", lambda r: h.rng.shuffle(r["voxels"])),
                          ("reordered keys", lambda r: None)):
        r = json.loads(json.dumps(base))
        mutate(r)
        keys = list(r.keys())
        h.rng.shuffle(keys)
        text = json.dumps({key: r[key] for key in keys}, indent=h.rng.choice([None, 0, 3]))
        f = "%s/rj%05d.json" % (d, k)
        k += 1
        open(f, "w").write(text)
        h.cli_case(cat, "equivalent: " + label, ["simulate", f, "--json"], "valid",
                   sane_sim(h.sim_ref), ok_rcs=(0, 3))
    for label, text, expect in structural:
        f = "%s/rj%05d.json" % (d, k)
        k += 1
        open(f, "w").write(text)
        h.cli_case(cat, label, ["simulate", f, "--json"], expect, sane_sim(), ok_rcs=(0, 3))
    # Byte damage: truncation (always refused), flips and insertions (either; sane if read).
    raw = h.robot_text.encode()
    for i in range(120):
        mode, b, expect = damage_text(
            h, raw, ["truncate", "flip", "flip", "insert", "nul", "trail", "bom"], tail=3)
        f = "%s/rb%05d.json" % (d, i)
        open(f, "wb").write(b)
        cmd = h.rng.choice([["simulate", f, "--json"]] * 6 + [["hausdorff", f, f, "--json"]] +
                           [["render", f, "--out", d + "/rb.png", "--size", "64x48"]])
        h.cli_case(cat, "bytes: " + mode, cmd, expect,
                   sane_sim() if cmd[0] == "simulate" else None, ok_rcs=(0, 3))
    # Size attacks.
    big = []
    for depth in (40, 1000, 100000):
        big.append(("nested arrays %d deep" % depth, '{"format": "plastivox-robot", "x": ' +
                    "[" * depth + "]" * depth + "}", "refuse"))
    r = json.loads(json.dumps(base))
    r["lattice"] = {"nx": 1000, "ny": 1000, "nz": 1000, "voxel_size": 0.01}
    big.append(("lattice 1000^3", json.dumps(r), "refuse"))
    r["lattice"] = {"nx": 128, "ny": 128, "nz": 128, "voxel_size": 0.01}
    big.append(("lattice 128^3 (the limit)", json.dumps(r), "valid"))
    r["lattice"] = {"nx": 129, "ny": 128, "nz": 128, "voxel_size": 0.01}
    big.append(("lattice 129x128x128", json.dumps(r), "refuse"))
    r = json.loads(json.dumps(base))
    r["name"] = "n" * 20000000
    big.append(("20 MB name", json.dumps(r), "either"))
    r = json.loads(json.dumps(base))
    r["loads"] = [{"at": [0, 0, 0], "force": [0, 0, -1e-9]}] * 200000
    big.append(("200 000 loads", json.dumps(r), "either"))
    r = json.loads(json.dumps(base))
    r["voxels"] = r["voxels"] * 20000
    big.append(("360 000 voxels, duplicates", json.dumps(r), "refuse"))
    r = json.loads(json.dumps(base))
    r["physics"]["duration"] = 0.21
    big.append(("number with 100 000 digits", json.dumps(r).replace(
        '"duration": 0.21', '"duration": 0.' + "2" * 100000), "valid"))
    for label, text, expect in big:
        f = "%s/rs%05d.json" % (d, k)
        k += 1
        open(f, "w").write(text)
        h.cli_case(cat, "size: " + label, ["simulate", f, "--json", "--duration", "0.25"], expect,
                   sane_sim(), ok_rcs=(0, 3))
        os.remove(f)
    # Not a regular file.
    os.mkfifo(d + "/fifo.json")
    for label, f in (("a folder", d), ("/dev/zero", "/dev/zero"), ("a FIFO", d + "/fifo.json"),
                     ("missing", d + "/missing.json"), ("empty", d + "/empty.json")):
        if label == "empty":
            open(f, "w").close()
        h.cli_case(cat, "path: " + label, ["simulate", f], "refuse")


def set_path(obj, path, v):
    keys = path.split(".")
    for key in keys[:-1]:
        obj = obj[int(key)] if isinstance(obj, list) else obj[key]
    last = keys[-1]
    if isinstance(obj, list):
        obj[int(last)] = v
    else:
        obj[last] = v


# ---- generators: VXA -----------------------------------------------------------------

def gen_vxa(h):
    import re
    cat = "vxa"
    d = h.scratch
    text = h.vxa_text
    leaves = [m for m in re.finditer(r"<(\w+)>([^<]*)</\1>", text)]
    values = ["", "abc", "-1", "0", "1e400", "nan", "inf", "-inf", "99999999999999999999",
              "1e-320", "0x10", " 1 ", "1,5", "-0"]
    k = 0

    def one(label, body, expect, enc="latin-1", check_ref=None, garbage=False):
        nonlocal k
        f = "%s/vx%05d.vxa" % (d, k)
        k += 1
        with open(f, "wb") as fh:
            fh.write(body if isinstance(body, bytes) else body.encode(enc, "replace"))
        check = sane_sim(check_ref)
        if garbage:  # a tag that is read must refuse text that is not a number
            check = first_of(check, lambda r: "" if json.loads(r["out"]).get(
                "final_state_hash") == h.vxa_ref["final_state_hash"] else
                "a value that is not a number was accepted and changed the life")
        h.cli_case(cat, label, ["simulate", f, "--json"], expect, check, ok_rcs=(0, 3))
        return f

    # Every leaf element: a bad value, deleted, given twice.
    for m in leaves:
        tag = m.group(1)
        for v in h.rng.sample(values, 4):
            one("value <%s>=%r" % (tag, v), text[:m.start(2)] + v + text[m.end(2):], "either",
                garbage=v in ("", "abc", "nan", "inf", "-inf", "1e400", "1,5", "0x10"))
        one("deleted <%s>" % tag, text[:m.start()] + text[m.end():], "either")
        one("twice <%s>" % tag, text[:m.end()] + m.group(0) + text[m.end():], "either")
    # Layers: wrong lengths, bad characters.
    layers = [m for m in re.finditer(r"<!\[CDATA\[([^\]]*)\]\]>", text)]
    for m in h.rng.sample(layers, min(len(layers), 12)):
        body = m.group(1)
        for label, new in (("short layer", body[: len(body) // 2]),
                           ("long layer", body + body),
                           ("letters in layer", body.replace("0", "q", 1)),
                           ("NaN in layer", body.replace("0", "nan", 1) if "," in body else body)):
            expect = "refuse" if new != body else "either"
            one(label, text[:m.start(1)] + new + text[m.end(1):], expect)
    # Byte damage.
    raw = text.encode("latin-1")
    for i in range(60):
        mode, b, expect = damage_text(h, raw, ["truncate", "flip", "flip", "insert"], tail=20)
        one("bytes: " + mode, b, expect)
    # XML attacks.
    head, rest = text.split("\n", 1)
    lol = "".join('<!ENTITY l%d "%s">' % (i, ("&l%d;" % (i - 1)) * 10 if i else "lol" * 10)
                  for i in range(10))
    attacks = [
        ("billion laughs", head + "\n<!DOCTYPE VXA [" + lol + "]>\n" +
         rest.replace("<DtFrac>0.9", "<DtFrac>&l9;"), "refuse"),
        ("external entity", head + '\n<!DOCTYPE VXA [<!ENTITY x SYSTEM "file:///etc/passwd">]>\n' +
         rest.replace("<DtFrac>0.9", "<DtFrac>&x;"), "refuse"),
        ("100 000 attributes", text.replace("<Integrator>", "<Integrator " + " ".join(
            'a%d="1"' % i for i in range(100000)) + ">", 1), "refuse"),
        ("65 attributes", text.replace("<Integrator>", "<Integrator " + " ".join(
            'a%d="1"' % i for i in range(65)) + ">", 1), "refuse"),
        ("64 attributes", text.replace("<Integrator>", "<Integrator " + " ".join(
            'a%d="1"' % i for i in range(64)) + ">", 1), "either"),
        ("100 000 unknown tags", text.replace("<Integration>", "<Integration>" + "".join(
            "<u%d/>" % i for i in range(100000)), 1), "either"),
        ("100 000 nested elements", text.replace("<Integration>", "<Integration>" +
                                                 "<n>" * 100000 + "</n>" * 100000, 1), "either"),
        ("X_Voxels 100000", re.sub(r"<X_Voxels>\d+", "<X_Voxels>100000", text), "refuse"),
        ("X_Voxels -3", re.sub(r"<X_Voxels>\d+", "<X_Voxels>-3", text), "refuse"),
        ("not XML", "hello", "refuse"),
        ("empty", "", "refuse"),
        ("UTF-16", text, "either"),
        ("two roots", text + text, "refuse"),
        ("comment in a number", text.replace("<DtFrac>0.9", "<DtFrac>0<!-- c -->.9"), "either"),
        ("unclosed CDATA", text.replace("]]></Layer>", "</Layer>", 1), "refuse"),
    ]
    for label, body, expect in attacks:
        f = one("xml: " + label, body, expect, enc="utf-16" if label == "UTF-16" else "latin-1")
        os.remove(f)
    # The equivalent file: whitespace between elements must not matter.
    one("equivalent: blank lines", text.replace("\n", "\n\n"), "valid", check_ref=h.vxa_ref)


# ---- generators: configs and command lines -------------------------------------------

EVOLVE_VALID = {
    "seed": lambda v: is_int(v) and 0 <= v < 2 ** 64,
    "population": lambda v: is_int(v) and 1 <= v <= 6,
    "generations": lambda v: is_int(v) and 0 <= v <= 100000000,
    "treatment": lambda v: v in ("none", "stress", "pressure", "strain", "strain_energy",
                                 "contact", "kinetic"),
    "min_fill": lambda v: is_num(v) and 0 <= v <= 1 and None,
    "max_mutation_tries": lambda v: is_int(v) and 1 <= v <= 10000000,
    "checkpoint_every": lambda v: is_int(v) and v >= 1 and v < 2 ** 31,
    "threads": lambda v: is_int(v) and 0 <= v <= 4096,
    "geometry": lambda v: v in ("largest-component", "keep-all"),
    "initial_population": lambda v: False if v != "random" else True,
}


def gen_config_cli(h):
    cat = "config-cli"
    d = h.scratch
    b = h.base
    base = base_evolve()
    extra = [0, 1, 2, 3, 6, 4096, 4097, 100001, "random", "body-plans", "keep-all", "stress",
             "contact", 0.5]
    k = 0
    for key, ok in list(EVOLVE_VALID.items()) + [("lattice", None), ("physics", None),
                                                   ("format", None), ("version", None),
                                                   ("surprise", None)]:
        for v in BAD_VALUES + extra:
            if key == "population" and is_int(v) and 6 < v <= 100000:
                continue  # valid, but minutes of work
            c = json.loads(json.dumps(base))
            c[key] = v
            valid = ok(v) if ok and not (isinstance(v, str) and v in RAW) else False
            if key in ("physics", "lattice") and v == {}:
                valid = None  # every field has a default
            if key == "version" and v == 1 and is_int(v):
                valid = True
            expect = {True: "valid", False: "refuse", None: "either"}[valid]
            f = "%s/ev%05d.json" % (d, k)
            out = "%s/ev%05d.h5" % (d, k)
            k += 1
            open(f, "w").write(dump_raw(c))
            h.cli_case(cat, "evolve %s=%s" % (key, json.dumps(v)[:20]),
                       ["evolve", "--config", f, "--out", out, "--threads", "1",
                        "--stop-after", "2"], expect)
            for p in (out, out + ".lock"):
                if os.path.exists(p):
                    os.remove(p)
    # Experiment configs: estimate only (a formula: must answer at once, issue 40).
    xbase = base_experiment()
    xmut = [
        (("evolution", "population"), 100000, "either"),
        (("evolution", "generations"), 100000000, "either"),
        (("evolution", "generations"), 10000000, "either"),
        (("evolution", "population"), 0, "refuse"),
        (("seeds",), [], "refuse"),
        (("seeds",), [-1], "refuse"),
        (("seeds",), [1, 1], "refuse"),
        (("seeds",), list(range(1, 1001)), "either"),
        (("treatments",), ["none", "none"], "refuse"),
        (("treatments",), ["bogus"], "refuse"),
        (("treatments",), [], "refuse"),
        (("analysis", "resamples"), 10, "refuse"),
        (("analysis", "resamples"), 10 ** 12, "refuse"),
        (("analysis", "robustness_draws"), -1, "refuse"),
        (("analysis", "rotations"), "some", "refuse"),
        (("rendering", "figure_size"), "100x100", "refuse"),
        (("rendering", "figure_size"), "99999x99999", "refuse"),
        (("rendering", "gallery_size"), "10x10", "refuse"),
        (("rendering", "gallery_size"), "16385x100", "refuse"),
        (("rendering", "video_size"), "0x0", "refuse"),
        (("rendering", "video_fps"), 0, "refuse"),
        (("rendering", "video_fps"), 1e9, "refuse"),
        (("rendering", "video_color"), "plaid", "refuse"),
        (("rendering", "surprise"), 1, "refuse"),
        (("surprise",), 1, "refuse"),
        (("name",), "../../etc", "either"),
        (("name",), "", "either"),
        (("evolution", "physics", "duration"), 1e4, "either"),
        (("evolution", "physics", "dt_frac"), 0, "refuse"),
    ]
    for path, v, expect in xmut:
        for extra_args in ([], ["--cores", "64"], ["--ranks", "4", "--json"]):
            c = json.loads(json.dumps(xbase))
            obj = c
            for p in path[:-1]:
                obj = obj[p]
            obj[path[-1]] = v
            f = "%s/xp%05d.json" % (d, k)
            k += 1
            open(f, "w").write(json.dumps(c))
            known = ("estimate not a formula" if ("generations" in path or "population" in path
                                                  or v == list(range(1, 1001))) else None)
            h.cli_case(cat, "experiment --estimate-only %s=%s" % (".".join(path), str(v)[:20]),
                       ["experiment", "--config", f, "--out", d + "/xp-out", "--estimate-only"] +
                       extra_args, expect, known=known)
    # Command lines: every command with random bad options and values.
    robot = b + "/robot.json"
    run = b + "/run.h5"
    commands = {
        "simulate": [robot],
        "render": [robot, "--out", d + "/c.png", "--size", "64x48"],
        "video": [robot, "--out", d + "/c.mp4", "--size", "64x48", "--fps", "4"],
        "view": [robot, "--out", d + "/c.html"],
        "export": [run, "--out", d + "/c.json"],
        "inspect": [run],
        "hausdorff": [robot, robot],
        "analyze": [run, "--out", d + "/c-an", "--threads", "1", "--resamples", "100",
                    "--robustness-draws", "1"],
        "gallery": [run, "--out", d + "/c-g.png", "--size", "480x270"],
        "figures": [b + "/study/stats.json", "--out", d + "/c-fig", "--size", "200x200"],
        "evolve": ["--config", b + "/evolve.json", "--out", d + "/c.h5", "--threads", "1"],
    }
    options = {
        "simulate": ["--treatment", "--preset", "--duration", "--physics", "--fps", "--record"],
        "render": ["--time", "--size", "--color", "--color-range", "--camera", "--zoom",
                   "--azimuth", "--elevation", "--antialias", "--samples"],
        "video": ["--fps", "--start", "--end", "--stride", "--codec", "--size", "--zoom"],
        "view": ["--fps", "--generation"],
        "export": ["--generation", "--demo"],
        "inspect": ["--json", "--bogus"],
        "hausdorff": ["--rotations", "--translation"],
        "analyze": ["--generation", "--robustness-draws", "--resamples", "--seed",
                    "--rotations", "--treatments", "--robustness-sampling"],
        "gallery": ["--columns", "--time", "--e0-range", "--samples", "--size"],
        "figures": ["--size", "--format"],
        "evolve": ["--threads", "--stop-after"],
    }
    bad = ["", "-1", "0", "nan", "inf", "-inf", "1e400", "99999999999999999999", "abc", "1x",
           "0x0", "-5x5", "1e9x1e9", "16385x16385", "65536x1", "3.5", "\x01", "x" * 5000,
           "--json", "2147483648", "-0", "none,none", ",", "1,2,3", "1e-320"]
    for i in range(420):
        cmd = h.rng.choice(sorted(commands))
        opt = h.rng.choice(options[cmd])
        val = h.rng.choice(bad)
        argv = [cmd] + commands[cmd] + [opt, val]
        if h.rng.random() < 0.1:
            argv = [cmd] + commands[cmd][: h.rng.randrange(len(commands[cmd]) + 1)] + [opt]
        h.cli_case(cat, "cli %s %s %r" % (cmd, opt, val[:12]), argv, "either",
                   check=cli_output_check(d))
        for junk in ("c.png", "c.mp4", "c.html", "c.json", "c.h5", "c.h5.lock", "c-g.png"):
            if os.path.exists(os.path.join(d, junk)):
                os.remove(os.path.join(d, junk))
        for junk in ("c-an", "c-fig"):
            shutil.rmtree(os.path.join(d, junk), ignore_errors=True)
    for argv in ([], ["bogus"], ["--help", "--help"], ["simulate", "a", "b"], ["-"],
                 ["simulate", "--physics", "{" * 100000], ["simulate", "--physics", "[]"],
                 ["evolve"], ["render", robot], ["analyze"], ["x" * 100000]):
        h.cli_case(cat, "cli %r" % " ".join(argv)[:30], argv,
                   "either" if argv in ([], ["--help", "--help"]) else "refuse",
                   known=None)


def cli_output_check(d):
    def check(r):
        taken = [f for f in os.listdir(d) if f.startswith("--")]
        for f in taken:
            p = os.path.join(d, f)
            shutil.rmtree(p) if os.path.isdir(p) else os.remove(p)
        if taken:
            return "took the option %s as the value of the option before it (wrote %s)" % (
                taken[0].split(".")[0], taken[0])
        # An accepted image must be a real PNG of a sane size.
        for name in ("c.png", "c-g.png"):
            p = os.path.join(d, name)
            if os.path.exists(p):
                with open(p, "rb") as f:
                    head = f.read(24)
                if head[:8] != b"\x89PNG\r\n\x1a\n":
                    return "accepted, but %s is not a PNG" % name
                w, hh = int.from_bytes(head[16:20], "big"), int.from_bytes(head[20:24], "big")
                if not (0 < w <= 16384 and 0 < hh <= 16384):
                    return "accepted with a %dx%d image" % (w, hh)
        return ""

    return check


# ---- generators: damaged results files, recorded lives, study folders ------------------

def damage(h, raw):
    b = bytearray(raw)
    mode = h.rng.choice(["truncate", "flip", "flip", "flip", "zero-block", "append", "garbage",
                         "signature", "empty"])
    pos = h.rng.randrange(len(raw))
    if mode == "truncate":
        b = b[:pos]
    elif mode == "flip":
        b[pos] ^= 1 << h.rng.randrange(8)
    elif mode == "zero-block":
        b[pos:pos + 512] = bytes(len(b[pos:pos + 512]))
    elif mode == "append":
        b += bytes(h.rng.randrange(256) for _ in range(h.rng.randrange(1, 4096)))
    elif mode == "garbage":
        b = bytearray(h.rng.randrange(256) for _ in range(len(raw)))
    elif mode == "signature":
        b[0:8] = b"\x89HDF\r\n\x1a\n"[::-1]
    else:
        b = bytearray()
    return mode + ("@%d" % pos if mode in ("truncate", "flip", "zero-block") else ""), bytes(b)


def same_as_baseline(h, name, reader, out):
    """An accepted damaged input must give exactly the undamaged input's output."""

    def check(r):
        rc, dig, insp = h.baseline[(name, reader)]
        if rc not in (0, 3):
            return ""
        if reader == "inspect":
            if strip_inspect(r) != insp:
                return "damaged file read without error, summary differs from the original's"
        elif file_digest(out) != dig:
            return "damaged file read without error, output differs from the original's"
        return ""

    return check


def gen_damaged(h):
    cat = "damaged-files"
    d = h.scratch
    b = h.base
    for name, src, n in (("run", b + "/run.h5", 200), ("life", b + "/life.h5", 200)):
        raw = open(src, "rb").read()
        for i in range(n):
            mode, data = damage(h, raw)
            f = "%s/%s-%04d.h5" % (d, "results" if name == "run" else "life", i)
            open(f, "wb").write(data)
            readers = h.readers(f)
            reader, argv, out = h.rng.choice(readers)
            if os.path.exists(out):
                os.remove(out)
            h.cli_case(cat, "%s %s: %s" % (name, reader, mode), argv, "either",
                       same_as_baseline(h, name, reader, out), ok_rcs=(0, 3))
            if i % 5 == 0:
                body = ("r = pv.%s(%r)\n" % ("read_results" if name == "run" else "render", f) +
                        ("require(r.best_fitness.tolist() == pv.read_results(%r).best_fitness"
                         ".tolist(), 'damaged results read, different fitness')" % src
                         if name == "run" else
                         "require((r == pv.render(%r)).all(), 'damaged life drawn differently')"
                         % src))
                h.py_case(cat, "python %s: %s" % (name, mode), body, "either")
            if name == "run" and i % 4 == 0:
                # Resuming from a damaged results file: refuse, or end at the same digest.
                def resumed(r, f=f):
                    got = digest_of(h.pv("inspect", f, "--json"))
                    if got != h.run_digest:
                        return "resumed a damaged results file to digest %s, not %s" % (
                            got, h.run_digest)
                    return ""

                h.cli_case(cat, "run evolve-resume: " + mode,
                           ["evolve", "--config", b + "/evolve.json", "--out", f, "--threads",
                            "1"], "either", resumed)
            for p in (f, f + ".lock", out):
                if os.path.exists(p):
                    os.remove(p)
    # Study folders: damage one output, rerun the same command; it must repair or refuse.
    study = b + "/study"
    files = sorted(os.path.relpath(os.path.join(r, f), study) for r, _, fs in os.walk(study)
                   for f in fs if not f.endswith((".lock", ".log")) and "/cache/" not in
                   os.path.join(r, f) and not f.startswith("."))
    for i, rel in enumerate(files * 2):
        copy = "%s/study-%03d" % (d, i)
        shutil.copytree(study, copy)
        target = os.path.join(copy, rel)
        raw = open(target, "rb").read()
        how = "truncated" if i < len(files) else "overwritten"
        data = raw[: len(raw) // 3] if how == "truncated" else b"damaged\n" * 7
        open(target, "wb").write(data)

        def repaired(r, target=target, data=data):
            if os.path.exists(target) and open(target, "rb").read() == data:
                return "rerun exits 0 and keeps the damaged file"
            return ""

        # read_study reads stats.json, champions.csv and statistics.csv (not hausdorff.csv,
        # whose numbers it takes from stats.json): a damaged one of those must be refused.
        if rel in ("stats.json", "champions.csv", "statistics.csv"):
            h.py_case(cat, "python read_study, %s %s" % (rel, how),
                      "s = pv.read_study(%r)\nreturn len(s.champions)" % copy,
                      "either" if how == "truncated" else "refuse")
        h.cli_case(cat, "study %s %s, rerun" % (rel, how),
                   ["experiment", "--config", b + "/experiment.json", "--out", copy,
                    "--threads", "1"], "either", repaired, known="damaged study not repaired")
        shutil.rmtree(copy)


# ---- generators: interruptions -------------------------------------------------------

def gen_interruption(h):
    cat = "interruption"
    d = h.scratch
    b = h.base
    cfg = b + "/long.json"
    sigs = [signal.SIGKILL, signal.SIGINT, signal.SIGTERM]
    for i in range(h.args.kills):
        sig = sigs[i % 3]
        twice = i % 7 == 6  # kill the resumed run too
        out = "%s/kill-%03d.h5" % (d, i)
        argv = [h.exe, "evolve", "--config", cfg, "--out", out, "--threads", "1"]
        delays = [h.rng.uniform(0.02, h.long_wall * 1.1) for _ in range(2 if twice else 1)]
        verdict = None
        for delay in delays:
            r = h.interrupt(argv, delay, sig)
            if r["timed_out"]:
                verdict = ("hang", "no exit within %g s after %s" % (h.timeout, sig.name))
                break
            if r["rc"] < 0 and -r["rc"] != sig:
                verdict = ("crash", "died of %s after %s" % (
                    signal.Signals(-r["rc"]).name, sig.name))
                break
            if sig != signal.SIGKILL and r["rc"] not in (0, 130, 143, -sig):
                verdict = ("wrong", "exit %d after %s" % (r["rc"], sig.name))
                break
            if any(m in r["err"] for m in CRASH_MARKS):
                verdict = ("crash", last_line(r["err"]))
                break
        r = h.run(argv)
        if verdict is None:
            outcome, reason = h.classify(r, "valid")
            if outcome == "accepted":
                got = digest_of(h.pv("inspect", out, "--json"))
                if got != h.long_digest:
                    outcome, reason = "lost", "resumed digest %s, uninterrupted %s" % (
                        got, h.long_digest)
                else:
                    leftovers = [f for f in os.listdir(d) if f.startswith(
                        "kill-%03d.h5.tmp" % i)]
                    if leftovers:
                        outcome, reason = "wrong", "temporaries left: %s" % leftovers
        else:
            outcome, reason = verdict
        repro = "cd %s && %s evolve --config %s --out %s --threads 1 & sleep %s; kill -%s $!; " \
                "then rerun and compare 'inspect --json' content_digest with %s" % (
                    d, h.exe, cfg, out, " then ".join("%.3f" % x for x in delays), sig.name,
                    h.long_digest)
        h.record(cat, "evolve %s at %s s%s" % (sig.name, "/".join("%.2f" % x for x in delays),
                                               ", twice" if twice else ""),
                 repro, outcome, reason, r)
        for f in os.listdir(d):
            if f.startswith("kill-%03d" % i):
                os.remove(os.path.join(d, f))
    # Two processes on one results file at once: the lock lets one through, the other gets
    # one line; the file ends at the uninterrupted digest.
    for i in range(h.args.kills // 9):
        out = "%s/twice-%03d.h5" % (d, i)
        argv = [h.exe, "evolve", "--config", cfg, "--out", out, "--threads", "1"]
        start = time.time()
        first = h.spawn(argv)
        time.sleep(h.rng.uniform(0.0, 0.3))
        r2 = h.run(argv)
        r1 = h.finish(first, start)
        o1, why1 = h.classify(r1, "either")
        o2, why2 = h.classify(r2, "either")
        outcome, reason = (o1, why1) if o1 in DEFECTS else (o2, why2)
        if outcome not in DEFECTS:
            if r1["rc"] != 0 and r2["rc"] != 0:
                outcome, reason = "wrong", "both refused: " + last_line(r2["err"])
            else:
                r = h.run(argv)  # whichever was refused: the same command again finishes
                got = digest_of(h.pv("inspect", out, "--json"))
                if got != h.long_digest:
                    outcome, reason = "lost", "two writers left digest %s, not %s" % (
                        got, h.long_digest)
                else:
                    outcome, reason = "accepted", "second writer: " + last_line(r2["err"])
        repro = "cd %s && (%s evolve --config %s --out %s --threads 1 &) ; the same again" % (
            d, h.exe, cfg, out)
        h.record(cat, "two evolves on one file", repro, outcome, reason, r2)
        for f in os.listdir(d):
            if f.startswith("twice-%03d" % i):
                os.remove(os.path.join(d, f))
    # Kills during a whole study, then the same command: the runs must end identical.
    x = b + "/experiment.json"
    ref = {f: digest_of(h.pv("inspect", b + "/study/runs/" + f, "--json"))
           for f in os.listdir(b + "/study/runs") if f.endswith(".h5")}
    for i in range(h.args.kills // 6):
        sig = sigs[i % 3]
        out = "%s/kstudy-%03d" % (d, i)
        argv = [h.exe, "experiment", "--config", x, "--out", out, "--threads", "1"]
        delay = h.rng.uniform(0.05, 1.5)
        r1 = h.interrupt(argv, delay, sig)
        r = h.run(argv)
        outcome, reason = h.classify(r, "valid")
        if r1["rc"] < 0 and -r1["rc"] != sig:
            outcome, reason = "crash", "died of %s after %s" % (
                signal.Signals(-r1["rc"]).name, sig.name)
        elif outcome == "accepted":
            got = {f: digest_of(h.pv("inspect", out + "/runs/" + f, "--json")) for f in ref}
            if got != ref:
                outcome, reason = "lost", "runs after resume %s, uninterrupted %s" % (got, ref)
            elif not os.path.exists(out + "/report.html"):
                outcome, reason = "lost", "resumed study has no report.html"
        repro = "cd %s && %s experiment --config %s --out %s --threads 1 & sleep %.3f; " \
                "kill -%s $!; rerun" % (d, h.exe, x, out, delay, sig.name)
        h.record(cat, "experiment %s at %.2f s" % (sig.name, delay), repro, outcome, reason, r)
        shutil.rmtree(out, ignore_errors=True)


# ---- generators: full disks, read-only folders, devices ------------------------------

def gen_disk(h):
    cat = "disk"
    d = h.scratch
    b = h.base
    sizes = ["4k", "12k", "24k", "40k", "64k", "100k", "160k", "256k", "512k", "1m", "4m"]
    for i in range(h.args.disk):
        size = sizes[i % len(sizes)]
        m = h.tmpfs("full%03d" % i, size)
        what = ["evolve", "evolve", "record", "record-history", "export", "render", "view",
                "experiment", "analyze"][i % 9]
        skip = {"PLASTIVOX_SKIP_DISK_CHECK": "1"} if i % 2 else None
        setup = "mkdir -p %s && mount -t tmpfs -o size=%s tmpfs %s" % (m, size, m)
        if what == "evolve":
            out = m + "/run.h5"
            argv = ["evolve", "--config", b + "/long.json", "--out", out, "--threads", "1"]

            def check_evolve(r, out=out):
                got = digest_of(h.pv("inspect", out, "--json"))
                return "" if got == h.long_digest else "exit 0, digest %s not %s" % (
                    got, h.long_digest)

            c = h.cli_case(cat, "full disk %s: evolve" % size, argv, "either", check_evolve,
                           env=skip, setup=setup)
            if c["outcome"] == "clean error" and os.path.exists(out):
                # The last checkpoint must be intact: resume it on a roomy disk.
                roomy = "%s/roomy-%03d.h5" % (d, i)
                shutil.copy(out, roomy)
                r = h.pv("evolve", "--config", b + "/long.json", "--out", roomy, "--threads", "1")
                got = digest_of(h.pv("inspect", roomy, "--json"))
                if got != h.long_digest:
                    h.record(cat, "full disk %s: evolve, resumed elsewhere" % size,
                             c["repro"] + " ; cp run.h5 elsewhere and rerun", "lost",
                             "digest %s not %s after resume (exit %d)" % (
                                 got, h.long_digest, r["rc"]), r)
                else:
                    h.record(cat, "full disk %s: evolve, resumed elsewhere" % size, c["repro"],
                             "accepted", "", r)
        elif what.startswith("record"):
            out = m + ("/life.h5" if what == "record" else "/life.history")
            argv = ["simulate", b + "/robot.json", "--record", out, "--fps", "200"]

            def check_life(r, out=out):
                if out.endswith(".h5"):
                    rr = h.pv("render", out, "--out", d + "/full.png", "--size", "64x48")
                    if rr["rc"] != 0:
                        return "exit 0 but the recorded life is unreadable: " + last_line(
                            rr["err"])
                return ""

            c = h.cli_case(cat, "full disk %s: %s" % (size, what), argv, "either", check_life,
                           ok_rcs=(0, 3), env=skip, setup=setup)
            if c["outcome"] == "clean error" and os.path.exists(out):
                h.record(cat, "full disk %s: %s leftover" % (size, what), c["repro"], "wrong",
                         "a failed recording left a partial %s" % out)
        else:
            argv = {
                "export": ["export", b + "/run.h5", "--out", m + "/c.json"],
                "render": ["render", b + "/robot.json", "--out", m + "/c.png", "--size",
                           "320x240"],
                "view": ["view", b + "/robot.json", "--out", m + "/c.html"],
                "experiment": ["experiment", "--config", b + "/experiment.json", "--out",
                               m + "/study", "--threads", "1"],
                "analyze": ["analyze", b + "/run.h5", "--out", m + "/an", "--threads", "1",
                            "--resamples", "100", "--robustness-draws", "1"],
            }[what]
            h.cli_case(cat, "full disk %s: %s" % (size, what), argv, "either", env=skip,
                       setup=setup)
        h.umount(m)
    # Read-only mounts holding finished outputs.
    ro = h.tmpfs("ro", "16m")
    shutil.copy(b + "/run.h5", ro + "/run.h5")
    shutil.copy(b + "/robot.json", ro + "/robot.json")
    shutil.copytree(b + "/study", ro + "/study")
    subprocess.run(["mount", "-o", "remount,ro", ro], check=True)
    setup = "mount -o remount,ro %s" % ro
    ro_cases = [
        ("inspect", ["inspect", ro + "/run.h5"], "valid", None),
        ("export out of", ["export", ro + "/run.h5", "--out", d + "/ro.json"], "valid", None),
        ("render from", ["render", ro + "/robot.json", "--out", d + "/ro.png", "--size",
                         "64x48"], "valid", None),
        ("finished evolve", ["evolve", "--config", b + "/evolve.json", "--out", ro + "/run.h5"],
         "valid", "cannot create lock file on a read-only mount"),
        ("new evolve", ["evolve", "--config", b + "/evolve.json", "--out", ro + "/new.h5"],
         "refuse", None),
        ("export into", ["export", b + "/run.h5", "--out", ro + "/c.json"], "refuse", None),
        ("record into", ["simulate", b + "/robot.json", "--record", ro + "/l.h5"], "refuse",
         None),
        ("render into", ["render", b + "/robot.json", "--out", ro + "/c.png"], "refuse", None),
        ("view into", ["view", b + "/robot.json", "--out", ro + "/c.html"], "refuse", None),
        ("video into", ["video", b + "/robot.json", "--out", ro + "/c.mp4"], "refuse", None),
        ("analyze into", ["analyze", b + "/run.h5", "--out", ro + "/an"], "refuse", None),
        ("finished study", ["experiment", "--config", b + "/experiment.json", "--out",
                            ro + "/study", "--threads", "1"], "either", None),
        ("new study", ["experiment", "--config", b + "/experiment.json", "--out",
                       ro + "/study2"], "refuse", None),
    ]
    for label, argv, expect, known in ro_cases:
        h.cli_case(cat, "read-only: " + label, argv, expect, ok_rcs=(0, 3), known=known,
                   setup=setup)
    h.py_case(cat, "read-only: python read_results",
              "return pv.read_results(%r).generations_done" % (ro + "/run.h5"), "valid")
    h.py_case(cat, "read-only: python save into",
              "pv.load_robot(BASE + '/robot.json').save(%r)" % (ro + "/x.json"), "refuse")
    h.umount(ro)
    # Devices, FIFOs, sockets and folders as outputs: refused, and left as they were.
    nodes = {}
    for name, make in (("null", lambda p: os.mknod(p, 0o666 | 0o020000, os.makedev(1, 3))),
                       ("full", lambda p: os.mknod(p, 0o666 | 0o020000, os.makedev(1, 7))),
                       ("fifo", os.mkfifo), ("dir", os.mkdir),
                       ("socket", lambda p: socket.socket(socket.AF_UNIX).bind(p))):
        p = "%s/node-%s" % (d, name)
        make(p)
        nodes[name] = (p, os.lstat(p).st_mode, os.lstat(p).st_ino)
    writers = [
        ["render", b + "/robot.json", "--size", "64x48", "--out"],
        ["video", b + "/robot.json", "--size", "64x48", "--fps", "4", "--out"],
        ["view", b + "/robot.json", "--out"],
        ["gallery", b + "/run.h5", "--size", "480x270", "--out"],
        ["export", b + "/run.h5", "--out"],
        ["simulate", b + "/robot.json", "--record"],
        ["evolve", "--config", b + "/evolve.json", "--out"],
        ["analyze", b + "/run.h5", "--resamples", "100", "--robustness-draws", "1", "--out"],
        ["figures", b + "/study/stats.json", "--size", "200x200", "--out"],
    ]
    for name, (p, mode, ino) in nodes.items():
        for w in writers:
            if name == "dir" and w[0] in ("analyze", "figures"):
                continue  # a folder is their output

            def left_alone(p=p, mode=mode, ino=ino):
                st = os.lstat(p)
                return "" if (st.st_mode, st.st_ino) == (mode, ino) else "replaced " + p

            h.cli_case(cat, "%s as --out of %s" % (name, w[0]), w + [p], "refuse",
                       post=left_alone)
            for f in os.listdir(d):
                if f.startswith("node-%s." % name):
                    path = os.path.join(d, f)
                    if os.path.isdir(path):
                        shutil.rmtree(path)
                    else:
                        os.remove(path)


# ---- generators: extreme physics ------------------------------------------------------

PHYSICS_VALID = {  # the documented ranges (validate in engine/core/src/physics_def.cpp)
    "density": lambda v: is_num(v) and v > 0,
    "poisson": lambda v: is_num(v) and 0 <= v < 0.5,
    "mu_static": lambda v: is_num(v) and v >= 0,
    "mu_kinetic": lambda v: is_num(v) and v >= 0,
    "e_min": lambda v: is_num(v) and 0 < v < 1e11,
    "e_max": lambda v: is_num(v) and v > 1e5,
    "bond_damping": lambda v: is_num(v) and v >= 0,
    "collision_damping": lambda v: is_num(v) and v >= 0,
    "global_damping": lambda v: is_num(v) and v >= 0,
    "global_damping_rot_factor": lambda v: is_num(v) and v >= 0,
    "collision_exclude_hops": lambda v: is_int(v) and 0 <= v <= 1000,
    "contact_diameter": lambda v: is_num(v) and 0 < v <= 10,
    "gravity": lambda v: is_num(v) and v <= 0,  # upwards gravity is refused
    "dt_frac": lambda v: is_num(v) and 1e-3 <= v <= 1.5,
    "act_frequency": lambda v: is_num(v) and v >= 0,
    "act_amplitude": lambda v: is_num(v) and 0 <= v < 0.9,
    "act_min_factor": lambda v: is_num(v) and 0 <= v <= 1,
    "settle_time": lambda v: is_num(v) and 0 <= v <= 0.3,
    "duration": lambda v: is_num(v) and 0.2 <= v <= 1e4,
    "max_change_per_step": lambda v: is_num(v) and v > 0,
    "min_devo_factor": lambda v: is_num(v) and v >= 0,
    "max_speed": lambda v: is_num(v) and v > 0,
    "record_fps": lambda v: is_num(v) and 0 <= v <= 10000,
    "floor": lambda v: isinstance(v, bool),
    "self_collision": lambda v: isinstance(v, bool),
    "sinking_invalid": lambda v: isinstance(v, bool),
    "growth": lambda v: v in ("integral", "rate"),
    "fitness": lambda v: v in ("3d", "xy"),
    "axial_modulus": lambda v: v in ("harmonic", "negative-voxel"),
    "bond_model": lambda v: v in ("exact", "voxelyze09"),
    "treatment": lambda v: v in ("none", "stress", "pressure", "strain", "strain_energy",
                                 "contact", "kinetic"),
}
PHYS_VALUES = [-1e308, -1, -0.0, 0, 5e-324, 1e-300, 1e-3, 0.1, 0.3, 0.49, 0.5, 0.9, 1, 1.5, 2,
               10, 10.5, 1000, 1001, 1e6, 1e12, 1e308, "1e400", "-1e400", "NaN", True, "x",
               None, [], "rate", "xy", "exact", "pressure", 3]


def gen_physics(h):
    cat = "physics"
    d = h.scratch
    base = base_robot()
    k = 0
    for field, ok in PHYSICS_VALID.items():
        for v in PHYS_VALUES:
            raw = isinstance(v, str) and v in ("1e400", "-1e400", "NaN")
            valid = ok(v) if not raw else False
            # A valid value must simulate (or be reported unstable, exit 3), except where
            # the documented step limit may refuse it: those are "either".
            expect = "valid" if valid else "refuse"
            slow = field in ("density", "dt_frac", "e_max", "e_min", "duration", "act_frequency",
                             "max_change_per_step", "record_fps") or (
                field == "gravity" and is_num(v) and abs(v) > 1e6)
            if valid and (slow or (is_num(v) and abs(v) > 1e6)):
                expect = "either"
            via_cli = k % 2 == 0
            k += 1
            if via_cli:
                argv = ["simulate", h.base + "/robot.json", "--json", "--physics",
                        dump_raw({field: v})]
            else:
                r = json.loads(json.dumps(base))
                r["physics"][field] = v
                f = "%s/ph%05d.json" % (d, k)
                open(f, "w").write(dump_raw(r))
                argv = ["simulate", f, "--json"]
            h.cli_case(cat, "%s=%s via %s" % (field, json.dumps(v), "--physics" if via_cli
                                               else "robot file"),
                       argv, expect, sane_sim(), ok_rcs=(0, 3))
    # Extreme but valid bodies: very stiff, very soft, the stiffness extremes side by side.
    for label, e in (("1e11 Pa", 1e11), ("1e5 Pa", 1e5), ("1e300 Pa (clamped)", 1e300),
                     ("5e-324 Pa (clamped)", 5e-324)):
        r = json.loads(json.dumps(base))
        for vx in r["voxels"]:
            vx[3] = e
        f = "%s/ph-e-%d.json" % (d, k)
        k += 1
        open(f, "w").write(json.dumps(r))
        h.cli_case(cat, "all voxels " + label, ["simulate", f, "--json"], "valid", sane_sim(),
                   ok_rcs=(0, 3))
    for label, env in (("steps limit 10", {"PLASTIVOX_MAX_STEPS": "10"}),
                       ("steps limit x", {"PLASTIVOX_MAX_STEPS": "x"}),
                       ("steps limit -1", {"PLASTIVOX_MAX_STEPS": "-1"}),
                       ("lattice limit 1", {"PLASTIVOX_MAX_LATTICE_SITES": "1"}),
                       ("lattice limit 1e99", {"PLASTIVOX_MAX_LATTICE_SITES": "1e99"})):
        h.cli_case(cat, "env " + label, ["simulate", h.base + "/robot.json", "--json"], "refuse",
                   env=env)
    # Recording bounds (issue 40, not done yet): a huge frame rate on a long life.
    for fps in ("10000", "1e9", "0", "-30", "nan"):
        h.cli_case(cat, "record at %s fps, 60 s" % fps,
                   ["simulate", h.base + "/robot.json", "--record", d + "/rec.h5", "--fps", fps,
                    "--duration", "60"], "either", ok_rcs=(0, 3),
                   known="no recording size limit" if fps == "10000" else None)
        if os.path.exists(d + "/rec.h5"):
            os.remove(d + "/rec.h5")


# ---- generators: Python ---------------------------------------------------------------

def gen_python(h):
    cat = "python"
    arrays = [
        ("empty 0x0x0", "np.ones((0, 0, 0), bool)", "refuse"),
        ("1-D", "np.ones(4, bool)", "refuse"),
        ("2-D", "np.ones((2, 2), bool)", "refuse"),
        ("4-D", "np.ones((2, 2, 2, 2), bool)", "refuse"),
        ("0-D", "np.array(True)", "refuse"),
        ("object dtype", "np.full((2, 2, 2), object(), dtype=object)", "refuse"),
        ("strings", "np.full((2, 2, 2), 'a')", "refuse"),
        ("complex", "np.ones((2, 2, 2), complex)", "refuse"),
        ("float geometry", "np.ones((2, 2, 2)) * 0.5", "either"),
        ("int8 geometry", "np.ones((2, 2, 2), np.int8)", "valid"),
        ("Fortran order", "np.asfortranarray(np.ones((2, 3, 2), bool))", "valid"),
        ("strided", "np.ones((4, 6, 4), bool)[::2, ::2, ::2]", "valid"),
        ("negative strides", "np.ones((2, 3, 2), bool)[::-1]", "valid"),
        ("broadcast 1000^3", "np.broadcast_to(np.array(True), (1000, 1000, 1000))", "refuse"),
        ("broadcast 129x128x128", "np.broadcast_to(np.array(True), (129, 128, 128))", "refuse"),
        ("all empty", "np.zeros((2, 2, 2), bool)", "refuse"),
        ("list of lists", "[[[1, 1], [1, 1]], [[1, 1], [1, 1]]]", "either"),
        ("None", "None", "refuse"),
        ("a string", "'robot'", "refuse"),
        ("masked array", "np.ma.masked_array(np.ones((2, 2, 2), bool))", "either"),
        ("1001 long", "np.broadcast_to(np.array(True), (1001, 1, 1))", "refuse"),
    ]
    values = [
        ("stiffness NaN", "stiffness", "np.full(g.shape, np.nan)", "refuse"),
        ("stiffness inf", "stiffness", "np.full(g.shape, np.inf)", "refuse"),
        ("stiffness 0", "stiffness", "np.zeros(g.shape)", "refuse"),
        ("stiffness -1", "stiffness", "-np.ones(g.shape)", "refuse"),
        ("stiffness 1e300", "stiffness", "np.full(g.shape, 1e300)", "valid"),
        ("stiffness int", "stiffness", "np.full(g.shape, 10 ** 9)", "valid"),
        ("stiffness wrong shape", "stiffness", "np.full((3, 3, 3), 1e9)", "refuse"),
        ("stiffness scalar", "stiffness", "1e9", "either"),
        ("stiffness strings", "stiffness", "np.full(g.shape, 'x')", "refuse"),
        ("phase NaN", "phase", "np.full(g.shape, np.nan)", "refuse"),
        ("phase huge", "phase", "np.full(g.shape, 1e300)", "either"),
        ("dev_rate inf", "dev_rate", "np.full(g.shape, -np.inf)", "refuse"),
        ("dev_rate wrong shape", "dev_rate", "np.zeros((2, 2))", "refuse"),
        ("treatment bogus", "treatment", "'bogus'", "refuse"),
        ("treatment int", "treatment", "3", "refuse"),
        ("voxel_size 0", "voxel_size", "0.0", "refuse"),
        ("voxel_size nan", "voxel_size", "float('nan')", "refuse"),
        ("voxel_size 1e9", "voxel_size", "1e9", "refuse"),
        ("voxel_size str", "voxel_size", "'0.01'", "refuse"),
        ("name bytes", "name", "b'x'", "either"),
        ("name 10 MB", "name", "'n' * 10000000", "either"),
        ("name NUL", "name", "'a\\0b'", "either"),
    ]
    for label, expr, expect in arrays:
        body = ("g = %s\nr = pv.Robot.from_arrays(g, stiffness=np.broadcast_to(1e9, np.shape(g)), "
                "phase=np.broadcast_to(0.0, np.shape(g)))\nreturn r.voxel_count" % expr)
        h.py_case(cat, "from_arrays geometry " + label, body, expect)
    for label, key, expr, expect in values:
        body = ("g = np.ones((2, 3, 2), bool)\nkw = dict(stiffness=np.full(g.shape, 1e9), "
                "phase=np.zeros(g.shape))\nkw[%r] = %s\nr = pv.Robot.from_arrays(g, **kw)\n"
                "r2 = pv.simulate(r.with_physics({'duration': 0.3}))\n"
                "require(r2.fitness == r2.fitness, 'NaN fitness')\nreturn r2.status"
                % (key, expr))
        h.py_case(cat, "from_arrays " + label, body, expect)
    body = ("g = np.ones((2, 3, 2), bool)\nkw = dict(stiffness=np.full(g.shape, 1e9), "
            "phase=np.zeros(g.shape))\na = pv.Robot.from_arrays(g, **kw)\n"
            "b = pv.Robot.from_arrays(np.asfortranarray(g), **{k: np.asfortranarray(v) "
            "for k, v in kw.items()})\nrequire(a == b, 'Fortran order gives another robot')\n"
            "require(pickle.loads(pickle.dumps(a)) == a, 'pickle changes the robot')")
    h.py_case(cat, "from_arrays layouts and pickle agree", body, "valid")
    R = "pv.load_robot(BASE + '/robot.json')"
    calls = [
        ("simulate physics bad field", "pv.simulate(%s, physics={'nope': 1})" % R, "refuse"),
        ("simulate physics NaN", "pv.simulate(%s, physics={'density': float('nan')})" % R,
         "refuse"),
        ("simulate physics list", "pv.simulate(%s, physics=[1, 2])" % R, "refuse"),
        ("simulate physics int keys", "pv.simulate(%s, physics={1: 2})" % R, "refuse"),
        ("simulate physics nested", "pv.simulate(%s, physics={'density': {'a': 1}})" % R,
         "refuse"),
        ("simulate physics huge int", "pv.simulate(%s, physics={'collision_exclude_hops': "
         "2 ** 70})" % R, "refuse"),
        ("simulate physics bool for number", "pv.simulate(%s, physics={'density': True})" % R,
         "refuse"),
        ("simulate treatment bogus", "pv.simulate(%s, treatment='x')" % R, "refuse"),
        ("simulate record_fps -1", "pv.simulate(%s, record_fps=-1)" % R, "refuse"),
        ("simulate record_fps nan", "pv.simulate(%s, record_fps=float('nan'))" % R, "refuse"),
        ("simulate record_fps 1e9", "pv.simulate(%s, record_fps=1e9)" % R, "refuse"),
        ("simulate record_fps str", "pv.simulate(%s, record_fps='30')" % R, "refuse"),
        ("simulate None", "pv.simulate(None)", "refuse"),
        ("simulate int", "pv.simulate(5)", "refuse"),
        ("simulate bytes path", "pv.simulate(b'/nonexistent.json')", "refuse"),
        ("simulate missing path", "pv.simulate('/nonexistent.json')", "refuse"),
        ("simulate folder", "pv.simulate(BASE)", "refuse"),
        ("simulate /dev/zero", "pv.simulate('/dev/zero')", "refuse"),
        ("simulate_many empty", "pv.simulate_many([])", "either"),
        ("simulate_many None item", "pv.simulate_many([%s, None])" % R, "refuse"),
        ("simulate_many threads -1", "pv.simulate_many([%s], threads=-1)" % R, "refuse"),
        ("simulate_many threads 1e9", "pv.simulate_many([%s], threads=10 ** 9)" % R, "either"),
        ("simulate_many threads str", "pv.simulate_many([%s], threads='2')" % R, "refuse"),
        ("simulate_many generator", "pv.simulate_many(%s for _ in range(3))" % R, "either"),
        ("simulate_many not iterable", "pv.simulate_many(3)", "refuse"),
        ("Simulator step -1", "pv.Simulator(%s).step(-1)" % R, "refuse"),
        ("Simulator step 2**63", "s = pv.Simulator(%s)\ns.step(2 ** 63)\n"
         "return s.status" % R, "either"),
        ("Simulator step 2**64", "pv.Simulator(%s).step(2 ** 64)" % R, "refuse"),
        ("Simulator step float", "pv.Simulator(%s).step(1.5)" % R, "refuse"),
        ("Simulator step None", "pv.Simulator(%s).step(None)" % R, "refuse"),
        ("Simulator after the end", "s = pv.Simulator(%s)\ns.run()\ns.step(10)\ns.run()\n"
         "return (s.status, s.positions.shape)" % R, "either"),
        ("Simulator positions writable?", "s = pv.Simulator(%s)\np = s.positions\np[:] = 1e9\n"
         "s.step(5)\nrequire(abs(s.positions).max() < 1, 'writing a copy moved the body')" % R,
         "either"),
        ("Simulator physics bad", "pv.Simulator(%s, physics={'dt_frac': 0})" % R, "refuse"),
        ("read_results int", "pv.read_results(3)", "refuse"),
        ("read_results folder", "pv.read_results(BASE)", "refuse"),
        ("read_results robot file", "pv.read_results(BASE + '/robot.json')", "refuse"),
        ("read_results a life", "pv.read_results(BASE + '/life.h5')", "refuse"),
        ("champion generation -1 (the last)",
         "pv.read_results(BASE + '/run.h5').champion(generation=-1)", "valid"),
        ("champion generation -2", "pv.read_results(BASE + '/run.h5').champion(generation=-2)",
         "refuse"),
        ("champion generation 99", "pv.read_results(BASE + '/run.h5').champion(generation=99)",
         "refuse"),
        ("champion generation 2**70",
         "pv.read_results(BASE + '/run.h5').champion(generation=2 ** 70)", "refuse"),
        ("read_study missing", "pv.read_study(BASE + '/nope')", "refuse"),
        ("read_study a file", "pv.read_study(BASE + '/robot.json')", "refuse"),
        ("load_robot None", "pv.load_robot(None)", "refuse"),
        ("load_robot results file", "pv.load_robot(BASE + '/run.h5')", "refuse"),
        ("save to folder", "%s.save(BASE)" % R, "refuse"),
        ("save to .txt", "%s.save(BASE + '/../py/x.txt')" % R, "refuse"),
        ("save to missing folder", "%s.save('/nonexistent/x.json')" % R, "refuse"),
        ("with_physics bad", "%s.with_physics({'poisson': 0.5})" % R, "refuse"),
        ("with_physics treatment bad", "%s.with_physics({}, treatment=[1])" % R, "refuse"),
        ("physics unknown preset", "pv.physics('nope')", "refuse"),
        ("physics bad kw", "pv.physics(density=-1)", "refuse"),
        ("render size 0", "pv.render(%s, size=(0, 0))" % R, "refuse"),
        ("render size huge", "pv.render(%s, size=(100000, 100000))" % R, "refuse"),
        ("render size negative", "pv.render(%s, size=(-5, 10))" % R, "refuse"),
        ("render size 3-tuple", "pv.render(%s, size=(5, 10, 3))" % R, "refuse"),
        ("render time nan", "pv.render(%s, size=(64, 48), time=float('nan'))" % R, "refuse"),
        ("render time -1", "pv.render(%s, size=(64, 48), time=-1)" % R, "refuse"),
        ("render colour bogus", "pv.render(%s, size=(64, 48), color='plaid')" % R, "refuse"),
        ("render out to folder", "pv.render(%s, size=(64, 48), out=BASE)" % R, "refuse"),
        ("evolve config bad", "pv.evolve({'population': -1}, BASE + '/../py/e.h5')", "refuse"),
        ("evolve config not dict", "pv.evolve([1], BASE + '/../py/e.h5')", "refuse"),
        ("evolve callback raises",
         "c = pv.default_config()\nc.update(population=3, generations=2, lattice={'nx': 3, "
         "'ny': 3, 'nz': 3, 'voxel_size': 0.01}, physics={'preset': 'gecco2018-code', "
         "'duration': 0.3})\ndef cb(p):\n    raise ValueError('stop here')\n"
         "pv.evolve(c, BASE + '/../py/cb.h5', threads=1, on_generation=cb)", "refuse"),
        ("evolve callback not callable",
         "c = pv.default_config()\nc.update(population=3, generations=2, lattice={'nx': 3, "
         "'ny': 3, 'nz': 3, 'voxel_size': 0.01}, physics={'preset': 'gecco2018-code', "
         "'duration': 0.3})\npv.evolve(c, BASE + '/../py/nc.h5', threads=1, on_generation=5)",
         "refuse"),
    ]
    for label, body, expect in calls:
        h.py_case(cat, label, body, expect)
    # Threads: one Simulator from many threads (RuntimeError or a correct life, never a
    # crash); a Simulator each (must equal the sequential life); render from threads.
    for i in range(h.args.thread_cases):
        n = 2 + i % 6
        kind = ["shared Simulator", "own Simulators", "render", "simulate_many in threads",
                "read_results"][i % 5]
        if kind == "shared Simulator":
            body = THREAD_SHARED % (R, n)
        elif kind == "own Simulators":
            body = THREAD_OWN % (R, R, n)
        elif kind == "render":
            body = THREAD_RENDER % (R, R, n)
        elif kind == "simulate_many in threads":
            body = THREAD_MANY % (R, n)
        else:
            body = THREAD_READ % n
        h.py_case(cat, "threads x%d: %s" % (n, kind), body, "either")
    # Random physics dicts through Python.
    for i in range(60):
        field = h.rng.choice(sorted(PHYSICS_VALID))
        v = h.rng.choice([x for x in PHYS_VALUES if not (isinstance(x, str) and x in RAW)] +
                         [float("nan"), float("inf")])
        valid = PHYSICS_VALID[field](v) if not (isinstance(v, float) and v != v) else False
        slow = field in ("density", "dt_frac", "e_max", "e_min", "duration", "act_frequency",
                         "max_change_per_step", "record_fps") or (is_num(v) and abs(v) > 1e6)
        expect = "refuse" if not valid else ("either" if slow else "valid")
        body = ("r = pv.simulate(%s, physics={%r: %r})\nrequire(r.fitness == r.fitness, "
                "'NaN fitness')\nreturn r.status" % (R, field, v))
        h.py_case(cat, "physics %s=%r" % (field, v), body, expect)


THREAD_SHARED = '''
s = pv.Simulator(%s)
errors, other = [], []
def go():
    try:
        for _ in range(20):
            s.step(3)
    except RuntimeError as e:
        errors.append(str(e))
    except BaseException as e:
        other.append(repr(e))
ts = [threading.Thread(target=go) for _ in range(%d)]
[t.start() for t in ts]
[t.join() for t in ts]
require(not other, "unexpected: %%s" %% other[:1])
require(all("another thread" in e for e in errors), "unclear error: %%s" %% errors[:1])
return "%%d refused" %% len(errors)
'''

THREAD_OWN = '''
ref = pv.Simulator(%s)
ref.run()
out = []
def go():
    s = pv.Simulator(%s)
    s.run()
    out.append(s.state_hash)
ts = [threading.Thread(target=go) for _ in range(%d)]
[t.start() for t in ts]
[t.join() for t in ts]
require(out and all(x == ref.state_hash for x in out), "threads gave other lives")
'''

THREAD_RENDER = '''
ref = pv.render(%s, size=(64, 48), time=0.1)
out = []
def go():
    out.append(pv.render(%s, size=(64, 48), time=0.1))
ts = [threading.Thread(target=go) for _ in range(%d)]
[t.start() for t in ts]
[t.join() for t in ts]
require(len(out) == len(ts) and all((x == ref).all() for x in out), "frames differ")
'''

THREAD_MANY = '''
rob = %s
ref = pv.simulate(rob).final_state_hash
out = []
def go():
    out.extend(r.final_state_hash for r in pv.simulate_many([rob, rob], threads=2))
ts = [threading.Thread(target=go) for _ in range(%d)]
[t.start() for t in ts]
[t.join() for t in ts]
require(out and all(x == ref for x in out), "lives differ")
'''

THREAD_READ = '''
res = pv.read_results(BASE + '/run.h5')
out = []
def go():
    out.append(res.champion().voxel_count)
    out.append(pv.read_results(BASE + '/run.h5').champion() == res.champion())
ts = [threading.Thread(target=go) for _ in range(%d)]
[t.start() for t in ts]
[t.join() for t in ts]
require(len(set(map(str, out))) <= 2, "threads disagree: %%s" %% out)
'''


# ---- main -------------------------------------------------------------------------------

def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--plastivox", required=True, help="the installed plastivox program")
    ap.add_argument("--pythonpath", required=True, help="folder holding the plastivox module")
    ap.add_argument("--work", default="/tmp/plastivox-hostile", help="scratch folder (wiped)")
    ap.add_argument("--out", default="hostile-results", help="folder for the tables and JSONL")
    ap.add_argument("--seed", type=int, default=40)
    ap.add_argument("--timeout", type=float, default=20.0, help="seconds before a case hangs")
    ap.add_argument("--kills", type=int, default=90, help="interrupted evolutions")
    ap.add_argument("--disk", type=int, default=44, help="full-disk cases")
    ap.add_argument("--thread-cases", type=int, default=40)
    ap.add_argument("--only", default=",".join(CATEGORIES), help="categories to run")
    args = ap.parse_args()
    if os.getuid() != 0 and ("disk" in args.only):
        sys.exit("hostile: the disk cases mount tmpfs and need root (or --only without disk)")
    h = Harness(args)
    h.setup()
    gens = {"robot-json": gen_robot_json, "vxa": gen_vxa, "config-cli": gen_config_cli,
            "damaged-files": gen_damaged, "interruption": gen_interruption, "disk": gen_disk,
            "physics": gen_physics, "python": gen_python}
    try:
        for c in args.only.split(","):
            t = time.time()
            before = len(h.cases)
            gens[c](h)
            print("hostile: %s: %d cases in %.0f s" % (c, len(h.cases) - before, time.time() - t),
                  flush=True)
    finally:
        for m in list(h.mounts):
            h.umount(m)
        h.report()


if __name__ == "__main__":
    main()
