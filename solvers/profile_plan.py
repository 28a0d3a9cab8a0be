"""Where a plan's time goes: the LP solver's share and the time per iteration, before and after a change.

Usage::

    python -m solvers.profile_plan [--out DIR] [--docs] [--backend native] [--baseline-ref 427770f]
                                  [--repeats 3] [--rounds 2]
    python -m solvers.profile_plan --quick     # one case, one repeat, no baseline (the test suite runs it)

Plans the paper's 8 cases (ellipsoid, cup, bell, goblet x precision, power)
with the LP backend ``--backend`` (default ``native``, the library's
default), each package in its own subprocess:

* ``before``: the ``synergrasp`` package as of ``--baseline-ref`` (by default
  main as it was without the geometry layer's redesign and its compiled loops),
  with ``highs``, its default, if it has no such backend (``native``);
* ``after``: the package of this checkout.

The two are measured ``--rounds`` times, alternating (load from other
processes hits both alike), and the medians kept. For each case: the wall
time and CPU time of the plan (the repeat with the least CPU time of
``--repeats``), its iterations over all attempts, its LP solves, and the
time inside the LP solver measured two ways: an independent CPU timer
around every ``Backend.solve`` call (validation of the LP data included),
and the sum of ``LPSolution.solve_time`` (the library's own wall-clock timer
around the backend's ``_solve``); and the trajectory, compared between the
two packages. Then the medians over the 8 cases of
the time per iteration and of the solver's share, the time of one
``q_distance`` (5 contacts, value + gradients) and of one ``contact_distance``
call, and cProfile's cumulative times of the main functions in the ellipsoid
precision plan. Writes ``profile.md`` and ``profile.csv`` to ``--out``
(default ``./bench-out/profile``, with ``--quick`` ``./bench-out/profile-quick``),
or with ``--docs`` to the committed ``solvers/results``, whose ``profile.md``
``python -m solvers.compare`` includes in its results.
"""

from __future__ import annotations

import argparse
import csv
import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

from synergrasp.cli import backend, output_folder, positive

ROOT = Path(__file__).resolve().parents[1]
#: The committed results (written with --docs).
COMMITTED = ROOT / "solvers" / "results"
#: Output folder of a run without --docs (relative to the working directory).
DEFAULT_OUT = Path("bench-out") / "profile"
#: main without the geometry layer's redesign (module split, compiled loops, HiGHS models updated in
#: place): its last commit before that work was merged, the planner of issue 16 included. (The work
#: itself started from 251b907, whose planner differs.)
BASELINE_REF = "427770f"
CASES = tuple((o, g) for g in ("precision", "power") for o in ("ellipsoid", "cup", "bell", "goblet"))
QUICK_CASES = (("ellipsoid", "precision"),)

#: Functions whose cumulative time is reported: (label, file suffixes, function name or names).
FUNCTIONS = (
    ("plan (total)", ("planner/core.py",), "plan"),
    ("starts (the attempts' start configurations)", ("planner/starts.py",), "starts"),
    ("executable_reach (the path to the grasp)", ("planner/reach.py",), "executable_reach"),
    ("grasp_status (cP, sQ, g_sQ, Jacobian)", ("planner/status.py",), "grasp_status"),
    ("check_grasp (g_Q of the real contacts)", ("planner/stop.py",), "check_grasp"),
    ("group_contact_distance (the cP rows)", ("objects/proximity.py", "objects/contact_distance.py"),
     "group_contact_distance"),
    ("scaled_contacts (sQ contacts)", ("objects/proximity.py", "objects/scaled_contacts.py"), "scaled_contacts"),
    ("smoothed_normals", ("planner/status.py",), "smoothed_normals"),
    ("q_distance", ("synergrasp/quality.py",), "q_distance"),
    ("Backend.solve (LP layer)", ("lp/base.py",), "solve"),
    ("HiGHS run (solver itself)", ("~",), "<built-in method highspy._core.run>"),
    ("native kernel (solver itself)", ("lp/native.py",), "_solve_blocks"),
    ("hand points and Jacobians", ("synergrasp/hand.py",), "points_and_jacobian"),
    ("step (Eq. 16, task priority)", ("planner/step.py",), "limited_step"),
)

