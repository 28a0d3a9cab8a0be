"""cP, the contact pseudo-distance of hand points to an object (paper Sec. 3.2), with gradients.

The object is a union of convex pieces. The cP of a point p is the
pseudo-distance between A = {p} and each piece B (the simplex Q is the
default regular simplex of `synergrasp.regular_simplex`), the minimum over
pieces: > 0 outside the object, < 0 inside a piece (the most negative piece
wins). With the single point as A its weight is 1, so the separation LP
(Eq. 1) is ``min sum rho s.t. Q^T rho - V^T beta = -p, sum beta = 1`` and
each penetration LP (Eq. 3) is ``min -rho s.t. rho q_k + V^T beta = p,
sum beta = 1``: 4 rows each, the witness only on B. Gradient:
``d value / d p = -y`` (separation) or ``+y`` (penetration, the active k),
y the duals of the 3 coordinate rows.

The broad phase (`synergrasp.objects.broad_phase`) prunes the pieces that
cannot be a point's minimiser, the narrow phase
(`synergrasp.objects.facets`) the vertices that cannot carry an LP's
optimum; penetration rays that leave a piece through the inside of a facet
are settled in closed form, and all the remaining LPs of a call are solved
as one block-diagonal LP (`synergrasp.lp.blocks.solve_blocks`).

Known limitation: inside the object, the value is the penetration into the
single piece in which the point is deepest, not into the union; a point just
behind an internal cut between two pieces reads as shallow.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .. import lp
from .._checks import as_points
from ..lp.blocks import Blocks, solve_blocks
from ..tolerances import DEGENERACY_TOL, VALUE_TOL
from . import facets
from .broad_phase import SIMPLEX, Probe


@dataclass(frozen=True)
class ContactDistance:
    """Result of `GraspObject.contact_distance` (cP, one row per hand point).

    Attributes
    ----------
    value : (n,) float
        Pseudo-distance from each point to the object (mm of the simplex
        gauge): > 0 outside, 0 on the surface, < 0 inside.
    grad : (n, 3) float
        d value / d p.
    nearest : (n, 3) float
        Witness point on the object (the LP's ``point_b``).
    normal : (n, 3) float
        Unit inward normal of the object at ``nearest`` (the supporting plane
        from the LP dual).
    piece : (n,) int
        Index of the minimising piece.
    inside : (n,) bool
        The point is inside (or on) a piece: penetration LPs were used.
    degenerate : (n,) bool
        The derivative does not exist (degenerate LP, or a tie between
        pieces or penetration directions); ``grad`` is a valid one-sided choice.
    candidates : (n,) int
        Number of pieces that survived the broad phase.
    lp_solves : int
        Solver calls made: 1 (all blocks stacked), 0 when every point is
        inside and settled in closed form, more only for backends with an LP
        size limit (``Backend.max_columns``).
    """

    value: np.ndarray
    grad: np.ndarray
    nearest: np.ndarray
    normal: np.ndarray
    piece: np.ndarray
    inside: np.ndarray
    degenerate: np.ndarray
    candidates: np.ndarray
    lp_solves: int


#: Farthest (mm) a hand point may lie beyond an object's size from its centre, along any axis, in its queries (1 km:
#: the LPs lose their accuracy some thousands of times farther; a point this far is in other units or a wrong frame).
MAX_REACH = 1e6


def check_points(points, obj=None) -> np.ndarray:
    """Hand points as a validated (n, 3) float array (a clear ValueError or TypeError otherwise).

    With ``obj`` (a GraspObject), points farther than `MAX_REACH` plus its
    size (`GraspObject.size`) from its centre along an axis are refused too.

    Parameters
    ----------
    points : (n, 3) array_like
        Hand points (mm).
    obj : GraspObject, optional

    Returns
    -------
    (n, 3) float
    """
    try:
        P = as_points(points, "points", dim=3)
    except ValueError as exc:
        raise ValueError(f"{exc}; hand points must be an (n, 3) array in mm") from None
    if obj is not None and len(P):
        far = float(np.abs(P - obj.center).max())
        if far > MAX_REACH + obj.size:
            raise ValueError(f"a hand point lies {far:.3g} mm from {obj.name}'s centre along an axis, farther than "
                             f"{MAX_REACH:.0e} mm (1 km) beyond its size ({obj.size:.3g} mm): are the points in other "
                             "units than the object, or in another frame? Give both in mm, in one frame")
    return P


def contact_distance(obj, points, backend="native", *, ids=None) -> ContactDistance:
    """cP of hand points against an object; see `GraspObject.contact_distance`.

    Parameters
    ----------
    obj : GraspObject
    points : (n, 3) array_like
    backend : str or synergrasp.lp.Backend
    ids : (n,) int, optional
        An identity of each point across calls (e.g. its row in a fixed set
        of hand points, different for different sets). With it, each LP
        block starts from the basis its (point, piece, k) had at its last
        optimum on this object (a warm start for backends with
        ``basis_hints``: the values are those of the LP, only the solver's
        path to them changes).

    Returns
    -------
    ContactDistance
    """
    P = check_points(points, obj)
    solver = lp.get_backend(backend)
    return _solve(obj, obj.index.probe(P), solver, None if ids is None else np.asarray(ids, dtype=np.int64))


def cp_bounds(obj, points):
    """Cheap lower and upper bounds of the cP of points, without an LP.

    The bounds of the broad phase (`synergrasp.objects.broad_phase`), taken
    over all pieces: outside the object ``max(plane gauge bound, gauge
    support bound) <= cP <= gauge to the nearest vertex``; inside a piece
    ``-inf < cP <= 0``. Where a bound is attained (e.g. straight above a
    vertex) it can differ from the LP's value by round-off (about 1e-14
    relative).

    Parameters
    ----------
    obj : GraspObject
    points : (n, 3) float

    Returns
    -------
    lower, upper : (n,) float

    Examples
    --------
    >>> from synergrasp import objects
    >>> obj = objects.ellipsoid()
    >>> lower, upper = cp_bounds(obj, [[0.0, 0.0, 80.0], [0.0, 0.0, 0.0]])
    >>> value = obj.contact_distance([[0.0, 0.0, 80.0]]).value[0]
    >>> bool(lower[0] <= value + 1e-9 and value <= upper[0] + 1e-9), bool(lower[1] == -np.inf), bool(upper[1] == 0.0)
    (True, True, True)
    """
    return obj.index.probe(check_points(points, obj)).bounds()


def group_contact_distance(obj, points, groups, backend="native", *, ids=None, far=None
                           ) -> tuple[ContactDistance, np.ndarray]:
    """The smallest cP in each group of points, and the point attaining it.

    A point whose lower bound of cP exceeds the upper bound of another point
    of its group cannot attain the group's minimum and gets no LP (valid
    bounds, so the minima are unchanged; `PieceIndex.group_probe`); the
    bounds of the others are reused by one call of `contact_distance`.

    With ``far``, a group that the broad phase alone places beyond its
    ``far[g]`` gets no LP at all: its row is a lower bound of its cP (larger
    than ``far[g]``) with a zero gradient, for a caller that only reads the
    group when it is nearer (the planner's clearance rows).

    Parameters
    ----------
    obj : GraspObject
    points : (n, 3) float
    groups : (n,) int
        Group of each point, ``0 ... G-1``, each with at least one point.
    backend : str or synergrasp.lp.Backend
    ids : (n,) int, optional
        An identity of each point across calls (see `contact_distance`);
        default: its row in ``points``.
    far : (G,) float, optional
        The distance (mm, in the gauge of cP) beyond which a group is only
        bounded; default: every group exact.

    Returns
    -------
    ContactDistance
        One row per group: that of its point with the smallest cP (the first
        of them on a tie). A group only bounded has the bound as its value,
        zero gradients, NaN nearest point and normal, piece -1 and no
        candidates.
    best : (G,) int
        That point's row in ``points`` (a bounded group's first point).

    Examples
    --------
    Points 20 and 10 mm above the pole of the paper's ellipsoid (group 0),
    and one 2 mm above it (group 1):

    >>> from synergrasp import objects
    >>> points = [[0.0, 0.0, 70.0], [0.0, 0.0, 60.0], [0.0, 0.0, 52.0]]
    >>> r, best = group_contact_distance(objects.ellipsoid(), points, [0, 0, 1])
    >>> r.value.round(2).tolist(), best.tolist()
    ([10.0, 2.0], [1, 2])

    The first group only bounded beyond 5 mm (no LP; over the pole's facet
    the bound is its cP):

    >>> r, best = group_contact_distance(objects.ellipsoid(), points, [0, 0, 1], far=[5.0, np.inf])
    >>> r.value.round(2).tolist(), r.piece.tolist(), best.tolist()
    ([10.0, 2.0], [-1, 0], [0, 2])
    """
    P = check_points(points, obj)
    solver = lp.get_backend(backend)
    groups = np.asarray(groups, dtype=np.int64)
    ids = np.arange(len(P)) if ids is None else np.asarray(ids, dtype=np.int64)
    keep, probe, floor = obj.index.group_probe(P, groups, far)
    cp = _solve(obj, probe, solver, ids[keep])
    order = np.lexsort((cp.value, groups[keep]))
    ordered = groups[keep][order]
    first = np.empty(len(order), dtype=bool)
    first[:1], first[1:] = True, ordered[1:] != ordered[:-1]
    picked = order[first]
    fields = dict(value=cp.value[picked], grad=cp.grad[picked], nearest=cp.nearest[picked], normal=cp.normal[picked],
                  piece=cp.piece[picked], inside=cp.inside[picked], degenerate=cp.degenerate[picked],
                  candidates=cp.candidates[picked])
    best = keep[picked]
    if len(picked) < len(floor):  # groups only bounded
        solved = ordered[first]
        bounded = dict(value=floor, grad=np.zeros((len(floor), 3)), nearest=np.full((len(floor), 3), np.nan),
                       normal=np.full((len(floor), 3), np.nan), piece=np.full(len(floor), -1),
                       inside=np.zeros(len(floor), dtype=bool), degenerate=np.zeros(len(floor), dtype=bool),
                       candidates=np.zeros(len(floor), dtype=cp.candidates.dtype))
        for name, column in bounded.items():
            column[solved] = fields[name]
        fields = bounded
        first_point = np.empty(len(floor), dtype=np.int64)
        first_point[groups[::-1]] = np.arange(len(groups))[::-1]
        first_point[solved] = best
        best = first_point
    return ContactDistance(**fields, lp_solves=cp.lp_solves), best


def _solve(obj, probe: Probe, solver, ids=None) -> ContactDistance:
    """`contact_distance` of the points of a `Probe`, with a `synergrasp.lp` backend.

    ``ids`` (n,) int, optional: an identity of each point across calls; with
    it and a backend with ``basis_hints``, the LP blocks start from their
    last optimal bases (`synergrasp.lp.blocks.BasisMemory` of the object's index).
    """
    index = obj.index
    P, n, n_pieces = probe.P, len(probe.P), index.n_pieces
    cand, bound = index.candidates(probe)
    memory = index.memory if ids is not None and solver.basis_hints else None
    outside = cand & (probe.S > 0.0)
    n_sep, n_pen = int(outside.sum()), int(cand.sum()) - int(outside.sum())
    n_blocks = n_sep + 4 * n_pen
    n_ids = 3 * int((cand @ index.facet_counts).sum()) * 4
    n_lead, n_vert, sign, keys = (np.empty(n_blocks, dtype=np.int64), np.empty(n_blocks, dtype=np.int64),
                                  np.empty(n_blocks), np.empty(n_blocks, dtype=np.int64))
    lead, cost = np.empty((4 * n_blocks, 3)), np.empty(4 * n_blocks)
    origin, rhs, vids = np.empty((n_blocks, 3)), np.empty((n_blocks, 3)), np.empty(n_ids, dtype=np.int64)
    block_point, block_piece, block_sep = (np.empty(n_blocks, dtype=np.int64), np.empty(n_blocks, dtype=np.int64),
                                           np.empty(n_blocks, dtype=bool))
    closed_point, closed_piece = np.empty(4 * n_pen, dtype=np.int64), np.empty(4 * n_pen, dtype=np.int64)
    closed_value, closed_grad, closed_witness = np.empty(4 * n_pen), np.empty((4 * n_pen, 3)), np.empty((4 * n_pen, 3))
    counts = np.zeros(4, dtype=np.int64)
    facets.cp_blocks(P, probe.PQ, probe.S, cand, bound, np.zeros(n, dtype=np.int64) if ids is None else ids, SIMPLEX,
               index.planes, index.plane_start, index.facet_nq, index.facet_mq, index.facet_vertices, index.vertices,
               VALUE_TOL, DEGENERACY_TOL, facets.CLOSED_FORM, np.zeros(n * n_pieces, dtype=np.int64),
               np.zeros(n, dtype=np.int64), np.full(len(index.vertices), -1, dtype=np.int64), np.empty(3),
               n_lead, lead, cost, n_vert, vids, sign, origin, rhs, keys, block_point, block_piece, block_sep,
               closed_point, closed_piece, closed_value, closed_grad, closed_witness, counts)
    nb, nl, nv, nc = counts
    if nb:
        blocks = Blocks(n_lead[:nb], lead[:nl], cost[:nl], n_vert[:nb], index.vertices, vids[:nv], sign[:nb],
                        origin[:nb], rhs[:nb], keys[:nb])
        sol = solve_blocks(solver, blocks, memory, "cP")
        lead_x, witness, y, degenerate, lp_solves = sol
    else:
        lead_x, witness, y, degenerate, lp_solves = np.empty(0), np.empty((0, 3)), np.empty((0, 3)), np.empty(0, dtype=bool), 0
    value, grad, nearest, normal = np.empty(n), np.empty((n, 3)), np.empty((n, 3)), np.empty((n, 3))
    piece, inside, flagged = np.empty(n, dtype=np.int64), np.empty(n, dtype=bool), np.zeros(n, dtype=bool)
    m = nb + nc
    chosen = np.full(n, -1, dtype=np.int64)
    facets.cp_pick(lead_x, witness, y, degenerate, block_point[:nb], block_piece[:nb], block_sep[:nb], closed_point[:nc],
             closed_piece[:nc], closed_value[:nc], closed_grad[:nc], closed_witness[:nc], n_pieces, VALUE_TOL,
             np.empty(m, dtype=np.int64), np.empty(m, dtype=np.int64), np.empty(m), np.empty((m, 3)), np.empty((m, 3)),
             np.empty((m, 3)), np.empty(m, dtype=bool), np.full(n * n_pieces, -1, dtype=np.int64),
             np.full(n * n_pieces, -np.inf), np.full(n, -1, dtype=np.int64), chosen, flagged,
             value, grad, nearest, normal, piece, inside)
    if (chosen < 0).any():  # pragma: no cover - every point keeps at least one piece
        raise RuntimeError("cP: a hand point lost all its candidate pieces; please report this bug")
    return ContactDistance(value=value, grad=grad, nearest=nearest, normal=normal, piece=piece, inside=inside,
                           degenerate=flagged, candidates=cand.sum(axis=1), lp_solves=lp_solves)
