"""The paper's experiments (Sec. 4): precision and power grasps of its four objects.

Plans the 8 cases with the default settings (the native LP backend), verifies each final
grasp independently on the object's true surface (``benchmarks/verification.py``: contacts
within 5 mm of it, qhull's verdict at its normals, no phalanx capsule and not the palm box
deeper than 3 mm by a dense sampled check), and writes to ``--out`` (default ``./examples-out/paper``) a table
beside the paper's own numbers (``paper_experiments.md``), the raw rows
(``paper_experiments.csv``) and the status and poses figures of every case.

With ``--docs`` it regenerates the documentation instead: the table in the
README and ``docs/paper-experiments.md`` (between their ``paper-table``
markers), the rows in ``docs/results/paper_experiments.csv`` and the figures in
``docs/figures/paper/``. ``--quick`` plans one case (the ellipsoid's precision
grasp) once, to check that the script runs.

Usage::

    python examples/paper_experiments.py [--out DIR] [--repeats 3] [--no-figures] [--quick] [--docs]
"""

from __future__ import annotations

import argparse
import csv
import sys
import time
import warnings
from pathlib import Path

import numpy as np

import synergrasp as sg
from synergrasp import viz
from synergrasp.cli import output_folder, positive, write_between_markers

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "benchmarks"))

from verification import verify  # noqa: E402

OBJECTS = ("ellipsoid", "cup", "bell", "goblet")
GRASPS = ("precision", "power")
#: The paper's results (Sec. 4): iterations, final sQ, final Q, time (s); None where not reported.
PAPER = {
    ("ellipsoid", "precision"): (176, -0.1123, -0.0792, 54),
    ("cup", "precision"): (163, -0.0798, -0.0570, 60),
    ("bell", "precision"): (165, -0.0260, -0.0260, None),
    ("goblet", "precision"): (166, -0.3315, -0.1513, None),
    ("ellipsoid", "power"): (63, -0.2209, -0.0625, 59),
    ("cup", "power"): (69, -0.4377, -0.1017, 80),
    ("bell", "power"): (169, -0.1979, -0.1386, None),
    ("goblet", "power"): (None, -0.6010, -0.2574, None),
}


def run_case(name, grasp, repeats):
    obj = sg.objects.get(name)
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        result = sg.plan(obj, grasp)
        times.append(time.perf_counter() - start)
    return obj, result, float(np.median(times))


def fmt(value, spec):
    return "-" if value is None or (isinstance(value, float) and np.isnan(value)) else format(value, spec)


def table(rows):
    head = ("| object | grasp | success | iterations (paper) | attempts, all iterations | sQ (paper) | Q (paper) | contacts "
            "| palm | penetration (mm) | time s (paper) | LP solves |\n|---|---|---|---|---|---|---|---|---|---|---|---|")
    lines = [head]
    for r in rows:
        paper = PAPER[(r["object"], r["grasp"])]
        lines.append(
            f"| {r['object']} | {r['grasp']} | {'yes' if r['verified'] else 'no'} | {r['iterations']} ({fmt(paper[0], 'd')}) "
            f"| {r['attempts']}, {r['all_iterations']} "
            f"| {r['sq']:+.4f} ({fmt(paper[1], '+.4f')}) | {fmt(r['q'], '+.4f')} ({fmt(paper[2], '+.4f')}) "
            f"| {r['n_contacts']}: {r['contacts']} | {'yes' if r['palm'] else 'no'} | {r['penetration']:.1f} "
            f"| {r['time_s']:.2f} ({fmt(paper[3], 'd')}) | {r['lp_solves']} |"
        )
    return "\n".join(lines)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--out", type=output_folder, default="examples-out/paper", help="output folder (default ./examples-out/paper)")
    parser.add_argument("--repeats", type=positive(int), default=3, help="plans per case for the median time (default 3)")
    parser.add_argument("--no-figures", action="store_true", help="skip the figures")
    parser.add_argument("--quick", action="store_true", help="one case (ellipsoid, precision), planned once")
    parser.add_argument("--docs", action="store_true",
                        help="write the README's and docs' tables, docs/results/ and docs/figures/paper/ instead of --out")
    args = parser.parse_args(argv)
    if args.docs and args.quick:
        parser.error("--docs needs the full run: drop --quick")
    warnings.simplefilter("ignore")
    hand = sg.SynergyHand.default()
    out = args.out
    figures, results = (ROOT / "docs" / "figures" / "paper", ROOT / "docs" / "results") if args.docs else (out, out)
    for folder in (figures, results):
        folder.mkdir(parents=True, exist_ok=True)
    cases = [("ellipsoid", "precision")] if args.quick else [(name, grasp) for grasp in GRASPS for name in OBJECTS]
    repeats = 1 if args.quick else args.repeats
    rows = []
    for name, grasp in cases:
        obj, result, median_time = run_case(name, grasp, repeats)
        row = {
            "object": name,
            "grasp": grasp,
            "success": result.success,
            "verified": verify(result, obj)["verified"],
            "iterations": result.iterations,
            "all_iterations": result.total_iterations,
            "attempts": len(result.attempts),
            "sq": result.final_sq,
            "q": result.final_q,
            "n_contacts": len(result.contact_labels),
            "contacts": " ".join(result.contact_labels),
            "palm": "P" in result.contact_labels,
            "penetration": result.penetration,
            "time_s": median_time,
            "lp_solves": result.lp_solves,
            "reason": result.reason,
        }
        rows.append(row)
        print(f"{name:9s} {grasp:9s} {'ok ' if row['verified'] else 'NO '} {result.iterations:4d} it "
              f"Q {row['q']:+.4f} {median_time:6.2f} s  {result.reason}", flush=True)
        if not args.no_figures:
            viz.plot_status(result, figures / f"{name}_{grasp}_status.png")
            viz.plot_poses(result, obj, hand, figures / f"{name}_{grasp}_poses.png")
    with open(results / "paper_experiments.csv", "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    text = table(rows)
    if args.docs:
        for path in (ROOT / "README.md", ROOT / "docs" / "paper-experiments.md"):
            write_between_markers(path, "<!-- paper-table:start -->", "<!-- paper-table:end -->", text)
    else:
        (out / "paper_experiments.md").write_text(text + "\n")
    print(text)
    print(f"wrote {results / 'paper_experiments.csv'}" + ("" if args.no_figures else f" and the figures in {figures}"))


if __name__ == "__main__":
    main()
