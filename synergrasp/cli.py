"""The ``synergrasp`` command line (``demo`` and ``plan``; ``validate``, ``batch`` and ``report`` registered from
their packages; exit codes in `EXIT_CODES`), and the helpers the examples and benchmarks share: argument types
(`positive`, `output_folder`, `add_unit_options`), output names (`output_stem`) and their ``--docs`` pages'
generated blocks (`write_between_markers`)."""

from __future__ import annotations

import argparse
import functools
import os
import sys
import time
import warnings
from pathlib import Path

import numpy as np


def _demo(args) -> int:
    import synergrasp as sg

    t = 2 * np.pi * np.arange(args.contacts) / args.contacts
    points = 40.0 * np.c_[np.cos(t), np.sin(t), np.zeros(args.contacts)]
    normals = -points / 40.0
    result = sg.q_distance(points, normals, mu=args.mu, backend=args.backend)
    print(f"{args.contacts} contacts spread on the equator of a 40 mm sphere, mu = {args.mu}, backend {args.backend}")
    value = round(result.value, 4) + 0.0  # no "-0.0000" beside "not force-closed"
    print(f"Q distance = {value:+.4f} ({'force-closed' if result.force_closure else 'not force-closed'})")
    print(f"|dQ/dp| max = {np.abs(result.grad_points).max():.3e} per mm, LP solves: {result.lp_solves}")
    return 0


def _vector(text):
    try:
        values = [float(v) for v in text.split(",")]
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected three numbers x,y,z, got {text!r}") from None
    if len(values) != 3:
        raise argparse.ArgumentTypeError(f"expected three numbers x,y,z, got {text!r}")
    if not all(np.isfinite(values)):
        raise argparse.ArgumentTypeError(f"expected three finite numbers x,y,z, got {text!r}")
    return values


def _attach_vectors(argv):
    """``argv`` with a vector value that starts with a minus sign joined to its option: ``--approach=-1,0,0``.

    argparse takes a separate value that starts with ``-`` and is not a
    single number for an option of its own ("expected one argument").
    """
    argv = list(sys.argv[1:] if argv is None else argv)
    for i in range(len(argv) - 2, -1, -1):
        option = argv[i]
        if len(option) > 2 and "--approach".startswith(option) and argv[i + 1].startswith("-") and "," in argv[i + 1]:
            argv[i:i + 2] = [f"{option}={argv[i + 1]}"]  # (an abbreviation too, as argparse takes it)
    return argv


def positive(kind):
    """An argparse type: a finite number (``float``) or a whole number (``int``) greater than 0."""

    wanted = "an integer" if kind is int else "a finite number"

    def parse(text):
        try:
            value = kind(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"expected {wanted} > 0, got {text!r}") from None
        if value <= 0 or (kind is not int and not np.isfinite(value)):  # (a huge int overflows isfinite)
            raise argparse.ArgumentTypeError(f"expected {wanted} > 0, got {text!r}")
        return value

    return parse


def backend(text):
    """An argparse type: the name of an installed LP backend (`synergrasp.lp.available_backends`)."""
    from .lp import get_backend

    try:
        get_backend(text)
    except (ValueError, TypeError, ImportError) as exc:
        raise argparse.ArgumentTypeError(str(exc)) from None
    return text


def output_folder(text):
    """An argparse type: a folder to write in, created if needed; a clear usage error if it cannot be.

    Parameters
    ----------
    text : str
        The ``--out`` argument (argparse also passes a string default through it).

    Returns
    -------
    pathlib.Path
        The folder, which exists and takes a new file.

    Raises
    ------
    argparse.ArgumentTypeError
        If the name is empty, names a file, or the folder cannot be created or written to.
    """
    from ._files import writable_folder

    try:
        return writable_folder(text)
    except ValueError as exc:
        raise argparse.ArgumentTypeError(str(exc)) from None


#: ``--units``: the factor that turns each unit into millimetres.
UNITS = {"m": 1000.0, "cm": 10.0, "mm": 1.0}
#: Exit status of the ``synergrasp`` command.
EXIT_CODES = {0: "success (plan: a stable grasp was found; validate: the grasp held)",
              1: "plan: no stable grasp was found, validate: the grasp did not hold (the outputs are written); "
                 "batch: no task gave a plan (every one a load error, timeout or failure; the records are written)",
              2: "bad input: an argument, the object file or the output folder, an object the hand cannot hold "
                 "(plan refuses one too large, too thin or too small before any attempt: ObjectRefused), or for batch "
                 "a Dask scheduler that does not answer; the error is printed to stderr",
              130: "interrupted (Ctrl-C; for batch also SIGTERM): batch after writing the results that had arrived "
                   "(rerun the same command to plan the rest); plan, validate and report write nothing more",
              141: "the standard output was closed before the command had printed everything (a pipe into head): "
                   "the files it writes were written first"}


