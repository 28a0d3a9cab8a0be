"""The gradient planner and the annealing baseline side by side, on the same hand, objects and verification.

Usage::

    python benchmarks/compare_planners.py [--subset N] [--only NAME ...] [--grasp precision power]
                                          [--no-physics] [--out DIR] [--docs] [--resume] [--quick]

Plans every case with ``sg.plan(obj, grasp, method="gradient")`` and ``method="annealing"`` (each with
its default options but without the executable reach, made after either search; one after the other
in one process) on the paper's 8 cases (its four objects,
precision and power) and on the test split of the generalisation benchmark
(``benchmarks/objectset.py``, both grasp types). Each grasp is verified independently on the object's
true surface (``benchmarks/verification.py``) and, unless ``--no-physics``, tested in MuJoCo
(``sg.validate``, about 0.1 s a grasp). For each method it reports:

* verified (and physical) success;
* the median and p90 time of all plans (wall clock ``time_s`` and CPU time of the search), and the
  median time to a verified grasp;
* evaluations: status evaluations of the gradient planner (one per iteration and attempt start),
  energy evaluations of the annealing;
* Q of the verified grasps on the true surface;
* the smoothness of the search trajectory (`smoothness`): palm path length, total rotation, and
  the sum of squared second differences of the normalised u.

The ratios of the gradient planner's median time to a verified grasp and of its success rate to
the annealing planner's test the paper's claim (>= 10 times faster at an equal or better success
rate). Rows go to ``DIR/rows.jsonl`` and the figure of both reaches of one object to
``DIR/planner-comparison.png`` (default ``bench-out/compare_planners``); ``--docs`` writes
``docs/planner-comparison.md`` and ``docs/figures/planner-comparison.png`` instead of the figure
under ``DIR``. ``--subset N`` keeps N test objects, evenly spaced in the split's fixed order.
``--resume`` keeps the rows already written under ``DIR`` and plans the other cases only.
``--quick`` (the tests) plans the ellipsoid's precision grasp only, the annealing with seed 2 and
3000 steps without a time limit.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import time
import warnings
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

import synergrasp as sg  # noqa: E402
from synergrasp.cli import output_folder, positive  # noqa: E402
from synergrasp.planner import ObjectRefused  # noqa: E402
from verification import verify  # noqa: E402
from objectset import select  # noqa: E402

ROOT = HERE.parent
PAGE = ROOT / "docs" / "planner-comparison.md"
FIGURE = ROOT / "docs" / "figures" / "planner-comparison.png"
METHODS = ("gradient", "annealing")
PAPER_OBJECTS = ("ellipsoid", "cup", "bell", "goblet")
#: The annealing options of the quick mode (deterministic on any machine).
QUICK_ANNEALING = {"seed": 2, "steps": 3000, "time_limit": None}
#: Options of both methods: the searches are compared, not the executable reach made after either.
SEARCH_ONLY = {"executable_reach": False}
#: The paper's claim: the gradient planner is at least this many times faster.
CLAIM = 10.0


def smoothness(trajectory, size):
    """Smoothness of a search trajectory.

    Parameters
    ----------
    trajectory : (k+1, 6 + n_syn) float
        Configurations ``[p, phi (XYZ Euler), z]``.
    size : float
        The object's size (mm): positions are divided by it in the normalised u.

    Returns
    -------
    dict
        ``path_mm``: palm path length; ``rotation_rad``: the sum of the rotation angles between
        consecutive palm orientations; ``jerk``: the sum of squared second differences of the
        normalised u (positions / size, angles unwrapped, synergies).
    """
    traj = np.asarray(trajectory, dtype=float)
    path = float(np.linalg.norm(np.diff(traj[:, :3], axis=0), axis=1).sum())
    R = np.array([sg.hand.rotation_xyz(phi) for phi in traj[:, 3:6]])
    cos = (np.einsum("kij,kij->k", R[:-1], R[1:]) - 1.0) / 2.0  # trace(R_i^T R_j) = sum of the elementwise product
    rotation = float(np.arccos(np.clip(cos, -1.0, 1.0)).sum())
    x = np.c_[traj[:, :3] / size, np.unwrap(traj[:, 3:6], axis=0), traj[:, 6:]]
    jerk = float(np.sum(np.diff(x, 2, axis=0) ** 2)) if len(x) > 2 else 0.0
    return {"path_mm": path, "rotation_rad": rotation, "jerk": jerk}


def cases(quick=False, subset=None, only=None):
    """The cases: (name, group, object factory), the paper's four objects first."""
    if quick:
        return [("paper/ellipsoid", "paper", lambda: sg.objects.get("ellipsoid"))]
    out = [(f"paper/{n}", "paper", lambda n=n: sg.objects.get(n)) for n in PAPER_OBJECTS]
    entries = select("test")
    if subset is not None and subset < len(entries):
        entries = [entries[int(i)] for i in np.linspace(0, len(entries) - 1, subset).round()]
    out += [(e.name, "test", e.make) for e in entries]
    if only:
        out = [c for c in out if any(c[0] == o or c[0].startswith(o) for o in only)]
    return out


