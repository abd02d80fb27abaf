"""docs/python.md's `python` blocks run as written, in order, as one session started at the top
of the repository, each in seconds (issue 54: its evolution example wrote into the run.h5 of
the line before and was refused, and its custom-fitness example ran at paper scale for minutes
with no output)."""

import os
import re
import time

import pytest

from conftest import SOURCE, run_cli

DOC = os.path.join(SOURCE, "docs", "python.md")
SECONDS_PER_BLOCK = 30  # "in seconds": the slowest block took ~5 s on the 2-core test machine


def python_blocks():
    """(heading, code) of every ```python block, in order."""
    text = open(DOC, encoding="utf-8").read()
    blocks, heading = [], ""
    for m in re.finditer(r"^(#+ [^\n]*)$|^```python\n(.*?)^```$", text, re.M | re.S):
        if m.group(1):
            heading = m.group(1)
        else:
            blocks.append((heading, m.group(2)))
    return blocks


def needs_dask(code):
    return "dask" in code


def test_every_python_block_of_docs_python_md_runs_as_written_in_order(tmp_path, monkeypatch):
    blocks = python_blocks()
    assert len(blocks) >= 13, [h for h, _ in blocks]
    # The top of the repository, as the doc says (tests/data/... is read by the first block),
    # with nothing written into the sources: a scratch folder that links to what is read.
    for name in ("tests", "examples"):
        os.symlink(os.path.join(SOURCE, name), tmp_path / name)
    monkeypatch.chdir(tmp_path)
    try:
        import dask.distributed  # noqa: F401 (Debian python3-distributed; CI has it)
        have_dask = True
    except ImportError:
        have_dask = False
    session = {}
    took = []
    for heading, code in blocks:
        if needs_dask(code) and not have_dask:
            continue  # test_dask.py is off too without it (python/CMakeLists.txt)
        if heading.startswith("## Results and studies") and "read_study" in code:
            # What the section says makes `study` from the run above.
            run_cli("analyze", "run.h5", "--out", "study", "--robustness-draws", "1",
                    "--threads", "2")
        start = time.monotonic()
        try:
            exec(compile(code, f"{DOC} ({heading})", "exec"), session)
        except Exception as e:  # name the block, not only the line
            pytest.fail(f"{heading}: {type(e).__name__}: {e}\n{code}")
        took.append((time.monotonic() - start, heading))
    for seconds, heading in took:
        assert seconds < SECONDS_PER_BLOCK, (heading, seconds)
    # What the blocks say they give.
    assert session["report"]["outcome"] == "finished"
    assert session["res"].generations_done == 3 and session["res"].finished
    assert session["study"].stats["format"] == "plastivox-analysis"
    assert os.path.getsize("frame.png") > 0 and session["img"].shape == (480, 640, 3)
    assert session["ev"].finished
    print("seconds per block:", ", ".join(f"{s:.1f} ({h})" for s, h in took))
