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

import math
import warnings
from dataclasses import dataclass
from functools import lru_cache

import numpy as np
from scipy.spatial import ConvexHull, QhullError

from ._checks import as_points, as_vector, positive_scalar
from ._jit import helper, kernel
from .pseudo_distance import MAX_LP_ENTRIES, lp_entries, optimum, regular_simplex

#: Q below minus this is force closure; closer to 0 is the boundary, within solver round-off.
FORCE_CLOSURE_TOL = 1e-9
#: Largest friction coefficient accepted (larger ones are not friction coefficients, and cone
#: edges that long leave the LP badly scaled).
MU_MAX = 1000.0
#: Most friction cone edges (sides of the linearised cone) accepted.
EDGES_MAX = 1000

_ORIGIN = np.zeros((1, 6))  # the origin of wrench space, the set the Q distance is measured to
_ORIGIN.setflags(write=False)
_SIMPLEX = regular_simplex(6)  # the default simplex in wrench space
_SIMPLEX.setflags(write=False)


def _unit_normals(normals, n_points):
    normals = as_points(normals, "normals", dim=3)
    if len(normals) != n_points:
        raise ValueError(f"normals has {len(normals)} rows but points has {n_points}; give one normal per contact")
    biggest = np.abs(normals).max(axis=1)
    if not biggest.all():
        raise ValueError(f"normals has zero-length rows {np.flatnonzero(biggest == 0).tolist()}; each contact needs a "
                         "direction")
    if biggest.min() > 1e-150 and biggest.max() < 1e150:  # no square under- or overflows (the common case)
        return _normalised(normals)
    with np.errstate(over="ignore", under="ignore"):
        length = np.sqrt(np.einsum("ij,ij->i", normals, normals))
    odd = ~(length >= 1e-150) | ~np.isfinite(length)  # the squares under- or overflowed: divide by the largest first
    if odd.any():
        normals = normals.copy()
        normals[odd] /= biggest[odd, None]
        scaled = np.sqrt(np.einsum("ij,ij->i", normals[odd], normals[odd]))
        with np.errstate(over="ignore"):
            length[odd] = scaled * biggest[odd]  # inf beyond the float range: the gradient through it is 0
        normals[odd] /= scaled[:, None]
        normals[~odd] /= length[~odd, None]
        return normals, length
    return normals / length[:, None], length


def _normalised(normals):
    """Unit rows of ``normals`` (n, 3) and their lengths (n,), for lengths whose squares neither under- nor overflow."""
    length = np.sqrt(np.einsum("ij,ij->i", normals, normals))
    return normals / length[:, None], length


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


@lru_cache(maxsize=32)
def _cone_matrix(mu, edges):
    """(3, m) read-only: column j is ``(1, mu cos t_j, mu sin t_j)``, the cone edges' weights of (n, e1, e2)."""
    cos, sin = _cos_sin(edges)
    M = np.ascontiguousarray(np.stack([np.ones_like(cos), mu * cos, mu * sin]))
    M.setflags(write=False)
    return M


def _wrenches(nhat, arm, L, mu, edges):
    """Primitive wrenches ``[d_ij ; arm_i x d_ij / L]`` (n*m, 6), contact-major, and the frames behind them.

    Edge j of contact i is ``d_ij = sum_k M[k, j] basis[k, i]`` with
    ``M[:, j] = (1, mu cos t_j, mu sin t_j)`` and ``basis = (n, e1, e2)``:
    e1 = normalise(a x n), a the coordinate axis least aligned with n
    (piecewise constant), e2 = n x e1.

    Returns
    -------
    W : (n*m, 6) float
    M : (3, m) float
    basis : (3, n, 3) float
    axis : (n,) int
        The axis a of each contact.
    vnorm : (n,) float
        ``|a x n|``.
    """
    n = len(nhat)
    M = _cone_matrix(float(mu), int(edges))
    W, basis = np.empty((n * M.shape[1], 6)), np.empty((3, n, 3))
    axis, vnorm = np.empty(n, dtype=np.int64), np.empty(n)
    _wrench_kernel(nhat, arm, float(L), M, W, basis, axis, vnorm)
    return W, M, basis, axis, vnorm


