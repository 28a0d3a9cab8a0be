"""Every LP backend side by side, from one LP to whole plans, in one process and one run.

Usage::

    python -m solvers.compare [--quick] [--out DIR] [--docs] [--max-iter N]

Backends: every available synergrasp backend (``sg.lp.available_backends()``)
plus two references a user might pick instead, both ordinary
:class:`synergrasp.lp.Backend` subclasses from :mod:`solvers.references`:
``scipy-linprog`` (``scipy.optimize.linprog(method="highs")``) and
``cvxpy-plain`` (a cvxpy model rebuilt for every LP, cvxpy's default solver).
``"highs"`` is the reference every other backend is checked against.

LP level (median and p95 wall time per call, LP solver calls per call, largest
difference of the value and the gradients from HiGHS's on the same inputs):

* ``cP value``: ``sg.pseudo_distance({p}, V)``, one point against the
  ellipsoid's single convex piece V;
* ``cP value+grad``: ``obj.contact_distance(p[None])`` (broad phase, the
  library's pruned LP, gradient, normal, witness);
* ``Q5 value`` / ``Q16 value``: ``sg.pseudo_distance(W, {0})`` on precomputed
  primitive wrenches of 5 or 16 contacts (8 cone edges);
* ``Q5 value+grad`` / ``Q16 value+grad``: ``sg.q_distance(points, normals)``,
  with the gradients with respect to the contact points and normals.

The inputs are random walks (a fingertip moving around 10 mm off the ellipsoid;
force-closed grasps of 5 or 16 contacts on a 40 mm sphere, each a small
perturbation of the previous one), identical for every backend.

Plan level: the paper's 8 cases (ellipsoid, cup, bell, goblet x precision,
power) with ``sg.plan(obj, grasp, backend=..., max_iter=...)``: success,
iterations, final g_Q, total wall time, time per iteration, the share of the
time spent inside the LP solver (sum of ``LPSolution.solve_time`` over the
wall time) and whether the trajectory coincides with HiGHS's (largest
``|u - u_highs|`` over the common length). Each case is first planned once,
untimed, with the shared HiGHS instance (the process's one-off work: the
hand's tables, the compiled kernels); then every backend plans a freshly
built object, so each pays the object's own first-use work alike. Every backend runs all 8 cases
(about 12 minutes on 2 cores); ``--slow-subset`` limits the cvxpy-based
backends to :data:`SLOW_PLAN_CASES` for a shorter run, and says so in the output.

The paper's own figures (MATLAB 2015 on an i5-2430M laptop) are added as fixed
rows, labelled as such: they come from another machine and another code.

Outputs in ``--out`` (default ``./bench-out/solver-comparison``, with
``--quick`` ``./bench-out/solver-comparison-quick``): ``lp_level.csv``,
``plan_level.csv``, ``summary.csv``, ``ratios.csv``, ``solver_ratios.csv``
(every backend's whole-call and in-solver ratio to HiGHS, per workload and
plan), ``environment.json``, ``README.md`` (the tables) and
``solver_comparison.png`` (log-scale bars). ``--docs`` writes the committed
results instead (``solvers/results``, unless ``--out`` is given), rewrites
``docs/solver-comparison.md`` and copies the figure to ``docs/figures/``. The
profile section comes from ``profile.md`` in the output folder, else from the
committed ``solvers/results/profile.md`` (``python -m solvers.profile_plan
--docs`` writes it).
"""

from __future__ import annotations

import argparse
import csv
import json
import os
import platform
import shutil
import sys
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

import synergrasp as sg
from benchmarks.bench_quality import grasp_sequence  # the same grasps as the benchmark
from synergrasp.lp import Backend

from .references import LinprogBackend, PlainCvxpyBackend, TimedBackend

ROOT = Path(__file__).resolve().parents[1]
#: The committed results (written with --docs).
COMMITTED = ROOT / "solvers" / "results"
#: Output folder of a run without --docs (relative to the working directory).
DEFAULT_OUT = Path("bench-out") / "solver-comparison"
REFERENCE = "highs"
FIGURE = "solver_comparison.png"

OBJECTS = ("ellipsoid", "cup", "bell", "goblet")
GRASPS = ("precision", "power")
CASES = tuple((o, g) for o in OBJECTS for g in GRASPS)
#: Plan cases of the cvxpy-based backends with --slow-subset (each of their LPs costs milliseconds).
SLOW_BACKENDS = ("cvxpy", "cvxpy-plain")
SLOW_PLAN_CASES = (("ellipsoid", "precision"), ("ellipsoid", "power"), ("goblet", "precision"))

#: The paper's figures (Liu et al.; MATLAB 2015, Intel i5-2430M laptop): another machine, another code.
PAPER_LABEL = "paper (MATLAB 2015, i5-2430M; other machine)"
PAPER_LP_MS = (30.0, 50.0)
PAPER_ITERATION_S = (0.3, 0.4)
PAPER_PLANS = {  # (iterations, g_Q, time s or None)
    ("ellipsoid", "precision"): (176, -0.0792, 54.0),
    ("ellipsoid", "power"): (63, -0.0625, 59.0),
    ("cup", "precision"): (163, -0.0570, 60.0),
    ("cup", "power"): (69, -0.1017, 80.0),
    ("bell", "precision"): (165, -0.0260, None),
    ("bell", "power"): (169, -0.1386, None),
    ("goblet", "precision"): (166, -0.1513, None),
    ("goblet", "power"): (None, -0.2574, None),
}

