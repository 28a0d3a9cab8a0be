"""How well the planner generalises: verified grasps on the benchmark's train or test split.

Usage::

    python benchmarks/generalise.py [--split train|test|all] [--grasp precision power] [--only NAME ...]
                                    [--option NAME=VALUE ...] [--runs R] [--jobs N] [--out DIR] [--docs] [--quick]
                                    [--rows] [--urdf-sizes MM ...] [--cloud N [--noise MM]] [--pose SEED]

Plans a grasp of every object of a split of ``benchmarks/objectset.py`` (269 objects from three
sources, split by shape) and verifies each plan independently of the planner, on the object's true
mesh (``verification.py``: contacts within 5 mm of it, force closure by qhull at its normals, no
phalanx capsule and not the palm box deeper than 3 mm in it).

Prints, for each grasp type, the verified rate, the median and p90 plan time and the plans'
iterations (the cost of a change to the planner, whatever the machine's load), the median Q of the
accepted grasps and the share of them with Q > -0.01, the contacts' gap to the true surface, the
hand's depth in it, how many accepted grasps have a collision-free executable reach, and a
taxonomy of why every failed attempt ended. With ``--runs R`` every object is planned R times (run
after run); the verified count is then the median of the runs' counts, each run's count beside it
(plan times near the time limit move a few objects between runs on a loaded machine), and the other
figures pool the runs' plans. Rows go to ``DIR/<split>_<grasp>.jsonl`` (default
``bench-out/generalise``, ``bench-out/generalise-sizes`` for a sweep of sizes); ``--docs`` also writes ``docs/generalisation.md``, its figure and the
README summary; ``--rows`` plans nothing and summarises (and documents) the rows already there.
``--urdf-sizes 60 150 --only urdf/`` plans the random_urdfs shapes at sizes the benchmark does not
hold (each shape in its split), for a sweep of sizes on train. ``--cloud 3000`` plans every object from
3000 points sampled on its mesh (``sg.objects.from_points``: a point cloud, no mesh) and verifies the
grasp on the mesh (rows in ``bench-out/generalise-cloud``); ``--noise 0.5`` adds Gaussian noise of
0.5 mm to every coordinate, as a scanner would. ``--pose SEED`` turns every object about its centre by
a rotation drawn uniformly and puts its centre 150 mm from the origin (rows in
``bench-out/generalise-posed``, or ``-cloud-posed`` with ``--cloud``; each row records its seed): the
benchmark's objects sit at the origin in the pose their files give, and a user's need not.
"""

from __future__ import annotations

import argparse
import ast
import json
import sys
import time
import warnings
import zlib
from collections import Counter
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np
import trimesh

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

import synergrasp as sg  # noqa: E402
from synergrasp.cli import output_folder, positive, write_between_markers  # noqa: E402
from synergrasp.planner import ObjectRefused  # noqa: E402
from objectset import SPLITS, URDF_SIZES, select  # noqa: E402
from verification import true_surface, verify  # noqa: E402

ROOT = HERE.parent
PAGE = ROOT / "docs" / "generalisation.md"
FIGURE = ROOT / "docs" / "figures" / "generalisation.png"
README_MARKERS = ("<!-- generalise:start -->", "<!-- generalise:end -->")
#: Objects of the quick mode (tests).
QUICK = ("household/can", "procedural/box_0")
#: How far (mm) from the origin ``--pose`` puts each object's centre, in a direction of its own.
SHIFT = 150.0