@helper
def _axis_cross(k, v0, v1, v2):
    """``e_k x v`` for the coordinate axis e_k."""
    if k == 0:
        return 0.0, -v2, v1
    if k == 1:
        return v2, 0.0, -v0
    return -v1, v0, 0.0


@kernel
def _wrench_kernel(nhat, arm, L, M, W, basis, axis, vnorm):
    """See `_wrenches`: fills ``W``, ``basis``, ``axis`` and ``vnorm``."""
    m = M.shape[1]
    for i in range(len(nhat)):
        n0, n1, n2 = nhat[i, 0], nhat[i, 1], nhat[i, 2]
        k = 0
        if abs(n1) < abs(n0):
            k = 1
        if abs(n2) < min(abs(n0), abs(n1)):
            k = 2
        axis[i] = k
        v0, v1, v2 = _axis_cross(k, n0, n1, n2)
        vn = math.sqrt(v0 * v0 + v1 * v1 + v2 * v2)
        vnorm[i] = vn
        e0, e1, e2 = v0 / vn, v1 / vn, v2 / vn
        basis[0, i, 0], basis[0, i, 1], basis[0, i, 2] = n0, n1, n2
        basis[1, i, 0], basis[1, i, 1], basis[1, i, 2] = e0, e1, e2
        basis[2, i, 0], basis[2, i, 1], basis[2, i, 2] = n1 * e2 - n2 * e1, n2 * e0 - n0 * e2, n0 * e1 - n1 * e0
        r0, r1, r2 = arm[i, 0] / L, arm[i, 1] / L, arm[i, 2] / L
        for j in range(m):
            for c in range(3):
                d = M[0, j] * basis[0, i, c] + M[1, j] * basis[1, i, c] + M[2, j] * basis[2, i, c]
                W[i * m + j, c] = d
            d0, d1, d2 = W[i * m + j, 0], W[i * m + j, 1], W[i * m + j, 2]
            W[i * m + j, 3] = r1 * d2 - r2 * d1
            W[i * m + j, 4] = r2 * d0 - r0 * d2
            W[i * m + j, 5] = r0 * d1 - r1 * d0


