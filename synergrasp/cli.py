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


def _vector(text):
    try:
        values = [float(v) for v in text.split(",")]
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected three numbers x,y,z, got {text!r}") from None
    if len(values) != 3:
        raise argparse.ArgumentTypeError(f"expected three numbers x,y,z, got {text!r}")
    return values


def _plan(args) -> int:
    from pathlib import Path

    from tqdm import tqdm

    from . import objects, viz
    from .hand import SynergyHand
    from .planner import plan

    obj = objects.get(args.object)
    hand = SynergyHand.default()
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    bar = tqdm(desc=f"{args.grasp} grasp of {obj.name}", unit="it", disable=args.quiet,
               bar_format="{desc}: {n_fmt} it [{elapsed}] {postfix}")

    def progress(check, status):
        bar.update(1)
        q = "  -   " if check.q != check.q else f"{check.q:+.3f}"
        bar.set_postfix_str(f"contacts {check.n_contacts}  g_sQ {status.g[-1]:+.3f}  g_Q {q}")

    result = plan(obj, args.grasp, backend=args.backend, approach=args.approach, max_iter=args.max_iter,
                  hand=hand, progress=progress)
    bar.close()
    stem = f"{Path(str(args.object)).stem}_{args.grasp}"
    files = [result.save(out / f"{stem}.json"), viz.plot_status(result, out / f"{stem}_status.png"),
             viz.plot_poses(result, obj, hand, out / f"{stem}_poses.png")]
    if not args.no_animation:
        files += [viz.animate(result, obj, hand, out / f"{stem}_reach.gif"),
                  viz.write_html(obj, hand, result.u, out / f"{stem}_grasp.html")]
    print(f"{'success' if result.success else 'FAILED'}: {result.reason}")
    print(f"iterations {result.iterations}, g_sQ {result.final_sq:+.4f}, g_Q {result.final_q:+.4f}, "
          f"contacts {', '.join(result.contact_labels) or 'none'}, penetration {result.penetration:.1f} mm")
    print(f"time {result.time_s:.2f} s, {result.lp_solves} LP solves ({result.backend})")
    print("wrote " + ", ".join(str(f) for f in files))
    return 0 if result.success else 1


def build_parser() -> argparse.ArgumentParser:
    """The argument parser of the ``synergrasp`` command (subcommands ``demo`` and ``plan``).

    Returns
    -------
    argparse.ArgumentParser
    """
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

    p = sub.add_parser(
        "plan",
        help="plan a reach-to-grasp motion and write the result and its figures",
        description="Plan a precision or power grasp of an object with the synergy hand (paper Sec. 3.2). "
        "Writes DIR/NAME_GRASP.json (the PlanResult), the status figure, the poses figure, a GIF of the reach "
        "and an interactive 3-D page of the final grasp. Exit status 0 on success, 1 if no stable grasp was found.",
    )
    p.add_argument("--object", default="ellipsoid",
                   help="a built-in (ellipsoid, cup, bell, goblet) or a mesh / point-cloud file (default ellipsoid)")
    p.add_argument("--grasp", choices=["precision", "power"], default="precision", help="grasp type (default precision)")
    p.add_argument("--backend", default="highs", help="LP backend: highs, clarabel or cvxpy (default highs)")
    p.add_argument("--approach", type=_vector, default=None, metavar="X,Y,Z",
                   help="direction from the object's centre to the start pose of the hand (default: the planner's list)")
    p.add_argument("--max-iter", type=int, default=1500, help="cap on the iterations over all attempts (default 1500)")
    p.add_argument("--out", default="synergrasp-out", metavar="DIR", help="output folder (default ./synergrasp-out)")
    p.add_argument("--no-animation", action="store_true", help="skip the GIF and the HTML page")
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    p.set_defaults(func=_plan)
    from .batch.cli import register as register_batch  # the batch and report subcommands
    register_batch(sub)
    return parser


def main(argv=None) -> int:
    """Entry point of the ``synergrasp`` command.

    Parameters
    ----------
    argv : list of str, optional
        Arguments without the program name; default ``sys.argv[1:]``.

    Returns
    -------
    int
        Exit status: 0 on success, 1 if ``plan`` found no stable grasp, 2 on a bad
        argument or input (the error is printed to stderr).

    Examples
    --------
    >>> main(["demo", "--contacts", "5"])    # doctest: +ELLIPSIS
    5 contacts spread on the equator of a 40 mm sphere, mu = 0.3, backend highs
    Q distance = -0.2425 (force-closed)
    ...
    0
    """
    args = build_parser().parse_args(argv)
    try:
        return args.func(args)
    except (ValueError, TypeError, OSError) as exc:
        print(f"synergrasp: error: {exc}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
