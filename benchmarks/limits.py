"""Objects at the hand's limits, drawn at random: slender ones (rods, pens, handles) and wide ones.

Usage::

    python benchmarks/limits.py [--family slender|wide] [--split train|test] [--count 16]
                                [--grasp precision power] [--jobs N] [--out DIR] [--quick]

The generalisation benchmark (``benchmarks/objectset.py``) holds few objects at the hand's limits:
one slender object on its train split and three on its test split (``sg.planner.core.axial_torque``
below 0.05), and no object too wide to wrap. This script draws ``--count`` of a family from a seeded
generator (``--split train``: seed 1; ``test``: seed 2), plans a grasp of each with the default
options and verifies it independently on its mesh (``verification.py``):

* ``slender``: rods, bars, capsules and hexagonal rods in turn, 8-28 mm thick (a bar up to twice as
  wide), 100-300 mm long;
* ``wide``: balls, cubes, cylinders (one to two diameters long) and boxes in turn, 80-160 mm across
  their narrowest side, from what the hand wraps to what it cannot (the hand opens about 160 mm
  between thumb and fingertips).

Prints each plan (verified, time, attempts, iterations, the Q distance on the true surface in the
object's own torque scale, friction's axial torque against it), then the verified count, the
iterations, the median Q and the median and largest plan time per grasp type. Rows go to
``DIR/<family>_<split>.jsonl`` (default ``bench-out/limits``). ``--quick`` plans the first train
slender object's precision grasp only (the test suite runs it).

To compare with another version of the package, run this script with ``PYTHONPATH`` pointing at a
checkout of it (``git worktree add ../before <commit>``, then ``PYTHONPATH=../before python
benchmarks/limits.py``).
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
#: The kinds of each family, drawn in turn.
FAMILIES = {"slender": ("rod", "bar", "capsule", "hexrod"), "wide": ("ball", "cube", "cylinder", "box")}


def shapes(family, seed, count):
    """A family's meshes: ``count`` (name, trimesh.Trimesh) pairs, its kinds in turn.

    Parameters
    ----------
    family : {"slender", "wide"}
    seed : int
    count : int

    Returns
    -------
    list of (str, trimesh.Trimesh)
        Names ``<kind>_<diameter>x<length>`` (slender) or ``<kind>_<narrowest side>`` (wide), mm.
    """
    rng = np.random.default_rng(seed)
    kinds = FAMILIES[family]
    out = []
    for i in range(count):
        kind = kinds[i % len(kinds)]
        if family == "slender":
            length, d = rng.uniform(100.0, 300.0), rng.uniform(8.0, 28.0)
            name = f"{kind}_{d:.0f}x{length:.0f}"
        else:
            d = rng.uniform(80.0, 160.0)
            name = f"{kind}_{d:.0f}"
        if kind in ("rod", "hexrod"):
            mesh = trimesh.creation.cylinder(radius=d / 2.0, height=length, sections=32 if kind == "rod" else 6)
        elif kind == "bar":
            mesh = trimesh.creation.box((d, rng.uniform(d, 2.0 * d), length))
        elif kind == "capsule":
            mesh = trimesh.creation.capsule(height=length - d, radius=d / 2.0, count=[16, 16])
        elif kind == "ball":
            mesh = trimesh.creation.icosphere(subdivisions=3, radius=d / 2.0)
        elif kind == "cube":
            mesh = trimesh.creation.box((d, d, d))
        elif kind == "cylinder":
            mesh = trimesh.creation.cylinder(radius=d / 2.0, height=rng.uniform(d, 2.0 * d), sections=48)
        else:
            mesh = trimesh.creation.box((d, rng.uniform(d, 1.5 * d), rng.uniform(d, 1.5 * d)))
        out.append((name, mesh))
    return out


def run(task):
    """Plan and verify one (name, vertices, faces, grasp) task: a JSON-able row."""
    name, vertices, faces, grasp = task
    warnings.simplefilter("ignore")
    obj = sg.objects.from_mesh(trimesh.Trimesh(vertices, faces), name=name, cache=False)
    torque = float(sg.planner.core.axial_torque(obj, 0.3)[1])
    start = time.perf_counter()
    result = sg.plan(obj, grasp)
    row = dict(name=name, grasp=grasp, success=result.success, time=time.perf_counter() - start,
               attempts=len(result.attempts), kinds=[a["kind"] for a in result.attempts],
               iterations=result.total_iterations, reason=result.reason, torque=torque)
    row.update(verify(result, obj))
    return row


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--family", choices=sorted(FAMILIES), default="slender", help="which kind of objects")
    parser.add_argument("--split", choices=sorted(SEEDS), default="train", help="which seeded set")
    parser.add_argument("--count", type=positive(int), default=16, help="objects in the set")
    parser.add_argument("--grasp", nargs="+", choices=["precision", "power"], default=["precision", "power"],
                        help="grasp types to plan")
    parser.add_argument("--jobs", type=positive(int), default=1, help="processes planning at once")
    parser.add_argument("--out", type=output_folder, default="bench-out/limits",
                        help="folder of <family>_<split>.jsonl")
    parser.add_argument("--quick", action="store_true", help="the first train slender object's precision grasp only")
    args = parser.parse_args(argv)
    if args.quick:
        args.family, args.split, args.count, args.grasp, args.jobs = "slender", "train", 1, ["precision"], 1
    tasks = [(name, mesh.vertices, mesh.faces, grasp)
             for name, mesh in shapes(args.family, SEEDS[args.split], args.count) for grasp in args.grasp]
    rows = []
    with ProcessPoolExecutor(args.jobs) as pool:
        for row in pool.map(run, tasks):
            rows.append(row)
            print(f"{row['name']:16s} {row['grasp']:9s} {'verified' if row['verified'] else 'no':8s} "
                  f"{row['time']:6.2f} s {row['attempts']:3d} attempts {row['iterations']:5d} iterations "
                  f"Q {row['q_true']:+.3f} axial torque {row['torque']:.3f}", flush=True)
    path = args.out / f"{args.family}_{args.split}.jsonl"
    path.write_text("".join(json.dumps(row) + "\n" for row in rows))
    for grasp in args.grasp:
        mine = [r for r in rows if r["grasp"] == grasp]
        q = [r["q_true"] for r in mine if r["verified"]]
        failed = [r["time"] for r in mine if not r["verified"]]
        print(f"{grasp}: {sum(r['verified'] for r in mine)}/{len(mine)} verified, "
              f"{sum(r['iterations'] for r in mine)} iterations in all, "
              f"median Q of the verified {np.median(q) if q else float('nan'):+.3f}, plan time median "
              f"{np.median([r['time'] for r in mine]):.2f} s, failed plans up to {max(failed, default=0.0):.2f} s")
    print(f"rows: {path}")
    return rows


if __name__ == "__main__":
    main()
