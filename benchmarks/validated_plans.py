"""Plans that keep searching until a grasp holds in MuJoCo: ``sg.plan(..., validate=True)`` on the paper's cases.

Usage::

    python benchmarks/validated_plans.py [--time-limit 30] [--quick]

Plans the paper's 8 cases (ellipsoid, cup, bell, goblet x precision, power) with ``validate=True``
(the default protocol, ``synergrasp.validate``): each accepted grasp is tested in simulation and
the plan goes on through further attempts until one holds, within the time limit. Prints, per
case, whether a grasp was accepted, whether it holds, the attempts and the plan's wall time, then
the count of cases that hold. ``--quick``: the ellipsoid's power grasp only (the tests run it).
"""

from __future__ import annotations

import argparse
import time
import warnings

import synergrasp as sg

CASES = tuple((o, g) for g in ("precision", "power") for o in ("ellipsoid", "cup", "bell", "goblet"))


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--time-limit", type=float, default=30.0, help="seconds per plan (default 30)")
    parser.add_argument("--quick", action="store_true", help="the ellipsoid's power grasp only")
    args = parser.parse_args(argv)
    warnings.simplefilter("ignore")
    rows = []
    for name, grasp in ((("ellipsoid", "power"),) if args.quick else CASES):
        start = time.perf_counter()
        result = sg.plan(name, grasp, validate=True, time_limit=args.time_limit)
        rows.append(dict(object=name, grasp=grasp, success=result.success, held=bool(result.held),
                         attempts=len(result.attempts), time=time.perf_counter() - start))
        r = rows[-1]
        print(f"{name:10s} {grasp:9s} accepted {'yes' if r['success'] else 'no':3s} holds {'yes' if r['held'] else 'no':3s} "
              f"{r['attempts']:3d} attempts {r['time']:6.1f} s", flush=True)
    for grasp in ("precision", "power"):
        mine = [r for r in rows if r["grasp"] == grasp]
        if mine:
            print(f"{grasp}: {sum(r['held'] for r in mine)}/{len(mine)} hold in simulation")
    return rows


if __name__ == "__main__":
    main()
