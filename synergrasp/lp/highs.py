"""HiGHS backend through highspy's own API (dual simplex, warm-started).

One ``Highs`` object is kept per backend instance and reused for every solve.
The last optimal basis of each LP *structure* is kept and handed to the solver
as a warm start when an LP with the same structure comes again. The structure
is the shape together with the sparsity pattern: inside the planner, LPs of one
shape can have different patterns (cP blocks list the vertices of the facets
facing each hand point, so the columns mean different vertices from one call to
the next), and a basis taken from an LP whose columns mean something else costs
more simplex iterations than a cold start. Keyed by pattern, the basis of the
previous iteration's LP of the same kind is found again.
"""

from __future__ import annotations

from collections import OrderedDict

import highspy
import numpy as np

from .base import Backend, csc_arrays

_STATUS = {
    highspy.HighsModelStatus.kOptimal: "optimal",
    highspy.HighsModelStatus.kInfeasible: "infeasible",
    highspy.HighsModelStatus.kUnbounded: "unbounded",
    highspy.HighsModelStatus.kUnboundedOrInfeasible: "infeasible",
}

#: Number of LP structures whose last optimal basis is remembered.
BASIS_CACHE_SIZE = 64


class HighsBackend(Backend):
    """LP backend on HiGHS (``highspy``), simplex with warm starts.

    Parameters
    ----------
    warm_start : bool
        Reuse the last optimal basis of an LP with the same shape and
        sparsity pattern.
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
        self._basis = OrderedDict()
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
        key = None
        if self.warm_start:
            key = (m, n, hash(indptr.tobytes()), hash(index.tobytes()))
            basis = self._basis.get(key)
            if basis is not None:
                h.setBasis(basis)
        h.run()
        model_status = h.getModelStatus()
        status = _STATUS.get(model_status, "failed")
        iterations = h.getInfoValue("simplex_iteration_count")[1]
        if status != "optimal":
            self._basis.pop(key, None)
            return status, None, None, iterations, h.modelStatusToString(model_status)
        solution = h.getSolution()
        if key is not None:
            self._basis[key] = h.getBasis()
            self._basis.move_to_end(key)
            if len(self._basis) > BASIS_CACHE_SIZE:
                self._basis.popitem(last=False)
        return status, solution.col_value, solution.row_dual, iterations, "Optimal"
