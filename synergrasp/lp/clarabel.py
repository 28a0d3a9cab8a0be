"""Clarabel backend through clarabel's own API (interior point).

The LP is passed as ``A x + s = b`` with ``s`` in the zero cone (equalities)
and ``-x + s = 0`` with ``s`` in the non-negative cone (``x >= 0``). Clarabel's
duals ``z`` follow ``q + A.T z = 0`` for this form, so ``y = -z`` on the equality
rows. Interior-point methods have no basis to warm-start from; the solver
object is rebuilt for each LP, its constraint matrix ``[A; -I]`` assembled
directly in compressed-column form.
"""

from __future__ import annotations

import clarabel
import numpy as np
import scipy.sparse as sp

from .._checks import positive_scalar
from .base import Backend, csc_arrays

#: Loosest ``tol`` a `ClarabelBackend` takes.
MAX_TOL = 1e-5

_STATUS = {
    "Solved": "optimal",
    "AlmostSolved": "optimal",
    "PrimalInfeasible": "infeasible",
    "AlmostPrimalInfeasible": "infeasible",
    "DualInfeasible": "unbounded",
    "AlmostDualInfeasible": "unbounded",
}


class ClarabelBackend(Backend):
    """LP backend on Clarabel (interior point, tight tolerances).

    Parameters
    ----------
    tol : float
        Used for Clarabel's gap and feasibility tolerances, in (0, 1e-5].

    Raises
    ------
    ValueError
        For a ``tol`` outside that range (a looser one gives wrong values and
        gradients that the library's own LPs, which skip the answer check,
        would not notice).
    """

    inaccurate = frozenset({"AlmostSolved"})

    def __init__(self, tol: float = 1e-10):
        super().__init__(name="clarabel")
        tol = positive_scalar(tol, "tol", MAX_TOL)
        settings = clarabel.DefaultSettings()
        settings.verbose = False
        settings.tol_gap_abs = settings.tol_gap_rel = tol
        settings.tol_feas = settings.tol_ktratio = tol
        self._settings = settings
        self._p_cache = {}

    def _zero_p(self, n):
        if n not in self._p_cache:
            self._p_cache[n] = sp.csc_matrix((n, n))
        return self._p_cache[n]

    def _solve(self, c, A, b):
        m, n = A.shape
        indptr, indices, data = csc_arrays(A)
        # [A; -I] column by column: each column's entries of A, then -1 in row m + j
        ptr = indptr.astype(np.int64) + np.arange(n + 1)
        diagonal = ptr[1:] - 1
        rows = np.empty(len(data) + n, dtype=np.int64)
        values = np.empty(len(data) + n)
        keep = np.ones(len(values), dtype=bool)
        keep[diagonal] = False
        rows[keep], values[keep] = indices, data
        rows[diagonal], values[diagonal] = m + np.arange(n), -1.0
        G = sp.csc_matrix((values, rows, ptr), shape=(m + n, n))
        h = np.concatenate([b, np.zeros(n)])
        cones = [clarabel.ZeroConeT(m), clarabel.NonnegativeConeT(n)]
        solver = clarabel.DefaultSolver(self._zero_p(n), c, G, h, cones, self._settings)
        solution = solver.solve()
        text = str(solution.status)
        status = _STATUS.get(text, "failed")
        if status != "optimal":
            return status, None, None, solution.iterations, text
        z = np.asarray(solution.z)
        return status, np.asarray(solution.x), -z[:m], solution.iterations, text
