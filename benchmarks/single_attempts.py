"""Single attempts of the planner from many starts: how often one attempt alone succeeds.

Usage::

    python benchmarks/single_attempts.py [--grasp precision|power] [--option NAME=VALUE ...]
                                         [--only NAME ...] [--standoffs 0 20] [--out FILE] [--jobs N]

A plan's success over the household set (benchmarks/household.py) depends on
the order in which its attempts are tried as much as on one attempt: this
script measures the attempt itself. From each of the 26 directions of a cube's
faces, edges and corners (`start_configuration`), each object of the
household set and the paper's four gets one attempt of at most
``iterations_per_attempt`` iterations per stand-off (precision) or pre-shape
(power: wide and palm-centred, or cupped), with the planner options given
(precision attempts use ``contact_target``, or with ``band_after=0`` the
``contact_band`` of a plan's second pass); an
attempt counts when the paper's criterion is met, the final contact wrenches
contain the origin strictly in their convex hull and no phalanx is deeper than
3 mm. Prints the count per object and in all, and with ``--out`` pickles every
attempt (start, outcome, iterations, status history) for offline study of
schedules.
"""

from __future__ import annotations

import argparse
import ast
import itertools
import pickle
import time
import warnings
from concurrent.futures import ProcessPoolExecutor
from functools import lru_cache
from types import SimpleNamespace

import numpy as np

import synergrasp as sg
from synergrasp.planner.core import PlannerOptions, _attempt, _power_start, _preshape, start_configuration

from household import MESHES, household_objects, mesh_files, verified

#: Directions of a cube's faces, edges and corners (object centre to hand).
DIRECTIONS = [d for d in itertools.product((-1.0, 0.0, 1.0), repeat=3) if any(d)]


@lru_cache(maxsize=1)
def objects():
    """The paper's four objects and the household set: name -> GraspObject (loaded once per process)."""
    objs = {f"paper/{name}": make() for name, make in sg.objects.BUILTINS.items()}
    objs.update({f"mesh/{name}": obj for name, obj in mesh_files(MESHES, 1.0).items()})
    objs.update({f"shape/{name}": obj for name, obj in household_objects().items()})
    return objs


def starts(hand, obj, grasp, opts, standoffs):
    """Every start of one object: (direction, variant, u0, stand-off)."""
    for d in DIRECTIONS:
        if grasp == "precision":
            u = start_configuration(hand, obj, d, opts.start_distance, opts.start_clearance)
            for standoff in standoffs:
                yield d, f"standoff {standoff:g}", u, standoff
        else:
            for name, preshape, wide in (("wide", opts.power_wide_preshape, True), ("cupped", opts.power_preshape, False)):
                yield d, name, _power_start(hand, obj, d, opts, _preshape(preshape, name, hand), wide), 0.0


def run_object(name, grasp, options, standoffs):
    """All single attempts on one object: a list of dicts."""
    warnings.simplefilter("ignore")
    obj = objects()[name]
    hand, opts = sg.SynergyHand.default(), PlannerOptions(**options)
    # the contact band of a plan's second pass is measured with band_after=0, as plan() takes it
    band = opts.contact_band if grasp == "precision" and opts.band_after == 0 else None
    rows = []
    for d, variant, u, standoff in starts(hand, obj, grasp, opts, standoffs):
        reason, traj, statuses, checks, final, depth, _ = _attempt(
            hand, obj, grasp, u, opts, "highs", opts.iterations_per_attempt, None, standoff, band
        )
        contact = checks[-1].contact
        result = SimpleNamespace(success=reason == "stop criterion met", penetration=depth,
                                 contact_points=final.nearest[contact], contact_normals=final.normals[contact])
        rows.append(dict(direction=d, variant=variant, ok=verified(result, obj), reason=reason,
                         iterations=len(traj) - 1, status=np.array(statuses), u0=u))
    return rows


def _value(text):
    try:
        return ast.literal_eval(text)
    except (ValueError, SyntaxError):
        return text


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--grasp", choices=["precision", "power"], default="precision")
    parser.add_argument("--option", nargs="+", default=[], metavar="NAME=VALUE",
                        help="planner options, e.g. band_after=0 (every attempt with the contact band; PlannerOptions fields)")
    parser.add_argument("--standoffs", nargs="+", type=float, default=[0.0, 20.0], help="precision stand-offs (mm)")
    parser.add_argument("--only", nargs="+", metavar="NAME", help="objects, e.g. shape/orange mesh/mug paper/bell")
    parser.add_argument("--out", help="pickle every attempt here")
    parser.add_argument("--jobs", type=int, default=1, help="worker processes")
    args = parser.parse_args(argv)
    options = dict(item.split("=", 1) for item in args.option)
    options = {key: _value(value) for key, value in options.items()}
    PlannerOptions(**options)  # unknown names fail here, before any work
    names = args.only or list(objects())
    start = time.perf_counter()
    with ProcessPoolExecutor(args.jobs) as pool:
        results = dict(zip(names, pool.map(run_object, names, *zip(*[(args.grasp, options, args.standoffs)] * len(names)))))
    for name, rows in results.items():
        ok = sum(r["ok"] for r in rows)
        print(f"{name:32s} {ok:3d}/{len(rows)}  ({sum(r['iterations'] for r in rows)} iterations)")
    ok, total = sum(r["ok"] for rows in results.values() for r in rows), sum(len(rows) for rows in results.values())
    print(f"{args.grasp}, options {options or 'default'}: {ok}/{total} single attempts verified "
          f"({100.0 * ok / max(total, 1):.1f}%), {time.perf_counter() - start:.0f} s")
    if args.out:
        with open(args.out, "wb") as f:
            pickle.dump({"grasp": args.grasp, "options": options, "attempts": results}, f)


if __name__ == "__main__":
    main()
