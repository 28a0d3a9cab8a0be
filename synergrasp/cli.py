"""The ``synergrasp`` command line."""

from __future__ import annotations

import argparse
import sys

import numpy as np


def _demo(args) -> int:
    import synergrasp as sg

    t = 2 * np.pi * np.arange(args.contacts) / args.contacts
    points = 40.0 * np.c_[np.cos(t), np.sin(t), np.zeros(args.contacts)]
    normals = -points / 40.0
    result = sg.q_distance(points, normals, mu=args.mu, backend=args.backend)
    print(f"{args.contacts} contacts spread on the equator of a 40 mm sphere, mu = {args.mu}, backend {args.backend}")
    print(f"Q distance = {result.value:+.4f} ({'force-closed' if result.force_closure else 'not force-closed'})")
    print(f"|dQ/dp| max = {np.abs(result.grad_points).max():.3e} per mm, LP solves: {result.lp_solves}")
    return 0


def build_parser() -> argparse.ArgumentParser:
    """The argument parser of the ``synergrasp`` command."""
    parser = argparse.ArgumentParser(
        prog="synergrasp",
        description="Reach-to-grasp planning and grasp quality for a synergy-controlled robotic hand.",
    )
    sub = parser.add_subparsers(dest="command", required=True)
    demo = sub.add_parser("demo", help="print the Q distance of a built-in grasp", description="Print the Q distance of contacts spread on a sphere's equator.")
    demo.add_argument("--contacts", type=int, default=5, help="number of contacts (default 5)")
    demo.add_argument("--mu", type=float, default=0.3, help="friction coefficient (default 0.3)")
    demo.add_argument("--backend", default="highs", help="LP backend: highs, clarabel or cvxpy (default highs)")
    demo.set_defaults(func=_demo)
    return parser


def main(argv=None) -> int:
    """Entry point of the ``synergrasp`` command."""
    args = build_parser().parse_args(argv)
    try:
        return args.func(args)
    except (ValueError, TypeError) as exc:
        print(f"synergrasp: error: {exc}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