WORKLOADS = ("cP value", "cP value+grad", "Q5 value", "Q5 value+grad", "Q16 value", "Q16 value+grad")

#: Tolerances of the agreement verdict vs HiGHS: values (relative, absolute below 1) and non-degenerate gradients.
VALUE_TOL = 1e-6
GRAD_TOL = 1e-4


@dataclass
class Settings:
    """What one run measures."""

    quick: bool
    max_iter: int
    lp_calls: dict
    plan_cases: dict = field(default_factory=dict)  # backend -> tuple of (object, grasp)

    @classmethod
    def make(cls, quick: bool, backends, max_iter=None, subset=False):
        if quick:
            calls = {name: 20 if name == REFERENCE else 6 for name in backends}
            cases = {name: (("ellipsoid", "precision"),) for name in backends}
            return cls(True, max_iter or 8, calls, cases)
        calls = {"highs": 300, "native": 300, "clarabel": 100, "scipy-linprog": 60, "cvxpy": 30, "cvxpy-plain": 30}
        calls = {name: calls.get(name, 60) for name in backends}
        cases = {name: SLOW_PLAN_CASES if subset and name in SLOW_BACKENDS else CASES for name in backends}
        return cls(False, max_iter or 600, calls, cases)


# --------------------------------------------------------------------------- backends


def make_backends() -> dict[str, Backend]:
    """Fresh instances of every available backend, then the two references."""
    backends = {name: type(sg.lp.get_backend(name))() for name in sg.lp.available_backends()}
    backends["scipy-linprog"] = LinprogBackend()
    backends["cvxpy-plain"] = PlainCvxpyBackend()
    return backends


def describe(name: str, backend: Backend) -> str:
    """One line on what the backend is."""
    return {
        "highs": "HiGHS via highspy, dual simplex, warm-started",
        "native": "the library's own dense simplex per independent block (numba), warm-started",
        "clarabel": "Clarabel interior point (own API)",
        "cvxpy": "parametrised cvxpy model per LP shape, Clarabel",
        "scipy-linprog": "scipy.optimize.linprog(method='highs'), reference",
        "cvxpy-plain": f"plain cvxpy model rebuilt per LP, default solver ({getattr(backend, 'solver_name', '') or 'default'}), reference",
    }.get(name, type(backend).__name__)


# --------------------------------------------------------------------------- LP-level inputs


def point_sequence(obj, length: int, offset: float = 10.0, seed: int = 1):
    """A random walk of points ``offset`` mm outside the ellipsoid (a fingertip moving around it)."""
    rng = np.random.default_rng(seed)
    semi = 0.5 * obj.extents
    direction = np.array([0.3, 1.0, 0.2])
    points = []
    for _ in range(length):
        direction = direction + 0.05 * rng.normal(size=3)
        direction /= np.linalg.norm(direction)
        surface = direction / np.sqrt(np.sum((direction / semi) ** 2))
        points.append(obj.center + surface + offset * direction)
    return points


def workload_inputs(length: int):
    """For each workload, a function ``call(backend, i) -> (value, flat gradient, degenerate)``."""
    obj = sg.objects.ellipsoid()
    vertices = obj.convex[0].vertices
    pts = point_sequence(obj, length)
    g5, g16 = grasp_sequence(5, length), grasp_sequence(16, length, seed=2)
    origin = np.zeros((1, 6))
    w5 = [sg.contact_wrenches(p, n) for p, n in g5]
    w16 = [sg.contact_wrenches(p, n) for p, n in g16]

    def pd_call(A_list, B_list):
        def call(backend, i):
            r = sg.pseudo_distance(A_list[i], B_list[i], backend=backend)
            return r.value, np.r_[r.grad_a.ravel(), r.grad_b.ravel()], r.degenerate

        return call

    def cp_call(backend, i):
        r = obj.contact_distance(pts[i][None], backend=backend)
        return float(r.value[0]), r.grad[0].copy(), bool(r.degenerate[0])

    def q_call(grasps):
        def call(backend, i):
            r = sg.q_distance(*grasps[i], backend=backend)
            return r.value, np.r_[r.grad_points.ravel(), r.grad_normals.ravel()], r.degenerate

        return call

    return {
        "cP value": pd_call([p[None] for p in pts], [vertices] * length),
        "cP value+grad": cp_call,
        "Q5 value": pd_call(w5, [origin] * length),
        "Q5 value+grad": q_call(g5),
        "Q16 value": pd_call(w16, [origin] * length),
        "Q16 value+grad": q_call(g16),
    }


