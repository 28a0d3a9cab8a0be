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
as one block-diagonal LP (`synergrasp.lp.blocks.BlockLP`).

Known limitation: inside the object, the value is the penetration into the
single piece in which the point is deepest, not into the union; a point just
behind an internal cut between two pieces reads as shallow.
"""

from __future__ import annotations

from dataclasses import dataclass, fields

import numpy as np

from .. import lp
from .._checks import as_points
from .._vectors import unit_rows
from ..lp.blocks import BlockLP
from ..tolerances import VALUE_TOL
from .broad_phase import SIMPLEX, Probe
from .facets import pick_rows, ray_exits, separation_blocks


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


def check_points(points) -> np.ndarray:
    """Hand points as a validated (n, 3) float array (a clear ValueError or TypeError otherwise)."""
    try:
        return as_points(points, "points", dim=3)
    except ValueError as exc:
        raise ValueError(f"{exc}; hand points must be an (n, 3) array in mm") from None


def contact_distance(obj, points, backend="highs", *, ids=None) -> ContactDistance:
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
    P = check_points(points)
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
    return obj.index.probe(check_points(points)).bounds()


def group_contact_distance(obj, points, groups, backend="highs", *, ids=None) -> tuple[ContactDistance, np.ndarray]:
    """The smallest cP in each group of points, and the point attaining it.

    A point whose lower bound of cP exceeds the upper bound of another point
    of its group cannot attain the group's minimum and gets no LP (valid
    bounds, so the minima are unchanged). The support bound of every point
    comes first (no facet plane evaluated), then the facet-plane bounds
    (`cp_bounds`) of the points it leaves, which are reused by the LPs.

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

    Returns
    -------
    ContactDistance
        One row per group: that of its point with the smallest cP (the first
        of them on a tie).
    best : (G,) int
        That point's row in ``points``.

    Examples
    --------
    Points 20 and 10 mm above the pole of the paper's ellipsoid (group 0),
    and one 2 mm above it (group 1):

    >>> from synergrasp import objects
    >>> points = [[0.0, 0.0, 70.0], [0.0, 0.0, 60.0], [0.0, 0.0, 52.0]]
    >>> r, best = group_contact_distance(objects.ellipsoid(), points, [0, 0, 1])
    >>> r.value.round(2).tolist(), best.tolist()
    ([10.0, 2.0], [1, 2])
    """
    P = check_points(points)
    solver = lp.get_backend(backend)
    groups = np.asarray(groups)
    ids = np.arange(len(P)) if ids is None else np.asarray(ids, dtype=np.int64)
    index = obj.index
    n_groups = groups.max() + 1
    cheap = index.probe(P, planes=False)
    upper = cheap.upper
    keep = _group_candidates(groups, cheap.lower.min(axis=1), upper, n_groups)
    probe = index.probe(P[keep])
    lower2, upper2 = probe.bounds()
    smallest = np.full(n_groups, np.inf)
    np.minimum.at(smallest, groups, upper)
    np.minimum.at(smallest, groups[keep], upper2)
    rows = _group_candidates(groups[keep], lower2, upper2, n_groups, smallest)
    keep = keep[rows]
    cp = _solve(obj, probe.take(rows), solver, ids[keep])
    order = np.lexsort((cp.value, groups[keep]))
    first = np.r_[True, groups[keep][order][1:] != groups[keep][order][:-1]]
    picked = order[first]
    taken = {f.name: getattr(cp, f.name)[picked] for f in fields(cp) if f.name != "lp_solves"}
    return ContactDistance(**taken, lp_solves=cp.lp_solves), keep[picked]


def _group_candidates(groups, lower, upper, n_groups, smallest=None):
    """Rows whose lower bound does not exceed the smallest upper bound of their group (within round-off).

    The row with a group's smallest upper bound is kept whatever the round-off.
    """
    if smallest is None:
        smallest = np.full(n_groups, np.inf)
        np.minimum.at(smallest, groups, upper)
    s = smallest[groups]
    return np.flatnonzero((lower <= s * (1 + VALUE_TOL) + VALUE_TOL) | (upper == s))


def _solve(obj, probe: Probe, solver, ids=None) -> ContactDistance:
    """`contact_distance` of the points of a `Probe`, with a `synergrasp.lp` backend.

    ``ids`` (n,) int, optional: an identity of each point across calls; with
    it and a backend with ``basis_hints``, the LP blocks start from their
    last optimal bases (`synergrasp.lp.blocks.BasisMemory` of the object's index).
    """
    index = obj.index
    P, PQ, S = probe.P, probe.PQ, probe.S
    n, n_pieces = len(P), index.n_pieces
    cand, bound = index.candidates(probe)
    memory = index.memory if ids is not None and solver.basis_hints else None
    blocks = BlockLP(memory)
    batches = []  # (batch index, points, pieces, separation?)
    done = []  # penetration rays in closed form: (points, piece, value, y, witness)

    # separation (Eq. 1): min sum rho  s.t.  Q^T rho - V^T beta = -p,  sum beta = 1
    pieces, rows = np.divmod(np.flatnonzero((cand & (S > 0.0)).T), n)  # pairs by piece, then point
    if len(rows):
        used, counts, vid = separation_blocks(index, P, PQ, bound, rows, pieces)
        rows, pieces = rows[used], pieces[used]
        keys = None if memory is None else (ids[rows] * n_pieces + pieces) * 5
        lead = np.broadcast_to(SIMPLEX, (len(rows), 4, 3))
        batch = blocks.add(lead, np.ones(4), index.vertices[vid], counts, -1.0, -P[rows], P[rows], keys, vid)
        batches.append((batch, rows, pieces, True))
    # penetration (Eq. 3) for each k: min -rho  s.t.  rho q_k + V^T beta = p,  sum beta = 1
    pieces, rows = np.divmod(np.flatnonzero((cand & (S <= 0.0)).T), n)
    if len(rows):  # the optimum is where the ray p - rho q_k leaves the piece: one ray per pair and k, by piece, k, point
        m = len(rows)
        order = np.lexsort((np.tile(rows, 4), np.repeat(np.arange(4), m), np.tile(pieces, 4)))
        rows, pieces, k = np.tile(rows, 4)[order], np.tile(pieces, 4)[order], np.repeat(np.arange(4), m)[order]
        closed, t, y, counts, vid = ray_exits(index, P[rows], -SIMPLEX[k], pieces)
        if closed.any():
            r, tc = rows[closed], t[closed]
            done.append((r, pieces[closed], -tc, -y[closed], P[r] - tc[:, None] * SIMPLEX[k[closed]]))
        if not closed.all():
            r, kr, pr = rows[~closed], k[~closed], pieces[~closed]
            keys = None if memory is None else (ids[r] * n_pieces + pr) * 5 + 1 + kr
            batch = blocks.add(SIMPLEX[kr, None], [-1.0], index.vertices[vid], counts, 1.0, P[r], P[r], keys, vid)
            batches.append((batch, r, pr, False))
    solved = blocks.solve(solver, "cP") if blocks.batches else []

    # one row per (point, piece[, k]) LP, then penetration = max over k, cP = min over pieces
    pts, pcs, vals, grads, wits, nrms, degs, sep = [], [], [], [], [], [], [], []
    for b, rows, j, separation in batches:
        lead_x, witness, y, deg = solved[b]
        pts.append(rows)
        pcs.append(j)
        vals.append(lead_x.sum(axis=1) if separation else -lead_x[:, 0])
        grads.append(-y if separation else y)
        nrms.append(y if separation else -y)
        wits.append(witness)
        degs.append(deg)
        sep.append(np.full(len(rows), separation))
    for rows, j, value, y, witness in done:
        pts.append(rows)
        pcs.append(j)
        vals.append(value)
        grads.append(y)
        nrms.append(-y)
        wits.append(witness)
        degs.append(np.zeros(len(rows), dtype=bool))
        sep.append(np.zeros(len(rows), dtype=bool))
    pts, pcs, vals = np.concatenate(pts), np.concatenate(pcs).astype(np.int64), np.concatenate(vals)
    grads = np.ascontiguousarray(np.concatenate(grads))
    chosen, degenerate = pick_rows(pts, pcs, vals, grads, np.concatenate(degs), n, n_pieces)
    if (chosen < 0).any():  # pragma: no cover - every point keeps at least one piece
        raise RuntimeError("cP: a hand point lost all its candidate pieces; please report this bug")
    return ContactDistance(
        value=vals[chosen],
        grad=grads[chosen],
        nearest=np.concatenate(wits)[chosen],
        normal=unit_rows(np.concatenate(nrms)[chosen]),
        piece=pcs[chosen],
        inside=~np.concatenate(sep)[chosen],
        degenerate=degenerate,
        candidates=cand.sum(axis=1),
        lp_solves=blocks.lp_solves,
    )
