"""Does the LP verdict (and Q) predict whether a planned grasp holds in MuJoCo?

Usage::

    python benchmarks/physics_study.py [--set paper household train test] [--meshes DIR [--scale S]]
                                       [--option NAME=VALUE ...] [--out DIR] [--quick] [--docs]

Plans a precision and a power grasp of every object of the chosen sets
(default options and LP backend, or the planner options given with
``--option``, as ``generalise.py`` takes them), then

* the LP verdict: the plan succeeded and is verified on the object's true mesh
  (``benchmarks/verification.py``: contacts within 5 mm, force-closed by qhull
  at the mesh's normals, no phalanx capsule and not the palm box deeper than
  3 mm); Q: the plan's final g_Q;
* validates the final configuration in MuJoCo (`synergrasp.validate`) under
  the default protocol (``synergrasp``) and the DexGraspBench-like preset,
  each also with the hand moved 40 mm back (the negative control, which must
  never hold), and under the default with the overlap check off
  (``max_penetration`` = inf, with its negative control too: what the
  physics does with the grasps the check rejects).

It prints, per set and grasp type, the LP rate next to the physical success
rate; the precision and recall of the LP verdict as a predictor of holding;
the Q threshold that best predicts holding (largest TPR - FPR, predicting
"holds" for Q below it); per grasp type, how well the grip after settling
over the object's weight predicts holding (ROC area, beside Q's, and its
best threshold); and, for the paper's cases, why each grasp fails.
On the paper set it also reruns the default protocol with one setting
changed at a time (time step, squeeze, servo stiffness, contact model,
friction): how far the verdicts depend on them.

Sets: ``paper`` (the paper's four objects), ``household`` (the 44 objects of
``benchmarks/household.py``), ``train`` and ``test`` (the generalisation
benchmark's splits: choose a planner option by its physics on ``train``,
report ``test``), and with ``--meshes`` every mesh or point-cloud file of a
folder. Writes under ``--out``
(default ``./bench-out/physics_study``): ``rows.csv``, per case the plan and
its validations as JSON, and the figures. ``--docs`` also writes
``docs/physics-study.md``, its figures in ``docs/figures/physics/`` and the
rates in the README (the default planner only). ``--quick`` (run by the
tests): the ellipsoid only.
"""

from __future__ import annotations

import argparse
import csv
import math
import re
import time
import warnings
from pathlib import Path

import numpy as np

import synergrasp as sg
from synergrasp.cli import output_folder, positive, write_between_markers
from synergrasp.planner import ObjectRefused
from generalise import check_options, planner_options
from household import MESHES, household_objects, mesh_files
from verification import verify
from synergrasp.physics import ball_pinch, hand_without, pinch_grasp

ROOT = Path(__file__).resolve().parents[1]
PAGE = ROOT / "docs" / "physics-study.md"
FIGURES = ROOT / "docs" / "figures" / "physics"
README_MARKERS = ("<!-- physics:start -->", "<!-- physics:end -->")
PAPER = ("ellipsoid", "cup", "bell", "goblet")
GRASPS = ("precision", "power")
#: The validations of every plan: name -> keyword arguments of `synergrasp.validate`.
VARIANTS = {
    "synergrasp": {},
    "synergrasp, 40 mm back": {"retreat": 40.0},
    "overlap ignored": {"max_penetration": math.inf},
    "overlap ignored, 40 mm back": {"max_penetration": math.inf, "retreat": 40.0},
    "dexgraspbench": {"preset": "dexgraspbench"},
    "dexgraspbench, 40 mm back": {"preset": "dexgraspbench", "retreat": 40.0},
}
PRESETS = ("synergrasp", "dexgraspbench")
#: Changes of the default protocol tried on the paper's cases (overlap check off): name -> settings.
SENSITIVITY = {
    "default": {},
    "timestep 4 ms": {"timestep": 0.004},
    "timestep 2 ms": {"timestep": 0.002},
    "timestep 0.5 ms": {"timestep": 0.0005},
    "squeeze 5 mm": {"squeeze": 5.0},
    "squeeze 20 mm": {"squeeze": 20.0},
    "kp 2.5": {"kp": 2.5},
    "kp 10": {"kp": 10.0},
    "point contacts": {"torsional_friction": 0.0},
    "mu 0.6": {"mu": 0.6},
    "mass 0.1 kg": {"mass": 0.1},
}


