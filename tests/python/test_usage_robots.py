"""Every robot that a usage line simulates (README.md "Using it", examples/README.md "Try
them") stands and walks under the physics that line gives it: each `plastivox simulate` line
runs again as written, from the top of the repository, with its life recorded, and the
recording is checked (conftest.py, assert_stands_and_walks). Slow: the lives are full-length."""

import json
import os
import shlex
import subprocess

import h5py
import pytest

from conftest import CLI, SOURCE, assert_stands_and_walks, deepest_below_floor


def usage_lines(markdown, heading):
    """The command lines of the first ```sh block after `heading` (comments dropped), as
    tests/readme_usage_test.cpp reads them."""
    with open(os.path.join(SOURCE, markdown)) as f:
        text = f.read()
    block = text[text.index("```sh\n", text.index(heading)) + 6:]
    block = block[:block.index("```")]
    return [line.split(" #")[0].rstrip() for line in block.splitlines() if line.strip()]


def simulations():
    """(line, plastivox arguments without --json/--record/--fps): one per distinct life."""
    seen, out = set(), []
    for markdown, heading in (("README.md", "## Using it"), ("examples/README.md", "## Try them")):
        for line in usage_lines(markdown, heading):
            words = shlex.split(line)
            if words[1:] == ["demo"]:  # the built-in walker under three treatments
                runs = [["simulate", "--treatment", t] for t in ("none", "stress", "pressure")]
            elif words[1] == "simulate":
                runs, rest = [["simulate"]], words[2:]
                while rest:
                    word = rest.pop(0)
                    if word in ("--record", "--fps"):
                        rest.pop(0)
                    elif word != "--json":
                        runs[0].append(word)
            else:
                continue
            for args in runs:
                if tuple(args) not in seen:
                    seen.add(tuple(args))
                    out.append((line, args))
    return out


@pytest.mark.parametrize(
    "line,args",
    [pytest.param(line, args, id=" ".join(args)) for line, args in simulations()])
def test_usage_line_robot_stands_and_walks(line, args, tmp_path):
    life = str(tmp_path / "life.h5")
    p = subprocess.run([CLI, *args, "--json", "--record", life, "--fps", "100"], cwd=SOURCE,
                       capture_output=True, text=True)
    assert p.returncode == 0, p.stderr
    with h5py.File(life, "r") as f:
        deepest = deepest_below_floor(f["position"][:], f["size"][:], f.attrs["voxel_size"])
    assert_stands_and_walks(line, json.loads(p.stdout), deepest)