def run(name, group, obj, grasp, method, options, physics):
    """Plan one case with one method, verify it: a JSON-able row (and the result)."""
    cpu = time.process_time()
    try:
        result = sg.plan(obj, grasp, method=method, **options)
    except ObjectRefused as exc:  # the planner refuses the object (too large, too thin...)
        return dict(name=name, group=group, grasp=grasp, method=method, refused=True, reason=str(exc),
                    success=False, verified=False, held=None), None
    cpu = time.process_time() - cpu
    record = result.attempts[0] if result.attempts else {}
    steps = record.get("steps", result.total_iterations)
    if method == "annealing":
        evaluations, cpu = record["evaluations"], record["cpu_s"]  # the search only: not the status history
    else:
        evaluations = sum(a["iterations"] + 1 for a in result.attempts)
    row = dict(name=name, group=group, grasp=grasp, method=method, refused=False, success=result.success,
               reason=result.reason, time=result.time_s, cpu=cpu, evaluations=int(evaluations), steps=int(steps),
               autograsps=record.get("autograsps"),
               iterations=result.iterations, attempts=len(result.attempts), lp_solves=result.lp_solves,
               surface_q=result.surface_q, held=None, load=float(_loadavg()[0]),
               **smoothness(result.trajectory, obj.torque_scale))
    row.update(verify(result, obj))
    if physics and row["verified"]:
        try:
            verdict = sg.validate(result, obj)
            row["held"], row["physics"] = bool(verdict.held), verdict.reason
        except ValueError as exc:  # the validation refuses the grasp (no hand point within its contact distance)
            row["held"], row["physics"] = False, f"refused: {exc}"
    return row, result


def _median(values):
    values = [v for v in values if v is not None and np.isfinite(v)]
    return float(np.median(values)) if values else float("nan")


def _p90(values):
    values = [v for v in values if v is not None and np.isfinite(v)]
    return float(np.percentile(values, 90)) if values else float("nan")


def summary(rows, physics=True):
    """Per method (and group): the figures of the comparison, as a dict of dicts."""
    out = {}
    for key in ["all", *sorted({r["group"] for r in rows})]:
        for method in METHODS:
            mine = [r for r in rows if r["method"] == method and (key == "all" or r["group"] == key)]
            if not mine:
                continue
            done = [r for r in mine if not r["refused"]]
            ok = [r for r in done if r["verified"]]
            out[(key, method)] = dict(
                plans=len(mine),
                verified=len(ok),
                rate=len(ok) / len(mine),
                held=sum(bool(r["held"]) for r in ok) if physics else None,
                time_median=_median([r["time"] for r in done]),
                time_p90=_p90([r["time"] for r in done]),
                cpu_median=_median([r["cpu"] for r in done]),
                cpu_p90=_p90([r["cpu"] for r in done]),
                time_to_grasp=_median([r["time"] for r in ok]),
                cpu_to_grasp=_median([r["cpu"] for r in ok]),
                evaluations=_median([r["evaluations"] for r in done]),
                steps=_median([r["steps"] for r in done]),
                q=_median([r["q_true"] for r in ok]),
                path_mm=_median([r["path_mm"] for r in ok]),
                rotation_rad=_median([r["rotation_rad"] for r in ok]),
                jerk=_median([r["jerk"] for r in ok]),
            )
    return out


def paired(rows):
    """The cases both methods verified: how many, and the median over them of the annealing's CPU time over the gradient's."""
    by = {(r["name"], r["grasp"], r["method"]): r for r in rows}
    ratios = [by[(n, g, "annealing")]["cpu"] / by[(n, g, "gradient")]["cpu"]
              for (n, g, m), r in by.items() if m == "gradient" and r["verified"]
              and by.get((n, g, "annealing"), {}).get("verified")]
    return len(ratios), _median(ratios)


