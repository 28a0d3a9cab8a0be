"""The true surface of an object given as a point cloud: nearest points, and planes fitted to their neighbours.

An object loaded from a point cloud has no mesh; its convex pieces cover
the cloud, and bridge its concavities. `PointSurface` stands for the
surface the cloud samples, where the planner judges a grasp
(`synergrasp.planner.stop.surface_check`, `synergrasp.planner.stop.mesh_depth`):
near a cloud point the surface is the plane fitted to its `NEIGHBOURS`
nearest points (their least-variance direction is the normal, as in Hoppe
et al., "Surface reconstruction from unorganized points", SIGGRAPH 1992),
within the disc those neighbours span; farther away there is no surface,
and the distance is to the nearest point itself. Near a sharp edge the
neighbours straddle it, and their plane is tilted between the faces.
"""

from __future__ import annotations

import numpy as np
from scipy.spatial import cKDTree

from .._checks import as_points
from .._vectors import sphere_directions

__all__ = ["NEIGHBOURS", "NET_NORMAL_POINTS", "VIEW_POINTS", "VIEW_DIRECTIONS", "TIE", "FACING", "PointSurface"]

#: Points of the cloud a local plane is fitted to (the point itself included).
NEIGHBOURS = 16
#: Most cloud points `PointSurface.net_normal` reads (a random sample of them beyond that).
NET_NORMAL_POINTS = 4000
#: Most cloud points `PointSurface.view_direction` judges (a random sample of them beyond that).
VIEW_POINTS = 1000
#: Lines of sight `PointSurface.view_direction` tries over the sphere, before it refines the best.
VIEW_DIRECTIONS = 128
#: Lines of sight that hide at most this share of points more than the best are as good (`view_direction`).
TIE = 0.01
#: A line of sight fewer than this share of the cloud's points face is not judged (`hidden_share`).
FACING = 0.3


