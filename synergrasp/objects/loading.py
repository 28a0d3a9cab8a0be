"""Loading objects: mesh files, point clouds, convex decomposition and its disk cache.

* Meshes (any format trimesh reads: .obj .stl .ply .off .glb .gltf): parts
  of negligible volume lying apart from the rest or enclosing nothing (a
  scan's specks, a ground plane: ``DEBRIS_FRACTION``, `drop_debris`) are
  dropped first, with a warning. Closed
  shells that pass through each other (an assembly exported as one mesh) are
  joined into their union (`union_of_bodies`, with a warning). A watertight
  mesh whose volume is more than ``CONVEX_RATIO`` (0.97) of its hull's is
  taken as its hull (unless it is more than the hull's, which no solid's is:
  a surface that passes through itself, decomposed with a warning); otherwise
  it is decomposed into at most
  ``max_parts`` convex parts with CoACD (approximate convex decomposition,
  the ``coacd`` package; ``COACD_PARAMS``: remeshed on a grid of at least 20
  voxels along the longest side and of voxels at most ``VOXEL_PITCH`` (12 mm)
  wide (`coacd_resolution`), then concavity threshold 0.07 with a light tree
  search, about 4-10 s for a 10k-face mesh on 2 cores), run in a child
  process (`run_coacd`): a mesh it does not finish within
  ``DECOMPOSITION_TIME_LIMIT`` seconds (CoACD loops on some shapes, such as
  two bodies a few mm apart) is decomposed from its surface samples like a
  point cloud (below), with a warning; the cache keeps that limit, and a
  load under a longer one tries CoACD again. A mesh that is not
  watertight has no inside to decompose. A watertight mesh wound inward is turned outward first
  (`orient_outward`, with a warning). An open one is closed first where that is sound (`close_mesh`:
  seams welded, planar holes capped; ``info["repair"]`` says what changed)
  and then treated like a watertight one. One that cannot be closed so (its
  holes are not planar, its edges non-manifold) is closed on a voxel grid:
  its vertices and ``OPEN_MESH_SAMPLES`` points sampled on its surface are a
  point cloud whose enclosed solid is clustered (below); if that encloses no
  volume either, the mesh is refused with the reason. Either way a warning
  says what was done. A mesh whose parts lie more than ``PART_GAP`` apart
  (`separate_parts`: several objects in one file, a scan's loose fragment)
  is planned as one rigid object, with a warning that says so.
* Point clouds (.ply without faces, .xyz, .npy, .npz, or an array): stray
  points first dropped (a scan's outliers, alone or in small groups:
  `STRAY_FACTOR`), then a small
  cloud, or a convex one (no facet of its hull farther than ``CLOUD_CONCAVITY``
  = 3 % of its size, or 4 sampling spacings, from its points), is one
  hull. Otherwise the cloud is voxelised, its gaps closed and its inside
  filled, and the filled voxels are clustered by k-means; k grows
  (2, 3, 4, 6, 8, 12, 16, ... up to ``max_parts``) until every cluster is
  convex by the same test, and each cluster's hull (its voxel centres and the
  cloud points nearest to it) is a piece. The solid includes what an opening
  leaves open to one side only: a voxel that sees the surface along five of
  the six axis directions is inside (the cloud of a box without its lid, or a
  scan that missed one side, is the whole box). A cloud of one side of an object (one camera
  view) is a shell that encloses nothing: it is closed by its hull, flat behind. Any cloud whose
  outward normals do not balance (`PointSurface.net_normal` longer than ``ONE_SIDED``) is warned
  of as seen from one side. A cloud that hides few of its points along some line of sight
  (`PointSurface.view_direction`, at most ``ONE_VIEW``) is one camera view: its pieces are swept
  away from the camera as far again as the view is deep (what the camera did not see is solid),
  and it is warned of as such.

Every piece keeps at most ``max_vertices`` hull vertices (farthest-point
sampling), which bounds the LP sizes of the cP and sQ queries.

Decompositions and clusterings are cached on disk, in ``$SYNERGRASP_CACHE``
or ``~/.cache/synergrasp``, keyed by the SHA-256 of the geometry read (the
vertices and faces, from every file a format names, or the points) and the
parameters; a cached load reads the pieces back
(``obj.info["cache"] == "hit"``). The pieces are computed before scaling; the
key holds the decomposition's grid resolution, which depends on the scaled size
above 240 mm (`coacd_resolution`), and, when debris was dropped (which depends
on the scale through ``PART_GAP``), what was kept. So the same file at another
scale is a hit as long as those stay the same.
"""

from __future__ import annotations

import hashlib
import json
import math
import os
import re
import sys
import warnings
from pathlib import Path

import numpy as np
import trimesh

from .._checks import as_path, as_points, integer, positive_scalar
from .._files import atomic_path
from .convex import SIZE_LIMITS, ConvexPiece, checked_hull
from .decompose import DecompositionTimeout, run_coacd
from .grasp_object import GraspObject
from .point_surface import PointSurface
from .repair import (
    MAX_CAP_FRACTION,
    MAX_PARTS,
    PLANARITY,
    TURNED_OUTWARD,
    WELD_TOLERANCE,
    RepairError,
    close_mesh,
    drop_debris,
    joining_gap,
    orient_outward,
    separate_parts,
    union_of_bodies,
)

#: Mesh file extensions (read with trimesh).
MESH_FORMATS = (".obj", ".stl", ".ply", ".off", ".glb", ".gltf")
#: Point-cloud file extensions (.ply without faces is a cloud too).
POINT_FORMATS = (".xyz", ".npy", ".npz", ".ply")
#: Every extension `load` accepts.
SUPPORTED_FORMATS = tuple(sorted(set(MESH_FORMATS + POINT_FORMATS)))
#: A watertight mesh with volume / hull volume above this (and not above 1, which no solid's is) is treated as convex.
CONVEX_RATIO = 0.97
#: A point cloud (or a cluster) is convex when no facet centroid of its hull is farther than
#: this fraction of the object's size from its points (or 4 sampling spacings, if larger:
#: a convex surface sampled at random leaves holes of about 3.3 median nearest-neighbour
#: distances between its points).
CLOUD_CONCAVITY = 0.03
#: Surface samples of a mesh that is not watertight and cannot be closed by capping (closed on a voxel grid).
OPEN_MESH_SAMPLES = 20000
#: A voxel is inside a cloud's solid when the cloud's voxels surround it along this many of the
#: six axis directions (5: an opening to one side is closed across).
ENCLOSED_DIRECTIONS = 5
#: Clouds with fewer points are always one hull.
SMALL_CLOUD = 64
#: A cloud whose outward normals have an area-weighted mean longer than this (`PointSurface.net_normal`: at most
#: 0.15 for clouds around the train shapes, at least 0.48 for one camera view of them but for a mug's) is warned of as
#: seen from one side.
ONE_SIDED = 0.3
#: A cloud that hides at most this share of its points along some line of sight (`PointSurface.view_direction`)
#: is one camera view: one view of each of 44 train shapes hid at most 0.055 along its best line, the clouds all
#: round them at least 0.20 along any (the middle of the gap, on a log scale).
ONE_VIEW = 0.1
#: Clouds of fewer points are not judged as camera views: sparse samples leave gaps between their lines of sight
#: (a cloud of 100 points around a ball hid 0.11 along its best line, before lines of sight widened with a surface's
#: tilt), and a camera gives thousands.
ONE_VIEW_POINTS = 1000
#: Stray points of a cloud: a point whose k-th nearest neighbour, for some k from 1 to `STRAY_NEIGHBOURS`,
#: is farther than `STRAY_FACTOR` times the cloud's median k-th neighbour distance (an isolated point, or
#: one of a group of at most `STRAY_NEIGHBOURS` apart from the rest) is dropped, when such points are at
#: most `STRAY_SHARE` of the cloud (more of them are a sparse part of the object, not strays).
STRAY_NEIGHBOURS = 8
STRAY_FACTOR = 10.0
STRAY_SHARE = 0.05
#: Parts of a mesh that no face joins and that lie farther apart than this (mm) are reported as separate objects.
PART_GAP = 10.0
#: A part of a mesh whose hull has at most this fraction of the largest part's hull volume, and that lies
#: farther than ``PART_GAP`` from the rest or is open, is debris and is dropped (`drop_debris`, with a warning).
DEBRIS_FRACTION = 1e-3
#: Closed shells that pass through each other are joined into their union (`union_of_bodies`); when the
#: volume they share is more than this fraction of the union's, with a warning (the file's volume was wrong).
UNION_WARNING = 0.01
#: Object sizes (largest bounding-box side, mm) outside this range trigger a warning.
SIZE_RANGE = (10.0, 500.0)
#: Objects smaller than this (largest side, mm) but within `SIZE_RANGE` get a softer warning: small for the
#: hand (plans of them often fail), and perhaps a file in centimetres.
SMALL_SIZE = 30.0
#: Widest remeshing voxel (mm) of the decomposition: the pieces stick out of the true surface by
#: up to about a third of it, under the planner's 5 mm contact threshold. Objects up to 240 mm
#: get the 20 voxels of ``COACD_PARAMS``.
VOXEL_PITCH = 12.0
#: Most voxels along the longest side (objects over 960 mm; the cost grows with it).
MAX_RESOLUTION = 80
#: CoACD parameters (``coacd.run_coacd``) besides ``max_convex_hull`` (``max_parts``) and
#: ``max_ch_vertex`` (``max_vertices``). Lighter than CoACD's defaults: the mesh is always
#: remeshed into a manifold on a voxel grid first (20 voxels along the longest side here, more
#: for objects larger than 240 mm: `coacd_resolution`), so the cost does not grow with the
#: face count and self-intersecting or open meshes work; concavity threshold 0.07, fewer
#: MCTS nodes and iterations. A 10k-face torus decomposes in about 4 s and a 10k-face mug
#: with a handle in about 10 s on 2 cores.
COACD_PARAMS = dict(
    threshold=0.07,
    preprocess_mode="on",
    preprocess_resolution=20,
    resolution=1000,
    mcts_nodes=8,
    mcts_iterations=30,
    mcts_max_depth=2,
    merge=True,
    decimate=True,
    seed=0,
)
#: Most seconds CoACD may take on one mesh (`run_coacd`; the slowest benchmark object, a mug with a
#: handle, takes about a minute on 2 cores). A mesh it does not finish is clustered like a point
#: cloud instead, with a warning.
DECOMPOSITION_TIME_LIMIT = 300.0
_CACHE_VERSION = 1


