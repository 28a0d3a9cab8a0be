"""Median wall-clock time of whole plans (the default native LP backend, or --backend), per paper case, in one run.

Usage::

    python benchmarks/bench_plan.py [--repeats 5] [--grasp precision|power|both]

Prints, for each of the paper's objects, the median plan time, the time per
iteration and the LP solves of the returned plan, and whether it succeeded;
then, for each grasp type, the median over all its plans (the four objects,
every repeat) and the slowest object's median.
"""

from __future__ import annotations

import argparse
import time
import warnings

import numpy as np

import synergrasp as sg
from synergrasp.cli import backend, positive


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--repeats", type=positive(int), default=5,
                        help="plans per object and grasp type; the median time is reported (default 5)")
    parser.add_argument("--grasp", choices=["precision", "power", "both"], default="both",
                        help="grasp type(s) to plan (default both)")
    parser.add_argument("--backend", type=backend, default="native", help="LP backend (default native)")
    args = parser.parse_args(argv)
    warnings.simplefilter("ignore")
    grasps = ["precision", "power"] if args.grasp == "both" else [args.grasp]
    print(f"{'object':10s} {'grasp':10s} {'success':8s} {'median s':>9s} {'ms/iter':>8s} {'iters':>6s} {'attempts':>8s} {'LPs':>6s}")
    summary = []
    for grasp in grasps:
        every, slowest = [], (0.0, "")
        for name in ("ellipsoid", "cup", "bell", "goblet"):
            obj = sg.objects.get(name)
            times = []
            for _ in range(args.repeats):
                start = time.perf_counter()
                result = sg.plan(obj, grasp, backend=args.backend)
                times.append(time.perf_counter() - start)
            median = float(np.median(times))
            print(f"{name:10s} {grasp:10s} {str(result.success):8s} {median:9.3f} "
                  f"{1e3 * median / max(result.total_iterations, 1):8.2f} {result.iterations:6d} "
                  f"{len(result.attempts):8d} {result.lp_solves:6d}", flush=True)
            every += times
            slowest = max(slowest, (median, name))
        summary.append(f"{grasp}: median plan time {np.median(every):.3f} s over {len(every)} plans "
                       f"(4 objects x {args.repeats}); slowest object {slowest[1]}, median {slowest[0]:.3f} s")
    print("\n".join(summary))


if __name__ == "__main__":
    main()