def run_lp_level(backends, settings, log):
    """Time every workload on every backend; returns (rows, raw results per (workload, backend)).

    The backends take turns call by call (each on its own instance, so its warm
    starts see only its own sequence): a burst of load from other processes
    then hits every backend alike.
    """
    length = max(settings.lp_calls.values()) + 1
    calls = workload_inputs(length)
    raw = {}
    for workload, call in calls.items():
        timed = {name: TimedBackend(backend) for name, backend in backends.items()}
        log_ = {name: dict(times=[], values=[], grads=[], degenerate=[]) for name in backends}
        for name in backends:
            call(timed[name], 0)  # warm-up: imports, model compilation, first basis
            timed[name].reset()
        for i in range(1, length):
            for name in backends:
                if i > settings.lp_calls[name]:
                    continue
                start = time.perf_counter()
                value, grad, deg = call(timed[name], i)
                elapsed = time.perf_counter() - start
                rec = log_[name]
                rec["times"].append(elapsed)
                rec["values"].append(value)
                rec["grads"].append(grad)
                rec["degenerate"].append(deg)
        for name in backends:
            rec = {k: np.array(v) for k, v in log_[name].items()}
            rec.update(lp_calls=timed[name].lp_calls, lp_time=timed[name].lp_time)
            raw[workload, name] = rec
            t = rec["times"] * 1e3
            log(f"  {workload:15s} {name:14s} median {np.median(t):9.3f} ms  p95 {np.percentile(t, 95):9.3f} ms  "
                f"({len(t)} calls)")
    rows = []
    for workload in calls:
        ref = raw[workload, REFERENCE]
        for name in backends:
            r = raw[workload, name]
            n = len(r["times"])
            # relative to the value (absolute below 1): interior-point solvers are accurate to about 1e-8 of it
            value_diff = float(np.max(np.abs(r["values"] - ref["values"][:n]) / np.maximum(1.0, np.abs(ref["values"][:n]))))
            ok = ~(r["degenerate"] | ref["degenerate"][:n])
            grad_diff = float(np.max(np.abs(r["grads"][ok] - ref["grads"][:n][ok]))) if ok.any() else float("nan")
            rows.append(dict(
                workload=workload,
                backend=name,
                calls=n,
                median_ms=float(np.median(r["times"]) * 1e3),
                p95_ms=float(np.percentile(r["times"], 95) * 1e3),
                lps_per_call=r["lp_calls"] / n,
                solver_share=r["lp_time"] / float(r["times"].sum()),
                solver_ms=1e3 * r["lp_time"] / n,
                value_diff=value_diff,
                grad_diff=grad_diff,
                grad_compared=int(ok.sum()),
                degenerate=int(r["degenerate"].sum()),
                agree=bool(value_diff <= VALUE_TOL and not (grad_diff > GRAD_TOL)),
            ))
    return rows, raw


# --------------------------------------------------------------------------- plan level


def run_plans(backends, settings, log):
    """Plan the selected cases on every backend; returns rows (HiGHS first for each case)."""
    rows, reference = [], {}
    for case in CASES:
        obj_name, grasp = case
        sg.plan(sg.objects.get(obj_name), grasp, max_iter=settings.max_iter, time_limit=None)  # untimed: one-off work
        for name, backend in backends.items():
            if case not in settings.plan_cases[name]:
                continue
            obj = sg.objects.get(obj_name)  # each backend plans a fresh object and pays its first-use work
            timed = TimedBackend(backend)
            start = time.perf_counter()
            error = ""
            try:
                # no time limit: a slow backend's plan must end where HiGHS's does for the verdicts to compare
                result = sg.plan(obj, grasp, backend=timed, max_iter=settings.max_iter, time_limit=None)
            except Exception as exc:  # a crash is data too
                result, error = None, f"{type(exc).__name__}: {exc}"
            wall = time.perf_counter() - start
            row = dict(backend=name, object=obj_name, grasp=grasp, source="measured", max_iter=settings.max_iter,
                       time_s=wall, lp_solves=timed.lp_calls, lp_time_s=timed.lp_time,
                       lp_share=timed.lp_time / wall if wall > 0 else float("nan"))
            if result is None:
                row.update(success=False, iterations=-1, total_iterations=-1, attempts=-1, final_q=float("nan"),
                           time_per_iter_ms=float("nan"),
                           reason=error, same_verdict=None, same_iterations=None, max_du=float("nan"))
            else:
                total = int(getattr(result, "total_iterations", result.iterations))
                row.update(success=bool(result.success), iterations=int(result.iterations), total_iterations=total,
                           attempts=len(getattr(result, "attempts", [])) or 1, final_q=result.final_q,
                           time_per_iter_ms=1e3 * wall / max(total, 1), reason=result.reason)
                if name == REFERENCE:
                    reference[case] = result
                ref = reference.get(case)
                if ref is None:
                    row.update(same_verdict=None, same_iterations=None, max_du=float("nan"))
                else:
                    common = min(len(ref.trajectory), len(result.trajectory))
                    du = np.abs(result.trajectory[:common] - ref.trajectory[:common])
                    row.update(same_verdict=bool(result.success) == bool(ref.success),
                               same_iterations=int(result.iterations) == int(ref.iterations)
                               and total == int(getattr(ref, "total_iterations", ref.iterations)),
                               max_du=float(du.max()) if du.size else 0.0)
            rows.append(row)
            log(f"  {obj_name:9s} {grasp:9s} {name:14s} success={row['success']!s:5s} it={row['iterations']:4d} "
                f"({row['total_iterations']} in {row['attempts']}) Q={row['final_q']:+.4f} {wall:8.2f} s  LP share {row['lp_share']:.0%}  max|du|={row['max_du']:.2g}")
    return rows