def write_between_markers(path, start, end, text):
    """Replace what lies between the lines ``start`` and ``end`` of a text file with ``text`` (a script's ``--docs``).

    Parameters
    ----------
    path : str or os.PathLike
        A page (README.md, a docs page) that holds both markers, ``start`` first.
    start, end : str
        The markers, e.g. ``"<!-- household:start -->"`` and ``"<!-- household:end -->"``; they are kept.
    text : str
        The new block, written on the lines between them.

    Raises
    ------
    ValueError
        If the page lacks a marker or holds them the wrong way round: nothing is written.

    Examples
    --------
    >>> import tempfile
    >>> from pathlib import Path
    >>> page = Path(tempfile.mkdtemp()) / "page.md"
    >>> _ = page.write_text("# Results\\n<!-- r:start -->\\nold\\n<!-- r:end -->\\nmore\\n")
    >>> write_between_markers(page, "<!-- r:start -->", "<!-- r:end -->", "- new")
    >>> print(page.read_text(), end="")
    # Results
    <!-- r:start -->
    - new
    <!-- r:end -->
    more
    """
    from ._files import atomic_path

    content = Path(path).read_text()
    first, last = content.find(start), content.find(end)
    if first < 0 or last < first + len(start):
        raise ValueError(f"{path} has no block between the markers {start!r} and {end!r}: add them, {start!r} first")
    with atomic_path(path) as tmp:
        tmp.write_text(content[:first + len(start)] + "\n" + text.strip("\n") + "\n" + content[last:])


def output_stem(obj_arg, grasp) -> str:
    """The file-name stem of a plan's outputs: the object's name, with its file's extension, and the grasp.

    Two input files that differ only by their extension (``capsule.xyz`` and
    ``capsule.npy``) get different names.

    Parameters
    ----------
    obj_arg : str
        The ``--object`` argument: a built-in name (in any case: the name in lower case) or a file path.
    grasp : str
        ``"precision"`` or ``"power"``.

    Returns
    -------
    str

    Examples
    --------
    >>> output_stem("ellipsoid", "precision"), output_stem("scans/capsule.xyz", "power"), output_stem("Cup", "power")
    ('ellipsoid_precision', 'capsule_xyz_power', 'cup_power')
    """
    from .objects import BUILTINS

    path = Path(str(obj_arg))
    suffix = path.suffix.lower().lstrip(".")
    if str(obj_arg).lower() in BUILTINS:  # a built-in by its name, in any case (as --object takes it)
        return f"{str(obj_arg).lower()}_{grasp}"
    return f"{path.stem}_{suffix}_{grasp}" if suffix else f"{path.stem}_{grasp}"


def attempt_table(result) -> str:
    """A plan's attempts, one line each: how it started (a pinch's width), its start palm position, iterations, why it ended.

    Parameters
    ----------
    result : PlanResult

    Returns
    -------
    str
        A text table with a header line.
    """
    rows = [("#", "start", "start palm (mm)", "iterations", "ended")]
    for number, attempt in enumerate(result.attempts, 1):
        start = attempt.get("start")
        palm = "(" + ", ".join(f"{x:.0f}" for x in start[:3]) + ")" if start is not None else "-"
        kind = str(attempt.get("kind", "-")) + (f" {attempt['width']:.0f} mm" if "width" in attempt else "")
        rows.append((str(number), kind, palm, str(attempt["iterations"]), attempt["reason"]))
    widths = [max(len(row[i]) for row in rows) for i in range(len(rows[0]) - 1)]
    return "\n".join("  ".join(cell.ljust(w) for cell, w in zip(row, widths)) + "  " + row[-1] for row in rows)


def add_unit_options(parser):
    """Add ``--scale`` and ``--units`` (one or the other) to a subcommand's parser; `object_from_args` reads them.

    Parameters
    ----------
    parser : argparse.ArgumentParser
    """
    units = parser.add_mutually_exclusive_group()
    units.add_argument("--scale", type=positive(float), default=None, metavar="FACTOR",
                       help="multiply the file's coordinates by FACTOR to get millimetres (1000 for metres)")
    units.add_argument("--units", choices=sorted(UNITS), default=None,
                       help="the file's length unit (m: --scale 1000, cm: --scale 10; default mm)")


