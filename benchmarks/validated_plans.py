"""Plans that keep searching until a grasp holds in MuJoCo: ``sg.plan(..., validate=True)`` on the paper's cases.

Usage::

    python benchmarks/validated_plans.py [--time-limit 30] [--quick]
    python benchmarks/validated_plans.py --split test [--grasp power precision] [--time-limit 10] [--jobs 2]

Plans the paper's 8 cases (ellipsoid, cup, bell, goblet x precision, power) with ``validate=True``
(the default protocol, ``synergrasp.validate``): each accepted grasp is tested in simulation and
the plan goes on through further attempts until one holds, within the time limit. Prints, per
case, whether a grasp was accepted, whether it holds, the attempts and the plan's wall time, then
the count of cases that hold. ``--quick``: the ellipsoid's power grasp only (the tests run it).

``--split train|test`` plans the objects of that split of the generalisation benchmark
(``objectset.py``) instead, in ``--jobs`` worker processes, each plan within ``--time-limit``
seconds (the planner's default of 10 s is a fair budget there), and prints the same per grasp type
with the median attempts and time: what ``validate=True`` adds to the first accepted grasp's
physical success rate (``physics_study.py``).
"""

from __future__ import annotations

import argparse
import sys
import time
import warnings
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

import synergrasp as sg  # noqa: E402
from synergrasp.cli import positive  # noqa: E402
from synergrasp.planner import ObjectRefused  # noqa: E402
from objectset import SPLITS, select  # noqa: E402

CASES = tuple((o, g) for g in ("precision", "power") for o in ("ellipsoid", "cup", "bell", "goblet"))


def plan_case(name, grasp, time_limit, split=None):
    """One plan with ``validate=True``: its row (dict)."""
    warnings.simplefilter("ignore")
    obj = name if split is None else next(e for e in select(split, only=[name]) if e.name == name).make()
    start = time.perf_counter()
    try:
        result = sg.plan(obj, grasp, validate=True, time_limit=time_limit)
    except ObjectRefused as exc:  # an object the hand cannot hold
        return dict(object=name, grasp=grasp, success=False, held=False, attempts=0,
                    time=time.perf_counter() - start, note=str(exc))
    return dict(object=name, grasp=grasp, success=result.success, held=bool(result.held),
                attempts=len(result.attempts), time=time.perf_counter() - start)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--time-limit", type=positive(float), default=None,
                        help="seconds per plan (default 30 on the paper's cases, 10 on a split)")
    parser.add_argument("--quick", action="store_true", help="the ellipsoid's power grasp only")
    parser.add_argument("--split", choices=SPLITS, help="the benchmark's split instead")
    parser.add_argument("--grasp", nargs="+", choices=["precision", "power"], default=["precision", "power"],
                        help="grasp types to plan (the paper's cases or the split's)")
    parser.add_argument("--jobs", type=positive(int), default=1, help="worker processes (with --split)")
    args = parser.parse_args(argv)
    warnings.simplefilter("ignore")
    limit = args.time_limit if args.time_limit is not None else (10.0 if args.split else 30.0)
    if args.split:
        tasks = [(e.name, g, limit, args.split) for g in args.grasp for e in select(args.split)]
    else:
        tasks = [(o, g, limit) for o, g in ((("ellipsoid", "power"),) if args.quick else CASES) if g in args.grasp]
    rows = []
    with ProcessPoolExecutor(args.jobs) as pool:
        for r in pool.map(plan_case, *zip(*tasks)):
            rows.append(r)
            print(f"{r['object']:28s} {r['grasp']:9s} accepted {'yes' if r['success'] else 'no':3s} "
                  f"holds {'yes' if r['held'] else 'no':3s} {r['attempts']:3d} attempts {r['time']:6.1f} s", flush=True)
    for grasp in args.grasp:
        mine = [r for r in rows if r["grasp"] == grasp]
        if mine:
            print(f"{grasp}: {sum(r['held'] for r in mine)}/{len(mine)} hold in simulation "
                  f"({sum(r['success'] for r in mine)} with an accepted grasp); attempts median "
                  f"{np.median([r['attempts'] for r in mine]):g}, time median {np.median([r['time'] for r in mine]):.2f} s, "
                  f"p90 {np.percentile([r['time'] for r in mine], 90):.2f} s")
    return rows


if __name__ == "__main__":
    main()
