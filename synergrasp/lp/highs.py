"""HiGHS backend through highspy's own API (dual simplex, warm-started).

One ``Highs`` object is kept per backend instance and reused for every solve;
when consecutive LPs have the same shape the previous optimal basis is handed
to the solver as a warm start.
"""

from __future__ import annotations

import highspy
import numpy as np

from .base import Backend, csc_arrays

_STATUS = {
    highspy.HighsModelStatus.kOptimal: "optimal",
    highspy.HighsModelStatus.kInfeasible: "infeasible",
    highspy.HighsModelStatus.kUnbounded: "unbounded",
    highspy.HighsModelStatus.kUnboundedOrInfeasible: "infeasible",
}


class HighsBackend(Backend):
    """LP backend on HiGHS (``highspy``), simplex with warm starts.

    Parameters
    ----------
    warm_start : bool
        Reuse the last optimal basis when the next LP has the same shape.
    options : dict
        Extra HiGHS options (``setOptionValue(key, value)``).
    """

    def __init__(self, warm_start: bool = True, **options):
        super().__init__(name="highs")
        self.warm_start = warm_start
        self._h = highspy.Highs()
        self._h.setOptionValue("output_flag", False)
        self._h.setOptionValue("presolve", "off")  # tiny dense LPs: presolve costs more than it saves
        self._h.setOptionValue("solver", "simplex")
        self._h.setOptionValue("simplex_scale_strategy", 0)  # data are well scaled (mm, unit normals)
        self._h.setOptionValue("simplex_initial_condition_check", False)
        for key, value in options.items():
            self._h.setOptionValue(key, value)
        self._basis = {}
        self._bounds_cache = {}

    def _bounds(self, n):
        if n not in self._bounds_cache:
            self._bounds_cache[n] = (np.zeros(n), np.full(n, highspy.kHighsInf), np.zeros(n, dtype=np.int32))
        return self._bounds_cache[n]

    def _solve(self, c, A, b):
        m, n = A.shape
        lower, upper, continuous = self._bounds(n)
        indptr, index, value = csc_arrays(A)
        h = self._h
        # column-wise matrix (format 1), minimise (sense 1), no offset, all columns continuous
        h.passModel(n, m, len(value), 1, 1, 0.0, c, lower, upper, b, b, indptr[:-1], index, value, continuous)
        basis = self._basis.get((m, n)) if self.warm_start else None
        if basis is not None:
            h.setBasis(basis)
        h.run()
        model_status = h.getModelStatus()
        status = _STATUS.get(model_status, "failed")
        iterations = h.getInfoValue("simplex_iteration_count")[1]
        message = h.modelStatusToString(model_status)
        if status != "optimal":
            self._basis.pop((m, n), None)
            return status, None, None, iterations, message
        solution = h.getSolution()
        if self.warm_start:
            self._basis[(m, n)] = h.getBasis()
        return status, solution.col_value, solution.row_dual, iterations, message