def paper_rows():
    """The paper's plan figures as fixed rows."""
    rows = []
    for (obj_name, grasp), (iterations, q, seconds) in PAPER_PLANS.items():
        rows.append(dict(
            backend=PAPER_LABEL, object=obj_name, grasp=grasp, source="paper", max_iter=None,
            success=True, iterations=iterations if iterations is not None else -1,
            total_iterations=iterations if iterations is not None else -1, attempts=1, final_q=q,
            time_s=seconds if seconds is not None else float("nan"),
            time_per_iter_ms=1e3 * seconds / iterations if seconds and iterations else float("nan"),
            lp_solves=-1, lp_time_s=float("nan"), lp_share=float("nan"),
            reason="reported in the paper (Table 3 / text)", same_verdict=None, same_iterations=None, max_du=float("nan"),
        ))
    return rows


# --------------------------------------------------------------------------- summary, ratios


def _median(lp_rows, workload, backend):
    for row in lp_rows:
        if row["workload"] == workload and row["backend"] == backend:
            return row["median_ms"]
    return float("nan")


def _plan(plan_rows, backend, case):
    for row in plan_rows:
        if row["backend"] == backend and (row["object"], row["grasp"]) == case:
            return row
    return None


def summarise(backends, lp_rows, plan_rows):
    """One row per backend."""
    rows = []
    for name, backend in backends.items():
        mine = [r for r in lp_rows if r["backend"] == name]
        plans = [r for r in plan_rows if r["backend"] == name]
        ell = _plan(plan_rows, name, ("ellipsoid", "precision"))
        rows.append(dict(
            backend=name,
            what=describe(name, backend),
            cP_vg_ms=_median(lp_rows, "cP value+grad", name),
            Q5_vg_ms=_median(lp_rows, "Q5 value+grad", name),
            Q16_vg_ms=_median(lp_rows, "Q16 value+grad", name),
            value_diff=max(r["value_diff"] for r in mine),
            grad_diff=float(np.nanmax([r["grad_diff"] for r in mine])) if any(np.isfinite(r["grad_diff"]) for r in mine) else float("nan"),
            plan_ellipsoid_precision_s=ell["time_s"] if ell else float("nan"),
            plans_run=len(plans),
            plans_succeeded=sum(bool(r["success"]) for r in plans),
            verdicts_agree=sum(r["same_verdict"] is True for r in plans),
        ))
    return rows


def ratios(lp_rows, plan_rows, quick=False):
    """The issue's target ratios, measured in this run."""
    out = []

    def add(name, numerator, denominator, target, note, rest=(float("nan"),) * 3):
        ratio = numerator / denominator if denominator and np.isfinite(denominator) and np.isfinite(numerator) else float("nan")
        rest_now, slow_solver, fast_solver = rest
        out.append(dict(ratio=name, value=ratio, target=target, met=bool(np.isfinite(ratio) and ratio >= target),
                        rest_now=rest_now, rest_allowed=allowed_rest(slow_solver, fast_solver, target), note=note))

    def lp_split(backend):  # (outside the solver, inside it), ms per Q5 value+grad call
        row = next((r for r in lp_rows if r["workload"] == "Q5 value+grad" and r["backend"] == backend), None)
        return (float("nan"),) * 2 if row is None else (row["median_ms"] * (1 - row["solver_share"]),
                                                        row["median_ms"] * row["solver_share"])

    q5 = _median(lp_rows, "Q5 value+grad", REFERENCE)
    q5_rest, q5_solver = lp_split(REFERENCE)
    for name, target in (("cvxpy", 20.0), ("scipy-linprog", 10.0)):
        add(f"Q5 value+grad: {name} / highs", _median(lp_rows, "Q5 value+grad", name), q5, target,
            "median time per call, ms", (q5_rest, lp_split(name)[1], q5_solver))
    case = ("ellipsoid", "precision")
    highs, cvx = _plan(plan_rows, REFERENCE, case), _plan(plan_rows, "cvxpy", case)
    h = highs["time_s"] if highs else float("nan")
    capped = " (quick mode: a plan capped after a few iterations, not comparable)" if quick else ""
    plan_rest = (h - highs["lp_time_s"], cvx["lp_time_s"], highs["lp_time_s"]) if highs and cvx else (float("nan"),) * 3
    add("plan ellipsoid precision: cvxpy / highs", cvx["time_s"] if cvx else float("nan"), h, 10.0,
        "wall time per plan, s" + capped, plan_rest)
    add("plan ellipsoid precision: paper 54 s / highs", PAPER_PLANS[case][2], h, 100.0,
        "the paper's time is from another machine (MATLAB 2015, i5-2430M)" + capped)
    return out


