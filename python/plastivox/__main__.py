"""`python3 -m plastivox ARGS`, and the `plastivox` command a pip install makes: both run the
plastivox program that the package carries (plastivox/bin/plastivox), with ARGS."""

import os
import sys


def main():
    program = os.path.join(os.path.dirname(os.path.abspath(__file__)), "bin", "plastivox")
    if not os.access(program, os.X_OK):
        sys.exit(f"plastivox: {program}: no program in this package (a build tree's module "
                 "has none: run the build's apps/plastivox instead)")
    os.execv(program, ["plastivox", *sys.argv[1:]])


if __name__ == "__main__":
    main()
