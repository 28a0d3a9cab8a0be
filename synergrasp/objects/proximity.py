"""Hand points against an object: cP (contact pseudo-distance), sQ contacts, capsule penetration.

The object is a union of convex pieces (`ConvexPiece`).
Everything here is vectorised over the hand points and solves all the LPs of
one call as ONE block-diagonal LP: the blocks are independent, so each block's
optimum and duals are exactly those of the LP on its own, and the per-call
overhead of the solver is paid once. Only ``backend.solve`` is used, so any
backend of `synergrasp.lp` works.

cP of a point p (paper Sec. 3.2; the documentation's "Contact distance (cP)" page)
    The pseudo-distance between A = {p} and each piece B (the simplex Q is
    the default regular simplex of `synergrasp.regular_simplex`), the
    minimum over pieces: > 0 outside the object, < 0 inside a piece (the most
    negative piece wins). With the single point as A its weight is 1, so the
    separation LP (Eq. 1) is ``min sum rho s.t. Q^T rho - V^T beta = -p,
    sum beta = 1`` and each penetration LP (Eq. 3) is ``min -rho s.t.
    rho q_k + V^T beta = p, sum beta = 1``: 4 rows each, the witness only on B.
    Gradient: ``d value / d p = -y`` (separation) or ``+y`` (penetration, the
    active k), y the duals of the 3 coordinate rows.

Candidate pieces (the broad phase)
    For the regular simplex ``|x| <= gauge_Q(x) <= 3 |x|``, so if e_j is the
    Euclidean distance from p to piece j, the piece's value lies in
    ``[e_j, 3 e_j]``: a piece with ``e_j > 3 min_i e_i`` cannot be the
    minimiser and is skipped (python-fcl's GJK gives e_j).
    Cheaper bounds come first and settle most points without fcl: the facet
    planes (an exact inside test, and a lower bound: the gauge ball
    ``p + t Q`` reaches the half-space behind plane f only for
    ``t >= (n_f . p + o_f) / -min_k n_f . q_k``), the nearest vertex (an
    upper bound), and the gauge itself: the value of piece j is at least
    ``3 max_k (q_k . p - h_j(q_k))`` (h_j the support function) and at most
    the gauge distance to any of its vertices. A point inside some piece
    only needs the pieces containing it (the others have values >= 0).

Vertices passed to each LP (the narrow phase)
    Only the vertices of the facets that can carry the optimum: for
    separation, facets facing p that the gauge ball ``p + v Q`` (v bounded
    above as above) can reach; for penetration and for the sQ rays, the
    facets the ray leaves through (closed form from the planes). The optimal
    face lies on one of them, so the value is unchanged and, when the LP is
    not degenerate, so are the duals (they are fixed by the optimal basis).
    The LPs are then tiny (4 rows, typically 4-30 columns per block). An sQ
    ray that leaves a single piece through the inside of a single facet needs
    no LP at all: its optimum (the exit point) and duals (the facet's plane)
    are in closed form, and only rays at ties (edges, vertices, coplanar
    facets, several pieces) are solved.

Every pruning uses valid bounds only; a property test checks the values
against brute force over all pieces and all vertices.

Known limitation: inside the object, the value is the penetration into the
single piece in which the point is deepest, not into the union; a point just
behind an internal cut between two pieces reads as shallow.
"""

from __future__ import annotations

from dataclasses import dataclass, fields

import fcl
import numpy as np

from .. import lp
from .._checks import as_points, positive_scalar
from .._vectors import cross, unit_rows
from ..pseudo_distance import regular_simplex

_Q = regular_simplex(3)
#: Lipschitz ratio of the regular-simplex gauge to the Euclidean norm in 3-D.
GAUGE_RATIO = 3.0
_ROWS = 4  # 3 coordinate rows + 1 convexity row per block
#: Tolerance on primal weights and reduced costs in the degeneracy test.
DEGENERACY_TOL = 1e-7
#: Largest LP (columns) per solver call, by backend name; the blocks are split into several
#: LPs above it. cvxpy canonicalises its parametrised dense matrix in time and memory that
#: grow much faster than the LP (0.6 s for 60 x 1373, gigabytes for 244 x 10000).
MAX_LP_COLUMNS = {"cvxpy": 400}
#: About how many LP blocks' last optimal bases an object keeps (`_BasisMemory` starts afresh above it).
MEMORY_SIZE = 20000


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
        Solver calls made: 1 (all blocks stacked), more only for backends with an LP size limit (``MAX_LP_COLUMNS``).
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
        stacked), more only for backends with an LP size limit (``MAX_LP_COLUMNS``).

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


@dataclass(frozen=True)
class Penetration:
    """Result of `GraspObject.penetration` (capsules against the object).

    Attributes
    ----------
    depth : float
        Deepest penetration depth over all capsules (mm), 0 if none collides.
    index : int
        Index of the deepest capsule, -1 if none collides.
    depths : (k,) float
        Penetration depth of each capsule (0 when clear).
    distances : (k,) float
        Signed distance of each capsule to the object (negative = penetration).
    piece : int
        Piece the deepest capsule penetrates most, -1 if none.
    witnesses : (k, 2, 3) float
        For each penetrating capsule, fcl's witness points in the piece it
        penetrates most: the capsule's point deepest in the object, then the
        object's point deepest in the capsule (the translation from the first
        to the second frees the capsule, its length is the depth); NaN for the
        capsules that do not penetrate.

    Notes
    -----
    The depth is fcl's signed distance (GJK/EPA), the translation that frees
    the capsule from one convex piece; for a capsule through several pieces it
    is the largest such depth, a lower bound of the depth into the union.
    """

    depth: float
    index: int
    depths: np.ndarray
    distances: np.ndarray
    piece: int
    witnesses: np.ndarray

    @property
    def collision(self) -> bool:
        """True when some capsule penetrates the object."""
        return self.index >= 0


# --------------------------------------------------------------------------- LP assembly


