"""HiGHS backend through highspy's own API (dual simplex, warm-started).

One ``Highs`` object is kept per backend instance and reused for every solve.
The last optimal basis is remembered twice, under the LP's *structure* (shape
and the number of entries of every column) and under its shape alone, and
handed to the solver as a warm start: the basis of the last LP with the same
structure if there is one, else that of the last LP with the same shape.
Inside the planner several kinds of LP can share a shape while their columns
mean different things (a cP block lists the vertices of the facets facing its
hand point, which change as the point moves); keyed by structure, each kind
finds its own previous basis, and the shape fallback still helps when the
pattern changes a little from one iteration to the next. A caller that knows
better names the columns to start basic (``solve(..., basic=...)``; the cP
LP blocks of `synergrasp.objects` pass those of their last optimum), and
HiGHS completes them to a basis.
"""

from __future__ import annotations

import ctypes
import os
import sys
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

#: HiGHS's own defaults for the options that the fast path turns off, used once more when an
#: unscaled, unpresolved solve runs into numerical trouble (e.g. nearly coplanar point sets).
_RESCUE = {"simplex_scale_strategy": 2, "presolve": "choose"}

_STATUSES = np.array([highspy.HighsBasisStatus.kLower, highspy.HighsBasisStatus.kBasic], dtype=object)

#: Number of LP structures and shapes whose last optimal basis is remembered.
BASIS_CACHE_SIZE = 64

#: The number of threads HiGHS picks for ``threads = 0`` (half the logical CPUs, rounded up),
#: named explicitly: left at 0, HiGHS asks the operating system for the CPU count on every run,
#: which costs about a tenth of a solve this small. Naming the same count keeps HiGHS's global
#: scheduler as it would be (an instance of another count fails to run; see ``_run``).
THREADS = max(1, ((os.cpu_count() or 1) + 1) // 2)


def _flush_c_streams() -> None:
    """``fflush(NULL)``: write out what the C library buffered (where the C library can be reached)."""
    try:
        ctypes.CDLL(None).fflush(None)
    except (OSError, TypeError, AttributeError):
        pass


def _new_highs() -> highspy.Highs:
    """A ``highspy.Highs`` instance, without the banner HiGHS prints on the process's stdout.

    HiGHS writes its banner ("Running HiGHS ...") from C++ straight to file
    descriptor 1 when the first instance is made, before any option can turn
    output off; descriptor 1 is pointed at the null device meanwhile (the C
    streams flushed before it is restored, so nothing buffered leaks out later).
    """
    try:
        sys.stdout.flush()
        saved = os.dup(1)
    except (OSError, ValueError, AttributeError):  # no usable stdout: nothing to hide
        return highspy.Highs()
    null = os.open(os.devnull, os.O_WRONLY)
    try:
        os.dup2(null, 1)
        try:
            return highspy.Highs()
        finally:
            _flush_c_streams()
    finally:
        os.dup2(saved, 1)
        os.close(saved)
        os.close(null)


class HighsBackend(Backend):
    """LP backend on HiGHS (``highspy``), simplex with warm starts.

    Parameters
    ----------
    warm_start : bool
        Start from the columns the caller names as basic (``basic``), else
        from the last optimal basis of an LP with the same shape and column
        counts, else of the last LP with the same shape.
    options : dict
        Extra HiGHS options (``setOptionValue(key, value)``).
    """

    vertex_solutions = True  # simplex: basic solutions with exact duals
    basis_hints = True

    def __init__(self, warm_start: bool = True, **options):
        super().__init__(name="highs")
        self.warm_start = warm_start
        self._h = _new_highs()
        self._h.setOptionValue("output_flag", False)
        self._h.setOptionValue("presolve", "off")  # tiny dense LPs: presolve costs more than it saves
        self._h.setOptionValue("solver", "simplex")
        self._h.setOptionValue("simplex_scale_strategy", 0)  # data are well scaled (mm, unit normals)
        self._h.setOptionValue("simplex_initial_condition_check", False)
        self._h.setOptionValue("threads", THREADS)
        for key, value in options.items():
            self._h.setOptionValue(key, value)
        self._basis = OrderedDict()
        self._bounds_cache = {}

    def _run(self):
        """``run()``; if HiGHS's global scheduler was set up with another number of threads, adopt it."""
        h = self._h
        if h.run() == highspy.HighsStatus.kError and h.getModelStatus() == highspy.HighsModelStatus.kNotset:
            h.setOptionValue("threads", 0)  # 0: whatever the running scheduler has
            h.run()

    def _rescue(self):
        """Solve the loaded model again from scratch with HiGHS's own scaling and presolve."""
        h = self._h
        fast = {key: h.getOptionValue(key)[1] for key in _RESCUE}
        h.clearSolver()
        for key, value in _RESCUE.items():
            h.setOptionValue(key, value)
        try:
            h.run()
        finally:
            for key, value in fast.items():
                h.setOptionValue(key, value)
        return h.getModelStatus()

    def _hint(self, basic, m):
        """Start from the columns ``basic`` (n,) bool; HiGHS completes the basis with row logicals.

        The basis is passed as an "alien" one (``HighsBasis.alien``, the
        default): HiGHS adds the logicals of the rows the columns leave
        uncovered, and drops columns that would make it singular.
        """
        basis = highspy.HighsBasis()
        basis.col_status = _STATUSES[basic.view(np.int8)].tolist()
        basis.row_status = [highspy.HighsBasisStatus.kLower] * m
        basis.valid = True
        self._h.setBasis(basis)

    def _bounds(self, n):
        if n not in self._bounds_cache:
            self._bounds_cache[n] = (np.zeros(n), np.full(n, highspy.kHighsInf), np.zeros(n, dtype=np.int32))
        return self._bounds_cache[n]

    def _solve(self, c, A, b, basic=None):
        m, n = A.shape
        lower, upper, continuous = self._bounds(n)
        indptr, index, value = csc_arrays(A)
        h = self._h
        # column-wise matrix (format 1), minimise (sense 1), no offset, all columns continuous
        h.passModel(n, m, len(value), 1, 1, 0.0, c, lower, upper, b, b, indptr[:-1], index, value, continuous)
        key = shape = None
        if self.warm_start and basic is not None and basic.any():  # the caller's guess
            self._hint(basic, m)
        elif self.warm_start:  # the last optimal basis of an LP of this structure, else of this shape
            key, shape = (m, n, hash(indptr.tobytes())), (m, n)  # pattern: the column counts
            basis = self._basis.get(key)
            if basis is None:
                basis = self._basis.get(shape)
            if basis is not None:
                h.setBasis(basis)
        self._run()
        model_status = h.getModelStatus()
        status = _STATUS.get(model_status, "failed")
        if status == "failed":  # numerical trouble (e.g. nearly coplanar sets): once more, cold and scaled
            model_status = self._rescue()
            status = _STATUS.get(model_status, "failed")
        iterations = h.getInfoValue("simplex_iteration_count")[1]
        if status != "optimal":
            self._basis.pop(key, None)
            self._basis.pop(shape, None)
            return status, None, None, iterations, h.modelStatusToString(model_status)
        solution = h.getSolution()
        if key is not None:
            basis = h.getBasis()
            for k in (key, shape):
                self._basis[k] = basis
                self._basis.move_to_end(k)
            while len(self._basis) > BASIS_CACHE_SIZE:
                self._basis.popitem(last=False)
        return status, solution.col_value, solution.row_dual, iterations, "Optimal"