# --------------------------------------------------------------------------- cache


def cache_dir() -> Path:
    """The decomposition cache directory: ``$SYNERGRASP_CACHE`` or ``~/.cache/synergrasp``.

    Examples
    --------
    >>> cache_dir().name != ""
    True
    """
    env = os.environ.get("SYNERGRASP_CACHE")
    return Path(env).expanduser() if env else Path.home() / ".cache" / "synergrasp"


def _cache_key(content: bytes, params: dict) -> str:
    h = hashlib.sha256(content)
    h.update(json.dumps({"v": _CACHE_VERSION, **params}, sort_keys=True, default=str).encode())
    return h.hexdigest()[:40]


def _cache_read(key: str):
    path = cache_dir() / f"{key}.npz"
    if not path.is_file():
        return None
    try:
        with np.load(path, allow_pickle=False) as data:
            meta = json.loads(str(data["meta"]))
            pieces = [data[f"piece_{i}"] for i in range(meta["n_pieces"])]
        return pieces, meta
    except Exception:  # a corrupt cache entry is recomputed
        return None


def _cache_write(key: str, pieces, meta: dict) -> None:
    folder = cache_dir()
    try:
        folder.mkdir(parents=True, exist_ok=True)
        arrays = {f"piece_{i}": p for i, p in enumerate(pieces)}
        with atomic_path(folder / f"{key}.npz") as tmp:  # (a reader in another process never sees half a file)
            np.savez(tmp, meta=np.array(json.dumps({**meta, "n_pieces": len(pieces)})), **arrays)
    except (OSError, ValueError) as exc:  # (ValueError: the entry's name is taken by something not a file)
        _warn(f"could not write the decomposition cache in {folder} ({exc}); set SYNERGRASP_CACHE to a writable folder")


def _cached(content: bytes, params: dict, compute, use_cache: bool):
    """Pieces from the cache, else ``compute()`` -> (pieces, meta), stored; returns (pieces, meta, status)."""
    if not use_cache:
        pieces, meta = compute()
        return pieces, meta, "disabled"
    key = _cache_key(content, params)
    hit = _cache_read(key)
    if hit is not None and not hit[1].get("timed_out_at", math.inf) < DECOMPOSITION_TIME_LIMIT:
        return hit[0], hit[1], "hit"  # (a decomposition that timed out is tried again under a longer limit)
    pieces, meta = compute()
    if meta.pop("transient", False):  # a fallback after a failure is not stored
        return pieces, meta, "miss"
    _cache_write(key, [np.asarray(p, dtype=float) for p in pieces], meta)
    return pieces, meta, "miss"


# --------------------------------------------------------------------------- helpers


def _warn(message: str) -> None:
    """``warnings.warn`` pointing at the first caller outside synergrasp.objects."""
    level, frame = 2, sys._getframe(1)
    while frame is not None and frame.f_globals.get("__name__", "").startswith("synergrasp.objects"):
        frame, level = frame.f_back, level + 1
    warnings.warn(message, UserWarning, stacklevel=level)


def _check_size(obj: GraspObject, what: str) -> None:
    size = obj.size
    lo, hi = SIZE_RANGE
    if size < lo:
        _warn(
            f"{what} is only {size:.3g} mm across (expected {lo:g}-{hi:g} mm for a hand): synergrasp works in mm; "
            "if the data are in metres pass scale=1000 (centimetres: scale=10, inches: scale=25.4)"
        )
    elif size < SMALL_SIZE:
        _warn(
            f"{what} is {size:.3g} mm across, small for this hand (plans of objects under about {SMALL_SIZE:g} mm "
            "often fail): synergrasp works in mm; if the data are in centimetres pass scale=10"
        )
    elif size > hi:
        _warn(
            f"{what} is {size:.4g} mm across (expected {lo:g}-{hi:g} mm for a hand): synergrasp works in mm; "
            "if the data are in tenths of mm or micrometres pass scale=0.1 or scale=0.001"
        )


def _check_scale(points, scale, what):
    """Refuse, before anything is scaled (and overflows), a ``scale`` that makes ``points`` (n, 3) larger than
    `SIZE_LIMITS` allows."""
    with np.errstate(over="ignore"):
        extent = float(np.ptp(points, axis=0).max()) if len(points) else 0.0
        size = extent * scale
    if scale != 1.0 and size > SIZE_LIMITS[1]:  # (at scale 1 the pieces' own check says so)
        raise ValueError(f"{what} is {extent:.3g} across in its own units, {size:.3g} mm at scale {scale:g}: beyond the "
                         f"{SIZE_LIMITS[1]:g} mm that synergrasp works with (lengths in mm); give the scale that turns "
                         "its units into mm (scale=1000 for metres, 10 for centimetres)")


def _scaled_first(points, scale) -> bool:
    """Whether ``points`` are scaled before their pieces are made: a size in mm once scaled (`_check_scale`), beyond
    what the pieces take in the file's own units (a file in 10 nm, a quantised one), so their pieces are computed
    and cached at the scaled size."""
    return scale != 1.0 and not SIZE_LIMITS[0] <= float(np.ptp(points, axis=0).max()) <= SIZE_LIMITS[1]


def _scaled(pieces, scale):
    return [np.asarray(p, dtype=float) * scale for p in pieces]


def _options(max_parts, max_vertices, cache=True):
    """The loaders' shared options, checked: (max_parts, max_vertices)."""
    if not isinstance(cache, (bool, np.bool_)):  # cache="no" would be true
        raise TypeError(f"cache must be True or False, got {cache!r}")
    return integer(max_parts, "max_parts"), integer(max_vertices, "max_vertices", 4)


def _reduce(points, max_vertices, name):
    return ConvexPiece(points, name=name, max_vertices=max_vertices).vertices


# --------------------------------------------------------------------------- meshes


def coacd_resolution(size: float) -> int:
    """Voxels along the longest side of the decomposition's remeshing grid for an object ``size`` mm across.

    At least ``COACD_PARAMS["preprocess_resolution"]`` (20), and enough that a voxel is at most
    `VOXEL_PITCH` mm wide, up to `MAX_RESOLUTION`: a 450 mm handle with 30 mm bars is remeshed on 38
    (on 20 its 30 mm bars would be 1.3 voxels thick, and the pieces would stick out of them by about 7 mm).

    Parameters
    ----------
    size : float
        The largest side of the object's bounding box (mm), > 0.

    Returns
    -------
    int

    Examples
    --------
    >>> coacd_resolution(120.0), coacd_resolution(450.0), coacd_resolution(2000.0)
    (20, 38, 80)
    """
    size = positive_scalar(size, "size")
    return int(np.clip(np.ceil(size / VOXEL_PITCH), COACD_PARAMS["preprocess_resolution"], MAX_RESOLUTION))


