"""Ray, nearest-point and signed-distance queries on a triangle mesh, quick on large meshes too.

The planner asks the object's true surface (`GraspObject.surface`) where the
seeds' inward rays leave it, where an accepted grasp's contacts are
nearest it, and how deep a phalanx lies in it. trimesh answers from an R-tree
of the triangles' boxes, which is quick for nearest points on the meshes the
planner usually sees: at most `TREE_FACES` faces, small ones and large closed
ones once simplified. Its rays are not (one R-tree query per ray: 23 ms for a
plan's 200 rays into the paper's 1280-face ellipsoid), and a larger mesh is
mostly one that could not be simplified, an open scan: there trimesh's tree
takes seconds to build (4 s for 450,000 faces) and a ray across the object
draws a candidate from every box it crosses (200 rays took 16 s).
`MeshQueries` answers without the tree:

* rays, on every mesh: every ray against every triangle in a compiled loop,
  trimesh's tests (the plane intersection, then the barycentric
  coordinates);
* nearest points, on a mesh of more than `TREE_FACES` faces: a k-d tree of
  the vertices bounds each point's distance by its nearest vertex, and only
  the faces with a corner near enough to hold its nearest point are compared
  with it (trimesh's comparison);
* signed distance, on such a mesh: as trimesh signs it, by the nearest
  face's normal where the point projects into that face, else by the parity
  of a line's crossings on either side of the point (trimesh's
  `contains_points`).
"""

from __future__ import annotations

from functools import cached_property

import numpy as np
import trimesh

from .._jit import helper, kernel

#: Meshes with more faces than this are queried for nearest points and signed distances without trimesh's R-tree.
TREE_FACES = 20000
#: trimesh's tests: a ray parallel to a plane within this (|d . n|) misses it; a point is in a
#: triangle within this of its barycentric range; a hit this far behind the origin still counts.
PARALLEL = 1e-5
BARYCENTRIC = 1e-13
BEHIND = 1e-6
#: trimesh's ``tol.merge``: a point this near the surface (mm) has distance 0 and no sign; of a point
#: projecting into its nearest face this far outside its barycentric range the sign comes from a ray;
#: two faces whose squared distances (mm^2) to a point differ by less are as near.
MERGE = 1e-8
#: Point-face pairs `MeshQueries.closest` compares at once on a large mesh.
PAIRS = 1_000_000
#: The direction of the parity rays (trimesh's `contains_points`), and of the second line drawn
#: through a point whose two rays disagree.
PARITY_RAY = np.array([0.4395064455, 0.617598629942, 0.652231566745])
SECOND_RAY = np.array([-0.7416198487, 0.3288290209, 0.5847050208])


