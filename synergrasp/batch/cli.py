"""The ``synergrasp batch`` and ``synergrasp report`` commands (registered by `synergrasp.cli`)."""

from __future__ import annotations

import signal
import sys
import threading

from ..cli import UNITS, command_line_hint, hand_from_args, positive, unit_option
from ..hand import POINT_KINDS

#: Failed tasks whose reasons `_batch` prints (the rest are in summary.csv).
SHOWN_FAILURES = 10


def register(sub, epilog: str = "") -> None:
    """Add the ``batch`` and ``report`` subcommands to the ``synergrasp`` parser's subparsers.

    Parameters
    ----------
    sub : argparse._SubParsersAction
        What ``ArgumentParser.add_subparsers`` returned.
    epilog : str
        The text after each subcommand's help (the exit codes).
    """
    from ..physics import PRESETS

    b = sub.add_parser(
        "batch",
        help="plan many objects and grasp types on a Dask cluster, resumable",
        description="Plan every OBJECT with every grasp type, one task per (object, grasp), on a local Dask "
        "cluster (or a running scheduler). Each plan is written to DIR/results/KEY/GRASP.json as it finishes; "
        "a rerun of the same command plans only what is missing; DIR/summary.csv is rebuilt from the results. "
        "Failures (an object that does not load, a plan that raises or times out) are recorded and do not stop "
        "the batch. The output folder is checked before planning. Exit status 0 when a task gave a plan "
        "(whether or not it found a grasp), 1 when none did, 130 if interrupted by Ctrl-C or SIGTERM (rerun to go on).",
        epilog=epilog,
    )
    b.add_argument("objects", nargs="+", metavar="OBJECT",
                   help="a built-in (ellipsoid, cup, bell, goblet), a mesh or point-cloud file, or a folder of them")
    b.add_argument("--grasp", nargs="+", choices=POINT_KINDS, default=["precision"],
                   help="grasp types (default precision)")
    b.add_argument("--out", default="batch-out", metavar="DIR", help="output folder (default ./batch-out)")
    b.add_argument("--workers", type=int, default=None, metavar="N",
                   help="worker processes of the local cluster (default: one per CPU)")
    b.add_argument("--scheduler", default=None, metavar="ADDRESS",
                   help="address of a running Dask scheduler (tcp://host:8786) instead of a local cluster")
    b.add_argument("--backend", default="native", help="LP backend: native, highs, clarabel or cvxpy (default native)")
    b.add_argument("--hand", default=None, metavar="FILE", help="hand file to plan with (default the paper's hand)")
    b.add_argument("--max-iter", type=positive(int), default=None,
                   help="cap on each plan's iterations (default: the planner's)")
    b.add_argument("--time-limit", type=positive(float), default=None, metavar="SECONDS",
                   help="a plan running longer is recorded as timed out, in place of the planner's own limit "
                   "(default: the planner's, 10 s, after which a plan ends without a grasp)")
    units = b.add_mutually_exclusive_group()
    units.add_argument("--scale", type=float, default=None, metavar="FACTOR",
                       help="multiply object files' coordinates by FACTOR to get millimetres (1000 for metres)")
    units.add_argument("--units", choices=sorted(UNITS), default=None,
                       help="the object files' length unit (m: --scale 1000, cm: --scale 10; default mm)")
    b.add_argument("--validate", nargs="?", const="synergrasp", default=None, choices=sorted(PRESETS),
                   metavar="PRESET", help="test every successful plan in MuJoCo (synergrasp validate) with PRESET "
                   f"({', '.join(sorted(PRESETS))}; default synergrasp); needs the sim extra")
    b.add_argument("--retry-failed", action="store_true", help="plan again the tasks recorded as failed")
    b.add_argument("--connect-timeout", type=float, default=10.0, metavar="SECONDS",
                   help="seconds to wait for --scheduler and a worker (default 10)")
    b.add_argument("--quiet", action="store_true", help="no progress bar")
    b.set_defaults(func=_batch)

    r = sub.add_parser(
        "report",
        help="write a page with the summary table and a gallery of a batch's final grasps",
        description="Write DIR/report.html: per-grasp summary, a gallery of final grasps (pictures under "
        "DIR/report/) and the table of every task of the batch in DIR.",
        epilog=epilog,
    )
    r.add_argument("dir", metavar="DIR", help="output folder of `synergrasp batch`")
    r.add_argument("--hand", default=None, metavar="FILE", help="hand file the batch planned with (default the paper's hand)")
    r.add_argument("--gallery", type=int, default=48, metavar="N", help="most plans in the gallery (default 48)")
    r.set_defaults(func=_report)


def _interrupt(signum, frame):
    """SIGTERM does what Ctrl-C does at that moment (during a batch: `run` notes it, and stops when it can)."""
    handler = signal.getsignal(signal.SIGINT)
    if not callable(handler):
        raise KeyboardInterrupt
    handler(signum, frame)


def _batch(args) -> int:
    from .runner import BatchInterrupted, run

    options = {} if args.max_iter is None else {"max_iter": args.max_iter}
    if args.hand is not None:
        options["hand"] = hand_from_args(args)
    options = options or None
    scale = args.scale if args.scale is not None else UNITS[args.units] if args.units is not None else 1.0
    main_thread = threading.current_thread() is threading.main_thread()
    previous = signal.signal(signal.SIGTERM, _interrupt) if main_thread else None  # SIGTERM stops like Ctrl-C
    try:
        report = run(args.objects, args.grasp, args.out, workers=args.workers, scheduler=args.scheduler,
                     backend=args.backend, options=options, time_limit=args.time_limit, scale=scale,
                     validate=args.validate, retry_failed=args.retry_failed, progress=not args.quiet,
                     connect_timeout=args.connect_timeout)
    except BatchInterrupted as exc:
        print(exc.report)
        _print_failures(exc.report, unit_option(args))
        print(f"synergrasp: interrupted; the {exc.report.finished} results of this run are written: "
              "rerun the same command to plan the rest", file=sys.stderr)
        return 130
    except KeyboardInterrupt:  # before the first task was submitted
        print("synergrasp: interrupted before planning started; nothing was planned", file=sys.stderr)
        return 130
    finally:
        if main_thread:
            signal.signal(signal.SIGTERM, previous)
    print(report)
    _print_failures(report, unit_option(args))
    return 1 if report.rows and all(row["status"] != "planned" for row in report.rows) else 0


def _print_failures(report, given=None) -> None:
    """Why tasks gave no plan (in this run or before), on stderr, with the command line's flags (a load error once;
    ``given``: the unit option the files were read with, `unit_option`)."""
    failures = {}
    for row in report.rows:
        if row["status"] != "planned":
            key = row["object"] if row["status"] == "load error" else f"{row['object']} {row['grasp']}"
            failures.setdefault(key, f"{row['status']}: {command_line_hint(row['reason'], given)}")
    for key, words in list(failures.items())[:SHOWN_FAILURES]:
        print(f"synergrasp: {key}: {words}", file=sys.stderr)
    if len(failures) > SHOWN_FAILURES:
        print(f"synergrasp: {len(failures) - SHOWN_FAILURES} more failures: see the reason column of "
              f"{report.out / 'summary.csv'}", file=sys.stderr)


def _report(args) -> int:
    from .report import write_report

    print(f"wrote {write_report(args.dir, gallery=args.gallery, hand=hand_from_args(args))}")
    return 0
