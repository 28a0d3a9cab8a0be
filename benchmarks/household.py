"""Success rate of the planner on household-sized objects beyond the paper's four.

Usage::

    python benchmarks/household.py [--meshes DIR] [--scale S] [--grasp precision|power|both] [--only NAME ...]

Plans a precision and a power grasp of every object and counts the plans that
end in a grasp verified on the object's true mesh (``verification.py``: the
contacts within 5 mm of it, force-closed by qhull at its normals, no phalanx
capsule and not the palm box deeper than 3 mm in it). The objects are

* 22 modelled and scanned meshes in ``benchmarks/meshes`` (household objects,
  toys, the Stanford bunny, random everyday-like shapes; sources and licences in
  ``benchmarks/meshes/SOURCES.md``), in millimetres at hand size;
* 22 turned and extruded household shapes built here (bottles, mugs, cans,
  fruit, boxes...);
* with ``--meshes``, every mesh or point-cloud file in another folder
  (``--scale 1000`` for files in metres), e.g. the YCB set.

The rate is reported for each grasp type, over all objects and per group.
"""

from __future__ import annotations

import argparse
import time
import sys
import warnings
from pathlib import Path

import numpy as np
import trimesh

sys.path.insert(0, str(Path(__file__).resolve().parent))

import synergrasp as sg  # noqa: E402
from synergrasp.cli import positive, write_between_markers  # noqa: E402
from synergrasp.planner import ObjectRefused  # noqa: E402
from verification import verify  # noqa: E402

#: The committed modelled and scanned meshes (mm).
MESHES = Path(__file__).parent / "meshes"


def _profile(*points):
    return np.array(points, dtype=float)


def household_objects():
    """Household-sized shapes (mm): name -> GraspObject."""
    revolve = sg.objects.revolve
    box = lambda x, y, z, name: sg.objects.from_mesh(trimesh.creation.box((x, y, z)), name=name, cache=False)  # noqa: E731
    capsule = lambda r, h, name: sg.objects.from_mesh(trimesh.creation.capsule(height=h, radius=r), name=name, cache=False)  # noqa: E731
    t = np.linspace(0, np.pi, 25)
    objects = {
        "water bottle": revolve(_profile((32, 0), (33, 150), (28, 175), (14, 195), (14, 215)), name="water bottle"),
        "wine bottle": revolve(_profile((37, 0), (37, 200), (15, 240), (13, 290)), name="wine bottle"),
        "soda can": revolve(_profile((30, 0), (33, 10), (33, 105), (28, 118)), name="soda can"),
        "mug body": revolve(_profile((38, 0), (41, 95)), name="mug body"),
        "drinking glass": revolve(_profile((28, 0), (36, 120)), name="drinking glass"),
        "jar": revolve(_profile((40, 0), (42, 90), (30, 100), (30, 115)), name="jar"),
        "apple": revolve(np.c_[38 * np.sin(t) * (1 - 0.1 * np.cos(t)), 75 * (1 - np.cos(t)) / 2], name="apple"),
        "orange": revolve(np.c_[37 * np.sin(t), 37 * (1 - np.cos(t))], name="orange"),
        "pear": revolve(_profile((0, 0), (30, 5), (36, 30), (30, 60), (20, 85), (12, 100), (0, 105)), name="pear"),
        "egg": revolve(np.c_[22 * np.sin(t) * (1 + 0.15 * np.cos(t)), 58 * (1 - np.cos(t)) / 2], name="egg"),
        "tennis ball": revolve(np.c_[33 * np.sin(t), 33 * (1 - np.cos(t))], name="tennis ball"),
        "bowl": revolve(_profile((35, 0), (70, 55)), name="bowl"),
        "spray bottle": revolve(_profile((34, 0), (34, 160), (20, 175), (12, 200)), name="spray bottle"),
        "salt shaker": revolve(_profile((22, 0), (18, 40), (22, 75), (16, 85)), name="salt shaker"),
        "lemon (turned)": revolve(np.c_[28 * np.sin(t), 80 * (1 - np.cos(t)) / 2], name="lemon (turned)"),
        "cereal box": box(60, 190, 270, "cereal box"),
        "tissue box": box(120, 120, 130, "tissue box"),
        "phone": box(75, 150, 8, "phone"),
        "remote control": box(45, 170, 22, "remote control"),
        "soap bar": box(60, 90, 30, "soap bar"),
        "banana-sized capsule": capsule(18, 140, "banana-sized capsule"),
        "marker pen": capsule(9, 120, "marker pen"),
    }
    return objects


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--meshes", type=Path, help="a folder of mesh or point-cloud files to add")
    parser.add_argument("--scale", type=positive(float), default=1.0, help="scale of the files in --meshes (1000 for metres)")
    parser.add_argument("--grasp", choices=["precision", "power", "both"], default="both",
                        help="grasp type(s) to plan (default both)")
    parser.add_argument("--only", nargs="+", metavar="NAME", help="plan only these objects")
    parser.add_argument("--docs", action="store_true",
                        help=f"write the table to {PAGE.relative_to(ROOT)}, the galleries to {FIGURES.relative_to(ROOT)} "
                             "and the rates to the README")
    args = parser.parse_args(argv)
    if args.meshes is not None and not args.meshes.is_dir():
        parser.error(f"--meshes {args.meshes} is not a folder: name a folder of mesh or point-cloud files")
    warnings.simplefilter("ignore")
    groups = {"meshes": mesh_files(MESHES, 1.0), "shapes": household_objects()}
    if args.meshes:
        groups[str(args.meshes)] = mesh_files(args.meshes, args.scale)
    unknown = sorted(set(args.only or ()) - {name for objects in groups.values() for name in objects})
    if unknown:
        parser.error(f"--only names objects the benchmark does not hold: {unknown}")
    grasps = ["precision", "power"] if args.grasp == "both" else [args.grasp]
    rows = []
    for group, objects in groups.items():
        for name, obj in objects.items():
            if not args.only or name in args.only:
                rows += [_run(group, name, obj, grasp) for grasp in grasps]
    summary = [_rate(rows, grasp, groups) for grasp in grasps]
    print("\n".join(summary))
    if args.docs:
        _write_docs(rows, grasps, summary)