def hand_from_args(args):
    """The hand of a command's ``--hand FILE`` (`SynergyHand.from_file`), or the paper's without it.

    Parameters
    ----------
    args : argparse.Namespace
        With ``hand`` (a path or None).

    Returns
    -------
    SynergyHand
    """
    from .hand import SynergyHand

    return SynergyHand.default() if args.hand is None else SynergyHand.from_file(args.hand)


def object_from_args(args):
    """The object of ``--object``, scaled by ``--scale`` or ``--units`` (files only).

    Parameters
    ----------
    args : argparse.Namespace
        With ``object``, ``scale`` and ``units`` (`add_unit_options`).

    Returns
    -------
    GraspObject
    """
    from . import objects

    scale = args.scale if args.scale is not None else UNITS[args.units] if args.units is not None else None
    builtin = args.object.lower() in objects.BUILTINS
    if scale is not None and builtin:
        option = "--scale" if args.scale is not None else "--units"
        raise ValueError(f"{option} applies to object files; the built-in {args.object!r} is in millimetres already")
    talk = not builtin and Path(args.object).expanduser().is_file() and not getattr(args, "quiet", False)
    if talk:  # a mesh seen for the first time is decomposed, which can take a minute
        print(f"loading {args.object} (a mesh or cloud new to the cache is cut into convex pieces first)", file=sys.stderr,
              flush=True)
    start = time.perf_counter()
    obj = objects.get(args.object) if scale is None else objects.get(args.object, scale=scale)
    if talk:
        print(f"{obj.name}: {obj.n_pieces} convex piece(s) ({obj.info.get('method', '?')}, cache "
              f"{obj.info.get('cache', '?')}), {time.perf_counter() - start:.1f} s", file=sys.stderr)
    return obj


def _plan(args) -> int:
    from tqdm import tqdm

    from . import viz
    from ._files import writable_folder
    from .lp import get_backend
    from .planner import clock, plan

    get_backend(args.backend)  # bad input is refused before the output folder is made
    hand = hand_from_args(args)
    obj = object_from_args(args)  # (a new mesh's pieces are cached: a refused --out below loses none of that work)
    out = writable_folder(args.out, "output folder (--out)")  # before the plan, so it is not lost
    bar = tqdm(desc=f"{args.grasp} grasp of {obj.name}", unit="it", disable=args.quiet,
               bar_format="{desc}: {n_fmt} it [{elapsed}] {postfix}")

    def progress(check, status):
        bar.update(1)
        q = "  -   " if check.q != check.q else f"{check.q:+.3f}"
        bar.set_postfix_str(f"contacts {check.n_contacts}  g_sQ {status.g[-1]:+.3f}  g_Q {q}")

    limit = {} if args.time_limit is None else {"time_limit": args.time_limit}
    wall, search = time.perf_counter(), clock()
    try:
        result = plan(obj, args.grasp, backend=args.backend, approach=args.approach, max_iter=args.max_iter,
                      hand=hand, progress=progress, **limit)
    finally:
        bar.close()
    wall = time.perf_counter() - wall
    compiling = wall - (clock() - search)  # numba's, once after an install
    stem = output_stem(args.object, args.grasp)
    animation = [out / f"{stem}_reach.gif", out / f"{stem}_grasp.html"]
    stale = [f for f in animation if f.is_file()]
    for f in stale:  # an earlier run's animation beside this run's files would show another plan (--no-animation, or
        f.unlink()  # this run interrupted before its own are written)
    files = [result.save(out / f"{stem}.json"),
             viz.plot_status(result, out / f"{stem}_status.png", labels=hand.point_labels(result.grasp)),
             viz.plot_poses(result, obj, hand, out / f"{stem}_poses.png")]
    if not args.no_animation:
        rows = "path" if len(result.path) else "trajectory"  # the reach to execute, else the search
        files += [viz.animate(result, obj, hand, animation[0], rows=rows),
                  viz.write_html(obj, hand, result.u, animation[1])]
    elif stale:
        print(f"removed an earlier run's {', '.join(f.name for f in stale)} (--no-animation)", file=sys.stderr)
    print(f"{'success' if result.success else 'FAILED'}: {result.reason}")
    q = "-" if result.final_q != result.final_q else f"{result.final_q:+.4f}"
    if result.surface_q == result.surface_q and f"{result.surface_q:.4f}" != f"{result.final_q:.4f}":  # as the reason
        q += f" (Q on the true surface, which it was accepted on: {result.surface_q:+.4f})"
    print(f"iterations {result.iterations}, g_sQ {result.final_sq:+.4f}, g_Q {q}, "
          f"contacts {', '.join(result.contact_labels) or 'none'}, penetration {result.penetration:.1f} mm")
    if len(result.path):
        print(f"executable reach: {len(result.path)} poses, clearance {result.clearance[0]:.1f} mm at the pre-grasp, "
              f"smallest {result.clearance.min():+.1f} mm; {result.reach['reason']}")
    with_compilation = " (with part of numba's compilation, below)" if compiling > 0.5 else ""
    print(f"time {result.time_s:.2f} s{with_compilation}, {result.lp_solves} LP solves ({result.backend})")
    if compiling > 0.5:  # over the whole call: the plan's own time starts after its checks of the object
        print(f"numba compiled the library's kernels for {compiling:.1f} s of this run's {wall:.1f} s (once after an "
              "install: later runs load them from its cache)")
    if not result.success:
        print(f"attempts ({result.total_iterations} iterations in all; every attempt's status trace is in "
              f"{Path(files[1]).name}):")
        print(attempt_table(result))
    print("wrote " + ", ".join(str(f) for f in files))
    return 0 if result.success else 1