class _Blocks:
    """Independent 4-row LP blocks, solved together as one block-diagonal LP.

    Blocks come in batches. Every block of a batch has the same ``L`` lead
    columns (entries in the 3 coordinate rows only, costs ``cost``), followed
    by one column per vertex v of the block's own vertex list (entries
    ``sign * v`` in the coordinate rows, 1 in the convexity row, cost 0); the
    right-hand side is ``[h, 1]``: ``lead x_L + sign V^T x_V = h``,
    ``sum x_V = 1``.

    Each block is written relative to an origin o (the hand point, or the
    object's centre): subtracting ``sign * o`` times the convexity row from
    the coordinate rows gives entries ``sign * (v - o)`` and right-hand side
    ``h - sign * o``. That is a row operation: the primal solution and the
    duals of the coordinate rows are unchanged, and the LP data become
    distances rather than coordinates (better conditioned).

    After the solve, each block is polished onto its optimal basis: the 4
    columns with the largest values form a basis B; if ``B x = b`` and
    ``B^T y = c_B`` give a primal and dual feasible pair (reduced costs >= 0),
    that exact vertex solution replaces the solver's. Interior-point backends
    then agree with the simplex to round-off, and the derivatives are the
    exact ones of the basis.

    With a `_BasisMemory` (``memory``), every block carries a key (``add``'s
    ``keys``, its vertices their indices ``ids``): the LP starts from the
    columns that were basic at the last optimum of a block with the same key
    (for a backend with ``basis_hints``), and the memory is then updated.
    """

    def __init__(self, memory=None):
        self.batches = []
        self.lp_solves = 0
        self.memory = memory
        self.keys, self.ids = [], []

    def add(self, lead, cost, vertices, counts, sign, rhs, origin, keys=None, ids=None) -> int:
        """Add a batch of B blocks; returns the batch index.

        Parameters
        ----------
        lead : (B, L, 3) float
            Coordinate entries of the lead columns of each block.
        cost : (L,) float
            Costs of the lead columns.
        vertices : (sum(counts), 3) float
            The blocks' vertex lists, concatenated in block order.
        counts : (B,) int
            Vertices per block (each >= 3).
        sign : float
            +1 or -1, the sign of the vertex entries.
        rhs : (B, 3) float
            Right-hand sides h of the coordinate rows.
        origin : (B, 3) float
            Origin o of each block.
        keys : (B,) int, optional
            Block keys for the memory (needed when there is one).
        ids : (sum(counts),) int, optional
            Index of each vertex in its piece (needed when there is a memory).
        """
        counts = np.asarray(counts)
        origin = np.broadcast_to(origin, (len(counts), 3))
        relative = sign * (vertices - np.repeat(origin, counts, axis=0))
        shifted = np.asarray(rhs) - sign * origin
        lead, cost = np.asarray(lead, dtype=float), np.asarray(cost, dtype=float)
        self.batches.append((lead, cost, vertices, counts, relative, shifted))
        self.keys.append(keys)
        self.ids.append(ids)
        return len(self.batches) - 1

    def solve(self, solver, what: str):
        """Solve all blocks as one LP.

        Returns
        -------
        list of (lead_x, witness, y, degenerate) per batch
            ``lead_x`` (B, L) the lead variables, ``witness`` (B, 3) the
            point ``sum_v x_v v``, ``y`` (B, 3) the duals of the coordinate
            rows, ``degenerate`` (B,) bool.
        """
        batches = self.batches
        n_lead = np.concatenate([np.full(len(b[3]), b[0].shape[1]) for b in batches])
        n_vert = np.concatenate([b[3] for b in batches])
        width = n_lead + n_vert
        start = np.concatenate([[0], np.cumsum(width)])
        n_blocks, n_cols = len(width), int(start[-1])
        block_of = np.repeat(np.arange(n_blocks), width)
        is_lead = np.arange(n_cols) - start[block_of] < n_lead[block_of]
        entries = np.zeros((n_cols, _ROWS))
        entries[is_lead, :3] = np.concatenate([b[0].reshape(-1, 3) for b in batches])
        entries[~is_lead, :3] = np.concatenate([b[4] for b in batches])
        entries[~is_lead, 3] = 1.0
        c = np.zeros(n_cols)
        c[is_lead] = np.concatenate([np.tile(b[1], len(b[3])) for b in batches])
        rhs = np.ones((n_blocks, _ROWS))
        rhs[:, :3] = np.concatenate([b[5] for b in batches])
        hint = None
        if self.memory is not None:
            colid = np.empty(n_cols, dtype=np.int64)  # lead columns -1, -2, ...; vertex columns their index
            colid[is_lead] = start[block_of[is_lead]] - np.flatnonzero(is_lead) - 1
            colid[~is_lead] = np.concatenate(self.ids)
            keys = np.concatenate(self.keys)[block_of]
            hint = self.memory.basic(keys, colid)
        # one LP for all blocks (or a few, for backends that scale badly with the LP size)
        limit = MAX_LP_COLUMNS.get(getattr(solver, "name", ""), n_cols)
        x, y = np.empty(n_cols), np.empty((n_blocks, _ROWS))
        first = 0
        self.lp_solves = 0
        while first < n_blocks:
            last = first + max(1, int(np.searchsorted(start[first + 1 :], start[first] + limit, side="right")))
            cols = slice(start[first], start[last])
            sub = entries[cols]
            rows = _ROWS * (block_of[cols, None] - first) + np.arange(_ROWS)
            nonzero = sub != 0.0
            indptr = np.zeros(sub.shape[0] + 1, dtype=np.int32)
            np.cumsum(nonzero.sum(axis=1), out=indptr[1:])
            A = lp.CSC(indptr, rows[nonzero].astype(np.int32), sub[nonzero], (_ROWS * (last - first), sub.shape[0]))
            if hint is None:
                sol = solver.solve(c[cols], A, rhs[first:last].ravel())
            else:  # a backend with basis_hints
                sol = solver.solve(c[cols], A, rhs[first:last].ravel(), basic=hint[cols])
            self.lp_solves += 1
            if not sol.optimal:
                raise lp.LPError(
                    f"the {what} LP was not solved: backend {sol.backend!r} returned status "
                    f"{sol.status!r} ({sol.message}). Try another backend (sg.lp.available_backends())."
                )
            x[cols], y[first:last] = sol.x, sol.y.reshape(-1, _ROWS)
            first = last
        if not getattr(solver, "vertex_solutions", False):  # a simplex's solution is already basic and exact
            x, y = _polish(entries, c, rhs, x, y, start, block_of)
        if self.memory is not None:
            self.memory.remember(keys, colid, x > 0.0)
        # The derivatives with respect to the hand point need only the duals y. They are unique
        # when the optimum has 4 positive variables in the block (a non-degenerate basis: B^T y = c_B);
        # several primal optima (a face of B parallel to one of Q's) leave y unique and are not flagged.
        xmax = np.maximum.reduceat(np.abs(x), start[:-1])
        positive = np.add.reduceat(x > DEGENERACY_TOL * np.maximum(1.0, xmax)[block_of], start[:-1])
        degenerate = positive < _ROWS
        vstart = np.concatenate([[0], np.cumsum(n_vert)[:-1]])
        witness = np.add.reduceat(x[~is_lead, None] * np.concatenate([b[2] for b in batches]), vstart, axis=0)
        lead_x = x[is_lead]
        out, first, lead_first = [], 0, 0
        for lead, _, _, counts, _, _ in batches:
            B, L = len(counts), lead.shape[1]
            part = slice(first, first + B)
            leads = lead_x[lead_first : lead_first + B * L].reshape(B, L)
            out.append((leads, witness[part], y[part, :3], degenerate[part]))
            first, lead_first = first + B, lead_first + B * L
        return out


