"""A built-in backend for the library's many small LPs: a dense simplex on each independent block.

The LPs of the geometry and of the Q distance are block diagonal: a cP call
stacks one 4-row block per hand point and convex piece, a Q distance one
block per direction of the simplex. A general solver pays its set-up for the
whole stacked LP on every call (`synergrasp.lp.highs`: 1-3 ms for 25-130
blocks of 4 rows), while each block alone is a few pivots on a 4 x 4 basis.
This backend splits the LP into its independent blocks (the connected
components of its rows, linked by the columns that share them; an exact
decomposition) and solves each with a dense revised simplex:

* phase 1 on artificial columns (rows with a negative right-hand side
  negated first), from the columns the caller names as basic (``basic``)
  or, without them, the last optimal basis of an LP of the same structure:
  those that keep the basis nonsingular enter it, and if their values are
  not all >= 0 one artificial column, minus the sum of the basic columns of
  negative value, lifts them all to >= 0 (the single-artificial start);
  then the artificials left basic at zero are pivoted out, or their row is
  redundant;
* phase 2 with Dantzig's pricing, Bland's rule after a run of degenerate
  pivots (no cycling), ties of the ratio test to the lowest column;
* the final basis refactorised (Gauss-Jordan with partial pivoting), its
  primal values and duals recomputed and checked: a reduced cost < 0 left
  by round-off is priced on (at most `RECHECKS` times per phase: an
  ill-conditioned basis can cycle through pivots its refactorisation
  undoes), and a basis that round-off left infeasible
  starts again from its own columns (at most `RESTARTS` times). If it is
  still infeasible then, but by no more than phase 1 accepts as feasible
  (the data's own round-off, e.g. entries of 1e-9 beside entries of 1), it
  is taken with its values clipped to 0;
* a block that fails all the same (a pivot on an entry barely above the
  pivot tolerance can leave a basis too ill-conditioned to refactorise
  feasibly, or cycling) is solved once more from its start, with a budget
  of pivots of its own, pivoting only on entries above `RESCUE_PIVOT_TOL`;
  if that fails too, the LP is reported failed.

The solution is a vertex with its exact duals (``vertex_solutions``). It is
meant for blocks of up to a few dozen rows (each block's work is dense);
larger LPs are solved correctly but slowly: use HiGHS for them.
"""

from __future__ import annotations

import numpy as np

from .._jit import helper, kernel
from .base import BASIS_CACHE_SIZE, STATUSES, Backend, csc_arrays

#: Feasibility, optimality and pivot tolerances, relative to the LP's data (the largest |b|, |c|, |A|).
TOL = 1e-9
#: Degenerate pivots in a row after which the pricing switches from Dantzig's rule to Bland's.
DEGENERATE_RUN = 8
#: Pivots allowed per block, per row and column of the block.
PIVOTS_PER_SIZE = 50
#: Fresh starts of a block whose basis round-off left infeasible, before it is reported failed.
RESTARTS = 3
#: Optima of one phase that the refactorised basis prices out again (round-off) before the try is given up: an
#: ill-conditioned basis can cycle through pivots that the refactorisation undoes.
RECHECKS = 5
#: Pivot tolerance (relative to the column's largest entry) of the second try of a block that failed with `TOL`.
RESCUE_PIVOT_TOL = 1e-7
#: Precedence of the blocks' status codes (0 optimal, 1 infeasible, 2 unbounded, 3 failed) in the LP's: an
#: infeasible block makes the LP infeasible, a failed one leaves an unbounded LP's status unknown.
STATUS_RANK = np.array([0, 3, 1, 2])