def object_sets(names, meshes=None, scale=1.0, quick=False):
    """The objects to study: set name -> {object name: GraspObject}."""
    sets = {}
    if "paper" in names:
        sets["paper"] = {name: sg.objects.get(name) for name in (PAPER[:1] if quick else PAPER)}
    if "household" in names:
        sets["household"] = {**mesh_files(MESHES, 1.0), **household_objects()}
    for split in ("train", "test"):  # the generalisation benchmark's splits (benchmarks/objectset.py)
        if split in names:
            from objectset import select

            sets[split] = {e.name: e.make() for e in select(split)}
    if meshes is not None:
        sets[str(meshes)] = mesh_files(meshes, scale)
    return sets


def case_folder(out, group, name, grasp):
    """The folder of one case's files under ``out``."""
    return out / "cases" / "_".join(re.sub(r"[^A-Za-z0-9_]+", "-", part) for part in (group, name, grasp))


def study_case(group, name, obj, grasp, out, options=None):
    """Plan one grasp (with the planner options ``options``, a dict) and validate it every way; one row of the study
    (dict)."""
    folder = case_folder(out, group, name, grasp)
    folder.mkdir(parents=True, exist_ok=True)
    row = dict(set=group, object=name, grasp=grasp)
    start = time.perf_counter()
    try:
        result = sg.plan(obj, grasp, options=sg.planner.PlannerOptions(**(options or {})))
    except ObjectRefused as exc:  # an object the hand cannot hold
        return dict(row, planned=False, lp=False, q=math.nan, plan_s=time.perf_counter() - start, note=str(exc))
    result.save(folder / "plan.json")
    row.update(planned=True, lp=verify(result, obj)["verified"], q=result.final_q, phalanx_penetration=result.penetration,
               plan_s=time.perf_counter() - start, note=result.reason)
    for variant, kwargs in VARIANTS.items():
        try:
            check = sg.validate(result, obj, **kwargs)
        except ValueError as exc:  # e.g. a failed plan whose hand touches nothing
            row[variant] = dict(held=False, outcome="not a grasp", reason=str(exc))
            continue
        check.save(folder / variant_file(variant))
        row[variant] = dict(held=check.held, outcome=check.outcome, reason=check.reason,
                            penetration=check.initial_penetration, body=check.penetration_body, mass=check.object_mass,
                            settle=check.settle_displacement, grip=check.grip_force, cpu=check.cpu_time,
                            displacement=float(np.nanmax(check.displacement, initial=-1.0)),
                            rotation=float(np.nanmax(check.rotation, initial=-1.0)))
    return row


def variant_file(variant):
    """The file name of a variant's validation in a case folder."""
    return f"{variant.replace(', ', '_').replace(' ', '_')}.json"


def held(row, variant):
    return bool(row.get(variant, {}).get("held", False))


def rates(rows, variant):
    """LP rate, physical rate, precision and recall of the LP verdict as a predictor of holding."""
    lp = np.array([r["lp"] for r in rows], bool)
    ok = np.array([held(r, variant) for r in rows], bool)
    precision = (lp & ok).sum() / lp.sum() if lp.any() else math.nan
    recall = (lp & ok).sum() / ok.sum() if ok.any() else math.nan
    return dict(n=len(rows), lp=int(lp.sum()), held=int(ok.sum()), both=int((lp & ok).sum()),
                precision=precision, recall=recall)