class PointSurface:
    """A point cloud as a surface: nearest points, local planes and signed distances.

    Parameters
    ----------
    points : (n, 3) array_like
        Points on the surface (mm), at least `NEIGHBOURS` of them.
    neighbours : int
        Points per fitted plane.

    Attributes
    ----------
    points : (n, 3) float
        The distinct points, read-only.
    neighbours : int
    tree : scipy.spatial.cKDTree
        Over ``points``.

    Raises
    ------
    TypeError
        If ``points`` are not numbers.
    ValueError
        If ``points`` is not a finite (n, 3) array with at least
        ``neighbours`` distinct rows, or ``neighbours`` is below 3.

    Examples
    --------
    The faces of a 60 mm cube sampled on a 31 x 31 grid each; a contact
    2 mm above the middle of its top face:

    >>> import numpy as np
    >>> g = np.linspace(-30.0, 30.0, 31)
    >>> a, b = (x.ravel() for x in np.meshgrid(g, g))
    >>> c = np.full_like(a, 30.0)
    >>> cube = np.vstack([np.c_[a, b, s * c] for s in (1, -1)] + [np.c_[a, s * c, b] for s in (1, -1)]
    ...                  + [np.c_[s * c, a, b] for s in (1, -1)])
    >>> surface = PointSurface(cube)
    >>> closest, gap, inward = surface.closest([[1.0, 1.0, 32.0]], toward=[[0.0, 0.0, -1.0]])
    >>> closest.round(6).tolist(), gap.round(6).tolist(), (inward.round(6) + 0.0).tolist()
    ([[1.0, 1.0, 30.0]], [2.0], [[0.0, 0.0, -1.0]])

    A point 40 mm beside the cube's top face is over no plane: its distance is
    to the nearest point (the face's edge), and 5 mm below the face it is 5 mm
    inside:

    >>> float(surface.closest([[70.0, 0.0, 30.0]], toward=[[-1.0, 0.0, 0.0]])[1][0])
    40.0
    >>> surface.signed_distance([[0.0, 0.0, 25.0]], lambda p: np.abs(p).max(axis=1) < 30.0).round(6).tolist()
    [5.0]
    """

    def __init__(self, points, neighbours: int = NEIGHBOURS):
        if isinstance(neighbours, bool) or not isinstance(neighbours, (int, np.integer)) or neighbours < 3:
            raise ValueError(f"neighbours must be an integer >= 3 (points per fitted plane), got {neighbours!r}")
        self.points = np.unique(as_points(points, "points", dim=3), axis=0)  # a repeated point fits no plane
        self.points.setflags(write=False)
        if len(self.points) < neighbours:
            raise ValueError(f"a point surface needs at least {neighbours} distinct points to fit planes to, got "
                             f"{len(self.points)}")
        self.neighbours = int(neighbours)
        self.tree = cKDTree(self.points)

    def _spacing(self, rows):
        """The median distance of the points ``rows`` to their nearest neighbours in the cloud (mm)."""
        return float(np.median(self.tree.query(self.points[rows], k=2)[0][:, 1]))

    def _planes(self, points):
        """The plane fitted around each query point's nearest cloud point: that point's row, the plane's unit normal
        (either sign) and its radius (the distance to the farthest of the neighbours)."""
        _, nearest = self.tree.query(points)
        distance, near = self.tree.query(self.points[nearest], k=self.neighbours)
        around = self.points[near] - self.points[near].mean(axis=1, keepdims=True)  # (m, k, 3)
        _, vectors = np.linalg.eigh(np.einsum("mki,mkj->mij", around, around))
        return nearest, vectors[:, :, 0], distance[:, -1]

    def closest(self, points, toward, contains=None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Each point's foot on the surface, its distance to it and the surface's inward normal there.

        The foot is on the plane fitted around the nearest cloud point, and
        the distance is to that plane, when the point lies over the plane's
        disc (as far from the cloud point as its farthest neighbour); else
        the foot is the nearest cloud point itself (a point over a gap of the
        cloud, such as a hull face spanning a concavity, is as far from the
        surface as from its nearest sample).

        Parameters
        ----------
        points : (c, 3) array_like
            At least one point.
        toward : (c, 3) array_like
            Directions into the object at the points (e.g. the convex
            pieces' inward normals): each normal is given their sign.
        contains : callable, optional
            ``contains(points) -> (k,) bool``, e.g. `GraspObject.contains`:
            where ``toward`` is more than 60 degrees from the fitted normal
            (nearly along the surface, its sign unsure), the side of the
            plane it finds inside, as in `signed_distance`, if it finds one.

        Returns
        -------
        closest : (c, 3) float
        gap : (c,) float
            mm, >= 0.
        inward : (c, 3) float
            Unit normals into the object.
        """
        points = as_points(points, "points", dim=3)
        toward = as_points(toward, "toward", dim=3)
        if toward.shape != points.shape:
            raise ValueError(f"closest needs one direction per point: points {points.shape}, toward {toward.shape}")
        nearest, normals, radius = self._planes(points)
        along = np.einsum("ij,ij->i", normals, toward) / np.maximum(np.linalg.norm(toward, axis=1), 1e-300)
        normals *= np.where(along < 0.0, -1.0, 1.0)[:, None]
        unsure = np.flatnonzero(np.abs(along) < 0.5)
        if contains is not None and len(unsure):
            outward, known = self._outward(nearest[unsure], normals[unsure], radius[unsure], contains)
            normals[unsure[known]] = -outward[known]
        offset = points - self.points[nearest]
        height = np.einsum("ij,ij->i", offset, normals)
        foot = points - height[:, None] * normals
        over = np.linalg.norm(foot - self.points[nearest], axis=1) <= radius
        closest = np.where(over[:, None], foot, self.points[nearest])
        gap = np.where(over, np.abs(height), np.linalg.norm(offset, axis=1))
        return closest, gap, normals

    def signed_distance(self, points, contains) -> np.ndarray:
        """Distance of each point to the plane fitted around its nearest cloud point, positive inside.

        The sign of each plane's normal is the one whose side of the cloud
        point ``contains`` finds inside the object (half the plane's radius
        away). Where it finds both sides inside or neither (a concavity that
        the convex pieces cover, or a thin wall), which side is inside is not
        known, and the point counts as outside (the distance to the plane,
        negated): the pieces' own depth judges it there.

        Parameters
        ----------
        points : (m, 3) array_like
            At least one point.
        contains : callable
            ``contains(points) -> (k,) bool``, e.g. `GraspObject.contains`.

        Returns
        -------
        (m,) float
            mm (trimesh's convention: positive inside).
        """
        points = as_points(points, "points", dim=3)
        nearest, normals, radius = self._planes(points)
        outward, known = self._outward(nearest, normals, radius, contains)
        inside = -np.einsum("ij,ij->i", points - self.points[nearest], outward)
        return np.where(known, inside, -np.abs(inside))

    def hidden_share(self, direction, rows=None, spacing=None, normals=None) -> float:
        """The share of the cloud's points facing a line of sight that another point hides along it.

        Seen along ``direction``, a point is hidden when another cloud point
        lies on its line of sight (within the cloud's spacing of it, sideways)
        more than three spacings nearer the eye. Only the points whose surface
        faces the line (its fitted normal within 60 degrees of it, either
        way) are judged: where the surface runs along the line, as at an
        object's silhouette, points on it line up without hiding anything;
        and a line that fewer than `FACING` of them face is not judged (its
        share is 1): a camera faces most of what it sees, and along such a
        line a cloud all round an object (the walls of an open box seen
        through its opening) has few points to hide.
        One camera view of an object hides none of its points along the
        camera's line of sight (each of its rays stops at the first surface
        it meets); a cloud all round an object hides about half of them along
        any line.

        Parameters
        ----------
        direction : (3,) array_like
            The line of sight (either sign: a hidden point is hidden either way).
        rows : (k,) int, optional
            The points judged (default all).
        spacing : float, optional
            The cloud's spacing (mm; default the median distance of the points
            judged to their nearest neighbours).
        normals : (k, 3) float, optional
            The fitted unit normals at the points judged (either sign; default
            fitted here).

        Returns
        -------
        float
            From 0 to 1 (1 when fewer than `FACING` of the points judged face the line).
        """
        d = np.asarray(direction, dtype=float)
        d = d / np.linalg.norm(d)
        rows = np.arange(len(self.points)) if rows is None else np.asarray(rows)
        spacing = self._spacing(rows) if spacing is None else spacing
        side = np.cross(d, np.eye(3)[np.argmin(np.abs(d))])
        side /= np.linalg.norm(side)
        across = self.points @ np.c_[side, np.cross(d, side)]
        depth = np.r_[self.points @ d, -np.inf]  # (a missing neighbour hides nothing)
        if normals is None:
            normals = self._planes(self.points[rows])[1]
        cosine = np.abs(normals @ d)
        facing = cosine > 0.5
        if facing.mean() < FACING:
            return 1.0
        judged = rows[facing]
        # a surface tilted from the line lies sparser across it: its points' lines of sight are as wide as their spacing
        # seen along the line (up to twice the spacing)
        apart, near = cKDTree(across).query(across[judged], k=self.neighbours, distance_upper_bound=2.0 * spacing)
        near = np.where(apart <= spacing / cosine[facing][:, None], near, len(depth) - 1)
        return float((depth[near] > depth[judged, None] + 3.0 * spacing).any(axis=1).mean())

    def view_direction(self, toward=None) -> tuple[np.ndarray, float]:
        """The line of sight along which the cloud hides the fewest of its points (`hidden_share`), and that share.

        `VIEW_DIRECTIONS` lines over the sphere are tried, then 32 within
        about 14 degrees of the best; where several lines hide about as few
        (within `TIE` of the fewest), the one nearest ``toward`` is kept, or
        without it their mean, the middle of the lines the camera could have
        looked along. At most `VIEW_POINTS` points are judged,
        drawn at random (a fixed seed). A share near 0 says the cloud is one
        camera view, taken along the line returned (either sign: the side the
        camera was on is the side the surface's outward normals face).

        Parameters
        ----------
        toward : (3,) array_like, optional
            A guess of the line (e.g. `net_normal`), which picks among lines
            that hide about as few points.

        Returns
        -------
        direction : (3,) float
            A unit vector.
        share : float
            From 0 to 1.

        Examples
        --------
        The faces of a 60 mm cube, as in the class's example: the whole cube
        hides a third or more of its points along any line; its three faces
        around the corner (30, 30, 30) hide none along a line from which all
        three are seen (its components of one sign):

        >>> import numpy as np
        >>> g = np.linspace(-30.0, 30.0, 31)
        >>> a, b = (x.ravel() for x in np.meshgrid(g, g))
        >>> c = np.full_like(a, 30.0)
        >>> faces = [np.c_[a, b, s * c] for s in (1, -1)] + [np.c_[a, s * c, b] for s in (1, -1)] + [
        ...     np.c_[s * c, a, b] for s in (1, -1)]
        >>> share = PointSurface(np.vstack(faces)).view_direction()[1]
        >>> bool(share > 0.3)
        True
        >>> direction, share = PointSurface(np.vstack(faces[::2])).view_direction()
        >>> share, bool(np.all(direction > 0.0) or np.all(direction < 0.0))
        (0.0, True)
        """
        rows = np.arange(len(self.points))
        if len(rows) > VIEW_POINTS:
            rows = np.sort(np.random.default_rng(0).choice(rows, VIEW_POINTS, replace=False))
        spacing = self._spacing(rows)
        normals = self._planes(self.points[rows])[1]
        best = None
        for lines in (sphere_directions(VIEW_DIRECTIONS), None):
            if lines is None:  # refined about the best
                lines = np.vstack([best, best + 0.25 * sphere_directions(32)])
                lines /= np.linalg.norm(lines, axis=1, keepdims=True)
            shares = np.array([self.hidden_share(line, rows, spacing, normals) for line in lines])
            ties = lines[shares <= shares.min() + TIE]  # lines that all see the cloud about as well
            if toward is not None and np.any(toward):  # the nearest to the guess
                best = ties[np.argmax(np.abs(ties @ np.asarray(toward, dtype=float)))]
            else:  # the middle of them
                ties *= np.where(ties @ ties[0] < 0.0, -1.0, 1.0)[:, None]
                best = ties.sum(axis=0) / np.linalg.norm(ties.sum(axis=0))
        return best, self.hidden_share(best, rows, spacing, normals)

    def net_normal(self, contains) -> np.ndarray:
        """The area-weighted mean of the surface's outward unit normals at the cloud's points.

        A closed surface's outward normals integrate to zero over its area
        (the divergence theorem), so a cloud around the whole object gives a
        short vector, and a cloud of one side of it (one camera view, an
        object on a table scanned from above) a vector up to 1 long, toward
        the side seen. Each point's normal is that of the plane fitted to its
        neighbours, turned outward by ``contains`` as in `signed_distance`
        (points where it does not tell the sides apart are left out), and
        weighted by the disc those neighbours span (its radius squared), so
        that the mean does not depend on how densely a part is sampled. At
        most `NET_NORMAL_POINTS` points are read, drawn at random (a fixed seed).

        Parameters
        ----------
        contains : callable
            ``contains(points) -> (k,) bool``, e.g. `GraspObject.contains`.

        Returns
        -------
        (3,) float
            Of length 0 to 1; 0 when no point's side is known.

        Examples
        --------
        The faces of a 60 mm cube sampled on a grid, as in the class's
        example, and the same cloud without its bottom face, seen from above:

        >>> import numpy as np
        >>> g = np.linspace(-30.0, 30.0, 31)
        >>> a, b = (x.ravel() for x in np.meshgrid(g, g))
        >>> c = np.full_like(a, 30.0)
        >>> cube = np.vstack([np.c_[a, b, s * c] for s in (1, -1)] + [np.c_[a, s * c, b] for s in (1, -1)]
        ...                  + [np.c_[s * c, a, b] for s in (1, -1)])
        >>> inside = lambda p: np.abs(p).max(axis=1) < 30.0
        >>> bool(np.linalg.norm(PointSurface(cube).net_normal(inside)) < 0.02)
        True
        >>> (PointSurface(cube[cube[:, 2] > -30.0]).net_normal(inside).round(2) + 0.0).tolist()
        [0.0, 0.0, 0.21]
        """
        rows = np.arange(len(self.points))
        if len(rows) > NET_NORMAL_POINTS:  # a random sample (a fixed seed): every k-th point of the sorted cloud is not
            rows = np.sort(np.random.default_rng(0).choice(rows, NET_NORMAL_POINTS, replace=False))
        distance, near = self.tree.query(self.points[rows], k=self.neighbours)
        around = self.points[near] - self.points[near].mean(axis=1, keepdims=True)
        radius = distance[:, -1]
        outward, known = self._outward(rows, np.linalg.eigh(np.einsum("mki,mkj->mij", around, around))[1][:, :, 0],
                                       radius, contains)
        weight = np.where(known, radius**2, 0.0)
        total = weight.sum()
        return (weight @ outward) / total if total > 0 else np.zeros(3)

    def _outward(self, rows, normals, radius, contains):
        """The normals of the planes at cloud points ``rows`` turned outward by ``contains`` half their radius to
        either side, and whether it told the sides apart (one inside, the other not)."""
        base = self.points[rows]
        step = 0.5 * radius[:, None] * normals
        plus, minus = np.asarray(contains(base + step), bool), np.asarray(contains(base - step), bool)
        return normals * np.where(minus, 1.0, -1.0)[:, None], plus != minus
