"""How closely a plan keeps its ``time_limit`` (target: within 10 %).

Usage::

    python benchmarks/bench_time_limit.py [--repeats 3] [--quick]

Plans the paper's objects with both grasp types under time limits of 0.2, 0.5, 1 and 2 s, with
an acceptance no grasp can meet (``q_accept = -10``), so that every plan runs until its limit.
Prints, per limit, the median and the largest wall-clock time of a plan (``time.perf_counter``
around ``sg.plan``, the clock the limit is kept by) over the limit, and the largest overrun over
all plans against the target. ``--quick``: the ellipsoid's precision grasp at 0.2 s, once.
"""

from __future__ import annotations

import argparse
import time
import warnings

import numpy as np

import synergrasp as sg
from synergrasp.cli import positive

TARGET = 0.10  # largest overrun, as a fraction of the limit
LIMITS = (0.2, 0.5, 1.0, 2.0)
OBJECTS = ("ellipsoid", "cup", "bell", "goblet")
GRASPS = ("precision", "power")


def overrun(obj, grasp, limit):
    """Wall time of a plan that cannot succeed, over its time limit."""
    start = time.perf_counter()
    result = sg.plan(obj, grasp, time_limit=limit, q_accept=-10.0, q_margin=-10.0, max_iter=10**7)
    elapsed = time.perf_counter() - start
    if result.success:
        raise RuntimeError(f"{grasp} plan of {obj.name} succeeded: it cannot measure its time limit")
    return elapsed / limit


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--repeats", type=positive(int), default=3,
                        help="plans per object, grasp type and time limit (default 3)")
    parser.add_argument("--quick", action="store_true", help="one plan (the tests run it)")
    args = parser.parse_args(argv)
    warnings.simplefilter("ignore")
    objects = {name: sg.objects.get(name) for name in (OBJECTS[:1] if args.quick else OBJECTS)}
    grasps, limits, repeats = (GRASPS[:1], LIMITS[:1], 1) if args.quick else (GRASPS, LIMITS, args.repeats)
    for obj in objects.values():  # warm-up: first calls and caches are not what a limit is about
        sg.plan(obj, "precision", max_iter=3, restarts=1)
    worst = 0.0
    for limit in limits:
        ratios = np.array([overrun(obj, grasp, limit) for _ in range(repeats) for obj in objects.values()
                           for grasp in grasps])
        worst = max(worst, float(ratios.max()))
        print(f"time_limit {limit:.1f} s: {len(ratios)} plans, time / limit median {np.median(ratios):.3f}, "
              f"max {ratios.max():.3f}", flush=True)
    print(f"largest overrun {100 * (worst - 1):+.1f} % of the limit (target <= {100 * TARGET:.0f} %): "
          f"{'met' if worst <= 1 + TARGET else 'NOT met'}")
    return worst


if __name__ == "__main__":
    main()
