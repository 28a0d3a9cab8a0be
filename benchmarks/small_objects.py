"""Small objects: the planner on spheres, cubes and cylinders of 20-50 mm, size by size.

Usage::

    python benchmarks/small_objects.py [--sizes 20 30 40 50] [--shapes sphere cube cylinder]
                                       [--grasp precision power] [--out DIR] [--quick]

The loader accepts objects from 10 mm; the generalisation benchmark (``benchmarks/objectset.py``)
has three families of small objects (16-45 mm) drawn at random. This script plans a grasp of each
shape at a fixed series of sizes
(``sphere``: that diameter; ``cube``: that side; ``cylinder``: that diameter, three times as
long), with the default options, and prints for each plan whether it succeeded, its time, its
attempts and the planner's reason, then the successes per grasp type. Rows go to
``DIR/small_objects.jsonl`` (default ``bench-out/small_objects``). ``--quick`` plans the 50 mm
sphere's precision grasp only (the test suite runs it).
"""

from __future__ import annotations

import argparse
import json
import time
import warnings

import trimesh

import synergrasp as sg
from synergrasp.cli import output_folder, positive

#: Each shape's mesh at size d (mm).
SHAPES = {
    "sphere": lambda d: trimesh.creation.icosphere(subdivisions=3, radius=d / 2.0),
    "cube": lambda d: trimesh.creation.box((d, d, d)),
    "cylinder": lambda d: trimesh.creation.cylinder(radius=d / 2.0, height=3.0 * d),
}


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--sizes", nargs="+", type=positive(float), default=[20.0, 30.0, 40.0, 50.0],
                        help="sizes (mm): the sphere's and cylinder's diameter, the cube's side")
    parser.add_argument("--shapes", nargs="+", choices=sorted(SHAPES),
                        default=["sphere", "cube", "cylinder"],
                        help="shapes to plan (a cylinder is three diameters long)")
    parser.add_argument("--grasp", nargs="+", choices=["precision", "power"], default=["precision", "power"],
                        help="grasp types to plan")
    parser.add_argument("--out", type=output_folder, default="bench-out/small_objects",
                        help="folder of small_objects.jsonl")
    parser.add_argument("--quick", action="store_true", help="the 50 mm sphere's precision grasp only")
    args = parser.parse_args(argv)
    if args.quick:
        args.sizes, args.shapes, args.grasp = [50.0], ["sphere"], ["precision"]
    warnings.simplefilter("ignore")  # the loader's notes on each mesh
    rows = []
    for shape in args.shapes:
        for size in args.sizes:
            obj = sg.objects.from_mesh(SHAPES[shape](size), name=f"{shape} {size:g} mm", cache=False)
            for grasp in args.grasp:
                start = time.perf_counter()
                result = sg.plan(obj, grasp)
                row = dict(shape=shape, size=size, grasp=grasp, success=bool(result.success),
                           time=time.perf_counter() - start, attempts=len(result.attempts), reason=result.reason)
                rows.append(row)
                print(f"{obj.name:18s} {grasp:9s} {'ok  ' if row['success'] else 'FAIL'} {row['time']:5.1f} s "
                      f"{row['attempts']:3d} attempts  {row['reason'][:90]}", flush=True)
    for grasp in args.grasp:
        mine = [r for r in rows if r["grasp"] == grasp]
        print(f"{grasp}: {sum(r['success'] for r in mine)}/{len(mine)} grasped")
    with open(args.out / "small_objects.jsonl", "w") as f:
        for row in rows:
            f.write(json.dumps(row) + "\n")
    return rows


if __name__ == "__main__":
    main()