def _decompose(mesh: trimesh.Trimesh, max_parts: int, max_vertices: int, params: dict) -> list[np.ndarray]:
    parts = run_coacd(mesh.vertices, mesh.faces, {**params, "max_convex_hull": max_parts, "max_ch_vertex": max_vertices},
                      DECOMPOSITION_TIME_LIMIT)
    pieces = []
    for vertices in parts:
        try:
            pieces.append(_reduce(vertices, max_vertices, "part"))
        except ValueError:  # a flat sliver: no volume to contact
            continue
    if not pieces:
        raise RuntimeError("CoACD returned no part with a volume")
    return pieces


def _from_mesh(
    mesh,
    scale: float = 1.0,
    *,
    name: str | None = None,
    max_parts: int = 16,
    max_vertices: int = 256,
    cache: bool = True,
    center=None,
    torque_scale=None,
    _source: str | None = None,
) -> GraspObject:
    """Implementation of `from_mesh` (``_source``: the file, for messages)."""
    scale = positive_scalar(scale, "scale")
    max_parts, max_vertices = _options(max_parts, max_vertices, cache)
    what = name or _source or "mesh"
    if isinstance(mesh, trimesh.Scene):
        mesh = _scene_mesh(mesh, what)
    if isinstance(mesh, trimesh.PointCloud):
        raise TypeError("mesh is a trimesh.PointCloud, not a mesh: load it with from_points(cloud), or load(file)")
    if not isinstance(mesh, trimesh.Trimesh):
        raise TypeError(f"mesh must be a trimesh.Trimesh or Scene, got {type(mesh).__name__}")
    if type(mesh) is not trimesh.Trimesh:  # a subclass (trimesh.primitives.Box, ...): its copy() differs
        mesh = trimesh.Trimesh(mesh.vertices, mesh.faces, process=False)
    if len(mesh.vertices) == 0:
        raise ValueError(f"{what} is empty: it has no vertices and no faces; check that its geometry was exported")
    if len(mesh.faces) == 0:
        raise ValueError(f"{what} has no faces; load a point cloud with from_points instead")
    faces = np.asarray(mesh.faces)
    if faces.min() < 0 or faces.max() >= len(mesh.vertices):
        raise ValueError(f"{what} has faces that name vertices it does not have (indices {faces.min()} to {faces.max()}, "
                         f"{len(mesh.vertices)} vertices): the mesh is corrupt; repair or re-export it")
    vertices = as_points(mesh.vertices, f"{what} vertices", dim=3)
    if len(np.unique(faces)) < len(vertices):  # vertices no face uses are not the object's surface
        mesh = mesh.copy()
        mesh.remove_unreferenced_vertices()
        vertices = np.asarray(mesh.vertices, dtype=float)
    mesh, debris = drop_debris(mesh, DEBRIS_FRACTION, PART_GAP / scale)
    if debris:
        vertices = np.asarray(mesh.vertices, dtype=float)
    _check_scale(vertices, scale, what)
    if debris:
        _warn(f"{what}: {len(debris)} loose fragment(s) dropped as debris ("
              + ", ".join(f"{d['faces']} faces {d['size'] * scale:.3g} mm across, "
                          + ("open" if d["open"] else "closed") + f", {d['distance'] * scale:.3g} mm from the rest"
                          for d in debris[:3]) + (", ..." if len(debris) > 3 else "")
              + f"): each has at most {DEBRIS_FRACTION:.1%} of the largest part's volume and either lies more than "
              f"{PART_GAP:g} mm from the rest, where it would make the object larger than it is, or is a flat open "
              "sheet (a ground plane, a label, a stray triangle), where its edges would be capped as holes. "
              "To keep them, set synergrasp.objects.loading.DEBRIS_FRACTION = 0")
    given_scale = scale
    if _scaled_first(vertices, scale):
        mesh = mesh.copy()
        mesh.apply_scale(scale)
        vertices, scale = np.asarray(mesh.vertices, dtype=float), 1.0
    hull_volume = checked_hull(np.unique(vertices, axis=0), what).volume  # raises "has no volume" for flat meshes
    watertight = bool(mesh.is_watertight)
    repair, refusal = None, None
    mesh, turned = orient_outward(mesh)
    if turned:
        _warn(f"{what}: {TURNED_OUTWARD}")
    if not watertight:
        try:
            mesh, repair = close_mesh(mesh, what)
        except RepairError as exc:  # not closable by capping: closed on a voxel grid below, or refused there
            refusal = exc.reason
    union = None
    if refusal is None:
        mesh, overlap = union_of_bodies(mesh)
        if overlap:
            union = {"method": "union", "overlap": overlap * scale**3, "volume": float(mesh.volume) * scale**3}
        if overlap > UNION_WARNING * abs(float(mesh.volume)):  # (shells that only graze each other are joined quietly)
            _warn(f"{what}: its closed shells pass through each other ({union['overlap']:.4g} mm^3 lies inside more "
                  f"than one, and its volume counted that twice); they were joined into the solid they enclose, "
                  f"{union['volume']:.4g} mm^3 (their union, manifold3d). Check the pieces (obj.piece_meshes())")
        if repair is not None or union is not None:
            vertices = np.asarray(mesh.vertices, dtype=float)
            hull_volume = checked_hull(np.unique(vertices, axis=0), what).volume  # of what was kept, welded, joined
    ratio, through_itself = None, False
    if refusal is None:
        ratio = float(abs(mesh.volume) / hull_volume) if hull_volume > 0 else 0.0
        through_itself = ratio > 1.0 + 1e-6  # more than its hull (beyond round-off): no solid's surface
        if through_itself:
            _warn(f"{what}: its volume is {ratio:.3g} times its convex hull's, which no solid's is: its surface passes "
                  "through itself. It is decomposed as the solid CoACD's voxel remeshing makes of it, not taken as "
                  "its hull; check the pieces (obj.piece_meshes()), or repair the mesh in a mesh editor")
    convex = ratio is not None and ratio > CONVEX_RATIO and not through_itself

    decomposition = dict(COACD_PARAMS)
    if refusal is None and not convex:  # decomposed by CoACD: its grid for the object's size
        decomposition["preprocess_resolution"] = coacd_resolution(float(np.ptp(vertices, axis=0).max()) * scale)

    def surface_cloud(**checks):
        """The solid the surface encloses, on a voxel grid: its vertices and surface samples, clustered."""
        samples, _ = trimesh.sample.sample_surface(mesh, OPEN_MESH_SAMPLES, seed=0)
        return _cluster_cloud(np.unique(np.vstack([vertices, samples]), axis=0), max_parts, max_vertices, what, **checks)

    def compute():
        if convex:
            return [_reduce(vertices, max_vertices, what)], {"method": "hull"}
        if refusal is not None:  # no inside to decompose
            pieces, meta = surface_cloud(require_inside=f"{what} is not watertight and cannot be capped ({refusal})")
            return pieces, {**meta, "method": f"voxel closing: {meta['method']}"}
        try:
            return _decompose(mesh, max_parts, max_vertices, decomposition), {"method": "coacd"}
        except DecompositionTimeout as exc:  # a shape CoACD loops on
            pieces, meta = surface_cloud()
            _warn(f"{what}: {exc}; its pieces are clusters of the solid its surface encloses instead "
                  f"({meta['method']}). Check them (obj.piece_meshes()), or raise "
                  "synergrasp.objects.loading.DECOMPOSITION_TIME_LIMIT: the next load tries CoACD again")
            return pieces, {**meta, "method": f"{meta['method']} (CoACD timed out)",
                            "timed_out_at": DECOMPOSITION_TIME_LIMIT}
        except Exception as exc:  # noqa: BLE001 - the hull is a usable fallback
            _warn(f"convex decomposition of {what} failed ({exc}); using its convex hull")
            return [_reduce(vertices, max_vertices, what)], {"method": "hull (decomposition failed)", "transient": True}

    # the geometry read, whatever files it came from (a .gltf's buffers, an .obj's groups): not the file's bytes
    content = vertices.tobytes() + np.asarray(mesh.faces, dtype=np.int64).tobytes()
    params = {
        "kind": "mesh" if watertight else "open mesh",
        "max_parts": max_parts,
        "max_vertices": max_vertices,
        "coacd": decomposition,
        "concavity": CLOUD_CONCAVITY,
        "samples": OPEN_MESH_SAMPLES,
    }
    if debris:  # which parts are debris depends on the scale (PART_GAP is in mm): the key names what was kept
        params["kept"] = hashlib.sha256(vertices.tobytes() + np.asarray(mesh.faces, dtype=np.int64).tobytes()).hexdigest()
    if union is not None:  # the file's shells joined: not the pieces of the file's own surface
        params["union"] = True
    if not watertight:
        params["repair"] = {"planarity": PLANARITY, "caps": MAX_CAP_FRACTION, "weld": WELD_TOLERANCE,
                            "enclosed": ENCLOSED_DIRECTIONS}
    pieces, meta, status = _cached(content, params, compute, cache)
    shown = mesh.copy(include_cache=True)  # at scale 1 its checks (watertight, winding) are not computed again
    shown.apply_scale(scale)
    if repair is not None:
        repair = {**repair, "cap_area": repair["cap_area"] * scale**2, "volume": repair["volume"] * scale**3}
        opened = repair["holes_filled"] or repair["welded_vertices"]
        if opened or repair["removed_faces"]:  # else only corners stored once per face, merged: the same surface
            _warn(f"{what} {'is not watertight' if opened else 'needed repair'}: {_describe(repair)}. "
                  "Check the pieces (obj.piece_meshes())"
                  + ("; contacts on a filled hole are on surface the file does not have" if repair["holes_filled"] else ""))
    elif refusal is not None:
        repair = {"method": "voxel closing", "reason": refusal, "filled_volume": meta.get("filled_volume", 0.0) * scale**3}
        _warn(f"{what} is not watertight and cannot be capped ({refusal}); it is closed "
              f"on a voxel grid instead: the solid its surface encloses ({repair['filled_volume']:.4g} mm^3), cut into "
              f"{len(pieces)} convex pieces. Check the pieces (obj.piece_meshes())")
    obj = GraspObject(
        _scaled(pieces, scale),
        name=what,
        mesh=shown,
        center=center,
        torque_scale=torque_scale,
        info={"source": _source or "mesh", "method": meta["method"], "cache": status, "volume_ratio": ratio,
              "watertight": watertight, "scale": given_scale,
              "repair": {**repair, "union": union} if repair and union else repair or union},
    )
    _check_size(obj, what)
    parts, gap = separate_parts(shown)
    if gap > PART_GAP:
        _warn(f"{what} is {parts} separate parts, some {gap:.0f} mm from the rest: they are planned as one rigid "
              "object. To grasp one of them, load it alone: its parts are " + (
                  'trimesh.load(path, force="mesh").split(only_watertight=False)' if _source
                  else "mesh.split(only_watertight=False) (a scene's: its geometry, scene.geometry.values())"))
    return obj


