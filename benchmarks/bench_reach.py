"""The executable reach on the paper's eight cases: how deep the hand goes, what it costs, and a MuJoCo replay.

Usage::

    python benchmarks/bench_reach.py [--repeats 3] [--out DIR] [--quick] [--docs]

For each case (a precision and a power grasp of the ellipsoid, cup, bell
and goblet, planned with the defaults, native LP backend included):

- **depth along the returned reach** (`PlanResult.path`): the library's
  fcl clearance (capsules and palm box against the convex pieces), and the
  independent check of ``reach_sampling.py`` (points on the capsule axes and
  the palm box's faces against the true mesh with trimesh): the deepest
  point, capsules and palm apart. The figure to reach: <= 3 mm in every
  case. Where the final grasp itself is deeper, its own depth is given
  beside it (the path cannot end shallower).
- **depth along the iteration** (`PlanResult.trajectory`, each iteration's
  pose), independently, for comparison: what the planner returned as its
  reach before.
- **time**: CPU time of whole plans with and without the repair
  (``executable_reach=False``), interleaved in the same run, ``--repeats``
  each; the overhead is the median over the cases of each case's ratio of
  medians. Also the repair's own CPU time inside the plan
  (``PlanResult.reach["cpu_time"]``) over the rest of the plan. Target:
  <= 20 %.
- **replay**: the path run in MuJoCo with the object free
  (`synergrasp.replay_reach`): how far the object moved before the hand had
  closed, and after the squeeze.

Prints a table; writes ``reach.csv`` under ``--out`` (default
``bench-out/reach``). ``--docs`` also writes ``docs/results/reach.csv``,
the table into ``docs/executable-reach.md`` (between its ``reach-table``
markers) and the summary into ``README.md`` (between its ``reach`` markers). ``--quick`` (used by the tests): the cup's two cases, one repeat,
no trajectory check.
"""

from __future__ import annotations

import argparse
import csv
import os
import time
import warnings
from pathlib import Path

import numpy as np
from reach_sampling import sampled_clearance

import synergrasp as sg
from synergrasp.cli import output_folder, positive, write_between_markers

ROOT = Path(__file__).resolve().parents[1]
PAGE = ROOT / "docs" / "executable-reach.md"
TOLERANCE = 3.0  # mm, the target depth along the reach
TARGET = 0.20  # plan time overhead
OBJECTS = ("ellipsoid", "cup", "bell", "goblet")
GRASPS = ("precision", "power")


def depths(hand, mesh, path):
    """Deepest penetration (mm, >= 0) of the capsules and of the palm over the poses, by the independent check."""
    values = np.array([sampled_clearance(hand, mesh, u) for u in path])
    return max(0.0, -float(values[:, :-1].min())), max(0.0, -float(values[:, -1].min()))


def timed_plan(obj, grasp, **options):
    start = time.process_time()
    result = sg.plan(obj, grasp, **options)
    return result, time.process_time() - start


def run_case(name, grasp, repeats, trajectory):
    hand, obj = sg.SynergyHand.default(), sg.objects.get(name)
    result = sg.plan(obj, grasp)  # also the warm-up (first calls, caches): not timed
    with_repair, without = [], []
    for k in range(repeats):  # interleaved, in turn first: the load of the machine falls on both alike
        for repair in ((True, False) if k % 2 == 0 else (False, True)):
            _, t = timed_plan(obj, grasp, executable_reach=repair)
            (with_repair if repair else without).append(t)
    row = dict(object=name, grasp=grasp, success=result.success, collision_free=result.collision_free,
               rows=len(result.path), cpu_with=float(np.median(with_repair)), cpu_without=float(np.median(without)))
    row["overhead"] = row["cpu_with"] / row["cpu_without"] - 1.0
    if not result.success:
        return row, result
    reach = result.reach
    row.update(depth_fcl=reach["depth"], deepest=reach["deepest"], grasp_depth_fcl=reach["grasp_depth"],
               grasp_shape=reach["grasp_shape"], repair_cpu=reach["cpu_time"],
               repair_share=reach["cpu_time"] / max(result.time_s - reach["cpu_time"], 1e-9),
               retreat=reach["retreat"], candidates=reach["candidates"])
    row["depth_capsules"], row["depth_palm"] = depths(hand, obj.mesh, result.path)
    grasp_own = sampled_clearance(hand, obj.mesh, result.u)
    row["grasp_depth"] = max(0.0, -float(grasp_own.min()))
    if trajectory:
        row["trajectory_capsules"], row["trajectory_palm"] = depths(hand, obj.mesh, result.trajectory)
    replay = sg.replay_reach(result, obj, hand=hand)
    row.update(replay=replay.outcome, moved_before_closed=replay.moved_before_closed,
               turned_before_closed=replay.turned_before_closed, moved_after_squeeze=replay.moved_after_squeeze,
               first_contact=replay.first_contact)
    return row, result


def fmt(row, key, spec=".1f"):
    value = row.get(key)
    return "-" if value is None or (isinstance(value, float) and np.isnan(value)) else format(value, spec)


