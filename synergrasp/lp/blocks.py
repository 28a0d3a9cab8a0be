"""Independent 4-row LP blocks stacked into one block-diagonal LP, with warm starts from their last bases.

The geometry of `synergrasp.objects` asks many tiny LPs at once (one per hand
point and convex piece, or per ray): 3 coordinate rows and one convexity row
each. `solve_blocks` stacks them (`Blocks`) into one block-diagonal LP, so that the solver's
per-call overhead is paid once; the blocks are independent, so each block's
optimum and duals are exactly those of the LP on its own. `BasisMemory`
keeps, per block key, the columns that were basic at the block's last
optimum, and hands them to backends with ``basis_hints`` as a warm start.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from .._jit import kernel
from ..tolerances import DEGENERACY_TOL
from .base import CSC, LPError

ROWS = 4  # 3 coordinate rows + 1 convexity row per block
#: About how many blocks' last optimal bases a `BasisMemory` keeps (it starts afresh above it).
MEMORY_SIZE = 20000


class Blocks(NamedTuple):
    """Independent 4-row LP blocks, described flat (block b: its lead columns, then its vertex columns).

    Block b reads ``lead x_L + sign_b (V_b - o_b)^T x_V = h_b - sign_b o_b``,
    ``sum x_V = 1``, ``x >= 0``, minimising ``cost . x_L``: its ``n_lead[b]``
    lead columns have entries in the 3 coordinate rows only; its
    ``n_vert[b]`` vertex columns are the points ``table[ids]`` of its vertex
    list, with entries ``sign_b * (v - o_b)`` in the coordinate rows and 1 in
    the convexity row. Writing each block relative to its origin o_b (the
    hand point, or the object's centre) subtracts ``sign_b o_b`` times the
    convexity row from the coordinate rows: a row operation, so the primal
    solution and the duals of the coordinate rows are those of
    ``lead x_L + sign_b V_b^T x_V = h_b``, and the LP data are distances
    rather than coordinates (better conditioned).

    Attributes
    ----------
    n_lead : (B,) int64
    lead : (sum(n_lead), 3) float
        Coordinate entries of the lead columns, block by block.
    cost : (sum(n_lead),) float
        Costs of the lead columns (vertex columns cost 0).
    n_vert : (B,) int64
        Vertices per block (each >= 1).
    table : (V, 3) float
        The points the vertex lists index.
    ids : (sum(n_vert),) int64
        The blocks' vertex lists, concatenated: rows of ``table``. They are
        also the vertex columns' identities in a `BasisMemory`.
    sign : (B,) float
        +1 or -1, the sign of each block's vertex entries.
    origin : (B, 3) float
    rhs : (B, 3) float
        Right-hand sides h of the coordinate rows.
    keys : (B,) int64 or None
        Block keys for a `BasisMemory` (needed when there is one).
    """

    n_lead: np.ndarray
    lead: np.ndarray
    cost: np.ndarray
    n_vert: np.ndarray
    table: np.ndarray
    ids: np.ndarray
    sign: np.ndarray
    origin: np.ndarray
    rhs: np.ndarray
    keys: np.ndarray | None = None

    @classmethod
    def uniform(cls, lead, cost, table, ids, counts, sign, rhs, origin, keys=None) -> "Blocks":
        """B blocks that share their lead columns' count and costs and the sign of their vertex entries.

        Parameters
        ----------
        lead : (B, L, 3) or (L, 3) float
            Coordinate entries of the lead columns (the same for every block if 2-D).
        cost : (L,) float
        table : (V, 3) float
        ids : (sum(counts),) int
        counts : (B,) int
        sign : float
        rhs : (B, 3) float
        origin : (B, 3) or (3,) float
        keys : (B,) int, optional
        """
        counts = np.asarray(counts, dtype=np.int64)
        B, lead = len(counts), np.asarray(lead, dtype=float)
        L = lead.shape[-2]
        return cls(np.full(B, L, dtype=np.int64), np.ascontiguousarray(np.broadcast_to(lead, (B, L, 3)).reshape(-1, 3)),
                   np.tile(np.asarray(cost, dtype=float), B), counts, np.ascontiguousarray(table, dtype=float),
                   np.asarray(ids, dtype=np.int64), np.full(B, float(sign)),
                   np.ascontiguousarray(np.broadcast_to(origin, (B, 3)), dtype=float),
                   np.ascontiguousarray(np.broadcast_to(rhs, (B, 3)), dtype=float),
                   None if keys is None else np.asarray(keys, dtype=np.int64))


class BlockSolution(NamedTuple):
    """The optimum of every block of a `Blocks` LP (`solve_blocks`).

    Attributes
    ----------
    lead_x : (sum(n_lead),) float
        The lead variables, block by block.
    witness : (B, 3) float
        The point ``sum_v x_v v`` of each block.
    y : (B, 3) float
        Duals of each block's coordinate rows.
    degenerate : (B,) bool
        The optimum has fewer than 4 positive variables, so the duals may
        not be unique. (Several primal optima, a face of the vertices
        parallel to the lead columns' cone, leave y unique and are not flagged.)
    lp_solves : int
        Solver calls made (1, more for a backend with ``max_columns`` below the LP's width).
    """

    lead_x: np.ndarray
    witness: np.ndarray
    y: np.ndarray
    degenerate: np.ndarray
    lp_solves: int


def solve_blocks(solver, blocks: Blocks, memory: BasisMemory | None = None, what: str = "block") -> BlockSolution:
    """Solve independent 4-row LP blocks together as one block-diagonal LP.

    One LP for all blocks, so that the solver's per-call overhead is paid
    once (a few LPs for a backend with ``max_columns``); the blocks are
    independent, so each block's optimum and duals are exactly those of the
    LP on its own. For a backend without ``vertex_solutions`` (an
    interior-point method), each block is then polished onto its optimal
    basis (`polish`): such backends then agree with the simplex to
    round-off, and the derivatives are the exact ones of the basis. With a
    `BasisMemory`, the LP starts from the columns that were basic at the last
    optimum of a block with the same key (for a backend with
    ``basis_hints``), and the memory is then updated.

    Parameters
    ----------
    solver : synergrasp.lp.Backend
    blocks : Blocks
    memory : BasisMemory, optional
    what : str
        Name of the LP in error messages.

    Returns
    -------
    BlockSolution

    Raises
    ------
    synergrasp.lp.LPError
        If the backend does not solve the LP to optimality.

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
    >>> blocks = Blocks.uniform(regular_simplex(3), np.ones(4), cube, np.arange(8), [8], -1.0, -p, p)
    >>> sol = solve_blocks(get_backend("highs"), blocks, what="cP")
    >>> round(float(sol.lead_x.sum()), 9), float(sol.witness[0, 2])
    (15.0, 10.0)
    """
    n_lead, n_vert = blocks.n_lead, blocks.n_vert
    n_blocks = len(n_lead)
    start = np.empty(n_blocks + 1, dtype=np.int64)
    start[0] = 0
    np.cumsum(n_lead + n_vert, out=start[1:])
    n_cols = int(start[-1])
    nnz = 3 * len(blocks.lead) + ROWS * len(blocks.ids)
    indptr, indices, data = np.empty(n_cols + 1, dtype=np.int32), np.empty(nnz, dtype=np.int32), np.empty(nnz)
    c, rhs, codes = np.empty(n_cols), np.empty((n_blocks, ROWS)), np.empty(n_cols, dtype=np.int64)
    keys = np.zeros(n_blocks, dtype=np.int64) if blocks.keys is None else blocks.keys
    nnz = _assemble(n_lead, blocks.lead, blocks.cost, n_vert, blocks.table, blocks.ids, blocks.sign, blocks.origin,
                    blocks.rhs, keys, BasisMemory.SPAN, indptr, indices, data, c, rhs, codes)
    hint = None if memory is None else memory.basic(codes)
    limit = solver.max_columns or n_cols
    if limit >= n_cols:
        x, y, lp_solves = _solve_one(solver, c, CSC(indptr, indices[:nnz], data[:nnz], (ROWS * n_blocks, n_cols)),
                                     rhs.ravel(), hint, what)
        y = y.reshape(-1, ROWS)
    else:
        x, y, lp_solves = np.empty(n_cols), np.empty((n_blocks, ROWS)), 0
        first = 0
        while first < n_blocks:  # a few LPs for a backend with a column limit
            last = first + max(1, int(np.searchsorted(start[first + 1:], start[first] + limit, side="right")))
            c0, c1 = int(start[first]), int(start[last])
            A = CSC(indptr[c0:c1 + 1] - indptr[c0], indices[indptr[c0]:indptr[c1]] - np.int32(ROWS * first),
                    data[indptr[c0]:indptr[c1]], (ROWS * (last - first), c1 - c0))
            x[c0:c1], part, _ = _solve_one(solver, c[c0:c1], A, rhs[first:last].ravel(),
                                           None if hint is None else hint[c0:c1], what)
            y[first:last] = part.reshape(-1, ROWS)
            lp_solves += 1
            first = last
    if not solver.vertex_solutions:  # a simplex's solution is already basic and exact
        polish(indptr, indices[:nnz], data[:nnz], c, rhs, x, y, start)
    if memory is not None:
        memory.remember(codes, x > 0.0)
    degenerate, witness, lead_x = np.empty(n_blocks, dtype=bool), np.zeros((n_blocks, 3)), np.empty(len(blocks.lead))
    _results(x, start, n_lead, blocks.table, blocks.ids, DEGENERACY_TOL, degenerate, witness, lead_x)
    return BlockSolution(lead_x, witness, np.ascontiguousarray(y[:, :3]), degenerate, lp_solves)


def _solve_one(solver, c, A, b, hint, what):
    sol = solver.solve(c, A, b, basic=hint, verify=False)  # geometry in mm, unit costs: well scaled
    if not sol.optimal:
        raise LPError(
            f"the {what} LP was not solved: backend {sol.backend!r} returned status "
            f"{sol.status!r} ({sol.message}). Try another backend (sg.lp.available_backends())."
        )
    return sol.x, sol.y, 1


@kernel
def _assemble(n_lead, lead, cost, n_vert, table, ids, sign, origin, h, keys, span, indptr, indices, data, c, rhs,
              codes):
    """The block-diagonal LP in compressed-column form; returns the number of entries.

    Fills ``indptr``, ``indices``, ``data`` (zeros left out), the costs
    ``c``, the right-hand side ``rhs`` (B, 4) and each column's memory code
    ``key * span + column id + 8`` (lead columns have ids -1, -2, ...,
    vertex columns their row in ``table``).
    """
    col, nnz, li, vi = 0, 0, 0, 0
    for b in range(len(n_lead)):
        row0 = ROWS * b
        s = sign[b]
        for r in range(3):
            rhs[b, r] = h[b, r] - s * origin[b, r]
        rhs[b, 3] = 1.0
        for j in range(n_lead[b]):
            indptr[col] = nnz
            c[col] = cost[li]
            codes[col] = keys[b] * span + 7 - j
            for r in range(3):
                if lead[li, r] != 0.0:
                    indices[nnz] = row0 + r
                    data[nnz] = lead[li, r]
                    nnz += 1
            li += 1
            col += 1
        for _ in range(n_vert[b]):
            v = ids[vi]
            indptr[col] = nnz
            c[col] = 0.0
            codes[col] = keys[b] * span + v + 8
            for r in range(3):
                value = s * (table[v, r] - origin[b, r])
                if value != 0.0:
                    indices[nnz] = row0 + r
                    data[nnz] = value
                    nnz += 1
            indices[nnz] = row0 + 3
            data[nnz] = 1.0
            nnz += 1
            vi += 1
            col += 1
    indptr[col] = nnz
    return nnz


@kernel
def _results(x, start, n_lead, table, ids, tol, degenerate, witness, lead_x):
    """Per block, into the last three (``witness`` zero on entry): degenerate (fewer than 4 clearly positive
    variables), the witness ``sum_v x_v v``, the lead variables."""
    li, vi = 0, 0
    for b in range(len(n_lead)):
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
            v = ids[vi]
            for r in range(3):
                witness[b, r] += x[j] * table[v, r]
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
    """The basic columns of LP blocks at their last optimum, by block key (warm starts of `solve_blocks`).

    A column is coded as one integer ``key * SPAN + column id + 8`` (lead
    columns have ids -1, -2, ..., vertex columns their vertex index); the
    codes of the columns that were basic are kept in a sorted array, so that
    looking up and updating the blocks of a whole LP is a few vectorised set
    operations.

    Examples
    --------
    >>> memory = BasisMemory()
    >>> span = BasisMemory.SPAN
    >>> memory.remember(7 * span + np.array([7, 12, 17]), np.array([True, False, True]))
    >>> memory.basic(np.array([7, 7, 8]) * span + np.array([7, 12, 7])).tolist()
    [True, False, False]
    """

    SPAN = 1 << 24  # column ids + 8 stay below it (vertex indices < 16.7 million)

    def __init__(self):
        self.codes = np.empty(0, dtype=np.int64)

    def __len__(self) -> int:
        """Number of (block, column) pairs kept."""
        return len(self.codes)

    def basic(self, codes):
        """(n,) bool: the columns (``codes`` (n,) int) basic at their block's last optimum."""
        return _members(codes, self.codes)

    def remember(self, codes, basic):
        """Replace what is kept of the blocks of ``codes`` (n,) by their columns ``basic`` (n,) bool."""
        old = self.codes if len(self.codes) <= 4 * MEMORY_SIZE else self.codes[:0]
        new = np.sort(codes[basic])
        out = np.empty(len(old) + len(new), dtype=np.int64)
        self.codes = out[:_replace_blocks(old, codes, new, self.SPAN, np.zeros(len(old), dtype=bool), out)]


def _members(values, sorted_set):
    """(n,) bool: which of ``values`` (n,) int are in ``sorted_set`` (sorted int array)."""
    if not len(sorted_set):
        return np.zeros(len(values), dtype=bool)
    at = np.minimum(np.searchsorted(sorted_set, values), len(sorted_set) - 1)
    return sorted_set[at] == values


@kernel
def _replace_blocks(old, codes, new, span, stale, out):
    """Into ``out``, merged in order: the sorted codes ``old`` of blocks that have none in ``codes``, and the sorted
    codes ``new``; returns their number. ``stale`` (len(old),) bool must come all False."""
    last = -1
    for i in range(len(codes)):  # a block's codes come together: look each block up once
        key = codes[i] // span
        if i > 0 and key == last:
            continue
        last = key
        lo, hi = 0, len(old)  # the first kept code of the block (a binary search; numpy's compiles slowly)
        while lo < hi:
            mid = (lo + hi) // 2
            if old[mid] < key * span:
                lo = mid + 1
            else:
                hi = mid
        while lo < len(old) and old[lo] < (key + 1) * span:
            stale[lo] = True
            lo += 1
    i, j, k = 0, 0, 0
    while i < len(old) or j < len(new):
        if i < len(old) and stale[i]:
            i += 1
        elif j == len(new) or (i < len(old) and old[i] <= new[j]):
            out[k] = old[i]
            i += 1
            k += 1
        else:
            out[k] = new[j]
            j += 1
            k += 1
    return k
