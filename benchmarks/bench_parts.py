"""Time the parts of a plan one at a time: its starts, the hand's contact test, and fixed attempts per iteration.

Usage::

    python benchmarks/bench_parts.py [--stride 6] [--repeats 3] [--out DIR] [--quick]

Whole plans are a poor instrument for a change of a few per cent: on a shared machine their times
move by a quarter between runs of the same code. This script times the parts on fixed inputs,
repeated, and prints a fingerprint of what they computed, so that two checkouts can be compared
part by part (run it once as is and once with ``PYTHONPATH=<other checkout>``, alternately; equal
fingerprints: the same seeds and trajectories). On every ``--stride``-th object of the
generalisation benchmark's train split (`objectset.py`):

* ``grid``: the object's distance grid (`synergrasp.objects.DistanceGrid`, what a power plan builds
  first), per object;
* ``pinch``: the first three pinch seeds (`synergrasp.planner.pinch_seeds`), per object;
* ``wrap``: the first wrap seed (`wrap_seeds`; the object's distance grid is built before, untimed);
* ``contact``: ``GraspObject.penetration(..., clear=False)`` of the phalanx capsules and the palm
  box (what a power attempt calls every iteration) at every configuration of the power attempts
  below, per call;
* ``precision`` / ``power``: an attempt (`run_attempt`) from each of the first two starts of the
  grasp (`starts`), every warm start dropped before it as a plan drops them, per iteration.

Each is wall-clock time, the smallest of ``--repeats`` passes (so a part that runs on several BLAS
threads counts once). Rows go to ``DIR/parts.csv`` (default
``bench-out/parts``). ``--quick`` (the test suite): three objects, one pass.
"""

from __future__ import annotations

import argparse
import csv
import hashlib
import sys
import time
import warnings
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

import synergrasp as sg  # noqa: E402
from synergrasp.cli import output_folder, positive  # noqa: E402
from objectset import select  # noqa: E402
from synergrasp.objects import DistanceGrid  # noqa: E402
from synergrasp.planner import (PlannerOptions, forget_warm_starts, pinch_seeds, run_attempt, starts,  # noqa: E402
                                wrap_seeds)


def _fingerprint(arrays):
    """First 12 hex digits of the SHA-1 of the arrays' bytes, in order."""
    digest = hashlib.sha1()
    for a in arrays:
        digest.update(np.ascontiguousarray(a, dtype=float).tobytes())
    return digest.hexdigest()[:12]


def _least(run, repeats):
    """(smallest wall-clock time of ``repeats`` calls of ``run()``, its last result)."""
    best, out = np.inf, None
    for _ in range(repeats):
        start = time.perf_counter()
        out = run()
        best = min(best, time.perf_counter() - start)
    return best, out


def measure(objects, hand, options, repeats):
    """The parts' rows: part, count (objects, calls or iterations), ms per count, fingerprint."""
    solver = sg.lp.get_backend("native")
    seconds, grids = _least(lambda: [DistanceGrid(obj.index, obj.bounds).values for obj in objects], repeats)
    rows = [("grid", len(objects), 1e3 * seconds / len(objects), _fingerprint(grids))]
    for obj in objects:
        obj.distance_grid(np.zeros((1, 3)))  # built once per object in a plan too; not what the seeds' times hold

    def seeds(kind, count):
        make = pinch_seeds if kind == "pinch" else wrap_seeds
        return [s.u for obj in objects for _, s in zip(range(count), make(hand, obj, options))]

    for kind, count in (("pinch", 3), ("wrap", 1)):
        seconds, us = _least(lambda: seeds(kind, count), repeats)
        rows.append((kind, len(objects), 1e3 * seconds / len(objects), _fingerprint(us)))

    trajectories = {}
    for grasp in ("precision", "power"):
        cases = [(obj, s.u) for obj in objects for _, s in zip(range(2), starts(hand, obj, grasp, options))]

        def attempts():
            out = []
            for obj, u in cases:
                forget_warm_starts(solver, obj)
                out.append((obj, run_attempt(hand, obj, grasp, u, options, backend=solver).trajectory))
            return out

        seconds, runs = _least(attempts, repeats)
        trajectories[grasp] = runs
        iterations = sum(len(t) - 1 for _, t in runs)
        rows.append((grasp, iterations, 1e3 * seconds / max(iterations, 1), _fingerprint(t for _, t in runs)))

    poses = [(obj, hand.segments(u)) for obj, t in trajectories["power"] for u in t]

    def contacts():
        return [obj.penetration(g.capsules, g.radius, box=(g.palm_center, g.palm_axes, g.palm_half_extents),
                                clear=False).distances for obj, g in poses]

    seconds, distances = _least(contacts, repeats)
    rows.append(("contact", len(poses), 1e3 * seconds / len(poses), _fingerprint(distances)))
    return rows


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--stride", type=positive(int), default=6, help="every N-th train object")
    parser.add_argument("--repeats", type=positive(int), default=3, help="passes; the smallest time is kept")
    parser.add_argument("--out", type=output_folder, default="bench-out/parts",
                        help="output folder for parts.csv (default bench-out/parts)")
    parser.add_argument("--quick", action="store_true", help="three objects, one pass (the test suite)")
    args = parser.parse_args(argv)
    warnings.simplefilter("ignore")
    entries = select("train")[:: args.stride]
    entries, repeats = (entries[:3], 1) if args.quick else (entries, args.repeats)
    objects = [e.make() for e in entries]
    hand, options = sg.SynergyHand.default(), PlannerOptions()
    for make in (pinch_seeds, wrap_seeds):  # compiled kernels loaded before anything is timed
        next(make(hand, objects[0], options), None)  # (the first object's distance grid with them)
    rows = measure(objects, hand, options, repeats)
    print(f"{len(objects)} objects (every {args.stride}th of train), smallest of {repeats} pass(es), wall-clock time")
    units = {"grid": "ms per object", "pinch": "ms per object (3 seeds)", "wrap": "ms per object (1 seed)",
             "contact": "ms per call", "precision": "ms per iteration", "power": "ms per iteration"}
    for part, count, ms, fingerprint in rows:
        print(f"{part:10s} {ms:8.3f} {units[part]:26s} over {count:5d}  fingerprint {fingerprint}")
    with open(args.out / "parts.csv", "w", newline="") as f:
        writer = csv.writer(f)
        writer.writerow(["part", "count", "ms", "fingerprint"])
        writer.writerows(rows)
    return rows


if __name__ == "__main__":
    main()
