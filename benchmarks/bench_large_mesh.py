"""Bounded resources: load and plan a large mesh, with wall time, CPU time and peak memory.

Usage::

    python benchmarks/bench_large_mesh.py [--faces 330000] [--open] [--mesh FILE [--scale S]]
                                          [--grasp precision|power] [--quick] [--out DIR]

Writes a torus of about ``--faces`` triangles (100 mm across, 40 mm major and 15 mm minor
radius: non-convex, so it is decomposed with CoACD) to a temporary STL file, or takes
``--mesh``, then in a fresh Python process loads it with ``sg.objects.load`` (no
decomposition cache, so the decomposition is measured) and plans a grasp. ``--open`` removes two
faces of the torus that touch at a vertex: an open scan that can be neither capped (it is closed on
a voxel grid) nor simplified, so the planner's surface tests run on every face. Reports the wall
and CPU time of the load and of the plan, the peak resident memory of that process
(``ru_maxrss``: everything, Python and the imported libraries included) and the plan's
outcome. ``--quick`` uses a 5,000-face torus (the test suite runs it). The figures go to
stdout and to ``--out``/large_mesh.json (default ``./bench-out``). The targets are under a
minute and under 4 GB for 330,000 faces.
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import tempfile
from pathlib import Path

from synergrasp.cli import output_folder, positive

#: What the child process runs: load, plan, measure. argv: path, scale, grasp.
CHILD = r"""
import json, resource, sys, time, warnings
warnings.simplefilter("ignore")
t0, c0 = time.perf_counter(), time.process_time()
import synergrasp as sg
path, scale, grasp = sys.argv[1], float(sys.argv[2]), sys.argv[3]
t1, c1 = time.perf_counter(), time.process_time()
obj = sg.objects.load(path, scale=scale, cache=False)
t2, c2 = time.perf_counter(), time.process_time()
result = sg.plan(obj, grasp)
t3, c3 = time.perf_counter(), time.process_time()
print(json.dumps({
    "import_s": t1 - t0, "load_s": t2 - t1, "load_cpu_s": c2 - c1, "plan_s": t3 - t2, "plan_cpu_s": c3 - c2,
    "total_s": t3 - t0, "peak_rss_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0,
    "faces": len(obj.mesh.faces), "pieces": obj.n_pieces, "method": obj.info["method"],
    "success": result.success, "iterations": result.total_iterations, "reason": result.reason,
}))
"""


def torus(faces: int, opened: bool = False):
    """A torus of about ``faces`` triangles (mm); ``opened``: less two faces that touch at a vertex."""
    import numpy as np
    import trimesh

    minor = max(8, int(round(np.sqrt(faces / 4.0))))
    mesh = trimesh.creation.torus(major_radius=40.0, minor_radius=15.0, major_sections=2 * minor, minor_sections=minor)
    if opened:  # two holes touching at vertex 0: it can be neither capped nor simplified
        fan = np.flatnonzero((mesh.faces == 0).any(axis=1))
        apart = next(f for f in fan[1:] if len(set(mesh.faces[f]) & set(mesh.faces[fan[0]])) == 1)
        keep = np.ones(len(mesh.faces), dtype=bool)
        keep[[fan[0], apart]] = False
        mesh.update_faces(keep)
    return mesh


def measure(path, scale=1.0, grasp="precision") -> dict:
    """Load and plan ``path`` in a fresh process; its timings and peak memory."""
    root = Path(__file__).resolve().parents[1]
    env_path = str(root)
    proc = subprocess.run([sys.executable, "-c", CHILD, str(path), str(scale), grasp], capture_output=True, text=True,
                          env={**__import__("os").environ, "PYTHONPATH": env_path}, timeout=3600)
    if proc.returncode != 0:
        raise SystemExit(f"the measurement failed:\n{proc.stderr}")
    return json.loads(proc.stdout.strip().splitlines()[-1])


def main(argv=None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--faces", type=positive(int), default=330_000, help="triangles of the generated torus (default 330000)")
    parser.add_argument("--mesh", type=Path, help="a mesh file to measure instead of the torus")
    parser.add_argument("--scale", type=positive(float), default=1.0, help="scale of --mesh to mm (1000 for metres)")
    parser.add_argument("--grasp", choices=["precision", "power"], default="precision",
                        help="grasp type to plan (default precision)")
    parser.add_argument("--open", action="store_true",
                        help="two faces of the torus removed, touching at a vertex (an open scan that can be neither "
                        "capped nor simplified)")
    parser.add_argument("--quick", action="store_true", help="a 5000-face torus")
    parser.add_argument("--out", type=output_folder, default="bench-out", help="output folder (default ./bench-out)")
    args = parser.parse_args(argv)
    if args.open and args.mesh is not None:
        parser.error("--open removes faces of the generated torus: it does not take --mesh")
    if args.mesh is not None and not args.mesh.is_file():
        parser.error(f"--mesh {args.mesh} is not a file: name a mesh file")
    with tempfile.TemporaryDirectory() as folder:
        if args.mesh is not None:
            path = args.mesh
        else:
            path = Path(folder) / "torus.stl"
            torus(5000 if args.quick else args.faces, opened=args.open).export(path)
        row = measure(path, args.scale if args.mesh is not None else 1.0, args.grasp)
    row.update(mesh=str(args.mesh or ("open torus" if args.open else "torus")), grasp=args.grasp)
    print(f"{row['mesh']}: {row['faces']} faces -> {row['pieces']} pieces ({row['method']}); "
          f"load {row['load_s']:.1f} s wall ({row['load_cpu_s']:.1f} s CPU), {args.grasp} plan {row['plan_s']:.1f} s wall "
          f"({row['plan_cpu_s']:.1f} s CPU, {row['iterations']} iterations, {'success' if row['success'] else 'no grasp'}); "
          f"whole process {row['total_s']:.1f} s, peak memory {row['peak_rss_mb']:.0f} MB")
    (args.out / "large_mesh.json").write_text(json.dumps(row, indent=1))
    return row


if __name__ == "__main__":
    main()
