"""Clouds around an object against clouds of one camera view: the net outward normal that tells them apart.

Usage::

    python benchmarks/one_sided.py [--split train|test] [--stride 3] [--views 3] [--noise MM] [--plan]
                                   [--out DIR] [--quick]

For every ``--stride``-th object of a split of ``benchmarks/objectset.py``, a cloud of 3000 points
sampled on its whole mesh (as ``generalise.py --cloud 3000`` plans) and ``--views`` clouds of one
camera view each (the first hits of a 120 x 120 grid of rays from a camera three object sizes away,
in a random direction; at most 3000 of them) are loaded with ``sg.objects.from_points``. For each it
prints the length of the cloud's net outward normal (`PointSurface.net_normal`: the area-weighted
mean of its points' outward normals, 0 for a closed surface), whether the loader warned that the
cloud is seen from one side (above ``ONE_SIDED``, or taken for one camera view: ``ONE_VIEW``), how
the pieces were made, or the loader's error.
A summary gives the largest value of the whole clouds, the smallest of the views, and how many of
each were warned of. ``--noise 0.5`` adds Gaussian noise of 0.5 mm to every coordinate. ``--plan``
also plans a precision and a power grasp of every camera view (default options) and verifies each
accepted grasp on the object's true mesh (``verification.verify``: contacts within 5 mm, force-closed
by qhull at the mesh's normals, no phalanx capsule and not the palm box deeper than 3 mm in it); the
summary counts the accepted grasps, the verified ones and why the others fail. Rows go to
``DIR/one_sided_<split>.jsonl`` (default ``bench-out/one_sided``). ``--quick`` (the test suite):
the first object, one view.
"""

from __future__ import annotations

import argparse
import json
import sys
import warnings
from pathlib import Path

import numpy as np
import trimesh

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

import synergrasp as sg  # noqa: E402
from synergrasp.cli import output_folder, positive  # noqa: E402
from generalise import true_surface  # noqa: E402
from objectset import select  # noqa: E402
from verification import DEPTH, GAP, verify  # noqa: E402
from synergrasp.objects.loading import ONE_SIDED, ONE_VIEW  # noqa: E402

#: Rays per side of the camera's square grid, and the most points a view keeps.
PIXELS, MAX_POINTS = 120, 3000


def camera_view(mesh, direction, rng):
    """The first hits of a grid of rays from a camera 3 sizes away along ``direction``: (k, 3), at most MAX_POINTS."""
    v = direction / np.linalg.norm(direction)
    centre, size = mesh.bounds.mean(axis=0), float(np.ptp(mesh.bounds, axis=0).max())
    eye = centre + 3.0 * size * v
    a = np.cross(v, [0.3, 0.5, 0.8])
    a /= np.linalg.norm(a)
    grid = np.linspace(-0.7, 0.7, PIXELS) * size
    s, t = (x.ravel()[:, None] for x in np.meshgrid(grid, grid))
    rays = centre + s * a + t * np.cross(v, a) - eye
    rays /= np.linalg.norm(rays, axis=1, keepdims=True)
    hits = mesh.ray.intersects_location(np.repeat(eye[None], len(rays), axis=0), rays, multiple_hits=False)[0]
    return hits[rng.choice(len(hits), MAX_POINTS, replace=False)] if len(hits) > MAX_POINTS else hits


def measure(points, noise, rng):
    """A cloud's row: net normal length, warned, method, or the loader's error."""
    if noise:
        points = points + rng.normal(scale=noise, size=points.shape)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            obj = sg.objects.from_points(points, cache=False)
        except ValueError as error:
            return {"net": None, "warned": False, "view": False, "method": None, "error": str(error)}
    net = float(np.linalg.norm(obj.point_surface.net_normal(obj.contains)))
    warned = any("seen from one side" in str(w.message) or "is one camera view" in str(w.message) for w in caught)
    return {"net": net, "warned": warned, "view": "camera" in obj.info, "method": obj.info["method"], "error": None}