MEASURE = r'''
import cProfile, json, pstats, sys, time
import numpy as np
import synergrasp as sg

repeats, root, quick = int(sys.argv[1]), sys.argv[2], sys.argv[3] == "1"
sys.path.insert(0, root)
from solvers.compare import grasp_sequence, point_sequence

CASES = json.loads(sys.argv[4])
names = sys.argv[5].split(",")  # the first one this package has, else the last (get_backend says why not)
backend = next((n for n in names if n in sg.lp.available_backends()), names[-1])
base = type(sg.lp.get_backend(backend))


class Timed(base):
    """The backend with an outside CPU timer around every solve, beside the library's own (wall) solve_time."""

    def reset(self):
        self.own = self.outside = 0.0
        self.n = 0

    def solve(self, *args, **kwargs):
        start = time.process_time()
        sol = super().solve(*args, **kwargs)
        self.outside += time.process_time() - start
        self.own += sol.solve_time
        self.n += 1
        return sol


out = {"synergrasp": sg.__file__, "backend": backend, "cases": {}}
for name, grasp in CASES:
    obj = sg.objects.get(name)
    runs = []
    for i in range(repeats + 1):  # the first run warms up (imports, compiled code, caches)
        be = Timed()
        be.reset()
        start, cpu = time.perf_counter(), time.process_time()
        r = sg.plan(obj, grasp, backend=be)
        wall, cpu = time.perf_counter() - start, time.process_time() - cpu
        if i:
            runs.append((cpu, wall, be.own, be.outside, be.n))
    cpu, wall, own, outside, n = min(runs)  # the run least disturbed by other processes
    out["cases"][name + " " + grasp] = dict(
        cpu_s=cpu, wall_s=wall, iterations=int(r.total_iterations), success=bool(r.success), lp_solves=n,
        lp_time_s=own, lp_cpu_s=outside, attempts=len(r.attempts), trajectory=np.asarray(r.trajectory).tolist())
be = base()
grasps = grasp_sequence(5, 31 if quick else 301)
sg.q_distance(*grasps[0], backend=be)
t = []
for p, nrm in grasps[1:]:
    s = time.perf_counter(); sg.q_distance(p, nrm, backend=be); t.append(time.perf_counter() - s)
out["q5_ms"] = float(np.median(t) * 1e3)
obj = sg.objects.ellipsoid()
points = point_sequence(obj, 31 if quick else 301)
obj.contact_distance(points[0][None], backend=be)
t = []
for p in points[1:]:
    s = time.perf_counter(); obj.contact_distance(p[None], backend=be); t.append(time.perf_counter() - s)
out["cp_ms"] = float(np.median(t) * 1e3)
profile = cProfile.Profile()
profile.enable()
sg.plan(obj, "precision", backend=base())
profile.disable()
cum = {}
for (path, line, func), (cc, nc, tt, ct, callers) in pstats.Stats(profile).stats.items():
    key = path + "::" + func
    cum[key] = cum.get(key, [0, 0.0])
    cum[key][0] += nc
    cum[key][1] += ct
out["profile"] = cum
print(json.dumps(out))
'''


def baseline_tree(ref: str, where: Path) -> Path:
    """The ``synergrasp`` package as of commit ``ref``, unpacked under ``where``."""
    archive = subprocess.run(["git", "archive", ref, "synergrasp"], cwd=ROOT, check=True, capture_output=True).stdout
    subprocess.run(["tar", "-x", "-C", str(where)], input=archive, check=True)
    return where


def measure(tree: Path | None, repeats: int, cases, quick: bool, backends: str) -> dict:
    """One measurement in a subprocess; ``backends``: comma-separated names, the first the package has is used."""
    env = dict(os.environ)  # the package of this checkout (not an installed copy) unless a tree is given
    env["PYTHONPATH"] = str(tree if tree is not None else ROOT) + os.pathsep + env.get("PYTHONPATH", "")
    proc = subprocess.run([sys.executable, "-c", MEASURE, str(repeats), str(ROOT), "1" if quick else "0",
                           json.dumps(cases), backends],
                          cwd=tempfile.gettempdir(), env=env, capture_output=True, text=True)
    if proc.returncode:
        raise RuntimeError(f"the measurement failed:\n{proc.stderr[-3000:]}")
    return json.loads(proc.stdout.strip().splitlines()[-1])


def combine(results: list) -> dict:
    """Medians over rounds of every timing (counts and the profile from the first round)."""
    out = dict(results[0])
    for key in ("q5_ms", "cp_ms"):
        out[key] = float(np.median([r[key] for r in results]))
    out["cases"] = {case: dict(values, **{k: float(np.median([r["cases"][case][k] for r in results]))
                                          for k in ("cpu_s", "wall_s", "lp_time_s", "lp_cpu_s")})
                    for case, values in results[0]["cases"].items()}  # the trajectories are those of the first round
    return out