def _epilog():
    return "exit status: " + "; ".join(f"{code} {meaning}" for code, meaning in EXIT_CODES.items())


def build_parser() -> argparse.ArgumentParser:
    """The argument parser of the ``synergrasp`` command (subcommands ``demo`` and ``plan``).

    Returns
    -------
    argparse.ArgumentParser
    """
    from . import __version__
    from .hand import POINT_KINDS

    parser = argparse.ArgumentParser(
        prog="synergrasp",
        description="Reach-to-grasp planning and grasp quality for a synergy-controlled robotic hand.",
        epilog=_epilog(),
    )
    parser.add_argument("--version", action="version", version=f"synergrasp {__version__}")
    sub = parser.add_subparsers(dest="command", required=True)
    demo = sub.add_parser("demo", help="print the Q distance of a built-in grasp",
                          description="Print the Q distance of contacts spread on a sphere's equator.", epilog=_epilog())
    demo.add_argument("--contacts", type=positive(int), default=5, help="number of contacts (default 5)")
    demo.add_argument("--mu", type=float, default=0.3, help="friction coefficient (default 0.3)")
    demo.add_argument("--backend", default="native", help="LP backend: native, highs, clarabel or cvxpy (default native)")
    demo.set_defaults(func=_demo)

    p = sub.add_parser(
        "plan",
        help="plan a reach-to-grasp motion and write the result and its figures",
        description="Plan a precision or power grasp of an object with the synergy hand (paper Sec. 3.2). "
        "Writes DIR/NAME_GRASP.json (the PlanResult, with its executable reach and the reach's clearance), the "
        "status figure, the poses figure, a GIF of the reach "
        "and an interactive 3-D page of the final grasp; NAME is the built-in's name or the file's stem and "
        "extension (capsule.xyz: capsule_xyz), so inputs of different names never share output files (files of one "
        "name in different folders do: give each its own --out). Every file is written "
        "to a temporary file first and then renamed. The output folder is checked before planning. "
        "A failed plan prints a table of its attempts and why each ended.",
        epilog=_epilog(),
    )
    p.add_argument("--object", default="ellipsoid",
                   help="a built-in (ellipsoid, cup, bell, goblet) or a mesh / point-cloud file (default ellipsoid)")
    p.add_argument("--grasp", choices=POINT_KINDS, default="precision", help="grasp type (default precision)")
    p.add_argument("--backend", default="native", help="LP backend: native, highs, clarabel or cvxpy (default native)")
    p.add_argument("--hand", default=None, metavar="FILE", help="hand file to plan with (default the paper's hand)")
    add_unit_options(p)
    p.add_argument("--approach", type=_vector, default=None, metavar="X,Y,Z",
                   help="direction from the object's centre to the start pose of the hand, e.g. 0,1,0 or -1,0,0 "
                        "(default: the planner's list)")
    p.add_argument("--max-iter", type=positive(int), default=1500,
                   help="cap on the iterations over all attempts (default 1500)")
    p.add_argument("--time-limit", type=positive(float), default=None, metavar="SECONDS",
                   help="cap on the wall-clock time of the plan's search; an attempt running when it passes ends "
                        "there, and the returned grasp's reach (and, with the annealing method, the trajectory's "
                        "history) is computed after it (default: the planner's, PlannerOptions.time_limit)")
    p.add_argument("--out", default="synergrasp-out", metavar="DIR", help="output folder (default ./synergrasp-out)")
    p.add_argument("--no-animation", action="store_true", help="skip the GIF and the HTML page")
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    p.set_defaults(func=_plan)
    from .physics.cli import add_validate_parser  # the validate subcommand lives with the physics package

    add_validate_parser(sub).epilog = _epilog()
    from .batch.cli import register as register_batch  # the batch and report subcommands

    register_batch(sub, _epilog())
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
        Exit status (`EXIT_CODES`): 0 on success, 1 if ``plan`` found no stable
        grasp, 2 on a bad argument, input file or output folder (the error is
        printed to stderr), 130 when interrupted by Ctrl-C, 141 when standard
        output was closed before everything was printed. Argument errors found
        by the parser exit with 2 too (``SystemExit``).

    Examples
    --------
    >>> main(["demo", "--contacts", "5"])    # doctest: +ELLIPSIS
    5 contacts spread on the equator of a 40 mm sphere, mu = 0.3, backend native
    Q distance = -0.2425 (force-closed)
    ...
    0
    """
    args = build_parser().parse_args(_attach_vectors(argv))
    given = unit_option(args)
    with warnings.catch_warnings():
        warnings.showwarning = functools.partial(_show_warning, given=given)
        try:
            status = args.func(args)
            sys.stdout.flush()  # (a closed pipe is met here, not in Python's last flush at exit)
            return status
        except KeyboardInterrupt:  # (batch says what it wrote itself)
            print("synergrasp: interrupted", file=sys.stderr)
            return 130
        except BrokenPipeError as exc:
            if not _stdout_closed():  # (another pipe: an error like the others)
                print(f"synergrasp: error: {exc}", file=sys.stderr)
                return 2
            devnull = os.open(os.devnull, os.O_WRONLY)  # nothing more to say to it, nor in Python's last flush
            os.dup2(devnull, sys.stdout.fileno())
            os.close(devnull)
            return 141
        except (ValueError, TypeError, OSError, ImportError) as exc:
            print(f"synergrasp: error: {command_line_hint(str(exc), given)}", file=sys.stderr)
            return 2


def _stdout_closed() -> bool:
    """Whether the process's standard output is a pipe whose reader has gone (poll reports an error on it)."""
    import select

    try:
        poller = select.poll()
        poller.register(sys.stdout.fileno(), select.POLLOUT)
        return any(events & (select.POLLERR | select.POLLHUP) for _, events in poller.poll(0))
    except (AttributeError, OSError, ValueError):  # no poll, or stdout not a file (captured, a notebook's)
        return False