def q_threshold(rows, variant):
    """The threshold t on Q that best predicts holding (Q < t), by the largest TPR - FPR.

    Returns
    -------
    dict or None
        ``t``, ``tpr``, ``fpr``, ``accuracy``, ``n``; None if every grasp with a
        Q held or none did (no threshold separates anything).
    """
    return best_threshold([(r["q"], held(r, variant)) for r in rows], below=True)


def grip_ratio(row, variant):
    """The grip after settling over the object's weight (MuJoCo's normal forces / m g), NaN without a simulation."""
    v = row.get(variant, {})
    grip, mass = v.get("grip", math.nan), v.get("mass", math.nan)
    return grip / (mass * 9.81) if v.get("outcome") not in (None, "penetration", "not a grasp") and mass > 0 else math.nan


def grip_threshold(rows, variant):
    """The threshold t on the grip over the weight that best predicts holding (ratio > t), as `best_threshold`."""
    return best_threshold([(grip_ratio(r, variant), held(r, variant)) for r in rows], below=False)


def best_threshold(data, below):
    """The threshold t on a score that best predicts holding, by the largest TPR - FPR, and the ROC area.

    Parameters
    ----------
    data : list of (float, bool)
        Score and whether the grasp held; NaN scores are left out.
    below : bool
        Holding is predicted for scores below t (else above).

    Returns
    -------
    dict or None
        ``t``, ``tpr``, ``fpr``, ``accuracy``, ``n``, ``auc`` (the area under the
        ROC curve: the chance that a grasp that held scores better than one that
        did not, ties counted half); None if every grasp with a score held or
        none did (no threshold separates anything).
    """
    data = [(x, ok) for x, ok in data if np.isfinite(x)]
    if not data:
        return None
    x, ok = np.array(data, dtype=float).T
    ok = ok.astype(bool)
    if ok.all() or not ok.any():
        return None
    score = -x if below else x  # higher: predicted to hold
    better = (score[ok][:, None] > score[~ok][None, :]).mean() + 0.5 * (score[ok][:, None] == score[~ok][None, :]).mean()
    values = np.unique(x)
    candidates = np.r_[values[0] - 1e-9, (values[1:] + values[:-1]) / 2, values[-1] + 1e-9]
    best = None
    for t in candidates:
        predicted = x < t if below else x > t
        tpr, fpr = (predicted & ok).sum() / ok.sum(), (predicted & ~ok).sum() / (~ok).sum()
        key = (tpr - fpr, -abs(t))
        if best is None or key > best[0]:
            best = (key, dict(t=float(t), tpr=float(tpr), fpr=float(fpr), accuracy=float((predicted == ok).mean()),
                              n=len(x), auc=float(better)))
    return best[1]


def sensitivity(out):
    """Outcomes under changes of the default protocol (rows of a Markdown table).

    Rows: the grasps built by construction (`synergrasp.physics.probes`),
    then the paper's planned cases. The overlap check is off in every
    column, so that each case is simulated.
    """
    hand = sg.SynergyHand.default()
    cases = [("box pinch", "thumb, index", *pinch_grasp(hand), hand),
             ("ball pinch", "thumb, index (a two-finger hand)", *ball_pinch(hand), hand_without(hand, "M", "R", "L"))]
    for grasp in GRASPS:
        for name in PAPER:
            result = sg.PlanResult.load(out / "cases" / f"paper_{name}_{grasp}" / "plan.json")
            cases.append((name, grasp, result, sg.objects.get(name), hand))
    lines = []
    for name, kind, grasp, obj, grasping_hand in cases:
        cells = []
        for settings in SENSITIVITY.values():
            check = sg.validate(grasp, obj, hand=grasping_hand, max_penetration=math.inf, **settings)
            worst = np.nanmax(check.displacement, initial=math.nan)
            cells.append(check.outcome + ("" if np.isnan(worst) else f" ({worst:.1f} mm)"))
        lines.append(f"| {name} | {kind} | " + " | ".join(cells) + " |")
        print(lines[-1], flush=True)
    return lines