def verdict(figures, rows=()):
    """The paper's claim on all cases: ratios and whether it holds, in words."""
    g, a = figures.get(("all", "gradient")), figures.get(("all", "annealing"))
    if g is None or a is None:
        return {}, "only one method was run"
    speed = a["cpu_to_grasp"] / g["cpu_to_grasp"] if g["verified"] and a["verified"] else float("nan")
    success = g["rate"] / a["rate"] if a["rate"] > 0 else float("inf")
    holds = bool(np.isfinite(speed) and speed >= CLAIM and g["rate"] >= a["rate"])
    n_both, per_case = paired(rows)
    if a["verified"] == 0:
        text = (f"The annealing planner verified no grasp ({g['verified']}/{g['plans']} for the gradient planner): "
                "its time to a verified grasp is not defined, and the claim cannot be measured as a ratio of times; "
                "the gradient planner's success rate is the larger one.")
    else:
        text = (f"The gradient planner's median CPU time to a verified grasp is {g['cpu_to_grasp']:.2f} s against "
                f"{a['cpu_to_grasp']:.2f} s for the annealing planner ({speed:.1f} times faster), at a success rate of "
                f"{g['rate']:.1%} against {a['rate']:.1%} (ratio {success:.2f}). The paper's claim (>= {CLAIM:g} times "
                f"faster at an equal or better success rate) {'holds' if holds else 'does not hold'} here"
                + ("" if holds else " as stated: the success rate is better, the speed-up smaller than 10") + ". "
                f"On the {n_both} cases both planners grasped, the annealing took a median {per_case:.1f} times the "
                "gradient planner's CPU time. Both medians of the annealing count only the grasps it found within "
                "its 10 s limit (in the other cases it found none within 10 s): without the limit its medians could "
                "only be longer, and the ratios larger.")
    return dict(speedup=speed, success_ratio=success, holds=holds, paired_cases=n_both, paired_ratio=per_case), text


