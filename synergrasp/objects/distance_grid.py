"""A signed-distance bound of an object sampled on a regular grid: many hand points screened at once.

The planner's power seeds (`synergrasp.planner.starts.wrap_seeds`) score
hundreds of thousands of hand points against an object; the exact queries
(`contact_distance`, python-fcl) are too slow for that and are kept for the
few candidates that survive. The grid holds `PieceIndex.min_plane_bound`, the
largest facet-plane value of the nearest piece: exactly the signed distance
inside a piece, a lower bound of the distance outside; between nodes it is
interpolated linearly, which is off by less than the node spacing. It is read
at points (`DistanceGrid.__call__`) or at sets of points in many poses
(`DistanceGrid.posed`, which places them itself and can stop reading a set at
its first point below a floor).

The nodes are filled block by block. Every facet plane changes by at most
``L r`` between a block's centre and a node within ``r`` of it (``L`` the
largest norm of the planes' normals, 1 up to round-off), so at the block's
nodes a piece's bound can only come from its facets within ``2 L r`` of its
largest value at the centre, and only the pieces whose bound at the centre is
within ``2 L r`` of the smallest can be the nearest. The blocks of `BLOCKS`
nodes a side choose their candidates this way among all facets, their
sub-blocks among the block's candidates, and every node evaluates only its
sub-block's: the values are those of `PieceIndex.min_plane_bound` at the
nodes, bit for bit, at a small part of its cost.
"""

from __future__ import annotations

import numpy as np

from .._jit import helper, kernel

#: Nodes a side of the blocks and of their sub-blocks whose candidate facets are chosen together.
BLOCKS = (8, 2)
#: Added to the pruning margins: the facet values at a block's centre are rounded.
_ROUND_OFF = 1e-6
#: The pose `DistanceGrid.__call__` reads its points in.
_IDENTITY, _ORIGIN = np.eye(3)[None], np.zeros((1, 3))