def summary(rows, sets):
    """Lines: per set and grasp type, LP and physical rates and the negative controls."""
    lines = []
    for group in sets:
        for grasp in GRASPS:
            mine = [r for r in rows if r["set"] == group and r["grasp"] == grasp]
            if not mine:
                continue
            own, anchors = rates(mine, "synergrasp"), rates(mine, "dexgraspbench")
            negatives = ", ".join(f"{v.split(',')[0]} {sum(held(r, v) for r in mine)}/{len(mine)}"
                                  for v in VARIANTS if v.endswith("40 mm back"))
            lines.append(f"{group}, {grasp}: LP verdict {own['lp']}/{own['n']}, held in MuJoCo {own['held']}/{own['n']} "
                         f"(synergrasp protocol), {anchors['held']}/{anchors['n']} (dexgraspbench); "
                         f"negative controls (40 mm back) held: {negatives}")
    return lines


def prediction(rows):
    """Lines: precision, recall and the best Q threshold for each preset."""
    lines = []
    for variant in PRESETS:
        r = rates(rows, variant)
        t = q_threshold(rows, variant)
        threshold = ("no threshold: " + ("every grasp held" if r["held"] == r["n"] else "no grasp held")) if t is None \
            else f"Q < {t['t']:+.3f} predicts holding (TPR {t['tpr']:.2f}, FPR {t['fpr']:.2f}, accuracy {t['accuracy']:.2f}, n = {t['n']})"
        lines.append(f"{variant}: LP verdict as a predictor of holding: precision {_fmt(r['precision'])} "
                     f"({r['both']}/{r['lp']}), recall {_fmt(r['recall'])} ({r['both']}/{r['held']}); {threshold}")
        for grasp in GRASPS:
            g = grip_threshold([row for row in rows if row["grasp"] == grasp], variant)
            if g is not None:
                lines.append(f"{variant}, {grasp}: the grip after settling over the weight predicts holding with a ROC "
                             f"area of {g['auc']:.2f} (Q: {_fmt(_q_auc(rows, variant, grasp))}); above {g['t']:.1f} "
                             f"(TPR {g['tpr']:.2f}, FPR {g['fpr']:.2f}, n = {g['n']})")
    return lines


def _q_auc(rows, variant, grasp):
    """The ROC area of Q (lower: holds) on the grasps of one type that the grip's line counts."""
    t = best_threshold([(r["q"] if np.isfinite(grip_ratio(r, variant)) else math.nan, held(r, variant))
                        for r in rows if r["grasp"] == grasp], below=True)
    return math.nan if t is None else t["auc"]


def _fmt(x):
    return "-" if x != x else f"{x:.2f}"


