"""Reference LP backends a user might pick instead of synergrasp's own, and a timing wrapper.

Both references are ordinary :class:`synergrasp.lp.Backend` subclasses, so they
can be passed wherever synergrasp takes a backend (``backend=LinprogBackend()``):

* :class:`LinprogBackend` -- ``scipy.optimize.linprog(method="highs")``, one
  call per LP with the dense (or, for large LPs, sparse) matrix, as a user
  would write it. scipy's ``eqlin.marginals`` are already ``d objective / d b``.
* :class:`PlainCvxpyBackend` -- a plain cvxpy model, built from scratch for
  every LP (no Parameters, nothing cached) and solved by cvxpy's default
  solver for LPs. cvxpy's equality duals follow ``c @ x + y @ (A @ x - b)``
  and are negated to the library's convention.

:class:`TimedBackend` wraps any backend and accumulates the solver time
(``LPSolution.solve_time``) and the number of calls, which is how the
comparison measures the share of a plan spent inside the LP solver.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from synergrasp.lp import CSC, Backend, get_backend
from synergrasp.lp.cvxpy import STATUS as CVXPY_STATUS

#: Above this many matrix entries the references pass scipy a sparse matrix.
DENSE_LIMIT = 200_000

_LINPROG_STATUS = {0: "optimal", 2: "infeasible", 3: "unbounded"}


def _matrix(A):
    """A as a user would hand it to a modelling call: dense, or sparse CSC when large."""
    if isinstance(A, CSC):
        if A.shape[0] * A.shape[1] <= DENSE_LIMIT:
            return A.toarray()
        return sp.csc_matrix((A.data, A.indices, A.indptr), shape=A.shape)
    return A


class LinprogBackend(Backend):
    """``scipy.optimize.linprog(method="highs")`` as an LP backend (no warm start, no reuse).

    Parameters
    ----------
    options : dict
        Passed to ``linprog`` as ``options``.
    """

    def __init__(self, **options):
        super().__init__(name="scipy-linprog")
        self.options = options

    def _solve(self, c, A, b):
        from scipy.optimize import linprog

        res = linprog(c, A_eq=_matrix(A), b_eq=b, bounds=(0, None), method="highs", options=self.options or None)
        status = _LINPROG_STATUS.get(res.status, "failed")
        iterations = int(getattr(res, "nit", -1) or 0)
        if status != "optimal":
            return status, None, None, iterations, res.message
        return status, res.x, res.eqlin.marginals, iterations, res.message


class PlainCvxpyBackend(Backend):
    """A plain cvxpy model rebuilt for every LP, solved by cvxpy's default LP solver.

    Attributes
    ----------
    solver_name : str
        The solver cvxpy chose at the last solve (cvxpy's default for LPs).
    """

    def __init__(self):
        super().__init__(name="cvxpy-plain")
        self.solver_name = ""

    def _solve(self, c, A, b):
        import cvxpy as cp

        x = cp.Variable(len(c), nonneg=True)
        equality = _matrix(A) @ x == b
        problem = cp.Problem(cp.Minimize(c @ x), [equality])
        problem.solve()
        stats = problem.solver_stats
        self.solver_name = stats.solver_name if stats else ""
        iterations = (stats.num_iters if stats else None) or -1
        status = CVXPY_STATUS.get(problem.status, "failed")
        if status != "optimal":
            return status, None, None, iterations, str(problem.status)
        return status, x.value, -np.asarray(equality.dual_value, dtype=float), iterations, str(problem.status)


class TimedBackend(Backend):
    """Wraps a backend and accumulates its solver time and calls.

    Parameters
    ----------
    inner : str or Backend
        The backend doing the work (a name is resolved with ``get_backend``).

    Attributes
    ----------
    lp_time : float
        Sum of ``LPSolution.solve_time`` (s) since the last :meth:`reset`.
    lp_calls : int
        Solves since the last :meth:`reset`.
    """

    def __init__(self, inner):
        self.inner = get_backend(inner)
        super().__init__(name=self.inner.name)
        self.vertex_solutions = self.inner.vertex_solutions
        self.basis_hints = self.inner.basis_hints
        self.max_columns = self.inner.max_columns
        self.lp_time = 0.0
        self.lp_calls = 0

    def reset(self):
        """Zero the accumulated time and calls."""
        self.lp_time, self.lp_calls = 0.0, 0

    def solve(self, c, A, b, basic=None, *, verify=True):
        sol = self.inner.solve(c, A, b, basic=basic, verify=verify)
        self.lp_time += sol.solve_time
        self.lp_calls += 1
        self.calls += 1
        return sol

    def __str__(self) -> str:
        return self.name