def solver_ratios(lp_rows, plan_rows):
    """Every backend against HiGHS, per workload and per plan: the whole-call ratio and the in-solver ratio.

    The whole-call ratio divides the median times per call (LP level) or the
    plan times; the in-solver ratio divides the time inside the LP solver per
    call (LP level) or per plan. The gap between the two is the time both pay
    alike outside the solver.
    """
    rows = []
    for row in lp_rows:
        ref = next((r for r in lp_rows if r["workload"] == row["workload"] and r["backend"] == REFERENCE), None)
        if row["backend"] == REFERENCE or ref is None:
            continue
        rows.append(dict(workload=row["workload"], backend=row["backend"], whole=row["median_ms"] / ref["median_ms"],
                         in_solver=row["solver_ms"] / ref["solver_ms"] if ref["solver_ms"] > 0 else float("nan"),
                         unit="per call"))
    for row in plan_rows:
        if row["source"] != "measured" or row["backend"] == REFERENCE:
            continue
        ref = _plan(plan_rows, REFERENCE, (row["object"], row["grasp"]))
        if ref is None:
            continue
        rows.append(dict(workload=f"plan {row['object']} {row['grasp']}", backend=row["backend"],
                         whole=row["time_s"] / ref["time_s"],
                         in_solver=row["lp_time_s"] / ref["lp_time_s"] if ref["lp_time_s"] > 0 else float("nan"),
                         unit="per plan"))
    return rows


def allowed_rest(slow_solver, fast_solver, target):
    """The most time outside the LP solver at which a slow/fast wall-time ratio still reaches ``target``.

    Both backends pay the same time R outside the solver (the library's Python around
    the LPs) plus their own solver time S, so ``(R + S_slow) / (R + S_fast) >= target``
    exactly when ``R <= (S_slow - target S_fast) / (target - 1)``; negative when even
    R = 0 would not do.

    Parameters
    ----------
    slow_solver, fast_solver : float
        Solver time of the slower and of the faster backend (same unit).
    target : float
        The ratio asked for, > 1.

    Returns
    -------
    float
        In the unit of the inputs.
    """
    return (slow_solver - target * fast_solver) / (target - 1.0)


def bounds(lp_rows, plan_rows) -> str:
    """What limits the ratios: the time outside the LP solver, which every backend pays alike."""
    text = []
    row = _plan(plan_rows, REFERENCE, ("ellipsoid", "precision"))
    if row is not None and row["time_s"] > 0:
        rest = row["time_s"] - row["lp_time_s"]
        text.append(
            f"Reading the ratios: with HiGHS, {row['lp_share']:.0%} of the ellipsoid precision plan is spent inside "
            f"the LP solver ({row['lp_time_s']:.3f} of {row['time_s']:.3f} s, {row['lp_solves']} LPs); the other "
            f"{rest:.3f} s (status assembly, cP/sQ geometry, the planner) is the same for every backend, so a "
            f"backend's plan time is about {rest:.3f} s plus its LP time and no LP backend could make this plan "
            f"more than {row['time_s'] / rest:.1f}x faster than HiGHS does now.")
    for q in (r for r in lp_rows if r["workload"] == "Q5 value+grad" and r["backend"] in (REFERENCE, "scipy-linprog")):
        text.append(f"Q5 value+grad on {q['backend']}: {q['median_ms']:.2f} ms per call, {q['lps_per_call']:g} LPs, "
                    f"{q['solver_share']:.0%} of it inside the solver.")
    return " ".join(text)


def verdict_check(plan_rows):
    """(all agree, list of disagreements) of the measured plans against HiGHS."""
    bad = [f"{r['backend']} {r['object']} {r['grasp']}" for r in plan_rows
           if r["source"] == "measured" and r["backend"] != REFERENCE and r["same_verdict"] is False]
    return not bad, bad


# --------------------------------------------------------------------------- output


def environment(backends):
    cpu = platform.processor() or ""
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    versions = {}
    for module in ("numpy", "scipy", "highspy", "clarabel", "cvxpy"):
        try:
            from importlib.metadata import version

            versions[module] = version(module)
        except Exception:
            versions[module] = "?"
    return dict(
        date=time.strftime("%Y-%m-%d %H:%M"),
        cpu=cpu,
        cores=os.cpu_count(),
        python=platform.python_version(),
        synergrasp=sg.__version__,
        versions=versions,
        cvxpy_default_solver=getattr(backends.get("cvxpy-plain"), "solver_name", ""),
        load_average=os.getloadavg() if hasattr(os, "getloadavg") else None,
    )


def write_csv(path, rows):
    if not rows:
        return
    keys = list(rows[0])
    with open(path, "w", newline="") as fh:
        writer = csv.DictWriter(fh, fieldnames=keys)
        writer.writeheader()
        for row in rows:
            writer.writerow({k: (f"{v:.6g}" if isinstance(v, float) else v) for k, v in row.items()})


def _fmt(value, digits=3):
    if value is None:
        return "-"
    if isinstance(value, bool):
        return "yes" if value else "no"
    if isinstance(value, (int, np.integer)):
        return str(value) if value >= 0 else "-"
    if isinstance(value, float):
        if not np.isfinite(value):
            return "-"
        if value == 0:
            return "0"
        if abs(value) < 1e-3 or abs(value) >= 1e5:
            return f"{value:.1e}"
        return f"{value:.{digits}g}"
    return str(value)


