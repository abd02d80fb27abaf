"""One plastivox.gradient_of as a whole process (docs/gradients.md, "Losses over the states of
a life"); not a test.

    build/python/python3 bench/grad_of_bench.py ROBOT [--duration S] [--simulate-first]

The loss is the mean x of the voxels in the life's last state (steps=[-1], counted from the
end), its derivative taken with respect to the phases. --simulate-first simulates the same
life once before (plastivox.simulate), as gradient_of itself did to count the steps from the
end until it kept the last states from its own forward pass: paired against the plain run,
the ratio is what that life cost. Prints the loss and the sum of |d loss / d phase|.
"""

import argparse

import numpy as np

import plastivox


def mean_final_x(states):
    pos = states["pos"]
    d = np.zeros_like(pos)
    d[-1, :, 0] = 1 / pos.shape[1]
    return float(pos[-1, :, 0].mean()), {"pos": d}


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("robot")
    parser.add_argument("--duration", type=float, default=1.0)
    parser.add_argument("--simulate-first", action="store_true")
    args = parser.parse_args()
    robot = plastivox.load_robot(args.robot)
    physics = {"duration": args.duration}
    if args.simulate_first:
        plastivox.simulate(robot, physics=physics)
    value, g = plastivox.gradient_of(robot, mean_final_x, steps=[-1], wrt=["phase"],
                                     physics=physics)
    print(value, float(np.abs(g["phase"]).sum()))


if __name__ == "__main__":
    main()
