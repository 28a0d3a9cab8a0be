"""The ``synergrasp validate`` subcommand: a saved plan result tested in MuJoCo."""

from __future__ import annotations

import os
import sys
from pathlib import Path

from ..cli import add_unit_options, hand_from_args, object_from_args, output_stem
from .protocol import PRESETS

__all__ = ["add_validate_parser"]


def add_validate_parser(subparsers):
    """Register ``validate`` on the ``synergrasp`` command's subparsers.

    Parameters
    ----------
    subparsers : argparse._SubParsersAction
        What ``ArgumentParser.add_subparsers`` returned.

    Returns
    -------
    argparse.ArgumentParser
        The subcommand's parser.
    """
    p = subparsers.add_parser(
        "validate",
        help="test a saved plan result in MuJoCo: squeeze, settle, push along six directions",
        description="Test a saved PlanResult in MuJoCo (the documentation's 'Physics validation' page): the hand "
        "squeezes, the grasp settles, and the object is pushed with its weight along -x, +x, -y, +y, -z, +z. "
        "Writes DIR/NAME_GRASP_validation.json, the displacement figure and, where MuJoCo can render offscreen, a "
        "still of the settled grasp. NAME is the object's as synergrasp plan names it (the built-in's name, or the "
        "file's stem and extension) and GRASP the result's grasp type, so the results of objects of different names "
        "(such as a batch's results/OBJECT/GRASP.json) never share output files; a result file named otherwise (run1.json) "
        "adds its stem: NAME_GRASP_run1_validation.json. Another preset, and --mu or --retreat when given, add "
        "theirs, so that a variant does not overwrite the validation it is compared with: "
        "NAME_GRASP_dexgraspbench_mu0.5_retreat40_validation.json. Exit status 0 if the grasp holds, 1 if "
        "not. Needs pip install \"synergrasp[sim]\".",
    )
    p.add_argument("result", help="a PlanResult JSON file (written by synergrasp plan)")
    p.add_argument("--object", required=True,
                   help="the object it was planned for: a built-in (ellipsoid, cup, bell, goblet) or a mesh / point-cloud file")
    add_unit_options(p)
    p.add_argument("--preset", choices=sorted(PRESETS), default="synergrasp", help="protocol settings (default synergrasp)")
    p.add_argument("--mu", type=float, default=None, help="friction coefficient (default: the preset's)")
    p.add_argument("--retreat", type=float, default=0.0, metavar="MM",
                   help="move the palm back this far after the squeeze is set: a negative control (default 0)")
    p.add_argument("--hand", default=None, metavar="FILE", help="hand file the result was planned with (default the paper's hand)")
    p.add_argument("--out", default="synergrasp-out", metavar="DIR", help="output folder (default ./synergrasp-out)")
    p.add_argument("--no-still", action="store_true", help="skip the rendered still")
    p.set_defaults(func=_validate)
    return p


def _validate(args) -> int:
    if sys.platform.startswith("linux"):  # offscreen rendering without a display, if mujoco is not imported yet
        os.environ.setdefault("MUJOCO_GL", "egl")
    from ..planner import PlanResult
    from .figure import RenderingUnavailable, plot_validation, render_still
    from .validate import validate

    from .._files import writable_folder

    result = PlanResult.load(args.result)  # bad input is refused before the output folder is made
    obj = object_from_args(args)
    hand = hand_from_args(args)
    out = writable_folder(args.out, "output folder (--out)")  # before the simulation, so no work is lost
    settings = {} if args.mu is None else {"mu": args.mu}
    check = validate(result, obj, hand=hand, preset=args.preset, retreat=args.retreat, **settings)
    stem, own = output_stem(args.object, result.grasp), Path(args.result).stem
    if own not in (stem, result.grasp):  # run1.json, run2.json of one object: their own files
        stem += f"_{own}"
    if args.preset != "synergrasp":  # a variant's own files, beside the validation it is compared with
        stem += f"_{args.preset}"
    if args.mu is not None:
        stem += f"_mu{args.mu:.12g}"
    if args.retreat != 0.0:
        stem += f"_retreat{args.retreat:.12g}"
    stem += "_validation"
    files = [check.save(out / f"{stem}.json"), plot_validation(check, out / f"{stem}.png")]
    still = out / f"{stem}_still.png"
    if still.is_file():  # an earlier run's still beside this run's files would show another grasp (--no-still, or no
        still.unlink()  # offscreen rendering this time)
        if args.no_still:
            print(f"removed an earlier run's {still.name} (--no-still)", file=sys.stderr)
    if not args.no_still:
        try:
            files.append(render_still(check, obj, still, hand=hand))
        except RenderingUnavailable as exc:
            print(f"skipped the still: {exc}")
    print(f"{'held' if check.held else 'NOT HELD'} ({check.outcome}): {check.reason}")
    print(f"initial penetration {check.initial_penetration:.1f} mm{' (' + check.penetration_body + ')' if check.penetration_body else ''}, "
          f"object {check.object_mass * 1e3:.0f} g, {len(check.contact_bodies)} contacts, grip {check.grip_force:.1f} N, "
          f"preset {check.settings.name}, {check.cpu_time:.2f} s CPU")
    print("wrote " + ", ".join(str(f) for f in files))
    return 0 if check.held else 1