class MeshQueries:
    """Queries on one triangle mesh, with what a large mesh needs built on first use.

    Parameters
    ----------
    mesh : trimesh.Trimesh

    Attributes
    ----------
    mesh : trimesh.Trimesh
    large : bool
        More than `TREE_FACES` faces: queried without trimesh's R-tree.

    Examples
    --------
    >>> import trimesh
    >>> q = MeshQueries(trimesh.creation.box((40.0, 40.0, 40.0)))
    >>> q.signed_distance([[0.0, 0.0, 15.0], [0.0, 0.0, 30.0]]).tolist()
    [5.0, -10.0]
    """

    def __init__(self, mesh):
        self.mesh = mesh
        self.large = len(mesh.faces) > TREE_FACES

    def first_hits(self, origins, directions):
        """The first triangle each ray meets, as ``mesh.ray.intersects_location(..., multiple_hits=False)``.

        Of hits at the same distance (coincident faces), the one whose normal
        runs most along the ray is kept: the face the ray leaves by.

        Parameters
        ----------
        origins, directions : (m, 3) float
            The rays (directions need not be unit).

        Returns
        -------
        locations : (h, 3) float
            Where each ray that meets the mesh first meets it (h <= m).
        rays : (h,) int
            Which ray, ascending.
        triangles : (h,) int
            The triangle met.
        """
        origins = np.ascontiguousarray(origins, dtype=float).reshape(-1, 3)
        directions = np.ascontiguousarray(directions, dtype=float).reshape(-1, 3)
        distance, met = np.empty(len(origins)), np.empty(len(origins), dtype=np.int64)
        _first_hits(origins, directions, *self._triangles, PARALLEL, BARYCENTRIC, BEHIND, distance, met)
        rays = np.flatnonzero(met >= 0)
        return origins[rays] + directions[rays] * distance[rays, None], rays, met[rays]

    def closest(self, points):
        """Each point's nearest point on the mesh, as ``trimesh.proximity.closest_point``.

        On a large mesh each point is compared with the faces that have a
        corner within ``sqrt(d^2 + reach^2)`` of it, ``d`` its nearest
        corner's distance and ``reach`` the farthest a point of a face can be
        from its nearest corner (`_reach`): these hold its nearest point. The
        comparison is trimesh's: of faces as near, the one whose normal points
        most towards the point (`_nearest_of_pairs`).

        Parameters
        ----------
        points : (n, 3) float

        Returns
        -------
        closest : (n, 3) float
        distance : (n,) float
        triangle : (n,) int
            The face of each nearest point.
        """
        points = np.asarray(points, dtype=float).reshape(-1, 3)
        if not self.large or not len(points):
            return trimesh.proximity.closest_point(self.mesh, points)
        used, tree = self._vertex_tree
        nearest, _ = tree.query(points)
        order, starts = self._vertex_faces
        closest, distance = np.empty((len(points), 3)), np.empty(len(points))
        triangle = np.empty(len(points), dtype=np.int64)
        batch, pairs = [], 0
        balls = tree.query_ball_point(points, np.sqrt(nearest**2 + self._reach**2) * (1.0 + 1e-9) + 1e-9)
        for i, ball in enumerate(balls):
            vertices = used[np.asarray(ball, dtype=np.int64)]
            lo, hi = starts[vertices], starts[vertices + 1]
            runs = np.repeat(lo - np.cumsum(np.r_[0, hi - lo][:-1]), hi - lo) + np.arange(int((hi - lo).sum()))
            batch.append((i, np.unique(order[runs])))
            pairs += len(batch[-1][1])
            if pairs >= PAIRS or i == len(balls) - 1:  # a bounded number of point-face pairs at once
                which = np.concatenate([np.full(len(f), k) for k, f in batch])
                faces = np.concatenate([f for _, f in batch])
                feet, pick = self._nearest_of_pairs(points[which], which, faces)
                closest[which[pick]], triangle[which[pick]] = feet[pick], faces[pick]
                distance[which[pick]] = np.linalg.norm(points[which[pick]] - feet[pick], axis=1)
                batch, pairs = [], 0
        return closest, distance, triangle

    def _nearest_of_pairs(self, points, which, faces):
        """Each point's foot on each of its faces (``which``: the point, ascending), and per point the pair picked.

        The nearest face; of faces as near within `MERGE` (an edge, a corner),
        the one whose normal points most towards the point (trimesh's rule,
        which weighs only its two nearest: at a corner its pick can differ).
        """
        feet = trimesh.triangles.closest_point(self.mesh.triangles[faces], points)
        away = points - feet
        squared = np.einsum("ij,ij->i", away, away)
        first = np.r_[True, which[1:] != which[:-1]]  # each point's first pair
        low = np.minimum.reduceat(squared, np.flatnonzero(first))[np.cumsum(first) - 1]
        near = squared - low < MERGE
        contest = near & (low > MERGE)  # off the surface: the face facing the point
        facing = np.einsum("ij,ij->i", self.mesh.face_normals[faces], away) / np.sqrt(np.maximum(squared, 1e-300))
        order = np.lexsort((faces, squared, np.where(contest, -facing, 0.0), ~near, which))
        return feet, order[np.flatnonzero(np.r_[True, which[order][1:] != which[order][:-1]])]

    def signed_distance(self, points):
        """Distance to the mesh, positive inside, as ``trimesh.proximity.signed_distance``.

        Parameters
        ----------
        points : (n, 3) float

        Returns
        -------
        (n,) float
        """
        points = np.asarray(points, dtype=float).reshape(-1, 3)
        if not self.large or not len(points):
            return trimesh.proximity.signed_distance(self.mesh, points)
        closest, distance, triangle = self.closest(points)
        signed = distance.copy()
        off = np.flatnonzero(distance > MERGE)
        normals = self.mesh.face_normals[triangle[off]]
        height = np.einsum("ij,ij->i", points[off] - closest[off], normals)
        foot = points[off] - normals * height[:, None]
        barycentric = trimesh.triangles.points_to_barycentric(self.mesh.triangles[triangle[off]], foot)
        within = ((barycentric >= -MERGE) & (barycentric <= 1.0 + MERGE)).all(axis=1)
        signed[off[within]] *= -np.sign(height[within])
        ray = off[~within]
        if len(ray):
            signed[ray] *= np.where(self._contains(points[ray]), 1.0, -1.0)
        return signed

    def _contains(self, points):
        """(n,) bool: trimesh's ray test of each point (``contains_points``), on the compiled loop.

        Outside the mesh's bounding box a point is outside. Else the faces a
        line through it crosses are counted ahead of and behind it: none on
        one side, outside; odd on both, inside; even on both, outside; a
        line whose two sides disagree (through an edge, or the mesh's
        opening) is drawn again along `SECOND_RAY` (fixed, where trimesh draws
        one at random), then taken as outside.
        """
        lo, hi = self.mesh.bounds
        inside = np.zeros(len(points), dtype=bool)
        todo = np.flatnonzero(((points >= lo) & (points <= hi)).all(axis=1))
        for direction in (PARITY_RAY, SECOND_RAY):
            if not len(todo):
                break
            counts = np.empty((len(todo), 2), dtype=np.int64)
            _crossings(np.ascontiguousarray(points[todo]), direction, *self._triangles, PARALLEL, BARYCENTRIC, counts)
            odd = counts % 2 == 1
            settled = (counts == 0).any(axis=1) | (odd[:, 0] == odd[:, 1])
            inside[todo[settled]] = odd[settled, 0] & (counts[settled] > 0).all(axis=1)
            todo = todo[~settled]
        return inside

    @cached_property
    def _triangles(self):
        """The compiled loops' triangle data: first corner, normal, two edges, and their Gram terms."""
        corners = np.asarray(self.mesh.triangles, dtype=float)
        e1, e2 = corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0]
        d00, d01, d11 = (e1 * e1).sum(axis=1), (e1 * e2).sum(axis=1), (e2 * e2).sum(axis=1)
        with np.errstate(divide="ignore"):
            inverse = 1.0 / (d00 * d11 - d01 * d01)  # inf for a degenerate triangle: it is never met
        return (np.ascontiguousarray(corners[:, 0]), np.ascontiguousarray(self.mesh.face_normals, dtype=float), e1,
                e2, d00, d01, d11, inverse)

    @cached_property
    def _vertex_tree(self):
        """The vertices some face uses, and a k-d tree of them."""
        from scipy.spatial import cKDTree

        used = np.unique(np.asarray(self.mesh.faces, dtype=np.int64))
        return used, cKDTree(np.asarray(self.mesh.vertices, dtype=float)[used])

    @cached_property
    def _reach(self) -> float:
        """The farthest a point of a face can be from the face's nearest corner: the longest edge over sqrt(3).

        (At most the circumradius of an acute face, half the longest edge of another.)
        """
        corners = np.asarray(self.mesh.triangles, dtype=float)
        return float(np.sqrt(((corners - np.roll(corners, 1, axis=1)) ** 2).sum(axis=2)).max() / np.sqrt(3.0))

    @cached_property
    def _vertex_faces(self):
        """The faces of each vertex: face indices sorted by vertex, and each vertex's start among them."""
        faces = np.asarray(self.mesh.faces, dtype=np.int64).ravel()
        order = np.argsort(faces, kind="stable")
        starts = np.searchsorted(faces[order], np.arange(len(self.mesh.vertices) + 1))
        return order // 3, starts


