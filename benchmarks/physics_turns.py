"""Does a grasp's physics verdict depend on the world frame? The paper's grasps validated with the scene turned.

Usage::

    python benchmarks/physics_turns.py [--turns 24] [--preset synergrasp] [--quick]

The validation (`sg.validate`) pushes the object along the world's six axis directions. Turning the
whole scene, object and hand together, by a rotation that maps the axes onto the axes (there are 24)
permutes the six pushes among themselves: the test is the same, so its verdict should be. This plans
the paper's eight cases (default options) and validates each grasp with the scene turned by each of
the first ``--turns`` of those rotations (`sg.physics.validate_turns`), and prints per case the verdict at
each turn (``H`` held, ``S`` slip, ``R`` rotation, ``N`` no contact, ``P`` penetration, ``U``
unstable), how many turns held and the range of the largest displacement under the pushes. A
verdict that changes with the turn comes from the simulation's sensitivity (the contacts' order, the
solver's sweeps), not from the grasp. ``--quick``: the ellipsoid's precision grasp at two turns.
Writes nothing.
"""

from __future__ import annotations

import argparse

import numpy as np

import synergrasp as sg
from synergrasp.cli import positive
from synergrasp.physics import AXIS_TURNS, validate_turns

CASES = [(name, grasp) for name in ("ellipsoid", "cup", "bell", "goblet") for grasp in ("precision", "power")]
LETTERS = {"held": "H", "slip": "S", "rotation": "R", "no contact": "N", "penetration": "P", "unstable": "U"}


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--turns", type=positive(int), default=24, help="turns per grasp, at most 24 (default 24)")
    parser.add_argument("--preset", default="synergrasp", choices=sorted(sg.physics.PRESETS),
                        help="validation preset (default synergrasp)")
    parser.add_argument("--quick", action="store_true", help="the ellipsoid's precision grasp at two turns")
    args = parser.parse_args(argv)
    if args.turns > len(AXIS_TURNS):
        parser.error(f"--turns: at most {len(AXIS_TURNS)} (the rotations that map the axes onto the axes)")
    cases, turns = (CASES[:1], 2) if args.quick else (CASES, args.turns)
    consistent = 0
    for name, grasp in cases:
        obj = sg.objects.get(name)
        checks = validate_turns(sg.plan(obj, grasp, executable_reach=False).u, obj, turns, preset=args.preset)
        verdicts = [check.outcome for check in checks]
        largest = [float(np.nanmax(check.displacement)) if np.isfinite(check.displacement).any() else np.nan
                   for check in checks]
        held = verdicts.count("held")
        consistent += len(set(verdicts)) == 1
        spread = f"{np.nanmin(largest):.2f}-{np.nanmax(largest):.2f} mm" if np.isfinite(largest).any() else "-"
        print(f"{name:10s} {grasp:9s} {''.join(LETTERS[v] for v in verdicts)}  held at {held}/{turns} turns; "
              f"largest displacement {spread}", flush=True)
    print(f"{consistent} of {len(cases)} grasps have one verdict at every turn ({args.preset} protocol)")


if __name__ == "__main__":
    main()