@kernel
def _gradient_kernel(alpha, dual, M, basis, axis, vnorm, arm, L, nhat, length, grad_points, grad_normals):
    """d Q / d p_i and d Q / d n_i (``grad_points``, ``grad_normals``) from the LP's weights and duals.

    d Q / d w_ij = -alpha_ij dual = alpha_ij g, so every sum over the edges j
    goes through ``s = M alpha_i`` (the weights of n, e1, e2): d Q / d (n, e1,
    e2)_i = s_i (g_f + g_t x arm_i / L), and d Q / d p_i = (sum_j d_ij) x g_t / L.
    The tangent basis contributes through its vector-Jacobian product:
    de1/dn = (I - e1 e1^T) [a]x / |a x n| and e2 = n x e1, so
    de2/dn = -[e1]x + [n]x de1/dn, and ``(de1/dn)^T w = -[a]x (I - e1 e1^T) w / |a x n|``.
    """
    m = M.shape[1]
    g0, g1, g2, t0, t1, t2 = -dual[0], -dual[1], -dual[2], -dual[3], -dual[4], -dual[5]
    for i in range(len(nhat)):
        s0 = s1 = s2 = 0.0
        for j in range(m):
            w = alpha[i * m + j]
            s0 += M[0, j] * w
            s1 += M[1, j] * w
            s2 += M[2, j] * w
        # sum_j d_ij x g_t / L
        d0 = s0 * basis[0, i, 0] + s1 * basis[1, i, 0] + s2 * basis[2, i, 0]
        d1 = s0 * basis[0, i, 1] + s1 * basis[1, i, 1] + s2 * basis[2, i, 1]
        d2 = s0 * basis[0, i, 2] + s1 * basis[1, i, 2] + s2 * basis[2, i, 2]
        grad_points[i, 0] = (d1 * t2 - d2 * t1) / L
        grad_points[i, 1] = (d2 * t0 - d0 * t2) / L
        grad_points[i, 2] = (d0 * t1 - d1 * t0) / L
        # h = g_f + g_t x arm / L: d Q / d (n, e1, e2) = s h
        a0, a1, a2 = arm[i, 0], arm[i, 1], arm[i, 2]
        h0 = g0 + (t1 * a2 - t2 * a1) / L
        h1 = g1 + (t2 * a0 - t0 * a2) / L
        h2 = g2 + (t0 * a1 - t1 * a0) / L
        n0, n1, n2 = basis[0, i, 0], basis[0, i, 1], basis[0, i, 2]
        e0, e1, e2 = basis[1, i, 0], basis[1, i, 1], basis[1, i, 2]
        # vector-Jacobian product of the tangent basis with g1 = s1 h, g2 = s2 h
        u0, u1, u2 = s2 * h0, s2 * h1, s2 * h2
        w0 = s1 * h0 - (n1 * u2 - n2 * u1)
        w1 = s1 * h1 - (n2 * u0 - n0 * u2)
        w2 = s1 * h2 - (n0 * u1 - n1 * u0)
        ew = e0 * w0 + e1 * w1 + e2 * w2
        w0, w1, w2 = w0 - e0 * ew, w1 - e1 * ew, w2 - e2 * ew
        c0, c1, c2 = _axis_cross(axis[i], w0, w1, w2)  # a x w
        vn = vnorm[i]
        q0 = s0 * h0 + (e1 * u2 - e2 * u1) - c0 / vn
        q1 = s0 * h1 + (e2 * u0 - e0 * u2) - c1 / vn
        q2 = s0 * h2 + (e0 * u1 - e1 * u0) - c2 / vn
        # through the normalisation of the given normal
        qn = q0 * nhat[i, 0] + q1 * nhat[i, 1] + q2 * nhat[i, 2]
        grad_normals[i, 0] = (q0 - qn * nhat[i, 0]) / length[i]
        grad_normals[i, 1] = (q1 - qn * nhat[i, 1]) / length[i]
        grad_normals[i, 2] = (q2 - qn * nhat[i, 2]) / length[i]


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
    W = _wrenches(nhat, np.zeros_like(nhat), 1.0, mu, edges)[0]
    return W[:, :3].reshape(len(nhat), int(edges), 3)


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
        Torque scale L (mm); default the largest ``|p_i - c|``, and at least
        that over `TORQUE_SCALE_RATIO`.

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
    return _wrenches(nhat, arm, L, mu, edges)[0]


def _prepare(points, normals, mu, edges, center, torque_scale):
    """Validated inputs: lever arms ``p_i - c`` (n, 3), unit normals (n, 3) and their lengths (n,), mu, c, L."""
    points = as_points(points, "points", dim=3)
    nhat, length = _unit_normals(normals, len(points))
    mu = positive_scalar(mu, "mu", MU_MAX)
    _angles(edges)  # validated here, before any work
    if lp_entries(len(points) * edges, 1, 6) > MAX_LP_ENTRIES:  # refused before the wrenches are built
        raise ValueError(f"{len(points)} contacts of {edges} cone edges make a Q-distance LP of more than the "
                         f"{MAX_LP_ENTRIES:.0e} nonzeros synergrasp builds: use fewer contacts (a grasp has a few)")
    c = np.zeros(3) if center is None else as_vector(center, "center", 3)
    with np.errstate(over="ignore"):  # refused just below, with the reason
        arm = points - c
    if not np.isfinite(arm).all():
        raise ValueError("the contacts' lever arms (points - center) overflow the float range: bring the points and the "
                         "centre nearer (the Q distance does not depend on where the object is)")
    if center is None and len(points) > 1:
        middle = points.mean(axis=0) if np.isfinite(points.sum()) else (points / len(points)).sum(axis=0)
        with np.errstate(over="ignore"):
            spread, far = _largest_arm(points - middle), _largest_arm(middle[None])  # (their squares may overflow)
        if far > max(FAR_CENTER, FAR_RATIO * spread):
            warnings.warn(f"the torques are taken about the origin, {far:.3g} from the contacts, which "
                          f"lie within {spread:.3g} of each other: Q then measures little more than the forces. Pass "
                          "center= (the object's centre, e.g. obj.center)", UserWarning, stacklevel=3)
    reach = _largest_arm(arm)  # the default torque scale
    if torque_scale is None:
        if reach <= 0:
            raise ValueError("every contact lies at the centre, so the default torque_scale is 0; pass torque_scale")
        L = reach
    else:
        L = positive_scalar(torque_scale, "torque_scale")
        if L < reach / TORQUE_SCALE_RATIO:
            raise ValueError(f"torque_scale {L:g} is more than {TORQUE_SCALE_RATIO:g} times smaller than the contacts' "
                             f"largest lever arm |p_i - c|, {reach:.3g}: the forces would vanish beside the torques and "
                             "the LPs lose their accuracy. It is a length in the points' units; omit it for that default")
        if reach > 0 and not reach / TORQUE_SCALE_WARN <= L <= reach * TORQUE_SCALE_WARN:  # (no arm: no torque)
            warnings.warn(f"torque_scale {L:g} is {max(L / reach, reach / L):.3g} times {'larger' if L > reach else 'smaller'} "
                          f"than the contacts' largest lever arm |p_i - c|, {reach:.3g}: is it in the points' units? (A "
                          "value in metres for points in mm, or the other way round, is 1000 times off.) Q is a different "
                          "number for every scale; omit torque_scale for the default, the largest lever arm",
                          UserWarning, stacklevel=3)
    return arm, nhat, length, mu, c, L


