"""cvxpy backend: a parametrised cvxpy model, compiled once per LP shape.

The model ``min c @ x  s.t.  A @ x == b, x >= 0`` is built with ``c``, ``A`` and
``b`` as cvxpy Parameters, so each shape is canonicalised once and later solves
only update the parameters. cvxpy's equality duals follow the Lagrangian
``c @ x + y @ (A @ x - b)``; they are negated to the library's convention.
"""

from __future__ import annotations

import cvxpy as cp
import numpy as np

from .base import CSC, Backend

#: cvxpy problem status -> library status.
STATUS = {
    cp.OPTIMAL: "optimal",
    cp.OPTIMAL_INACCURATE: "optimal",
    cp.INFEASIBLE: "infeasible",
    cp.INFEASIBLE_INACCURATE: "infeasible",
    cp.UNBOUNDED: "unbounded",
    cp.UNBOUNDED_INACCURATE: "unbounded",
}


class CvxpyBackend(Backend):
    """LP backend on a cvxpy model (solver chosen by ``solver``).

    Parameters
    ----------
    solver : str or None
        cvxpy solver name (any case), ``"CLARABEL"`` by default (ships with
        cvxpy); None lets cvxpy choose.
    solver_options : dict
        Passed to ``Problem.solve``.

    Raises
    ------
    ValueError
        For a ``solver`` cvxpy does not have installed.
    """

    inaccurate = frozenset({cp.OPTIMAL_INACCURATE})

    #: cvxpy canonicalises its parametrised dense matrix in time and memory that grow much faster
    #: than the LP (0.6 s for 60 x 1373, gigabytes for 244 x 10000): stacked blocks go in LPs of
    #: at most this many columns.
    max_columns = 400

    def __init__(self, solver: str = "CLARABEL", **solver_options):
        super().__init__(name="cvxpy")
        installed = cp.installed_solvers()
        if solver is not None and (not isinstance(solver, str) or solver.upper() not in installed):
            raise ValueError(f"cvxpy has no solver {solver!r} installed; it has {', '.join(installed)} (None: "
                             "cvxpy picks one)")
        self.solver = solver
        if solver is not None and solver.upper() == "CLARABEL" and not solver_options:
            solver_options = {"tol_gap_abs": 1e-10, "tol_gap_rel": 1e-10, "tol_feas": 1e-10}
        self.solver_options = solver_options
        self._models = {}

    def _model(self, m, n):
        if (m, n) not in self._models:
            x = cp.Variable(n, nonneg=True)
            c, A, b = cp.Parameter(n), cp.Parameter((m, n)), cp.Parameter(m)
            equality = A @ x == b
            problem = cp.Problem(cp.Minimize(c @ x), [equality])
            self._models[(m, n)] = (problem, x, c, A, b, equality)
        return self._models[(m, n)]

    def _solve(self, c, A, b):
        problem, x, c_par, A_par, b_par, equality = self._model(*A.shape)
        c_par.value, A_par.value, b_par.value = c, A.toarray() if isinstance(A, CSC) else A, b
        # cold: warm-started from the last LP of the same shape, Clarabel stopped at its iteration limit on LPs it
        # solves cold (the pseudo-distance of segments 1e4 long after one of a simplex 1e300 across)
        problem.solve(solver=self.solver, warm_start=False, **self.solver_options)
        status = STATUS.get(problem.status, "failed")
        iterations = problem.solver_stats.num_iters if problem.solver_stats else -1
        if status != "optimal":
            return status, None, None, iterations or -1, str(problem.status)
        return status, x.value, -np.asarray(equality.dual_value), iterations or -1, str(problem.status)
