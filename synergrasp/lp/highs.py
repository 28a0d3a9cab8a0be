"""HiGHS backend through highspy's own API (dual simplex, warm-started, models updated in place).

An LP's *structure* is its shape and sparsity pattern. The backend keeps a
few ``Highs`` objects, each holding the last LP of one structure with its
optimal basis. An LP whose structure one of them holds (inside the planner:
the Q-distance LPs, whose layout depends only on the number of contacts) is
written into it in place, its columns swapped for the new ones, and solved
from that basis; HiGHS then skips the set-up of a new model. Any other LP
replaces the model of the least recently used object and starts from the
last optimal basis of an LP with the same shape and column counts, else of
the same shape (several kinds of LP can share a shape while their columns
mean different things: a cP block lists the vertices of the facets facing
its hand point, which change as the point moves). A caller that knows
better names the columns to start basic (``solve(..., basic=...)``; the cP
LP blocks of `synergrasp.objects` pass those of their last optimum), and
HiGHS completes them to a basis.
"""

from __future__ import annotations

import ctypes
import math
import os
import sys
from collections import OrderedDict

import highspy
import numpy as np

from .base import BASIS_CACHE_SIZE, Backend, csc_arrays

_STATUS = {
    highspy.HighsModelStatus.kOptimal: "optimal",
    highspy.HighsModelStatus.kInfeasible: "infeasible",
    highspy.HighsModelStatus.kUnbounded: "unbounded",
    highspy.HighsModelStatus.kUnboundedOrInfeasible: "infeasible",
}
#: Model statuses of an LP that HiGHS did not run (a model it refused).
_NOT_RUN = (highspy.HighsModelStatus.kNotset, highspy.HighsModelStatus.kModelEmpty,
            highspy.HighsModelStatus.kModelError, highspy.HighsModelStatus.kLoadError)

#: HiGHS's own defaults for the options that the fast path turns off, used once more when an
#: unscaled, unpresolved solve runs into numerical trouble (e.g. nearly coplanar point sets).
_RESCUE = {"simplex_scale_strategy": 2, "presolve": "choose"}

_STATUSES = np.array([highspy.HighsBasisStatus.kLower, highspy.HighsBasisStatus.kBasic], dtype=object)

#: Number of ``Highs`` objects kept, each holding the last LP of one structure (see the module docstring).
MODEL_CACHE_SIZE = 8

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


class _Model:
    """One ``Highs`` object, the right-hand side of the LP it holds and that LP's optimal basis (None if not solved)."""

    def __init__(self, highs):
        self.highs = highs
        self.rhs = None
        self.basis = None