def fidelity(obj, samples=2000, mesh=None):
    """How far the convex pieces' outer surface is from the true surface (a one-sided Hausdorff-type distance).

    Points are sampled on the pieces' surfaces; those whose point 1 mm outwards lies in another piece
    are inside the union and left out; the rest are measured to the object's mesh.

    Parameters
    ----------
    obj : GraspObject
    samples : int
    mesh : trimesh.Trimesh, optional
        The true surface (default the object's mesh; for an object made from a cloud, the mesh it was
        sampled from).

    Returns
    -------
    (float, float)
        The largest and the 95th-percentile distance (mm); 0 for an object without a mesh.
    """
    mesh = obj.mesh if mesh is None else mesh
    if mesh is None:
        return 0.0, 0.0
    pieces = trimesh.util.concatenate(obj.piece_meshes())
    points, faces = trimesh.sample.sample_surface(pieces, samples, seed=0)
    outer = points[~obj.contains(points + 1.0 * pieces.face_normals[faces])]
    gap = trimesh.proximity.closest_point(mesh, outer)[1]
    return float(gap.max()), float(np.percentile(gap, 95))


def pose(name, seed, shift=SHIFT):
    """(4, 4) float: a rotation drawn uniformly, then a move of ``shift`` mm in a direction drawn uniformly, from
    ``seed`` and the object's ``name`` (`run` applies it to the object centred at the origin)."""
    from scipy.spatial.transform import Rotation

    rng = np.random.default_rng([seed, zlib.crc32(name.encode())])
    matrix = np.eye(4)
    matrix[:3, :3] = Rotation.random(random_state=rng).as_matrix()
    direction = rng.normal(size=3)
    matrix[:3, 3] = shift * direction / np.linalg.norm(direction)
    return matrix


def placed(obj, name, seed):
    """``obj`` centred at the origin, then turned and moved by `pose` of ``name`` and ``seed``."""
    centre = np.eye(4)
    centre[:3, 3] = -np.asarray(obj.center, dtype=float)
    return obj.transformed(pose(name, seed) @ centre)


def run(entry_name, grasp, options, urdf_sizes=URDF_SIZES, cloud=None, noise=0.0, posed=None):
    """Plan and verify one object (or a cloud of ``cloud`` points sampled on it, each moved by Gaussian noise of
    standard deviation ``noise`` mm along each axis; with ``posed`` a seed, turned and moved by `pose`): a JSON-able
    row."""
    warnings.simplefilter("ignore")
    (entry,) = [e for e in select("all", urdf_sizes=urdf_sizes) if e.name == entry_name]
    obj = entry.make()
    labels = dict(name=entry.name, source=entry.source, split=entry.split, pose=posed)
    obj = obj if posed is None else placed(obj, entry.name, posed)
    if cloud is None:
        return plan_row(obj, grasp, options, **labels)
    mesh = true_surface(obj)
    points = trimesh.sample.sample_surface(mesh, cloud, seed=0)[0]
    points = points + np.random.default_rng(0).normal(scale=noise, size=points.shape) if noise else points
    return plan_row(sg.objects.from_points(points, name=f"{entry.name} ({cloud} points)"), grasp, options,
                    truth=obj, **labels)


def plan_row(obj, grasp, options, truth=None, **labels):
    """Plan a grasp of ``obj`` and verify it: a JSON-able row, starting with ``labels`` (name, source, split).

    ``truth``: the object whose true surface the grasp is verified on (default ``obj``; the mesh a
    point cloud ``obj`` was sampled from).
    """
    truth = obj if truth is None else truth
    start = time.perf_counter()
    try:
        result = sg.plan(obj, grasp, **options)
    except ObjectRefused as exc:  # the planner refuses the object (too large, too thin...)
        return dict(**labels, grasp=grasp, success=False, verified=False, time=time.perf_counter() - start,
                    reason=str(exc), refused=True, iterations=0, attempts=[])
    row = dict(**labels, grasp=grasp, success=result.success,
               time=time.perf_counter() - start, reason=result.reason, refused=False, q=result.final_q,
               iterations=result.total_iterations, n_attempts=len(result.attempts),
               contacts=list(result.contact_labels), penetration=result.penetration, surface_q=result.surface_q, collision_free=result.collision_free,
               reach_source=result.reach.get("source"),
               attempts=[dict(kind=a["kind"], outcome=a["outcome"], iterations=a["iterations"])
                         for a in result.attempts])
    row.update(verify(result, truth))
    row["overhang"], row["overhang95"] = fidelity(obj, mesh=true_surface(truth))
    return row


