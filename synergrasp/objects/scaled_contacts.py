"""sQ contacts: the object scaled about its centre until it touches each hand point (paper Sec. 3.2).

Along the ray from the object's centre c through a hand point p, the scaled
copy touches p at scale ``s = 1 / t`` with ``t = max {t : c + t (p - c) in a
piece}``: the contact carried back to the object's own scale is the point
``c + t (p - c)`` where the ray leaves the object, and its inward normal is
the supporting plane there (the dual of the LP ``max t s.t. c + t (p - c) =
sum lambda_v v, sum lambda = 1``). A ray that leaves a single piece through
the inside of a single facet needs no LP (`synergrasp.objects.facets.ray_exit`);
only rays at ties (edges, vertices, several pieces) are solved, stacked into
one LP.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .. import lp
from .._vectors import unit_rows
from ..lp.blocks import Blocks, solve_blocks
from ..tolerances import DEGENERACY_TOL, VALUE_TOL
from . import facets
from .contact_distance import check_points

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


def scaled_contacts(obj, points, backend="native") -> ScaledContacts:
    """sQ contacts of hand points; see `GraspObject.scaled_contacts`."""
    P = check_points(points, obj)
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
    n, n_pieces = len(P), index.n_pieces
    m = n * n_pieces  # at most one row per (point, piece)
    missed = np.empty(n, dtype=bool)
    pts, pcs, ts, ys = np.empty(m, dtype=np.int64), np.empty(m, dtype=np.int64), np.empty(m), np.empty((m, 3))
    closed, n_vert = np.empty(m, dtype=bool), np.empty(m, dtype=np.int64)
    vids, counts = np.empty(3 * n * len(index.planes), dtype=np.int64), np.zeros(2, dtype=np.int64)
    facets.sq_rows(c0.copy(), U, index.planes, index.plane_start, index.vertices, index.facet_vertices, CANDIDATE_TOL, VALUE_TOL,
             DEGENERACY_TOL, facets.CLOSED_FORM, np.empty(len(index.planes)), np.empty(n_pieces),
             np.full(len(index.vertices), -1, dtype=np.int64), missed, pts, pcs, ts, ys, closed, n_vert, vids, counts)
    if missed.any():
        raise ValueError(
            f"the rays from the object's centre {c0.tolist()} through points rows "
            f"{np.nonzero(missed)[0].tolist()} miss the object; the centre must lie inside the object"
        )
    rows, nv = counts
    pts, pcs, ts, ys, closed = pts[:rows], pcs[:rows], ts[:rows], ys[:rows], closed[:rows]
    degs = np.zeros(rows, dtype=bool)
    lp_solves = 0
    if not closed.all():  # min -t  s.t.  t (p - c) - V^T lambda = -c,  sum lambda = 1
        lp_rows = ~closed
        r = pts[lp_rows]
        blocks = Blocks.uniform(U[r, None, :], [-1.0], index.vertices, vids[:nv], n_vert[:rows][lp_rows], -1.0,
                                np.broadcast_to(-c0, (len(r), 3)), c0)
        sol = solve_blocks(solver, blocks, what="sQ ray")
        ts[lp_rows], ys[lp_rows], degs[lp_rows], lp_solves = sol.lead_x, sol.y, sol.degenerate, sol.lp_solves
    chosen, flagged = np.full(n, -1, dtype=np.int64), np.zeros(n, dtype=bool)
    facets.pick_rows(pts, pcs, -ts, ys, degs, n_pieces, VALUE_TOL, np.full(n * n_pieces, -1, dtype=np.int64),
              np.full(n * n_pieces, -np.inf), np.full(n, -1, dtype=np.int64), chosen, flagged)
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
        degenerate=flagged,
        lp_solves=lp_solves,
    )