def figure(pair, path):
    """Both reaches of one object: the palm's path (3-D) and the synergies along the normalised progress."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    name, obj, results = pair
    fig = plt.figure(figsize=(11, 4.5))
    ax = fig.add_subplot(1, 2, 1, projection="3d")
    verts = np.vstack([p.vertices for p in obj.convex])
    ax.scatter(*verts[:: max(1, len(verts) // 400)].T, s=2, c="0.6")
    colors = {"gradient": "tab:blue", "annealing": "tab:orange"}
    for method, r in results.items():
        p = r.trajectory[:, :3]
        ax.plot(*p.T, color=colors[method], lw=1.0, label=f"{method} ({len(p) - 1} steps, {'grasp' if r.success else 'no grasp'})")
        ax.scatter(*p[0], color=colors[method], marker="o")
        ax.scatter(*p[-1], color=colors[method], marker="*", s=80)
    ax.set_title(f"{name}: palm position (mm), o start, * end")
    ax.legend(loc="upper left", fontsize=8)
    ax2 = fig.add_subplot(1, 2, 2)
    for method, r in results.items():
        t = np.linspace(0.0, 1.0, len(r.trajectory))
        for j, style in ((6, "-"), (7, "--")):
            ax2.plot(t, r.trajectory[:, j], style, color=colors[method], lw=1.0, label=f"{method} z{j - 5}")
    ax2.set_xlabel("fraction of the search trajectory")
    ax2.set_ylabel("synergy value")
    ax2.legend(fontsize=8)
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def _fmt(value, spec):
    return "-" if value is None or (isinstance(value, float) and not np.isfinite(value)) else format(value, spec)


def tables(figures, physics):
    """The summary and smoothness tables (markdown lines)."""
    lines = ["| cases | method | plans | verified | held in MuJoCo | time median / p90 (s) | CPU median / p90 (s) "
             "| median time to a verified grasp (s, CPU s) | evaluations (median) | steps (median) "
             "| Q on the true surface (median) |",
             "|---|---|---|---|---|---|---|---|---|---|---|"]
    for (key, method), f in figures.items():
        lines.append(f"| {key} | {method} | {f['plans']} | {f['verified']} ({f['rate']:.1%}) "
                     f"| {_fmt(f['held'], 'd') if physics else '-'} | {_fmt(f['time_median'], '.2f')} / {_fmt(f['time_p90'], '.2f')} "
                     f"| {_fmt(f['cpu_median'], '.2f')} / {_fmt(f['cpu_p90'], '.2f')} "
                     f"| {_fmt(f['time_to_grasp'], '.2f')}, {_fmt(f['cpu_to_grasp'], '.2f')} | {_fmt(f['evaluations'], '.0f')} "
                     f"| {_fmt(f['steps'], '.0f')} "
                     f"| {_fmt(f['q'], '+.3f')} |")
    smooth = ["| cases | method | palm path (mm) | total rotation (rad) | sum of squared second differences of u |",
              "|---|---|---|---|---|"]
    for (key, method), f in figures.items():
        smooth.append(f"| {key} | {method} | {_fmt(f['path_mm'], '.0f')} | {_fmt(f['rotation_rad'], '.2f')} "
                      f"| {_fmt(f['jerk'], '.3g')} |")
    return lines, smooth


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--subset", type=positive(int), help="only N test objects, evenly spaced in the split's order")
    parser.add_argument("--only", nargs="+", metavar="NAME", help="case names or prefixes (paper/, household/...)")
    parser.add_argument("--grasp", nargs="+", default=["precision", "power"], choices=["precision", "power"],
                        help="grasp types to plan (default both)")
    parser.add_argument("--no-physics", action="store_true", help="skip the MuJoCo test of the verified grasps")
    parser.add_argument("--out", type=output_folder, default="bench-out/compare_planners", help="folder of the rows")
    parser.add_argument("--docs", action="store_true", help=f"write {PAGE.relative_to(ROOT)} and its figure")
    parser.add_argument("--quick", action="store_true", help="the ellipsoid's precision grasp only (tests)")
    parser.add_argument("--resume", action="store_true",
                        help="keep the rows already in DIR/rows.jsonl and plan only the cases missing there")
    args = parser.parse_args(argv)
    if args.docs and args.quick:
        parser.error("--docs needs a real run: drop --quick")
    warnings.simplefilter("ignore")
    physics = not args.no_physics
    grasps = ["precision"] if args.quick else args.grasp
    options = {"gradient": dict(SEARCH_ONLY), "annealing": {**SEARCH_ONLY, **(QUICK_ANNEALING if args.quick else {})}}
    rows, kept = [], None
    done = {}
    if args.resume and (args.out / "rows.jsonl").exists():
        for line in (args.out / "rows.jsonl").read_text().splitlines():
            row = json.loads(line)
            done[(row["name"], row["grasp"], row["method"])] = row
    todo = cases(args.quick, args.subset, args.only)
    with open(args.out / "rows.jsonl", "w") as f:
        for name, group, make in todo:
            obj = None
            for grasp in grasps:
                results = {}
                for method in METHODS:
                    if (name, grasp, method) in done:
                        row, result = done[(name, grasp, method)], None
                    else:
                        obj = obj or make()
                        row, result = run(name, group, obj, grasp, method, options[method], physics)
                    rows.append(row)
                    f.write(json.dumps(row) + "\n")
                    f.flush()
                    if result is not None:
                        results[method] = result
                    print(f"{name:32s} {grasp:9s} {method:9s} {'ok' if row['verified'] else 'NO':3s} "
                          f"{row.get('time', float('nan')):6.2f} s  {row['reason'][:80]}", flush=True)
                both = len(results) == 2 and all(r.success for r in results.values())
                if len(results) == 2 and (kept is None or (both and not kept[3])):
                    kept = (f"{name} ({grasp})", obj, results, both)
    if kept is None or not kept[3]:  # resumed: plan again the first case both methods grasped, for the figure
        pairs = [(r["name"], r["grasp"]) for r in rows if r["method"] == "gradient" and r["verified"]
                 and any(o["name"] == r["name"] and o["grasp"] == r["grasp"] and o["method"] == "annealing"
                         and o["verified"] for o in rows)]
        if pairs:
            name, grasp = pairs[0]
            obj = next(make for n, _, make in todo if n == name)()
            results = {m: sg.plan(obj, grasp, method=m, **options[m]) for m in METHODS}
            kept = (f"{name} ({grasp})", obj, results, all(r.success for r in results.values()))
    figures = summary(rows, physics)
    ratios, words = verdict(figures, rows)
    main_table, smooth_table = tables(figures, physics)
    print("\n".join(main_table + [""] + smooth_table + ["", words]))
    fig_path = figure(kept[:3], FIGURE if args.docs else args.out / "planner-comparison.png")
    print(f"wrote {args.out / 'rows.jsonl'} and {fig_path}")
    if args.docs:
        resumed = sum((r["name"], r["grasp"], r["method"]) in done for r in rows)
        _write_page(rows, main_table, smooth_table, words, kept[0], args, resumed)
    return dict(rows=rows, figures={f"{k[0]}/{k[1]}": v for k, v in figures.items()}, ratios=ratios, figure=str(fig_path))


def _loadavg():
    try:
        return os.getloadavg()
    except OSError:  # not on every platform
        return (float("nan"),) * 3


def _load_words(rows, resumed):
    """How loaded the machine was while the rows were measured (the 1-min load average at each plan's end)."""
    loads = [r["load"] for r in rows if np.isfinite(r.get("load", float("nan")))]
    words = (f"The 1-minute load average of the 2-core machine at the end of the plans was {min(loads):.1f} to "
             f"{max(loads):.1f} (median {np.median(loads):.1f}; {len(loads)} of {len(rows)} plans recorded it)"
             if loads else "The plans' rows do not record the machine's load")
    words += ("; wall-clock times stretch when the load exceeds the machine's cores (the annealing's 10 s limit is"
              " of wall-clock time), the CPU times much less.")
    if resumed:
        words += (f" {resumed} of the {len(rows)} plans were read from the rows of earlier parts of the run (`--resume`:"
                  " after an interruption, or the parts run side by side, e.g. one `--grasp` each, their rows"
                  " concatenated).")
    return words


def _write_page(rows, main_table, smooth_table, words, pictured, args, resumed=0):
    """docs/planner-comparison.md."""
    command = "python benchmarks/compare_planners.py --docs" + (f" --subset {args.subset}" if args.subset else "") \
        + (f" --only {' '.join(args.only)}" if args.only else "")
    n_test = len({r["name"] for r in rows if r["group"] == "test"})
    lines = [
        "# Planner comparison: gradient against annealing",
        "",
        "The paper's claim is that its gradient-based reach finds stable grasps faster, and along smoother",
        "motions, than the random search of GraspIt!'s eigengrasp planner. Both planners of synergrasp are run",
        "here on the same hand, the same objects and the same verification: `sg.plan(obj, grasp)` (the",
        "gradient planner, [concept page](concepts/planner.md)) and `sg.plan(obj, grasp, method=\"annealing\")`",
        "(the GraspIt!-style baseline, [concept page](concepts/annealing.md)), each with its default options",
        "(a 10 s time limit each) but without the executable reach, which either would make the same way after",
        "its search.",
        "",
        f"Written by `{command}`: the paper's 8 cases and {n_test} objects of the test split of the",
        "generalisation benchmark" + (f" (`--subset {args.subset}`: evenly spaced in the split's order, to fit the run in"
                                      " the time available; the full split is the command without `--subset`)"
                                      if args.subset else "") + ", both grasp types, one run.",
        _load_words(rows, resumed),
        "",
        "A grasp counts when it is verified on the object's true surface (`benchmarks/verification.py`:",
        "contacts within 5 mm of the mesh, force closure by the hull of the wrenches at the mesh's points and",
        "normals, no phalanx capsule and not the palm box deeper than 3 mm); \"held\" counts the verified grasps that also hold in MuJoCo",
        "(`sg.validate`, default protocol). Times are of the search: the annealing's CPU time excludes the",
        "status history of its trajectory, computed after the search.",
        "",
        "## Verdict",
        "",
        words,
        "",
        "## Success, time, evaluations, quality",
        "",
        *main_table,
        "",
        "Evaluations: status evaluations (one per iteration and attempt start) of the gradient planner,",
        "energy evaluations of the annealing (cP of the hand points and the capsules' collision test, about",
        "half a status evaluation). Steps: iterations over all attempts of the gradient planner; annealing",
        "steps of the annealing (each draws up to 11 neighbours until one is legal).",
        "",
        "## Smoothness of the search trajectory (verified grasps, medians)",
        "",
        *smooth_table,
        "",
        "The gradient planner's trajectory is its successful attempt's iterations; the annealing's is the",
        "sequence of states the search moved to, then the auto-grasp's closing. The second differences are",
        "of u normalised as the planners step it (positions in object sizes, angles in rad, synergies).",
        "",
        f"![Both reaches of {pictured}](figures/planner-comparison.png)",
        "",
        f"*Both searches for {pictured}: the palm's path and the synergies along each trajectory.*",
        "",
        "## Every plan",
        "",
        "| case | grasp | method | verified | held | time (s) | CPU (s) | evaluations | steps | Q true | palm path (mm) "
        "| reason |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        lines.append(f"| {r['name']} | {r['grasp']} | {r['method']} | {'yes' if r['verified'] else 'no'} "
                     f"| {'-' if r['held'] is None else ('yes' if r['held'] else 'no')} | {_fmt(r.get('time'), '.2f')} "
                     f"| {_fmt(r.get('cpu'), '.2f')} | {r.get('evaluations', '-')} | {r.get('steps', '-')} "
                     f"| {_fmt(r.get('q_true'), '+.3f')} "
                     f"| {_fmt(r.get('path_mm'), '.0f')} | {r['reason'][:70]} |")
    PAGE.write_text("\n".join(lines) + "\n")
    print(f"wrote {PAGE}")


if __name__ == "__main__":
    main()
