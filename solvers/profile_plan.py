"""Where a plan's time goes, and what the overhead work around the LP solver changed.

Usage::

    python -m solvers.profile_plan [--out DIR] [--docs] [--baseline-ref e9c86e9] [--repeats 5]

Profiles ``sg.plan(sg.objects.ellipsoid(), "precision")`` on HiGHS twice, each in
its own subprocess:

* ``before``: the current package with the files of the overhead work (the LP
  layer ``synergrasp/lp/*.py``, ``pseudo_distance.py``, ``quality.py``, the
  geometry around the LPs ``objects/proximity.py``, ``objects/grasp_object.py``,
  ``planner/status.py`` and the hand kinematics ``hand.py``) taken from
  ``--baseline-ref`` (the commit before that work), everything else (the
  planner's loop and step, the objects' loading) as it is now, so that only
  those files differ;
* ``after``: the current package.

Both are measured ``--rounds`` times, alternating, and the medians kept. For
each: the median wall time of the plan over ``--repeats`` runs, its
iterations and LP solves, the time inside the LP solver (sum of
``LPSolution.solve_time``), the median time of one ``q_distance`` (5 contacts,
value + gradients) and of one ``contact_distance`` call, and the cumulative
times of the main functions under cProfile. Writes ``profile.md`` and
``profile.csv`` to ``--out`` (default ``./bench-out/profile``), or with
``--docs`` to the committed ``solvers/results``, whose ``profile.md``
``python -m solvers.compare`` includes in its results.
"""

from __future__ import annotations

import argparse
import csv
import json
import os
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
#: The committed results (written with --docs).
COMMITTED = ROOT / "solvers" / "results"
#: Output folder of a run without --docs (relative to the working directory).
DEFAULT_OUT = Path("bench-out") / "profile"
#: The commit before the overhead work on the Q distance and the geometry around the LPs. (The earlier
#: work on the LP layer started from 079b621, whose files no longer fit the rest of the package.)
BASELINE_REF = "e9c86e9"
#: The files the overhead work may change (relative to the repository root).
TOUCHED = ("synergrasp/lp/__init__.py", "synergrasp/lp/base.py", "synergrasp/lp/highs.py",
           "synergrasp/lp/clarabel.py", "synergrasp/lp/cvxpy.py", "synergrasp/pseudo_distance.py",
           "synergrasp/quality.py", "synergrasp/objects/proximity.py", "synergrasp/objects/grasp_object.py",
           "synergrasp/planner/status.py", "synergrasp/hand.py")

#: Functions whose cumulative time is reported: (label, file suffix, function name or names).
FUNCTIONS = (
    ("plan (total)", "planner/core.py", "plan"),
    ("grasp_status (cP, sQ, g_sQ, Jacobian)", "planner/status.py", "grasp_status"),
    ("check_grasp (g_Q of the real contacts)", "planner/stop.py", "check_grasp"),
    ("contact_distance (cP)", "objects/proximity.py", "contact_distance"),
    ("scaled_contacts (sQ contacts)", "objects/proximity.py", "scaled_contacts"),
    ("smoothed_normals", "planner/status.py", "smoothed_normals"),
    ("q_distance", "synergrasp/quality.py", "q_distance"),
    ("pseudo_distance (its LP optimum)", "synergrasp/pseudo_distance.py", ("pseudo_distance", "_pseudo_distance")),
    ("Backend.solve (LP layer)", "lp/base.py", "solve"),
    ("HiGHS run (solver itself)", "~", "<built-in method highspy._core.run>"),
    ("hand points and Jacobians", "synergrasp/hand.py", "points_and_jacobian"),
    ("step (Eq. 16, task priority)", "planner/step.py", "limited_step"),
)

MEASURE = r'''
CASES = (("ellipsoid", "precision"), ("ellipsoid", "power"), ("cup", "precision"))
import cProfile, json, pstats, sys, time
import numpy as np
import synergrasp as sg
sys.path.insert(0, sys.argv[2])
from solvers.references import TimedBackend
from solvers.compare import grasp_sequence, point_sequence
from synergrasp.lp.highs import HighsBackend

repeats = int(sys.argv[1])
obj = sg.objects.ellipsoid()
out = {"synergrasp": sg.__file__, "cases": {}}
for name, grasp in CASES:
    target = obj if name == "ellipsoid" else sg.objects.get(name)
    walls = []
    for i in range(repeats + 1):
        be = TimedBackend(HighsBackend())
        start = time.perf_counter()
        r = sg.plan(target, grasp, backend=be)
        wall = time.perf_counter() - start
        if i:
            walls.append(wall)
    out["cases"][name + " " + grasp] = dict(
        wall_s=float(np.median(walls)), iterations=int(getattr(r, "total_iterations", r.iterations)),
        success=bool(r.success), lp_solves=be.lp_calls, lp_time_s=be.lp_time)
out.update(out["cases"]["ellipsoid precision"])
be = HighsBackend()
grasps = grasp_sequence(5, 301)
sg.q_distance(*grasps[0], backend=be)
t = []
for p, n in grasps[1:]:
    s = time.perf_counter(); sg.q_distance(p, n, backend=be); t.append(time.perf_counter() - s)
out["q5_ms"] = float(np.median(t) * 1e3)
points = point_sequence(obj, 301)
obj.contact_distance(points[0][None], backend=be)
t = []
for p in points[1:]:
    s = time.perf_counter(); obj.contact_distance(p[None], backend=be); t.append(time.perf_counter() - s)
out["cp_ms"] = float(np.median(t) * 1e3)
profile = cProfile.Profile()
profile.enable()
sg.plan(obj, "precision", backend=HighsBackend())
profile.disable()
stats = pstats.Stats(profile).stats
cum = {}
for (path, line, name), (cc, nc, tt, ct, callers) in stats.items():
    key = path + "::" + name
    cum[key] = cum.get(key, [0, 0.0])
    cum[key][0] += nc
    cum[key][1] += ct
out["profile"] = cum
out["profile_total_s"] = sum(v[2] for v in stats.values())
print(json.dumps(out))
'''


