"""The build step of `pip install .` (pyproject.toml holds the package's description): CMake
configures the project and builds only the two targets the package needs, in Release, then
they are placed in the package beside its Python files:

    plastivox/__init__.py, __main__.py,     python/plastivox
    _env.py, analysis.py
    plastivox/_core.<abi>.so                the compiled module (target plastivox_python)
    plastivox/bin/plastivox                 the program (target plastivox), run by the
                                            `plastivox` command and `python3 -m plastivox`
    plastivox/share/plastivox/assets/       assets/ (shaders, viewer scripts, presets)

The program and the module look for share/plastivox/assets above themselves
(render/include/plastivox/render/assets.hpp), so the installed package works wherever it is.
setuptools' folders are build-pip/ (the CMake build in build-pip/temp.*/cmake, kept, so a
second install only rebuilds what changed). CMAKE_BUILD_PARALLEL_LEVEL sets the number of
compile jobs (default: every core); PLASTIVOX_CMAKE_ARGS adds arguments to CMake's configure.
"""
import importlib.util
import os
import re
import shlex
import shutil
import subprocess
import sys
from pathlib import Path


def check_build_tools():
    """pip install --no-build-isolation builds with this interpreter's own setuptools and wheel
    (pyproject.toml). Without them pip says only "invalid command 'bdist_wheel'" or
    "No module named 'setuptools'"; this says in one line what to install instead."""
    missing = [m for m in ("setuptools", "wheel") if importlib.util.find_spec(m) is None]
    if missing:
        sys.exit(f"setup.py: {sys.executable} lacks {' and '.join(missing)}: build with Debian's "
                 "python3 (/usr/bin/python3 -m venv --system-site-packages ~/pv after apt-get "
                 f"install python3-setuptools python3-wheel), or pip install {' '.join(missing)} "
                 "into this one")


check_build_tools()

from setuptools import Extension, setup  # noqa: E402 (after the check that it is there)
from setuptools.command.build_ext import build_ext

ROOT = Path(__file__).resolve().parent


def project_version():
    """The version in CMakeLists.txt's project(), the one the program and module report."""
    found = re.search(r"project\(plastivox VERSION ([0-9.]+)", (ROOT / "CMakeLists.txt").read_text())
    if not found:
        sys.exit("setup.py: CMakeLists.txt: no `project(plastivox VERSION x.y.z)` line")
    return found.group(1)


class CMakeBuild(build_ext):
    """Builds the extension plastivox._core, and with it the program, through CMake."""

    def build_extension(self, ext):
        cmake_dir = Path(self.build_temp, "cmake").resolve()
        jobs = os.environ.get("CMAKE_BUILD_PARALLEL_LEVEL") or str(os.cpu_count() or 1)
        subprocess.run(["cmake", "-S", str(ROOT), "-B", str(cmake_dir), "-DCMAKE_BUILD_TYPE=Release",
                        "-DPLASTIVOX_TESTS=OFF", "-DPLASTIVOX_BENCH=OFF",
                        f"-DPython_EXECUTABLE={sys.executable}",
                        *shlex.split(os.environ.get("PLASTIVOX_CMAKE_ARGS", ""))], check=True)
        subprocess.run(["cmake", "--build", str(cmake_dir), "-j", jobs,
                        "--target", "plastivox", "plastivox_python"], check=True)

        module = Path(self.get_ext_fullpath(ext.name))  # plastivox/_core.<abi>.so
        built = cmake_dir / "python" / "plastivox" / module.name
        if not built.is_file():
            sys.exit(f"setup.py: CMake built no {built} (is {sys.executable} the Python "
                     "whose headers CMake found?)")
        package = module.parent
        package.mkdir(parents=True, exist_ok=True)
        shutil.copy2(built, module)
        (package / "bin").mkdir(exist_ok=True)
        shutil.copy2(cmake_dir / "apps" / "plastivox", package / "bin" / "plastivox")
        assets = package / "share" / "plastivox" / "assets"
        shutil.rmtree(assets, ignore_errors=True)
        shutil.copytree(ROOT / "assets", assets)


setup(
    version=project_version(),
    ext_modules=[Extension("plastivox._core", sources=[])],
    cmdclass={"build_ext": CMakeBuild},
    options={"build": {"build_base": "build-pip"}},
)