class NativeBackend(Backend):
    """LP backend of the library itself: each independent block of the LP by a dense simplex.

    Parameters
    ----------
    warm_start : bool
        Start from the columns the caller names as basic (``basic``), else
        from the last optimal basis of an LP with the same structure (shape
        and sparsity pattern). False: every LP starts from the artificial
        basis.

    Examples
    --------
    Two independent blocks, ``min x0 + x1 s.t. x0 - x1 = 1`` and
    ``min x2 s.t. x2 + x3 = 2``:

    >>> backend = NativeBackend()
    >>> sol = backend.solve([1.0, 1.0, 1.0, 0.0], [[1.0, -1.0, 0.0, 0.0], [0.0, 0.0, 1.0, 1.0]], [1.0, 2.0])
    >>> sol.status, sol.x.tolist(), sol.y.tolist()
    ('optimal', [1.0, 0.0, 0.0, 2.0], [1.0, 0.0])
    """

    vertex_solutions = True  # simplex: basic solutions with exact duals
    basis_hints = True

    def __init__(self, warm_start: bool = True):
        super().__init__(name="native")
        self.warm_start = warm_start
        self._bases = {}  # structure -> last optimal basic columns (n,) bool

    def forget(self) -> None:
        """Drop the remembered bases: the next LPs start as those of a new instance."""
        self._bases.clear()

    def _solve(self, c, A, b, basic=None):
        m, n = A.shape
        indptr, indices, data = csc_arrays(A)  # int32 indices (`Backend.solve` checked them)
        indptr, indices = _writable(indptr, np.int32), _writable(indices, np.int32)  # one signature (not read-only)
        c, b, data = _writable(c, float), _writable(b, float), _writable(data, float)
        key = None  # the LP's structure, hashed only where a remembered basis is read, stored or dropped
        if not self.warm_start:
            hint = np.zeros(n, dtype=bool)
        elif basic is not None:
            hint = basic
        else:
            key = _structure(m, n, indptr, indices)
            hint = self._bases.get(key, np.zeros(n, dtype=bool))
        hint = _writable(hint, bool)
        # the blocks: rows linked by shared columns, rows and columns ordered block by block
        order, starts = np.empty(m + n, dtype=np.int64), np.zeros((2, m + 3), dtype=np.int64)
        sizes = np.zeros(3, dtype=np.int64)  # blocks, most rows, most columns
        _blocks(indptr, indices, np.empty(2 * m + n, dtype=np.int64), order, starts, sizes)
        rows_max, width = int(sizes[1]), int(sizes[1] + sizes[2] + 1)
        scale = np.empty(3)
        _scale(b, c, data, scale)
        xy, out = np.zeros(n + m), np.zeros(2, dtype=np.int64)  # x then y; status, pivots
        _solve_blocks(indptr, indices, data, c, b, hint, order, np.ascontiguousarray(starts[:, :sizes[0] + 2]), scale,
                      np.empty(m, dtype=np.int64), np.empty((3, rows_max, width)), np.empty((7, width)),
                      np.empty((2, width), dtype=np.int64), np.empty(width, dtype=bool), xy, out)
        x, y = xy[:n], xy[n:]
        status, pivots = STATUSES[int(out[0])], int(out[1])  # status codes 0-3 (`STATUS_RANK`)
        if status != "optimal":
            self._bases.pop(key or _structure(m, n, indptr, indices), None)
            return status, None, None, pivots, f"{status} (native dense simplex, {pivots} pivots)"
        if self.warm_start and basic is None:
            self._bases.pop(key, None)
            self._bases[key] = x > 0.0
            while len(self._bases) > BASIS_CACHE_SIZE:
                self._bases.pop(next(iter(self._bases)))
        return status, x, y, pivots, "Optimal"


def _writable(v, dtype):
    """``v`` as a C-contiguous, writable array of ``dtype`` (the kernels' one signature), copied only if it is not."""
    if isinstance(v, np.ndarray) and v.dtype == dtype and v.flags.c_contiguous and v.flags.writeable:
        return v
    return np.array(v, dtype=dtype, order="C")


def _structure(m, n, indptr, indices):
    """An LP's shape and sparsity pattern, hashed: the key of its remembered basis."""
    return m, n, hash(indptr.tobytes()), hash(indices.tobytes())


@kernel
def _scale(b, c, data, out):
    """Into ``out`` (3,): the largest ``|b|``, ``|c|`` and ``|A|`` (0 for an empty array)."""
    for i, v in enumerate((b, c, data)):
        top = 0.0
        for e in v:
            top = max(top, abs(e))
        out[i] = top


