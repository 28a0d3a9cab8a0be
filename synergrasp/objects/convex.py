"""Convex pieces: a vertex set with its hull planes, facets and fcl geometry.

An object is a union of convex pieces. Each `ConvexPiece` keeps

* ``vertices`` (k, 3): the hull's vertices (interior points dropped), the
  vertex set the LPs of the hand-point queries work on;
* ``planes`` (f, 4): the hull's facet planes ``[n, o]`` with unit outward
  normal n, so that ``x`` is inside iff ``n . x + o <= 0`` for every facet;
* ``facets`` (f, 3): the triangles (indices into ``vertices``), outward wound;
* ``fcl`` : the piece as an ``fcl.Convex`` for python-fcl's distance queries.

`checked_hull` is the hull of a point set with a clear error when it has no volume or an absurd
size (the loader's check of every mesh and cloud).
"""

from __future__ import annotations

import fcl
import numpy as np
from scipy.spatial import ConvexHull, QhullError

from .._checks import as_points
from .._jit import kernel

#: Relative size (to the piece's extent) below which a piece is flat.
FLAT_TOL = 1e-6


def _no_volume(name: str, detail: str) -> ValueError:
    return ValueError(f"{name} has no volume: {detail}; a grasp object needs a 3-D solid")


#: Object sizes (largest side, mm) outside this range are refused: no hand grasps them, and the
#: geometry's tolerances do not fit them. (10-500 mm is the usual range; outside it, a warning.)
SIZE_LIMITS = (1e-6, 1e6)


def checked_hull(points: np.ndarray, name: str) -> ConvexHull:
    """Convex hull of ``points``, with a clear error when they span no volume or are of an absurd size.

    Parameters
    ----------
    points : (m, 3) float
        Distinct points (mm).
    name : str
        What they are, for the messages.

    Returns
    -------
    scipy.spatial.ConvexHull

    Raises
    ------
    ValueError
        Points more than ``SIZE_LIMITS[1]`` or less than ``SIZE_LIMITS[0]`` mm
        across (the message suggests a scale), fewer than 4 points, or points
        that coincide or lie on a line or a plane.
    """
    size = float(np.ptp(points, axis=0).max()) if len(points) else 0.0
    lo, hi = SIZE_LIMITS
    if size > hi or 0.0 < size < lo:
        hint = "scale=1000 for metres" if size < lo else "scale=0.001 for micrometres"
        raise ValueError(f"{name} is {size:.3g} mm across, outside the {lo:g}-{hi:g} mm that synergrasp works with "
                         f"(lengths in mm): rescale it ({hint})")
    if len(points) < 4:
        raise _no_volume(name, f"it has only {len(points)} distinct point(s), at least 4 are needed")
    centred = points - points.mean(axis=0)
    extent = float(np.ptp(points, axis=0).max())
    if extent <= 0:
        raise _no_volume(name, "all its points coincide")
    sv = np.linalg.svd(centred, compute_uv=False)
    if sv[-1] <= FLAT_TOL * extent * np.sqrt(len(points)):
        on_line = sv[1] <= FLAT_TOL * extent * np.sqrt(len(points))
        raise _no_volume(name, "all its points lie on a line" if on_line else "all its points lie on a plane")
    try:
        return ConvexHull(points)
    except QhullError as exc:  # pragma: no cover - guarded by the SVD test above
        raise _no_volume(name, f"qhull failed ({str(exc).splitlines()[0]})") from exc


def farthest_point_subset(points: np.ndarray, k: int) -> np.ndarray:
    """Indices of ``k`` points chosen by farthest-point sampling (deterministic).

    The sampling starts from the extreme points along x, y and z, so the
    subset keeps the bounding box.

    Parameters
    ----------
    points : (n, 3) float
    k : int

    Returns
    -------
    (min(k, n),) int ndarray
    """
    n = len(points)
    if k >= n:
        return np.arange(n)
    seeds = np.unique(np.concatenate([points.argmin(axis=0), points.argmax(axis=0)]))[:k]
    chosen = np.empty(k, dtype=int)
    chosen[: len(seeds)] = seeds
    diff = points[:, None, :] - points[seeds][None]
    dist = np.einsum("ijk,ijk->ij", diff, diff).min(axis=1)
    _farthest(np.ascontiguousarray(points, dtype=float), dist, chosen, len(seeds))
    return np.sort(chosen)