def _runs(rows):
    """The run numbers of the rows (rows of a single run have none: run 0)."""
    return sorted({r.get("run", 0) for r in rows})


def _verified(rows, source=None):
    """The median over the runs of the verified count (of one source), and each run's count."""
    counts = [sum(r["verified"] for r in rows if r.get("run", 0) == k and source in (None, r["source"]))
              for k in _runs(rows)]
    return float(np.median(counts)), counts


def _count(value):
    return f"{value:g}"


def summarise(rows, grasp):
    """Lines of the summary of one grasp type (the median over the runs of the verified count, see --runs)."""
    mine = [r for r in rows if r["grasp"] == grasp]
    if not mine:
        return []
    runs = _runs(mine)
    n = len(mine) // len(runs)
    ok, counts = _verified(mine)
    spread = f", median of {len(runs)} runs: {', '.join(map(str, counts))}" if len(runs) > 1 else ""
    times = np.array([r["time"] for r in mine])
    iterations = np.array([r["iterations"] for r in mine])
    accepted = [r for r in mine if r["success"]]
    q = np.array([r["q_true"] for r in accepted]) if accepted else np.array([np.nan])
    gaps = np.array([r["gap"] for r in accepted]) if accepted else np.array([np.nan])
    closing = sum(r["collision_free"] and r.get("reach_source") == "closing approach" for r in accepted)
    lines = [
        f"{grasp}: {_count(ok)}/{n} verified ({100.0 * ok / n:.1f}%{spread}), by source: "
        + ", ".join(f"{s} {_count(_verified(mine, s)[0])}/{sum(r['source'] == s for r in mine) // len(runs)}"
                    for s in sorted({r["source"] for r in mine})),
        f"  plan time: median {np.median(times):.2f} s, p90 {np.percentile(times, 90):.2f} s, max {times.max():.2f} s; "
        f"iterations per plan: median {np.median(iterations):.0f}, {iterations.sum()} in all",
        f"  accepted {len(accepted)}{f' (the {len(runs)} runs pooled)' if len(runs) > 1 else ''}: median Q on the true surface {np.nanmedian(q):+.3f}, "
        f"Q > -0.01: {np.mean(q > -0.01) * 100:.1f}%, "
        f"contact gap to the true surface median {np.nanmedian(gaps):.1f} mm, max {np.nanmax(gaps):.1f} mm",
        f"  depth in the true mesh of the accepted grasps: phalanges max {_largest(accepted, 'depth'):.1f} mm, "
        f"palm max {_largest(accepted, 'palm_depth'):.1f} mm; collision-free executable reach: "
        f"{sum(r['collision_free'] for r in accepted)}/{len(accepted)}"
        + (f" ({closing} closing the hand on the way)" if closing else ""),
    ]
    failed = Counter(a["outcome"] for r in mine for a in r["attempts"] if a["outcome"] != "grasp")
    refused = Counter(r["reason"].split(":")[0] for r in mine if r["refused"])
    lines.append("  attempts that failed: " + (", ".join(f"{k} {v}" for k, v in failed.most_common()) or "none"))
    if refused:
        lines.append("  objects refused: " + ", ".join(f"{k} {v}" for k, v in refused.most_common()))
    overhang = np.array([r.get("overhang", np.nan) for r in mine])
    lines.append(f"  decomposition: the pieces stick out of the true surface by at most {np.nanmedian(overhang):.1f} mm "
                 f"(median over the objects), {np.nanpercentile(overhang, 90):.1f} mm (p90)")
    unverified = [r for r in accepted if not r["verified"]]
    if unverified:
        lines.append("  accepted but not verified: " + ", ".join(
            f"{r['name']}{_run_tag(r, runs)} (gap {r['gap']:.1f} mm, hull {'closed' if r['closed'] else 'open'}, depth {r['depth']:.1f}, palm {r['palm_depth']:.1f} mm)"
            for r in unverified))
    return lines