def per_case(result: dict) -> dict:
    """Per case: CPU ms per iteration, the solver's share (CPU, and by the library's wall-clock timer), µs per LP."""
    rows = {}
    for case, c in result["cases"].items():
        rows[case] = dict(ms_per_iteration=1e3 * c["cpu_s"] / max(c["iterations"], 1),
                          lp_share=c["lp_cpu_s"] / c["cpu_s"], lp_share_wall=c["lp_time_s"] / c["wall_s"],
                          us_per_lp=1e6 * c["lp_cpu_s"] / max(c["lp_solves"], 1))
    return rows


def summary(result: dict) -> dict:
    """Medians over the cases of the time per iteration and of the solver's share."""
    rows = per_case(result).values()
    return {key: float(np.median([r[key] for r in rows])) for key in ("ms_per_iteration", "lp_share", "lp_share_wall")}


def trajectory_change(before: dict, after: dict, case: str) -> float:
    """Largest |u_after - u_before| over the common length of the returned trajectories (mm, rad)."""
    a, b = np.asarray(after["cases"][case]["trajectory"]), np.asarray(before["cases"][case]["trajectory"])
    n = min(len(a), len(b))
    return float(np.abs(a[:n] - b[:n]).max()) if n else float("nan")


def cumulative(result: dict, suffixes, name):
    calls, total = 0, 0.0
    names = (name,) if isinstance(name, str) else name
    for key, (n, t) in result["profile"].items():
        path, func = key.split("::", 1)
        if func in names and any(s == "~" or path.endswith(s) for s in suffixes):
            calls += n
            total += t
    return calls, total


