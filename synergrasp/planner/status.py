"""The grasp status vector g (paper Eqs. 12-14) and its Jacobian dg/du.

g = [cP of each hand point ; g_sQ]: the contact pseudo-distance of the 5
fingertips (precision) or the 16 phalanx and palm points (power), then the
Q distance of the contacts the hand would make with the object scaled about
its centre (sQ). The Jacobian chains the dual-based derivatives of cP and of
the Q distance with the hand's analytic point Jacobians; nothing is
differentiated numerically.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from .._vectors import unit_rows
from ..hand import SynergyHand
from ..objects.proximity import group_contact_distance
from ..quality import q_distance


@dataclass(frozen=True)
class Status:
    """The grasp status at one configuration.

    Attributes
    ----------
    g : (n+1,) float
        cP of each hand point (mm), then g_sQ.
    J : (n+1, len(u)) float
        dg/du.
    points : (n, 3) float
        The hand points.
    nearest : (n, 3) float
        Nearest object point of each hand point.
    normals : (n, 3) float
        Inward object normal at ``nearest``.
    lp_solves : int
        Solver calls made.
    """

    g: np.ndarray
    J: np.ndarray
    points: np.ndarray
    nearest: np.ndarray
    normals: np.ndarray
    lp_solves: int


def smoothed_normals(obj, x, pieces, length):
    """Inward normals of a smoothed surface and their derivatives.

    The facet normals of a polytope are piecewise constant, so their derivative
    along the surface is zero almost everywhere and the way a smooth object's
    normal turns as a contact slides is lost. Each piece's surface is smoothed by
    the log-sum-exp of its facet planes, ``f(x) = h log sum_f exp((n_f . x + o_f) / h)``,
    whose gradient is a softmax-weighted average of the facet normals.

    Parameters
    ----------
    obj : GraspObject
    x : (n, 3) float
        Points on (or near) the surface.
    pieces : (n,) int
        The piece of each point.
    length : float
        Smoothing length h (mm).

    Returns
    -------
    normals : (n, 3) float
        Unit inward normals.
    jac : (n, 3, 3) float
        d normal / d x.

    Examples
    --------
    At the pole of the ellipsoid the smoothed inward normal points down the z axis:

    >>> from synergrasp import objects
    >>> n, jac = smoothed_normals(objects.ellipsoid(), np.array([[0.0, 0.0, 50.0]]), np.array([0]), 5.0)
    >>> bool(np.allclose(n, [[0.0, 0.0, -1.0]], atol=1e-2)), jac.shape
    (True, (1, 3, 3))
    """
    m = np.empty((len(x), 3))  # softmax-weighted facet normals
    dm = np.empty((len(x), 3, 3))  # their derivatives with respect to x
    for k in np.unique(pieces):  # all points on one piece at once
        rows = pieces == k
        a, offset = obj.convex[k].planes[:, :3], obj.convex[k].planes[:, 3]
        s = (x[rows] @ a.T + offset) / length
        w = np.exp(s - s.max(axis=1, keepdims=True))
        w /= w.sum(axis=1, keepdims=True)
        moments = w @ obj._normal_moments[k]  # the weighted n_f and n_f n_f^T in one product
        m[rows] = moments[:, :3]
        dm[rows] = (moments[:, 3:].reshape(-1, 3, 3) - m[rows, :, None] * m[rows, None, :]) / length
    norm = np.linalg.norm(m, axis=1)
    n_out = m / norm[:, None]
    projector = np.eye(3) - n_out[:, :, None] * n_out[:, None, :]
    return -n_out, -(projector @ dm) / norm[:, None, None]


@dataclass(frozen=True)
class PadDistance:
    """cP rows of the status: one per watched hand point or pad line.

    Attributes
    ----------
    value : (n,) float
        cP (mm).
    jac : (n, len(u)) float
        d value / d u.
    nearest : (n, 3) float
        Nearest object point.
    normal : (n, 3) float
        Inward object normal there.
    lp_solves : int
    """

    value: np.ndarray
    jac: np.ndarray
    nearest: np.ndarray
    normal: np.ndarray
    lp_solves: int


def segment_distance(obj, skin, palm, jac_skin, jac_palm, backend="highs") -> PadDistance:
    """cP of the phalanges and of the palm point (the power grasp's contact rows).

    A phalanx touches an object anywhere on its skin, not only at one point:
    the cP of a segment is the smallest cP of its skin points
    (`SynergyHand.skin_and_jacobian`: both ends, the middle, the palmar and
    the two lateral sides), so a phalanx whose end or side dips into the
    object reads as penetrating. Its derivative is that of the skin point
    attaining the minimum. Skin points whose lower bound of cP exceeds an
    upper bound of another point of the same segment cannot attain it and
    are left out (`synergrasp.objects.proximity.group_contact_distance`,
    valid bounds, so the rows are unchanged); the rest and the palm point
    are one LP.

    Parameters
    ----------
    obj : GraspObject
    skin : (k, m, 3) float
        Skin points of each segment.
    palm : (3,) float
        The palm point.
    jac_skin : (k, m, 3, nu) float
        d skin / d u.
    jac_palm : (3, nu) float
        d palm / d u.
    backend : str

    Returns
    -------
    PadDistance
        k + 1 rows: the segments, then the palm point.

    Examples
    --------
    >>> from synergrasp import SynergyHand, objects
    >>> from synergrasp.planner import start_configuration
    >>> hand, obj = SynergyHand.default(), objects.ellipsoid()
    >>> skin, palm, jac_skin, jac_palm = hand.skin_and_jacobian(start_configuration(hand, obj))
    >>> segment_distance(obj, skin, palm, jac_skin, jac_palm).jac.shape
    (16, 8)
    """
    k, m = skin.shape[:2]
    groups = np.r_[np.repeat(np.arange(k), m), k]  # the segments, then the palm point alone
    cp, best = group_contact_distance(obj, np.vstack([skin.reshape(-1, 3), palm]), groups, backend)
    jac = np.einsum("ka,kab->kb", cp.grad[:-1], jac_skin.reshape(k * m, 3, -1)[best[:-1]])
    return PadDistance(
        value=cp.value,
        jac=np.vstack([jac, cp.grad[-1] @ jac_palm]),
        nearest=cp.nearest,
        normal=cp.normal,
        lp_solves=cp.lp_solves,
    )


def capsule_rows(hand, obj, u, status, penetration=None) -> Status:
    """A power status whose segment rows also see the phalanx capsules' penetration.

    The skin points of a segment (`segment_distance`) sample its capsule: an
    object's edge or a thin plate can cut into the capsule between them, deep,
    while every skin point reads shallow or outside. A segment whose capsule
    penetrates the object (python-fcl's signed distance,
    `synergrasp.objects.GraspObject.penetration`) deeper than its row reads
    gets that signed distance (negative, mm) as its row instead. The capsule
    is the set of points within its radius of its axis, so the distance moves
    with the axis point nearest the capsule's deepest point, ``(1 - t) a + t b``:
    the derivative is the unit translation that frees the capsule (from its
    point deepest in the object to the object's point deepest in it, the
    penetration normal) times that point's Jacobian ``(1 - t) J_a + t J_b``.

    Parameters
    ----------
    hand : SynergyHand
    obj : GraspObject
    u : (6 + n_syn,) float
        The configuration of ``status``.
    status : Status
        A power grasp's status at ``u`` (`grasp_status` with ``kind="power"``).
    penetration : Penetration, optional
        ``obj.penetration(hand.segments(u).capsules, hand.finger_radius)`` if
        already computed.

    Returns
    -------
    Status
        ``status`` with the rows of the deeper capsules replaced (``status``
        itself when none is deeper); nearest points and normals stay the skin
        points'.

    Examples
    --------
    A phalanx through an 8 mm plate: its skin points are all within 4 mm of a
    face, its capsule is 12 mm deep.

    >>> import trimesh
    >>> from synergrasp import SynergyHand, objects
    >>> hand = SynergyHand.default()
    >>> plate = objects.from_mesh(trimesh.creation.box((200.0, 200.0, 8.0)), cache=False)
    >>> u = np.zeros(hand.n_u)
    >>> u[:3] = -hand.segments(u).capsules[1].mean(axis=0)  # the thumb's middle phalanx centred in the plate
    >>> skin = grasp_status(hand, plate, u, "power")
    >>> seen = capsule_rows(hand, plate, u, skin)
    >>> bool(skin.g[1] > -5.0), bool(seen.g[1] < -10.0)
    (True, True)
    """
    ends, jac_ends = hand.segments_and_jacobian(u)
    pen = obj.penetration(ends, hand.finger_radius) if penetration is None else penetration
    deeper = np.flatnonzero((pen.distances < 0.0) & (pen.distances < status.g[: len(ends)]))
    if not len(deeper):
        return status
    inner, outer = pen.witnesses[deeper, 0], pen.witnesses[deeper, 1]
    free = unit_rows(outer - inner)
    a, b = ends[deeper, 0], ends[deeper, 1]
    axis = b - a
    t = np.clip(np.einsum("ij,ij->i", inner - a, axis) / np.maximum(np.einsum("ij,ij->i", axis, axis), 1e-12), 0.0, 1.0)
    jac_point = (1.0 - t)[:, None, None] * jac_ends[deeper, 0] + t[:, None, None] * jac_ends[deeper, 1]
    g, J = status.g.copy(), status.J.copy()
    g[deeper] = pen.distances[deeper]
    J[deeper] = np.einsum("ia,iab->ib", free, jac_point)
    return replace(status, g=g, J=J)


def _require(hand, obj):
    """TypeError unless ``hand`` is a SynergyHand and ``obj`` a GraspObject."""
    from ..objects import GraspObject

    if not isinstance(hand, SynergyHand):
        raise TypeError(f"hand must be a SynergyHand, got {type(hand).__name__}")
    if not isinstance(obj, GraspObject):
        raise TypeError(f"obj must be a GraspObject, got {type(obj).__name__}")


def grasp_status(hand, obj, u, kind, *, mu=0.3, edges=8, backend="highs", smoothing=None) -> Status:
    """Status vector and Jacobian at configuration u.

    Parameters
    ----------
    hand : SynergyHand
    obj : GraspObject
    u : (8,) float
        Configuration (mm, rad, synergies).
    kind : {"precision", "power"}
        Which hand points.
    mu, edges : float, int
        Friction model of the sQ term.
    backend : str
        LP backend.

    Returns
    -------
    Status

    Raises
    ------
    TypeError
        If ``hand`` is not a SynergyHand or ``obj`` not a GraspObject.

    Examples
    --------
    >>> from synergrasp import SynergyHand, objects
    >>> from synergrasp.planner import start_configuration
    >>> hand, obj = SynergyHand.default(), objects.ellipsoid()
    >>> st = grasp_status(hand, obj, start_configuration(hand, obj), "precision")
    >>> st.g.shape, st.J.shape
    ((6,), (6, 8))
    """
    _require(hand, obj)
    if kind == "power":
        points, jac, skin, palm, jac_skin, jac_palm = hand.power_and_skin(u)
        cp = segment_distance(obj, skin, palm, jac_skin, jac_palm, backend)
    else:
        points, jac = hand.points_and_jacobian(u, kind)  # (n, 3), (n, 3, nu)
        cp = obj.contact_distance(points, backend=backend)
        cp = PadDistance(cp.value, np.einsum("ia,iab->ib", cp.grad, jac), cp.nearest, cp.normal, cp.lp_solves)
    sc = obj.scaled_contacts(points, backend=backend)
    if smoothing:
        normals, jac_n = smoothed_normals(obj, sc.contact, sc.piece, smoothing)
        jac_normal = jac_n @ sc.jac_contact
    else:
        normals, jac_normal = sc.normal, sc.jac_normal
    sq = q_distance(
        sc.contact, normals, mu=mu, edges=edges, center=obj.center, torque_scale=obj.torque_scale, backend=backend
    )
    # d g_sQ / d p_i through the contact carried back to the object and its normal
    grad_sq = np.einsum("ia,iab->ib", sq.grad_points, sc.jac_contact) + np.einsum("ia,iab->ib", sq.grad_normals, jac_normal)
    J = np.vstack([cp.jac, np.einsum("ia,iab->b", grad_sq, jac)])
    return Status(
        g=np.append(cp.value, sq.value),
        J=J,
        points=points,
        nearest=cp.nearest,
        normals=cp.normal,
        lp_solves=cp.lp_solves + sc.lp_solves + sq.lp_solves,
    )