@kernel
def _farthest(points, dist, chosen, start):
    """``chosen[start:]``: each the point farthest from those before (the first of equals), ``dist`` kept up to date."""
    for i in range(start, len(chosen)):
        pick, far = 0, -np.inf
        for p in range(len(points)):
            if dist[p] > far:
                pick, far = p, dist[p]
        chosen[i] = pick
        cx, cy, cz = points[pick, 0], points[pick, 1], points[pick, 2]
        for p in range(len(points)):
            dx, dy, dz = points[p, 0] - cx, points[p, 1] - cy, points[p, 2] - cz
            d = dx * dx + dy * dy + dz * dz
            if d < dist[p]:
                dist[p] = d


class ConvexPiece:
    """A convex piece of an object: hull vertices, facet planes, fcl geometry.

    Parameters
    ----------
    points : (n, 3) array_like
        Any points; the piece is their convex hull.
    name : str
        Used in error messages.
    max_vertices : int, optional
        If the hull has more vertices, keep this many by farthest-point
        sampling (the result is inscribed in the full hull).

    Attributes
    ----------
    vertices : (k, 3) float
        Hull vertices.
    planes : (f, 4) float
        Facet planes ``[n, o]``, unit outward ``n``; inside iff ``n . x + o <= 0``.
    facets : (f, 3) int
        Outward-wound triangles, indices into ``vertices``.
    volume : float
        Volume (mm^3).
    centroid : (3,) float
        Volume centroid.

    Raises
    ------
    ValueError
        If the points are fewer than 4, non-finite, or span no volume.
    """

    def __init__(self, points, name: str = "piece", max_vertices: int | None = None):
        points = as_points(points, name, dim=3)
        hull = checked_hull(np.unique(points, axis=0), name)
        verts = hull.points[hull.vertices]
        if max_vertices is not None and len(verts) > max_vertices:
            verts = verts[farthest_point_subset(verts, int(max_vertices))]
            hull = checked_hull(verts, name)
            verts = hull.points[hull.vertices]
        remap = np.full(len(hull.points), -1)
        remap[hull.vertices] = np.arange(len(hull.vertices))
        facets = remap[hull.simplices]
        planes = hull.equations.copy()
        # qhull's simplices are not consistently wound: orient each triangle outward
        tri = verts[facets]
        normal = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
        flip = np.einsum("ij,ij->i", normal, planes[:, :3]) < 0
        facets[flip] = facets[flip][:, ::-1]
        self.vertices = verts
        self.planes = planes
        self.facets = facets
        self.volume = float(hull.volume)
        # centroid: tetrahedra from an interior point to each (outward-wound) facet
        inner = verts.mean(axis=0)
        tri = verts[facets]
        vol = np.einsum("ij,ij->i", tri[:, 0] - inner, np.cross(tri[:, 1] - inner, tri[:, 2] - inner)) / 6.0
        tet_centroid = (tri.sum(axis=1) + inner) / 4.0
        self.centroid = (vol[:, None] * tet_centroid).sum(axis=0) / vol.sum()
        for arr in (self.vertices, self.planes, self.facets):
            arr.setflags(write=False)
        self._fcl = None

    def __repr__(self) -> str:
        return f"ConvexPiece({len(self.vertices)} vertices, {len(self.facets)} facets, volume {self.volume:.1f})"

    @property
    def fcl(self) -> fcl.CollisionObject:
        """The piece as an ``fcl.CollisionObject`` (an ``fcl.Convex``, identity transform)."""
        if self._fcl is None:
            faces = np.hstack([np.full((len(self.facets), 1), 3), self.facets]).ravel()
            geom = fcl.Convex(np.ascontiguousarray(self.vertices), len(self.facets), faces)
            self._fcl = fcl.CollisionObject(geom, fcl.Transform())
        return self._fcl

    def signed_distance_bound(self, points: np.ndarray) -> np.ndarray:
        """``max_f (n_f . p + o_f)`` for each point: <= 0 inside, else a lower bound of the distance.

        Parameters
        ----------
        points : (n, 3) float

        Returns
        -------
        (n,) float
        """
        return (points @ self.planes[:, :3].T + self.planes[:, 3]).max(axis=1)

    def transformed(self, rotation: np.ndarray, translation: np.ndarray, scale: float = 1.0) -> "ConvexPiece":
        """The piece moved by ``x -> scale * R x + t``."""
        return ConvexPiece(scale * self.vertices @ rotation.T + translation)
