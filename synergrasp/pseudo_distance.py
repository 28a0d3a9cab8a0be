"""Pseudo-distance between convex polytopes (paper Eqs. 1-3) with dual-based derivatives.

For point sets A = conv{a_i} and B = conv{b_j} in R^d and a simplex
Q = conv{q_k} (k = 1..d+1) containing the origin:

* separation (Eq. 1): ``d_s = min sum rho  s.t.  sum rho_k q_k = sum beta_j b_j - sum alpha_i a_i``,
  i.e. the smallest gauge_Q(b - a) over a in A, b in B (>= 0);
* penetration (Eqs. 2-3), used when d_s = 0:
  ``d_p = max_k d_p(k)``, ``d_p(k) = min -rho  s.t.  rho q_k = sum alpha_i a_i - sum beta_j b_j`` (<= 0).

The pseudo-distance is d_s when positive, else d_p: positive apart, 0 touching,
negative overlapping, continuous throughout. Note the paper's order: separation
measures b - a, penetration a - b; the gauge of a simplex is not symmetric.

Derivatives come from the LP duals: for ``min c@x s.t. G x = h, x >= 0`` with a
unique optimum, ``d value / d G[r, c] = -y_r x_c`` (``y = d value / d h``), so
``d d_s / d a_i = -alpha_i y`` and ``d d_s / d b_j = beta_j y`` (y: the duals of the
d coordinate rows), and with opposite signs for the active penetration LP.
Where the LP is degenerate (non-unique primal or dual, or several k attaining
the max) the derivative does not exist; ``degenerate`` is set, and a simplex
backend's vertex gives a valid one-sided choice (an interior-point backend's
centre of the optimal face need not: docs/concepts/pseudo-distance.md).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache
from typing import NamedTuple

import numpy as np

from . import lp
from ._checks import as_points
from .tolerances import DEGENERACY_TOL, VALUE_TOL

#: Largest dimension d accepted (the penetration LP has (d+1)(d+2) rows).
MAX_DIM = 1000
#: Most nonzeros of the penetration LP (d+1 blocks of d + (na+nb)(d+1) entries each) that are built: about
#: 0.2 GB with its indices, and tens of seconds to solve; larger sets are refused before anything is built.
MAX_LP_ENTRIES = 10_000_000
#: Point sets are solved translated to the centre of their common bounding box (the
#: pseudo-distance is translation invariant: far from the origin, the coordinates' magnitude
#: would swamp the LPs' tolerances); those whose spread (half the largest side of that box)
#: falls outside this range are also divided by it, and the value scaled back (the
#: pseudo-distance scales with the data, its gradients do not change).
SCALE_RANGE = (1e-3, 1e6)


@lru_cache(maxsize=None)
def _regular_simplex(d: int) -> np.ndarray:
    # Helmert basis of the sum-zero subspace of R^(d+1): deterministic orientation.
    helmert = np.zeros((d, d + 1))
    for j in range(1, d + 1):
        helmert[j - 1, :j] = 1.0
        helmert[j - 1, j] = -j
        helmert[j - 1] /= np.sqrt(j * (j + 1))
    vertices = helmert.T * np.sqrt((d + 1) / d)
    vertices.setflags(write=False)
    return vertices


def regular_simplex(d: int) -> np.ndarray:
    """The default simplex Q: regular, centred at the origin, circumradius 1.

    Parameters
    ----------
    d : int
        Dimension, ``d >= 2``.

    Returns
    -------
    (d+1, d) float ndarray
        Vertices ``q_k`` with ``|q_k| = 1`` and ``q_i . q_k = -1/d`` for ``i != k``.

    Examples
    --------
    >>> Q = regular_simplex(3)
    >>> Q.shape, bool(np.allclose(np.linalg.norm(Q, axis=1), 1.0))
    ((4, 3), True)
    """
    if isinstance(d, bool) or not isinstance(d, (int, np.integer)) or not 2 <= d <= MAX_DIM:
        raise ValueError(f"d must be an integer from 2 to {MAX_DIM}, got {d!r}")
    return _regular_simplex(int(d)).copy()


#: Largest condition number of a user simplex's vertices (at unit size, with a row of ones): a regular
#: simplex has about 1.7; one flattened to 1e-7 of its size has 1.7e7, where the solvers' answers part by
#: 2e-7 of the value, and at 1e-9 they call the always-feasible separation LP infeasible.
MAX_SIMPLEX_CONDITION = 1e7


def check_simplex(simplex, d: int) -> np.ndarray:
    """Validate a user simplex: shape (d+1, d), finite, origin strictly inside.

    Returns
    -------
    (d+1, d) float ndarray

    Raises
    ------
    ValueError
        If the shape is wrong, the simplex is degenerate or the origin is not
        strictly inside it.
    """
    Q = as_points(simplex, "simplex", dim=d)
    if Q.shape[0] != d + 1:
        raise ValueError(f"simplex must have d+1 = {d + 1} vertices in R^{d}, got {Q.shape[0]}")
    top = float(np.abs(Q).max())
    M = np.vstack([Q.T / (top if top > 0 else 1.0), np.ones(d + 1)])  # at unit size: the test does not depend on Q's
    cond = np.linalg.cond(M)
    if cond > MAX_SIMPLEX_CONDITION:
        raise ValueError(f"simplex is degenerate or nearly so: its vertices (scaled to unit size) have a condition "
                         f"number of {cond:.3g}, above {MAX_SIMPLEX_CONDITION:g} (they lie in or near a hyperplane), "
                         "and the LPs' tolerances cannot resolve so flat a gauge. Use a rounder simplex "
                         "(sg.regular_simplex(d) is the default)")
    barycentric = np.linalg.solve(M, np.r_[np.zeros(d), 1.0])
    if barycentric.min() <= 1e-12:
        raise ValueError(
            "simplex must contain the origin strictly inside; its barycentric coordinates "
            f"of the origin are {np.round(barycentric, 6).tolist()}. Centre it at the origin."
        )
    return Q


@dataclass(frozen=True)
class PseudoDistance:
    """Result of :func:`pseudo_distance`.

    Attributes
    ----------
    value : float
        Pseudo-distance: > 0 separated, 0 touching, < 0 overlapping.
    kind : str
        ``"separation"`` (Eq. 1) or ``"penetration"`` (Eqs. 2-3).
    grad_a : (na, d) float
        d value / d a_i.
    grad_b : (nb, d) float
        d value / d b_j.
    simplex : (d+1, d) float
        The simplex Q used.
    degenerate : bool
        True when the derivative does not exist (non-unique LP solution, or a
        tie between penetration directions); the gradients are then a valid
        one-sided choice with a simplex backend (native, HiGHS), and the
        gradient of the centre of the optimal face, which need not be one,
        with an interior-point backend (Clarabel, cvxpy).
    lp_solves : int
        Number of solver calls made (1 or 2; up to 4 for sets that touch to
        round-off). The d+1 penetration LPs of Eq. 3
        are independent and solved together as one block-diagonal LP. They are
        all feasible exactly when the value of Eq. 1 is 0, so the regime of the
        previous call with the same shapes is tried first (the result does not
        depend on the order).
    alpha : (na,) float
        Optimal weights of A's vertices.
    beta : (nb,) float
        Optimal weights of B's vertices.
    point_a, point_b : (d,) float
        Witness points ``sum alpha_i a_i`` and ``sum beta_j b_j``.
    normal_b : (d,) float
        Unit inward normal of B at ``point_b`` (the supporting hyperplane of the
        LP dual): moving B along ``normal_b`` (away from A) increases the
        value, at the rate ``grad_b.sum(axis=0) @ normal_b`` > 0.
    active : int
        Index k of the active penetration direction (-1 for separation).
    """

    value: float
    kind: str
    grad_a: np.ndarray
    grad_b: np.ndarray
    simplex: np.ndarray
    degenerate: bool
    lp_solves: int
    alpha: np.ndarray
    beta: np.ndarray
    point_a: np.ndarray
    point_b: np.ndarray
    normal_b: np.ndarray
    active: int


class Optimum(NamedTuple):
    """The LP optimum behind a pseudo-distance (:func:`optimum`), without derived arrays.

    ``dual`` (d,) is signed so that ``grad_a = -alpha[:, None] * dual`` and
    ``grad_b = beta[:, None] * dual``; the other fields are those of :class:`PseudoDistance`.
    """

    value: float
    kind: str
    degenerate: bool
    lp_solves: int
    alpha: np.ndarray
    beta: np.ndarray
    dual: np.ndarray
    active: int


def _degenerate(x, reduced, m, columns=None) -> bool:
    """Not a vertex optimum with exactly m positive primal and m zero reduced costs.

    ``columns`` (m, n) float, optional: the LP's matrix, for a solution that need not be a vertex (an
    interior-point solver's): its m positive columns must then also be independent (the weight of a point
    repeated in A or B, split between its copies, is not a vertex either).
    """
    positive = x > DEGENERACY_TOL * max(1.0, float(np.abs(x).max()))
    tight = np.count_nonzero(np.abs(reduced) <= DEGENERACY_TOL)
    if np.count_nonzero(positive) != m or tight != m:
        return True
    return columns is not None and np.linalg.matrix_rank(columns[:, positive]) < m


def _readonly(*arrays):
    for a in arrays:
        a.setflags(write=False)
    return arrays


class _Layout:
    """Everything about the Eq. 1 and stacked Eq. 3 LPs that depends only on (na, nb, d).

    Column rho_k has d entries (the coordinate rows); column alpha_i has d + 1
    (coordinates, then the row ``sum alpha = 1``); column beta_j has d + 1
    (coordinates, then the row ``sum beta = 1``). Built once per shape
    (:func:`_layout`), all arrays read-only.

    Attributes
    ----------
    sep_rows, sep_ptr : int32 arrays
        CSC row indices and column pointers of the separation matrix.
    sep_cols : int array
        Column of each stored entry (for the reduced costs).
    sep_c, sep_h : float arrays
        Costs ``[1 (nq), 0 (na + nb)]`` and right-hand side ``[0 (d), 1, 1]``.
    pen_rows, pen_ptr : int32 arrays
        The same for the block-diagonal stack of the nq penetration LPs.
    pen_c, pen_h : float arrays
        Costs ``[-1, 0 ...]`` and right-hand side ``[0 (d), 1, 1]`` per block.
    block_rows, block_cols : int arrays
        Row and column of each stored entry of one penetration block, relative to the block.
    block_c : float array
        Costs of one block.
    """

    def __init__(self, na, nb, d):
        nq, mk = d + 1, d + 2
        coordinate = np.arange(d)
        weights = np.concatenate([np.tile(np.append(coordinate, d), na), np.tile(np.append(coordinate, d + 1), nb)])
        counts = np.full(na + nb, d + 1)
        self.sep_rows = np.concatenate([np.tile(coordinate, nq), weights]).astype(np.int32)
        sep_counts = np.concatenate([np.full(nq, d), counts])
        self.sep_ptr = np.concatenate([[0], np.cumsum(sep_counts)]).astype(np.int32)
        self.sep_cols = np.repeat(np.arange(nq + na + nb), sep_counts)
        self.sep_c = np.zeros(nq + na + nb)
        self.sep_c[:nq] = 1.0
        self.sep_h = np.zeros(mk)
        self.sep_h[d:] = 1.0
        block = np.concatenate([coordinate, weights])
        self.pen_rows = (block[None, :] + mk * np.arange(nq)[:, None]).ravel().astype(np.int32)
        block_counts = np.concatenate([[d], counts])
        self.pen_ptr = np.concatenate([[0], np.cumsum(np.tile(block_counts, nq))]).astype(np.int32)
        nk = 1 + na + nb
        self.block_rows = block
        self.block_cols = np.repeat(np.arange(nk), block_counts)
        self.block_c = np.zeros(nk)
        self.block_c[0] = -1.0
        self.pen_c = np.tile(self.block_c, nq)
        self.pen_h = np.tile(self.sep_h, nq)
        self.overlapped_last = False  # which regime the last call of this shape was in
        _readonly(
            self.sep_rows, self.sep_ptr, self.sep_cols, self.sep_c, self.sep_h, self.pen_rows, self.pen_ptr,
            self.block_rows, self.block_cols, self.block_c, self.pen_c, self.pen_h,
        )


@lru_cache(maxsize=256)
def _layout(na: int, nb: int, d: int) -> _Layout:
    return _Layout(na, nb, d)


@lru_cache(maxsize=None)
def _min_vertex_norm(d: int) -> float:
    return float(np.linalg.norm(_regular_simplex(d), axis=1).min())


def _weight_data(A, B, sign):
    """Entries of the alpha columns (``sign * a_i``, 1) and beta columns (``-sign * b_j``, 1)."""
    (na, d), nb = A.shape, len(B)
    out = np.empty((na + nb, d + 1))
    np.multiply(A, sign, out=out[:na, :d])
    np.multiply(B, -sign, out=out[na:, :d])
    out[:, d] = 1.0
    return out.ravel()


def _require_optimal(sol, what: str):
    if not sol.optimal:
        raise lp.LPError(
            f"the {what} LP was not solved: backend {sol.backend!r} returned status "
            f"{sol.status!r} ({sol.message}). Try another backend (sg.lp.available_backends())."
        )


def _unit(v):
    n = math.sqrt(float(v @ v))
    return v / n if n > 0 else v


def reset_regime_memory() -> None:
    """Forget which regime (apart or overlapping) the last call of each LP shape ended in.

    `pseudo_distance` solves first the LP of the regime its last call with
    the same shapes of ``A`` and ``B`` ended in, and the other only when
    needed. Both orders give the value up to round-off, not bit for bit (the
    backend's warm starts differ). After this call, with a new backend instance
    (or one told to `Backend.forget` its warm starts), the next calls behave as
    in a new process: `synergrasp.plan` does both first, so that a plan does not
    depend on what its process solved before.

    Examples
    --------
    >>> import numpy as np
    >>> from synergrasp.lp.highs import HighsBackend
    >>> A, B = np.eye(3), np.eye(3) + 5.0
    >>> first = pseudo_distance(A, B, backend=HighsBackend()).value
    >>> reset_regime_memory()  # and a new backend instance: no warm start carried over
    >>> pseudo_distance(A, B, backend=HighsBackend()).value == first
    True
    """
    _layout.cache_clear()


def pseudo_distance(A, B, *, simplex=None, backend="native") -> PseudoDistance:
    """Pseudo-distance between conv(A) and conv(B), with gradients (paper Eqs. 1-3).

    Parameters
    ----------
    A : (na, d) array_like
        Vertices of the first set (any points; their convex hull is used).
    B : (nb, d) array_like
        Vertices of the second set, same dimension d >= 2.
    simplex : (d+1, d) array_like, optional
        The simplex Q, origin strictly inside; default ``regular_simplex(d)``.
        Scaling Q by c divides every value by c.
    backend : str or synergrasp.lp.Backend
        LP backend name (see ``synergrasp.lp.available_backends()``).

    Returns
    -------
    PseudoDistance
        ``value``, ``kind``, ``grad_a`` (na, d), ``grad_b`` (nb, d), ``simplex``,
        ``degenerate``, ``lp_solves`` and the witness data.

    Raises
    ------
    ValueError
        NaN/inf, wrong shapes, mismatched dimensions, empty sets, a simplex that
        does not contain the origin, an unknown backend.
    synergrasp.lp.LPError
        If the backend fails to solve an LP (its status is in the message).

    Notes
    -----
    The LPs are solved to a tolerance relative to the data: a gap or an
    overlap smaller than about 1e-8 times the sets' extent (their
    coordinates' magnitude) is within round-off and can read as touching, a
    value of 0 (segments 1e10 long whose ends are 1 apart touch), depending
    on the backend and on its warm start.

    Examples
    --------
    Two points 3 apart, regular simplex in the plane: the gauge of x = b - a
    is -2 min_k q_k . x, so 3 when x points at a vertex of Q (here (0, -3))
    and 3 sqrt(3) = 5.196 when x points at the middle of an edge ((3, 0)).

    >>> r = pseudo_distance([[0.0, 0.0]], [[0.0, -3.0]])
    >>> r.kind, round(r.value, 9)
    ('separation', 3.0)
    >>> round(pseudo_distance([[0.0, 0.0]], [[3.0, 0.0]]).value, 3)
    5.196
    """
    A = as_points(A, "A", min_dim=2)
    B = as_points(B, "B", dim=A.shape[1])
    d = A.shape[1]
    if d > MAX_DIM:
        raise ValueError(f"A and B have points of dimension {d}; at most {MAX_DIM} is supported")
    Q = _regular_simplex(d) if simplex is None else check_simplex(simplex, d)
    # a given simplex is solved at about unit size, divided by a power of two (exactly), for the LPs' tolerances:
    # the gauge of c Q is that of Q divided by c
    size = 1.0 if simplex is None else 2.0 ** round(math.log2(float(np.abs(Q).max())))
    given = None if simplex is None else Q / size  # optimum's own default needs no check
    lo, hi = np.minimum(A.min(axis=0), B.min(axis=0)), np.maximum(A.max(axis=0), B.max(axis=0))
    centre = 0.5 * lo + 0.5 * hi  # the bounding box's centre (no overflow near the largest floats)
    spread = float(np.max(0.5 * hi - 0.5 * lo))
    low, high = SCALE_RANGE
    unit = spread if spread > high or 0.0 < spread < low else 1.0
    opt = optimum((A - centre) / unit, (B - centre) / unit, simplex=given, backend=backend, checked=True)
    opt = opt._replace(value=opt.value * unit)
    with np.errstate(over="ignore"):
        value = opt.value / size
    if not np.isfinite(value):
        raise ValueError(f"the pseudo-distance of A and B overflows the float range (coordinates up to "
                         f"{max(np.abs(lo).max(), np.abs(hi).max()):.3g}"
                         + ("" if simplex is None else f", simplex of size {size:.3g}") + "); rescale the data")
    alpha, beta, dual = opt.alpha, opt.beta, opt.dual / size
    return PseudoDistance(
        value=value,
        kind=opt.kind,
        grad_a=alpha[:, None] * -dual,
        grad_b=beta[:, None] * dual,
        simplex=Q,
        degenerate=opt.degenerate,
        lp_solves=opt.lp_solves,
        alpha=alpha,
        beta=beta,
        point_a=alpha @ A,
        point_b=beta @ B,
        normal_b=_unit(opt.dual),  # (the direction of the duals before the simplex's size divides them)
        active=opt.active,
    )


def lp_entries(na: int, nb: int, d: int) -> int:
    """Nonzeros of the penetration LP of ``na`` and ``nb`` points in ``d`` dimensions (compared with `MAX_LP_ENTRIES`).

    Examples
    --------
    >>> lp_entries(40, 1, 6)   # 5 contacts of 8 cone edges against the origin of wrench space
    2051
    """
    return (d + 1) * (d + (na + nb) * (d + 1))


def optimum(A, B, *, simplex=None, backend="native", checked=False) -> Optimum:
    """The LP optimum behind :func:`pseudo_distance`: value, weights and duals, no derived arrays.

    What :func:`pseudo_distance` and :func:`synergrasp.q_distance` build their
    results from. Its gradients are ``grad_a = -alpha[:, None] * dual`` and
    ``grad_b = beta[:, None] * dual``.

    Parameters
    ----------
    A : (na, d) array_like
    B : (nb, d) array_like
    simplex : (d+1, d) array_like, optional
        Default ``regular_simplex(d)``.
    backend : str or synergrasp.lp.Backend
    checked : bool
        ``A``, ``B`` and ``simplex`` are already validated finite float
        arrays, scaled as :func:`pseudo_distance` scales them (a caller that
        checked them skips the checks, and the LP answers' verification,
        `synergrasp.lp.Backend.solve`'s ``verify``).

    Returns
    -------
    Optimum

    Raises
    ------
    ValueError, synergrasp.lp.LPError
        As :func:`pseudo_distance`.

    Notes
    -----
    The data are solved as given: :func:`pseudo_distance` first translates
    the point sets to their bounding box's centre, and rescales those whose
    size falls outside ``SCALE_RANGE``.

    Examples
    --------
    >>> opt = optimum([[0.0, 0.0]], [[0.0, -3.0]])
    >>> opt.kind, round(opt.value, 9), opt.alpha.tolist(), opt.beta.tolist()
    ('separation', 3.0, [1.0], [1.0])
    """
    if not checked:
        A = as_points(A, "A", min_dim=2)
        B = as_points(B, "B", dim=A.shape[1])
        if A.shape[1] > MAX_DIM:
            raise ValueError(f"A and B have points of dimension {A.shape[1]}; at most {MAX_DIM} is supported")
    d = A.shape[1]
    entries = lp_entries(len(A), len(B), d)
    if entries > MAX_LP_ENTRIES:
        raise ValueError(f"{len(A)} + {len(B)} points in {d} dimensions make a penetration LP of {entries:.3g} nonzeros, "
                         f"more than the {MAX_LP_ENTRIES:.0e} synergrasp builds ({d + 1} blocks, each of all the points); "
                         "use fewer points (their hulls' vertices are enough) or fewer dimensions")
    if simplex is None:
        Q, qmin = _regular_simplex(d), _min_vertex_norm(d)
    else:
        Q = simplex if checked else check_simplex(simplex, d)
        qmin = float(np.linalg.norm(Q, axis=1).min())
    solver = lp.get_backend(backend)
    coord_scale = 1.0 + max(np.abs(A).max(), np.abs(B).max())
    zero = VALUE_TOL * coord_scale * d / qmin
    lay = _layout(len(A), len(B), d)

    # The penetration LPs (Eq. 3) are all feasible exactly when the sets overlap or touch
    # (the q_k positively span R^d), which is when Eq. 1 gives 0. So the order of the two solves
    # does not change the result; the regime of the previous call of the same shape goes first.
    solves = 0
    result = None
    verify = not checked  # the library's callers pass data they scaled (pseudo_distance, q_distance)
    if lay.overlapped_last:
        solves += 1
        result = _penetration(A, B, Q, lay, solver, zero, solves, strict=False, verify=verify)
    if result is None:
        solves += 1
        result = _separation(A, B, Q, lay, solver, zero, solves, verify=verify)
        if result is None:  # Eq. 1 gave 0: the sets touch or overlap
            solves += 1
            result = _penetration(A, B, Q, lay, solver, zero, solves, strict=True, verify=verify)
        if result is None:  # Eq. 1 within round-off of 0 but Eq. 3 infeasible within tolerance: touching
            solves += 1
            result = _separation(A, B, Q, lay, solver, zero, solves, touching=True, verify=verify)
    lay.overlapped_last = result.kind == "penetration"
    return result


def _separation(A, B, Q, lay, solver, zero, solves, touching=False, verify=True):
    """Eq. 1; None when its value is 0 (the sets touch or overlap), unless ``touching``."""
    (na, d), nb, nq = A.shape, len(B), len(Q)
    # x = [rho (nq), alpha (na), beta (nb)]; rows: d coordinates, sum alpha, sum beta
    data = np.empty(nq * d + (na + nb) * (d + 1))
    data[: nq * d] = Q.ravel()
    data[nq * d :] = _weight_data(A, B, 1.0)
    G = lp.CSC(lay.sep_ptr, lay.sep_rows, data, (d + 2, nq + na + nb))
    sol = solver.solve(lay.sep_c, G, lay.sep_h, verify=verify)
    _require_optimal(sol, "separation (Eq. 1)")
    if sol.objective <= zero and not touching:
        return None
    x, y = sol.x, sol.y
    reduced = lay.sep_c - np.bincount(lay.sep_cols, weights=data * y[lay.sep_rows], minlength=len(lay.sep_c))
    columns = None if solver.vertex_solutions else G.toarray()
    return Optimum(sol.objective, "separation", _degenerate(x, reduced, d + 2, columns), solves, x[nq : nq + na],
                    x[nq + na :], y[:d], -1)


def _penetration(A, B, Q, lay, solver, zero, solves, strict=True, verify=True):
    """Eqs. 2-3 (the nq LPs stacked block-diagonally); None when infeasible (the sets are apart).

    Tried first (``strict=False``), any status but optimal means "not this regime": a
    simplex warm-started from a feasible neighbour may stop short of proving infeasibility.
    """
    (na, d), nb, nq = A.shape, len(B), len(Q)
    # block k: x = [rho, alpha (na), beta (nb)], rho q_k - sum alpha a + sum beta b = 0
    nk, mk = 1 + na + nb, d + 2
    blocks = np.empty((nq, d + (na + nb) * (d + 1)))
    blocks[:, :d], blocks[:, d:] = Q, _weight_data(A, B, -1.0)
    Gp = lp.CSC(lay.pen_ptr, lay.pen_rows, blocks.ravel(), (nq * mk, nq * nk))
    psol = solver.solve(lay.pen_c, Gp, lay.pen_h, verify=verify)
    if psol.status == "infeasible" or (not strict and not psol.optimal):
        return None
    _require_optimal(psol, "penetration (Eq. 3)")
    values = -np.maximum(psol.x[::nk], 0.0)  # rho >= 0: a solver's round-off below 0 is not a positive depth
    k = int(values.argmax())
    x, y = psol.x[k * nk : (k + 1) * nk], psol.y[k * mk : (k + 1) * mk]
    ties = np.count_nonzero(values >= values[k] - zero) > 1
    reduced = lay.block_c - np.bincount(lay.block_cols, weights=blocks[k] * y[lay.block_rows], minlength=nk)
    columns = None
    if not solver.vertex_solutions:
        columns = np.zeros((mk, nk))
        columns[lay.block_rows, lay.block_cols] = blocks[k]
    return Optimum(float(values[k]), "penetration", ties or _degenerate(x, reduced, mk, columns), solves, x[1 : 1 + na],
                    x[1 + na :], -y[:d], k)