def case_table(rows):
    """Markdown table: every case, why it fails under each protocol."""
    head = ["| set | object | grasp | LP | Q | synergrasp | initial penetration (mm) | mass (g) | squeeze shift (mm) "
            "| grip (N) | overlap ignored | dexgraspbench | 40 mm back (synergrasp, overlap ignored, dexgraspbench) |",
            "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    lines = []
    for r in rows:
        if not r["planned"]:
            lines.append(f"| {r['set']} | {r['object']} | {r['grasp']} | no plan: {r['note']} | | | | | | | | | |")
            continue
        own = r["synergrasp"]
        pen = f"{own.get('penetration', math.nan):.1f}" + (f" ({own['body']})" if own.get("body") else "")
        neg = ", ".join(r[v]["outcome"] for v in VARIANTS if v.endswith("40 mm back"))
        lines.append(
            f"| {r['set']} | {r['object']} | {r['grasp']} | {'yes' if r['lp'] else 'no'} | {r['q']:+.3f} "
            f"| {own['outcome']}: {own['reason']} | {pen} | {1e3 * own.get('mass', math.nan):.0f} "
            f"| {own.get('settle', math.nan):.1f} | {own.get('grip', math.nan):.1f} "
            f"| {r['overlap ignored']['outcome']} | {r['dexgraspbench']['outcome']} | {neg} |")
    return head + lines


def plot(rows, path):
    """Q against held for both presets (one panel each), the best threshold as a line."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, len(PRESETS), figsize=(10, 3.2), sharex=True)
    rng = np.random.default_rng(0)
    top = 0.1  # failed plans reach Q of several units: drawn at the right edge
    for ax, variant in zip(axes, PRESETS):
        for grasp, colour in zip(GRASPS, ("tab:blue", "tab:orange")):
            for lp, marker in ((True, "o"), (False, "x")):
                mine = [r for r in rows if r["grasp"] == grasp and r["lp"] == lp and np.isfinite(r["q"])]
                if mine:
                    y = np.array([held(r, variant) for r in mine], float) + rng.uniform(-0.12, 0.12, len(mine))
                    ax.scatter([min(r["q"], top) for r in mine], y, c=colour, marker=marker, s=22,
                               label=f"{grasp}, LP {'yes' if lp else 'no'}")
        t = q_threshold(rows, variant)
        if t is not None:
            ax.axvline(t["t"], color="k", ls="--", lw=1)
        ax.set_yticks([0, 1], ["not held", "held"])
        ax.set_xlabel(f"Q (final g_Q; above {top:g} drawn at {top:g})")
        ax.set_title(f"protocol {variant}", fontsize=10)
    axes[0].legend(fontsize=7, loc="center left")
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path


def write_csv(rows, path):
    fields = ["set", "object", "grasp", "planned", "lp", "q", "plan_s"]
    with open(path, "w", newline="") as f:
        writer = csv.writer(f)
        writer.writerow(fields + [f"{v}: {k}" for v in VARIANTS for k in ("held", "outcome", "penetration", "reason")])
        for r in rows:
            cells = [r.get(k, "") for k in fields]
            for v in VARIANTS:
                check = r.get(v, {})
                cells += [check.get("held", ""), check.get("outcome", ""), check.get("penetration", ""), check.get("reason", "")]
            writer.writerow(cells)
    return path


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--set", nargs="+", choices=["paper", "household", "train", "test"],
                        default=["paper", "household"],
                        help="object sets (default paper and household; train, test: the generalisation benchmark's "
                             "splits)")
    parser.add_argument("--meshes", type=Path, help="also every mesh or point-cloud file of this folder")
    parser.add_argument("--scale", type=positive(float), default=1.0, help="scale of the files in --meshes (1000 for metres)")
    parser.add_argument("--out", type=output_folder, default="bench-out/physics_study", help="output folder")
    parser.add_argument("--option", nargs="+", default=[], metavar="NAME=VALUE", help="planner options")
    parser.add_argument("--quick", action="store_true", help="the paper's ellipsoid only, no time-step check")
    parser.add_argument("--docs", action="store_true",
                        help=f"write {PAGE.relative_to(ROOT)}, its figures and the README's physics lines")
    args = parser.parse_args(argv)
    try:
        options = planner_options(args.option)
        check_options(options)  # a bad option fails here, before any work
    except (TypeError, ValueError) as exc:
        parser.error(str(exc))
    if args.docs and options:
        parser.error("--docs writes the study of the default planner: drop --option")
    warnings.simplefilter("ignore")
    sets = object_sets(["paper"] if args.quick else args.set, args.meshes, args.scale, args.quick)
    rows = []
    for group, objects in sets.items():
        for name, obj in objects.items():
            for grasp in GRASPS:
                rows.append(study_case(group, name, obj, grasp, args.out, options))
                r = rows[-1]
                own = r.get("synergrasp", {})
                print(f"{group:9s} {name:22s} {grasp:9s} LP {'yes' if r['lp'] else 'no ':3s} Q {r['q']:+.3f} "
                      f"{own.get('outcome', 'not planned'):11s} {own.get('reason', r.get('note', ''))[:90]}", flush=True)
    lines = summary(rows, sets) + prediction(rows)
    print("\n".join(lines))
    changes = sensitivity(args.out) if "paper" in sets and not args.quick else []
    files = [write_csv(rows, args.out / "rows.csv"), plot(rows, args.out / "q_vs_held.png")]
    print("wrote " + ", ".join(str(f) for f in files))
    if args.docs:
        write_docs(rows, lines, changes)


def write_docs(rows, lines, changes):
    """The results page, its figure and the README lines."""
    FIGURES.mkdir(parents=True, exist_ok=True)
    plot(rows, FIGURES / "q_vs_held.png")
    groups = list(dict.fromkeys(r["set"] for r in rows))
    sizes = {g: len({r["object"] for r in rows if r["set"] == g}) for g in groups}
    named = {"paper": "the paper's four objects", "household": f"the {sizes.get('household')} household objects",
             "train": f"the {sizes.get('train')} objects of the generalisation benchmark's train split",
             "test": f"the {sizes.get('test')} objects of the generalisation benchmark's test split"}
    objects = [named.get(g, f"the {sizes[g]} files of {g}") for g in groups]
    text = [
        "# Physics study",
        "",
        "Do the planner's grasps hold in MuJoCo, and does the LP verdict (or Q) predict it? Written by",
        f"`python benchmarks/physics_study.py --set {' '.join(groups)} --docs`: a precision and a power grasp of",
        f"{', '.join(objects[:-1]) + ' and ' if len(objects) > 1 else ''}{objects[-1]}, planned with the default "
        "options, each validated as the",
        "[physics validation](concepts/physics-validation.md) page describes: under the project's protocol",
        "(`synergrasp`), the DexGraspBench-like preset, both with the hand moved 40 mm back (negative",
        "controls), and under the project's protocol with the overlap check off (`overlap ignored`, with its",
        "negative control too: what the simulation does with the grasps the check rejects). The LP verdict",
        "is the plan's success, verified as on the [household objects](household-objects.md) page.",
        "",
        *[f"- {line}" for line in lines],
        "",
        "![Q against held, both protocols: circles LP-verified, crosses not; dashed: the best threshold]"
        "(figures/physics/q_vs_held.png)",
        "",
        "## Every case",
        "",
        "Outcomes: `held`; `penetration` (the hand overlaps the object deeper than the protocol's",
        "`max_penetration` at the planned configuration; not simulated); `unstable`; `no contact` (the",
        "squeeze pushed the object out of the hand); `slip` (moved too far under a push); `rotation`",
        "(turned too far). The squeeze shift is how far the object moved while the fingers closed.",
        "",
        *case_table(rows),
        "",
    ]
    if changes:
        text += ["## Sensitivity to the protocol's settings", "",
                 "The grasps built by construction (a box and a ball pinched between the thumb and index tips,",
                 "`synergrasp.physics.probes`) and the paper's cases under the project's protocol with one setting",
                 "changed (the overlap check off in every column, so that each case is simulated), with the largest",
                 "displacement under a push (mm). The time-step columns check the integration; the others show how",
                 "far the verdicts depend on the hand's strength, the squeeze, the contact model and the friction.", "",
                 "| grasp | kind | " + " | ".join(SENSITIVITY) + " |",
                 "|---|---|" + "---|" * len(SENSITIVITY), *changes, ""]
    PAGE.write_text("\n".join(text))
    readme = ROOT / "README.md"
    write_between_markers(readme, *README_MARKERS, "\n".join(f"- {line}" for line in lines))
    print(f"wrote {PAGE}, {FIGURES} and the physics lines in {readme}")


if __name__ == "__main__":
    main()
