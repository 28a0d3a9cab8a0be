"""How many pre-grasps the executable reach needs: collision-free reaches against its budget.

Usage::

    python benchmarks/reach_budget.py [--split train|test|all] [--grasp precision|power] [--budgets 12 24 40]
                                      [--only NAME ...] [--out DIR]

Plans every object of a split of the generalisation benchmark (``benchmarks/objectset.py``), then
makes the executable reach of every accepted grasp again with each ``budget`` of pre-grasps
(`synergrasp.planner.executable_reach`; each with its approach and close, then its closing
approach), and prints, per budget, how many reaches are collision-free and the median and largest
CPU time of one reach. Rows go to
``DIR/reach_budget_<split>_<grasp>.jsonl`` (default ``bench-out/reach_budget``).
"""

from __future__ import annotations

import argparse
import json
import sys
import time
import warnings
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

import synergrasp as sg  # noqa: E402
from synergrasp.cli import output_folder, positive  # noqa: E402
from objectset import SPLITS, select  # noqa: E402
from synergrasp.planner import ObjectRefused, executable_reach  # noqa: E402


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--split", default="train", choices=SPLITS + ("all",),
                        help="split of objectset.py to plan; all: train and test")
    parser.add_argument("--grasp", default="power", choices=["precision", "power"],
                        help="grasp type to plan")
    parser.add_argument("--budgets", nargs="+", type=positive(int), default=[12, 24, 40],
                        help="budgets (pre-grasps); each accepted grasp's reach is made with each")
    parser.add_argument("--only", nargs="+", metavar="NAME", help="object names or prefixes")
    parser.add_argument("--out", type=output_folder, default="bench-out/reach_budget",
                        help="folder of the rows")
    args = parser.parse_args(argv)
    try:
        entries = select(args.split, args.only)
    except ValueError as exc:
        parser.error(str(exc))
    warnings.simplefilter("ignore")
    hand, rows = sg.SynergyHand.default(), []
    for entry in entries:
        obj = entry.make()
        try:
            result = sg.plan(obj, args.grasp, executable_reach=False)
        except ObjectRefused:  # an object the hand cannot hold
            continue
        if not result.success:
            continue
        row = dict(name=entry.name)
        for budget in args.budgets:
            start = time.process_time()
            reach = executable_reach(hand, obj, result.u, tolerance=3.0, budget=budget)  # as sg.plan makes it
            row[str(budget)] = dict(collision_free=reach.collision_free, cpu=time.process_time() - start)
        rows.append(row)
        print(f"{entry.name:32s} " + "  ".join(f"{b}: {'yes' if row[str(b)]['collision_free'] else 'no ':3s} "
                                               f"{row[str(b)]['cpu']:5.2f} s" for b in args.budgets), flush=True)
    (args.out / f"reach_budget_{args.split}_{args.grasp}.jsonl").write_text("".join(json.dumps(r) + "\n" for r in rows))
    for budget in args.budgets:
        cpu = np.array([r[str(budget)]["cpu"] for r in rows])
        free = sum(r[str(budget)]["collision_free"] for r in rows)
        print(f"budget {budget}: {free}/{len(rows)} collision-free reaches of accepted {args.grasp} grasps, "
              f"CPU per reach median {np.median(cpu):.2f} s, max {cpu.max():.2f} s")
    return rows


if __name__ == "__main__":
    main()
