"""An independent dense check of the hand's clearance: sample points tested against the object's true mesh.

Used by ``bench_reach.py`` and by the tests of ``synergrasp.planner.clearance``
as the independent reference: no fcl, no convex pieces. Each phalanx capsule
is the set of points within its radius of its axis, so its signed distance
to a solid is the smallest signed distance of its axis points minus the
radius (exact outside the object; inside, the depth of the ball around the
deepest axis point, the translation depth where the surface is locally
flat). The palm box is sampled on its six faces, on grids refined where the
minimum can be (`box_clearance`). Signed distances come from
trimesh (``trimesh.proximity.signed_distance``, positive inside; the sign
is flipped here: positive outside).
"""

from __future__ import annotations

import numpy as np
import trimesh


def axis_samples(ends, spacing):
    """Points along each capsule axis, (k, m, 3), at most ``spacing`` apart."""
    length = np.linalg.norm(ends[:, 1] - ends[:, 0], axis=1).max()
    t = np.linspace(0.0, 1.0, max(2, int(np.ceil(length / spacing)) + 1))
    return ends[:, None, 0] + t[None, :, None] * (ends[:, None, 1] - ends[:, None, 0])


def box_clearance(signed, center, axes, half, spacing):
    """Smallest ``signed`` distance over the faces of a box, by refining a grid on each face.

    Each face is cut into square cells whose centres are sampled; a cell is
    split in four while its centre is within half its diagonal of the best
    value found (the signed distance changes by at most the distance moved,
    so only such cells can hold the minimum), until the cells are
    ``spacing`` wide.

    Parameters
    ----------
    signed : callable
        ``(m, 3) -> (m,)`` signed distances.
    center : (3,) float
    axes : (3, 3) float
        Columns: the box's axes in the world.
    half : (3,) float
        Half sizes.
    spacing : float
        Finest cell size (mm).

    Returns
    -------
    float
    """
    faces = []
    for i in range(3):
        j, k = [a for a in range(3) if a != i]
        for sign in (-1.0, 1.0):
            faces.append((i, j, k, sign))
    size = 8.0 * spacing
    cells = []  # (face, a, b, cell size)
    for f, (i, j, k, sign) in enumerate(faces):
        na, nb = (max(1, int(np.ceil(2 * half[x] / size))) for x in (j, k))
        a = -half[j] + (np.arange(na) + 0.5) * (2 * half[j] / na)
        b = -half[k] + (np.arange(nb) + 0.5) * (2 * half[k] / nb)
        for x in a:
            for y in b:
                cells.append((f, x, y, max(2 * half[j] / na, 2 * half[k] / nb)))
    best = np.inf
    while cells:
        local = np.zeros((len(cells), 3))
        for r, (f, x, y, _) in enumerate(cells):
            i, j, k, sign = faces[f]
            local[r, i], local[r, j], local[r, k] = sign * half[i], x, y
        values = signed(center + local @ axes.T)
        best = min(best, float(values.min()))
        keep = [(c, v) for c, v in zip(cells, values) if c[3] > spacing and v <= best + c[3] / np.sqrt(2.0)]
        cells = [(f, x + dx * w / 4, y + dy * w / 4, w / 2) for (f, x, y, w), _ in keep for dx in (-1, 1) for dy in (-1, 1)]
    return best


def sampled_clearance(hand, mesh, u, spacing=0.5, band=20.0):
    """Signed distance (mm, positive outside) of each capsule and of the palm box to ``mesh`` at ``u``.

    Only shapes within ``band`` mm are measured; a farther one gets ``inf``.

    Parameters
    ----------
    hand : SynergyHand
    mesh : trimesh.Trimesh
        A watertight mesh of the object.
    u : (6 + n_syn,) float
    spacing : float
        Largest distance between samples (mm).
    band : float
        mm.

    Returns
    -------
    (k + 1,) float
        The capsules in the order of ``hand.segments(u).labels``, then the palm.
    """
    geo = hand.segments(u)
    query = trimesh.proximity.ProximityQuery(mesh)
    lo, hi = mesh.bounds[0] - band, mesh.bounds[1] + band
    out = np.full(len(geo.capsules) + 1, np.inf)
    for i, points in enumerate(axis_samples(geo.capsules, spacing)):
        near = points[np.all((points >= lo - geo.radius) & (points <= hi + geo.radius), axis=1)]
        if len(near):
            out[i] = float((-query.signed_distance(near)).min()) - geo.radius
    corners = geo.palm_corners
    if np.all(corners.max(axis=0) >= lo) and np.all(corners.min(axis=0) <= hi):
        out[-1] = box_clearance(lambda p: -query.signed_distance(p), geo.palm_center, geo.palm_axes,
                                geo.palm_half_extents, spacing)
    out[out >= band] = np.inf  # a shape's nearest point may lie outside the band: only smaller values are exact
    return out


if __name__ == "__main__":
    raise SystemExit(f"{__file__} is a helper module, not a script: bench_reach.py and verification.py import it")
