"""The LP interface shared by every backend.

Every backend solves the standard-form linear programme

    minimise    c @ x
    subject to  A @ x == b,   x >= 0

and returns an :class:`LPSolution`. Dual sign convention (identical for all
backends): the Lagrangian is ``c @ x - y @ (A @ x - b)``, so ``y`` is the
sensitivity of the optimal value to the right-hand side, ``y_r = d value / d b_r``,
the reduced costs ``c - A.T @ y`` are >= 0, and for a unique optimum
``d value / d A[r, j] = -y[r] * x[j]``.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

from typing import ClassVar, NamedTuple

import numpy as np

from .._checks import numeric
from .._jit import kernel

#: The statuses an :class:`LPSolution` can carry.
STATUSES = ("optimal", "infeasible", "unbounded", "failed")
#: Last optimal bases a backend remembers (one per LP structure), for LPs solved without a given basis.
BASIS_CACHE_SIZE = 64


class LPError(RuntimeError):
    """An LP that had to be solved to optimality was not.

    Raised by the grasp-quality layers (never by a backend's ``solve``), with
    the backend's name and status in the message.
    """


@dataclass(frozen=True)
class LPSolution:
    """Result of one standard-form LP solve.

    Attributes
    ----------
    status : str
        One of ``"optimal"``, ``"infeasible"``, ``"unbounded"``, ``"failed"``.
    x : (n,) float
        Primal solution (NaN unless optimal).
    objective : float
        Optimal value ``c @ x`` (NaN unless optimal).
    y : (m,) float
        Duals of the equality rows, ``y_r = d objective / d b_r``
        (Lagrangian ``c @ x - y @ (A @ x - b)``; NaN unless optimal).
    iterations : int
        Solver iterations (simplex or interior-point), -1 if unknown.
    solve_time : float
        Wall-clock seconds spent in the backend's ``solve`` call.
    backend : str
        Name of the backend that produced it.
    message : str
        The solver's own status text, for diagnostics.
    """

    status: str
    x: np.ndarray
    objective: float
    y: np.ndarray
    iterations: int
    solve_time: float
    backend: str
    message: str = ""

    @property
    def optimal(self) -> bool:
        """True when ``status == "optimal"``."""
        return self.status == "optimal"


@dataclass
class Backend:
    """Base class of the LP backends: input checks, timing, error capture.

    Subclasses implement :meth:`_solve`, returning
    ``(status, x, y, iterations, message)``; :meth:`solve` wraps it so that a
    solver's own exception comes back as status ``"failed"``, never raised.

    Attributes
    ----------
    name : str
        Registry name of the backend.
    vertex_solutions : bool
        Class attribute: the optimal ``x`` is always a basic (vertex) solution
        with its exact duals, as a simplex method gives; an interior-point
        solution may lie inside an optimal face and is only accurate to the
        solver's tolerance. Callers that move a solution onto its optimal
        basis can skip that step when this is True.
    basis_hints : bool
        Class attribute: :meth:`solve` can start from the columns named by
        its ``basic`` argument (a simplex warm start); other backends ignore
        the argument.
    max_columns : int or None
        Class attribute: the largest LP (in columns) worth passing in one
        call; callers that stack independent blocks (`synergrasp.lp.blocks`)
        split them into several LPs above it. None: no limit.
    calls : int
        Number of solves done by this instance.

    Examples
    --------
    A backend only implements ``_solve``; ``solve`` adds the checks and timing.

    >>> class Trivial(Backend):
    ...     def _solve(self, c, A, b):
    ...         return "optimal", np.linalg.lstsq(A, b, rcond=None)[0], np.zeros(len(b)), 0, "ok"
    >>> Trivial(name="trivial").solve([0.0], [[2.0]], [4.0]).x
    array([2.])
    """

    name: str = "base"
    calls: int = field(default=0, init=False)
    vertex_solutions: ClassVar[bool] = False
    basis_hints: ClassVar[bool] = False
    max_columns: ClassVar[int | None] = None
    #: The solver's messages for an answer it found to a looser tolerance than asked ("almost solved"):
    #: `solve` checks such an answer (`optimality_gaps`) even with ``verify=False``.
    inaccurate: ClassVar[frozenset] = frozenset()

    def solve(self, c, A, b, basic=None, *, verify=True) -> LPSolution:
        """Solve ``min c @ x  s.t.  A @ x == b, x >= 0``.

        Parameters
        ----------
        c : (n,) float
            Cost vector.
        A : (m, n) float ndarray or CSC
            Equality-constraint matrix, dense or column-compressed (the latter
            skips the sparsity scan for large structured LPs).
        b : (m,) float
            Right-hand side.
        basic : (n,) bool, optional
            Columns believed to be basic at the optimum (e.g. from a similar
            LP solved before). Backends with ``basis_hints`` start from them,
            completing the basis with row logicals; the others ignore it. It
            changes only the solver's path: the value is the LP's (where the
            optimum is not unique, which optimal vertex comes back may differ).
        verify : bool
            Check an optimal answer (`optimality_gaps`): a solution that breaks
            the constraints, a reduced cost below 0 or a duality gap, each by
            more than `VERIFY_TOL` of the data's scale, comes back as
            ``"failed"`` with the gaps in its message. Solvers' tolerances are
            absolute (HiGHS's 1e-7), so on badly scaled data (entries of 1e12,
            costs of 1e-9) they can call a wrong answer optimal. The library's
            own LPs, scaled by their callers, skip it (``verify=False``), unless
            the solver says its answer is inaccurate (`inaccurate`).
            Either way an optimal ``x`` of an LP with ``b == 0`` that is 0 to
            within `HOMOGENEOUS_ZERO` comes back as exactly 0.

        Returns
        -------
        LPSolution
            Status, primal ``x``, objective, duals ``y`` (see the module
            docstring for the sign convention), iterations, time.

        Raises
        ------
        TypeError
            If the data are not numeric.
        ValueError
            If the shapes do not match, an entry is not finite, or ``basic``
            is not an (n,) bool array; or if a subclass's ``_solve`` returns a
            status not in `STATUSES`, iterations that are not an integer, or
            an optimal ``x`` or ``y`` of the wrong shape.
        """
        try:
            c = np.ascontiguousarray(numeric(c))
            b = np.ascontiguousarray(numeric(b))
            if isinstance(A, CSC):
                data = np.ascontiguousarray(numeric(A.data))
                A = A if data is A.data else A._replace(data=data)
                values = A.data
            else:
                A = np.ascontiguousarray(numeric(A))
                values = A
        except (TypeError, ValueError, OverflowError):
            raise TypeError("LP data c, A and b must be arrays of real numbers, not text, booleans or complex numbers "
                            "(A may be a synergrasp.lp.CSC)") from None
        if isinstance(A, CSC):
            A = _checked_csc(A)
        if A.ndim != 2 or c.shape != (A.shape[1],) or b.shape != (A.shape[0],):
            raise ValueError(
                f"LP data of mismatched shapes: c {c.shape}, A {A.shape}, b {b.shape}; "
                "expected c (n,), A (m, n), b (m,)"
            )
        # any NaN or inf makes the sum non-finite (finite entries can only overflow it: then check each)
        with np.errstate(over="ignore", invalid="ignore"):  # finite entries near 1e308 may overflow the sum
            total = c.sum() + values.sum() + b.sum()
        if not math.isfinite(total) and not (
            np.isfinite(c).all() and np.isfinite(values).all() and np.isfinite(b).all()
        ):
            raise ValueError("LP data contains NaN or inf; check the geometry passed in")
        hint = None if basic is None else _hint(basic, A.shape[1])
        self.calls += 1
        m, n = A.shape
        start = time.perf_counter()
        try:
            if m == 0 or n == 0:  # no rows or no columns: answered here (solvers fail on some of these)
                status, x, y, iterations, message = _trivial(c, b)
            elif hint is not None and self.basis_hints:
                status, x, y, iterations, message = self._solve(c, A, b, basic=hint)
            else:
                status, x, y, iterations, message = self._solve(c, A, b)
            if status == "unbounded":  # an interior-point solver may say so of an LP with no feasible point at all
                status, message = self._unbounded_or_infeasible(c, A, b, message)
        except (KeyboardInterrupt, SystemExit, GeneratorExit):
            raise
        except BaseException as exc:  # a solver's own failure becomes a status (a Rust panic is a BaseException)
            status, x, y, iterations, message = "failed", None, None, -1, f"{type(exc).__name__}: {exc}"
        elapsed = time.perf_counter() - start
        if status not in STATUSES or not isinstance(iterations, (int, np.integer)):
            raise ValueError(f"backend {self.name!r}: _solve returned status {status!r} and iterations {iterations!r}; "
                             f"the status must be one of {STATUSES} and the iterations an integer (-1 if unknown)")
        if status == "optimal":
            x = np.asarray(x, dtype=float)
            y = np.asarray(y, dtype=float)
            if x.shape != (n,) or y.shape != (m,):
                raise ValueError(f"backend {self.name!r}: _solve returned x of shape {x.shape} and y of shape {y.shape} "
                                 f"for an LP of {m} rows and {n} columns; they must be ({n},) and ({m},)")
            if not b.any() and _top(x) <= HOMOGENEOUS_ZERO:  # x = 0 is exact: what an interior point approaches
                x = np.zeros(n)
            objective = float(c @ x)
            if verify or message in self.inaccurate:
                gaps = optimality_gaps(c, A, b, x, y)
                if max(gaps.values()) > VERIFY_TOL:
                    status, message = "failed", (
                        f"{self.name} called it optimal ({message}), but its answer is off by "
                        + ", ".join(f"{v:.2g} ({k})" for k, v in gaps.items() if v > VERIFY_TOL)
                        + " relative to the data's scale: the LP is badly scaled for the solver's tolerances; "
                        "rescale its rows, columns or costs")
                    x, y, objective = np.full(n, np.nan), np.full(m, np.nan), float("nan")
        else:
            x, y, objective = np.full(n, np.nan), np.full(m, np.nan), float("nan")
        return LPSolution(status, x, objective, y, int(iterations), elapsed, self.name, message)

    def _unbounded_or_infeasible(self, c, A, b, message):
        """The status of an LP the solver called unbounded: ``"infeasible"`` if it has no feasible point (the LP
        without costs is infeasible), else ``"unbounded"``; and the message.

        A primal-dual method that finds the dual infeasible may report it whether or not the primal is feasible
        (Clarabel's ``DualInfeasible`` for ``0 = 1``).
        """
        feasibility = self._solve(np.zeros_like(c), A, b)
        if feasibility[0] == "infeasible":
            return "infeasible", f"{message}, and without its costs the LP is infeasible ({feasibility[4]})"
        return "unbounded", message

    def forget(self) -> None:
        """Drop what earlier solves keep for later ones (warm starts, models updated in place).

        The solves after it go as those of a new instance: a plan calls it
        first, so that its result does not depend on the LPs solved before
        it. The base class keeps nothing.
        """

    def _solve(self, c, A, b):  # pragma: no cover - abstract
        raise NotImplementedError


def _trivial(c, b):
    """``_solve``'s answer to an LP without rows (x >= 0 alone) or without columns (0 == b)."""
    m, n = len(b), len(c)
    if n == 0:
        if np.any(b != 0.0):
            return "infeasible", None, None, 0, "no columns: A @ x == b needs b == 0"
        return "optimal", np.zeros(0), np.zeros(m), 0, "no columns: x is empty"
    if np.any(c < 0.0):
        return "unbounded", None, None, 0, "no rows: a negative cost lowers the objective without bound"
    return "optimal", np.zeros(n), np.zeros(0), 0, "no rows: x = 0"


#: Largest relative gap (`optimality_gaps`) of an answer `Backend.solve` calls optimal.
VERIFY_TOL = 1e-6
#: An optimal answer of an LP with ``b == 0`` whose ``x`` has no entry larger than this is returned as ``x = 0``:
#: its exact optimum, which an interior-point solver approaches to round-off (1e-24 from Clarabel), and which no
#: scale of the data can judge an ``x`` of round-off against (the LP is unchanged when ``x`` is scaled).
HOMOGENEOUS_ZERO = 1e-9


def optimality_gaps(c, A, b, x, y) -> dict:
    """How far ``x`` and ``y`` are from optimal for ``min c @ x, A @ x == b, x >= 0``, relative to the data's scale.

    Parameters
    ----------
    c : (n,) float
    A : (m, n) float ndarray or CSC
    b : (m,) float
    x : (n,) float
    y : (m,) float
        Duals, ``c - A.T @ y >= 0`` at the optimum.

    Returns
    -------
    dict
        ``"rows"``: the largest ``|A @ x - b|``, over the largest of ``|b|``
        and ``|A_rj x_j|``; ``"bounds"``: the most negative ``x``, over the
        largest ``|x|``; ``"reduced costs"``: the most negative ``c - A.T @ y``,
        over the largest of ``|c|`` and ``|A_rj y_r|``; ``"gap"``:
        ``|c @ x - b @ y|`` over the larger of ``max|c| max|x|`` and
        ``max|b| max|y|``. 0 for an exact optimum. Without costs (``c == 0``)
        every feasible ``x`` is optimal: the last two are 0, whatever ``y``.

    Examples
    --------
    >>> optimality_gaps(np.array([1.0]), np.array([[1.0]]), np.array([1e21]), np.array([1e19]), np.array([1.0]))["rows"]
    0.99
    """
    if not c.any():  # a feasibility problem: y = 0 is its dual, and an interior-point y of round-off says nothing
        y = np.zeros_like(y)
    if isinstance(A, CSC):
        cols = np.repeat(np.arange(A.shape[1]), np.diff(A.indptr))
        ax_terms = A.data * x[cols]
        ax = np.bincount(A.indices, weights=ax_terms, minlength=A.shape[0])
        aty_terms = A.data * y[A.indices]
        aty = np.bincount(cols, weights=aty_terms, minlength=A.shape[1])
    else:
        ax_terms, aty_terms = A * x, A * y[:, None]
        ax, aty = ax_terms.sum(axis=1), aty_terms.sum(axis=0)

    def ratio(value, *scales):
        scale = max(map(_top, scales))
        return float(value) / scale if scale > 0 else (0.0 if value == 0 else math.inf)

    reduced = c - aty
    return {
        "rows": ratio(_top(ax - b), b, ax_terms),
        "bounds": ratio(max(-float(x.min()), 0.0) if len(x) else 0.0, x),
        "reduced costs": ratio(max(-float(reduced.min()), 0.0) if len(c) else 0.0, c, aty_terms),
        "gap": ratio(abs(float(c @ x) - float(b @ y)), _top(c) * _top(x), _top(b) * _top(y)),
    }


def _top(v) -> float:
    """The largest magnitude of an array, 0 if it is empty."""
    return float(np.abs(v).max()) if np.size(v) else 0.0


def _hint(basic, n):
    """The ``basic`` argument of `Backend.solve` as an (n,) bool array."""
    hint = np.asarray(basic)
    if hint.shape != (n,) or hint.dtype != bool:
        raise ValueError(f"basic must be an ({n},) bool array naming the columns to start basic, got {hint.dtype} {hint.shape}")
    return hint


@kernel
def _well_formed(indptr, indices, m):
    """Whether ``indptr`` runs from 0 to ``len(indices)`` without decreasing and every index is in ``[0, m)``."""
    if indptr[0] != 0 or indptr[-1] != len(indices):
        return False
    for j in range(len(indptr) - 1):
        if indptr[j + 1] < indptr[j]:
            return False
    for i in indices:
        if i < 0 or i >= m:
            return False
    return True


def _checked_csc(A: "CSC") -> "CSC":
    """``A`` (float ``data``) with int32 indices, refused (ValueError) unless it is a well-formed column-compressed
    (m, n) matrix: the backends index with it unchecked."""
    indptr, indices, shape = A.indptr, A.indices, A.shape
    if not (isinstance(indptr, np.ndarray) and isinstance(indices, np.ndarray)):
        indptr, indices = np.asarray(indptr), np.asarray(indices)
    if len(shape) != 2 or not all(isinstance(k, (int, np.integer)) and k >= 0 for k in shape) \
            or indptr.dtype.kind not in "iu" or indices.dtype.kind not in "iu":
        raise ValueError(f"a CSC matrix needs integer indptr and indices and a shape (m, n) of integers >= 0, got "
                         f"indptr {indptr.dtype}, indices {indices.dtype}, shape {A.shape!r}")
    m, n = shape
    nnz = len(A.data)
    if indptr.dtype != np.int32 or indices.dtype != np.int32:  # lossless (uint64 beyond 2^63 reads < 0: refused)
        indptr, indices = indptr.astype(np.int64), indices.astype(np.int64)
    if indptr.shape != (n + 1,) or indices.shape != (nnz,) or not _well_formed(indptr, indices, m):
        raise ValueError(f"malformed CSC matrix of shape {tuple(shape)}: indptr must be n + 1 = {n + 1} non-decreasing "
                         f"offsets from 0 to the {nnz} entries, and indices that many row numbers from 0 to {m - 1}; "
                         f"got indptr of shape {indptr.shape} from {indptr[0] if len(indptr) else None} to "
                         f"{indptr[-1] if len(indptr) else None}, indices of shape {indices.shape}"
                         + (f" from {indices.min()} to {indices.max()}" if len(indices) else ""))
    if indptr.dtype == np.int32 and indices.dtype == np.int32 and indptr is A.indptr and indices is A.indices:
        return A
    return CSC(indptr.astype(np.int32), indices.astype(np.int32), A.data, (int(m), int(n)))


class CSC(NamedTuple):
    """A minimal column-compressed matrix (no copies; `Backend.solve` checks that it is well formed).

    Attributes
    ----------
    indptr : (n+1,) int32
        Column start offsets into ``indices`` and ``data``.
    indices : (nnz,) int32
        Row index of each entry.
    data : (nnz,) float
        Entry values.
    shape : (int, int)
        ``(m, n)``.

    Examples
    --------
    >>> A = CSC(np.array([0, 1, 2], dtype=np.int32), np.array([0, 0], dtype=np.int32), np.array([2.0, 3.0]), (1, 2))
    >>> A.toarray()
    array([[2., 3.]])
    """

    indptr: np.ndarray
    indices: np.ndarray
    data: np.ndarray
    shape: tuple

    @property
    def ndim(self) -> int:
        return 2

    def toarray(self) -> np.ndarray:
        """The dense (m, n) array."""
        out = np.zeros(self.shape)
        columns = np.repeat(np.arange(self.shape[1]), np.diff(self.indptr))
        np.add.at(out, (self.indices, columns), self.data)
        return out

    def rmatvec(self, y) -> np.ndarray:
        """``A.T @ y`` as an (n,) array."""
        columns = np.repeat(np.arange(self.shape[1]), np.diff(self.indptr))
        return np.bincount(columns, weights=self.data * y[self.indices], minlength=self.shape[1])


def csc_arrays(A):
    """Column-compressed arrays ``(indptr, indices, data)`` of a dense or CSC matrix.

    Parameters
    ----------
    A : (m, n) float ndarray or CSC

    Returns
    -------
    indptr : (n+1,) int32
    indices : (nnz,) int32
    data : (nnz,) float
    """
    if isinstance(A, CSC):
        return A.indptr, A.indices, A.data
    At = A.T
    nonzero = At != 0
    indptr = np.zeros(A.shape[1] + 1, dtype=np.int32)
    np.cumsum(nonzero.sum(axis=1), out=indptr[1:])
    return indptr, np.nonzero(nonzero)[1].astype(np.int32), At[nonzero]