@kernel
def _blocks(indptr, indices, scratch, order, starts, sizes):
    """Order the rows and columns block by block (a block: rows linked by shared columns, numbered by their
    first row). Block k's rows are ``order[starts[0, k]:starts[0, k + 1]]``, its columns
    ``order[m + starts[1, k + 1]:m + starts[1, k + 2]]``; ``order[m:m + starts[1, 1]]`` are the columns
    without entries. ``sizes`` receives (blocks, most rows, most columns); ``starts`` must come zeroed."""
    n = len(indptr) - 1
    m = (len(scratch) - n) // 2
    parent, block_of_row, block_of_col = scratch[:m], scratch[m:2 * m], scratch[2 * m:]
    row_order, col_order, row_start, col_start = order[:m], order[m:], starts[0], starts[1]
    for r in range(m):
        parent[r] = r
    for j in range(n):
        if indptr[j + 1] == indptr[j]:
            continue
        a = _root(parent, np.int64(indices[indptr[j]]))
        for e in range(indptr[j] + 1, indptr[j + 1]):
            r = _root(parent, np.int64(indices[e]))
            if r != a:
                if r < a:
                    parent[a] = r
                    a = r
                else:
                    parent[r] = a
    count = 0
    for r in range(m):
        root = _root(parent, r)
        if root == r:
            block_of_row[r] = count
            count += 1
        else:
            block_of_row[r] = block_of_row[root]
        row_start[block_of_row[r] + 1] += 1
    for j in range(n):
        block_of_col[j] = -1 if indptr[j + 1] == indptr[j] else block_of_row[indices[indptr[j]]]
        col_start[block_of_col[j] + 2] += 1
    most_rows, most_cols = 1, 1
    for k in range(count):
        most_rows = max(most_rows, row_start[k + 1])
        most_cols = max(most_cols, col_start[k + 2])
    for k in range(count):  # counts to starts, then counting sort (stable)
        row_start[k + 1] += row_start[k]
    for k in range(count + 1):
        col_start[k + 1] += col_start[k]
    for r in range(m):
        k = block_of_row[r]
        row_order[row_start[k]] = r
        row_start[k] += 1
    for j in range(n):
        k = block_of_col[j] + 1
        col_order[col_start[k]] = j
        col_start[k] += 1
    for k in range(count, 0, -1):  # shift the advanced starts back
        row_start[k] = row_start[k - 1]
    row_start[0] = 0
    for k in range(count + 1, 0, -1):
        col_start[k] = col_start[k - 1]
    col_start[0] = 0
    sizes[0] = count
    sizes[1] = most_rows
    sizes[2] = most_cols


@helper
def _root(parent, r):
    while parent[r] != r:
        parent[r] = parent[parent[r]]
        r = parent[r]
    return r


