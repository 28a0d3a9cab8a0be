"""Plan a precision grasp of an object read from a mesh file.

By default the script writes a small mesh with trimesh, a capsule 70 mm wide and 130 mm long
(a bottle-sized solid), to a temporary ``.stl`` file, loads it with ``sg.objects.load(path)``
and plans a precision grasp of it. Pass ``--mesh`` to use your own file instead (any format
``sg.objects.load`` reads: .obj .stl .ply .off .glb .gltf, or a point cloud), with ``--scale``
if it is not in millimetres (``--scale 1000`` for metres).

``sg.objects.load`` takes a watertight, (nearly) convex mesh as its convex hull and cuts any
other into convex parts (CoACD, a few seconds the first time, then read from the on-disk
cache); ``obj.info`` says which. The script prints the object, then the plan's outcome: success
with its contacts and quality, or the reason no grasp was found. It saves the ``PlanResult``
and a figure of the hand's poses into ``--out``.

Usage::

    python examples/plan_mesh_file.py [--out DIR] [--mesh FILE [--scale S]]   # default ./examples-out
"""

import argparse
import sys
import tempfile
from pathlib import Path

import trimesh

import synergrasp as sg
from synergrasp import viz
from synergrasp.cli import output_folder, output_stem, positive


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=output_folder, default="examples-out", help="output folder (default ./examples-out)")
    parser.add_argument("--mesh", help="a mesh or point-cloud file to grasp (default: a generated capsule)")
    parser.add_argument("--scale", type=positive(float), default=1.0, help="factor to millimetres (1000 for metres)")
    args = parser.parse_args(argv)
    if args.scale != 1.0 and not args.mesh:
        parser.error("--scale applies to a --mesh file; the generated capsule is in mm")
    out = args.out

    if args.mesh:
        try:
            obj = sg.objects.load(args.mesh, scale=args.scale)
        except (OSError, TypeError, ValueError) as exc:  # no such file, not a mesh, no volume...
            parser.error(str(exc))
    else:
        with tempfile.TemporaryDirectory() as folder:
            path = Path(folder) / "capsule.stl"
            trimesh.creation.capsule(height=60.0, radius=35.0, count=[32, 32]).export(path)   # mm, along z
            print(f"wrote a temporary mesh {path.name} ({path.stat().st_size} bytes)")
            # a one-off temporary file: no use caching its decomposition
            obj = sg.objects.load(path, cache=False)
    print(f"loaded {obj}: method {obj.info['method']!r}, watertight {obj.info.get('watertight')}, "
          f"centre {obj.center.round(1) + 0.0} mm")

    hand = sg.SynergyHand.default()
    try:
        result = sg.plan(obj, "precision", hand=hand)
    except sg.planner.ObjectRefused as exc:  # e.g. an object too large for the hand, or in the wrong units
        sys.exit(f"cannot plan: {exc}")
    if result.success:
        print(f"success: {result.reason}")
        print(f"contacts {', '.join(result.contact_labels)}, g_Q {result.final_q:+.4f}, "
              f"penetration {result.penetration:.2f} mm, {result.iterations} iterations, {result.time_s:.1f} s")
    else:
        print(f"no grasp: {result.reason}")
    stem = out / output_stem(obj.name, "precision")  # the extension too: mug.stl and mug.ply do not collide
    files = [result.save(f"{stem}.json"), viz.plot_poses(result, obj, hand, f"{stem}_poses.png")]
    print("wrote " + ", ".join(str(f) for f in files))


if __name__ == "__main__":
    main()