class DistanceGrid:
    """The pieces' signed-distance bound on a regular grid around an object.

    Parameters
    ----------
    index : PieceIndex
        The object's pieces.
    bounds : (2, 3) float
        The object's bounding box (mm).
    pad : float
        Margin around the box (mm). Points farther out read ``pad``.
    cells : int
        Cells along the box's longest side (with the margin).
    min_spacing : float
        Smallest node spacing (mm).

    Attributes
    ----------
    spacing : float
        Node spacing (mm).
    origin : (3,) float
        The first node.
    values : (nx, ny, nz) float
        The bound at every node (mm; < 0 inside).

    Examples
    --------
    >>> from synergrasp import objects
    >>> obj = objects.ellipsoid()                     # semi-axes 30, 40, 50 mm
    >>> grid = obj.distance_grid
    >>> grid([[0.0, 0.0, 45.0], [0.0, 0.0, 55.0], [0.0, 0.0, 500.0]]).round(0).tolist()
    [-5.0, 5.0, 12.0]
    """

    def __init__(self, index, bounds, pad=12.0, cells=40, min_spacing=1.5):
        bounds = np.asarray(bounds, dtype=float)
        low, high = bounds[0] - pad, bounds[1] + pad
        self.spacing = max(float((high - low).max()) / cells, float(min_spacing))
        shape = np.ceil((high - low) / self.spacing).astype(int) + 1
        axes = [low[i] + self.spacing * np.arange(shape[i]) for i in range(3)]
        self.origin = low
        self.pad = float(pad)
        planes, start = index.planes, index.plane_start
        slope = float(np.linalg.norm(planes[:, :3], axis=1).max())
        self.values = np.empty(shape)
        every = np.stack([start[:-1], start[1:]], axis=1).ravel()  # every piece, with all its facets
        lists = [a for _ in BLOCKS for a in (np.empty_like(every), np.empty(len(planes), dtype=np.int64))]
        scratch = [np.empty(len(planes)), np.empty(len(start) - 1)]  # facet values at a centre, piece bounds
        _fill(*axes, planes, every, np.arange(len(planes)), slope, np.array(BLOCKS, dtype=np.int64), *scratch, *lists,
              self.values)
        self.values.setflags(write=False)

    def __call__(self, points) -> np.ndarray:
        """The bound at points, interpolated linearly between nodes.

        Parameters
        ----------
        points : (..., 3) array_like
            mm.

        Returns
        -------
        (...) float
            mm; ``pad`` outside the grid (and for NaN points).

        Raises
        ------
        ValueError
            If the last axis of ``points`` is not 3.
        """
        points = np.asarray(points, dtype=float)
        if points.shape[-1:] != (3,):
            raise ValueError(f"points must have shape (..., 3) (mm), got shape {points.shape}")
        flat = np.ascontiguousarray(points.reshape(1, -1, 3))
        out = np.empty((1, 1, flat.shape[1]))  # one set in the identity pose: x * 1 + y * 0 + z * 0 + 0 is x
        _posed(self.values, self.origin, self.spacing, self.pad, flat, _IDENTITY, _ORIGIN,
               np.full(flat.shape[1], -np.inf), out)
        return out.reshape(points.shape[:-1])

    def posed(self, points, rotations, translations, floors=None) -> np.ndarray:
        """The bound at sets of points placed in many poses, with an optional cut for screens.

        ``out[p, s, i]`` is the bound (as `__call__` gives it, up to the
        placement's round-off) at ``rotations[p] @ points[s, i] +
        translations[p]``, without building the placed points. With
        ``floors``, the points of each set are read in order in each pose
        until one reads below its floor (or its value or floor is NaN); the
        set's later points then read -inf, not evaluated. So the last point
        read of a set is at or above its floor exactly when every point
        before it was: a screen that rejects a pose at its first point too
        deep puts its most selective points first and tests the last.

        Parameters
        ----------
        points : (g, m, 3) array_like
            g sets of m points, in the poses' frame (mm).
        rotations : (n, 3, 3) array_like
            Each pose's rotation (columns: its frame's axes in the world).
        translations : (n, 3) array_like
            Each pose's origin (mm).
        floors : (m,) array_like, optional
            mm; default: no cut.

        Returns
        -------
        (n, g, m) float
            mm; ``pad`` off the grid (and for NaN points), -inf after a cut.

        Raises
        ------
        ValueError
            If the shapes do not fit.

        Examples
        --------
        A point 35 mm along the local z axis and the local origin, placed
        as they are and turned onto the world's x axis, in the paper's
        ellipsoid (semi-axes 30, 40, 50 mm): 15 mm under the pole, then 5 mm
        off the side. With floors of 0, a set is cut at its first point
        inside:

        >>> from synergrasp import objects
        >>> grid = objects.ellipsoid().distance_grid
        >>> turn = np.array([[0.0, 0.0, 1.0], [0.0, 1.0, 0.0], [-1.0, 0.0, 0.0]])  # local z to world x
        >>> points, poses = [[[0.0, 0.0, 35.0], [0.0, 0.0, 0.0]]], [np.eye(3), turn]
        >>> grid.posed(points, poses, np.zeros((2, 3))).round(0).tolist()
        [[[-14.0, -28.0]], [[5.0, -28.0]]]
        >>> grid.posed(points, poses, np.zeros((2, 3)), floors=[0.0, 0.0]).round(0).tolist()
        [[[-14.0, -inf]], [[5.0, -28.0]]]
        """
        points = np.ascontiguousarray(points, dtype=float)
        rotations = np.ascontiguousarray(rotations, dtype=float)
        translations = np.ascontiguousarray(translations, dtype=float)
        n = len(rotations)
        if points.ndim != 3 or points.shape[2] != 3:
            raise ValueError(f"points must have shape (g, m, 3) (mm), got shape {points.shape}")
        if rotations.shape != (n, 3, 3) or translations.shape != (n, 3):
            raise ValueError(f"rotations and translations must have shapes (n, 3, 3) and (n, 3), got "
                             f"{rotations.shape} and {translations.shape}")
        floors = np.full(points.shape[1], -np.inf) if floors is None else np.ascontiguousarray(floors, dtype=float)
        if floors.shape != points.shape[1:2]:
            raise ValueError(f"floors must have shape ({points.shape[1]},), one per point of a set, got {floors.shape}")
        out = np.empty((n, *points.shape[:2]))
        _posed(self.values, self.origin, self.spacing, self.pad, points, rotations, translations, floors, out)
        return out


@kernel
def _posed(values, origin, spacing, pad, points, rotations, translations, floors, out):
    """``out[p, s, i]``: ``values`` interpolated linearly at ``rotations[p] @ points[s, i] + translations[p]``
    (mm), ``pad`` off the grid; a set's points after the first one not above its floor read -inf, not evaluated."""
    nx, ny, nz = values.shape
    for p in range(rotations.shape[0]):
        R, t = rotations[p], translations[p]
        for s in range(points.shape[0]):
            cut = False
            for k in range(points.shape[1]):
                if cut:
                    out[p, s, k] = -np.inf
                    continue
                lx, ly, lz = points[s, k, 0], points[s, k, 1], points[s, k, 2]
                x = (lx * R[0, 0] + ly * R[0, 1] + lz * R[0, 2] + t[0] - origin[0]) / spacing  # node units
                y = (lx * R[1, 0] + ly * R[1, 1] + lz * R[1, 2] + t[1] - origin[1]) / spacing
                z = (lx * R[2, 0] + ly * R[2, 1] + lz * R[2, 2] + t[2] - origin[2]) / spacing
                if not (0.0 <= x <= nx - 1 and 0.0 <= y <= ny - 1 and 0.0 <= z <= nz - 1):  # NaN too
                    value = pad
                else:
                    i, j, m = min(int(x), nx - 2), min(int(y), ny - 2), min(int(z), nz - 2)
                    fx, fy, fz = x - i, y - j, z - m
                    c00 = values[i, j, m] * (1.0 - fx) + values[i + 1, j, m] * fx
                    c10 = values[i, j + 1, m] * (1.0 - fx) + values[i + 1, j + 1, m] * fx
                    c01 = values[i, j, m + 1] * (1.0 - fx) + values[i + 1, j, m + 1] * fx
                    c11 = values[i, j + 1, m + 1] * (1.0 - fx) + values[i + 1, j + 1, m + 1] * fx
                    value = (c00 * (1.0 - fy) + c10 * fy) * (1.0 - fz) + (c01 * (1.0 - fy) + c11 * fy) * fz
                out[p, s, k] = value
                cut = not value >= floors[k]  # a NaN value or floor cuts too