def baseline_tree(ref: str, where: Path) -> Path:
    """A copy of the current package with the TOUCHED files as they were at ``ref``."""
    shutil.copytree(ROOT / "synergrasp", where / "synergrasp", ignore=shutil.ignore_patterns("__pycache__"))
    for rel in TOUCHED:
        try:
            text = subprocess.run(["git", "show", f"{ref}:{rel}"], cwd=ROOT, check=True, capture_output=True, text=True).stdout
        except subprocess.CalledProcessError:
            continue  # the file did not exist at ref: keep the current one
        (where / rel).write_text(text)
    return where


def measure(tree: Path | None, repeats: int) -> dict:
    env = dict(os.environ)  # the package of this checkout (not an installed copy) unless a tree is given
    env["PYTHONPATH"] = str(tree if tree is not None else ROOT) + os.pathsep + env.get("PYTHONPATH", "")
    proc = subprocess.run([sys.executable, "-c", MEASURE, str(repeats), str(ROOT)], cwd=tempfile.gettempdir(),
                          env=env, capture_output=True, text=True, check=True)
    return json.loads(proc.stdout.strip().splitlines()[-1])


def combine(results: list) -> dict:
    """Medians over rounds of every timing (counts and the profile from the first round)."""
    out = dict(results[0])
    for key in ("wall_s", "lp_time_s", "q5_ms", "cp_ms"):
        out[key] = float(np.median([r[key] for r in results]))
    out["cases"] = {case: dict(values, wall_s=float(np.median([r["cases"][case]["wall_s"] for r in results])),
                               lp_time_s=float(np.median([r["cases"][case]["lp_time_s"] for r in results])))
                    for case, values in results[0]["cases"].items()}
    return out


def cumulative(result: dict, suffix: str, name: str):
    calls, total = 0, 0.0
    for key, (n, t) in result["profile"].items():
        path, func = key.split("::", 1)
        if func in ((name,) if isinstance(name, str) else name) and (suffix == "~" or path.endswith(suffix)):
            calls += n
            total += t
    return calls, total


