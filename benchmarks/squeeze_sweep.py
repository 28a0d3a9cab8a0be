"""Can any squeeze hold the paper's precision grasps? A sweep of the squeeze and of the servos' stiffness.

Usage::

    python benchmarks/squeeze_sweep.py [--kp 5 25] [--mass KG] [--directions 12] [--quick]

The project's protocol squeezes along one direction of the synergy plane
(`synergrasp.physics.squeeze_targets`). This plans the paper's four precision
grasps (default options) and simulates the hold test of each (the project's
protocol but for its servo stiffness ``kp`` and, with ``--mass``, the
object's mass) with the synergies' servo targets moved by every step of a
grid instead: ``--directions`` directions evenly spread over the synergy
plane, each with the sizes 0.05, 0.1, 0.2 and 0.4 (synergy units). Prints,
per grasp and stiffness, how many of the squeezes hold and the squeeze whose
largest displacement under the six pushes is the smallest (a test that was
not simulated, overlap or instability, counts as infinitely far).
``--quick``: the ellipsoid, 4 directions and the size 0.4.
"""

from __future__ import annotations

import argparse
import warnings

import numpy as np

import synergrasp as sg
from synergrasp.cli import positive
from synergrasp.physics import protocol
from synergrasp.physics.simulate import simulate

SIZES = (0.05, 0.1, 0.2, 0.4)
OBJECTS = ("ellipsoid", "cup", "bell", "goblet")


def sweep(obj, u, hand, kp, directions, sizes, mass=None):
    """The hold test of configuration u with each squeeze: rows of (angle deg, size, outcome, largest displacement mm)."""
    settings = protocol("synergrasp", kp=kp, mass=mass)
    rows = []
    for angle in np.linspace(0.0, 360.0, directions, endpoint=False):
        for size in sizes:
            squeezed = u.copy()
            squeezed[6:8] += size * np.array([np.cos(np.radians(angle)), np.sin(np.radians(angle))])
            m = simulate(hand, obj, u, hand.joint_angles(u), hand.joint_angles(squeezed), settings)
            shifts = m["displacement"]  # NaN where the test was not simulated (overlap, instability)
            worst = float(shifts.max()) if np.isfinite(shifts).all() else np.inf
            rows.append((float(angle), size, m["outcome"], worst))
    return rows


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--kp", type=positive(float), nargs="+", default=[5.0, 25.0], help="servo stiffnesses (N m/rad)")
    parser.add_argument("--mass", type=positive(float), default=None, help="the object's mass (kg; default: from its volume)")
    parser.add_argument("--directions", type=positive(int), default=12, help="directions in the synergy plane")
    parser.add_argument("--quick", action="store_true", help="the ellipsoid, 4 directions, the size 0.4")
    args = parser.parse_args(argv)
    warnings.simplefilter("ignore")
    hand = sg.SynergyHand.default()
    objects, directions, sizes = (OBJECTS[:1], 4, SIZES[-1:]) if args.quick else (OBJECTS, args.directions, SIZES)
    summary = {}
    for name in objects:
        obj = sg.objects.get(name)
        u = np.asarray(sg.plan(obj, "precision").u, dtype=float)
        for kp in args.kp:
            rows = sweep(obj, u, hand, kp, directions, sizes, args.mass)
            held = sum(r[2] == "held" for r in rows)
            angle, size, outcome, worst = min(rows, key=lambda r: r[3])
            summary[name, kp] = held
            print(f"{name:10s} kp {kp:g}: {held}/{len(rows)} squeezes hold; the best: {angle:.0f} deg, size {size:g}: "
                  f"{outcome}, largest displacement {worst:.1f} mm", flush=True)
    return summary


if __name__ == "__main__":
    main()
