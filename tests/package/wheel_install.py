"""Builds the wheel the way a user does, offline, and uses it from an unrelated folder.

    python3 wheel_install.py SOURCE_DIR WORK_DIR BUILD_TREE_PYTHON_DIR

SOURCE_DIR's files (as git lists them: tracked and not ignored) are copied to WORK_DIR/src,
so nothing of a build tree is near; there `pip wheel --no-index --no-build-isolation` builds
the wheel (a fresh CMake build of the two targets it needs, at -O1: see main), a fresh
virtual environment (--system-site-packages, for numpy) installs it, and from / the module
simulates the demo walker (the same fitness and state hash as the build tree's module),
renders a frame (its shaders found beside it), and `plastivox --help`, `python -m plastivox
--help` and `plastivox render` run. The same CMake build is also installed with `cmake --install` into a
prefix, whose program and module render too (assets in <prefix>/share/plastivox/assets).
The copied sources and their build are deleted before anything installed runs.
"""

import glob
import os
import shutil
import subprocess
import sys
import time


def run(cmd, cwd="/", env=None, quiet=False):
    """Runs cmd; on failure prints its output and stops the test. Returns stdout."""
    print("$", " ".join(cmd), flush=True)
    p = subprocess.run(cmd, cwd=cwd, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                       text=True)
    if p.returncode != 0 or not quiet:
        print(p.stdout, flush=True)
    if p.returncode != 0:
        sys.exit(f"FAILED (exit {p.returncode}): {' '.join(cmd)}")
    return p.stdout


def check(ok, message):
    if not ok:
        sys.exit("FAILED: " + message)


def copy_sources(source, dest):
    listed = subprocess.run(["git", "ls-files", "-z", "--cached", "--others", "--exclude-standard"],
                            cwd=source, stdout=subprocess.PIPE, check=True).stdout
    copied = 0
    for rel in filter(None, listed.decode().split("\0")):
        src = os.path.join(source, rel)
        if os.path.isfile(src):  # a tracked file deleted in the work tree is left out
            os.makedirs(os.path.dirname(os.path.join(dest, rel)), exist_ok=True)
            shutil.copy2(src, os.path.join(dest, rel))
            copied += 1
    check(copied > 0, f"git lists no files in {source}")


# The line the README gives: what the installed module computes from any folder.
EXAMPLE = ("import plastivox; r = plastivox.simulate(plastivox.demo_walker()); "
           "print(plastivox.__file__); print(r.fitness, r.final_state_hash)")
RENDER = ("import plastivox; a = plastivox.render(plastivox.demo_walker(), size=(64, 48)); "
          "print(a.shape, int(a.max()))")


def main():
    source, work, build_python = (os.path.abspath(a) for a in sys.argv[1:4])
    shutil.rmtree(work, ignore_errors=True)
    src = os.path.join(work, "src")
    copy_sources(source, src)

    venv = os.path.join(work, "venv")
    run([sys.executable, "-m", "venv", "--system-site-packages", venv])
    py = os.path.join(venv, "bin", "python")

    # No index at all: the build and the install must need nothing from the network. Built at
    # -O1 without link-time optimisation (PLASTIVOX_CMAKE_ARGS, setup.py's way to pass CMake
    # options, which a user may set too): what is tested is the packaging, and the suite's
    # longest test took 400 to 500 s compiling at -O3 with LTO. The module's results must still
    # be the -O3 build tree's to the bit (checked below), as the determinism rules say.
    wheels = os.path.join(work, "wheels")
    start = time.monotonic()
    run([py, "-m", "pip", "wheel", "--no-index", "--no-build-isolation", "--no-deps",
         "-w", wheels, src], quiet=True,
        env={**os.environ, "PLASTIVOX_CMAKE_ARGS": "-DCMAKE_CXX_FLAGS_RELEASE='-O1 -DNDEBUG' "
             "-DCMAKE_INTERPROCEDURAL_OPTIMIZATION=OFF"})
    print(f"wheel built in {time.monotonic() - start:.0f} s", flush=True)
    built = glob.glob(os.path.join(wheels, "plastivox-*.whl"))
    check(len(built) == 1, f"expected one plastivox wheel in {wheels}, found {built}")
    run([py, "-m", "pip", "install", "--no-index", built[0]])

    # cmake --install of the same CMake build, into a prefix.
    cmake_dirs = glob.glob(os.path.join(src, "build-pip", "temp.*", "cmake"))
    check(len(cmake_dirs) == 1, f"expected one CMake build in {src}/build-pip, found {cmake_dirs}")
    prefix = os.path.join(work, "prefix")
    run(["cmake", "--install", cmake_dirs[0], "--prefix", prefix], quiet=True)
    check(os.path.isfile(os.path.join(prefix, "share", "plastivox", "assets", "viewer", "viewer.js")),
          "cmake --install left out the assets")
    shutil.rmtree(src)  # what is installed must need neither the sources nor their build

    # From /, with no build tree or source on the path.
    env = {k: v for k, v in os.environ.items()
           if k not in ("PYTHONPATH", "PLASTIVOX_ASSETS", "PLASTIVOX_CLI")}
    installed = run([py, "-c", EXAMPLE], env=env).split("\n")
    check(installed[0].startswith(venv + "/"), f"plastivox imported from {installed[0]}, not the venv")
    reference = run([sys.executable, "-c", EXAMPLE], env={**env, "PYTHONPATH": build_python})
    check(installed[1] == reference.split("\n")[1],
          f"the wheel's module gives {installed[1]!r}, the build tree's {reference.split()[1:]!r}")
    check(run([py, "-c", RENDER], env=env).startswith("(48, 64, 3)"), "render from the wheel")

    program = os.path.join(venv, "bin", "plastivox")
    usage = run([program, "--help"], env=env, quiet=True)
    check("usage" in usage and "simulate" in usage, "plastivox --help prints no usage")
    check(run([py, "-m", "plastivox", "--help"], env=env, quiet=True) == usage,
          "python -m plastivox --help differs from plastivox --help")
    walker = os.path.join(source, "examples", "walker.json")
    png = os.path.join(work, "frame.png")
    run([program, "render", walker, "--out", png, "--size", "64x48"], env=env)
    check(os.path.getsize(png) > 0, f"{png} is empty")

    # Nothing in the package points back at the sources' assets/.
    package = os.path.dirname(installed[0])
    for path in [os.path.join(package, "bin", "plastivox"), *glob.glob(package + "/_core*.so")]:
        with open(path, "rb") as f:
            check((src + "/assets").encode() not in f.read(), f"{path} names {src}/assets")

    # The prefix's program and module find <prefix>/share/plastivox/assets.
    os.remove(png)
    run([os.path.join(prefix, "bin", "plastivox"), "render", walker, "--out", png, "--size", "64x48"],
        env=env)
    check(os.path.getsize(png) > 0, f"{png} is empty")
    prefix_python = os.path.join(prefix, "lib", "python3", "dist-packages")
    check(run([sys.executable, "-c", RENDER], env={**env, "PYTHONPATH": prefix_python})
          .startswith("(48, 64, 3)"), "render from the cmake --install module")
    print("OK")


if __name__ == "__main__":
    main()
