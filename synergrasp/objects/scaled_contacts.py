"""sQ contacts: the object scaled about its centre until it touches each hand point (paper Sec. 3.2).

Along the ray from the object's centre c through a hand point p, the scaled
copy touches p at scale ``s = 1 / t`` with ``t = max {t : c + t (p - c) in a
piece}``: the contact carried back to the object's own scale is the point
``c + t (p - c)`` where the ray leaves the object, and its inward normal is
the supporting plane there (the dual of the LP ``max t s.t. c + t (p - c) =
sum lambda_v v, sum lambda = 1``). A ray that leaves a single piece through
the inside of a single facet needs no LP (`synergrasp.objects.facets.ray_exits`);
only rays at ties (edges, vertices, several pieces) are solved, stacked into
one LP.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .. import lp
from .._jit import kernel
from .._vectors import unit_rows
from ..lp.blocks import BlockLP
from ..tolerances import VALUE_TOL
from .contact_distance import check_points
from .facets import pick_rows, ray_exits

#: Pieces whose exit parameter is within this relative distance of the largest are candidates
#: for the ray's last exit (their exits are then compared within `VALUE_TOL`).
CANDIDATE_TOL = 1e-7


@dataclass(frozen=True)
class ScaledContacts:
    """Result of `GraspObject.scaled_contacts` (sQ contacts, one row per hand point).

    The object scaled by ``scale`` about its centre c touches the hand point
    p; along the ray from c, ``t = 1 / scale`` is the largest t with
    ``c + t (p - c)`` in the object.

    Attributes
    ----------
    scale : (n,) float
        Scale s at which the scaled object touches p (< 1 if p is inside).
    contact : (n, 3) float
        The contact carried back to the object's own scale:
        ``c + t (p - c)``, on the surface of the original object.
    normal : (n, 3) float
        Unit inward normal there (the dual's supporting plane). Scaling
        about c preserves normals, so it is also the normal of the scaled
        object at p.
    point : (n, 3) float
        The scaled contact itself, equal to p.
    grad_scale : (n, 3) float
        d scale / d p.
    jac_contact : (n, 3, 3) float
        d contact / d p (``[i, a, b] = d contact_a / d p_b``).
    jac_normal : (n, 3, 3) float
        d normal / d p: zero. The normal is piecewise constant (constant on
        each facet of the polytope) and jumps across edges, where the
        derivative does not exist (``degenerate`` is then set).
    piece : (n,) int
        Piece where the ray leaves the object.
    inside : (n,) bool
        p is inside the object (``scale < 1``).
    degenerate : (n,) bool
        The ray leaves through an edge or vertex (or ties between pieces):
        the derivatives are a valid one-sided choice.
    lp_solves : int
        Solver calls made: 0 when every ray leaves a single piece through the
        inside of a single facet (closed form), else 1 (the other rays' blocks
        stacked), more only for backends with an LP size limit (``Backend.max_columns``).

    Notes
    -----
    The scaled contact ``point`` is p itself (d point / d p = identity) and
    its normal is ``normal``.
    """

    scale: np.ndarray
    contact: np.ndarray
    normal: np.ndarray
    point: np.ndarray
    grad_scale: np.ndarray
    jac_contact: np.ndarray
    jac_normal: np.ndarray
    piece: np.ndarray
    inside: np.ndarray
    degenerate: np.ndarray
    lp_solves: int


def scaled_contacts(obj, points, backend="highs") -> ScaledContacts:
    """sQ contacts of hand points; see `GraspObject.scaled_contacts`."""
    P = check_points(points)
    solver = lp.get_backend(backend)
    index = obj.index
    c0 = obj.center
    U = P - c0
    length = np.sqrt(np.einsum("ij,ij->i", U, U))
    at_centre = length <= VALUE_TOL * obj.torque_scale
    if at_centre.any():
        raise ValueError(
            f"points rows {np.nonzero(at_centre)[0].tolist()} coincide with the object's centre "
            f"{c0.tolist()}: the ray from the centre through the point, and so the sQ scale, is undefined"
        )
    T = np.empty((len(P), index.n_pieces))
    _piece_exits(c0, U, index.planes, index.plane_start, np.empty(len(index.planes)), T)
    best = T.max(axis=1)
    missed = ~np.isfinite(best)
    if missed.any():
        raise ValueError(
            f"the rays from the object's centre {c0.tolist()} through points rows "
            f"{np.nonzero(missed)[0].tolist()} miss the object; the centre must lie inside the object"
        )
    # the pieces the ray leaves last (within a tolerance): one entry per (point, piece) pair, by piece, then point
    cand = T >= (best * (1 - CANDIDATE_TOL) - VALUE_TOL)[:, None]
    alone = cand.sum(axis=1) == 1
    n = len(P)
    pcs, pts = np.divmod(np.flatnonzero(cand.T), n)
    closed, ts, ys, counts, vid = ray_exits(index, np.broadcast_to(c0, (len(pts), 3)), U[pts], pcs, alone[pts])
    degs = np.zeros(len(pts), dtype=bool)
    blocks = BlockLP()
    if not closed.all():  # min -t  s.t.  t (p - c) - V^T lambda = -c,  sum lambda = 1
        rows = pts[~closed]
        blocks.add(U[rows, None, :], [-1.0], index.vertices[vid], counts, -1.0, np.broadcast_to(-c0, (len(rows), 3)), c0)
        lead_x, _, y, deg = blocks.solve(solver, "sQ ray")[0]
        ts[~closed], ys[~closed], degs[~closed] = lead_x[:, 0], y, deg
    chosen, degenerate = pick_rows(pts, pcs, -ts, ys, degs, n, index.n_pieces)
    t, y = ts[chosen], ys[chosen]
    dt = t[:, None] * y  # d t / d p
    return ScaledContacts(
        scale=1.0 / t,
        contact=c0 + t[:, None] * U,
        normal=unit_rows(y),
        point=P.copy(),
        grad_scale=-dt / t[:, None] ** 2,
        jac_contact=t[:, None, None] * (np.eye(3) + U[:, :, None] * y[:, None, :]),
        jac_normal=np.zeros((n, 3, 3)),
        piece=pcs[chosen],
        inside=t > 1.0,
        degenerate=degenerate,
        lp_solves=blocks.lp_solves,
    )


@kernel
def _piece_exits(c, U, planes, plane_start, depth, T):
    """Into ``T`` (n, J): the largest t with ``c + t u`` in piece j (the ray leaves it there), -inf when it misses it.

    ``depth`` (F,) is scratch: how far c lies behind each facet plane (< 0: in front).
    """
    n, J = len(U), len(plane_start) - 1
    for f in range(len(planes)):
        depth[f] = -(planes[f, 0] * c[0] + planes[f, 1] * c[1] + planes[f, 2] * c[2] + planes[f, 3])
    for i in range(n):
        for j in range(J):
            t_hi, t_lo, blocked = np.inf, 0.0, False
            for f in range(plane_start[j], plane_start[j + 1]):
                a = planes[f, 0] * U[i, 0] + planes[f, 1] * U[i, 1] + planes[f, 2] * U[i, 2]
                if a > 0.0:
                    t_hi = min(t_hi, depth[f] / a)
                elif a < 0.0:
                    t_lo = max(t_lo, depth[f] / a)
                elif depth[f] < 0.0:
                    blocked = True  # parallel to the plane, on its outer side
            T[i, j] = -np.inf if blocked or t_lo > t_hi * (1 + 1e-12) + 1e-12 else t_hi