@kernel
def _first_hits(origins, directions, v0, normals, e1, e2, d00, d01, d11, inverse, parallel, barycentric, behind,
                distance, met):
    """For each ray, the parameter ``distance`` and triangle ``met`` of its first hit (-1: none).

    Of hits at the same distance (coincident faces) the one whose normal runs most along the ray is kept.
    """
    for r in range(len(origins)):
        ox, oy, oz = origins[r, 0], origins[r, 1], origins[r, 2]
        dx, dy, dz = directions[r, 0], directions[r, 1], directions[r, 2]
        squared = dx * dx + dy * dy + dz * dz
        best, hit, leaving = np.inf, -1, 0.0
        for f in range(len(v0)):
            across, t = _plane_hit(ox, oy, oz, dx, dy, dz, f, v0, normals, parallel)
            if across == 0.0:
                continue
            ahead = t * squared  # the hit's distance along the ray, times the direction's length
            if ahead <= -behind or ahead > best or (ahead == best and across <= leaving):
                continue
            if _in_triangle(ox + dx * t, oy + dy * t, oz + dz * t, f, v0, e1, e2, d00, d01, d11, inverse,
                            barycentric):
                best, hit, leaving = ahead, f, across
        distance[r] = best / squared if hit >= 0 else np.nan
        met[r] = hit


