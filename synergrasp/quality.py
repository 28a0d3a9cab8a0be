"""Grasp quality: friction cones, contact wrenches and the Q distance (paper Eqs. 4-10).

Contact i sits at ``p_i`` with unit normal ``n_i`` pointing INTO the object.
Its linearised friction cone has the m edges

    d_ij = n_i + mu (cos t_j e1_i + sin t_j e2_i),   t_j = 2 pi j / m,

so ``d_ij . n_i = 1`` (Eq. 4), with ``(e1_i, e2_i)`` a tangent basis of ``n_i``
(e1 = normalise(a x n), a the coordinate axis least aligned with n; e2 = n x e1).
The primitive wrenches are ``w_ij = [d_ij ; (p_i - c) x d_ij / L]`` with the
object's reference point c and torque scale L, and the Q distance is the
pseudo-distance between W = conv{w_ij} and the origin of wrench space (Eqs. 9-10):
positive when the grasp is not force-closed, negative when it is, more negative
for a larger margin. Its gradients with respect to the contact points and
normals follow from the LP duals through ``w_ij(p_i, n_i)``.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import numpy as np
from scipy.spatial import ConvexHull, QhullError

from . import lp
from ._checks import as_points, as_vector, positive_scalar
from ._vectors import cross
from .pseudo_distance import _min_vertex_norm, _pseudo_distance, _regular_simplex

#: Q below minus this is force closure; closer to 0 is the boundary, within solver round-off.
FORCE_CLOSURE_TOL = 1e-9
#: Largest friction coefficient accepted (larger ones are not friction coefficients, and cone
#: edges that long leave the LP badly scaled).
MU_MAX = 1000.0
#: Most friction cone edges (sides of the linearised cone) accepted.
EDGES_MAX = 1000

_ORIGIN = np.zeros((1, 6))  # the origin of wrench space, the set the Q distance is measured to
_ORIGIN.setflags(write=False)
_SIMPLEX, _SIMPLEX_MIN_NORM = _regular_simplex(6), _min_vertex_norm(6)


def _unit_normals(normals, n_points):
    normals = as_points(normals, "normals", dim=3)
    if len(normals) != n_points:
        raise ValueError(f"normals has {len(normals)} rows but points has {n_points}; give one normal per contact")
    length = np.sqrt(np.einsum("ij,ij->i", normals, normals))
    huge = ~np.isfinite(length)  # the squares overflowed (entries beyond 1e154): divide by the largest first
    if huge.any():
        normals = normals.copy()
        biggest = np.abs(normals[huge]).max(axis=1)
        normals[huge] /= biggest[:, None]
        length[huge] = np.sqrt(np.einsum("ij,ij->i", normals[huge], normals[huge]))
        unit = normals / length[:, None]
        with np.errstate(over="ignore"):
            length[huge] *= biggest  # inf where beyond the float range: the gradient through it is 0
        return unit, length
    if length.min() < 1e-12:
        raise ValueError(f"normals has zero-length rows {np.nonzero(length < 1e-12)[0].tolist()}; each contact needs a direction")
    return normals / length[:, None], length


#: ``_AXIS_CROSS[k] @ v = e_k x v`` for the coordinate axes e_k.
_AXIS_CROSS = np.array([[[0, 0, 0], [0, 0, -1], [0, 1, 0]], [[0, 0, 1], [0, 0, 0], [-1, 0, 0]],
                        [[0, -1, 0], [1, 0, 0], [0, 0, 0]]], dtype=float)
_AXIS_CROSS.setflags(write=False)


def _frame(nhat):
    """The basis (n, e1, e2) of each contact: e1 = normalise(a x n), e2 = n x e1.

    ``a`` is the coordinate axis least aligned with n (piecewise constant).

    Returns
    -------
    basis : (3, n, 3) float
        ``basis[0] = nhat``, ``basis[1] = e1``, ``basis[2] = e2``.
    tangent : tuple
        ``(C, vnorm)`` for :func:`_basis_vjp`: ``C`` (n, 3, 3) the matrices
        ``[a]x`` of the axes and ``vnorm`` (n,) ``|a x n|``.
    """
    C = _AXIS_CROSS[np.abs(nhat).argmin(axis=1)]
    v = np.einsum("iab,ib->ia", C, nhat)
    vnorm = np.sqrt(np.einsum("ij,ij->i", v, v))
    basis = np.empty((3,) + nhat.shape)
    basis[0] = nhat
    np.divide(v, vnorm[:, None], out=basis[1])
    basis[2] = cross(nhat, basis[1])
    return basis, (C, vnorm)


def _basis_vjp(basis, C, vnorm, g1, g2):
    """Vector-Jacobian product of the tangent basis: ``(de1/dn)^T g1 + (de2/dn)^T g2``.

    With de1/dn = (I - e1 e1^T) [a]x / |a x n| and e2 = n x e1, so
    de2/dn = -[e1]x + [n]x de1/dn; ``(de1/dn)^T w = -[a]x (I - e1 e1^T) w / |a x n|``.
    """
    n_g2, e1_g2 = cross(basis[:2], g2)
    e1 = basis[1]
    w = g1 - n_g2
    w -= e1 * np.einsum("ij,ij->i", e1, w)[:, None]
    return e1_g2 - np.einsum("iab,ib->ia", C, w) / vnorm[:, None]


def _angles(edges):
    """(cos t_j, sin t_j), t_j = 2 pi j / m, for a valid edge count m."""
    if isinstance(edges, bool) or not isinstance(edges, (int, np.integer)) or not 3 <= edges <= EDGES_MAX:
        raise ValueError(f"edges must be an integer from 3 to {EDGES_MAX} (sides of the linearised friction cone), "
                         f"got {edges!r}")
    return _cos_sin(int(edges))


@lru_cache(maxsize=32)
def _cos_sin(edges):
    t = 2.0 * np.pi * np.arange(edges) / edges
    return np.cos(t), np.sin(t)


def _cone(nhat, mu, edges):
    """Cone edges as combinations of (n, e1, e2), for a validated ``mu`` and ``edges``.

    Edge j of contact i is ``sum_k M[k, j] basis[k, i]`` with
    ``M[:, j] = (1, mu cos t_j, mu sin t_j)`` and ``basis = (n, e1, e2)``.

    Returns
    -------
    M : (3, m) float
    basis : (3, n, 3) float
    tangent : tuple
        For :func:`_basis_vjp` (see :func:`_frame`).
    """
    basis, tangent = _frame(nhat)
    return _cone_matrix(float(mu), int(edges)), basis, tangent


@lru_cache(maxsize=32)
def _cone_matrix(mu, edges):
    """(3, m) read-only: column j is ``(1, mu cos t_j, mu sin t_j)``."""
    cos, sin = _cos_sin(edges)
    M = np.stack([np.ones_like(cos), mu * cos, mu * sin])
    M.setflags(write=False)
    return M


def _wrenches(M, basis, arm, L):
    """(n*m, 6) wrenches ``[d_ij ; arm_i x d_ij / L]``, contact-major."""
    frames = np.concatenate([basis, cross(arm / L, basis)], axis=2)  # (3, n, 6): [d ; arm x d / L] of n, e1, e2
    return np.einsum("kj,kia->ija", M, frames).reshape(-1, 6)


def friction_cone_edges(normals, mu=0.3, edges=8):
    """Edges of the linearised friction cones (paper Eq. 4).

    Parameters
    ----------
    normals : (n, 3) array_like
        Contact normals pointing into the object (normalised here).
    mu : float
        Coulomb friction coefficient, > 0.
    edges : int
        Number m of cone edges, >= 3.

    Returns
    -------
    (n, m, 3) float ndarray
        ``d_ij = n_i + mu (cos t_j e1_i + sin t_j e2_i)``, with ``d_ij . n_i = 1``.

    Examples
    --------
    >>> d = friction_cone_edges([[0.0, 0.0, 1.0]], mu=0.5, edges=4)
    >>> d.shape, bool(np.allclose(d[0, :, 2], 1.0))
    ((1, 4, 3), True)
    """
    normals = as_points(normals, "normals", dim=3)
    nhat, _ = _unit_normals(normals, len(normals))
    mu = positive_scalar(mu, "mu", MU_MAX)
    _angles(edges)
    M, basis, _ = _cone(nhat, mu, edges)
    return np.einsum("kj,kia->ija", M, basis)


def contact_wrenches(points, normals, mu=0.3, edges=8, center=None, torque_scale=None):
    """Primitive contact wrenches ``w_ij = [d_ij ; (p_i - c) x d_ij / L]`` (paper Eq. 7).

    Parameters
    ----------
    points : (n, 3) array_like
        Contact points (mm).
    normals : (n, 3) array_like
        Contact normals pointing into the object.
    mu : float
        Friction coefficient, > 0.
    edges : int
        Cone edges m, >= 3.
    center : (3,) array_like, optional
        Torque reference point c; default the origin.
    torque_scale : float, optional
        Torque scale L (mm); default the largest ``|p_i - c|``.

    Returns
    -------
    (n*m, 6) float ndarray
        Wrenches in contact-major order (all edges of contact 0 first).

    Examples
    --------
    >>> W = contact_wrenches([[0.0, 0.0, 40.0]], [[0.0, 0.0, -1.0]], edges=4)
    >>> W.shape
    (4, 6)
    """
    arm, nhat, _, mu, c, L = _prepare(points, normals, mu, edges, center, torque_scale)
    M, basis, _ = _cone(nhat, mu, edges)
    return _wrenches(M, basis, arm, L)


def _prepare(points, normals, mu, edges, center, torque_scale):
    """Validated inputs: lever arms ``p_i - c`` (n, 3), unit normals (n, 3) and their lengths (n,), mu, c, L."""
    points = as_points(points, "points", dim=3)
    nhat, length = _unit_normals(normals, len(points))
    mu = positive_scalar(mu, "mu", MU_MAX)
    _angles(edges)  # validated here, before any work
    c = np.zeros(3) if center is None else as_vector(center, "center", 3)
    arm = points - c
    if torque_scale is None:
        L = float(np.sqrt((arm * arm).sum(axis=1).max()))  # the largest |p_i - c|
        if L <= 0:
            raise ValueError("every contact lies at the centre, so the default torque_scale is 0; pass torque_scale")
    else:
        L = positive_scalar(torque_scale, "torque_scale")
    return arm, nhat, length, mu, c, L


def force_closure_by_hull(wrenches, tol=1e-9) -> bool:
    """Independent force-closure test: the origin strictly inside the convex hull of the wrenches.

    Uses qhull (``scipy.spatial.ConvexHull``), not an LP, so it can cross-check
    :func:`q_distance`.

    Parameters
    ----------
    wrenches : (k, 6) array_like
        Primitive contact wrenches (``contact_wrenches``).
    tol : float
        Margin by which the origin must be inside every facet plane.

    Returns
    -------
    bool
        False as well when the wrenches span less than 6 dimensions.

    Examples
    --------
    >>> t = 2 * np.pi * np.arange(3) / 3
    >>> p = 40.0 * np.c_[np.cos(t), np.sin(t), np.zeros(3)]
    >>> force_closure_by_hull(contact_wrenches(p, -p)), force_closure_by_hull(contact_wrenches(p[:2], -p[:2]))
    (True, False)
    """
    W = as_points(wrenches, "wrenches", dim=6)
    if isinstance(tol, bool) or not isinstance(tol, (int, float, np.floating, np.integer)) or not np.isfinite(tol) or tol < 0:
        raise ValueError(f"tol must be a finite number >= 0, got {tol!r}")
    try:
        hull = ConvexHull(W)
    except QhullError:
        return False
    return bool((hull.equations[:, -1] < -tol).all())


@dataclass(frozen=True)
class QDistance:
    """Result of :func:`q_distance`.

    Attributes
    ----------
    value : float
        Q distance: > 0 not force-closed, < 0 force-closed (more negative =
        larger margin; about -0.1 is a good grasp).
    grad_points : (n, 3) float
        d value / d p_i, with ``center`` and ``torque_scale`` held fixed.
    grad_normals : (n, 3) float
        d value / d n_i (through the normalisation of n_i, so orthogonal to a
        unit n_i), with ``center`` and ``torque_scale`` held fixed.
    wrenches : (n*edges, 6) float
        Primitive wrenches, contact-major.
    simplex : (7, 6) float
        The simplex Q used in wrench space.
    center : (3,) float
        Torque reference point c.
    torque_scale : float
        Torque scale L.
    force_closure : bool
        ``value < -FORCE_CLOSURE_TOL`` (1e-9: solver round-off at the boundary
        does not count as a margin).
    kind : str
        ``"separation"`` (Q+) or ``"penetration"`` (Q-).
    degenerate : bool
        The derivative does not exist at this grasp (see :class:`PseudoDistance`).
    lp_solves : int
        Solver calls made.
    """

    value: float
    grad_points: np.ndarray
    grad_normals: np.ndarray
    wrenches: np.ndarray
    simplex: np.ndarray
    center: np.ndarray
    torque_scale: float
    force_closure: bool
    kind: str
    degenerate: bool
    lp_solves: int


def q_distance(points, normals, *, mu=0.3, edges=8, center=None, torque_scale=None, backend="highs") -> QDistance:
    """Q distance of a grasp and its gradients (paper Eqs. 4-10).

    Parameters
    ----------
    points : (n, 3) array_like
        Contact points (mm).
    normals : (n, 3) array_like
        Contact normals pointing INTO the object (any length > 0; normalised).
    mu : float
        Coulomb friction coefficient, > 0.
    edges : int
        Sides m of the linearised friction cone, >= 3.
    center : (3,) array_like, optional
        Torque reference point; default the origin.
    torque_scale : float, optional
        Torque scale L (mm); default the largest distance of a contact from ``center``.
    backend : str or synergrasp.lp.Backend
        LP backend.

    Returns
    -------
    QDistance

    Raises
    ------
    ValueError
        NaN/inf, wrong shapes, zero normals, ``mu <= 0``, ``edges < 3``, bad
        ``center``/``torque_scale``, unknown backend.
    synergrasp.lp.LPError
        If the LP backend fails.

    Examples
    --------
    Two opposite point contacts can never resist every wrench:

    >>> r = q_distance([[0, 0, 1.0], [0, 0, -1.0]], [[0, 0, -1.0], [0, 0, 1.0]])
    >>> r.force_closure
    False
    """
    arm, nhat, length, mu, c, L = _prepare(points, normals, mu, edges, center, torque_scale)
    M, basis, tangent = _cone(nhat, mu, edges)
    W = _wrenches(M, basis, arm, L)
    res = _pseudo_distance(W, _ORIGIN, _SIMPLEX, _SIMPLEX_MIN_NORM, lp.get_backend(backend))

    # d value / d w_ij = -alpha_ij dual = alpha_ij g, so every sum over the edges j goes through
    # s = M alpha_i (the weights of n, e1, e2): d value / d (n, e1, e2)_i = s_i (g_f + g_t x arm_i / L)
    s = M @ res.alpha.reshape(len(arm), -1).T  # (3, n)
    g = -res.dual
    grad_points = cross(np.einsum("ki,kia->ia", s, basis), g[3:]) / L  # sum_j d_ij x g_t / L
    h = g[:3] + cross(g[3:], arm) / L
    sh = s[:, :, None] * h  # d value / d (n, e1, e2)
    grad_nhat = sh[0] + _basis_vjp(basis, *tangent, sh[1], sh[2])
    grad_normals = (grad_nhat - np.einsum("ij,ij->i", grad_nhat, nhat)[:, None] * nhat) / length[:, None]
    return QDistance(
        value=res.value,
        grad_points=grad_points,
        grad_normals=grad_normals,
        wrenches=W,
        simplex=_SIMPLEX,
        center=c,
        torque_scale=L,
        force_closure=res.value < -FORCE_CLOSURE_TOL,
        kind=res.kind,
        degenerate=res.degenerate,
        lp_solves=res.lp_solves,
    )