def plan_view(points, mesh_obj):
    """Plan a precision and a power grasp of a view's cloud; each accepted grasp verified on ``mesh_obj``."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        try:
            obj = sg.objects.from_points(points, cache=False)
        except ValueError:
            return {}
    out = {}
    for grasp in ("precision", "power"):
        try:
            result = sg.plan(obj, grasp)
        except ValueError as error:  # refused (too wide, too thin): no grasp claimed
            out[grasp] = {"accepted": False, "refused": str(error)[:120]}
            continue
        check = verify(result, mesh_obj)
        out[grasp] = {"accepted": bool(result.success), "time_s": result.time_s,
                      **{k: check[k] for k in ("verified", "gap", "closed", "depth", "palm_depth")}}
    return out


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--split", choices=["train", "test"], default="train",
                        help="split of objectset.py (default train)")
    parser.add_argument("--stride", type=positive(int), default=3, help="every N-th object of the split")
    parser.add_argument("--views", type=int, default=3, help="camera views per object")
    parser.add_argument("--noise", type=float, default=0.0, help="Gaussian noise (mm) added to every coordinate")
    parser.add_argument("--plan", action="store_true",
                        help="plan each camera view's grasps and verify them on the true mesh")
    parser.add_argument("--out", type=output_folder, default="bench-out/one_sided",
                        help="folder of the rows (default bench-out/one_sided)")
    parser.add_argument("--quick", action="store_true", help="the first object, one view (the test suite)")
    args = parser.parse_args(argv)
    if args.views < 0 or not args.noise >= 0:
        parser.error(f"--views and --noise must be >= 0; got {args.views}, {args.noise}")
    entries = select(args.split)[:: args.stride]
    entries, views = (entries[:1], 1) if args.quick else (entries, args.views)
    rng = np.random.default_rng(1)
    rows = []
    for entry in entries:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            mesh_obj = entry.make()
            mesh = true_surface(mesh_obj)
        clouds = [("whole", trimesh.sample.sample_surface(mesh, MAX_POINTS, seed=0)[0])]
        clouds += [(f"view {k + 1}", camera_view(mesh, rng.normal(size=3), rng)) for k in range(views)]
        for kind, points in clouds:
            row = {"name": entry.name, "cloud": kind, "points": len(points), **measure(points, args.noise, rng)}
            if args.plan and kind != "whole" and row["error"] is None:
                row["plans"] = plan_view(points, mesh_obj)
            rows.append(row)
            shown = row["error"][:70] if row["error"] else f"{row['net']:.3f}{' warned' if row['warned'] else ''}"
            planned = " ".join(f"{g} {'refused' if 'refused' in p else 'verified' if p['verified'] else 'FALSE ACCEPT' if p['accepted'] else 'failed'}"
                               for g, p in row.get("plans", {}).items())
            print(f"{entry.name:32s} {kind:7s} {shown}  {row['method'] or ''}  {planned}", flush=True)
    with open(args.out / f"one_sided_{args.split}.jsonl", "w") as f:
        f.writelines(json.dumps(row) + "\n" for row in rows)
    for kind, test in (("whole clouds", lambda r: r["cloud"] == "whole"), ("camera views", lambda r: r["cloud"] != "whole")):
        chosen = [r for r in rows if test(r)]
        nets = [r["net"] for r in chosen if r["net"] is not None]
        extreme = (max if kind == "whole clouds" else min)(nets, default=float("nan"))
        print(f"{kind}: {len(chosen)}, warned as seen from one side {sum(r['warned'] for r in chosen)} "
              f"(ONE_SIDED = {ONE_SIDED}), net normal {'largest' if kind == 'whole clouds' else 'smallest'} "
              f"{extreme:.3f}, taken for one camera view and swept away from it {sum(r['view'] for r in chosen)} "
              f"(ONE_VIEW = {ONE_VIEW}), refused {sum(r['error'] is not None for r in chosen)}")
    if args.plan:
        for grasp in ("precision", "power"):
            plans = [r["plans"][grasp] for r in rows if grasp in r.get("plans", {})]
            accepted = [p for p in plans if p["accepted"]]
            false = [p for p in accepted if not p["verified"]]
            print(f"{grasp}: {len(plans)} views planned, {len(accepted)} grasps accepted, "
                  f"{len(accepted) - len(false)} verified on the mesh; of the {len(false)} others: "
                  f"{sum(max(p['depth'], p['palm_depth']) > DEPTH for p in false)} with the hand over {DEPTH:g} mm "
                  f"deep in it, {sum(not p['closed'] for p in false)} not force-closed, "
                  f"{sum(p['gap'] > GAP for p in false)} with a contact over {GAP:g} mm off")
    return rows


if __name__ == "__main__":
    main()