def _largest_arm(arm):
    """The largest ``|p_i - c|`` of lever arms ``arm`` (n, 3), also where its square would overflow or underflow."""
    top = float(np.abs(arm).max())  # the largest lever arm component
    if top <= 0:
        return 0.0
    if 1e-150 < top < 1e150:  # no square under- or overflows (the common case)
        return float(np.sqrt((arm * arm).sum(axis=1).max()))
    with np.errstate(over="ignore", under="ignore"):
        length = float(np.sqrt((arm * arm).sum(axis=1).max()))
    if not 0 < length < np.inf:  # its square overflowed or underflowed: the same length, scaled
        length = top * float(np.sqrt(((arm / top) ** 2).sum(axis=1).max()))
    return length


#: Without a ``center``, the torques are taken about the origin; a warning says so when the contacts' centroid
#: is farther from it than `FAR_CENTER` mm (no object a hand holds is larger: the origin is not its centre) and
#: than ``FAR_RATIO`` times the contacts' largest distance from their centroid.
FAR_CENTER = 500.0
FAR_RATIO = 10.0
#: A given ``torque_scale`` must be at least the contacts' largest lever arm (its default) over this factor.
TORQUE_SCALE_RATIO = 1e4
#: A given ``torque_scale`` further than this factor from the contacts' largest lever arm is warned about (a length
#: in other units than the points'); the library's own calls pass ``checked=True``, which skips the check.
TORQUE_SCALE_WARN = 100.0
#: Most wrenches `force_closure_by_hull` takes: qhull's 6-D hull of 160 takes about 0.7 s, of 320 about 8 s.
MAX_HULL_WRENCHES = 256


def force_closure_by_hull(wrenches, tol=FORCE_CLOSURE_TOL) -> bool:
    """Independent force-closure test: the origin strictly inside the convex hull of the wrenches.

    Uses qhull (``scipy.spatial.ConvexHull``), not an LP, so it can cross-check
    :func:`q_distance`.

    Parameters
    ----------
    wrenches : (k, 6) array_like
        Primitive contact wrenches (``contact_wrenches``).
    tol : float
        Margin by which the origin must be inside every facet plane, relative
        to the largest wrench coordinate (the verdict is the same for the
        wrenches in any unit).

    Returns
    -------
    bool
        False as well when the wrenches span less than 6 dimensions.

    Raises
    ------
    ValueError
        For more than `MAX_HULL_WRENCHES` wrenches, a non-finite wrench or a bad ``tol``.

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
    if len(W) > MAX_HULL_WRENCHES:
        raise ValueError(f"force_closure_by_hull builds the 6-D convex hull of all {len(W)} wrenches, which takes qhull "
                         f"minutes beyond a few hundred; it takes at most {MAX_HULL_WRENCHES} (fewer contacts or cone "
                         "edges: contact_wrenches(..., edges=8)), or use q_distance")
    scale = float(np.abs(W).max())  # (as_points refuses an empty array)
    if scale == 0.0:
        return False
    try:
        hull = ConvexHull(W / scale)  # the verdict does not depend on the wrenches' unit
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


def _shape(value) -> str:
    """An argument's shape in messages: ``shape (n, 3)`` of an array, else its type."""
    return f"of shape {value.shape}" if isinstance(value, np.ndarray) else f"a {type(value).__name__}"


