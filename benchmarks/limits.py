"""Objects at the hand's limits, drawn at random: slender ones (rods, pens, handles) and wide ones.

Usage::

    python benchmarks/limits.py [--family slender|thin|wide] [--split train|test] [--count 16]
                                [--grasp precision power] [--jobs N] [--slender-scale default|diameter]
                                [--out DIR] [--quick]

The generalisation benchmark (``benchmarks/objectset.py``) holds few objects at the hand's limits:
one slender object on its train split and three on its test split (``sg.planner.core.axial_torque``
below 0.05), and no object too wide to wrap. This script draws ``--count`` of a family from a seeded
generator (``--split train``: seed 1; ``test``: seed 2), plans a grasp of each with the default
options and verifies it independently on its mesh (``verification.py``):

* ``slender``: rods, bars, capsules and hexagonal rods in turn, 8-28 mm thick (a bar up to twice as
  wide), 100-300 mm long;
* ``thin``: flat plates (blades, rulers: 2-7 mm thick, 12-40 mm wide), wires (3-8 mm), tapered
  rods (chopsticks, drumsticks: 6-16 mm at the base, 0.4-0.8 of that at the tip) and L-shaped
  hex keys (3-8 mm) in turn, 120-300 mm long;
* ``wide``: balls, cubes, cylinders (one to two diameters long) and boxes in turn, 80-160 mm across
  their narrowest side, from what the hand wraps to what it cannot (the hand opens about 160 mm
  between thumb and fingertips).

Prints each plan (verified, time, attempts, iterations, the Q distance on the true surface in the
object's default torque scale, friction's axial torque against it), then the verified count, the
iterations, the median Q and the median and largest plan time per grasp type. ``--slender-scale
diameter`` loads each slender object (``sg.planner.status.slender``) with a torque scale of its
diameter about its long axis instead of its bounding radius. Rows go to
``DIR/<family>_<split>[_diameter].jsonl`` (default ``bench-out/limits``). ``--quick`` plans the first train
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
FAMILIES = {"slender": ("rod", "bar", "capsule", "hexrod"), "thin": ("plate", "wire", "taper", "key"),
            "wide": ("ball", "cube", "cylinder", "box")}


def shapes(family, seed, count):
    """A family's meshes: ``count`` (name, trimesh.Trimesh) pairs, its kinds in turn.

    Parameters
    ----------
    family : {"slender", "thin", "wide"}
    seed : int
    count : int

    Returns
    -------
    list of (str, trimesh.Trimesh)
        Names ``<kind>_<thickness>x<length>`` (slender, thin) or ``<kind>_<narrowest side>`` (wide), mm.
    """
    rng = np.random.default_rng(seed)
    kinds = FAMILIES[family]
    out = []
    for i in range(count):
        kind = kinds[i % len(kinds)]
        if family == "slender":
            length, d = rng.uniform(100.0, 300.0), rng.uniform(8.0, 28.0)
            name = f"{kind}_{d:.0f}x{length:.0f}"
        elif family == "thin":  # (named by the real thickness: a plate's d - 1, a taper's base 2 d)
            length, d = rng.uniform(120.0, 300.0), rng.uniform(3.0, 8.0)
            name = f"{kind}_{d - 1.0 if kind == 'plate' else 2.0 * d if kind == 'taper' else d:.0f}x{length:.0f}"
        else:
            d = rng.uniform(80.0, 160.0)
            name = f"{kind}_{d:.0f}"
        if kind in ("rod", "hexrod"):
            mesh = trimesh.creation.cylinder(radius=d / 2.0, height=length, sections=32 if kind == "rod" else 6)
        elif kind == "bar":
            mesh = trimesh.creation.box((d, rng.uniform(d, 2.0 * d), length))
        elif kind == "capsule":
            mesh = trimesh.creation.capsule(height=length - d, radius=d / 2.0, count=[16, 16])
        elif kind == "plate":  # a blade, a ruler: 2-7 mm thick, 12-40 mm wide
            mesh = trimesh.creation.box((d - 1.0, rng.uniform(12.0, 40.0), length))
        elif kind == "wire":
            mesh = trimesh.creation.cylinder(radius=d / 2.0, height=length, sections=16)
        elif kind == "taper":  # a chopstick, a drumstick: 2 d at the base, 0.8-1.6 d at the tip
            mesh = trimesh.creation.cylinder(radius=d, height=length, sections=24)
            tip = mesh.vertices[:, 2] > 0.0
            mesh.vertices[tip, :2] *= rng.uniform(0.4, 0.8)
        elif kind == "key":  # a hex key: a long and a short leg at a right angle
            short = rng.uniform(0.15, 0.3) * length
            long_leg = trimesh.creation.cylinder(radius=d / 2.0, height=length, sections=6)
            short_leg = trimesh.creation.cylinder(radius=d / 2.0, height=short + d, sections=6)
            short_leg.apply_transform(trimesh.transformations.rotation_matrix(np.pi / 2.0, [0.0, 1.0, 0.0]))
            short_leg.apply_translation([(short + d) / 2.0 - d / 2.0, 0.0, length / 2.0 - d / 2.0])
            mesh = trimesh.util.concatenate([long_leg, short_leg])
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
    """Plan and verify one (name, vertices, faces, grasp, diameter) task: a JSON-able row.

    ``diameter``: a slender object (`synergrasp.planner.status.slender`) is loaded with a torque scale of
    twice its axial radius (every Q, the criterion's margins and the acceptance in those units).
    """
    name, vertices, faces, grasp, diameter = task
    warnings.simplefilter("ignore")
    mesh = trimesh.Trimesh(vertices, faces)
    obj = truth = sg.objects.from_mesh(mesh, name=name, cache=False)
    torque = float(sg.planner.core.axial_torque(obj, 0.3)[1])
    if diameter and sg.planner.status.slender(obj, 0.3):  # the same pieces, another torque scale
        obj = sg.objects.GraspObject(obj.pieces, center=obj.center, name=name, mesh=obj.mesh, info=obj.info,
                                     torque_scale=2.0 * sg.planner.status.axial_radius(obj))
    start = time.perf_counter()
    result = sg.plan(obj, grasp)
    row = dict(name=name, grasp=grasp, success=result.success, time=time.perf_counter() - start,
               attempts=len(result.attempts), kinds=[a["kind"] for a in result.attempts],
               iterations=result.total_iterations, reason=result.reason, torque=torque, torque_scale=obj.torque_scale)
    row.update(verify(result, truth))  # (q_true in the default torque scale)
    return row


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--family", choices=sorted(FAMILIES), default="slender", help="which kind of objects")
    parser.add_argument("--split", choices=sorted(SEEDS), default="train", help="which seeded set")
    parser.add_argument("--count", type=positive(int), default=16, help="objects in the set")
    parser.add_argument("--grasp", nargs="+", choices=["precision", "power"], default=["precision", "power"],
                        help="grasp types to plan")
    parser.add_argument("--jobs", type=positive(int), default=1, help="processes planning at once")
    parser.add_argument("--slender-scale", choices=["default", "diameter"], default="default",
                        help="a slender object's torque scale: its bounding radius, or its diameter about its axis")
    parser.add_argument("--out", type=output_folder, default="bench-out/limits",
                        help="folder of <family>_<split>[_diameter].jsonl")
    parser.add_argument("--quick", action="store_true", help="the first train slender object's precision grasp only")
    args = parser.parse_args(argv)
    if args.quick:
        args.family, args.split, args.count, args.grasp, args.jobs = "slender", "train", 1, ["precision"], 1
    tasks = [(name, mesh.vertices, mesh.faces, grasp, args.slender_scale == "diameter")
             for name, mesh in shapes(args.family, SEEDS[args.split], args.count) for grasp in args.grasp]
    rows = []
    with ProcessPoolExecutor(args.jobs) as pool:
        for row in pool.map(run, tasks):
            rows.append(row)
            print(f"{row['name']:16s} {row['grasp']:9s} {'verified' if row['verified'] else 'no':8s} "
                  f"{row['time']:6.2f} s {row['attempts']:3d} attempts {row['iterations']:5d} iterations "
                  f"Q {row['q_true']:+.3f} axial torque {row['torque']:.3f}", flush=True)
    path = args.out / f"{args.family}_{args.split}{'_diameter' if args.slender_scale == 'diameter' else ''}.jsonl"
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