@kernel
def _solve_blocks(indptr, indices, data, c, b, hint, order, starts, scale, local, F2, F1, I1, inbasis, xy, out):
    """Solve every block of the LP (`_blocks` ordered them): ``xy`` receives x then y, ``out`` (the LP's
    status, pivots). Empty columns stay at 0 (one of negative cost makes a feasible LP unbounded). Scratch: F2
    (3, rows, width) for the block, its basis inverse and a work matrix; F1 (7, width) and I1 (2, width).

    Each block is a two-phase revised simplex on ``T x = rhs, x >= 0`` (T = [A_k | I | a], rhs >= 0; for a
    block of mk rows the last mk + 1 columns, I and ``a``, are artificial, ``a`` written by `_start`), written
    here rather than in a helper of its own: numba compiles a kernel with all the helpers it calls, and every
    further level of calls compiles them all once more (most of the kernels' compilation time)."""
    m, n = len(b), len(c)
    row_order, col_order, row_start, col_start = order[:m], order[m:], starts[0], starts[1]
    T, Binv, work = F2[0], F2[1], F2[2]
    rhs, cost, xb, yb, d, colnorm, sign = F1[0], F1[1], F1[2], F1[3], F1[4], F1[5], F1[6]
    basis, cols = I1[0], I1[1]
    x, y = xy[:n], xy[n:]
    tol, degenerate_run, pivots_per_size = TOL, DEGENERATE_RUN, PIVOTS_PER_SIZE
    status, pivots = 0, 0
    tol_b = tol * (1.0 + scale[0])
    tol_c = tol * (1.0 + scale[1])
    for k in range(col_start[0], col_start[1]):  # columns without entries
        if c[col_order[k]] < -tol_c:
            status = 2
    for blk in range(starts.shape[1] - 2):
        r0, r1 = row_start[blk], row_start[blk + 1]
        k0, k1 = col_start[blk + 1], col_start[blk + 2]
        mk, nk = r1 - r0, k1 - k0
        for i in range(mk):
            local[row_order[r0 + i]] = i
        # dense block [A_k | I | a] with rows of negative right-hand side negated
        width = nk + mk + 1
        for i in range(mk):
            r = row_order[r0 + i]
            sign[i] = -1.0 if b[r] < 0.0 else 1.0
            rhs[i] = sign[i] * b[r]
            for j in range(width):
                T[i, j] = 0.0
            T[i, nk + i] = 1.0
        for j in range(nk):
            col = col_order[k0 + j]
            cols[j] = col
            for e in range(indptr[col], indptr[col + 1]):
                i = local[indices[e]]
                T[i, j] += sign[i] * data[e]
        for j in range(width):
            s = 0.0
            for i in range(mk):
                s = max(s, abs(T[i, j]))
            colnorm[j] = s
        st, max_pivots = 4, pivots_per_size * width
        for pivot_tol in (tol, RESCUE_PIVOT_TOL):  # a block that failed is solved again with the stricter pivot test
            pv = 0  # each try has the whole budget of pivots
            for j in range(width):
                inbasis[j] = j < nk and hint[cols[j]]
            st = 4
            for restart in range(RESTARTS):  # a basis that round-off left infeasible is started again from its columns
                last = restart == RESTARTS - 1  # ... and on the last restart taken if it is feasible within tol_b * mk
                _start(mk, width, T, rhs, nk, pivot_tol, tol_b, colnorm, basis, inbasis, Binv, work, xb, d)
                # phase 1: minimise the artificials
                for j in range(width):
                    cost[j] = 1.0 if j >= nk else 0.0
                st, p = _iterate(mk, T, rhs, cost, nk, tol_b, tol, pivot_tol, degenerate_run, max_pivots - pv, basis,
                                 inbasis, Binv, work, xb, yb, d, colnorm)
                pv += p
                if st == 4 and not (last and _clipped(mk, xb, tol_b * mk)):
                    continue
                if st not in (0, 4):
                    st = 3
                    break
                infeasibility = 0.0
                for i in range(mk):
                    if basis[i] >= nk:
                        infeasibility += xb[i]
                if infeasibility > tol_b * mk:
                    st = 1
                    break
                pv += _drive_out(mk, nk, T, pivot_tol, colnorm, basis, inbasis, Binv, d)
                _factor(mk, T, basis, Binv, work)
                _values(mk, Binv, rhs, xb)
                for i in range(mk):
                    xb[i] = max(xb[i], 0.0) if basis[i] < nk else 0.0
                # phase 2: the LP's costs; artificials never enter
                for j in range(nk):
                    cost[j] = c[cols[j]]
                for j in range(nk, width):
                    cost[j] = 0.0
                st, p = _iterate(mk, T, rhs, cost, nk, tol_b, tol_c, pivot_tol, degenerate_run, max_pivots - pv, basis,
                                 inbasis, Binv, work, xb, yb, d, colnorm)
                pv += p
                if st == 4 and last and _clipped(mk, xb, tol_b * mk):
                    _duals(mk, Binv, cost, basis, yb)
                    st = 0
                if st != 4:
                    break
            if st == 4:  # out of restarts
                st = 3
            pivots += pv
            if st != 3:
                break
        if STATUS_RANK[st] > STATUS_RANK[status]:
            status = st
        if st != 0:
            continue
        for j in range(nk):
            x[cols[j]] = 0.0
        for i in range(mk):
            if basis[i] < nk:
                x[cols[basis[i]]] = max(xb[i], 0.0)
            y[row_order[r0 + i]] = sign[i] * yb[i]
    out[0] = status
    out[1] = pivots


