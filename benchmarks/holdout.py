"""Objects no benchmark holds: random_urdfs shapes outside the generalisation benchmark, at sizes it does not use.

Usage::

    python benchmarks/holdout.py [--count 40] [--size 100] [--grasp precision power] [--wheel PATH]
                                 [--jobs N] [--out DIR]

The generalisation benchmark (``objectset.py``) holds 60 of the 1000 random compound shapes of
pybullet_data's ``random_urdfs`` at 80 and 120 mm, and the household set six more. This script draws
``--count`` of the others (``numpy.random.default_rng(SEED).choice`` over the numbers neither uses),
scales each to a largest extent of ``--size`` mm, plans each grasp type with the default options
and verifies the plan on the true mesh as ``generalise.py`` does, then prints ``generalise.py``'s
summary. No planner setting is chosen on these objects: they check the test split's figures on
other shapes, and (``--size``) at other sizes.

The meshes come from the ``pybullet`` 3.2.7 wheel on PyPI (zlib licence, Bullet Physics), fetched
with ``pip download pybullet==3.2.7`` into ``DIR`` unless ``--wheel`` names it, and are
written as STL (centred on their bounding box) under ``DIR/meshes``. Rows go to
``DIR/holdout_<grasp>.jsonl`` (default ``bench-out/holdout``).
"""

from __future__ import annotations

import argparse
import io
import subprocess
import sys
import warnings
import zipfile
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np
import trimesh

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

import synergrasp as sg  # noqa: E402
from synergrasp.cli import output_folder, positive  # noqa: E402
from generalise import plan_row, print_row, summarise, write_rows  # noqa: E402
from objectset import MESHES, URDFS  # noqa: E402

#: Seed of the draw (the benchmark's own draw used 2026).
SEED = 1129
#: The wheel the meshes come from.
VERSION = "3.2.7"


def unused_numbers() -> list[str]:
    """The random_urdfs numbers (``"000"`` ... ``"999"``) that neither the benchmark nor the household set holds."""
    used = {p.stem for p in URDFS.glob("*.stl")} | {p.stem.removeprefix("random_") for p in MESHES.glob("random_*.stl")}
    return [f"{i:03d}" for i in range(1000) if f"{i:03d}" not in used]


def draw(count: int) -> list[str]:
    """The ``count`` numbers of the holdout set, ascending (a fixed draw: the first ones of a larger draw differ)."""
    rest = unused_numbers()
    if not 1 <= count <= len(rest):
        raise ValueError(f"--count must be between 1 and {len(rest)}, got {count}")
    return sorted(np.random.default_rng(SEED).choice(rest, count, replace=False).tolist())


def fetch_wheel(folder: Path) -> Path:
    """The pybullet wheel in ``folder``, downloaded there with pip (no cache, no build) when it is not."""
    pattern = f"pybullet-{VERSION}-*.whl"
    if not any(folder.glob(pattern)):
        command = [sys.executable, "-m", "pip", "download", f"pybullet=={VERSION}", "--no-deps", "--no-cache-dir",
                   "--only-binary=:all:", "--quiet", "-d", str(folder)]
        if subprocess.run(command).returncode != 0:
            raise SystemExit(f"could not download pybullet {VERSION} (no network?): download its wheel elsewhere and "
                             "pass it with --wheel")
    found = sorted(folder.glob(pattern))
    if not found:
        raise SystemExit(f"pip download left no pybullet {VERSION} wheel in {folder}; pass one with --wheel")
    return found[0]


def extract(wheel: Path, numbers, folder: Path) -> list[Path]:
    """Write each number's mesh from the wheel as ``folder/NNN.stl``, centred on its bounding box."""
    folder.mkdir(parents=True, exist_ok=True)
    paths = []
    with zipfile.ZipFile(wheel) as z:
        members = set(z.namelist())
        for k in numbers:
            path = folder / f"{k}.stl"
            if not path.is_file():
                member = f"pybullet_data/random_urdfs/{k}/{k}.obj"
                if member not in members:
                    raise SystemExit(f"{wheel} has no {member}: pass the pybullet {VERSION} wheel with --wheel")
                data = z.read(member)
                mesh = trimesh.load(io.BytesIO(data), file_type="obj", force="mesh")
                mesh.apply_translation(-mesh.bounds.mean(axis=0))
                mesh.export(path)
            paths.append(path)
    return paths


def run(path, size, grasp):
    """Plan and verify one holdout object: a JSON-able row (``generalise.plan_row``'s)."""
    warnings.simplefilter("ignore")
    mesh = trimesh.load(path, force="mesh")
    name = f"{Path(path).stem}@{size:g}"
    obj = sg.objects.from_mesh(mesh, size / float(mesh.extents.max()), name=f"urdf {name}")
    return plan_row(obj, grasp, {}, name=f"holdout/{name}", source="holdout", split="holdout")


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--count", type=positive(int), default=40, help="objects drawn")
    parser.add_argument("--size", type=positive(float), default=100.0, help="largest extent (mm)")
    parser.add_argument("--grasp", nargs="+", default=["precision", "power"], choices=["precision", "power"],
                        help="grasp types to plan")
    parser.add_argument("--wheel", type=Path, help="the pybullet wheel (default: downloaded into --out)")
    parser.add_argument("--jobs", type=positive(int), default=1, help="worker processes")
    parser.add_argument("--out", type=output_folder, default="bench-out/holdout", help="folder of the rows")
    args = parser.parse_args(argv)
    if args.wheel is not None and not zipfile.is_zipfile(args.wheel):
        parser.error(f"--wheel {args.wheel} is not a wheel (a zip file): pass the pybullet {VERSION} wheel, or leave "
                     "--wheel out to download it")
    try:
        numbers = draw(args.count)
    except ValueError as exc:
        parser.error(str(exc))
    wheel = args.wheel if args.wheel is not None else fetch_wheel(args.out)
    paths = extract(wheel, numbers, args.out / "meshes")
    tasks = [(path, grasp) for grasp in args.grasp for path in paths]
    rows = []
    with ProcessPoolExecutor(args.jobs) as pool:
        for row in pool.map(run, [str(p) for p, _ in tasks], [args.size] * len(tasks), [g for _, g in tasks]):
            rows.append(row)
            print_row(row)
    write_rows(rows, args.out, "holdout")
    summary = [line for grasp in args.grasp for line in summarise(rows, grasp)]
    print("\n".join(summary))
    return rows


if __name__ == "__main__":
    main()
