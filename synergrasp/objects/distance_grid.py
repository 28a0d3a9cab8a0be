"""A signed-distance bound of an object sampled on a regular grid: many hand points screened at once.

The planner's power seeds (`synergrasp.planner.starts.wrap_seeds`) score
hundreds of thousands of hand points against an object; the exact queries
(`contact_distance`, python-fcl) are too slow for that and are kept for the
few candidates that survive. The grid holds `PieceIndex.min_plane_bound`, the
largest facet-plane value of the nearest piece: exactly the signed distance
inside a piece, a lower bound of the distance outside; between nodes it is
interpolated linearly, which is off by less than the node spacing.
"""

from __future__ import annotations

import numpy as np

from .._jit import kernel


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
        nodes = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, 3)
        self.origin = low
        self.pad = float(pad)
        self.values = index.min_plane_bound(nodes).reshape(shape)
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
        flat = points.reshape(-1, 3)
        out = np.empty(len(flat))
        _trilinear(self.values, self.origin, self.spacing, self.pad, flat, out)
        return out.reshape(points.shape[:-1])


@kernel
def _trilinear(values, origin, spacing, pad, points, out):
    """``out[k]``: ``values`` interpolated linearly at ``points[k]`` (node units from ``origin``), ``pad`` off the grid."""
    nx, ny, nz = values.shape
    for k in range(points.shape[0]):
        x = (points[k, 0] - origin[0]) / spacing
        y = (points[k, 1] - origin[1]) / spacing
        z = (points[k, 2] - origin[2]) / spacing
        if not (0.0 <= x <= nx - 1 and 0.0 <= y <= ny - 1 and 0.0 <= z <= nz - 1):  # NaN too
            out[k] = pad
            continue
        i, j, m = min(int(x), nx - 2), min(int(y), ny - 2), min(int(z), nz - 2)
        fx, fy, fz = x - i, y - j, z - m
        c00 = values[i, j, m] * (1.0 - fx) + values[i + 1, j, m] * fx
        c10 = values[i, j + 1, m] * (1.0 - fx) + values[i + 1, j + 1, m] * fx
        c01 = values[i, j, m + 1] * (1.0 - fx) + values[i + 1, j, m + 1] * fx
        c11 = values[i, j + 1, m + 1] * (1.0 - fx) + values[i + 1, j + 1, m + 1] * fx
        out[k] = (c00 * (1.0 - fy) + c10 * fy) * (1.0 - fz) + (c01 * (1.0 - fy) + c11 * fy) * fz