def _run_tag(row, runs):
    """" in run k" when the rows hold several runs."""
    return f" in run {row.get('run', 0)}" if len(runs) > 1 else ""


def _largest(rows, key):
    """Largest value of a key over rows (NaN for none)."""
    values = [r[key] for r in rows]
    return float(np.nanmax(values)) if values else float("nan")


def planner_options(items):
    """``--option NAME=VALUE ...`` as a dict of planner options (the scripts' common flag).

    Each value is a Python literal (number, tuple, bool, None), else the text itself. ValueError for an
    item without ``=``.
    """
    bad = [item for item in items if "=" not in item]
    if bad:
        raise ValueError(f"--option takes NAME=VALUE items, got {bad}")
    return {name: _literal(value) for name, value in (item.split("=", 1) for item in items)}


def check_options(options):
    """Refuse (ValueError, TypeError) options `sg.plan` would refuse, before any object is planned: a refused
    option would otherwise read as a refused object on every row. The planner checks them on a built-in
    object's first iteration."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        sg.plan(sg.objects.ellipsoid(), "precision", **{"max_iter": 1, "time_limit": 0.1, **options, "executable_reach": False})


def _literal(text):
    """``text`` as a Python literal, else the text itself."""
    try:
        return ast.literal_eval(text)
    except (ValueError, SyntaxError):
        return text


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--split", default="test", choices=SPLITS + ("all",),
                        help="split of objectset.py to plan; all: train and test (default test)")
    parser.add_argument("--grasp", nargs="+", default=["precision", "power"], choices=["precision", "power"],
                        help="grasp types to plan (default both)")
    parser.add_argument("--only", nargs="+", metavar="NAME", help="object names or prefixes (e.g. urdf/)")
    parser.add_argument("--option", nargs="+", default=[], metavar="NAME=VALUE", help="planner options")
    parser.add_argument("--runs", type=positive(int), default=1, help="plan every object this many times (a median count)")
    parser.add_argument("--jobs", type=positive(int), default=1, help="worker processes")
    parser.add_argument("--out", type=output_folder, default=None,
                        help="folder of the rows (default bench-out/generalise, and bench-out/generalise-sizes for "
                             "--urdf-sizes other than the benchmark's)")
    parser.add_argument("--docs", action="store_true",
                        help=f"write {PAGE.relative_to(ROOT)}, its figure and the README summary")
    parser.add_argument("--quick", action="store_true", help=f"only {', '.join(QUICK)}")
    parser.add_argument("--rows", action="store_true",
                        help="plan nothing: summarise (and with --docs, write the docs from) the rows already in --out")
    parser.add_argument("--cloud", type=int, default=None, metavar="N",
                        help="plan each object from N points sampled on its surface (sg.objects.from_points), and "
                             "verify on its mesh")
    parser.add_argument("--noise", type=float, default=0.0, metavar="MM",
                        help="with --cloud: Gaussian noise of this standard deviation (mm) added to every coordinate")
    parser.add_argument("--pose", type=int, default=None, metavar="SEED",
                        help=f"turn each object about its centre by a rotation drawn uniformly and put its centre {SHIFT:g} mm "
                             "from the origin, "
                             "from SEED and its name (the planner should not care where an object is, nor how it is "
                             "turned)")
    parser.add_argument("--urdf-sizes", nargs="+", type=positive(float), default=list(URDF_SIZES), metavar="MM",
                        help="sizes of the random_urdfs shapes (default: the benchmark's); with --only urdf/, a sweep "
                             "of sizes, split by shape as the benchmark")
    args = parser.parse_args(argv)
    args.urdf_sizes = list(dict.fromkeys(args.urdf_sizes))
    sweep = tuple(args.urdf_sizes) != URDF_SIZES
    if args.docs and (sweep or args.cloud is not None or args.pose is not None):
        parser.error("--docs writes the benchmark's page: it takes the benchmark's --urdf-sizes and meshes, in their "
                     "own pose, only (no --cloud nor --pose)")
    if args.pose is not None and args.pose < 0:
        parser.error(f"--pose must be a seed >= 0, got {args.pose}")
    if args.cloud is not None and args.cloud < 100:
        parser.error(f"--cloud must be at least 100 points, got {args.cloud}")
    if not args.noise >= 0 or (args.noise and args.cloud is None):
        parser.error(f"--noise must be >= 0 mm and needs --cloud, got {args.noise}")
    if args.out is None:  # a sweep's rows never replace the benchmark's (which --rows --docs would document)
        args.out = Path("bench-out") / ("generalise" + ("-sizes" if sweep else "") + ("-cloud" if args.cloud else "")
                                        + ("-posed" if args.pose is not None else ""))
    try:
        options = planner_options(args.option)
        check_options(options)
        if args.only and not args.quick:
            select(args.split, args.only, tuple(args.urdf_sizes))
    except (TypeError, ValueError) as exc:
        parser.error(str(exc))
    rows = _read_rows(args.out, args.split, args.grasp) if args.rows else _plan_all(args, options)
    summary = [line for grasp in args.grasp for line in summarise(rows, grasp)]
    print("\n".join(summary))
    if args.docs:
        _write_docs(rows, args.split, options, summary)


def _plan_all(args, options):
    """Plan and verify every (object, grasp) task of the run; the rows, also written to --out."""
    sizes = tuple(args.urdf_sizes)
    entries = select("all" if args.quick else args.split, QUICK if args.quick else args.only, sizes)
    tasks = [(k, e.name, g) for k in range(args.runs) for g in args.grasp for e in entries]
    rows = []
    with ProcessPoolExecutor(args.jobs) as pool:
        futures = [(k, pool.submit(run, name, grasp, options, sizes, args.cloud, args.noise, args.pose))
                   for k, name, grasp in tasks]
        for k, future in futures:
            rows.append({**future.result(), "run": k})
            print_row(rows[-1], f"run {k} " if args.runs > 1 else "")
    write_rows(rows, args.out, args.split)
    return rows


def print_row(row, prefix=""):
    """One line of a planned row: name, grasp, verified, time, reason."""
    print(f"{prefix}{row['name']:32s} {row['grasp']:9s} {'ok' if row['verified'] else 'NO':3s} {row['time']:6.2f} s  "
          f"{row['reason'][:90]}", flush=True)


def write_rows(rows, out, split):
    """The rows as ``out/<split>_<grasp>.jsonl``, one file per grasp type (what ``--rows`` reads)."""
    out.mkdir(parents=True, exist_ok=True)
    for grasp in sorted({r["grasp"] for r in rows}):
        with open(out / f"{split}_{grasp}.jsonl", "w") as f:
            f.writelines(json.dumps(r) + "\n" for r in rows if r["grasp"] == grasp)


def _read_rows(out, split, grasps):
    """The rows of an earlier run, from ``out/<split>_<grasp>.jsonl``."""
    rows = []
    for grasp in grasps:
        path = out / f"{split}_{grasp}.jsonl"
        if not path.is_file():
            raise SystemExit(f"no rows at {path}: run without --rows first")
        rows += [json.loads(line) for line in path.read_text().splitlines()]
    return rows


def plot(rows, path):
    """The figure of a run: the verified share per source and grasp, and the plan times (cumulative; runs pooled)."""
    import matplotlib  # noqa: PLC0415 - only for the docs

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt  # noqa: PLC0415

    grasps = [g for g in ("precision", "power") if any(r["grasp"] == g for r in rows)]
    sources = sorted({r["source"] for r in rows})
    fig, (bars, times) = plt.subplots(1, 2, figsize=(10, 3.8))
    width = 0.8 / len(grasps)
    for k, grasp in enumerate(grasps):
        shares = []
        for source in sources:
            mine = [r for r in rows if r["grasp"] == grasp and r["source"] == source]
            shares.append(100.0 * sum(r["verified"] for r in mine) / max(len(mine), 1))
        x = np.arange(len(sources)) + (k - (len(grasps) - 1) / 2) * width
        bars.bar(x, shares, width, label=grasp)
        mine = sorted(r["time"] for r in rows if r["grasp"] == grasp)
        ok = sorted(r["time"] for r in rows if r["grasp"] == grasp and r["verified"])
        times.step(ok, 100.0 * np.arange(1, len(ok) + 1) / len(mine), where="post", label=f"{grasp}: verified")
    bars.set_xticks(np.arange(len(sources)), sources)
    bars.set_ylabel("verified (%)")
    bars.set_ylim(0, 118)
    bars.set_yticks(range(0, 101, 20))
    bars.axhline(95, color="grey", lw=0.8, ls="--")
    bars.legend(loc="upper center", ncol=2)
    bars.set_title("verified grasps by source")
    times.set_xscale("log")
    times.set_xlabel("plan time (s, wall clock)")
    times.set_ylabel("objects with a verified grasp by then (%)")
    times.set_ylim(0, 100)
    times.legend(loc="upper left")
    times.set_title("plan time")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def per_object(rows):
    """Per (object, grasp), in order: its first run's row, "yes"/"no" (or "k/R" when the runs differ), its median time."""
    groups = {}
    for r in rows:
        groups.setdefault((r["name"], r["grasp"]), []).append(r)
    for mine in groups.values():
        ok = sum(r["verified"] for r in mine)
        verified = "yes" if ok == len(mine) else "no" if ok == 0 else f"{ok}/{len(mine)}"
        yield mine[0], verified, float(np.median([r["time"] for r in mine]))