#: Library advice (a keyword argument to pass) and the command line's way of saying it.
_COMMAND_LINE_ADVICE = {"scale=": "--units m or cm, or --scale FACTOR", "as hand=": "--hand FILE"}


def command_line_hint(message: str, given: str | None = None) -> str:
    """A library message that suggests ``scale=...`` or ``hand=...``, with the command line's way of saying it.

    Parameters
    ----------
    message : str
    given : str, optional
        The unit option the file was read with (``"--units m"``): advice on
        the scale then says so, instead of suggesting that option again.

    Returns
    -------
    str
        ``message``, then ``(on the command line: FLAGS)`` for each advice it gives.

    Examples
    --------
    >>> command_line_hint("pass scale=1000")
    'pass scale=1000 (on the command line: --units m or cm, or --scale FACTOR)'
    >>> command_line_hint("pass scale=0.001", given="--units m")
    'pass scale=0.001 (on the command line: it was read with --units m; drop it if the file is in mm, or give other --units or --scale)'
    """
    hints = [f"it was read with {given}; drop it if the file is in mm, or give other --units or --scale"
             if advice == "scale=" and given else flags
             for advice, flags in _COMMAND_LINE_ADVICE.items() if advice in message]
    return message + "".join(f" (on the command line: {flags})" for flags in hints)


def unit_option(args) -> str | None:
    """The ``--units`` or ``--scale`` the command was given, as typed (None: neither)."""
    if getattr(args, "scale", None) is not None:
        return f"--scale {args.scale:g}"
    return f"--units {args.units}" if getattr(args, "units", None) is not None else None


def _show_warning(message, category, filename, lineno, file=None, line=None, *, given=None):
    """Warnings as one line on stderr, without the library's file and line."""
    print(f"synergrasp: warning: {command_line_hint(str(message), given)}", file=sys.stderr)


if __name__ == "__main__":
    sys.exit(main())
