"""Can the hand make a power grasp of an object at all? The most phalanges that reach it with the palm on it.

Usage::

    python benchmarks/power_reach.py [--only NAME ...] [--grid 9] [--samples 32] [--rolls 12] [--out DIR] [--quick]

The paper's power criterion needs the palm and at least three phalanges in contact (N_c >= 4 with
g_Q < -0.1, N_c counting the palm). This script lays the palm on the object, a denser version of
the planner's wrap seeds (`synergrasp.planner.wrap_seeds`): on ``--samples`` surface points
(`surface_samples`), with each of the palm's 9 skin points in turn on the point, the palm facing
along the inward normal, in ``--rolls`` rolls about it, 0, 2 and 4 mm off the surface, with the
synergies on a ``--grid`` x ``--grid`` grid. A pose counts when no phalanx axis is nearer the object
than the finger radius less ``max_penetration`` and no palm skin point is deeper than
``max_penetration`` (on the object's `DistanceGrid`, as the wrap seeds are screened). For each
object it prints the most phalanges whose power point lies within ``eps_c`` of the surface in a
pose that counts: under 3, none of the paper's kind was found for this hand (-1: no pose keeps
out of the object). The palm is anchored at its nine skin points only, so an object that touches
the face between them is not searched there: a count under 3 does not prove that no power grasp
exists (a 30 mm ball counts 2 here, and the planner grasps it with the palm and four phalanges).

Objects: those of ``benchmarks/objectset.py`` whose names start with one of ``--only`` (default
the three small-object families). Rows go to ``DIR/power_reach.csv`` (default
``bench-out/power_reach``). ``--quick`` (the test suite): a 30 mm ball and the paper's cup, on
a 3 x 3 grid, 16 points, 8 rolls.
"""

from __future__ import annotations

import argparse
import csv
import sys
import warnings
from pathlib import Path

import numpy as np
import trimesh

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

import synergrasp as sg  # noqa: E402
from synergrasp.cli import output_folder, positive  # noqa: E402
from objectset import select  # noqa: E402
from synergrasp.planner import PlannerOptions, roll_frames, surface_samples  # noqa: E402

#: Distances of the palm skin point off the surface (mm).
STANDOFFS = (0.0, 2.0, 4.0)
#: Points along each phalanx capsule's axis that must stay out of the object.
ALONG = np.linspace(0.0, 1.0, 6)


def hand_table(hand, steps):
    """At each synergy value of a steps x steps grid, the power points, the palm skin and the capsule axes' points.

    Parameters
    ----------
    hand : SynergyHand
    steps : int
        Values per synergy, evenly spaced between its limits.

    Returns
    -------
    power : (g, k, 3) float
        The k phalanges' power points in the palm frame.
    palm : (p, 3) float
        The palm's skin points (the palm is rigid: the same at every synergy value).
    axes : (g, k * len(ALONG), 3) float
    """
    lo, hi = hand.synergy_limits[:, 0], hand.synergy_limits[:, 1]
    grids = [np.linspace(a, b, steps) for a, b in zip(lo, hi)]
    power, axes = [], []
    for z in np.array(np.meshgrid(*grids, indexing="ij")).reshape(hand.n_syn, -1).T:
        u = np.r_[np.zeros(6), z]
        power.append(hand.points(u, "power")[:-1])
        capsules = hand.segments(u).capsules
        axes.append((capsules[None, :, 0] * (1.0 - ALONG[:, None, None]) + capsules[None, :, 1] * ALONG[:, None, None])
                    .reshape(-1, 3))
    palm = hand.skin_and_jacobian(np.zeros(hand.n_u), "power")[1]
    return np.array(power), palm, np.array(axes)


def most_phalanges(hand, obj, table, options, samples, rolls, seed=0):
    """The most phalanges within ``eps_c`` of the surface in a pose with the palm on it that cuts in nowhere.

    Parameters
    ----------
    hand : SynergyHand
    obj : GraspObject
    table : tuple
        `hand_table`'s arrays.
    options : PlannerOptions
        Its ``eps_c`` and ``max_penetration``.
    samples, rolls : int
        Surface points and palm rolls about each normal.
    seed : int

    Returns
    -------
    int
        -1 when no pose keeps out of the object.
    """
    power, palm, axes = table
    points, normals, _, _ = surface_samples(obj, samples, seed)
    R = roll_frames(normals, rolls)
    anchor = np.repeat(points, rolls, axis=0)
    outward = np.repeat(normals, rolls, axis=0)
    best, grid = -1, obj.distance_grid
    for at in palm:
        for standoff in STANDOFFS:
            t = anchor + standoff * outward - R @ at  # (poses, 3)
            clear = ((grid.posed(palm[None], R, t).min(axis=2) >= -options.max_penetration)
                     & (grid.posed(axes, R, t).min(axis=2) >= hand.finger_radius - options.max_penetration))
            touching = (grid.posed(power, R, t) < options.eps_c).sum(axis=2)
            if clear.any():
                best = max(best, int(touching[clear].max()))
    return best


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--only", nargs="+", default=["procedural/small_"], help="object name prefixes")
    parser.add_argument("--grid", type=positive(int), default=9, help="synergy values per synergy")
    parser.add_argument("--samples", type=positive(int), default=32, help="surface points")
    parser.add_argument("--rolls", type=positive(int), default=12, help="rolls of the palm about each normal")
    parser.add_argument("--out", type=output_folder, default="bench-out/power_reach",
                        help="folder of power_reach.csv")
    parser.add_argument("--quick", action="store_true", help="a 30 mm ball and the paper's cup, coarser")
    args = parser.parse_args(argv)
    warnings.simplefilter("ignore")  # the loader's notes on each mesh
    hand, options = sg.SynergyHand.default(), PlannerOptions()
    if args.quick:
        args.grid, args.samples, args.rolls = 3, 16, 8
        objects = [("30 mm ball", "-", sg.objects.from_mesh(trimesh.creation.icosphere(3, 15.0), name="30 mm ball",
                                                            cache=False)),
                   ("cup", "-", sg.objects.get("cup"))]
    else:
        try:
            objects = [(e.name, e.split, e.make()) for e in select("all", only=args.only)]
        except ValueError as exc:
            parser.error(str(exc))
    table = hand_table(hand, args.grid)
    rows = []
    for name, split, obj in objects:
        n = most_phalanges(hand, obj, table, options, args.samples, args.rolls)
        rows.append(dict(name=name, split=split, size_mm=round(float(obj.size), 1), most_phalanges=n))
        said = f"at most {n} phalanges with the palm on it" if n >= 0 else "no pose with the palm on it keeps out of it"
        print(f"{name:32s} {split:5s} {obj.size:6.1f} mm  {said}", flush=True)
    with open(args.out / "power_reach.csv", "w", newline="") as fh:
        writer = csv.DictWriter(fh, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    print(f"wrote {args.out / 'power_reach.csv'}")
    return rows


if __name__ == "__main__":
    main()