def _table(headers, rows):
    lines = ["| " + " | ".join(headers) + " |", "|" + "---|" * len(headers)]
    lines += ["| " + " | ".join(_fmt(v) for v in row) + " |" for row in rows]
    return "\n".join(lines)


def markdown(env, settings, lp_rows, plan_rows, summary, ratio_rows, figure_link, profile_text="", solver_rows=()):
    """The results as markdown (used for results/README.md and the docs page)."""
    agree, bad = verdict_check(plan_rows)
    slow = ", ".join(f"{o} {g}" for o, g in SLOW_PLAN_CASES)
    mode = "quick (reduced)" if settings.quick else "full"
    parts = [
        f"Run: {env['date']}, {mode} mode, on {env['cpu']} ({env['cores']} cores; other processes may have been "
        f"running, so times are medians). Python {env['python']}, "
        + ", ".join(f"{k} {v}" for k, v in env["versions"].items())
        + f"; cvxpy's default LP solver here: {env['cvxpy_default_solver'] or '?'}. Plans capped at "
        f"max_iter = {settings.max_iter}.",
        "",
        "### Summary (one row per backend)",
        "",
        _table(
            ["backend", "what", "cP v+g ms", "Q5 v+g ms", "Q16 v+g ms", "max value diff", "max grad diff",
             "plan ellipsoid precision s", "plans run", "succeeded", "verdict = highs"],
            [[r["backend"], r["what"], r["cP_vg_ms"], r["Q5_vg_ms"], r["Q16_vg_ms"], r["value_diff"], r["grad_diff"],
              r["plan_ellipsoid_precision_s"], r["plans_run"], r["plans_succeeded"], r["verdicts_agree"]] for r in summary]
            + [[PAPER_LABEL, "30-50 ms per LP", None, None, None, None, None, PAPER_PLANS["ellipsoid", "precision"][2],
                None, None, None]],
        ),
        "",
        "Differences are the largest differences from HiGHS over all LP-level calls, values relative to HiGHS's "
        "(absolute below 1), gradients absolute (on calls where neither backend flags the LP degenerate).",
        "",
        "### Target ratios (same run)",
        "",
        _table(["ratio", "measured", "target", "met", "outside the solver now", "at most, for the target", "note"],
               [[r["ratio"], r["value"], f">= {r['target']:g}x", r["met"], r["rest_now"], r["rest_allowed"], r["note"]]
                for r in ratio_rows]),
        "",
        "Outside the solver: the time both backends spend alike around the LPs (the library's Python: geometry, "
        "wrenches, gradients, the planner), in the unit of the note (for Q5 the median call time times the run's "
        "share of time inside the solver); *at most* is the largest such time at which "
        "the ratio would still reach its target with this run's solver times (see `allowed_rest`; negative: not "
        "even with none).",
        "",
        "### Whole-call and in-solver ratios to HiGHS",
        "",
        "For every workload and plan: the backend's time over HiGHS's, for the whole call (median time per call, or "
        "the plan's time) and inside the LP solver only (solver time per call, or per plan). Where the two differ, "
        "the time both backends spend alike outside the solver holds the whole-call ratio down.",
        "",
        _table(["workload", "backend", "whole call", "inside the solver", "unit"],
               [[r["workload"], r["backend"], r["whole"], r["in_solver"], r["unit"]] for r in solver_rows]),
        "",
        "Plans whose verdict (success or not) differs from HiGHS's on the same case, every plan run to the same "
        f"max_iter with no time limit: {'none' if agree else '; '.join(bad)}.",
        "",
        bounds(lp_rows, plan_rows),
        "",
        f"![time per call and per plan, log scale]({figure_link})",
        "",
        "### LP level",
        "",
        "Wall time per call of the library function (v = value only, `sg.pseudo_distance` on precomputed sets; "
        "v+g = the library call with gradients with respect to the physical inputs), LP solver calls per call, "
        "share of the time inside the solver, agreement with HiGHS.",
        "",
        _table(
            ["workload", "backend", "calls", "median ms", "p95 ms", "LPs/call", "solver share", "value diff",
             "grad diff", "degenerate", "agrees"],
            [[r["workload"], r["backend"], r["calls"], r["median_ms"], r["p95_ms"], r["lps_per_call"],
              f"{r['solver_share']:.0%}", r["value_diff"], r["grad_diff"], r["degenerate"], r["agree"]]
             for r in lp_rows]
            + [[PAPER_LABEL, "MATLAB", None, "30-50 per LP", None, None, None, None, None, None, None]],
        ),
        "",
        "### Plan level",
        "",
        f"`sg.plan(obj, grasp, backend=..., max_iter={settings.max_iter})`. Iterations are those of the returned "
        "reach; all attempts = iterations over every attempt (number of attempts), the planner restarting from "
        "another approach direction after a stall. Time is the wall time of the call, ms/iteration divides it by "
        "all attempts' iterations; "
        "LP share = time inside the backend's solve over that; max |du| = largest deviation of the configuration "
        "u (mm, rad) from HiGHS's trajectory over the common length. "
        + (f"Quick mode: one case, capped at {settings.max_iter} iterations (not a finished plan). " if settings.quick
           else f"The cvxpy-based backends ({', '.join(SLOW_BACKENDS)}) ran only {slow} (--slow-subset); the "
           "other backends ran all 8 cases. " if any(len(v) < len(CASES) for v in settings.plan_cases.values())
           else "Every backend ran all 8 cases.")
        + " The paper rows are its reported figures (time only for the four cases it gives).",
        "",
        _table(
            ["object", "grasp", "backend", "success", "iterations", "all attempts", "final Q", "time s",
             "ms/iteration", "LP solves", "LP share", "same verdict", "same iterations", "max abs du"],
            [[r["object"], r["grasp"], r["backend"], r["success"], r["iterations"],
              f"{r['total_iterations']} ({r['attempts']})" if r["source"] == "measured" else "-", r["final_q"], r["time_s"],
              r["time_per_iter_ms"], r["lp_solves"], "-" if not np.isfinite(r["lp_share"]) else f"{r['lp_share']:.0%}",
              r["same_verdict"], r["same_iterations"], r["max_du"]] for r in plan_rows],
        ),
        "",
        f"Paper, per iteration: {PAPER_ITERATION_S[0]}-{PAPER_ITERATION_S[1]} s; per LP: "
        f"{PAPER_LP_MS[0]:g}-{PAPER_LP_MS[1]:g} ms ({PAPER_LABEL}).",
    ]
    if profile_text:
        parts += ["", profile_text.strip()]
    return "\n".join(parts) + "\n"