@kernel
def _crossings(points, direction, v0, normals, e1, e2, d00, d01, d11, inverse, parallel, barycentric, crossings):
    """How many triangles the line through each point along ``direction`` crosses ahead of it and behind it."""
    dx, dy, dz = direction[0], direction[1], direction[2]
    for r in range(len(points)):
        ox, oy, oz = points[r, 0], points[r, 1], points[r, 2]
        ahead, behind = 0, 0
        for f in range(len(v0)):
            across, t = _plane_hit(ox, oy, oz, dx, dy, dz, f, v0, normals, parallel)
            if across != 0.0 and t != 0.0 and _in_triangle(ox + dx * t, oy + dy * t, oz + dz * t, f, v0, e1, e2,
                                                           d00, d01, d11, inverse, barycentric):
                if t > 0.0:
                    ahead += 1
                else:
                    behind += 1
        crossings[r, 0], crossings[r, 1] = ahead, behind


@helper
def _plane_hit(ox, oy, oz, dx, dy, dz, f, v0, normals, parallel):
    """Where the line ``o + t d`` meets triangle ``f``'s plane: ``(across, t)``, with ``across`` the direction's
    component along the normal, returned as 0 (and ``t`` as 0) when the line runs within ``parallel`` of the plane."""
    across = dx * normals[f, 0] + dy * normals[f, 1] + dz * normals[f, 2]
    if abs(across) <= parallel:
        return 0.0, 0.0
    t = ((v0[f, 0] - ox) * normals[f, 0] + (v0[f, 1] - oy) * normals[f, 1] + (v0[f, 2] - oz) * normals[f, 2]) / across
    return across, t


@helper
def _in_triangle(x, y, z, f, v0, e1, e2, d00, d01, d11, inverse, barycentric):
    """Whether a point of triangle ``f``'s plane lies in it (barycentric coordinates, trimesh's Cramer rule)."""
    wx, wy, wz = x - v0[f, 0], y - v0[f, 1], z - v0[f, 2]
    d02 = e1[f, 0] * wx + e1[f, 1] * wy + e1[f, 2] * wz
    d12 = e2[f, 0] * wx + e2[f, 1] * wy + e2[f, 2] * wz
    b2 = (d00[f] * d12 - d01[f] * d02) * inverse[f]
    b1 = (d11[f] * d02 - d01[f] * d12) * inverse[f]
    b0 = 1.0 - b1 - b2
    return (-barycentric < b0 < 1.0 + barycentric and -barycentric < b1 < 1.0 + barycentric
            and -barycentric < b2 < 1.0 + barycentric)