def mesh_files(folder, scale):
    """Mesh and point-cloud files of a folder: name -> GraspObject."""
    return {
        path.stem: sg.objects.load(path, scale=scale)
        for path in sorted(Path(folder).iterdir())
        if path.suffix.lower() in sg.objects.SUPPORTED_FORMATS
    }


def _run(group, name, obj, grasp):
    """Plan one grasp; a row of the table (dict) with the result and the object."""
    start = time.perf_counter()
    try:
        result = sg.plan(obj, grasp)
        ok, why = verify(result, obj)["verified"], result.reason
    except ObjectRefused as exc:  # an object the hand cannot hold
        result, ok, why = None, False, str(exc)
    row = dict(group=group, name=name, grasp=grasp, ok=ok, time=time.perf_counter() - start, reason=why,
               result=result, obj=obj)
    print(f"{name:22s} {grasp:9s} {'ok' if ok else 'NO':3s} {row['time']:6.2f} s  {why[:90]}", flush=True)
    return row


def _rate(rows, grasp, groups):
    """One line: verified plans of one grasp type, over all objects and per group."""
    mine = [r for r in rows if r["grasp"] == grasp]
    parts = ", ".join(f"{g} {sum(r['ok'] for r in mine if r['group'] == g)}/{sum(r['group'] == g for r in mine)}"
                      for g in groups if any(r["group"] == g for r in mine))
    ok = sum(r["ok"] for r in mine)
    return f"{grasp}: {ok}/{len(mine)} verified force-closed grasps ({100.0 * ok / max(len(mine), 1):.0f}%; {parts})"


ROOT = Path(__file__).resolve().parents[1]
PAGE = ROOT / "docs" / "household-objects.md"
FIGURES = ROOT / "docs" / "figures" / "household"
README_MARKERS = ("<!-- household:start -->", "<!-- household:end -->")


def _write_docs(rows, grasps, summary):
    """The docs page (rates, one row per object) and a gallery of final grasps per grasp type."""
    from synergrasp import viz

    FIGURES.mkdir(parents=True, exist_ok=True)
    hand = sg.SynergyHand.default()
    lines = [
        "# Household objects",
        "",
        "Plans beyond the paper's four objects, written by `python benchmarks/household.py --docs`: a",
        "precision and a power grasp of 22 modelled and scanned meshes (`benchmarks/meshes`, sources in",
        "its `SOURCES.md`) and 22 turned and extruded household shapes built by the script, all with the",
        "default options. A plan counts when the paper's stop criterion is met, the origin lies strictly",
        "inside the convex hull of the final contact wrenches (an independent check of force closure) and",
        "no phalanx is deeper than 3 mm in the object.",
        "",
        *[f"- **{line}**" for line in summary],
        "",
    ]
    for grasp in grasps:
        mine = [r for r in rows if r["grasp"] == grasp]
        shown = [(r["result"], r["obj"], f"{r['name']}: {'ok' if r['ok'] else 'failed'}") for r in mine if r["result"]]
        figure = viz.plot_grasps(shown, hand, FIGURES / f"{grasp}.png", columns=8)
        lines += [f"## {grasp.capitalize()} grasps", "", f"![Final {grasp} grasps](figures/household/{figure.name})", "",
                  "| object | group | verified | attempts | iterations | contacts | g_Q | penetration (mm) | time (s) |",
                  "|---|---|---|---|---|---|---|---|---|"]
        for r in mine:
            res = r["result"]
            if res is None:
                lines.append(f"| {r['name']} | {r['group']} | no: {r['reason']} | | | | | | |")
                continue
            lines.append(
                f"| {r['name']} | {r['group']} | {'yes' if r['ok'] else 'no'} | {len(res.attempts)} | {res.total_iterations} "
                f"| {len(res.contact_labels)} | {res.final_q:.3f} | {res.penetration:.1f} | {r['time']:.2f} |"
            )
        lines.append("")
    PAGE.write_text("\n".join(lines))
    readme = ROOT / "README.md"
    write_between_markers(readme, *README_MARKERS, "\n".join(f"- **{line}**" for line in summary))
    print(f"wrote {PAGE}, {FIGURES} and the summary in {readme}")


if __name__ == "__main__":
    main()
