"""Slender objects: rods, bars, capsules and hexagonal rods of 8-28 mm x 100-300 mm, drawn at random.

Usage::

    python benchmarks/slender.py [--split train|test] [--count 16] [--grasp precision power] [--jobs N]
                                 [--out DIR] [--quick]

The generalisation benchmark (``benchmarks/objectset.py``) holds few slender objects (one on its
train split, three on its test split, by ``sg.planner.core.axial_torque`` below 0.05), while pens,
cutlery, tools and handles are common. This script draws ``--count`` of them from a seeded generator
(``--split train``: seed 1; ``test``: seed 2; the four kinds in turn, diameter 8-28 mm, length
100-300 mm), plans a grasp of each with the default options and verifies it independently on its
mesh (``verification.py``). Prints each plan (verified, time, attempts, iterations, the Q distance
on the true surface in the object's own torque scale, friction's axial torque against it), then the
verified count, the iterations and the median Q per grasp type. Rows go to
``DIR/slender_<split>.jsonl`` (default ``bench-out/slender``). ``--quick`` plans the first train
object's precision grasp only (the test suite runs it).

To compare with another version of the package, run this script with ``PYTHONPATH`` pointing at a
checkout of it (``git worktree add ../before <commit>``, then ``PYTHONPATH=../before python
benchmarks/slender.py``).
"""

from __future__ import annotations

import argparse
import json
import sys
import time
import warnings
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np
import trimesh

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

import synergrasp as sg  # noqa: E402
from synergrasp.cli import output_folder, positive  # noqa: E402
from verification import verify  # noqa: E402

#: The generator's seed of each split.
SEEDS = {"train": 1, "test": 2}
KINDS = ("rod", "bar", "capsule", "hexrod")


def shapes(seed, count):
    """The split's slender meshes: ``count`` (name, trimesh.Trimesh) pairs, the four kinds in turn.

    Parameters
    ----------
    seed : int
    count : int

    Returns
    -------
    list of (str, trimesh.Trimesh)
        Names ``<kind>_<diameter>x<length>`` (mm).
    """
    rng = np.random.default_rng(seed)
    out = []
    for i in range(count):
        kind = KINDS[i % len(KINDS)]
        length, d = rng.uniform(100.0, 300.0), rng.uniform(8.0, 28.0)
        if kind == "rod":
            mesh = trimesh.creation.cylinder(radius=d / 2.0, height=length, sections=32)
        elif kind == "bar":
            mesh = trimesh.creation.box((d, rng.uniform(d, 2.0 * d), length))
        elif kind == "capsule":
            mesh = trimesh.creation.capsule(height=length - d, radius=d / 2.0, count=[16, 16])
        else:
            mesh = trimesh.creation.cylinder(radius=d / 2.0, height=length, sections=6)
        out.append((f"{kind}_{d:.0f}x{length:.0f}", mesh))
    return out


def run(task):
    """Plan and verify one (name, vertices, faces, grasp) task: a JSON-able row."""
    name, vertices, faces, grasp = task
    warnings.simplefilter("ignore")
    obj = sg.objects.from_mesh(trimesh.Trimesh(vertices, faces), name=name, cache=False)
    start = time.perf_counter()
    result = sg.plan(obj, grasp)
    row = dict(name=name, grasp=grasp, success=result.success, time=time.perf_counter() - start,
               attempts=len(result.attempts), iterations=result.total_iterations, reason=result.reason,
               torque=float(sg.planner.core.axial_torque(obj, 0.3)[1]))
    row.update(verify(result, obj))
    return row


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--split", choices=sorted(SEEDS), default="train", help="which seeded set")
    parser.add_argument("--count", type=positive(int), default=16, help="objects in the set")
    parser.add_argument("--grasp", nargs="+", choices=["precision", "power"], default=["precision", "power"],
                        help="grasp types to plan")
    parser.add_argument("--jobs", type=positive(int), default=1, help="processes planning at once")
    parser.add_argument("--out", type=output_folder, default="bench-out/slender", help="folder of slender_<split>.jsonl")
    parser.add_argument("--quick", action="store_true", help="the first train object's precision grasp only")
    args = parser.parse_args(argv)
    if args.quick:
        args.split, args.count, args.grasp, args.jobs = "train", 1, ["precision"], 1
    tasks = [(name, mesh.vertices, mesh.faces, grasp) for name, mesh in shapes(SEEDS[args.split], args.count)
             for grasp in args.grasp]
    rows = []
    with ProcessPoolExecutor(args.jobs) as pool:
        for row in pool.map(run, tasks):
            rows.append(row)
            print(f"{row['name']:16s} {row['grasp']:9s} {'verified' if row['verified'] else 'no':8s} "
                  f"{row['time']:6.2f} s {row['attempts']:3d} attempts {row['iterations']:5d} iterations "
                  f"Q {row['q_true']:+.3f} axial torque {row['torque']:.3f}", flush=True)
    path = args.out / f"slender_{args.split}.jsonl"
    path.write_text("".join(json.dumps(row) + "\n" for row in rows))
    for grasp in args.grasp:
        mine = [r for r in rows if r["grasp"] == grasp]
        q = [r["q_true"] for r in mine if r["verified"]]
        print(f"{grasp}: {sum(r['verified'] for r in mine)}/{len(mine)} verified, "
              f"{sum(r['iterations'] for r in mine)} iterations in all, "
              f"median Q of the verified {np.median(q) if q else float('nan'):+.3f}")
    print(f"rows: {path}")
    return rows


if __name__ == "__main__":
    main()