@helper
def _candidates(ax, ay, az, i0, i1, j0, j1, k0, k1, slope, planes, pieces, n_pieces, facets, facet_value, piece_value,
                out_pieces, out_facets):
    """Candidates of the box of nodes ``i0..i1, j0..j1, k0..k1`` among ``pieces``/``facets``; their count.

    ``pieces[2 p], pieces[2 p + 1]``: piece p's candidate facets are
    ``facets[pieces[2 p]:pieces[2 p + 1]]`` (its plane rows). The box's are
    written the same way to ``out_pieces``/``out_facets``.
    """
    cx, cy, cz = 0.5 * (ax[i0] + ax[i1]), 0.5 * (ay[j0] + ay[j1]), 0.5 * (az[k0] + az[k1])
    reach = slope * 0.5 * np.sqrt((ax[i1] - ax[i0]) ** 2 + (ay[j1] - ay[j0]) ** 2 + (az[k1] - az[k0]) ** 2)
    low = np.inf
    for p in range(n_pieces):
        value = -np.inf
        for t in range(pieces[2 * p], pieces[2 * p + 1]):
            f = facets[t]
            facet_value[f] = cx * planes[f, 0] + cy * planes[f, 1] + cz * planes[f, 2] + planes[f, 3]
            value = max(value, facet_value[f])
        piece_value[p] = value
        low = min(low, value)
    kept, n = 0, 0
    for p in range(n_pieces):
        if piece_value[p] - reach > low + reach + _ROUND_OFF:
            continue  # everywhere in the box, another piece's bound is smaller
        out_pieces[2 * kept] = n
        floor = piece_value[p] - 2.0 * reach - _ROUND_OFF
        for t in range(pieces[2 * p], pieces[2 * p + 1]):
            if facet_value[facets[t]] >= floor:
                out_facets[n] = facets[t]
                n += 1
        out_pieces[2 * kept + 1] = n
        kept += 1
    return kept


@kernel
def _fill(ax, ay, az, planes, every, rows, slope, blocks, facet_value, piece_value, pieces1, facets1, pieces2,
          facets2, out):
    """``out[i, j, k]``: ``min_p max_f`` of the facet planes at node ``(ax[i], ay[j], az[k])``, block by block.

    ``every``/``rows``: all pieces with all their facets, in `_candidates`' layout.
    """
    J = len(every) // 2
    big, small = blocks[0], blocks[1]
    for i0 in range(0, len(ax), big):
        for j0 in range(0, len(ay), big):
            for k0 in range(0, len(az), big):
                i1, j1, k1 = min(i0 + big, len(ax)) - 1, min(j0 + big, len(ay)) - 1, min(k0 + big, len(az)) - 1
                n1 = _candidates(ax, ay, az, i0, i1, j0, j1, k0, k1, slope, planes, every, J, rows, facet_value,
                                 piece_value, pieces1, facets1)
                for i2 in range(i0, i1 + 1, small):
                    for j2 in range(j0, j1 + 1, small):
                        for k2 in range(k0, k1 + 1, small):
                            i3, j3, k3 = min(i2 + small - 1, i1), min(j2 + small - 1, j1), min(k2 + small - 1, k1)
                            n2 = _candidates(ax, ay, az, i2, i3, j2, j3, k2, k3, slope, planes, pieces1, n1, facets1,
                                             facet_value, piece_value, pieces2, facets2)
                            for i in range(i2, i3 + 1):
                                for j in range(j2, j3 + 1):
                                    for k in range(k2, k3 + 1):
                                        x, y, z = ax[i], ay[j], az[k]
                                        best = np.inf
                                        for p in range(n2):
                                            value = -np.inf
                                            for t in range(pieces2[2 * p], pieces2[2 * p + 1]):
                                                f = facets2[t]
                                                value = max(value, x * planes[f, 0] + y * planes[f, 1]
                                                            + z * planes[f, 2] + planes[f, 3])
                                                if value >= best:
                                                    break
                                            best = min(best, value)
                                        out[i, j, k] = best
