"""The README's Python lines with a python3 first on PATH that is not the one CMake built the
module for (issue 54: with pyenv or conda first, `PYTHONPATH=build/python python3` failed with
"No module named 'numpy'", and the pip line with "invalid command 'bdist_wheel'"). The foreign
python3 is a venv without pip and without the system's packages, so it has neither numpy nor
setuptools nor wheel."""

import os
import re
import subprocess
import sys

import pytest

from conftest import SOURCE

# ctest runs the suites with PYTHONPATH=<build>/python (python/CMakeLists.txt).
BUILD_PYTHON = os.path.abspath(os.environ.get("PYTHONPATH", "").split(os.pathsep)[0])


def readme_block_line(after, contains):
    """The line of the first ```sh block after `after` in README.md that contains `contains`."""
    text = open(os.path.join(SOURCE, "README.md"), encoding="utf-8").read()
    at = text.index(after)
    start = text.index("```sh\n", at) + len("```sh\n")
    block = text[start:text.index("```", start)]
    lines = [line for line in block.splitlines() if contains in line]
    assert len(lines) == 1, (after, contains, block)
    return lines[0]


@pytest.fixture(scope="module")
def foreign_path(tmp_path_factory):
    """A PATH whose first python3 is a bare venv's (no numpy, setuptools or wheel)."""
    venv = tmp_path_factory.mktemp("foreign") / "venv"
    subprocess.run([sys.executable, "-m", "venv", "--without-pip", str(venv)], check=True)
    python3 = venv / "bin" / "python3"
    env = {**os.environ, "PATH": f"{venv / 'bin'}{os.pathsep}{os.environ['PATH']}"}
    env.pop("PYTHONPATH", None)  # as a user's shell has it
    found = subprocess.run(["sh", "-c", "command -v python3"], env=env, capture_output=True,
                           text=True).stdout.strip()
    assert found == str(python3)
    has = subprocess.run([str(python3), "-c", "import numpy"], capture_output=True)
    assert has.returncode != 0, "the venv must not see the system's numpy"
    return env


def test_the_readme_python_line_runs_with_a_foreign_python3_first_on_path(foreign_path,
                                                                          tmp_path):
    assert os.path.isfile(os.path.join(BUILD_PYTHON, "plastivox", "__init__.py")), BUILD_PYTHON
    line = readme_block_line("From Python", "import plastivox")
    # The build step is done (ctest runs after it); the rest runs as written, from a folder
    # whose build/ is this build tree.
    command = line.split(" && ", 1)[1]
    assert command.startswith("build/python/python3 "), command
    top = tmp_path / "clone"
    top.mkdir()
    os.symlink(os.path.dirname(BUILD_PYTHON), top / "build")
    p = subprocess.run(["sh", "-c", command], cwd=top, env=foreign_path, capture_output=True,
                       text=True)
    assert p.returncode == 0, p.stdout + p.stderr
    assert float(p.stdout.strip()) > 0
    # What the README said before: the foreign python3 finds the module but no numpy, and says
    # so in one line that names the way out.
    old = 'PYTHONPATH=build/python python3 -c "import plastivox"'
    p = subprocess.run(["sh", "-c", old], cwd=top, env=foreign_path, capture_output=True,
                       text=True)
    assert p.returncode != 0
    last = p.stderr.strip().splitlines()[-1]
    assert re.search(r"plastivox needs numpy, which \S+ lacks: run the python3 the module was "
                     r"built for \(build/python/python3", last), p.stderr


def test_the_readme_pip_line_names_debians_python3_and_setup_names_what_is_missing(
        foreign_path, tmp_path):
    line = readme_block_line("Or install it with pip", "pip install")
    assert line.startswith("/usr/bin/python3 -m venv --system-site-packages "), line
    # The build step of the pip line under the foreign python3 (what pip runs): one line naming
    # what is missing and what to install, before anything is built.
    p = subprocess.run(["python3", os.path.join(SOURCE, "setup.py"), "bdist_wheel"],
                       cwd=tmp_path, env=foreign_path, capture_output=True, text=True)
    assert p.returncode == 1
    lines = p.stderr.strip().splitlines()
    assert len(lines) == 1, p.stderr
    assert re.fullmatch(r"setup\.py: \S+/python3 lacks setuptools and wheel: build with Debian's "
                        r"python3 \(/usr/bin/python3 -m venv --system-site-packages ~/pv after "
                        r"apt-get install python3-setuptools python3-wheel\), or pip install "
                        r"setuptools wheel into this one", lines[0]), lines[0]
    assert os.listdir(tmp_path) == []  # nothing built
