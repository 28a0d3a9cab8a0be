"""The generalisation benchmark's objects, from three sources, with a fixed train/test split.

* ``household``: the 44 objects of ``benchmarks/household.py`` (22 modelled and scanned meshes, 22
  turned and extruded shapes).
* ``urdf``: 60 of the 1000 random compound shapes of pybullet_data's ``random_urdfs`` (files in
  ``benchmarks/meshes/random_urdfs``, picked by a seeded draw, see ``SOURCES.md`` there), each at
  two sizes: largest extent 80 mm and 120 mm.
* ``procedural``: 105 shapes built here from a seeded random draw, 5 of each of 21 families (boxes,
  cylinders, cones, spheres, ellipsoids, tori, mugs with a handle, thin plates, bowls, capsules,
  L- and T-shapes, rounded boxes, random convex polytopes, smooth blobs, prisms, handle bars,
  dumbbells, and small objects of 16-45 mm: ellipsoids, boxes and cylinders).

That is 269 objects. The split is fixed by the object's *base* name (the shape, whatever its
size): an object is in ``test`` when the first byte of the SHA-256 of its base name is below 128,
else in ``train``. Options, orders and thresholds of the planner are chosen on ``train`` only;
``test`` is reported.

Usage::

    python benchmarks/objectset.py [--split train|test|all]   # list the objects and their split
"""

from __future__ import annotations

import argparse
import hashlib
import sys
from dataclasses import dataclass
from pathlib import Path
from typing import Callable

import numpy as np
import trimesh

import synergrasp as sg

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

from household import MESHES, household_objects  # noqa: E402

#: Folder of the random_urdfs meshes (raw units of the source, centred on their bounding box).
URDFS = MESHES / "random_urdfs"
#: Largest extent (mm) of each random_urdfs shape, one object per size.
URDF_SIZES = (80.0, 120.0)
#: Procedural shapes per family.
PER_FAMILY = 5
#: Seed of the procedural draw.
SEED = 2026
SPLITS = ("train", "test")


@dataclass(frozen=True)
class Entry:
    """One benchmark object.

    Attributes
    ----------
    name : str
        Unique name, ``source/base`` or ``source/base@size``.
    source : str
        ``"household"``, ``"urdf"`` or ``"procedural"``.
    base : str
        The shape, whatever its size; it fixes the split.
    make : callable
        Builds the `GraspObject` (mm).
    """

    name: str
    source: str
    base: str
    make: Callable

    @property
    def split(self) -> str:
        """``"test"`` or ``"train"``, from the SHA-256 of the base name."""
        return split_of(self.base)


def split_of(base: str) -> str:
    """The split of a shape: ``"test"`` when the first byte of sha256(base) is below 128.

    Parameters
    ----------
    base : str

    Returns
    -------
    str
    """
    return "test" if hashlib.sha256(base.encode()).digest()[0] < 128 else "train"


# --------------------------------------------------------------------------- procedural shapes


def _mesh(mesh, name):
    return sg.objects.from_mesh(mesh, name=name)


def _union(*meshes):
    return trimesh.boolean.union(list(meshes), engine="manifold")


def _difference(a, b):
    return trimesh.boolean.difference([a, b], engine="manifold")


def _box(r):
    return trimesh.creation.box((r.uniform(25, 80), r.uniform(30, 120), r.uniform(30, 160)))


def _cylinder(r):
    return trimesh.creation.cylinder(radius=r.uniform(15, 40), height=r.uniform(40, 160), sections=48)


def _cone(r):
    r1, r2, h = r.uniform(20, 42), r.uniform(5, 30), r.uniform(40, 140)
    return trimesh.creation.revolve(np.array([[0.0, 0.0], [r1, 0.0], [r2, h], [0.0, h]]), sections=48)


def _sphere(r):
    return trimesh.creation.icosphere(subdivisions=3, radius=r.uniform(22, 45))


def _ellipsoid(r):
    m = trimesh.creation.icosphere(subdivisions=3, radius=1.0)
    m.apply_scale(r.uniform(15, 50, size=3))
    return m


def _torus(r):
    return trimesh.creation.torus(major_radius=r.uniform(28, 45), minor_radius=r.uniform(7, 14), major_sections=48,
                                  minor_sections=16)


