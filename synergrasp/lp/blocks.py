"""Independent 4-row LP blocks stacked into one block-diagonal LP, with warm starts from their last bases.

The geometry of `synergrasp.objects` asks many tiny LPs at once (one per hand
point and convex piece, or per ray): 3 coordinate rows and one convexity row
each. `BlockLP` stacks them into one block-diagonal LP, so that the solver's
per-call overhead is paid once; the blocks are independent, so each block's
optimum and duals are exactly those of the LP on its own. `BasisMemory`
keeps, per block key, the columns that were basic at the block's last
optimum, and hands them to backends with ``basis_hints`` as a warm start.
"""

from __future__ import annotations

import numpy as np

from .._jit import kernel
from ..tolerances import DEGENERACY_TOL
from .base import CSC, LPError

ROWS = 4  # 3 coordinate rows + 1 convexity row per block
#: About how many blocks' last optimal bases a `BasisMemory` keeps (it starts afresh above it).
MEMORY_SIZE = 20000


class BlockLP:
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

    For a backend without ``vertex_solutions`` (an interior-point method),
    each block is then polished onto its optimal basis: the 4 columns with
    the largest values form a basis B; if ``B x = b`` and ``B^T y = c_B``
    give a primal and dual feasible pair (reduced costs >= 0), that exact
    vertex solution replaces the solver's. Such backends then agree with the
    simplex to round-off, and the derivatives are the exact ones of the basis.

    With a `BasisMemory` (``memory``), every block carries a key (``add``'s
    ``keys``, its vertices their indices ``ids``): the LP starts from the
    columns that were basic at the last optimum of a block with the same key
    (for a backend with ``basis_hints``), and the memory is then updated.

    Parameters
    ----------
    memory : BasisMemory, optional

    Attributes
    ----------
    lp_solves : int
        Solver calls made by the last `solve` (1, more for a backend with
        ``max_columns`` below the LP's width).

    Examples
    --------
    The separation LP of the point p = (0, 0, 25) and a 20 mm cube (paper
    Eq. 1 with the regular simplex Q): lead columns ``q_k`` of cost 1, the
    cube's corners as vertex columns with sign -1, right-hand side ``-p``.
    Straight above the top face, along a vertex direction of Q, the value is
    the Euclidean gap, 15 mm, and the witness lies on the top face.

    >>> import itertools
    >>> from synergrasp import regular_simplex
    >>> from synergrasp.lp import get_backend
    >>> cube = np.array(list(itertools.product([-10.0, 10.0], repeat=3)))
    >>> p = np.array([[0.0, 0.0, 25.0]])
    >>> blocks = BlockLP()
    >>> batch = blocks.add(regular_simplex(3)[None], np.ones(4), cube, [8], -1.0, -p, p)
    >>> lead_x, witness, y, degenerate = blocks.solve(get_backend("highs"), "cP")[batch]
    >>> round(float(lead_x.sum()), 9), float(witness[0, 2])
    (15.0, 10.0)
    """

    def __init__(self, memory: BasisMemory | None = None):
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
            Vertices per block (each >= 1).
        sign : float
            +1 or -1, the sign of the vertex entries.
        rhs : (B, 3) float
            Right-hand sides h of the coordinate rows.
        origin : (B, 3) or (3,) float
            Origin o of each block.
        keys : (B,) int, optional
            Block keys for the memory (needed when there is one).
        ids : (sum(counts),) int, optional
            An identity of each vertex within its key's blocks (needed when there is a memory).
        """
        counts = np.asarray(counts, dtype=np.int64)
        origin = np.ascontiguousarray(np.broadcast_to(origin, (len(counts), 3)), dtype=float)
        lead = np.ascontiguousarray(np.broadcast_to(lead, (len(counts),) + np.shape(lead)[-2:]), dtype=float)
        self.batches.append((lead, np.asarray(cost, dtype=float), np.ascontiguousarray(vertices, dtype=float), counts,
                             float(sign), np.asarray(rhs, dtype=float), origin))
        self.keys.append(keys)
        self.ids.append(ids)
        return len(self.batches) - 1

    def solve(self, solver, what: str):
        """Solve all blocks as one LP (or a few, for a backend with ``max_columns``).

        Parameters
        ----------
        solver : synergrasp.lp.Backend
        what : str
            Name of the LP in error messages.

        Returns
        -------
        list of (lead_x, witness, y, degenerate) per batch
            ``lead_x`` (B, L) the lead variables, ``witness`` (B, 3) the
            point ``sum_v x_v v``, ``y`` (B, 3) the duals of the coordinate
            rows, ``degenerate`` (B,) bool: the optimum has fewer than 4
            positive variables, so the duals may not be unique. (Several
            primal optima, a face of the vertices parallel to the lead
            columns' cone, leave y unique and are not flagged.)

        Raises
        ------
        synergrasp.lp.LPError
            If the backend does not solve the LP to optimality.
        """
        batches = self.batches
        n_lead = np.concatenate([np.full(len(b[3]), b[0].shape[1], dtype=np.int64) for b in batches])
        n_vert = np.concatenate([b[3] for b in batches])
        lead = np.concatenate([b[0].reshape(-1, 3) for b in batches])
        cost = np.concatenate([np.tile(b[1], len(b[3])) for b in batches])
        vertices = np.concatenate([b[2] for b in batches])
        sign = np.concatenate([np.full(len(b[3]), b[4]) for b in batches])
        origin = np.concatenate([b[6] for b in batches])
        rhs = np.ones((len(n_lead), ROWS))
        rhs[:, :3] = np.concatenate([b[5] for b in batches]) - sign[:, None] * origin
        start = np.concatenate([[0], np.cumsum(n_lead + n_vert)])
        nnz = 3 * len(lead) + ROWS * len(vertices)
        indptr, indices, data, c = np.empty(start[-1] + 1, dtype=np.int32), np.empty(nnz, dtype=np.int32), np.empty(nnz), np.empty(start[-1])
        nnz = _assemble(n_lead, lead, cost, n_vert, vertices, sign, origin, start, indptr, indices, data, c)
        indices, data = indices[:nnz], data[:nnz]
        n_blocks, n_cols = len(n_lead), int(start[-1])
        hint = None
        if self.memory is not None:
            keys = np.concatenate(self.keys)
            colid = _column_ids(start, n_lead, np.concatenate(self.ids).astype(np.int64))
            block_keys = np.repeat(keys, start[1:] - start[:-1])
            hint = self.memory.basic(block_keys, colid)
        limit = solver.max_columns or n_cols
        x, y = np.empty(n_cols), np.empty((n_blocks, ROWS))
        first = 0
        self.lp_solves = 0
        while first < n_blocks:  # one LP for all blocks, or a few for a backend with a column limit
            last = first + max(1, int(np.searchsorted(start[first + 1:], start[first] + limit, side="right")))
            c0, c1 = int(start[first]), int(start[last])
            A = CSC(indptr[c0:c1 + 1] - indptr[c0], indices[indptr[c0]:indptr[c1]] - np.int32(ROWS * first),
                    data[indptr[c0]:indptr[c1]], (ROWS * (last - first), c1 - c0))
            b = rhs[first:last].ravel()
            if hint is None:
                sol = solver.solve(c[c0:c1], A, b)
            else:
                sol = solver.solve(c[c0:c1], A, b, basic=hint[c0:c1])
            self.lp_solves += 1
            if not sol.optimal:
                raise LPError(
                    f"the {what} LP was not solved: backend {sol.backend!r} returned status "
                    f"{sol.status!r} ({sol.message}). Try another backend (sg.lp.available_backends())."
                )
            x[c0:c1], y[first:last] = sol.x, sol.y.reshape(-1, ROWS)
            first = last
        if not solver.vertex_solutions:  # a simplex's solution is already basic and exact
            polish(indptr, indices, data, c, rhs, x, y, start)
        if self.memory is not None:
            self.memory.remember(block_keys, colid, x > 0.0)
        degenerate, witness, lead_x = np.empty(n_blocks, dtype=bool), np.zeros((n_blocks, 3)), np.empty(len(lead))
        _results(x, start, n_lead, vertices, DEGENERACY_TOL, degenerate, witness, lead_x)
        out, first, lead_first = [], 0, 0
        for b in batches:
            B, L = len(b[3]), b[0].shape[1]
            part = slice(first, first + B)
            out.append((lead_x[lead_first:lead_first + B * L].reshape(B, L), witness[part], y[part, :3], degenerate[part]))
            first, lead_first = first + B, lead_first + B * L
        return out


@kernel
def _assemble(n_lead, lead, cost, n_vert, vertices, sign, origin, start, indptr, indices, data, c):
    """The block-diagonal LP in compressed-column form, into ``indptr``, ``indices``, ``data`` and ``c``; returns nnz.

    Block b (columns ``start[b] ... start[b+1] - 1``) has ``n_lead[b]`` lead
    columns (entries ``lead`` in its coordinate rows, zeros left out, costs
    ``cost``) then ``n_vert[b]`` vertex columns (entries
    ``sign[b] * (v - origin[b])``, zeros left out, and 1 in its convexity
    row; cost 0).
    """
    n_blocks = len(n_lead)
    n_cols = start[n_blocks]
    col, nnz, li, vi = 0, 0, 0, 0
    for b in range(n_blocks):
        row0 = ROWS * b
        for _ in range(n_lead[b]):
            indptr[col] = nnz
            c[col] = cost[li]
            for r in range(3):
                if lead[li, r] != 0.0:
                    indices[nnz] = row0 + r
                    data[nnz] = lead[li, r]
                    nnz += 1
            li += 1
            col += 1
        s = sign[b]
        for _ in range(n_vert[b]):
            indptr[col] = nnz
            for r in range(3):
                value = s * (vertices[vi, r] - origin[b, r])
                if value != 0.0:
                    indices[nnz] = row0 + r
                    data[nnz] = value
                    nnz += 1
            indices[nnz] = row0 + 3
            data[nnz] = 1.0
            c[col] = 0.0
            nnz += 1
            vi += 1
            col += 1
    indptr[n_cols] = nnz
    return nnz


def _column_ids(start, n_lead, vertex_ids):
    """(n,) int64: each column's identity within its block: lead columns -1, -2, ..., vertex columns their vertex id."""
    n_cols = int(start[-1])
    block_of = np.repeat(np.arange(len(n_lead)), start[1:] - start[:-1])
    offset = np.arange(n_cols) - start[block_of]
    is_lead = offset < n_lead[block_of]
    colid = np.empty(n_cols, dtype=np.int64)
    colid[is_lead] = -offset[is_lead] - 1
    colid[~is_lead] = vertex_ids
    return colid


@kernel
def _results(x, start, n_lead, vertices, tol, degenerate, witness, lead_x):
    """Per block, into the last three (``witness`` zero on entry): degenerate (fewer than 4 clearly positive
    variables), the witness ``sum_v x_v v``, the lead variables."""
    n_blocks = len(n_lead)
    li, vi = 0, 0
    for b in range(n_blocks):
        c0, c1 = start[b], start[b + 1]
        xmax = 0.0
        for j in range(c0, c1):
            xmax = max(xmax, abs(x[j]))
        level = tol * max(1.0, xmax)
        positive = 0
        for j in range(c0, c1):
            if x[j] > level:
                positive += 1
        degenerate[b] = positive < ROWS
        for j in range(n_lead[b]):
            lead_x[li] = x[c0 + j]
            li += 1
        for j in range(c0 + n_lead[b], c1):
            for r in range(3):
                witness[b, r] += x[j] * vertices[vi, r]
            vi += 1


def polish(indptr, indices, data, c, rhs, x, y, start):
    """Replace each block's solution by the exact one of its optimal basis, where that is feasible.

    Parameters
    ----------
    indptr, indices, data : CSC arrays of the LP (block b in rows ``4 b ... 4 b + 3``)
    c : (n,) float
    rhs : (B, 4) float
    x : (n,) float
        Solver's primal solution (updated in place).
    y : (B, 4) float
        Solver's duals per block (updated in place).
    start : (B+1,) int
        First column of each block.
    """
    n_blocks, n_cols = len(rhs), len(x)
    block_of = np.repeat(np.arange(n_blocks), start[1:] - start[:-1])
    entries = np.zeros((n_cols, ROWS))
    columns = np.repeat(np.arange(n_cols), np.diff(indptr))
    entries[columns, indices % ROWS] = data
    order = np.lexsort((-x, block_of))  # per block, columns by decreasing value
    rank = np.arange(n_cols) - start[block_of[order]]
    basis = order[rank < ROWS].reshape(n_blocks, ROWS)
    M = entries[basis]  # (B, 4 columns, 4 rows): M[b].T is the basis matrix
    det = np.linalg.det(M)
    scale = np.abs(M).max(axis=(1, 2)) ** ROWS
    ok = np.abs(det) > 1e-12 * np.maximum(scale, 1e-300)
    M_safe = np.where(ok[:, None, None], M, np.eye(ROWS))
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


class BasisMemory:
    """The basic columns of LP blocks at their last optimum, by block key (warm starts of `BlockLP`).

    Each (block key, column id) pair that was basic is kept as one integer
    ``key * SPAN + column id + 8`` (lead columns have ids -1, -2, ...,
    vertex columns their vertex index) in a sorted array, so that looking up
    and updating the blocks of a whole LP is a few vectorised set operations.

    Examples
    --------
    >>> memory = BasisMemory()
    >>> memory.remember(np.array([7, 7, 7]), np.array([-1, 4, 9]), np.array([True, False, True]))
    >>> memory.basic(np.array([7, 7, 8]), np.array([-1, 4, -1])).tolist()
    [True, False, False]
    """

    SPAN = 1 << 24  # column ids + 8 stay below it (vertex indices < 16.7 million)

    def __init__(self):
        self.codes = np.empty(0, dtype=np.int64)

    def __len__(self) -> int:
        """Number of (block, column) pairs kept."""
        return len(self.codes)

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