class _BasisMemory:
    """The basic columns of LP blocks at their last optimum, by block key (warm starts of the cP LP).

    Each (block key, column id) pair that was basic is kept as one integer
    ``key * SPAN + column id + 8`` (lead columns have ids -1, -2, ...,
    vertex columns their vertex index) in a sorted array, so that looking up
    and updating the blocks of a whole LP is a few vectorised set operations.
    """

    SPAN = 1 << 24  # column ids + 8 stay below it (vertex indices of a piece < 16.7 million)

    def __init__(self):
        self.codes = np.empty(0, dtype=np.int64)

    def basic(self, keys, colid):
        """(n,) bool: the columns (block key ``keys`` (n,), id ``colid`` (n,)) basic at their block's last optimum."""
        return _members(keys * self.SPAN + colid + 8, self.codes)

    def remember(self, keys, colid, basic):
        """Replace what is kept of the blocks in ``keys`` (n,) by their columns ``basic`` (n,) bool."""
        old = self.codes if len(self.codes) <= 4 * MEMORY_SIZE else self.codes[:0]
        stale = _members(old // self.SPAN, np.unique(keys))
        self.codes = np.sort(np.concatenate([old[~stale], keys[basic] * self.SPAN + colid[basic] + 8]))


def _members(values, sorted_set):
    """(n,) bool: which of ``values`` (n,) int are in ``sorted_set`` (sorted int array)."""
    if not len(sorted_set):
        return np.zeros(len(values), dtype=bool)
    at = np.minimum(np.searchsorted(sorted_set, values), len(sorted_set) - 1)
    return sorted_set[at] == values


def _polish(entries, c, rhs, x, y, start, block_of):
    """Replace each block's solution by the exact one of its optimal basis, where that is feasible.

    Parameters
    ----------
    entries : (n, 4) float
        Column entries in their block's 4 rows.
    c : (n,) float
    rhs : (B, 4) float
    x : (n,) float
        Solver's primal solution (updated in place).
    y : (B, 4) float
        Solver's duals per block (updated in place).
    start : (B+1,) int
        First column of each block.
    block_of : (n,) int
    """
    n_blocks = len(rhs)
    order = np.lexsort((-x, block_of))  # per block, columns by decreasing value
    rank = np.arange(len(x)) - start[block_of[order]]
    basis = order[rank < _ROWS].reshape(n_blocks, _ROWS)
    M = entries[basis]  # (B, 4 columns, 4 rows): M[b].T is the basis matrix
    det = np.linalg.det(M)
    scale = np.abs(M).max(axis=(1, 2)) ** _ROWS
    ok = np.abs(det) > 1e-12 * np.maximum(scale, 1e-300)
    M_safe = np.where(ok[:, None, None], M, np.eye(_ROWS))
    xb = np.linalg.solve(np.swapaxes(M_safe, 1, 2), rhs[..., None])[..., 0]
    yb = np.linalg.solve(M_safe, c[basis][..., None])[..., 0]
    xscale = np.maximum(1.0, np.abs(xb).max(axis=1))
    ok &= xb.min(axis=1) >= -1e-12 * xscale
    reduced = c - np.einsum("nr,nr->n", entries, yb[block_of])
    yscale = np.maximum(1.0, np.abs(yb).max(axis=1))
    ok &= np.minimum.reduceat(reduced, start[:-1]) >= -1e-9 * yscale
    if ok.any():
        cols = np.nonzero(ok[block_of])[0]
        x[cols] = 0.0
        x[basis[ok]] = np.maximum(xb[ok], 0.0)
        y[ok] = yb[ok]
    return x, y


def _check_points(points):
    try:
        return as_points(points, "points", dim=3)
    except ValueError as exc:
        raise ValueError(f"{exc}; hand points must be an (n, 3) array in mm") from None


def _largest_gap(pq: np.ndarray, wq: np.ndarray) -> np.ndarray:
    """``max_k pq[:, k] - wq[k]``: gauge distances (over 3) between points and vertices.

    Parameters
    ----------
    pq : (n, 4) float
        ``q_k . p`` of n points.
    wq : (4, C) or (4, n, m) float
        ``q_k . v`` of C vertices (the same for every point), or of m
        vertices per point.

    Returns
    -------
    (n, C) or (n, m) float
    """
    gap = pq[:, 0, None] - wq[0]
    for k in range(1, 4):
        np.maximum(gap, pq[:, k, None] - wq[k], out=gap)
    return gap


def _nonzero(mask):
    """``np.nonzero`` of a 2-D mask (row and column of each True entry, row by row), in a third of its time."""
    return np.divmod(np.flatnonzero(mask), mask.shape[1])


def _followed(first):
    """Whether each sorted row is followed by another of its group (``first`` marks group starts)."""
    out = np.empty(len(first), dtype=bool)
    np.logical_not(first[1:], out=out[:-1])
    out[-1:] = False
    return out


def _first_per_group(group, key):
    """Index of the smallest ``key`` within each group (and the order used)."""
    order = np.lexsort((key, group))
    sorted_group = group[order]
    first = np.empty(len(order), dtype=bool)
    first[:1] = True
    np.not_equal(sorted_group[1:], sorted_group[:-1], out=first[1:])
    return order, first


# --------------------------------------------------------------------------- cP


@dataclass(frozen=True)
class _Probe:
    """What the broad phase knows of hand points before any LP (computed once per point).

    Only the pieces whose gauge support bound (see `_candidates`) is within
    the tolerance of `_candidates` of ``upper`` can be a point's cP
    minimiser or contain it (the bound is then <= 0); the facet planes of
    the other pieces are not evaluated for that point.

    Attributes
    ----------
    P : (n, 3) float
        The points.
    PQ : (n, 4) float
        ``q_k . p``.
    values : (n, F) float
        ``n_f . p + o_f`` for every facet plane of the pieces evaluated, 0
        for the others.
    S : (n, J) float
        Their maximum over each piece evaluated: <= 0 inside piece j, else a
        lower bound of the distance; inf for the pieces not evaluated.
    lower : (n, J) float
        Lower bound of piece j's value for a point outside it (see
        `_candidates`); inf for the pieces not evaluated.
    upper : (n,) float
        Gauge distance to the nearest vertex, an upper bound of cP.
    """

    P: np.ndarray
    PQ: np.ndarray
    values: np.ndarray
    S: np.ndarray
    lower: np.ndarray
    upper: np.ndarray

    @classmethod
    def of(cls, obj, P) -> "_Probe":
        """The probe of points ``P`` (n, 3) against ``obj``."""
        PQ = P @ _Q.T
        upper = obj._vertex_gauge(PQ)
        support = GAUGE_RATIO * _largest_gap(PQ, obj._support.T)  # (n, J) gauge support bound
        near = None  # a single piece is every point's candidate
        if len(obj.convex) > 1:
            near = np.maximum(support, 0.0) <= _loosened(upper)[:, None]
        S, values, gauge = obj._plane_values(P, near)
        return cls(P, PQ, values, S, np.maximum(np.maximum(gauge, 0.0), support), upper)

    def take(self, rows) -> "_Probe":
        """The probe of the points ``rows`` only."""
        return _Probe(*(getattr(self, f.name)[rows] for f in fields(self)))


def _loosened(upper):
    """An upper bound of cP plus the round-off tolerance of the pruning (the broad phase's one tolerance)."""
    return upper + 1e-9 * (1.0 + np.abs(upper))


def _candidates(obj, probe):
    """(n, J) bool: the pieces that can be each point's cP minimiser.

    Inside some piece: the pieces containing the point (the others have
    values >= 0). Outside, piece j is dropped when a lower bound of its value
    exceeds an upper bound of another piece's value. The bounds:

    * the gauge's Lipschitz bounds, ``e_j <= value_j <= 3 e_j`` with e_j the
      Euclidean distance (python-fcl's exact, GJK, distance);
    * the simplex gauge itself, ``gauge(x) = 3 max_k (-q_k . x)``: the value
      is at least ``3 max_k (q_k . p - h_j(q_k))`` (h_j the support function
      of the piece) and at least ``(n_f . p + o_f) / -min_k n_f . q_k`` for
      every facet plane f (the gauge ball ``p + t Q`` reaches the half-space
      behind the plane only from that t on; at least the plane's Euclidean
      distance), and at most the gauge distance to any vertex (never more
      than 3 times the distance to the nearest vertex, so that Euclidean
      bound would add nothing).

    Every bound is valid, so the pruning never changes a value; fcl is only
    called for the points the cheap bounds leave with several candidates.

    Returns
    -------
    cand : (n, J) bool
    bound : (n,) float
        Upper bound of each point's cP (``probe.upper``, tightened by fcl).
    """
    S, lower = probe.S, probe.lower
    bound = probe.upper.copy()
    if S.shape[1] == 1:  # a single piece is every point's candidate: only the bound is needed
        return np.ones(S.shape, dtype=bool), bound
    inside = S <= 0.0
    cand = lower <= _loosened(bound)[:, None]
    out = inside.any(axis=1)
    cand[out] = inside[out]
    todo = np.nonzero(~out & (cand.sum(axis=1) > 1))[0]
    if len(todo):
        query, request = fcl.CollisionObject(fcl.Sphere(0.0), fcl.Transform()), fcl.DistanceRequest()
    for i in todo:
        js = np.nonzero(cand[i])[0]
        query.setTranslation(probe.P[i])
        exact = np.array([fcl.distance(query, obj.convex[j].fcl, request, fcl.DistanceResult()) for j in js])
        np.maximum(exact, 0.0, out=exact)  # fcl reports -1 for a point it finds on or in a piece
        low = np.maximum(exact, lower[i, js])
        high = min(GAUGE_RATIO * exact.min(), bound[i]) * (1 + 1e-6) + 1e-6
        cand[i, js] = low <= high
        bound[i] = min(bound[i], high)
    return cand, bound


def cp_bounds(obj, points):
    """Cheap lower and upper bounds of the cP of points, without an LP.

    The bounds of the broad phase (see `_candidates`), taken over all pieces:
    outside the object ``max(plane gauge bound, gauge support bound) <= cP
    <= gauge to the nearest vertex``; inside a piece ``-inf < cP <= 0``.
    Where a bound is attained (e.g. straight above a vertex) it can differ
    from the LP's value by round-off (about 1e-14 relative).

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
    return _bounds(_Probe.of(obj, _check_points(points)))


def _bounds(probe):
    """`cp_bounds` of the points of a `_Probe`."""
    inside = (probe.S <= 0.0).any(axis=1)
    return np.where(inside, -np.inf, probe.lower.min(axis=1)), np.where(inside, 0.0, probe.upper)


def _exit_facets(D, a, ray, tol=1e-9):
    """Facets through which rays leave a piece.

    Parameters
    ----------
    D : (e,) float
        ``n_f . x0 + o_f`` at each ray's origin (<= 0: origins inside), for
        the facets listed.
    a : (e,) float
        ``n_f . d``, d the ray's direction.
    ray : (e,) int
        The ray of each entry, sorted, every ray ``0 ... R-1`` with at least one entry.

    Returns
    -------
    (e,) bool
        The facets whose plane the ray ``x0 + r d`` (r >= 0) crosses last
        (within ``tol``): the exit point lies on one of them.
    """
    with np.errstate(divide="ignore", invalid="ignore"):
        r = np.where(a > 0, -D / a, np.inf)
    r_exit = np.minimum.reduceat(r, np.flatnonzero(np.r_[True, ray[1:] != ray[:-1]]))[ray]
    return r <= r_exit * (1 + tol) + tol


def _separation_facets(obj, D, PQ, bound, outside):
    """Facets that can carry the separation optimum of each point, on the pieces it is outside of.

    The optimum b* lies on a facet facing p (``n . p + o > 0``), and inside the
    gauge ball ``p + v Q`` with v <= ``bound``. A facet is dropped when that
    ball cannot reach it: it lies beyond the facet's plane, or a facet plane
    of the ball (normal ``-q_k``, offset ``bound / 3``) separates them.
    Should round-off leave a point with no facet at all, every facet facing
    it is kept.

    Parameters
    ----------
    obj : GraspObject
    D : (n, F) float
        ``n_f . p + o_f`` of the facet planes (at least of the pieces in ``outside``).
    PQ : (n, 4) float
        ``q_k . p``.
    bound : (n,) float
        Upper bound of each point's cP.
    outside : (n, J) bool
        The candidate pieces each point is outside of.

    Returns
    -------
    rows, pieces : (P,) int
        The (point, piece) pairs, by piece, then point.
    pair, facets : (m,) int
        The kept facets: the pair of each and its index in the plane arrays,
        sorted by pair, then facet.
    """
    pieces, rows = _nonzero(outside.T)  # pairs by piece, then point
    pair, facets = _pair_facets(obj, pieces)
    at = rows[pair]
    values, b = np.take(D, at * D.shape[1] + facets), bound[at]
    tol = 1e-9 * (1.0 + b)
    keep = (values > 0.0) & (values + b * obj._facet_nq[facets] <= tol)  # facing p, within reach
    # the ball's facet k separates a triangle when all its vertices lie beyond it (tested on the few kept)
    kept = np.flatnonzero(keep)
    f, r = facets[kept], at[kept]
    reach = b[kept] / 3.0 + tol[kept]
    apart = obj._facet_mq[0][f] + PQ[r, 0] > reach
    for k in range(1, 4):
        apart |= obj._facet_mq[k][f] + PQ[r, k] > reach
    keep[kept[apart]] = False
    lost = np.bincount(at[keep], minlength=len(D)) == 0
    if lost[rows].any():  # a piece the ball cannot reach is not the minimiser: round-off
        keep |= lost[at] & (values > 0.0)
    return rows, pieces, pair[keep], facets[keep]


def _pair_facets(obj, pieces):
    """Every facet of each of a list of pieces, concatenated.

    Parameters
    ----------
    obj : GraspObject
    pieces : (P,) int

    Returns
    -------
    pair, facets : (m,) int
        For each entry, its position in ``pieces`` and the facet's index in
        the plane arrays (``obj._planes``), sorted by position, then facet.
    """
    counts = obj._plane_counts[pieces]
    pair = np.repeat(np.arange(len(pieces)), counts)
    facets = np.arange(counts.sum()) - np.repeat(np.cumsum(counts) - counts - obj._plane_starts[pieces], counts)
    return pair, facets


def _block_vertices(obj, block, facets, n_blocks):
    """The vertex lists of LP blocks: the vertices of the facets listed for each.

    Parameters
    ----------
    obj : GraspObject
    block, facets : (m,) int
        Block and facet (index in the plane arrays) of each entry, blocks
        ``0 ... n_blocks-1`` each with at least one facet.
    n_blocks : int

    Returns
    -------
    vertices : (sum(counts), 3) float
        Each block's vertices, in index order, blocks concatenated.
    counts : (n_blocks,) int
    ids : (sum(counts),) int
        The vertices' rows in ``obj._vertices``.
    """
    n_vertices = len(obj._vertices)
    codes = np.unique((block[:, None] * n_vertices + obj._facet_vertex_rows[facets]).ravel())
    ids = codes % n_vertices
    return obj._vertices[ids], np.bincount(codes // n_vertices, minlength=n_blocks), ids


def contact_distance(obj, points, backend="highs") -> ContactDistance:
    """cP of hand points against an object; see `GraspObject.contact_distance`."""
    P = _check_points(points)
    solver = lp.get_backend(backend)
    return _contact_distance(obj, _Probe.of(obj, P), solver)


def group_contact_distance(obj, points, groups, backend="highs") -> tuple[ContactDistance, np.ndarray]:
    """The smallest cP in each group of points, and the point attaining it.

    A point whose lower bound of cP (`cp_bounds`) exceeds the upper bound of
    another point of its group cannot attain the group's minimum and gets no
    LP (valid bounds, so the minima are unchanged); the bounds of the others
    are reused by one call of `contact_distance`.

    Parameters
    ----------
    obj : GraspObject
    points : (n, 3) float
    groups : (n,) int
        Group of each point, ``0 ... G-1``, each with at least one point.
    backend : str or synergrasp.lp.Backend

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
    P = _check_points(points)
    solver = lp.get_backend(backend)
    groups = np.asarray(groups)
    probe = _Probe.of(obj, P)
    lower, upper = _bounds(probe)
    smallest = np.full(groups.max() + 1, np.inf)
    np.minimum.at(smallest, groups, upper)
    # the point with a group's smallest upper bound is kept whatever the round-off
    index = np.flatnonzero((lower <= smallest[groups] * (1 + 1e-9) + 1e-9) | (upper == smallest[groups]))
    cp = _contact_distance(obj, probe.take(index), solver, index)
    order, first = _first_per_group(groups[index], cp.value)
    rows = order[first]
    picked = {f.name: getattr(cp, f.name)[rows] for f in fields(cp) if f.name != "lp_solves"}
    return ContactDistance(**picked, lp_solves=cp.lp_solves), index[rows]


def _contact_distance(obj, probe, solver, ids=None) -> ContactDistance:
    """`contact_distance` of the points of a `_Probe`, with a `synergrasp.lp` backend.

    ``ids`` (n,) int, optional: an identity of each point across calls (its row
    in the caller's point set); with it, each LP block starts from the basis
    its (point, piece, k) had at its last optimum on this object (a warm start
    for simplex backends: the values are those of the LP, only the solver's
    path to them changes).
    """
    P, PQ, S, values = probe.P, probe.PQ, probe.S, probe.values
    n, n_pieces = len(P), len(obj.convex)
    cand, bound = _candidates(obj, probe)

    # separation (Eq. 1): min sum rho  s.t.  Q^T rho - V^T beta = -p,  sum beta = 1
    outside = cand & (S > 0.0)  # (n, J) candidate pieces the point is outside of
    blocks = _Blocks(obj._lp_bases if ids is not None and getattr(solver, "basis_hints", False) else None)
    batches = []  # (batch index, points, pieces, separation?)
    done = []  # penetration rays in closed form: (points, piece, value, y, witness)
    if outside.any():
        rows, pieces, pair, facets = _separation_facets(obj, values, PQ, bound, outside)
        used = np.bincount(pair, minlength=len(rows)) > 0  # a pair the ball cannot reach is no minimiser
        rows, pieces = rows[used], pieces[used]
        verts, counts, vid = _block_vertices(obj, (np.cumsum(used) - 1)[pair], facets, len(rows))
        lead = np.broadcast_to(_Q, (len(rows), 4, 3))
        keys = None if ids is None else (ids[rows] * n_pieces + pieces) * 5
        batches.append((blocks.add(lead, np.ones(4), verts, counts, -1.0, -P[rows], P[rows], keys, vid), rows, pieces, True))
    pieces, rows = _nonzero((cand & (S <= 0.0)).T)  # (point, piece) pairs, by piece, then point
    if len(rows):  # Eq. 3 for each k: min -rho  s.t.  rho q_k + V^T beta = p,  sum beta = 1
        # the optimum is where the ray p - rho q_k leaves the piece: one ray per pair and k, by piece, k, point
        k = np.repeat(np.arange(4), len(rows))
        order = np.lexsort((np.tile(rows, 4), k, np.tile(pieces, 4)))
        rows, pieces, k = np.tile(rows, 4)[order], np.tile(pieces, 4)[order], k[order]
        ray, facets = _pair_facets(obj, pieces)
        exits = _exit_facets(np.take(values, rows[ray] * values.shape[1] + facets), -obj._facet_q[facets, k[ray]], ray)
        ray, facets = ray[exits], facets[exits]
        closed, t, y = _facet_exit(obj, P[rows], -_Q[k], ray, facets)
        if closed.any():
            r, tc = rows[closed], t[closed]
            done.append((r, pieces[closed], -tc, -y[closed], P[r] - tc[:, None] * _Q[k[closed]]))
        if not closed.all():
            entry = ~closed[ray]
            r, kr, pr = rows[~closed], k[~closed], pieces[~closed]
            verts, counts, vid = _block_vertices(obj, (np.cumsum(~closed) - 1)[ray[entry]], facets[entry], len(r))
            keys = None if ids is None else (ids[r] * n_pieces + pr) * 5 + 1 + kr
            batches.append((blocks.add(_Q[kr, None], [-1.0], verts, counts, 1.0, P[r], P[r], keys, vid), r, pr, False))
    solved = blocks.solve(solver, "cP") if blocks.batches else []

    # one row per (point, piece[, k]) LP, then penetration = max over k, cP = min over pieces
    pts, pcs, vals, grads, wits, nrms, degs, ks = [], [], [], [], [], [], [], []
    for b, rows, j, separation in batches:
        lead_x, witness, y, deg = solved[b]
        pts.append(rows)
        pcs.append(np.broadcast_to(j, rows.shape))
        vals.append(lead_x.sum(axis=1) if separation else -lead_x[:, 0])
        grads.append(-y if separation else y)
        nrms.append(y if separation else -y)
        wits.append(witness)
        degs.append(deg)
        ks.append(np.full(len(rows), separation))
    for rows, j, value, y, witness in done:
        pts.append(rows)
        pcs.append(j)
        vals.append(value)
        grads.append(y)
        nrms.append(-y)
        wits.append(witness)
        degs.append(np.zeros(len(rows), dtype=bool))
        ks.append(np.zeros(len(rows), dtype=bool))
    pts, pcs, vals = np.concatenate(pts), np.concatenate(pcs), np.concatenate(vals)
    grads, wits, nrms = np.concatenate(grads), np.concatenate(wits), np.concatenate(nrms)
    degs, sep_rows = np.concatenate(degs), np.concatenate(ks)

    # penetration: the max over k (ties between k make the derivative one-sided)
    pair = pts * len(obj.convex) + pcs
    order, first = _first_per_group(pair, -vals)
    head = np.nonzero(first)[0]
    best_rows = order[head]
    follower = np.minimum(head + 1, len(order) - 1)
    same = (follower != head) & (pair[order[follower]] == pair[best_rows])
    tie_k = same & (np.abs(vals[order[follower]] - vals[best_rows]) <= 1e-9 * (1 + np.abs(vals[best_rows])))
    degs = degs.copy()
    degs[best_rows] |= tie_k
    # cP: the min over the candidate pieces (rows come out sorted by point)
    order2, first2 = _first_per_group(pts[best_rows], vals[best_rows])
    chosen = best_rows[order2[first2]]
    if len(chosen) != n:  # pragma: no cover - every point keeps at least one piece
        raise RuntimeError("cP: a hand point lost all its candidate pieces; please report this bug")
    degenerate = degs[chosen].copy()
    # a tie between pieces with different gradients: the derivative is one-sided
    nxt = first2 & _followed(first2)
    if nxt.any():
        a, b = best_rows[order2[nxt]], best_rows[order2[np.nonzero(nxt)[0] + 1]]
        close = np.abs(vals[b] - vals[a]) <= 1e-9 * (1 + np.abs(vals[a]))
        differ = np.abs(grads[b] - grads[a]).max(axis=1) > 1e-9 * (1 + np.abs(grads[a]).max(axis=1))
        degenerate[pts[a[close & differ]]] = True

    return ContactDistance(
        value=vals[chosen],
        grad=grads[chosen],
        nearest=wits[chosen],
        normal=unit_rows(nrms[chosen]),
        piece=pcs[chosen],
        inside=~sep_rows[chosen],
        degenerate=degenerate,
        candidates=cand.sum(axis=1),
        lp_solves=blocks.lp_solves,
    )


# --------------------------------------------------------------------------- sQ


def _ray_exits(obj, u):
    """Closed-form exit parameter of the rays c + t u (t >= 0) from every piece.

    Returns
    -------
    t_exit : (n, J) float
        Largest t with ``c + t u`` in piece j; -inf when the ray misses it.
    r : (n, F) float
        Where each ray crosses each facet plane it leaves through (``n_f . u > 0``),
        inf for the other planes; F counts the facets of all pieces.
    """
    a = u @ obj._planes[:, :3].T  # (n, F)
    b = obj._centre_depths  # (F,)  >= 0 where c is inside the facet's half-space
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = b / a
    upper = np.where(a > 0, ratio, np.inf)
    starts = obj._plane_starts
    t_hi = np.minimum.reduceat(upper, starts, axis=1)
    if obj._centre_in_every_piece:  # every ray starts inside every piece and leaves it at t_hi > 0
        return t_hi, upper
    lower = np.where(a < 0, ratio, -np.inf)
    blocked = (a == 0) & (b < 0)
    t_lo = np.maximum(np.maximum.reduceat(lower, starts, axis=1), 0.0)
    miss = np.logical_or.reduceat(blocked, starts, axis=1) | (t_lo > t_hi * (1 + 1e-12) + 1e-12)
    return np.where(miss, -np.inf, t_hi), upper


def scaled_contacts(obj, points, backend="highs") -> ScaledContacts:
    """sQ contacts of hand points; see `GraspObject.scaled_contacts`."""
    P = _check_points(points)
    solver = lp.get_backend(backend)
    c0 = obj.center
    U = P - c0
    length = np.linalg.norm(U, axis=1)
    at_centre = length <= 1e-9 * obj.torque_scale
    if at_centre.any():
        raise ValueError(
            f"points rows {np.nonzero(at_centre)[0].tolist()} coincide with the object's centre "
            f"{c0.tolist()}: the ray from the centre through the point, and so the sQ scale, is undefined"
        )
    T, R = _ray_exits(obj, U)
    best = T.max(axis=1)
    missed = ~np.isfinite(best)
    if missed.any():
        raise ValueError(
            f"the rays from the object's centre {c0.tolist()} through points rows "
            f"{np.nonzero(missed)[0].tolist()} miss the object; the centre must lie inside the object"
        )
    # the pieces the ray leaves last (closed form, within a tolerance)
    cand = T >= (best * (1 - 1e-7) - 1e-9)[:, None]
    alone = cand.sum(axis=1) == 1
    # one entry per (point, piece) pair, by piece, then point:
    # min -t  s.t.  t (p - c) - V^T lambda = -c,  sum lambda = 1
    pcs, pts = _nonzero(cand.T)
    pair, facets = _pair_facets(obj, pcs)
    # the optimum is the exit point: only the facets the ray leaves through (as in _exit_facets)
    exits = np.take(R, pts[pair] * R.shape[1] + facets) <= (T[pts, pcs] * (1 + 1e-9) + 1e-9)[pair]
    pair, facets = pair[exits], facets[exits]
    closed, ts, ys = _facet_exit(obj, c0, U[pts], pair, facets)
    closed &= alone[pts]
    degs = np.zeros(len(pts), dtype=bool)
    blocks = _Blocks()
    if not closed.all():
        lp_pairs = np.flatnonzero(~closed)
        entry = ~closed[pair]
        block = (np.cumsum(~closed) - 1)[pair[entry]]
        verts, counts, _ = _block_vertices(obj, block, facets[entry], len(lp_pairs))
        rows = pts[lp_pairs]
        blocks.add(U[rows, None, :], [-1.0], verts, counts, -1.0, np.broadcast_to(-c0, (len(rows), 3)), c0)
        lead_x, _, y, deg = blocks.solve(solver, "sQ ray")[0]
        ts[lp_pairs], ys[lp_pairs], degs[lp_pairs] = lead_x[:, 0], y, deg
    # each piece's rays in closed form, then its LP rays
    order = np.lexsort((pts, ~closed, pcs))
    pts, pcs, ts, ys, degs = pts[order], pcs[order], ts[order], ys[order], degs[order]
    order, first = _first_per_group(pts, -ts)
    chosen = order[first]
    degenerate = degs[chosen].copy()
    nxt = first & _followed(first)
    if nxt.any():  # the ray leaves two pieces at once: one-sided derivatives unless the planes agree
        a, b = order[nxt], order[np.nonzero(nxt)[0] + 1]
        close = np.abs(ts[b] - ts[a]) <= 1e-9 * (1 + np.abs(ts[a]))
        differ = np.abs(ys[b] - ys[a]).max(axis=1) > 1e-9 * (1 + np.abs(ys[a]).max(axis=1))
        degenerate[pts[a[close & differ]]] = True
    t, y = ts[chosen], ys[chosen]
    n = len(P)
    dt = t[:, None] * y  # d t / d p
    contact = c0 + t[:, None] * U
    eye = np.eye(3)
    jac_contact = t[:, None, None] * (eye + U[:, :, None] * y[:, None, :])
    return ScaledContacts(
        scale=1.0 / t,
        contact=contact,
        normal=unit_rows(y),
        point=P.copy(),
        grad_scale=-dt / t[:, None] ** 2,
        jac_contact=jac_contact,
        jac_normal=np.zeros((n, 3, 3)),
        piece=pcs[chosen],
        inside=t > 1.0,
        degenerate=degenerate,
        lp_solves=blocks.lp_solves,
    )


def _facet_exit(obj, c0, U, ray, facet):
    """The exit of rays from a piece in closed form, where a ray leaves through the inside of one facet.

    With a single exit plane (outward normal n_f, offset o_f) the optimum of
    the sQ LP (and of a penetration LP) is the ray's exit point,
    ``t = -(n_f . c + o_f) / (n_f . u)``, and the duals of the coordinate
    rows of the sQ LP are ``y = -n_f / (n_f . u)`` (so that ``y . u = -1``).
    Faces of a mesh are often split into coplanar triangles (a quad into
    two, a cap into a fan), all of them exit facets of the ray: when the exit
    point lies clearly inside one of them (its barycentric weights all above
    ``10 * DEGENERACY_TOL``) the LP's optimal basis is that triangle, unique,
    and this is the solution the LP would give.

    Parameters
    ----------
    obj : GraspObject
    c0 : (3,) or (m, 3) float
        The rays' origin(s).
    U : (m, 3) float
        The rays' directions.
    ray, facet : (e,) int
        The facets each ray may leave through (`_exit_facets`; at least one
        per ray, all of one piece), as indices in the plane arrays
        (``obj._planes``), sorted by ray.

    Returns
    -------
    closed : (m,) bool
        The rays settled here: every exit facet in one plane and the exit point
        clearly inside one of them (so the LP's degeneracy test would not fire).
    t : (m,) float
        Exit parameters (meaningful where ``closed``).
    y : (m, 3) float
        Duals of the coordinate rows (meaningful where ``closed``).
    """
    planes = obj._planes
    start = np.searchsorted(ray, np.arange(len(U)))
    first = facet[start]  # each ray's first exit facet: its plane
    normal, offset = planes[first, :3], planes[first, 3]
    a = np.einsum("ij,ij->i", normal, U)
    t = -((normal @ c0 if c0.ndim == 1 else np.einsum("ij,ij->i", normal, c0)) + offset) / a
    plane = planes[facet]
    coplanar = np.abs(plane - planes[first][ray]).max(axis=1) <= 1e-9 * (1.0 + np.abs(plane[:, 3]))
    # barycentric weights of the exit point in every exit facet
    tri = obj._vertices[obj._facet_vertex_rows[facet]] - (c0 + t[:, None] * U)[ray, None, :]
    area = np.einsum("ikj,ij->ik", cross(tri[:, [1, 2, 0]], tri[:, [2, 0, 1]]), plane[:, :3])
    inner = (area / area.sum(axis=1, keepdims=True)).min(axis=1)
    closed = np.logical_and.reduceat(coplanar, start) & (
        np.maximum.reduceat(inner, start) > 10 * DEGENERACY_TOL * np.maximum(1.0, t))
    return closed, t, -normal / a[:, None]


# --------------------------------------------------------------------------- capsules


def _frame(direction):
    """Rotation whose z axis is the unit ``direction``."""
    z = direction
    a = np.eye(3)[int(np.argmin(np.abs(z)))]
    x = np.cross(a, z)
    x /= np.linalg.norm(x)
    return np.column_stack([x, np.cross(z, x), z])


def penetration(obj, segments, radius) -> Penetration:
    """Deepest capsule penetration; see `GraspObject.penetration`."""
    try:
        seg = np.asarray(segments, dtype=float)
    except (TypeError, ValueError) as exc:
        raise TypeError(f"segments must be a numeric (k, 2, 3) array, got {type(segments).__name__}") from exc
    if seg.ndim != 3 or seg.shape[1:] != (2, 3) or len(seg) == 0:
        raise ValueError(f"segments must have shape (k, 2, 3) (end points of k capsule axes), got {seg.shape}")
    if not np.isfinite(seg).all():
        raise ValueError("segments contains NaN or inf")
    k = len(seg)
    try:
        r = np.asarray(radius, dtype=float)
    except (TypeError, ValueError):
        raise TypeError(f"radius must be a number or an array of ({k},) numbers, got {type(radius).__name__}") from None
    if r.ndim == 0:
        r = np.full(k, positive_scalar(float(r), "radius"))
    elif r.shape != (k,):
        raise ValueError(f"radius must be a number or shape ({k},), got shape {r.shape}")
    elif not (np.isfinite(r).all() and (r > 0).all()):
        raise ValueError("radius must be finite and > 0 for every capsule")
    request = fcl.DistanceRequest(enable_signed_distance=True)
    distances = np.empty(k)
    deepest_piece = np.full(k, -1)
    witnesses = np.full((k, 2, 3), np.nan)
    manager = obj._fcl_manager
    for i in range(k):
        a, b = seg[i]
        axis = b - a
        length = float(np.linalg.norm(axis))
        if length <= 1e-12:
            geom, rot = fcl.Sphere(float(r[i])), np.eye(3)
        else:
            geom, rot = fcl.Capsule(float(r[i]), length), _frame(axis / length)
        capsule = fcl.CollisionObject(geom, fcl.Transform(rot, 0.5 * (a + b)))
        data = fcl.DistanceData(request=request)
        manager.distance(capsule, data, fcl.defaultDistanceCallback)
        distances[i] = data.result.min_distance
        if distances[i] < 0:
            results = [fcl.DistanceResult() for _ in obj.convex]
            per = [fcl.distance(capsule, piece.fcl, request, res) for piece, res in zip(obj.convex, results)]
            distances[i] = min(per)
            deepest_piece[i] = int(np.argmin(per))
            witnesses[i] = results[deepest_piece[i]].nearest_points
    depths = np.maximum(-distances, 0.0)
    index = int(np.argmax(depths)) if (depths > 0).any() else -1
    return Penetration(
        depth=float(depths[index]) if index >= 0 else 0.0,
        index=index,
        depths=depths,
        distances=distances,
        piece=int(deepest_piece[index]) if index >= 0 else -1,
        witnesses=witnesses,
    )