def q_distance(points, normals, *, mu=0.3, edges=8, center=None, torque_scale=None, backend="native",
               checked=False) -> QDistance:
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
        Torque scale L (mm); default the largest distance of a contact from
        ``center``, and at least that over `TORQUE_SCALE_RATIO`.
    backend : str or synergrasp.lp.Backend
        LP backend.
    checked : bool
        ``points`` and ``normals`` are finite (n, 3) float arrays, the
        normals of lengths between 1e-150 and 1e150, and ``center`` and
        ``torque_scale`` are given and valid, as the library's own geometry
        makes them (a caller that produced them skips their checks; ``mu``
        and ``edges`` are checked all the same).

    Returns
    -------
    QDistance

    Raises
    ------
    ValueError
        NaN/inf, wrong shapes, zero normals, ``mu <= 0``, ``edges < 3``, bad
        ``center``/``torque_scale`` (or either missing with ``checked``),
        unknown backend.
    TypeError
        If ``checked`` is not a bool.
    synergrasp.lp.LPError
        If the LP backend fails.

    Warns
    -----
    UserWarning
        Without ``center``, when the contacts lie farther than `FAR_CENTER` mm
        from the origin (and far relative to their spread): the torques are
        then taken about a point that cannot be the object's centre. With a
        ``torque_scale`` more than `TORQUE_SCALE_WARN` times larger or smaller
        than the contacts' largest lever arm: a length in other units than
        the points' (metres for mm) gives a Q 1000 times off.

    Examples
    --------
    Two opposite point contacts can never resist every wrench:

    >>> r = q_distance([[0, 0, 1.0], [0, 0, -1.0]], [[0, 0, -1.0], [0, 0, 1.0]])
    >>> r.force_closure
    False
    """
    if not isinstance(checked, bool):
        raise TypeError(f"checked must be True or False, got {type(checked).__name__} {checked!r}")
    if checked and (center is None or torque_scale is None):
        raise ValueError("checked=True is for arrays the library made, with center and torque_scale given: give "
                         "them, or leave checked False")
    if checked:  # the same arrays as _prepare's for such inputs (their types and shapes still checked: cheap)
        if not (isinstance(points, np.ndarray) and isinstance(normals, np.ndarray) and points.ndim == 2
                and points.shape[1:] == (3,) and normals.shape == points.shape and np.shape(center) == (3,)):
            raise ValueError("checked=True is for (n, 3) float arrays the library made, one normal per contact point, "
                             f"and a (3,) center; got points {_shape(points)}, normals {_shape(normals)} and center "
                             f"{_shape(center)}: leave checked False")
        if not len(points):
            raise ValueError("points is empty: it needs at least one contact")
        mu, _ = positive_scalar(mu, "mu", MU_MAX), _angles(edges)
        (nhat, length), arm, c, L = _normalised(normals), points - center, center, float(torque_scale)
    else:
        arm, nhat, length, mu, c, L = _prepare(points, normals, mu, edges, center, torque_scale)
    W, M, basis, axis, vnorm = _wrenches(nhat, arm, L, mu, edges)
    res = optimum(W, _ORIGIN, backend=backend, checked=True)
    grad_points, grad_normals = np.empty_like(arm), np.empty_like(arm)
    _gradient_kernel(res.alpha, res.dual, M, basis, axis, vnorm, arm, float(L), nhat, length, grad_points, grad_normals)
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
