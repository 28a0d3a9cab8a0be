"""CPU time of one physics validation (target: at most 1 s), median of several runs.

Usage::

    python benchmarks/bench_validate.py [--repeats 5] [--quick]

Times `synergrasp.validate` (model building, squeeze, settling and the six
pushes) with the default protocol on grasps built by construction (a box and
a ball pinched between the thumb and index tips, each also 40 mm back) and,
unless ``--quick``, on the paper's eight planned grasps (planned first, not
timed), each also with the overlap check off so that it is simulated. CPU time (``time.process_time``) of the validating process; prints
each case's median and the median and largest over all cases. A held grasp
costs most: its pushes run until the object is at rest.
"""

from __future__ import annotations

import argparse
import math
import time
import warnings

import numpy as np

import synergrasp as sg
from synergrasp.cli import positive
from synergrasp.physics import ball_pinch, hand_without, pinch_grasp

TARGET = 1.0  # s of CPU per validation


def cases(quick):
    """(name, configuration or result, object, hand, settings) of every timed validation."""
    hand = sg.SynergyHand.default()
    u, box = pinch_grasp(hand)
    v, ball = ball_pinch(hand)
    two = hand_without(hand, "M", "R", "L")
    out = [("box pinch", u, box, hand, {}), ("box pinch, 40 mm back", u, box, hand, {"retreat": 40.0}),
           ("ball pinch (thumb and index)", v, ball, two, {})]
    if not quick:
        for grasp in ("precision", "power"):
            for name in ("ellipsoid", "cup", "bell", "goblet"):
                obj = sg.objects.get(name)
                result = sg.plan(obj, grasp)
                out.append((f"{name} {grasp}", result, obj, hand, {}))
                # a grasp refused for its overlap costs little: simulate it all the same
                out.append((f"{name} {grasp}, overlap ignored", result, obj, hand, {"max_penetration": math.inf}))
    return out


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--repeats", type=positive(int), default=5, help="validations per case (default 5)")
    parser.add_argument("--quick", action="store_true", help="the constructed grasps only, 2 repeats")
    args = parser.parse_args(argv)
    warnings.simplefilter("ignore")
    repeats = 2 if args.quick else args.repeats
    medians = []
    print(f"{'case':44s} {'outcome':12s} {'median CPU s':>12s}")
    for name, grasp, obj, hand, settings in cases(args.quick):
        times = []
        for _ in range(repeats):
            start = time.process_time()
            check = sg.validate(grasp, obj, hand=hand, **settings)
            times.append(time.process_time() - start)
        medians.append(float(np.median(times)))
        print(f"{name:44s} {check.outcome:12s} {medians[-1]:12.3f}", flush=True)
    worst = max(medians)
    print(f"one validation: median {np.median(medians):.3f} s CPU over {len(medians)} cases, largest {worst:.3f} s "
          f"({'within' if worst <= TARGET else 'ABOVE'} the {TARGET:g} s target)")


if __name__ == "__main__":
    main()