@helper
def _clipped(m, xb, limit):
    """True, with ``xb`` clipped to >= 0, when no value is below ``-limit`` (a basis feasible within the
    tolerance phase 1 accepts); False, ``xb`` unchanged, otherwise."""
    for i in range(m):
        if xb[i] < -limit:
            return False
    for i in range(m):
        xb[i] = max(xb[i], 0.0)
    return True


@helper
def _drive_out(m, n, T, tol, colnorm, basis, inbasis, Binv, d):
    """After phase 1: the artificials still basic (at zero) pivoted out on any column of their row, else their
    row is redundant. Returns the pivots."""
    pivots = 0
    for i in range(m):
        if basis[i] < n:
            continue
        best, enter = 0.0, n  # n: none (a literal -1 would have numba compile _column for it too)
        for j in range(n):
            if inbasis[j]:
                continue
            v = 0.0
            for r in range(m):
                v += Binv[i, r] * T[r, j]
            if abs(v) > max(best, tol * colnorm[j]):
                best, enter = abs(v), j
        if enter < n:
            _column(m, Binv, T, enter, d)
            inbasis[basis[i]] = False
            inbasis[enter] = True
            basis[i] = enter
            _pivot(m, Binv, d, i)
            pivots += 1
    return pivots


@helper
def _start(m, width, T, rhs, n, tol, tol_b, colnorm, basis, inbasis, Binv, work, xb, d):
    """A starting basis: the columns flagged in ``inbasis`` crashed into the artificial basis (those that keep it
    nonsingular). If their values are not all >= 0, the artificial column ``a`` = -(the sum of the basic columns
    of negative value) replaces the most negative one: every negative value rises to >= 0. Sets ``basis``,
    ``Binv``, ``xb`` and ``inbasis``."""
    for i in range(m):
        basis[i] = n + i
    _factor(m, T, basis, Binv, work)
    for j in range(n):
        if not inbasis[j]:
            continue
        _column(m, Binv, T, j, d)
        best, row = tol * colnorm[j], m  # m: none (a literal -1 would have numba compile _pivot for it too)
        for i in range(m):
            if basis[i] >= n and abs(d[i]) > best:
                best, row = abs(d[i]), i
        if row < m:
            basis[row] = j
            _pivot(m, Binv, d, row)
    if not _factor(m, T, basis, Binv, work):
        for i in range(m):
            basis[i] = n + i
        _factor(m, T, basis, Binv, work)
    _values(m, Binv, rhs, xb)
    worst, row = -tol_b, -1
    for i in range(m):
        if xb[i] < worst:
            worst, row = xb[i], i
    if row >= 0:
        extra = width - 1
        for r in range(m):
            T[r, extra] = 0.0
        for i in range(m):
            if xb[i] < -tol_b:
                for r in range(m):
                    T[r, extra] -= T[r, basis[i]]
        colnorm[extra] = 0.0
        for r in range(m):
            colnorm[extra] = max(colnorm[extra], abs(T[r, extra]))
        basis[row] = extra
        _factor(m, T, basis, Binv, work)
        _values(m, Binv, rhs, xb)
    for i in range(m):
        xb[i] = max(xb[i], 0.0)
    for j in range(width):
        inbasis[j] = False
    for i in range(m):
        inbasis[basis[i]] = True