def _describe(repair: dict) -> str:
    """What `close_mesh` did, in words."""
    done = []
    if repair["removed_faces"]:
        done.append(f"{repair['removed_faces']} duplicate or degenerate faces dropped")
    if repair["welded_vertices"]:
        done.append(f"{repair['welded_vertices']} vertices welded along open seams")
    if repair["holes_filled"]:
        done.append(f"{repair['holes_filled']} hole(s) capped with {repair['cap_area']:.4g} mm^2 of new surface "
                    f"({repair['cap_fraction']:.1%} of the closed surface)")
    return ", ".join(done) + f"; the closed mesh's volume is {repair['volume']:.4g} mm^3"


# --------------------------------------------------------------------------- point clouds


def _spacing(points: np.ndarray) -> float:
    """Median distance from a point to its nearest neighbour (the sampling density)."""
    from scipy.spatial import cKDTree

    sample = points if len(points) <= 20000 else points[:: len(points) // 20000 + 1]
    dist, _ = cKDTree(points).query(sample, k=2)
    return float(np.median(dist[:, 1]))


def _without_strays(points: np.ndarray, what: str, scale: float) -> np.ndarray:
    """``points`` (n, 3) without its stray points (a scan's outliers; see `STRAY_FACTOR`), with a warning if any
    (its distances in mm: the points' units times ``scale``)."""
    if len(points) < SMALL_CLOUD:
        return points
    from scipy.spatial import cKDTree

    dist = cKDTree(points).query(points, k=STRAY_NEIGHBOURS + 1)[0][:, 1:]  # (n, STRAY_NEIGHBOURS): k = 1, 2, ...
    typical = np.median(dist, axis=0)
    stray = (dist > STRAY_FACTOR * typical).any(axis=1)
    dist, typical = dist * scale, typical * scale  # (for the warnings: in mm)
    if not stray.any():
        return points
    if stray.sum() > STRAY_SHARE * len(points):
        _warn(f"{what}: {int(stray.sum())} points ({stray.mean():.1%} of the cloud) lie apart from the rest (up to "
              f"{dist[stray, 0].max():.2g} mm from the nearest other point, where the cloud's typical spacing is "
              f"{typical[0]:.2g} mm); more than {STRAY_SHARE:.0%}, so they are kept as a sparsely sampled part of the "
              "object. If they are a scan's outliers, remove them: they make the object larger than it is")
        return points
    _warn(f"{what}: {int(stray.sum())} stray point(s) dropped (up to {dist[stray, 0].max():.2g} mm from the nearest "
          f"other point, where the cloud's typical spacing is {typical[0]:.2g} mm): isolated points or groups of at "
          f"most {STRAY_NEIGHBOURS}, whose k-th nearest neighbour, for some k from 1 to {STRAY_NEIGHBOURS}, is more "
          f"than {STRAY_FACTOR:g} times as far as is typical in the cloud. A scan's outliers would make the object "
          "larger than it is")
    return points[~stray]


def _cloud_parts(points: np.ndarray):
    """How many groups of points lie apart, and the widest gap that joins them (mm).

    Points in the same or neighbouring cells of a grid of ``PART_GAP / 2`` (or
    of 4 sampling spacings, for a sparse cloud) are one group; the gap is
    `joining_gap`'s, 0 for one group. Only the `MAX_PARTS` largest groups are
    measured (a cloud with many outliers kept has one group for each).
    """
    from scipy import ndimage

    cell = max(0.5 * PART_GAP, 4.0 * _spacing(points))
    cells = np.floor((points - points.min(axis=0)) / cell).astype(np.int64)
    grid = np.zeros(cells.max(axis=0) + 1, dtype=bool)
    grid[tuple(cells.T)] = True
    labels, count = ndimage.label(grid, structure=np.ones((3, 3, 3), dtype=bool))
    if count < 2:
        return 1, 0.0
    label = labels[tuple(cells.T)] - 1
    measured = np.argsort(-np.bincount(label, minlength=count), kind="stable")[:MAX_PARTS]
    return count, joining_gap([points[label == k] for k in measured])


def _concavity(members: np.ndarray, name: str) -> float:
    """How far the hull of ``members`` bulges away from them: the largest distance
    from a hull facet's centroid to the nearest member (0 for points filling a convex set)."""
    from scipy.spatial import cKDTree

    hull = checked_hull(members, name)
    centroids = hull.points[hull.simplices].mean(axis=1)
    return float(cKDTree(members).query(centroids)[0].max())


def _filled_voxels(points: np.ndarray, pitch: float):
    """Voxels of a cloud with its gaps closed and its inside filled.

    The cloud's voxels are dilated by one (closing gaps of about two voxels);
    the inside is what they enclose, together with every voxel that they
    surround along `ENCLOSED_DIRECTIONS` of the six axis directions (an
    opening to one side is closed across); the dilation is then undone.

    Returns
    -------
    solid : (m, 3) float
        Centres of all the solid voxels.
    interior : (m,) bool
        The voxel does not touch a voxel holding a cloud point: it lies inside
        the surface, so its centre may join a piece's hull without bulging
        past the surface.
    """
    from scipy import ndimage

    lo = points.min(axis=0)
    index = np.floor((points - lo) / pitch).astype(int) + 2
    grid = np.zeros(index.max(axis=0) + 3, dtype=bool)
    grid[tuple(index.T)] = True
    cube = np.ones((3, 3, 3), dtype=bool)
    closed = ndimage.binary_dilation(grid, structure=cube)
    seen = np.zeros(closed.shape, dtype=np.int8)  # along how many axis directions a cloud voxel lies
    for axis in range(3):
        seen += np.logical_or.accumulate(closed, axis=axis)
        seen += np.flip(np.logical_or.accumulate(np.flip(closed, axis=axis), axis=axis), axis=axis)
    inside = ndimage.binary_fill_holes(closed | (seen >= ENCLOSED_DIRECTIONS))
    solid = ndimage.binary_erosion(inside, structure=cube) | grid
    cells = np.argwhere(solid)
    return (cells - 2 + 0.5) * pitch + lo, ~closed[tuple(cells.T)]


def _thick(solid: np.ndarray, interior: np.ndarray, pitch: float) -> bool:
    """Whether some inner voxel of `_filled_voxels` has all six neighbours inner too (an inside, not stray voxels)."""
    from scipy import ndimage

    cells = np.round((solid[interior] - solid.min(axis=0)) / pitch).astype(np.int64) + 1
    if not len(cells):
        return False
    grid = np.zeros(cells.max(axis=0) + 2, dtype=bool)
    grid[tuple(cells.T)] = True
    return bool(ndimage.binary_erosion(grid).any())


def _cluster_cloud(points: np.ndarray, max_parts: int, max_vertices: int, name: str, require_inside: str | None = None):
    """Convex pieces of a cloud: its hull when it is convex, else hulls of k-means clusters of its filled solid.

    ``require_inside``: the cloud samples an open mesh that could not be capped, for
    that reason; a cloud whose voxels enclose nothing is then refused (ValueError).
    ``meta["filled_volume"]`` is the volume of the solid (mm^3, before scaling).
    """
    from scipy.cluster.vq import kmeans2

    size = float(np.ptp(points, axis=0).max())
    spacing = _spacing(points)
    tolerance = max(CLOUD_CONCAVITY * size, 4.0 * spacing)
    concavity = _concavity(points, name)
    meta = {"method": "hull", "concavity": concavity, "tolerance": tolerance}
    if len(points) < SMALL_CLOUD or concavity <= tolerance or max_parts == 1:
        return [_reduce(points, max_vertices, name)], {**meta, "filled_volume": float(checked_hull(points, name).volume)}
    pitch = max(size / 40.0, 1.5 * spacing)
    solid, interior = _filled_voxels(points, pitch)
    for finer in (pitch / 2, pitch / 4):  # a solid too thin for the grid to hold an inside (a 10 mm wall): finer
        if require_inside is None or interior.any() or finer < 1.5 * spacing:
            break
        voxels = _filled_voxels(points, finer)
        if _thick(*voxels, finer):  # (a sheet's samples leave stray inner voxels on a fine grid: not an inside)
            pitch, (solid, interior) = finer, voxels
    if require_inside is not None and not interior.any():
        raise ValueError(
            f"{require_inside}, and its surface encloses no volume on a voxel grid either (pitch {pitch:.3g} mm): "
            "it cannot be closed soundly. Close it in a mesh editor"
        )
    tolerance = max(tolerance, 1.5 * pitch)
    members = np.vstack([solid[interior], points])  # the surface itself comes from the cloud
    meta["filled_volume"] = float(len(solid) * pitch**3)
    if _concavity(members, name) <= tolerance:  # the filled solid is convex (an opening closed across)
        return [_reduce(members, max_vertices, name)], {**meta, "method": "hull of the filled solid"}
    rng = np.random.default_rng(0)
    for k in sorted({k for k in (2, 3, 4, 6, 8, 12, 16, 24, 32) if k < max_parts} | {max_parts}):
        centroids, _ = kmeans2(solid, k, minit="++", seed=rng)
        label = np.argmin(((members[:, None, :] - centroids[None]) ** 2).sum(axis=2), axis=1)
        groups = [members[label == c] for c in np.unique(label)]
        worst = 0.0
        for group in groups:
            try:
                worst = max(worst, _concavity(group, name))
            except ValueError:  # a flat cluster has no bulge
                continue
        if worst <= tolerance:
            break
    shapes, flat = [], False
    for group in groups:
        try:
            shapes.append(ConvexPiece(group, name=name, max_vertices=max_vertices))
        except ValueError:  # a flat cluster: a sheet of points with no inside behind it
            flat = True
    pieces = [shape.vertices for shape in shapes]
    if (flat or not interior.any()) and (not shapes or _seen_from_one_side(points, shapes)):
        # a shell of the side of the object that was seen (one camera view): closed flat behind, by its hull
        return [_reduce(points, max_vertices, name)], {**meta, "method": "hull of a cloud seen from one side"}
    meta.update(method=f"kmeans ({len(pieces)} clusters)", cluster_concavity=worst, tolerance=tolerance)
    return pieces, meta


def _swept_view(points: np.ndarray, pieces: list, meta: dict, max_vertices: int, name: str):
    """A camera view's pieces swept away from the camera, as far again as the view is deep; other clouds' as they are.

    The cloud is a view when it has at least `ONE_VIEW_POINTS` points and hides
    at most `ONE_VIEW` of them along its best line of sight (`PointSurface.view_direction`, of the lines that
    hide about as few the nearest to the net outward normal,
    `PointSurface.net_normal`, turned outward by the pieces); the camera was
    on the side the outward normals face. Returns the pieces and their meta, with
    ``camera`` (a unit vector toward it), ``swept`` (mm) and ``hidden``.
    """
    if len(points) < ONE_VIEW_POINTS:
        return pieces, meta
    surface = PointSurface(points)
    net = surface.net_normal(_inside([ConvexPiece(v, name=name) for v in pieces]))
    direction, hidden = surface.view_direction(toward=net)
    toward = float(net @ direction)
    if hidden > ONE_VIEW or toward == 0.0:  # not a view, or which side the camera was on is not known
        return pieces, meta
    camera = direction * math.copysign(1.0, toward)
    depth = float(np.ptp(points @ camera))
    swept = [_reduce(np.vstack([v, v - depth * camera]), max_vertices, name) for v in pieces]
    return swept, {**meta, "method": f"{meta['method']}, swept away from the camera", "camera": camera.tolist(),
                   "swept": depth, "hidden": hidden}


def _inside(shapes: list):
    """``contains(points) -> (k,) bool`` of the union of convex pieces (`ConvexPiece`), by their distance bounds."""
    return lambda q: np.min([shape.signed_distance_bound(q) for shape in shapes], axis=0) <= 0.0


def _seen_from_one_side(points: np.ndarray, shapes: list) -> bool:
    """Whether a cloud's outward normals, turned outward by its pieces (`ConvexPiece`), do not balance (`ONE_SIDED`)."""
    return bool(np.linalg.norm(PointSurface(points).net_normal(_inside(shapes))) > ONE_SIDED)


def _warn_one_sided(obj: GraspObject, what: str) -> None:
    """Warn of a camera view (swept away from the camera), or a cloud whose outward normals do not balance
    (`ONE_SIDED`): the cloud samples one side."""
    camera = obj.info.get("camera")
    if camera is not None:
        _warn(f"{what} is one camera view, seen from ({', '.join(f'{x:.2f}' for x in camera)}): along that line "
              f"{obj.info['hidden']:.0%} of its points lie behind others (a cloud all round an object hides about "
              "half). What the camera did not see is taken as solid: the pieces are swept "
              f"{obj.info['swept']:.0f} mm away from it (as far again as the view is deep), where the hand does not "
              "go and a grasp finds no points to touch, so grasps hold on the side seen; for grasps all round, scan "
              "the object from several sides or give its mesh")
        return
    net = obj.point_surface.net_normal(obj.contains)
    length = float(np.linalg.norm(net))
    if length > ONE_SIDED:
        toward = ", ".join(f"{x:.2f}" for x in net / length)
        _warn(f"{what} seems to be seen from one side: the outward normals of its points do not balance (their "
              f"area-weighted mean is {length:.2f} long, toward ({toward}); about 0 for a cloud around the whole object, "
              "as from a scan on several sides). The unseen side is closed by the pieces' hull faces, where a grasp "
              "finds no points to touch, so grasps must hold on the side seen; for grasps all round, scan the object "
              "from several sides or give its mesh")


def _from_points(
    points,
    scale: float = 1.0,
    *,
    name: str | None = None,
    max_parts: int = 16,
    max_vertices: int = 256,
    cache: bool = True,
    center=None,
    torque_scale=None,
    _source: str | None = None,
) -> GraspObject:
    """Implementation of `from_points` (``_source``: the file, for messages)."""
    what = name or _source or "point cloud"
    if isinstance(points, trimesh.PointCloud):
        points = np.asarray(points.vertices)
    points = _xyz_columns(points)  # (n, 6): x y z, then normals or colours
    scale = positive_scalar(scale, "scale")
    max_parts, max_vertices = _options(max_parts, max_vertices, cache)
    pts = np.unique(as_points(points, what if _source else "points", dim=3), axis=0)
    pts = _without_strays(pts, what, scale)
    _check_scale(pts, scale, what)
    given_scale = scale
    if _scaled_first(pts, scale):
        pts, scale = pts * scale, 1.0
    checked_hull(pts, what)  # raises "has no volume" for flat or too small clouds
    params = {"kind": "cloud", "max_parts": max_parts, "max_vertices": max_vertices,
              "concavity": CLOUD_CONCAVITY, "small": SMALL_CLOUD, "enclosed": ENCLOSED_DIRECTIONS,
              "strays": [STRAY_NEIGHBOURS, STRAY_FACTOR, STRAY_SHARE], "one_sided": ONE_SIDED,
              "one_view": [ONE_VIEW, ONE_VIEW_POINTS]}
    pieces, meta, status = _cached(
        pts.tobytes(), params, lambda: _swept_view(pts, *_cluster_cloud(pts, max_parts, max_vertices, what),
                                                   max_vertices, what), cache
    )
    obj = GraspObject(
        _scaled(pieces, scale),
        name=what,
        center=center,
        torque_scale=torque_scale,
        points=pts * scale if len(pts) >= SMALL_CLOUD else None,  # a few points are corners, not samples
        info={"source": _source or "points", "method": meta["method"], "cache": status,
              "concavity": meta.get("concavity"), "scale": given_scale,
              **({"camera": meta["camera"], "swept": meta["swept"] * scale, "hidden": meta["hidden"]}
                 if "camera" in meta else {})},
    )
    _check_size(obj, what)
    if len(pts) < SMALL_CLOUD:
        _warn(f"{what} has only {len(pts)} distinct points: they are taken as the corners of a convex solid (their "
              f"hull), not as samples of a surface; a scanned cloud needs at least {SMALL_CLOUD} points"
              + (" (a mesh file without faces, such as an OBJ of lines, is read as its vertices)" if _source else ""))
    if obj.point_surface is not None:
        _warn_one_sided(obj, what)
    parts, gap = _cloud_parts(pts * scale) if len(pts) >= SMALL_CLOUD else (1, 0.0)
    if gap > PART_GAP:
        _warn(f"{what} is {parts} separate groups of points, some {gap:.0f} mm from the rest: they are planned as one "
              "rigid object. To grasp one of them, pass its points alone")
    return obj


def from_mesh(
    mesh,
    scale: float = 1.0,
    *,
    name: str | None = None,
    max_parts: int = 16,
    max_vertices: int = 256,
    cache: bool = True,
    center=None,
    torque_scale=None,
) -> GraspObject:
    """An object from a triangle mesh: its hull if (nearly) convex, else convex parts.

    Parameters
    ----------
    mesh : trimesh.Trimesh or trimesh.Scene
        The surface (a scene's meshes are concatenated; trimesh's primitives,
        such as ``trimesh.primitives.Box``, are meshes too).
    scale : float
        Factor applied to the coordinates (``scale=1000`` for a mesh in metres).
    name : str, optional
        Object name (default the mesh's file name or "mesh").
    max_parts : int
        Most convex parts of a decomposition.
    max_vertices : int
        Most hull vertices per piece.
    cache : bool
        Use the on-disk decomposition cache.
    center, torque_scale : optional
        See `GraspObject`.

    Returns
    -------
    GraspObject
        ``info["method"]`` is ``"hull"``, ``"coacd"`` or (not watertight)
        ``"surface points: ..."``, ``info["cache"]`` is
        ``"hit"``, ``"miss"`` or ``"disabled"``, ``info["volume_ratio"]`` the
        mesh's volume over its hull's (None when not watertight),
        ``info["repair"]`` what `close_mesh` did, or for closed shells joined
        into their union ``{"method": "union", "overlap", "volume"}`` (mm^3).

    Raises
    ------
    TypeError
        If ``mesh`` is not a trimesh.Trimesh or Scene, or ``cache`` is not a bool.
    ValueError
        If the mesh is empty, has no faces or no volume (all vertices on a plane),
        or has a NaN or inf vertex.

    Warns
    -----
    UserWarning
        If the mesh is not watertight, its closed shells pass through each
        other, its volume exceeds its hull's, debris was dropped, its parts lie
        apart, or the object's size is outside 10-500 mm.

    Examples
    --------
    A convex mesh is taken as its hull (a non-convex one is decomposed, which takes
    seconds the first time and is then read from the cache):

    >>> import trimesh
    >>> import synergrasp as sg
    >>> mesh = trimesh.creation.cylinder(radius=35.0, height=100.0)     # mm
    >>> obj = sg.objects.from_mesh(mesh, name="can", cache=False)
    >>> obj, obj.info["method"]
    (GraspObject('can', 1 pieces, 70 x 70 x 100 mm, L=61.0), 'hull')
    """
    return _from_mesh(mesh, scale, name=name, max_parts=max_parts, max_vertices=max_vertices, cache=cache,
                      center=center, torque_scale=torque_scale)


def from_points(
    points,
    scale: float = 1.0,
    *,
    name: str | None = None,
    max_parts: int = 16,
    max_vertices: int = 256,
    cache: bool = True,
    center=None,
    torque_scale=None,
) -> GraspObject:
    """An object from a point cloud: one hull, or the hulls of k-means clusters of its filled inside.

    Parameters
    ----------
    points : (n, 3) array_like or trimesh.PointCloud
        Points on (or in) the object. An (n, k) array with k > 3 columns
        (fewer than its rows: x y z, then normals or colours, as scanners
        export them) gives its first three.
    scale : float
        Factor applied to the coordinates (``scale=1000`` for metres).
    name : str, optional
        Object name (default "point cloud").
    max_parts : int
        Most clusters (pieces).
    max_vertices : int
        Most hull vertices per piece.
    cache : bool
        Use the on-disk cache for the clustering.
    center, torque_scale : optional
        See `GraspObject`.

    Returns
    -------
    GraspObject
        ``info["method"]`` is ``"hull"`` or ``"kmeans (k clusters)"``; no
        ``mesh``: its ``points`` are the cloud (strays dropped), the surface a
        grasp is judged on (`GraspObject.point_surface`), unless the cloud
        is small (fewer than 64 points: corners, not samples of a surface;
        its hull is then its surface).

    Raises
    ------
    TypeError
        If ``points`` are not numbers, or ``cache`` is not a bool.
    ValueError
        If the cloud is empty, not (n, 3), non-finite, or flat (no volume).

    Warns
    -----
    UserWarning
        If the object's size is outside 10-500 mm (or under `SMALL_SIZE`), or if
        stray points were dropped (at most `STRAY_SHARE` of the cloud, each with
        its k-th nearest neighbour, for some k from 1 to `STRAY_NEIGHBOURS`,
        farther than `STRAY_FACTOR` times the cloud's typical k-th neighbour
        distance: isolated points and groups of up to 8), or kept (more of them),
        or if groups of the points lie more than `PART_GAP` apart, or if the
        cloud has fewer than `SMALL_CLOUD` points (taken as corners), or if it
        seems to be seen from one side (its outward normals do not balance:
        `ONE_SIDED`; closed by its hull when its points enclose nothing), or
        is one camera view (`ONE_VIEW`; its pieces swept away from the camera).

    Examples
    --------
    500 points on a sphere of radius 30 mm: a convex cloud, so one hull.

    >>> import numpy as np
    >>> import synergrasp as sg
    >>> rng = np.random.default_rng(0)
    >>> points = rng.normal(size=(500, 3))
    >>> points *= 30.0 / np.linalg.norm(points, axis=1, keepdims=True)
    >>> obj = sg.objects.from_points(points, name="ball", cache=False)
    >>> obj.n_pieces, obj.info["method"], bool(obj.contains([[0.0, 0.0, 0.0]])[0])
    (1, 'hull', True)
    """
    return _from_points(points, scale, name=name, max_parts=max_parts, max_vertices=max_vertices, cache=cache,
                        center=center, torque_scale=torque_scale)


# --------------------------------------------------------------------------- files


def _read_array_file(path: Path, ext: str):
    """(kind, data) from .npy/.npz/.xyz: ("points", array) or ("mesh", Trimesh, unprocessed)."""
    if ext == ".xyz":
        try:
            data = np.loadtxt(path, ndmin=2, comments="#", encoding="utf-8-sig")  # (a byte-order mark is skipped)
        except ValueError as whitespace:
            try:
                data = np.loadtxt(path, ndmin=2, comments="#", delimiter=",", encoding="utf-8-sig")
            except ValueError:
                # the first reading's reason (a row of another length, a word), without numpy's advice on usecols
                raise ValueError(str(whitespace).split("; use `usecols`")[0] + " (expected x y z per line; "
                                 "start a header or comment line with #)") from None
        if data.ndim != 2 or data.shape[1] < 3:
            raise ValueError(f"expected at least 3 columns x y z per line, got shape {data.shape}")
        return "points", _xyz_columns(data, rows=True)
    if ext == ".npy":
        return "points", _xyz_columns(np.load(path, allow_pickle=False))
    with np.load(path, allow_pickle=False) as data:
        keys = list(data.keys())
        if "vertices" in keys and "faces" in keys:
            faces, n = np.asarray(data["faces"]), len(np.atleast_1d(data["vertices"]))
            if faces.dtype.kind not in "iu" or faces.ndim != 2 or faces.shape[1] != 3 \
                    or (faces.size and (faces.min() < 0 or faces.max() >= n)):
                raise ValueError(f"'faces' must be an (m, 3) array of integer vertex indices from 0 to {n - 1}, "
                                 f"got {faces.dtype} of shape {faces.shape}"
                                 + (f" from {faces.min()} to {faces.max()}" if faces.size and faces.dtype.kind in "iuf"
                                    else ""))
            return "mesh", trimesh.Trimesh(data["vertices"], faces, process=False)  # processed after the checks
        if "points" in keys:
            return "points", _xyz_columns(data["points"])
        if len(keys) == 1:
            return "points", data[keys[0]]
    raise ValueError(f"an .npz object file needs an array 'points' (or 'vertices' and 'faces'), found keys {keys}")


def _xyz_columns(data, rows=False):
    """The x y z of rows with further columns (normals, colours), as .xyz and .npy files hold them. An array of
    3 columns, or (unless ``rows``: a text file's lines are its points) of as many columns as rows or more (perhaps
    (3, n)), comes back as it is. A first column that counts the rows is refused."""
    if not (isinstance(data, np.ndarray) and data.ndim == 2 and data.shape[1] > 3 and (rows or data.shape[1] < len(data))):
        return data
    counting = np.arange(len(data))
    if len(data) > 3 and any((data[:, 0] == counting + k).all() for k in (0, 1)):
        raise ValueError(f"its first column counts the lines ({data[0, 0]:g}, {data[1, 0]:g}, {data[2, 0]:g}, ...): "
                         "a point number, not x. Remove that column (the first three are read as x y z)")
    return data[:, :3]


def _scene_mesh(scene, what):
    """A scene's meshes as one mesh; a warning names the geometry without faces that is left out (ValueError when
    none has faces: a point cloud)."""
    left = [type(g).__name__ for g in scene.geometry.values() if not (isinstance(g, trimesh.Trimesh) and len(g.faces))]
    if left and len(left) == len(scene.geometry):
        raise ValueError(f"{what} is a scene without faces (its geometry: {', '.join(sorted(set(left)))}): pass a point "
                         "cloud to from_points (a trimesh.PointCloud or its vertices), or its file to load()")
    if left:
        _warn(f"{what}: {len(left)} of the scene's geometries have no faces ({', '.join(sorted(set(left)))}) and are "
              "left out; only its meshes make the object")
    return scene.to_mesh()


def _mesh_or_points(data, parts, what):
    """("mesh", Trimesh) or ("points", array) from what trimesh read (unprocessed): meshes processed as
    trimesh.load would (duplicate vertices merged), a scene's meshes concatenated."""
    for part in parts:
        if isinstance(part, trimesh.Trimesh):
            part.process()
    if isinstance(data, trimesh.Scene):
        meshes = [g for g in parts if isinstance(g, trimesh.Trimesh) and len(g.faces)]
        data = _scene_mesh(data, what) if meshes else np.vstack([g.vertices for g in parts])
    if isinstance(data, trimesh.PointCloud) or (isinstance(data, trimesh.Trimesh) and len(data.faces) == 0):
        data = np.asarray(data.vertices)
    if not isinstance(data, (np.ndarray, trimesh.Trimesh)):
        raise ValueError(f"expected a mesh or a point cloud, found a {type(data).__name__}")
    return ("points" if isinstance(data, np.ndarray) else "mesh"), data


def load(
    path,
    scale: float = 1.0,
    *,
    name: str | None = None,
    max_parts: int = 16,
    max_vertices: int = 256,
    cache: bool = True,
    center=None,
    torque_scale=None,
) -> GraspObject:
    """Load an object from a mesh or point-cloud file.

    Parameters
    ----------
    path : str or os.PathLike
        A mesh (.obj .stl .ply .off .glb .gltf) or a point cloud (.ply
        without faces, .xyz text ``x y z`` per line, .npy (n, 3), .npz with
        ``points`` or ``vertices`` and ``faces``). Further columns of .xyz
        and .npy (normals, colours) are left out.
    scale : float
        Factor applied to the coordinates: synergrasp works in mm, so pass
        ``scale=1000`` for a file in metres.
    name : str, optional
        Object name (default the file name).
    max_parts : int
        Most convex parts (decomposition or clusters).
    max_vertices : int
        Most hull vertices per piece.
    cache : bool
        Use the on-disk decomposition cache (``cache_dir()``).
    center, torque_scale : optional
        See `GraspObject`.

    Returns
    -------
    GraspObject

    Raises
    ------
    TypeError
        If ``path`` is not a str or os.PathLike (a mesh or points already in
        memory go to `from_mesh` or `from_points`), or ``cache`` is not a bool.
    FileNotFoundError
        If the file does not exist.
    ValueError
        If the extension is not supported (the message lists the supported
        ones), the file cannot be read (or a file it refers to, such as a
        .gltf's buffer, is missing), a vertex is NaN or inf, or its content
        has no volume.

    Warns
    -----
    UserWarning
        As `from_mesh` or `from_points` warn (a mesh not watertight, debris
        dropped, the size outside 10-500 mm, ...).

    Examples
    --------
    Write a 60 x 50 x 90 mm box to an STL file and load it:

    >>> import tempfile
    >>> from pathlib import Path
    >>> import trimesh
    >>> import synergrasp as sg
    >>> with tempfile.TemporaryDirectory() as folder:
    ...     path = Path(folder) / "box.stl"
    ...     _ = trimesh.creation.box(extents=[60.0, 50.0, 90.0]).export(path)
    ...     obj = sg.objects.load(path, cache=False)
    >>> obj
    GraspObject('box.stl', 1 pieces, 60 x 50 x 90 mm, L=59.6)
    >>> obj.info["method"], obj.info["watertight"]
    ('hull', True)

    A file in metres needs ``scale=1000``; without it the object is 1000 times too
    small and a ``UserWarning`` says so.
    """
    path = _object_path(path).expanduser()
    if path.is_dir():
        raise FileNotFoundError(f"'{path}' is a folder, not an object file: give a mesh or point-cloud file in it")
    if not path.is_file():
        raise FileNotFoundError(f"object file not found: '{path}'")
    ext = path.suffix.lower()
    if ext not in SUPPORTED_FORMATS:
        raise ValueError(
            f"cannot load '{path}': unknown format {ext or '(no extension)'!r}; "
            f"supported extensions: {', '.join(SUPPORTED_FORMATS)}"
        )
    if path.stat().st_size == 0:
        raise ValueError(f"cannot load '{path}': the file is empty")
    name = name or path.name
    options = dict(name=name, max_parts=max_parts, max_vertices=max_vertices, cache=cache,
                   center=center, torque_scale=torque_scale, _source=str(path))
    reading = f"could not read '{path}' as a {ext} file"
    kind = None
    try:
        if ext in (".xyz", ".npy", ".npz"):
            kind, data = _read_array_file(path, ext)
        else:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                # unprocessed, so that a vertex with NaN or inf is seen (processing drops it with its faces)
                data = trimesh.load(str(path), file_type=ext[1:], process=False)
            if isinstance(data, trimesh.Scene) and not data.geometry:
                raise ValueError("no geometry found in the file" + _why_empty(path, ext))
            _check_complete(path, ext, data)
    except FileNotFoundError as exc:  # a file it refers to (a .gltf's buffer or image): the file itself exists
        raise ValueError(f"{reading}: a file it refers to is missing: '{exc.filename or exc}' (looked for in "
                         f"'{path.absolute().parent}'); keep the files it names next to it, or export it as one .glb") from exc
    except (OSError, ValueError, KeyError, IndexError, TypeError, UnicodeDecodeError, EOFError) as exc:
        raise ValueError(f"{reading}: {exc}") from exc
    except Exception as exc:  # noqa: BLE001 - third-party readers raise anything
        raise ValueError(f"{reading}: {type(exc).__name__}: {exc}") from exc
    if kind != "points":  # a mesh file, or an .npz mesh
        parts = list(data.geometry.values()) if isinstance(data, trimesh.Scene) else [data]
        for part in parts:  # the error from_mesh gives, before anything is dropped
            as_points(np.asarray(getattr(part, "vertices", np.zeros((0, 3)))), f"{name} vertices", dim=3)
        try:
            kind, data = _mesh_or_points(data, parts, name)
        except Exception as exc:  # noqa: BLE001 - third-party processing raises anything
            raise ValueError(f"{reading}: {type(exc).__name__}: {exc}") from exc
    if kind == "points":
        data = np.asarray(data)
        if data.size == 0:
            raise ValueError(f"could not read '{path}': it contains no points")
        return _from_points(data, scale, **options)
    return _from_mesh(data, scale, **options)


#: glTF extensions trimesh does not decode: their geometry would be read as zeros or unscaled integers.
UNREAD_GLTF_EXTENSIONS = ("KHR_draco_mesh_compression", "EXT_meshopt_compression", "KHR_mesh_quantization")


def _why_empty(path, ext) -> str:
    """Why a file held no geometry, where its first bytes say (another format, a binary STL's count), else ""."""
    with open(path, "rb") as handle:
        head = handle.read(84)
    for magic, kind in ((b"ply", ".ply"), (b"OFF", ".off"), (b"glTF", ".glb"), (b"v ", ".obj")):
        if head.startswith(magic) and ext != kind:
            return f": it is a {kind} file by its first bytes; rename it with the {kind} extension"
    if ext == ".stl" and len(head) == 84 and not head.lstrip().startswith(b"solid"):
        count, size = int.from_bytes(head[80:84], "little"), path.stat().st_size
        if size != 84 + 50 * count:
            return (f": as a binary STL its header declares {count} triangles, {84 + 50 * count} bytes, and the file "
                    f"has {size} bytes (truncated, damaged, or not an STL)")
    return ""


def _check_complete(path, ext, data):
    """ValueError for a file read as less than it holds: a PLY or OFF with fewer vertices or faces than its header
    declares (truncated), an OBJ whose last line is cut short, a PLY of triangle strips, a glTF whose geometry is compressed or quantised in a way trimesh
    does not decode."""
    if ext in (".gltf", ".glb"):
        raw = path.read_bytes()
        try:
            if ext == ".glb":  # 12-byte header, then the JSON chunk: its length, its type, its text
                raw = raw[20:20 + int.from_bytes(raw[12:16], "little")]
            used = set(json.loads(raw.decode("utf-8")).get("extensionsUsed", []))
        except (ValueError, UnicodeDecodeError, AttributeError):
            return  # (read by trimesh all the same: nothing more to say)
        unread = sorted(used & set(UNREAD_GLTF_EXTENSIONS))
        if unread:
            raise ValueError(f"its geometry uses {', '.join(unread)}, which the glTF reader does not decode (the parts "
                             "would come out as zeros or integers): export it again without mesh compression or "
                             "quantisation")
        return
    if ext == ".obj":
        _check_obj_end(path)
        return
    if ext not in (".ply", ".off"):
        return
    with open(path, "rb") as handle:
        head = handle.read(4096).decode("latin-1")
    if ext == ".ply":
        declared = {m.group(1): int(m.group(2)) for m in re.finditer(r"^element (vertex|face) (\d+)", head, re.M)}
    else:  # OFF: the counts on the first line that is not a comment, after the keyword
        words = " ".join(line.split("#")[0] for line in head.splitlines()[:3]).split()
        counts = [w for w in words if w.isdigit()][:2]
        declared = dict(zip(("vertex", "face"), map(int, counts)))
    parts = list(data.geometry.values()) if isinstance(data, trimesh.Scene) else [data]
    read = {"vertex": sum(len(getattr(p, "vertices", ())) for p in parts),
            "face": sum(len(getattr(p, "faces", ())) for p in parts)}
    if ext == ".ply" and not read["face"] and re.search(r"^element tristrips [1-9]", head, re.M):
        raise ValueError("its faces are triangle strips (a 'tristrips' element), which the PLY reader does not read: "
                         "export it with a 'face' element")
    short = [f"{read[k]} of its {n} {k}{'ices' if k == 'vertex' else 's'}" for k, n in declared.items() if read[k] < n]
    if short:
        raise ValueError(f"it holds {' and '.join(short)} its header declares: the file is truncated or damaged; "
                         "export it again")


def _check_obj_end(path):
    """ValueError when an OBJ file's last line is a vertex or a face cut short (fewer than 3 numbers): a truncated
    file, which the OBJ reader reads as a mesh with a hole or as vertices of the wrong dimension."""
    with open(path, "rb") as handle:
        handle.seek(0, os.SEEK_END)
        handle.seek(max(0, handle.tell() - 4096))
        tail = handle.read().decode("latin-1")
    lines = tail.rstrip().splitlines()
    last = lines[-1].split("#")[0].split() if lines else []
    if last and last[0] in ("v", "f") and len(last) < 4:
        what = "a vertex needs 3 coordinates" if last[0] == "v" else "a face needs 3 vertices"
        raise ValueError(f"its last line ({' '.join(last)!r}) is cut short ({what}): the file is truncated; "
                         "export it again")


def _object_path(value) -> Path:
    """``load``'s path as a Path; a mesh, a point cloud or anything else that is not a path is refused with
    the function that takes it."""
    if isinstance(value, (str, os.PathLike)):
        return as_path(value, "the object file")
    if isinstance(value, (trimesh.Trimesh, trimesh.Scene)):
        hint = ": for a trimesh mesh already in memory use sg.objects.from_mesh(mesh)"
    elif isinstance(value, (np.ndarray, list, tuple, trimesh.PointCloud)):
        hint = ": for points already in memory use sg.objects.from_points(points)"
    else:
        hint = ""
    raise TypeError(f"path must be a file path (str or os.PathLike), got {type(value).__name__}{hint}")


def get(name_or_path, **kwargs) -> GraspObject:
    """A built-in object by name, or an object loaded from a file.

    Parameters
    ----------
    name_or_path : str or os.PathLike
        ``"ellipsoid"``, ``"cup"``, ``"bell"``, ``"goblet"``, or a file path
        for `load`.
    **kwargs
        Passed to the factory or to `load`.

    Returns
    -------
    GraspObject

    Raises
    ------
    TypeError
        If it is neither a string nor a path.
    ValueError
        If it is neither a built-in name nor an existing file (the message
        lists the built-ins), or is empty.

    Examples
    --------
    >>> import synergrasp as sg
    >>> sorted(sg.objects.BUILTINS)
    ['bell', 'cup', 'ellipsoid', 'goblet']
    >>> sg.objects.get("cup")
    GraspObject('cup', 6 pieces, 75 x 75 x 80 mm, L=51.5)
    >>> sg.objects.get("ellipsoid", tolerance=0.2).info["max_gap"] <= 0.2   # factory options
    True
    """
    from .shapes import BUILTINS

    if not isinstance(name_or_path, (str, os.PathLike)):
        raise TypeError(f"an object is a built-in name ({', '.join(BUILTINS)}) or a file path, "
                        f"got {type(name_or_path).__name__}")
    if isinstance(name_or_path, str) and name_or_path.lower() in BUILTINS:
        return BUILTINS[name_or_path.lower()](**kwargs)
    if not str(name_or_path).strip():  # Path("") is the current folder
        raise ValueError(f"the object name is empty: give a built-in ({', '.join(BUILTINS)}) or a file path")
    path = Path(name_or_path).expanduser()
    if path.is_file():
        return load(path, **kwargs)
    if path.is_dir():
        raise ValueError(f"object {str(name_or_path)!r} is a folder: give a mesh or point-cloud file in it "
                         f"({', '.join(SUPPORTED_FORMATS)}) or a built-in ({', '.join(BUILTINS)})")
    raise ValueError(
        f"unknown object {str(name_or_path)!r}: not a built-in ({', '.join(BUILTINS)}) and no such file"
    )
