"""Load an evolution results file, plot its fitness curve (if matplotlib is installed) and
render the champion.

    PYTHONPATH=build/python python3 examples/python/results_report.py run.h5 [--out-dir DIR]
"""

import argparse
import os

import plastivox


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("results", help="an evolution results file (.h5)")
    ap.add_argument("--out-dir", default=".", help="where the figure and the frame go")
    ap.add_argument("--size", default="640x480", help="frame size, WxH")
    args = ap.parse_args()

    res = plastivox.read_results(args.results)
    print(res)
    print(f"best fitness {res.best_fitness[-1]:.4f} after {res.generations_done} generations "
          f"(written by plastivox {res.provenance['plastivox_version']} "
          f"on {res.provenance['host']})")
    os.makedirs(args.out_dir, exist_ok=True)
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("matplotlib is not installed: no fitness plot")
    else:
        fig, ax = plt.subplots(figsize=(6, 4))
        ax.plot(res.best_fitness, label="best")
        ax.plot(res.mean_fitness, label="mean of the survivors")
        ax.set_xlabel("generation")
        ax.set_ylabel("fitness (voxel lengths)")
        ax.set_title(f"{res.treatment}, seed {res.seed}")
        ax.legend()
        path = os.path.join(args.out_dir, "fitness.png")
        fig.savefig(path, dpi=100)
        print(f"wrote {path}")

    champion = res.champion()
    w, h = (int(v) for v in args.size.split("x"))
    frame = os.path.join(args.out_dir, "champion.png")
    time = min(champion.physics["duration"], champion.physics["settle_time"] + 0.5)
    plastivox.render(res, time=time, size=(w, h), out=frame)
    print(f"wrote {frame}: {champion} at t = {time:g} s")


if __name__ == "__main__":
    main()