def figure(path, lp_rows, plan_rows, backends):
    """Log-scale bars: median time per LP-level call, and time per plan, for each backend."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    names = list(backends)
    colours = dict(zip(names, plt.get_cmap("tab10").colors))
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(13, 5.4), gridspec_kw=dict(width_ratios=[1.1, 1]))
    width = 0.8 / len(names)
    x = np.arange(len(WORKLOADS))
    for i, name in enumerate(names):
        heights = [_median(lp_rows, w, name) for w in WORKLOADS]
        ax1.bar(x + (i - (len(names) - 1) / 2) * width, heights, width, label=name, color=colours[name])
    ax1.axhspan(*PAPER_LP_MS, color="0.85", zorder=0, label="paper: 30-50 ms per LP (other machine)")
    ax1.set_xticks(x, [w.replace(" value", "\nvalue") for w in WORKLOADS], fontsize=8)
    ax1.set_yscale("log")
    ax1.set_ylabel("median time per call (ms)")
    ax1.set_title("LP level")
    cases = [c for c in CASES if any((r["object"], r["grasp"]) == c and r["source"] == "measured" for r in plan_rows)]
    x = np.arange(len(cases))
    labels = names + [PAPER_LABEL]
    width = 0.8 / len(labels)
    for i, name in enumerate(labels):
        heights = []
        for case in cases:
            row = _plan(plan_rows, name, case)
            heights.append(row["time_s"] if row is not None else np.nan)
        colour = colours.get(name, "0.6")
        ax2.bar(x + (i - (len(labels) - 1) / 2) * width, heights, width, label=name if name in colours else "paper (other machine)",
                color=colour, hatch=None if name in colours else "//")
        for xi, case in zip(x, cases):
            row = _plan(plan_rows, name, case)
            if row is not None and row["source"] == "measured" and not row["success"]:
                ax2.plot(xi + (i - (len(labels) - 1) / 2) * width, row["time_s"] * 1.3, "x", color="k", ms=4)
    ax2.set_xticks(x, [f"{o}\n{g}" for o, g in cases], fontsize=8)
    ax2.set_yscale("log")
    ax2.set_ylabel("time per plan (s)")
    ax2.set_title("Plan level (x = no grasp found within max_iter)")
    handles, labels_ = ax1.get_legend_handles_labels()
    h2, l2 = ax2.get_legend_handles_labels()
    handles.append(h2[-1])
    labels_.append("paper: time per plan (other machine)")
    fig.legend(handles, labels_, loc="lower center", ncol=4, fontsize=8, frameon=False)
    fig.tight_layout(rect=(0, 0.1, 1, 1))
    fig.savefig(path, dpi=110)
    plt.close(fig)


DOCS_INTRO = """# Solver comparison

synergrasp solves many small LPs: each cP query, each sQ ray, each Q distance. This page compares
the LP backends on exactly those LPs, from one call to whole plans, all measured in one run of

```bash
python -m solvers.compare --docs      # full run, about 12 minutes on 2 cores
python -m solvers.compare --quick     # reduced run, well under a minute (the test suite runs it)
```