def report(before: dict | None, after: dict, ref: str) -> tuple[str, list]:
    """The markdown section and CSV rows (``before`` None: the current package only)."""
    sa = summary(after)
    sb = summary(before) if before else None
    fmt = lambda v, spec: "-" if v is None else format(v, spec)  # noqa: E731

    def row(label, b, a, spec, ratio=True):
        speed = f"{b / a:.2f}x" if ratio and b and a else "-"
        return [label, fmt(b, spec), fmt(a, spec), speed]

    rows = [
        row("CPU time per iteration, median over the cases (ms)", sb and sb["ms_per_iteration"], sa["ms_per_iteration"], ".3g"),
        row("share of the plan's CPU time inside Backend.solve, median", sb and sb["lp_share"], sa["lp_share"], ".0%", False),
        row("share of its wall time in the backends' solve_time, median", sb and sb["lp_share_wall"], sa["lp_share_wall"],
            ".0%", False),
        row("q_distance, 5 contacts, value + gradients (ms)", before and before["q5_ms"], after["q5_ms"], ".3g"),
        row("contact_distance, one point (ms)", before and before["cp_ms"], after["cp_ms"], ".3g"),
    ]
    cases = list(after["cases"])
    ba, bb = after["backend"], before and before["backend"]
    lines = [
        "### Profile: where a plan's time goes",
        "",
        f"`python -m solvers.profile_plan --docs`: the paper's {len(cases)} cases planned, *before* = the "
        f"`synergrasp` package as of commit `{ref}` with the `{bb}` LP backend"
        f"{f' (its default; it has no `{ba}`)' if bb != ba else ''}, *after* = now with `{ba}`, "
        "each in its own process, alternating; "
        "per case the repeat with the least CPU time, then the median over the rounds. The solver's share is "
        "measured two ways: CPU time inside every `Backend.solve` call over the plan's CPU time (an outside "
        "timer), and the sum of the backend's own wall-clock timer (`LPSolution.solve_time`, around its "
        "`_solve`) over the plan's wall time." if before else
        f"`python -m solvers.profile_plan`: {len(cases)} case(s) planned with the `{ba}` LP backend (no baseline).",
        "",
        "| measure | before | after | speed-up |",
        "|---|---|---|---|",
    ] + ["| " + " | ".join(r) + " |" for r in rows]
    csv_rows = [dict(measure=r[0], before=r[1], after=r[2], speedup=r[3]) for r in rows]
    used = f"`{bb}` before, `{ba}` after" if before and bb != ba else f"`{ba}`"
    lines += ["", f"Per case ({used}; iterations over all attempts):", "",
              "| plan | iterations before / after | LP solves before / after | CPU s before / after | ms per iteration "
              "before / after | LP share (CPU) before / after | µs per LP before / after | success, attempts before / after | "
              "max abs du |",
              "|---|---|---|---|---|---|---|---|---|"]
    pa, pb = per_case(after), per_case(before) if before else {}
    for case in cases:
        a, ca = pa[case], after["cases"][case]
        b, cb = pb.get(case), (before["cases"].get(case) if before else None)
        pair = lambda x, y, spec: f"{fmt(x, spec)} / {fmt(y, spec)}"  # noqa: E731
        lines.append(
            f"| {case} | {pair(cb and cb['iterations'], ca['iterations'], 'd')} | "
            f"{pair(cb and cb['lp_solves'], ca['lp_solves'], 'd')} | {pair(cb and cb['cpu_s'], ca['cpu_s'], '.3g')} | "
            f"{pair(b and b['ms_per_iteration'], a['ms_per_iteration'], '.3g')} | {pair(b and b['lp_share'], a['lp_share'], '.0%')} | "
            f"{pair(b and b['us_per_lp'], a['us_per_lp'], '.0f')} | "
            f"{'-' if cb is None else ('yes' if cb['success'] else 'no') + ', ' + str(cb['attempts'])} / "
            f"{'yes' if ca['success'] else 'no'}, {ca['attempts']} | "
            f"{'-' if cb is None else format(trajectory_change(before, after, case), '.2g')} |")
        csv_rows.append(dict(measure=f"{case} ms per iteration", before=fmt(b and b["ms_per_iteration"], ".4g"),
                             after=f"{a['ms_per_iteration']:.4g}", speedup=""))
        csv_rows.append(dict(measure=f"{case} LP share", before=fmt(b and b["lp_share"], ".3f"),
                             after=f"{a['lp_share']:.3f}", speedup=""))
    if before:
        lines += ["", "max abs du: the largest difference of the returned trajectories (u: mm and rad) over their "
                  "common length; round-off in the LP data and in the compiled loops' order of operations, where "
                  "the iterations and attempts are the same"
                  + (f" (and the two backends' own solutions: `{bb}` and `{ba}` may return different optimal "
                     "vertices and duals)." if bb != ba else ".")]
    lines += ["", "Cumulative time of the main functions in one profiled ellipsoid precision plan (cProfile inflates "
              "every time; the shares are what matter):", "",
              "| function | calls (after) | before s | after s | share of the plan (after) |", "|---|---|---|---|---|"]
    total_after = cumulative(after, ("planner/core.py",), "plan")[1] or 1.0
    for label, suffixes, name in FUNCTIONS:
        nb, tb = cumulative(before, suffixes, name) if before else (0, None)
        na, ta = cumulative(after, suffixes, name)
        lines.append(f"| {label} | {na} | {fmt(tb, '.3f')} | {ta:.3f} | {ta / total_after:.0%} |")
    return "\n".join(lines) + "\n", csv_rows


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--out", type=output_folder, default=None,
                        help=f"output folder (default ./{DEFAULT_OUT}, with --quick ./{DEFAULT_OUT}-quick)")
    parser.add_argument("--docs", action="store_true", help="write the committed results in solvers/results")
    parser.add_argument("--backend", type=backend, default="native",
                        help="LP backend (default native, the library's; the baseline without it uses highs)")
    parser.add_argument("--baseline-ref", default=BASELINE_REF)
    parser.add_argument("--repeats", type=positive(int), default=3, help="timed plans per case and round")
    parser.add_argument("--rounds", type=positive(int), default=2, help="before/after measurement rounds, alternating")
    parser.add_argument("--quick", action="store_true", help="one case, one repeat, one round, no baseline")
    args = parser.parse_args(argv)
    quick_out = DEFAULT_OUT.with_name(DEFAULT_OUT.name + "-quick")
    out = args.out if args.out is not None else COMMITTED if args.docs else quick_out if args.quick else DEFAULT_OUT
    cases = [list(c) for c in (QUICK_CASES if args.quick else CASES)]
    repeats, rounds = (1, 1) if args.quick else (args.repeats, args.rounds)
    befores, afters = [], []
    with tempfile.TemporaryDirectory() as tmp:
        tree = None if args.quick else baseline_tree(args.baseline_ref, Path(tmp))
        for i in range(rounds):  # alternate, so that load from other processes hits both alike
            pair = [(befores, tree, f"{args.backend},highs"), (afters, None, args.backend)]
            pair = pair if tree is not None else pair[1:]
            for results, where, backends in pair if i % 2 == 0 else pair[::-1]:
                results.append(measure(where, repeats, cases, args.quick, backends))
    before, after = (combine(befores) if befores else None), combine(afters)
    text, rows = report(before, after, args.baseline_ref)
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