def report(before: dict, after: dict, ref: str) -> tuple[str, list]:
    def row(label, key, scale=1.0, fmt="{:.3g}"):
        b, a = before[key] * scale, after[key] * scale
        return [label, fmt.format(b), fmt.format(a), f"{b / a:.2f}x" if a else "-"]

    per_iter = lambda r: 1e3 * r["wall_s"] / max(r["iterations"], 1)
    before["ms_per_iteration"], after["ms_per_iteration"] = per_iter(before), per_iter(after)
    before["lp_share"] = before["lp_time_s"] / before["wall_s"]
    after["lp_share"] = after["lp_time_s"] / after["wall_s"]
    before["ms_per_lp"] = 1e3 * before["lp_time_s"] / before["lp_solves"]
    after["ms_per_lp"] = 1e3 * after["lp_time_s"] / after["lp_solves"]
    rows = [
        row("plan wall time, median (s)", "wall_s"),
        ["iterations", str(before["iterations"]), str(after["iterations"]), "-"],
        ["LP solves", str(before["lp_solves"]), str(after["lp_solves"]), "-"],
        row("time inside the LP solver (s)", "lp_time_s"),
        row("LP solver time per LP (ms)", "ms_per_lp"),
        ["share of the plan inside the LP solver", f"{before['lp_share']:.0%}", f"{after['lp_share']:.0%}", "-"],
        row("time per iteration (ms)", "ms_per_iteration"),
        row("q_distance, 5 contacts, value + gradients (ms)", "q5_ms"),
        row("contact_distance, one point (ms)", "cp_ms"),
    ]
    lines = [
        "### Profile: where a plan's time goes",
        "",
        "`python -m solvers.profile_plan`: `sg.plan(sg.objects.ellipsoid(), \"precision\")` on HiGHS. *Before* = "
        f"the LP layer, `pseudo_distance.py`, `quality.py`, the cP/sQ geometry (`objects/proximity.py`, "
        f"`objects/grasp_object.py`), `planner/status.py` and `hand.py` as of commit `{ref}`, *after* = now; "
        "the rest of the planner and of the objects is the current one in both, so only the overhead work differs.",
        "",
        "| measure | before | after | speed-up |",
        "|---|---|---|---|",
    ] + ["| " + " | ".join(r) + " |" for r in rows]
    csv_rows = [dict(measure=r[0], before=r[1], after=r[2], speedup=r[3]) for r in rows]
    lines += [
        "",
        "Other plans (HiGHS, median wall time; iterations over all attempts):",
        "",
        "| plan | before s | after s | speed-up | iterations | LP solves | LP solver s before / after |",
        "|---|---|---|---|---|---|---|",
    ]
    for case, a in after["cases"].items():
        b = before["cases"].get(case)
        if b is None:
            continue
        lines.append(f"| {case} | {b['wall_s']:.3g} | {a['wall_s']:.3g} | {b['wall_s'] / a['wall_s']:.2f}x | "
                     f"{b['iterations']} / {a['iterations']} | {b['lp_solves']} / {a['lp_solves']} | "
                     f"{b['lp_time_s']:.3g} / {a['lp_time_s']:.3g} |")
        csv_rows.append(dict(measure=f"plan {case} wall s", before=f"{b['wall_s']:.4g}", after=f"{a['wall_s']:.4g}",
                             speedup=f"{b['wall_s'] / a['wall_s']:.2f}x"))
    lines += [
        "",
        "Cumulative time of the main functions in one profiled plan (cProfile inflates every time, "
        "the shares are what matter):",
        "",
        "| function | calls | before s | after s | share of the plan (after) |",
        "|---|---|---|---|---|",
    ]
    total_after = cumulative(after, "planner/core.py", "plan")[1] or 1.0
    for label, suffix, name in FUNCTIONS:
        nb, tb = cumulative(before, suffix, name)
        na, ta = cumulative(after, suffix, name)
        lines.append(f"| {label} | {na} | {tb:.3f} | {ta:.3f} | {ta / total_after:.0%} |")
        csv_rows.append(dict(measure=f"cProfile cumulative: {label}", before=f"{tb:.4f}", after=f"{ta:.4f}", speedup=""))
    lines += [
        "",
        "What changed (earlier, from commit `079b621`, in the LP layer and `pseudo_distance.py`, already in "
        "*before*): HiGHS starts from the last optimal basis of an LP with the same structure (shape and "
        "sparsity pattern), else of the same shape; `pseudo_distance` builds its LPs from per-shape cached "
        "index arrays; the LP layer checks for NaN/inf with one sum; Clarabel's `[A; -I]` is assembled "
        "directly in compressed-column form. Since *before*: `q_distance` works on the pseudo-distance "
        "optimum itself (no derived arrays), sums its gradients over the cone edges through the rank-one "
        "structure of the duals and computes every cross product with one `einsum` (shared with the hand "
        "kinematics); an sQ ray that leaves one piece through the inside of one facet is settled in closed "
        "form (exit point, barycentric weights, the facet's plane as the dual; the LP only at ties), its "
        "exit facets taken from the ray exits already computed; cP computes the facet plane values once "
        "for the broad phase and the facet pruning and tests the gauge ball only on facets that face the "
        "point and are in reach; the smoothed normals weight the facet normals and their outer products "
        "in one matrix product. The LP solver's own time per solve is unchanged (fewer solves: no sQ LP "
        "away from ties); what remains outside it is the status assembly, the cP geometry and the planner "
        "(see the cumulative table).",
    ]
    return "\n".join(lines) + "\n", csv_rows


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--out", type=Path, default=None, help=f"output folder (default ./{DEFAULT_OUT})")
    parser.add_argument("--docs", action="store_true", help="write the committed results in solvers/results")
    parser.add_argument("--baseline-ref", default=BASELINE_REF)
    parser.add_argument("--repeats", type=int, default=3, help="timed plans per case and round")
    parser.add_argument("--rounds", type=int, default=2, help="before/after measurement rounds, alternating")
    args = parser.parse_args(argv)
    befores, afters = [], []
    with tempfile.TemporaryDirectory() as tmp:
        tree = baseline_tree(args.baseline_ref, Path(tmp))
        for i in range(args.rounds):  # alternate, so that load from other processes hits both alike
            pair = [(befores, tree), (afters, None)]
            for results, where in pair if i % 2 == 0 else pair[::-1]:
                results.append(measure(where, args.repeats))
        assert all(b["synergrasp"].startswith(tmp) for b in befores), befores[0]["synergrasp"]
    assert all(a["synergrasp"].startswith(str(ROOT)) for a in afters), afters[0]["synergrasp"]
    before, after = combine(befores), combine(afters)
    text, rows = report(before, after, args.baseline_ref)
    out = args.out if args.out is not None else COMMITTED if args.docs else DEFAULT_OUT
    out.mkdir(parents=True, exist_ok=True)
    (out / "profile.md").write_text(text)
    with open(out / "profile.csv", "w", newline="") as fh:
        writer = csv.DictWriter(fh, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    print(text)
    return before, after


if __name__ == "__main__":
    main(sys.argv[1:])