def _write_docs(rows, split, options, summary):
    """The results page and the README's summary lines."""
    runs = len(_runs(rows))
    lines = [
        "# Generalisation",
        "",
        f"Written by `python benchmarks/generalise.py --split {split}{f' --runs {runs}' if runs > 1 else ''} --docs`"
        + (f" with options {options}" if options else "") + ".",
        "",
        "```text",
        *summary,
        "```",
        "",
        f"![Verified grasps by source and plan times, {split} split](figures/{FIGURE.name})",
        "",
        *([f"With {runs} runs, an object's *verified* says in how many runs it was, its time is the median of "
           "its runs' and the other columns are its first run's.", ""] if runs > 1 else []),
        "| object | source | grasp | verified | time (s) | attempts | Q | Q on the true surface | gap (mm) | pieces' overhang (mm) | reason |",
        "|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for r, verified, seconds in per_object(rows):
        lines.append(f"| {r['name']} | {r['source']} | {r['grasp']} | {verified} | {seconds:.2f} "
                     f"| {r.get('n_attempts', '')} | {r.get('q', float('nan')):.3f} | {r.get('q_true', float('nan')):.3f} "
                     f"| {r.get('gap', float('nan')):.1f} | {r.get('overhang', float('nan')):.1f} | {r['reason'][:80]} |")
    PAGE.write_text("\n".join(lines) + "\n")
    FIGURE.parent.mkdir(parents=True, exist_ok=True)
    plot(rows, FIGURE)
    heads = [line for line in summary if not line.startswith(" ")]
    write_between_markers(ROOT / "README.md", *README_MARKERS, "\n".join(f"- **{line}**" for line in heads))
    print(f"wrote {PAGE}")


if __name__ == "__main__":
    main()