def _mug(r):
    radius, height, wall = r.uniform(30, 42), r.uniform(70, 110), 4.0
    body = trimesh.creation.cylinder(radius=radius, height=height, sections=48)
    hollow = trimesh.creation.cylinder(radius=radius - wall, height=height, sections=48)
    hollow.apply_translation((0, 0, wall))
    handle = trimesh.creation.torus(major_radius=0.3 * height, minor_radius=5.0, major_sections=32, minor_sections=12)
    handle.apply_transform(trimesh.transformations.rotation_matrix(np.pi / 2, (1, 0, 0)))
    handle.apply_translation((radius, 0, 0))
    return _union(_difference(body, hollow), handle)


def _plate(r):
    return trimesh.creation.box((r.uniform(60, 120), r.uniform(50, 90), r.uniform(4, 12)))


def _bowl(r):
    radius, wall = r.uniform(40, 65), 4.0
    outer = trimesh.creation.icosphere(subdivisions=4, radius=radius)
    inner = trimesh.creation.icosphere(subdivisions=4, radius=radius - wall)
    lid = trimesh.creation.box((3 * radius, 3 * radius, 2 * radius))
    lid.apply_translation((0, 0, radius))
    return _difference(_difference(outer, inner), lid)


def _capsule(r):
    return trimesh.creation.capsule(height=r.uniform(60, 150), radius=r.uniform(10, 25))


def _l_shape(r):
    t, a, b = r.uniform(15, 35), r.uniform(60, 120), r.uniform(50, 100)
    w = r.uniform(20, 50)
    leg1 = trimesh.creation.box((a, w, t))
    leg1.apply_translation((a / 2, 0, t / 2))
    leg2 = trimesh.creation.box((t, w, b))
    leg2.apply_translation((t / 2, 0, b / 2))
    return _union(leg1, leg2)


def _t_shape(r):
    t, a, b, w = r.uniform(15, 30), r.uniform(70, 130), r.uniform(50, 110), r.uniform(20, 45)
    bar = trimesh.creation.box((a, w, t))
    bar.apply_translation((0, 0, b + t / 2))
    stem = trimesh.creation.box((t, w, b))
    stem.apply_translation((0, 0, b / 2))
    return _union(bar, stem)


def _rounded_box(r):
    half, rounding = r.uniform(15, 50, size=3), r.uniform(4, 12)
    corners = np.array(np.meshgrid(*[(-h, h) for h in half])).reshape(3, -1).T
    ball = trimesh.creation.icosphere(subdivisions=2, radius=rounding)
    return trimesh.convex.convex_hull(np.vstack([ball.vertices + c for c in corners]))


def _random_convex(r):
    points = r.normal(size=(r.integers(8, 30), 3)) * r.uniform(15, 45, size=3)
    return trimesh.convex.convex_hull(points)


def _blob(r):
    m = trimesh.creation.icosphere(subdivisions=4, radius=1.0)
    v = m.vertices
    k = r.normal(size=(6, 3))
    bump = sum(r.uniform(0.1, 0.25) * np.sin(v @ k[i] * r.uniform(1.5, 3.0) + r.uniform(0, 2 * np.pi)) for i in range(6))
    m.vertices = v * (1.0 + bump)[:, None] * r.uniform(28, 45)
    return m


def _prism(r):
    sides = int(r.choice([3, 4, 5, 6, 8]))
    return trimesh.creation.cylinder(radius=r.uniform(18, 40), height=r.uniform(40, 150), sections=sides)


def _handle_bar(r):
    return trimesh.creation.cylinder(radius=r.uniform(8, 14), height=r.uniform(100, 180), sections=32)


def _small_round(r):
    m = trimesh.creation.icosphere(subdivisions=3, radius=1.0)
    m.apply_scale(r.uniform(10, 20, size=3))
    return m


def _small_box(r):
    return trimesh.creation.box(r.uniform(18, 40, size=3))


def _small_cylinder(r):
    return trimesh.creation.cylinder(radius=r.uniform(8, 16), height=r.uniform(20, 45), sections=32)


def _dumbbell(r):
    ball, length, bar = r.uniform(18, 30), r.uniform(90, 150), r.uniform(8, 14)
    a, b = trimesh.creation.icosphere(3, ball), trimesh.creation.icosphere(3, ball)
    a.apply_translation((0, 0, -length / 2))
    b.apply_translation((0, 0, length / 2))
    return _union(a, b, trimesh.creation.cylinder(radius=bar, height=length, sections=32))