def table(rows):
    lines = ["| object | grasp | collision-free | rows | deepest along the reach: fcl (shape) | independent: capsules / palm "
             "| the grasp's own depth: independent (fcl, shape) | along the iteration: capsules / palm | moved before closed (mm) "
             "| plan CPU s with / without repair | overhead |",
             "|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        deepest = max(r.get("depth_capsules", np.nan), r.get("depth_palm", np.nan))
        ok = "yes" if deepest <= TOLERANCE else ("no: the grasp itself" if r.get("grasp_depth", 0) > TOLERANCE else "no")
        lines.append(
            f"| {r['object']} | {r['grasp']} | {'yes' if r['collision_free'] else 'no'} ({ok}) | {r['rows']} "
            f"| {fmt(r, 'depth_fcl')} ({r.get('deepest') or '-'}) | {fmt(r, 'depth_capsules')} / {fmt(r, 'depth_palm')} "
            f"| {fmt(r, 'grasp_depth')} ({fmt(r, 'grasp_depth_fcl')}, {r.get('grasp_shape') or '-'}) "
            f"| {fmt(r, 'trajectory_capsules')} / {fmt(r, 'trajectory_palm')} | {fmt(r, 'moved_before_closed')} "
            f"| {r['cpu_with']:.2f} / {r['cpu_without']:.2f} | {100 * r['overhead']:+.0f} % |")
    return "\n".join(lines)


def summary(rows):
    overhead = float(np.median([r["overhead"] for r in rows]))
    share = float(np.median([r["repair_share"] for r in rows if "repair_share" in r]))
    done = [r for r in rows if "depth_capsules" in r]
    deepest = [max(r["depth_capsules"], r["depth_palm"]) for r in done]
    worst = done[int(np.argmax(deepest))]
    capsules = [r["depth_capsules"] for r in done]
    blocked = [f"{r['object']} {r['grasp']} (grasp {r['grasp_depth']:.1f} mm, path {max(r['depth_capsules'], r['depth_palm']):.1f} mm, "
               f"{r['grasp_shape']})" for r in done
               if max(r["depth_capsules"], r["depth_palm"]) > TOLERANCE and r["grasp_depth"] > TOLERANCE]
    lines = [f"deepest point along the returned reach, capsules and palm (independent check): <= {TOLERANCE:g} mm in "
             f"{sum(d <= TOLERANCE for d in deepest)} of {len(done)} cases; largest {max(deepest):.1f} mm "
             f"({worst['object']} {worst['grasp']}, {'palm' if worst['depth_palm'] > worst['depth_capsules'] else 'a capsule'})",
             f"the phalanx capsules alone: <= {TOLERANCE:g} mm in {sum(d <= TOLERANCE for d in capsules)} of {len(done)} "
             f"cases; largest {max(capsules):.1f} mm",
             f"cases whose final grasp itself is deeper than {TOLERANCE:g} mm: {len(blocked)}"
             + (f" ({'; '.join(blocked)})" if blocked else "")]
    if any("trajectory_capsules" in r for r in rows):
        traj = [r["trajectory_capsules"] for r in rows if "trajectory_capsules" in r]
        lines.append(f"along the iteration's trajectory (capsules, independent): deepest {max(traj):.1f} mm, "
                     f"median of the per-case maxima {np.median(traj):.1f} mm")
    moved = [r["moved_before_closed"] for r in rows if "moved_before_closed" in r]
    free = [r["moved_before_closed"] for r in rows if r.get("collision_free")]
    lines.append(f"MuJoCo replay, object moved before the hand closed: median {np.median(moved):.1f} mm over "
                 f"{len(moved)} cases" + (f"; collision-free reaches: largest {max(free):.1f} mm" if free else ""))
    lines.append(f"plan time overhead of the repair: median {100 * overhead:+.1f} % over {len(rows)} cases "
                 f"({'within' if overhead <= TARGET else 'ABOVE'} the {100 * TARGET:.0f} % target); "
                 f"the repair's own CPU over the rest of the plan: median {100 * share:.1f} %")
    return lines


def write_csv(rows, path):
    keys = list(dict.fromkeys(k for r in rows for k in r))
    path.parent.mkdir(parents=True, exist_ok=True)
    with path.open("w", newline="") as handle:
        writer = csv.DictWriter(handle, fieldnames=keys)
        writer.writeheader()
        writer.writerows(rows)
    return path


def write_docs(rows, lines):
    write_csv(rows, ROOT / "docs" / "results" / "reach.csv")
    write_between_markers(ROOT / "README.md", "<!-- reach:start -->", "<!-- reach:end -->",
                          "\n".join(f"- {line}" for line in lines))
    load = os.getloadavg()[0]
    write_between_markers(PAGE, "<!-- reach-table -->", "<!-- /reach-table -->",
                          f"{table(rows)}\n\n" + "\n".join(f"- {line}" for line in lines)
                          + f"\n- load average of the machine during the run: {load:.1f} (2 cores)")


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--repeats", type=positive(int), default=3, help="timed plans per case, with and without (default 3)")
    parser.add_argument("--out", type=output_folder, default="bench-out/reach", help="output folder")
    parser.add_argument("--quick", action="store_true", help="the cup's two cases, one repeat, no trajectory check")
    parser.add_argument("--docs", action="store_true", help="also write docs/results/reach.csv, the docs table and the README summary")
    args = parser.parse_args(argv)
    if args.quick and args.docs:
        parser.error("--docs needs the full run (without --quick)")
    warnings.simplefilter("ignore")
    cases = [(o, g) for g in GRASPS for o in (("cup",) if args.quick else OBJECTS)]
    rows = []
    for name, grasp in cases:
        row, _ = run_case(name, grasp, 1 if args.quick else args.repeats, trajectory=not args.quick)
        rows.append(row)
        print(f"{name} {grasp}: done", flush=True)
    print(table(rows))
    lines = summary(rows)
    print("\n".join(lines))
    print(f"wrote {write_csv(rows, args.out / 'reach.csv')}")
    if args.docs:
        write_docs(rows, lines)
        print(f"wrote {PAGE}, docs/results/reach.csv and README.md")


if __name__ == "__main__":
    main()