@helper
def _iterate(m, T, rhs, cost, n, tol_b, tol_c, tol, degenerate_run, max_pivots, basis, inbasis, Binv, work, xb, yb, d,
             colnorm):
    """Primal simplex from a feasible basis over the first ``n`` columns (the others never enter).
    Returns (status, pivots), status 0 optimal, 2 unbounded, 3 out of pivots or cycling (`RECHECKS`), or 4 when
    the refactorised basis turns out infeasible (round-off); at an optimum the basis is refactorised and checked."""
    pivots, degenerate, refactorised, rechecks = 0, 0, False, 0
    while True:
        _duals(m, Binv, cost, basis, yb)
        enter = _price(m, n, T, cost, yb, colnorm, inbasis, tol_c, degenerate >= degenerate_run)
        if refactorised and enter >= 0:
            rechecks += 1
            if rechecks > RECHECKS:  # round-off of an ill-conditioned basis cycles: not this pivot tolerance
                return 3, pivots
        if enter < 0:
            if refactorised:
                return 0, pivots
            # optimal for this basis: refactorise, recompute and check (priced again, by Bland's rule, at the top
            # of the loop: one pricing call, as a second one with a literal True would be compiled again)
            _factor(m, T, basis, Binv, work)
            _values(m, Binv, rhs, xb)
            for i in range(m):
                if xb[i] < -tol_b:
                    return 4, pivots  # round-off left the basis infeasible: start again from it
            refactorised, degenerate = True, degenerate_run
            continue
        if pivots >= max_pivots:
            return 3, pivots
        _column(m, Binv, T, enter, d)
        row, theta = m, 0.0  # m: none, as in _start
        for i in range(m):
            if d[i] > tol * colnorm[enter]:
                ratio = max(xb[i], 0.0) / d[i]
                if row == m or ratio < theta - tol_b or (ratio <= theta + tol_b and basis[i] < basis[row]):
                    row, theta = i, ratio
        if row == m:
            return 2, pivots
        degenerate = degenerate + 1 if theta <= tol_b else 0
        for i in range(m):
            xb[i] -= theta * d[i]
        xb[row] = theta
        inbasis[basis[row]] = False
        inbasis[enter] = True
        basis[row] = enter
        _pivot(m, Binv, d, row)
        pivots += 1
        refactorised = False


@helper
def _price(m, n, T, cost, yb, colnorm, inbasis, tol_c, bland):
    """The entering column among the first ``n`` nonbasic ones: the most negative reduced cost below the
    tolerance (Dantzig's rule), or with ``bland`` the first such column; -1 if none."""
    enter, best = -1, -tol_c
    for j in range(n):
        v = cost[j]
        for i in range(m):
            v -= yb[i] * T[i, j]
        if v < -tol_c * (1.0 + colnorm[j]) and (v < best or (bland and enter < 0)):
            if inbasis[j]:
                continue
            best, enter = v, j
            if bland:
                break
    return enter


@helper
def _factor(m, T, basis, Binv, work):
    """Binv = inverse of the basis columns (Gauss-Jordan, partial pivoting); False if singular."""
    for i in range(m):
        for r in range(m):
            work[i, r] = T[i, basis[r]]
            Binv[i, r] = 1.0 if i == r else 0.0
    for col in range(m):
        p, big = col, abs(work[col, col])
        for i in range(col + 1, m):
            if abs(work[i, col]) > big:
                p, big = i, abs(work[i, col])
        if big == 0.0:
            return False
        if p != col:
            for r in range(m):
                work[p, r], work[col, r] = work[col, r], work[p, r]
                Binv[p, r], Binv[col, r] = Binv[col, r], Binv[p, r]
        inv = 1.0 / work[col, col]
        for r in range(m):
            work[col, r] *= inv
            Binv[col, r] *= inv
        for i in range(m):
            if i != col and work[i, col] != 0.0:
                f = work[i, col]
                for r in range(m):
                    work[i, r] -= f * work[col, r]
                    Binv[i, r] -= f * Binv[col, r]
    return True


@helper
def _column(m, Binv, T, j, d):
    for i in range(m):
        v = 0.0
        for r in range(m):
            v += Binv[i, r] * T[r, j]
        d[i] = v


@helper
def _pivot(m, Binv, d, row):
    """Update Binv for the basis whose column ``row`` is replaced by the one of direction d = Binv a."""
    inv = 1.0 / d[row]
    for r in range(m):
        Binv[row, r] *= inv
    for i in range(m):
        if i != row and d[i] != 0.0:
            f = d[i]
            for r in range(m):
                Binv[i, r] -= f * Binv[row, r]


@helper
def _values(m, Binv, rhs, xb):
    for i in range(m):
        v = 0.0
        for r in range(m):
            v += Binv[i, r] * rhs[r]
        xb[i] = v


@helper
def _duals(m, Binv, cost, basis, yb):
    for r in range(m):
        v = 0.0
        for i in range(m):
            v += cost[basis[i]] * Binv[i, r]
        yb[r] = v