class HighsBackend(Backend):
    """LP backend on HiGHS (``highspy``), simplex with warm starts.

    Parameters
    ----------
    warm_start : bool
        Start from the columns the caller names as basic (``basic``), else
        from the last optimal basis of an LP with the same structure (solved
        in place), else with the same shape and column counts, else with the
        same shape. False: every LP is passed as a new model and solved cold.
    options : dict
        Extra HiGHS options (``setOptionValue(key, value)``).

    Raises
    ------
    ValueError
        For an option HiGHS refuses (an unknown name, or a value of the
        wrong type or range).
    """

    vertex_solutions = True  # simplex: basic solutions with exact duals
    basis_hints = True

    def __init__(self, warm_start: bool = True, **options):
        super().__init__(name="highs")
        self.warm_start = warm_start
        self._options = {
            "output_flag": False,
            "presolve": "off",  # tiny dense LPs: presolve costs more than it saves
            "solver": "simplex",
            "simplex_scale_strategy": 0,  # data are well scaled (mm, unit normals)
            "simplex_initial_condition_check": False,
            "large_matrix_value": math.inf,  # (1e15 by default: larger entries made HiGHS report an "Empty" model)
            "threads": THREADS,
            **options,
        }
        probe = _new_highs()  # an option HiGHS refuses (a misspelt name, a value of the wrong type) is refused now
        probe.setOptionValue("output_flag", False)
        for key, value in options.items():
            if probe.setOptionValue(key, value) != highspy.HighsStatus.kOk:
                raise ValueError(f"HiGHS refuses the option {key}={value!r} (an unknown name, or a value of the wrong "
                                 "type or range): see HiGHS's list of options, https://ergo-code.github.io/HiGHS/")
        self._models = OrderedDict()  # structure -> _Model, least recently used first
        self._basis = OrderedDict()
        self._bounds_cache = {}
        self.in_place = 0  # solves done in place (a model of the same structure updated)

    def forget(self) -> None:
        """Drop the kept models and the remembered bases: the next LPs are solved cold, as by a new instance."""
        self._models.clear()
        self._basis.clear()

    def _make_highs(self):
        h = _new_highs()
        for key, value in self._options.items():
            h.setOptionValue(key, value)
        return h

    def _model_for(self, key):
        """The model object for a structure: its own if kept, else a new or the least recently used one."""
        model = self._models.pop(key, None)
        if model is None:
            if len(self._models) >= MODEL_CACHE_SIZE:
                model = self._models.popitem(last=False)[1]
                model.rhs = model.basis = None
            else:
                model = _Model(self._make_highs())
        self._models[key] = model
        return model

    @staticmethod
    def _run(h):
        """``run()``; if HiGHS's global scheduler was set up with another number of threads, adopt it."""
        if h.run() == highspy.HighsStatus.kError and h.getModelStatus() == highspy.HighsModelStatus.kNotset:
            h.setOptionValue("threads", 0)  # 0: whatever the running scheduler has
            h.run()

    @staticmethod
    def _rescue(h):
        """Solve the loaded model again from scratch with HiGHS's own scaling and presolve."""
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

    @staticmethod
    def _hint(h, basic, m):
        """Start from the columns ``basic`` (n,) bool; HiGHS completes the basis with row logicals.

        The basis is passed as an "alien" one (``HighsBasis.alien``, the
        default): HiGHS adds the logicals of the rows the columns leave
        uncovered, and drops columns that would make it singular.
        """
        basis = highspy.HighsBasis()
        basis.col_status = _STATUSES[basic.view(np.int8)].tolist()
        basis.row_status = [highspy.HighsBasisStatus.kLower] * m
        basis.valid = True
        h.setBasis(basis)

    def _bounds(self, n):
        if n not in self._bounds_cache:
            self._bounds_cache[n] = (np.zeros(n), np.full(n, highspy.kHighsInf), np.zeros(n, dtype=np.int32),
                                     np.arange(n, dtype=np.int32))
        return self._bounds_cache[n]

    def _solve(self, c, A, b, basic=None):
        m, n = A.shape
        lower, upper, continuous, every = self._bounds(n)
        indptr, index, value = csc_arrays(A)
        counts = hash(indptr.tobytes())  # the column counts
        model = self._model_for((m, n, counts, hash(index.tobytes())))  # the structure
        h = model.highs
        hinted = self.warm_start and basic is not None and basic.any()
        if self.warm_start and not hinted and model.basis is not None:  # the same structure: update it in place
            h.deleteCols(n, every)
            h.addCols(n, c, lower, upper, len(value), indptr[:-1], index, value)
            if not np.array_equal(b, model.rhs):
                h.changeRowsBounds(m, every[:m] if m <= n else np.arange(m, dtype=np.int32), b, b)
            h.setBasis(model.basis)
            self.in_place += 1
        else:
            # column-wise matrix (format 1), minimise (sense 1), no offset, all columns continuous
            h.passModel(n, m, len(value), 1, 1, 0.0, c, lower, upper, b, b, indptr[:-1], index, value, continuous)
            if hinted:  # the caller's guess
                self._hint(h, basic, m)
            elif self.warm_start:  # the last optimal basis of an LP with these column counts, else of this shape
                basis = self._basis.get((m, n, counts))
                if basis is None:
                    basis = self._basis.get((m, n))
                if basis is not None:
                    h.setBasis(basis)
        model.rhs = b.copy()
        self._run(h)
        model_status = h.getModelStatus()
        status = _STATUS.get(model_status, "failed")
        if status == "failed":  # numerical trouble (e.g. nearly coplanar sets): once more, cold and scaled
            model_status = self._rescue(h)
            status = _STATUS.get(model_status, "failed")
        iterations = h.getInfoValue("simplex_iteration_count")[1]
        if iterations < 0 or model_status in _NOT_RUN:
            iterations = -1  # HiGHS refused the model and did not run: its counter holds no count
        if status != "optimal":
            model.basis = None
            self._basis.pop((m, n, counts), None)
            self._basis.pop((m, n), None)
            return status, None, None, iterations, h.modelStatusToString(model_status)
        solution = h.getSolution()
        if self.warm_start:
            model.basis = basis = h.getBasis()
        if self.warm_start and not hinted:
            for k in ((m, n, counts), (m, n)):
                self._basis[k] = basis
                self._basis.move_to_end(k)
            while len(self._basis) > BASIS_CACHE_SIZE:
                self._basis.popitem(last=False)
        return status, solution.col_value, solution.row_dual, iterations, "Optimal"