FAMILIES = {
    "box": _box, "cylinder": _cylinder, "cone": _cone, "sphere": _sphere, "ellipsoid": _ellipsoid,
    "torus": _torus, "mug": _mug, "plate": _plate, "bowl": _bowl, "capsule": _capsule, "l_shape": _l_shape,
    "t_shape": _t_shape, "rounded_box": _rounded_box, "random_convex": _random_convex, "blob": _blob,
    "prism": _prism, "handle_bar": _handle_bar, "dumbbell": _dumbbell,
    "small_round": _small_round, "small_box": _small_box, "small_cylinder": _small_cylinder,
}


def _procedural(family, index):
    def make():
        rng = np.random.default_rng([SEED, list(FAMILIES).index(family), index])
        mesh = FAMILIES[family](rng)
        mesh.apply_translation(-mesh.bounds.mean(axis=0))
        return _mesh(mesh, f"{family}_{index}")

    return make


def _urdf(path, size):
    def make():
        mesh = trimesh.load(path, force="mesh")
        return sg.objects.from_mesh(mesh, size / float(mesh.extents.max()), name=f"urdf {path.stem}@{size:g}")

    return make


def catalogue(urdf_sizes=URDF_SIZES) -> list[Entry]:
    """Every object of the benchmark, in a fixed order (nothing is built until ``make()``).

    Parameters
    ----------
    urdf_sizes : sequence of float
        The sizes of the random_urdfs shapes (default `URDF_SIZES`; others for a sweep of sizes
        outside the benchmark, the split unchanged since it goes by shape).

    Returns
    -------
    list of Entry
    """
    entries = []
    household = None

    def from_household(name):
        def make():
            nonlocal household
            if household is None:
                household = household_objects()
            return household[name]

        return make

    for path in sorted(MESHES.glob("*.stl")):
        entries.append(Entry(f"household/{path.stem}", "household", f"household/{path.stem}",
                             (lambda p=path: sg.objects.load(p))))
    for name in _household_shape_names():
        entries.append(Entry(f"household/{name}", "household", f"household/{name}", from_household(name)))
    for path in sorted(URDFS.glob("*.stl")):
        for size in urdf_sizes:
            entries.append(Entry(f"urdf/{path.stem}@{size:g}", "urdf", f"urdf/{path.stem}", _urdf(path, size)))
    for family in FAMILIES:
        for index in range(PER_FAMILY):
            entries.append(Entry(f"procedural/{family}_{index}", "procedural", f"procedural/{family}_{index}",
                                 _procedural(family, index)))
    return entries


def _household_shape_names():
    """Names of household.py's built shapes, read without building them."""
    import ast
    import inspect

    tree = ast.parse(inspect.getsource(household_objects))
    for node in ast.walk(tree):
        if isinstance(node, ast.Dict):
            return [k.value for k in node.keys]
    raise RuntimeError("household_objects() has no dict of shapes")


def select(split="all", only=None, urdf_sizes=URDF_SIZES) -> list[Entry]:
    """The entries of one split (``"train"``, ``"test"`` or ``"all"``), optionally only some names.

    Parameters
    ----------
    split : str
    only : sequence of str, optional
        Names or name prefixes (``"urdf/"``) to keep; one that names no object of the split is refused
        (ValueError).
    urdf_sizes : sequence of float
        See `catalogue`.

    Returns
    -------
    list of Entry
    """
    if split not in SPLITS + ("all",):
        raise ValueError(f"split must be one of {SPLITS + ('all',)}, got {split!r}")
    chosen = [e for e in catalogue(urdf_sizes) if split == "all" or e.split == split]
    if only:
        unknown = [o for o in only if not any(e.name == o or e.name.startswith(o) for e in chosen)]
        if unknown:
            raise ValueError(f"{unknown} name no object of the {split!r} split: give names such as "
                             f"{', '.join(e.name for e in chosen[:: max(1, len(chosen) // 3)][:3])}, or prefixes such "
                             "as urdf/ (python benchmarks/objectset.py lists them)")
        chosen = [e for e in chosen if any(e.name == o or e.name.startswith(o) for o in only)]
    return chosen


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--split", default="all", choices=SPLITS + ("all",),
                        help="split to list; all: train and test (default all)")
    parser.add_argument("--build", action="store_true", help="build every object (fills the decomposition cache)")
    args = parser.parse_args(argv)
    entries = select(args.split)
    for e in entries:
        line = f"{e.split:5s} {e.name}"
        if args.build:
            line += f"  {e.make()!r}"
        print(line, flush=True)
    counts = {s: sum(e.split == s for e in entries) for s in SPLITS}
    print(f"{len(entries)} objects: " + ", ".join(f"{s} {n}" for s, n in counts.items()))


if __name__ == "__main__":
    main()
