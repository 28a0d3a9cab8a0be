"""Benchmarks of synergrasp.objects: cP and sQ queries, built-ins, loading and its cache.

Run: ``python benchmarks/bench_objects.py [--quick] [--backend highs]``. Prints
median wall-clock times (many repetitions); no figure is asserted here.

* cP, 16 hand points around the goblet 0-40 mm from its surface (like a hand's
  power points), values and gradients, one call: median ms.
* sQ contacts for the same points; cP/sQ for 5 points on the ellipsoid.
* Loading a ~10k-face non-convex mesh (a mug: a hollow cylinder with a
  handle, subdivided) from .obj: first load (CoACD decomposition), cached load.
"""

from __future__ import annotations

import argparse
import os
import statistics
import tempfile
import time
from pathlib import Path

import numpy as np
import trimesh

import synergrasp.objects as so
from synergrasp.cli import backend


def hand_like_points(obj, n=16, gap=(0.0, 40.0), seed=0):
    """n points 0-40 mm off the object's surface along its outward normals."""
    rng = np.random.default_rng(seed)
    mesh = obj.to_mesh()
    surface, face = trimesh.sample.sample_surface(mesh, n, seed=seed)
    return surface + rng.uniform(*gap, size=(n, 1)) * mesh.face_normals[face]


def median_ms(fn, repeat):
    fn()  # warm-up (imports, caches, solver basis)
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        fn()
        times.append(time.perf_counter() - start)
    return 1e3 * statistics.median(times)


def mug_mesh():
    """A non-convex mug of about 10k faces: a hollow turned body (watertight) and a ring handle."""
    t = np.linspace(0.0, np.pi / 2, 8)
    outer = np.column_stack([40.0 - 4.0 * (1 - np.sin(t)), 4.0 * (1 - np.cos(t))])  # rounded bottom edge
    profile = np.vstack(
        [[0.0, 0.0], outer, [40.0, 95.0], [38.5, 96.5], [36.0, 95.0], [35.0, 12.0], [30.0, 8.0], [0.0, 8.0]]
    )
    body = trimesh.creation.revolve(profile, sections=256)
    if body.volume < 0:
        body.invert()
    handle = trimesh.creation.torus(major_radius=24.0, minor_radius=5.5, major_sections=64, minor_sections=24)
    handle.apply_transform(trimesh.transformations.rotation_matrix(np.pi / 2, [1, 0, 0]))
    handle.apply_translation([58.0, 0.0, 50.0])
    return trimesh.util.concatenate([body, handle])


def torus_mesh(target_faces=10_000):
    """A torus (watertight, non-convex) with about target_faces faces."""
    sections = int(round(np.sqrt(target_faces / 4)))
    return trimesh.creation.torus(
        major_radius=40.0, minor_radius=12.0, major_sections=2 * sections, minor_sections=sections
    )


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--backend", type=backend, default="native", help="LP backend (default native)")
    parser.add_argument("--quick", action="store_true", help="fewer repetitions, skip the mesh loads")
    args = parser.parse_args()
    repeat = 30 if args.quick else 300

    goblet = so.goblet()
    pts = hand_like_points(goblet)
    r = goblet.contact_distance(pts, backend=args.backend)
    print(f"goblet: {goblet.n_pieces} pieces, {[len(v) for v in goblet.pieces]} vertices")
    print(f"  16 points, cP range {r.value.min():.1f}..{r.value.max():.1f}, candidates/point {r.candidates.mean():.2f}")
    t = median_ms(lambda: goblet.contact_distance(pts, backend=args.backend), repeat)
    print(f"  cP 16 points ({args.backend}): median {t:.2f} ms")
    rng = np.random.default_rng(1)
    moving = lambda: pts + rng.normal(scale=0.3, size=pts.shape)  # noqa: E731 - like a planner step
    t = median_ms(lambda: goblet.contact_distance(moving(), backend=args.backend), repeat)
    print(f"  cP 16 points moving 0.3 mm per call (no warm start): median {t:.2f} ms")
    t = median_ms(lambda: goblet.scaled_contacts(pts, backend=args.backend), repeat)
    print(f"  sQ 16 points ({args.backend}): median {t:.2f} ms")
    t = median_ms(lambda: goblet.scaled_contacts(moving(), backend=args.backend), repeat)
    print(f"  sQ 16 points moving: median {t:.2f} ms")

    ell = so.ellipsoid()
    pts5 = hand_like_points(ell, n=5, gap=(0.0, 60.0), seed=1)
    t = median_ms(lambda: ell.contact_distance(pts5, backend=args.backend), repeat)
    print(f"ellipsoid ({len(ell.pieces[0])} vertices): cP 5 points median {t:.2f} ms")
    t = median_ms(lambda: ell.scaled_contacts(pts5, backend=args.backend), repeat)
    print(f"ellipsoid: sQ 5 points median {t:.2f} ms")

    for name in so.BUILTINS:
        t = median_ms(lambda: so.get(name), 5 if args.quick else 20)
        print(f"build {name}: median {t:.1f} ms")

    if args.quick:
        return
    with tempfile.TemporaryDirectory() as tmp:
        os.environ["SYNERGRASP_CACHE"] = str(Path(tmp) / "cache")
        for label, mesh in (("torus", torus_mesh()), ("mug", mug_mesh())):
            path = Path(tmp) / f"{label}.obj"
            mesh.export(path)
            start = time.perf_counter()
            obj = so.load(path)
            first = time.perf_counter() - start
            start = time.perf_counter()
            again = so.load(path)
            second = time.perf_counter() - start
            print(
                f"load {label} ({len(mesh.faces)} faces, watertight {mesh.is_watertight}): "
                f"first {first:.2f} s ({obj.info['method']}, {obj.n_pieces} pieces), "
                f"cached {1e3 * second:.0f} ms (cache {again.info['cache']})"
            )
            pts = hand_like_points(obj)
            t = median_ms(lambda: obj.contact_distance(pts, backend=args.backend), 50)
            print(f"  cP 16 points on {label}: median {t:.2f} ms")


if __name__ == "__main__":
    main()
