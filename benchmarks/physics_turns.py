"""Does a grasp's physics verdict depend on the world frame? The paper's grasps validated with the scene turned.

Usage::

    python benchmarks/physics_turns.py [--turns 24] [--preset synergrasp] [--quick]

The validation (`sg.validate`) pushes the object along the world's six axis directions. Turning the
whole scene, object and hand together, by a rotation that maps the axes onto the axes (there are 24)
permutes the six pushes among themselves: the test is the same, so its verdict should be. This plans
the paper's eight cases (default options) and validates each grasp with the scene turned by each of
the first ``--turns`` of those rotations (the identity first), and prints per case the verdict at
each turn (``H`` held, ``S`` slip, ``R`` rotation, ``N`` no contact, ``P`` penetration, ``U``
unstable), how many turns held and the range of the largest displacement under the pushes. A
verdict that changes with the turn comes from the simulation's sensitivity (the contacts' order, the
solver's sweeps), not from the grasp. ``--quick``: the ellipsoid's precision grasp at two turns.
Writes nothing.
"""

from __future__ import annotations

import argparse
import itertools
import warnings

import numpy as np
from scipy.spatial.transform import Rotation

import synergrasp as sg
from synergrasp.cli import positive
from synergrasp.hand import rotation_xyz

CASES = [(name, grasp) for name in ("ellipsoid", "cup", "bell", "goblet") for grasp in ("precision", "power")]
LETTERS = {"held": "H", "slip": "S", "rotation": "R", "no contact": "N", "penetration": "P", "unstable": "U"}


def axis_turns():
    """The 24 rotations that map the axes onto the axes, (24, 3, 3), the identity first."""
    turns = [np.eye(3)[list(order)] * np.array(signs)[:, None]
             for order in itertools.permutations(range(3)) for signs in itertools.product((1.0, -1.0), repeat=3)]
    return np.array([R for R in turns if np.linalg.det(R) > 0])


def turned(obj, u, R):
    """The object and the configuration u turned together by R about the origin."""
    M = np.eye(4)
    M[:3, :3] = R
    v = np.array(u, dtype=float)
    v[:3] = R @ v[:3]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # (Euler angles at their lock: the rotation is still exact)
        v[3:6] = Rotation.from_matrix(R @ rotation_xyz(v[3:6])).as_euler("XYZ")
    return obj.transformed(M), v


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--turns", type=positive(int), default=24, help="turns per grasp, at most 24 (default 24)")
    parser.add_argument("--preset", default="synergrasp", choices=sorted(sg.physics.PRESETS),
                        help="validation preset (default synergrasp)")
    parser.add_argument("--quick", action="store_true", help="the ellipsoid's precision grasp at two turns")
    args = parser.parse_args(argv)
    if args.turns > 24:
        parser.error("--turns: at most 24 (the rotations that map the axes onto the axes)")
    cases, turns = (CASES[:1], axis_turns()[:2]) if args.quick else (CASES, axis_turns()[: args.turns])
    hand = sg.SynergyHand.default()
    consistent = 0
    for name, grasp in cases:
        obj = sg.objects.get(name)
        result = sg.plan(obj, grasp, executable_reach=False)
        verdicts, largest = [], []
        for R in turns:
            moved, u = turned(obj, result.u, R)
            check = sg.validate(u, moved, hand=hand, preset=args.preset)
            verdicts.append(check.outcome)
            largest.append(float(np.nanmax(check.displacement)) if np.isfinite(check.displacement).any() else np.nan)
        held = verdicts.count("held")
        consistent += len(set(verdicts)) == 1
        spread = f"{np.nanmin(largest):.2f}-{np.nanmax(largest):.2f} mm" if np.isfinite(largest).any() else "-"
        print(f"{name:10s} {grasp:9s} {''.join(LETTERS[v] for v in verdicts)}  held at {held}/{len(turns)} turns; "
              f"largest displacement {spread}", flush=True)
    print(f"{consistent} of {len(cases)} grasps have one verdict at every turn ({args.preset} protocol)")


if __name__ == "__main__":
    main()
