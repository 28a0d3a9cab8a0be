"""How often one planner attempt alone ends in a verified grasp, from the planner's own starts.

Usage::

    python benchmarks/single_attempts.py [--split train|test|all] [--grasp precision|power] [--starts K]
                                         [--only NAME ...] [--option NAME=VALUE ...] [--pose SEED] [--jobs N]
                                         [--out FILE]

For every object of a split of the generalisation benchmark (``benchmarks/objectset.py``), the
first K starts the planner would try (`synergrasp.planner.starts`) each get one attempt
(`synergrasp.planner.run_attempt`), whatever the others did. An attempt counts when it ends in a
grasp that passes the benchmarks' independent check on the true mesh (``verification.py``:
contacts within 5 mm of it, force-closed by qhull at its normals, no phalanx capsule and not the
palm box deeper than 3 mm in it). Prints the rate per object and in all, the iterations spent per verified
attempt (what a plan pays for a grasp from these starts: an attempt that succeeds more often by running
longer need not be a better one), the outcomes of the attempts, and with
``--out`` writes every attempt (JSON lines: its start, outcome and reason, the depth of the hand in the object, the
contacts, g_sQ and g_Q where it ended). ``--pose SEED`` turns and moves every object as
``generalise.py --pose SEED`` does.
"""

from __future__ import annotations

import argparse
import itertools
import json
import sys
import time
import warnings
from collections import Counter
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path
from types import SimpleNamespace

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

import synergrasp as sg  # noqa: E402
from synergrasp.cli import positive  # noqa: E402
from generalise import check_options, placed, planner_options  # noqa: E402
from verification import verify  # noqa: E402
from objectset import SPLITS, select  # noqa: E402
from synergrasp.planner import PlannerOptions, run_attempt, starts  # noqa: E402


def run_object(name, grasp, count, options, posed=None):
    """The first ``count`` starts of one object (turned and moved by `placed` with seed ``posed``, if given), one
    attempt each: a list of dicts."""
    warnings.simplefilter("ignore")
    (entry,) = [e for e in select("all") if e.name == name]
    obj, hand, opts = entry.make(), sg.SynergyHand.default(), PlannerOptions(**options)
    obj = obj if posed is None else placed(obj, name, posed)
    rows = []
    for start in itertools.islice(starts(hand, obj, grasp, opts), count):
        t0 = time.perf_counter()
        r = run_attempt(hand, obj, grasp, start.u, opts)
        plan_like = SimpleNamespace(success=r.success, u=r.trajectory[-1], contact_points=r.final.nearest[r.check.contact])
        check = verify(plan_like, obj)
        rows.append(dict(name=name, pose=posed, start=start.kind, detail=start.detail, outcome=r.outcome.name.lower(),
                         reason=r.reason, depth=r.penetration, contacts=r.check.n_contacts, sq=float(r.final.g[-1]),
                         verified=check["verified"], iterations=r.iterations, q=r.check.q, time=time.perf_counter() - t0))
    return rows


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--split", default="train", choices=SPLITS + ("all",),
                        help="split of objectset.py; all: train and test")
    parser.add_argument("--grasp", choices=["precision", "power"], default="precision", help="grasp type")
    parser.add_argument("--starts", type=positive(int), default=4, help="starts per object (the planner's first K)")
    parser.add_argument("--only", nargs="+", metavar="NAME", help="object names or prefixes")
    parser.add_argument("--option", nargs="+", default=[], metavar="NAME=VALUE", help="planner options")
    parser.add_argument("--pose", type=int, default=None, metavar="SEED", help="turn and move every object (a seed >= 0)")
    parser.add_argument("--jobs", type=positive(int), default=1, help="worker processes")
    parser.add_argument("--out", type=Path, help="write every attempt here (JSON lines)")
    args = parser.parse_args(argv)
    if args.pose is not None and args.pose < 0:
        parser.error(f"--pose must be a seed >= 0, got {args.pose}")
    if args.out is not None and args.out.is_dir():  # refused before the run, not after it
        parser.error(f"--out names the file the attempts are written to; {args.out} is a folder: "
                     f"give a file in it, e.g. {args.out / 'attempts.jsonl'}")
    try:
        options = planner_options(args.option)
        check_options(options)  # a bad option fails here, before any work
        names = [e.name for e in select(args.split, args.only)]
    except (TypeError, ValueError) as exc:
        parser.error(str(exc))
    start = time.perf_counter()
    with ProcessPoolExecutor(args.jobs) as pool:
        results = list(pool.map(run_object, names, *zip(*[(args.grasp, args.starts, options, args.pose)] * len(names))))
    rows = [r for rs in results for r in rs]
    for name, rs in zip(names, results):
        print(f"{name:32s} {sum(r['verified'] for r in rs)}/{len(rs)}  ({sum(r['iterations'] for r in rs)} iterations)")
    ok = sum(r["verified"] for r in rows)
    print("outcomes: " + ", ".join(f"{k} {v}" for k, v in Counter(r["outcome"] for r in rows).most_common()))
    by_kind = Counter(r["start"] for r in rows)
    print("by start: " + ", ".join(f"{k} {sum(r['verified'] for r in rows if r['start'] == k)}/{n}" for k, n in by_kind.items()))
    posed = "" if args.pose is None else f", pose {args.pose}"
    spent = sum(r["iterations"] for r in rows)
    print(f"{args.grasp}, {args.split}{posed}, options {options or 'default'}: {ok}/{len(rows)} single attempts verified "
          f"({100.0 * ok / max(len(rows), 1):.1f}%), {spent} iterations in all, {spent / max(ok, 1):.0f} per verified "
          f"attempt, {time.perf_counter() - start:.0f} s")
    if args.out:
        args.out.parent.mkdir(parents=True, exist_ok=True)
        args.out.write_text("".join(json.dumps(r) + "\n" for r in rows))


if __name__ == "__main__":
    main()