Backends: every available synergrasp backend (`"highs"`, `"native"`, `"clarabel"`, `"cvxpy"`) and two
references a user might pick instead, both written as `synergrasp.lp.Backend` subclasses in
`solvers/references.py` and passed as backend objects: `scipy-linprog`
(`scipy.optimize.linprog(method="highs")`, one call per LP) and `cvxpy-plain` (a cvxpy model
rebuilt for every LP and solved by cvxpy's default solver). HiGHS is the reference: every other
backend's values and gradients are compared with its own on the same inputs. The raw numbers are in
`solvers/results/` (CSV files, `README.md`, the figure); the paper's figures come from MATLAB 2015
on an i5-2430M laptop, another machine and another code, and are shown for orientation only.

The time of a plan is not all LP solving: the share spent inside the solver is in the plan table,
and the profile section at the end shows where the rest goes.

What a speed ratio between two backends can reach is set by the time both spend alike outside the
solver (the library's code around the LPs: geometry, wrenches, gradients, the planner). The
target-ratio table shows that time as measured and the most it could be for each target with the
solver times of the same run; the table of whole-call and in-solver ratios shows, for every workload
and plan, how far the first falls below the second. The loops that run on every planner iteration
(the cP and sQ geometry, the LP block assembly, the contact wrenches and their gradients, the
smoothed normals, the hand's kinematics) are compiled (numba, cached on disk), so that time is a
fraction of what the numpy version took; the profile section at the end measures it before and
after.

"""


def write_docs(text, figure_path):
    docs = ROOT / "docs"
    (docs / "figures").mkdir(parents=True, exist_ok=True)
    shutil.copyfile(figure_path, docs / "figures" / FIGURE)
    (docs / "solver-comparison.md").write_text(DOCS_INTRO + "## Results\n\n" + text)


def main(argv=None) -> dict:
    """Run the comparison; returns the tables (``lp``, ``plan``, ``summary``, ``ratios``) and paths."""
    from synergrasp.cli import output_folder, positive  # (here: profile_plan imports this module beside an older package)

    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--quick", action="store_true", help="reduced run: few calls, one short plan per backend")
    parser.add_argument("--out", type=output_folder, default=None,
                        help=f"output folder (default ./{DEFAULT_OUT}, with --quick ./{DEFAULT_OUT}-quick; "
                             "with --docs solvers/results)")
    parser.add_argument("--docs", action="store_true",
                        help="write the committed results (solvers/results), docs/solver-comparison.md and its figure")
    parser.add_argument("--max-iter", type=positive(int), default=None, help="plan iteration cap (600; quick: 8)")
    parser.add_argument("--slow-subset", action="store_true",
                        help=f"run the cvxpy-based backends' plans on {len(SLOW_PLAN_CASES)} cases only (a shorter run)")
    parser.add_argument("--quiet", action="store_true")
    args = parser.parse_args(argv)
    log = (lambda *a: None) if args.quiet else (lambda *a: print(*a, flush=True))
    if args.docs and args.quick:
        parser.error("--docs needs the full run: drop --quick")
    default = COMMITTED if args.docs else DEFAULT_OUT.with_name(DEFAULT_OUT.name + "-quick") if args.quick else DEFAULT_OUT
    out = Path(args.out) if args.out is not None else default
    out.mkdir(parents=True, exist_ok=True)
    backends = make_backends()
    settings = Settings.make(args.quick, backends, args.max_iter, args.slow_subset)
    started = time.perf_counter()

    log(f"LP level ({', '.join(backends)})")
    lp_rows, _ = run_lp_level(backends, settings, log)
    log("Plan level")
    plan_rows = run_plans(backends, settings, log) + paper_rows()
    summary = summarise(backends, lp_rows, plan_rows)
    ratio_rows = ratios(lp_rows, plan_rows, settings.quick)
    solver_rows = solver_ratios(lp_rows, plan_rows)
    env = environment(backends)
    env["run_seconds"] = time.perf_counter() - started
    env["mode"] = "quick" if settings.quick else "full"

    write_csv(out / "lp_level.csv", lp_rows)
    write_csv(out / "plan_level.csv", plan_rows)
    write_csv(out / "summary.csv", summary)
    write_csv(out / "ratios.csv", ratio_rows)
    write_csv(out / "solver_ratios.csv", solver_rows)
    (out / "environment.json").write_text(json.dumps(env, indent=1))
    figure(out / FIGURE, lp_rows, plan_rows, backends)
    profile_path = out / "profile.md" if (out / "profile.md").exists() else COMMITTED / "profile.md"
    profile_text = profile_path.read_text() if profile_path.exists() else ""
    text = markdown(env, settings, lp_rows, plan_rows, summary, ratio_rows, FIGURE, profile_text, solver_rows)
    (out / "README.md").write_text("# Solver comparison results\n\nWritten by `python -m solvers.compare"
                                   + (" --quick" if settings.quick else "") + "`.\n\n" + text)
    if args.docs:
        write_docs(markdown(env, settings, lp_rows, plan_rows, summary, ratio_rows, f"figures/{FIGURE}", profile_text,
                            solver_rows),
                   out / FIGURE)

    log("\nRatios (same run):")
    for r in ratio_rows:
        log(f"  {r['ratio']:48s} {r['value']:8.1f}x  target >= {r['target']:g}x  {'met' if r['met'] else 'NOT met'}")
    agree, bad = verdict_check(plan_rows)
    log(f"  plans whose verdict differs from HiGHS's: {'none' if agree else '; '.join(bad)}")
    log(f"done in {env['run_seconds']:.0f} s; results in {out}")
    return dict(lp=lp_rows, plan=plan_rows, summary=summary, ratios=ratio_rows, solver_ratios=solver_rows,
                environment=env, out=out)


if __name__ == "__main__":
    main(sys.argv[1:])
