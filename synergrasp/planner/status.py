"""The grasp status vector g (paper Eqs. 12-14) and its Jacobian dg/du.

g = [cP rows ; g_sQ]: the contact pseudo-distance of the hand's parts, then
the Q distance of the contacts the hand would make with the object scaled
about its centre (sQ). Every part is watched over its skin: a phalanx's row
is the smallest cP of the points on its capsule, the palm's that of the palm
point, the rim of the palm box's front face and the point of the face over
the object's nearest vertex (`palm_face_point`). A precision grasp's contact
rows are the five fingertips (each the smaller of its pad point's cP and its
distal phalanx's row); its other phalanges and the palm are clearance rows.
A power grasp's rows are the 15 phalanges and the palm. The Jacobian chains
the dual-based derivatives of cP and of the Q distance with the hand's
analytic point Jacobians; nothing is differentiated numerically.
"""

from __future__ import annotations

import weakref
from dataclasses import dataclass, replace

import numpy as np

from .._checks import positive_scalar
from .._jit import kernel
from .._vectors import unit_rows
from ..hand import SynergyHand, grasp_kind
from ..objects import GraspObject
from ..objects.contact_distance import group_contact_distance
from ..quality import q_distance


#: Added to the row of each cP candidate point of a precision status to name it in the object's
#: memory of LP bases (a power status's points are named by their rows): each point's cP blocks
#: start from the last optimal bases of the same point of the same kind of status.
PRECISION_IDS = 1 << 20


@dataclass(frozen=True)
class Status:
    """The grasp status at one configuration.

    Attributes
    ----------
    g : (n+1,) float
        cP of each row (mm), then g_sQ.
    J : (n+1, len(u)) float
        dg/du, each row that of the point attaining it held fixed on the hand;
        where the palm's row is attained at the palm face point
        (`palm_face_point`), which follows the object's edge rather than the
        palm, the row is the palm's motion at that point, not dg_P/du.
    labels : list of str
        The n cP rows: ``"T0" ... "L0"`` (fingertips), ``"T1" ... "L3"``
        (phalanges), ``"P"`` (the palm, always last).
    contact : (n,) bool
        Rows whose touching counts as a contact of the grasp (precision: the
        fingertips; power: every row). The others only keep clear.
    segment_rows : (k,) int
        The row of each phalanx capsule (``hand.segments(u).labels`` order).
    points : (h, 3) float
        The hand points of the sQ term (the fingertips, or the 16 power points).
    nearest : (n, 3) float
        Nearest object point of each row.
    normals : (n, 3) float
        Inward object normal at ``nearest``.
    pieces : (n,) int
        The piece ``nearest`` lies on.
    row_points : (n, 3) float
        The hand point attaining each row (a skin point or a fingertip pad).
    point_jac : (n, 3, len(u)) float
        Its Jacobian.
    lp_solves : int
        Solver calls made.
    """

    g: np.ndarray
    J: np.ndarray
    labels: list
    contact: np.ndarray
    segment_rows: np.ndarray
    points: np.ndarray
    nearest: np.ndarray
    normals: np.ndarray
    pieces: np.ndarray
    row_points: np.ndarray
    point_jac: np.ndarray
    lp_solves: int


def read_only(record):
    """A copy of a dataclass (a `Status`, a `GraspCheck`) whose arrays are read-only copies.

    What a ``progress`` callback receives: editing it cannot change the plan.

    Parameters
    ----------
    record : dataclass instance

    Returns
    -------
    The same type.

    Examples
    --------
    >>> from synergrasp import SynergyHand, objects
    >>> from synergrasp.planner import start_configuration
    >>> hand, obj = SynergyHand.default(), objects.ellipsoid()
    >>> st = grasp_status(hand, obj, start_configuration(hand, obj), "precision")
    >>> shown = read_only(st)
    >>> shown.g.flags.writeable, st.g.flags.writeable, bool((shown.g == st.g).all())
    (False, True, True)
    """
    arrays = {}
    for name in record.__dataclass_fields__:
        value = getattr(record, name)
        if isinstance(value, np.ndarray):
            arrays[name] = value.copy()
            arrays[name].setflags(write=False)
    return replace(record, **arrays)


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
    length = positive_scalar(length, "length (mm)")  # (0 or less: no smoothing, or a flipped normal)
    x = np.ascontiguousarray(x, dtype=float)
    pieces = np.asarray(pieces, dtype=np.int64)
    index = obj.index
    start = np.zeros(len(x) + 1, dtype=np.int64)
    np.cumsum(index.facet_counts[pieces], out=start[1:])
    w = np.empty(start[-1])
    _smoothing_exponents(x, pieces, index.planes, index.plane_start, float(length), start, w)
    np.exp(w, out=w)  # numpy's vectorised exp: several times faster than a compiled loop's
    normals, jac = np.empty((len(x), 3)), np.empty((len(x), 3, 3))
    _smoothed_normals(pieces, index.planes, index.plane_start, float(length), start, w, normals, jac)
    return normals, jac


@kernel
def _smoothing_exponents(x, pieces, planes, plane_start, h, start, s):
    """``(n_f . x + o_f) / h`` minus its max over the facets of x's piece, into ``s[start[i]:start[i+1]]``."""
    for i in range(len(x)):
        j = pieces[i]
        sub = planes[plane_start[j]:plane_start[j + 1]]
        out = s[start[i]:start[i + 1]]
        x0, x1, x2 = x[i, 0], x[i, 1], x[i, 2]
        smax = -np.inf
        for f in range(len(sub)):
            out[f] = (x0 * sub[f, 0] + x1 * sub[f, 1] + x2 * sub[f, 2] + sub[f, 3]) / h
            smax = max(smax, out[f])
        for f in range(len(sub)):
            out[f] -= smax


@kernel
def _smoothed_normals(pieces, planes, plane_start, h, start, w, normals, jac):
    """`smoothed_normals` into ``normals`` (n, 3) and ``jac`` (n, 3, 3), from the softmax weights' numerators ``w``.

    With the softmax weights w_f of ``(n_f . x + o_f) / h``, the gradient of
    the smoothed surface is ``m = sum w_f n_f``, its derivative
    ``dm = (sum w_f n_f n_f^T - m m^T) / h``; the inward unit normal is
    ``-m / |m|`` with derivative ``-(I - n n^T) dm / |m|``.
    """
    for i in range(len(pieces)):
        j = pieces[i]
        sub = planes[plane_start[j]:plane_start[j + 1]]
        wi = w[start[i]:start[i + 1]]
        total = m0 = m1 = m2 = 0.0
        s00 = s01 = s02 = s11 = s12 = s22 = 0.0
        for f in range(len(sub)):
            a0, a1, a2, wf = sub[f, 0], sub[f, 1], sub[f, 2], wi[f]
            total += wf
            m0 += wf * a0
            m1 += wf * a1
            m2 += wf * a2
            s00 += wf * a0 * a0
            s01 += wf * a0 * a1
            s02 += wf * a0 * a2
            s11 += wf * a1 * a1
            s12 += wf * a1 * a2
            s22 += wf * a2 * a2
        m0, m1, m2 = m0 / total, m1 / total, m2 / total
        d00, d01, d02 = (s00 / total - m0 * m0) / h, (s01 / total - m0 * m1) / h, (s02 / total - m0 * m2) / h
        d11, d12, d22 = (s11 / total - m1 * m1) / h, (s12 / total - m1 * m2) / h, (s22 / total - m2 * m2) / h
        norm = np.sqrt(m0 * m0 + m1 * m1 + m2 * m2)
        n0, n1, n2 = m0 / norm, m1 / norm, m2 / norm
        normals[i, 0], normals[i, 1], normals[i, 2] = -n0, -n1, -n2
        # -(I - n n^T) dm / |m|, dm symmetric
        for c, (e0, e1, e2) in enumerate(((d00, d01, d02), (d01, d11, d12), (d02, d12, d22))):
            ne = n0 * e0 + n1 * e1 + n2 * e2  # (n^T dm)[column c]
            jac[i, 0, c] = -(e0 - n0 * ne) / norm
            jac[i, 1, c] = -(e1 - n1 * ne) / norm
            jac[i, 2, c] = -(e2 - n2 * ne) / norm


def hand_penetration(hand, obj, u):
    """Penetration of the hand's phalanx capsules and palm box into the object at ``u`` (python-fcl).

    Parameters
    ----------
    hand : SynergyHand
    obj : GraspObject
    u : (6 + n_syn,) float

    Returns
    -------
    Penetration
        `synergrasp.objects.GraspObject.penetration` of the k capsules of
        ``hand.segments(u)``, then the palm box (entry k); only the shapes
        that touch the object are measured (``clear=False``: the others'
        ``distances`` read +inf).
    """
    geo = hand.segments(u)
    return obj.penetration(geo.capsules, geo.radius, box=(geo.palm_center, geo.palm_axes, geo.palm_half_extents),
                           clear=False)


def capsule_rows(hand, obj, u, status, penetration=None) -> Status:
    """A status whose phalanx and palm rows also see the capsules' and the palm box's penetration.

    The skin points of a segment (`grasp_status`) sample its capsule, and the
    palm's sample the box's front face: an object's edge or a thin plate can
    cut into a capsule between them, and a convex object can push into the
    palm box's sides, deep, while every skin point reads shallow or outside.
    A segment whose capsule, or a palm whose box, penetrates the object
    (python-fcl's signed distance, `hand_penetration`) deeper than its row
    reads gets that signed distance (negative, mm) as its row instead. Its
    derivative is the unit translation that frees the shape (from its point
    deepest in the object to the object's point deepest in it, the
    penetration normal) times the Jacobian of the point that carries the
    shape: for a capsule, the set of points within its radius of its axis,
    the axis point nearest its deepest point, ``(1 - t) a + t b``, moving with
    ``(1 - t) J_a + t J_b``; for the box, its deepest point itself, fixed to
    the palm (`SynergyHand.palm_jacobian`).

    Parameters
    ----------
    hand : SynergyHand
    obj : GraspObject
    u : (6 + n_syn,) float
        The configuration of ``status``.
    status : Status
        A status at ``u`` (`grasp_status`).
    penetration : Penetration, optional
        ``hand_penetration(hand, obj, u)`` if already computed.

    Returns
    -------
    Status
        ``status`` with the rows of the deeper shapes replaced (``status``
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
    pen = hand_penetration(hand, obj, u) if penetration is None else penetration
    rows = np.r_[status.segment_rows, len(status.labels) - 1]  # the capsules, then the palm box
    deeper = np.flatnonzero((pen.distances < 0.0) & (pen.distances < status.g[rows]))
    if not len(deeper):
        return status
    inner, outer = pen.witnesses[deeper, 0], pen.witnesses[deeper, 1]
    free = unit_rows(outer - inner)
    jac_point = np.empty((len(deeper), 3, hand.n_u))
    capsule = deeper < len(status.segment_rows)
    if capsule.any():
        ends, jac_ends = hand.segments_and_jacobian(u)
        k = deeper[capsule]
        a, b = ends[k, 0], ends[k, 1]
        axis = b - a
        t = np.clip(np.einsum("ij,ij->i", inner[capsule] - a, axis) / np.maximum(np.einsum("ij,ij->i", axis, axis), 1e-12),
                    0.0, 1.0)
        jac_point[capsule] = (1.0 - t)[:, None, None] * jac_ends[k, 0] + t[:, None, None] * jac_ends[k, 1]
    if not capsule.all():
        jac_point[~capsule] = hand.palm_jacobian(u, inner[~capsule])
    g, J = status.g.copy(), status.J.copy()
    g[rows[deeper]] = pen.distances[deeper]
    J[rows[deeper]] = np.einsum("ia,iab->ib", free, jac_point)
    return replace(status, g=g, J=J)


def status_rows(hand, kind):
    """The cP rows of a grasp type's status, and which of them are contacts.

    Parameters
    ----------
    hand : SynergyHand
    kind : {"precision", "power"}

    Returns
    -------
    labels : list of str
        Row labels (see `Status`).
    contact : (n,) bool
        Rows that count as contacts.
    segment_rows : (k,) int
        The row of each phalanx (in ``hand.segments(u).labels`` order).

    Examples
    --------
    >>> from synergrasp import SynergyHand
    >>> labels, contact, _ = status_rows(SynergyHand.default(), "precision")
    >>> labels[:6], int(contact.sum()), labels[-1]
    (['T0', 'I0', 'M0', 'R0', 'L0', 'T1'], 5, 'P')
    """
    grasp_kind(kind)
    rows = _ROWS.setdefault(hand, {})
    if kind not in rows:  # the same for every status of a hand: built once
        rows[kind] = _status_rows(hand, kind)
    labels, contact, segment_rows = rows[kind]
    return list(labels), contact.copy(), segment_rows.copy()


#: An object is slender when friction at its surface resists a torque about its long axis of less than this
#: fraction of its bounding radius per unit of grip force (``mu * axial_radius / radius``, `steering_scale`).
SLENDER = 0.05
#: `status_rows` of each hand that asked, by grasp type.
_ROWS = weakref.WeakKeyDictionary()


def _status_rows(hand, kind):
    """`status_rows`, built from the hand's point labels."""
    segments, chains = hand.point_labels("power")[:-1], hand.point_chains("power")[:-1]
    if kind == "power":
        return segments + ["P"], np.ones(len(segments) + 1, bool), np.arange(len(segments))
    distal = {chain: i for i, chain in enumerate(chains)}  # each finger's last segment
    tips = hand.point_labels("precision")  # one per finger, in the fingers' order
    labels = tips + [lab for i, lab in enumerate(segments) if distal[chains[i]] != i] + ["P"]
    rows = [chains[i] if distal[chains[i]] == i else labels.index(lab) for i, lab in enumerate(segments)]
    return labels, np.arange(len(labels)) < len(tips), np.array(rows)


def principal_axes(obj):
    """The object's principal axes: the singular vectors of its pieces' vertices about their mean.

    Parameters
    ----------
    obj : GraspObject

    Returns
    -------
    (3, 3) float
        Unit axes as rows, the shortest first, each signed so that its
        components sum to zero or more.

    Examples
    --------
    >>> from synergrasp import objects
    >>> principal_axes(objects.ellipsoid()).round(3).tolist()   # semi-axes 30, 40, 50 mm along x, y, z
    [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]
    """
    points = np.vstack(obj.pieces) - obj.center
    _, _, axes = np.linalg.svd(points - points.mean(axis=0), full_matrices=False)
    axes = axes[::-1]  # shortest first
    return axes * np.where(axes.sum(axis=1) < 0, -1.0, 1.0)[:, None]


def axial_radius(obj):
    """How far the object reaches from its long axis: the farthest of its pieces' vertices from the line.

    The long axis is the longest of `principal_axes`, through the object's
    centre.

    Parameters
    ----------
    obj : GraspObject

    Returns
    -------
    float
        mm.

    Examples
    --------
    >>> import trimesh
    >>> from synergrasp import objects
    >>> rod = objects.from_mesh(trimesh.creation.cylinder(radius=10.0, height=300.0, sections=32), cache=False)
    >>> round(axial_radius(rod), 3)
    10.0
    """
    axis = principal_axes(obj)[2]
    points = np.vstack(obj.pieces) - obj.center
    return float(np.linalg.norm(points - np.outer(points @ axis, axis), axis=1).max())


def slender(obj, mu):
    """Whether an object is slender: friction at its surface resists little torque about its long axis.

    Parameters
    ----------
    obj : GraspObject
    mu : float
        Friction coefficient.

    Returns
    -------
    bool
        ``mu * axial_radius(obj) < SLENDER * obj.radius``: the torque about
        the long axis per unit of grip force is less than `SLENDER` of its
        bounding radius.

    Examples
    --------
    >>> import trimesh
    >>> from synergrasp import objects
    >>> rod = objects.from_mesh(trimesh.creation.cylinder(radius=10.0, height=300.0, sections=32), cache=False)
    >>> slender(rod, 0.3), slender(objects.ellipsoid(), 0.3)
    (True, False)
    """
    return mu * axial_radius(obj) < SLENDER * obj.radius


def steering_scale(obj, mu):
    """The torque scale of the rows that steer a power attempt: the object's, or its diameter if it is slender.

    A power attempt's sQ row and contacts' own g_Q row (`grasp_status`,
    `contact_quality`) weigh torques by it (a precision attempt's by the
    object's: on slender shapes chosen to measure it, the diameter gave as
    many precision grasps in more iterations); the paper's criterion and the
    acceptance on the true surface use the object's ``torque_scale``, as
    a plan's Q values do (its status trace's g_sQ row, ``final_sq``, is in
    this scale). Friction at a surface at most ``r``
    mm from an object's long axis (`axial_radius`) resists a torque about
    that axis of at most ``mu * r`` per unit of grip force. When that is
    less than `SLENDER` of the object's bounding radius (a rod, a pen, a
    handle), every grasp's Q distance stays near 0 along that torque at the
    default torque scale, and a row in those units is too flat to steer by:
    the rows then weigh torques at ``2 r`` (if less than the object's torque
    scale), the torques about the axis as forces at its surface.

    Parameters
    ----------
    obj : GraspObject
    mu : float
        Friction coefficient.

    Returns
    -------
    float
        ``min(obj.torque_scale, 2 * axial_radius(obj))`` if the object is
        `slender`, else ``obj.torque_scale`` (mm).

    Examples
    --------
    >>> import trimesh
    >>> from synergrasp import objects
    >>> rod = objects.from_mesh(trimesh.creation.cylinder(radius=10.0, height=300.0, sections=32), cache=False)
    >>> round(rod.torque_scale, 1), round(steering_scale(rod, 0.3), 1)
    (150.3, 20.0)
    >>> steering_scale(objects.ellipsoid(), 0.3) == objects.ellipsoid().torque_scale
    True
    """
    scale = float(obj.torque_scale)
    return min(scale, 2.0 * axial_radius(obj)) if slender(obj, mu) else scale


def _torque_scale(obj, torque_scale):
    """A row's torque scale: ``torque_scale`` (mm, checked) if given, else the object's."""
    return obj.torque_scale if torque_scale is None else positive_scalar(torque_scale, "torque_scale (mm)")


def _require(hand, obj):
    """TypeError unless ``hand`` is a SynergyHand and ``obj`` a GraspObject."""
    if not isinstance(hand, SynergyHand):
        raise TypeError(f"hand must be a SynergyHand, got {type(hand).__name__}")
    if not isinstance(obj, GraspObject):
        raise TypeError(f"obj must be a GraspObject, got {type(obj).__name__}")


def palm_face_point(hand, obj, u):
    """The point of the palm box's front face over the object's part nearest to it.

    The palm's skin points sample its front face at the centre, the corners
    and the edge midpoints, 42-48 mm apart on the paper's hand: a smaller
    object, a corner of one, or a bar lying across the palm can touch the
    face between them while every sample reads it 20-40 mm away, and a wrap
    then lifts the palm off an object it touches. Where a convex piece comes
    nearest a flat face, at a vertex or along an edge, one of its edges
    does. So every edge of the object's convex pieces (``obj.index.edges``)
    is clipped to the prism over the face (its extent in the palm frame's x
    and y, in front of the box's back face); of the clipped edges' ends, the
    one nearest the face's plane (the deepest, when some are behind it) is
    projected onto the face. The point is fixed to the palm, like the other
    skin points.

    Parameters
    ----------
    hand : SynergyHand
    obj : GraspObject
    u : (6 + n_syn,) float

    Returns
    -------
    (1, 3) float, or (0, 3) when no part of the object lies over the face
        World point (mm).

    Examples
    --------
    A 20 mm cube 2 mm in front of the face, between the samples: the
    nearest sample is 16 mm from it, the face point 2 mm.

    >>> import trimesh
    >>> from synergrasp import SynergyHand, objects
    >>> hand = SynergyHand.default()
    >>> u = np.zeros(hand.n_u)
    >>> center, axes = hand.palm_box(u)
    >>> corner = center + axes @ [0.5 * hand.palm_half_extents[0], 0.5 * hand.palm_half_extents[1], 0.0]
    >>> cube = objects.from_mesh(trimesh.creation.box((20.0, 20.0, 20.0)), cache=False)
    >>> cube = cube.transformed(trimesh.transformations.translation_matrix(corner + [0.0, 0.0, hand.palm_half_extents[2] + 12.0]))
    >>> samples = hand.skin_and_jacobian(u, "power")[1]
    >>> face = palm_face_point(hand, cube, u)
    >>> gaps = trimesh.proximity.closest_point(cube.to_mesh(), np.vstack([samples, face]))[1]
    >>> round(float(gaps[:-1].min()), 1), round(float(gaps[-1]), 1)
    (15.9, 2.0)
    """
    center, axes = hand.palm_box(u)
    half = np.asarray(hand.palm_half_extents, dtype=float)
    point = np.empty(3)
    if not _deepest_over_face(obj.index.vertices, obj.index.edges, center, axes, half, point):
        return np.zeros((0, 3))
    return (center + axes @ np.array([point[0], point[1], half[2]]))[None]


#: Depths (mm) within which two points over the palm's face count as equally deep (`palm_face_point`).
TIE = 1e-9


@kernel
def _deepest_over_face(vertices, edges, center, axes, half, out):
    """The deepest point (palm frame) of the edges clipped to the prism over the palm's face, into ``out``.

    The prism: ``|x| <= half[0]``, ``|y| <= half[1]``, ``z >= -half[2]``
    (in front of the box's back face). Each edge ``a + t d``, ``t`` in
    [0, 1], is clipped slab by slab; ``z`` is linear along it, so its least
    value over the clipped part is at one of the part's ends. Of ends as deep
    as the deepest within `TIE` (a piece's facet parallel to the face), the
    one nearest the face's centre: the choice does not hang on round-off.
    Returns whether any edge crosses the prism.
    """
    best = np.inf
    for e in range(len(edges)):
        i, j = edges[e, 0], edges[e, 1]
        p0, p1, p2 = vertices[i, 0] - center[0], vertices[i, 1] - center[1], vertices[i, 2] - center[2]
        q0, q1, q2 = vertices[j, 0] - center[0], vertices[j, 1] - center[1], vertices[j, 2] - center[2]
        a = (p0 * axes[0, 0] + p1 * axes[1, 0] + p2 * axes[2, 0],
             p0 * axes[0, 1] + p1 * axes[1, 1] + p2 * axes[2, 1],
             p0 * axes[0, 2] + p1 * axes[1, 2] + p2 * axes[2, 2])
        d = (q0 * axes[0, 0] + q1 * axes[1, 0] + q2 * axes[2, 0] - a[0],
             q0 * axes[0, 1] + q1 * axes[1, 1] + q2 * axes[2, 1] - a[1],
             q0 * axes[0, 2] + q1 * axes[1, 2] + q2 * axes[2, 2] - a[2])
        lo, hi = 0.0, 1.0
        for k in range(3):
            low, high = -half[k], (half[k] if k < 2 else np.inf)
            if d[k] == 0.0:
                if a[k] < low or a[k] > high:
                    lo = np.inf  # parallel to the slab and outside it
            else:
                t0, t1 = (low - a[k]) / d[k], (high - a[k]) / d[k]
                lo, hi = max(lo, min(t0, t1)), min(hi, max(t0, t1))
        if lo <= hi:
            t = lo if d[2] > 0.0 else hi
            x, y, z = a[0] + t * d[0], a[1] + t * d[1], a[2] + t * d[2]
            if z < best - TIE or (z <= best + TIE and x * x + y * y < out[0] * out[0] + out[1] * out[1]):
                best = min(best, z)
                out[0], out[1], out[2] = x, y, z
    return best < np.inf


def grasp_status(hand, obj, u, kind, *, mu=0.3, edges=8, backend="native", smoothing=None, far=None,
                 torque_scale=None) -> Status:
    """Status vector and Jacobian at configuration u.

    All rows come from one cP call: each row is the smallest cP over its skin
    points (``SynergyHand.skin_and_jacobian(u, kind)``: a power grasp's
    phalanges at five places along their axes, a precision grasp's at three;
    a fingertip's row also over its pad point, the precision hand point), with
    the derivative of the point attaining it.

    Parameters
    ----------
    hand : SynergyHand
    obj : GraspObject
    u : (8,) float
        Configuration (mm, rad, synergies).
    kind : {"precision", "power"}
        Which rows are contacts (see `status_rows`) and which hand points
        the sQ term scales the object to.
    mu, edges : float, int
        Friction model of the sQ term.
    backend : str
        LP backend.
    smoothing : float, optional
        Normal smoothing length (mm) of the sQ contacts (`smoothed_normals`).
    far : (n,) float, optional
        Per cP row, a distance (mm) beyond which the row may be only bounded:
        a row that the broad phase alone places beyond it gets no LP, its
        value is a lower bound of its cP (larger than ``far``), its Jacobian
        row is zero and its nearest point and normal are NaN
        (`group_contact_distance`). For a caller that reads a row only when
        it is nearer than that (the planner's clearance rows). Default: every
        row exact.
    torque_scale : float, optional
        The sQ row's torque scale (mm; default the object's ``torque_scale``;
        the planner's attempts pass `steering_scale`).

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
    >>> st.g.shape, st.J.shape, st.labels[:2]
    ((17,), (17, 8), ['T0', 'I0'])
    """
    _require(hand, obj)
    points, jac, skin, palm, jac_skin, jac_palm = hand.points_and_skin(u, kind)
    labels, contact, segment_rows = status_rows(hand, kind)
    if far is not None:
        far = np.asarray(far, dtype=float)
        if far.shape != (len(labels),) or np.isnan(far).any():
            raise ValueError(f"far must be {len(labels)} distances (one per cP row of a {kind} status), not NaN, "
                             f"got shape {far.shape}")
    k, m = skin.shape[:2]
    face = palm_face_point(hand, obj, u)
    palm, jac_palm = np.vstack([palm, face]), np.concatenate([jac_palm, hand.palm_jacobian(u, face)])
    groups = [np.repeat(segment_rows, m), np.full(len(palm), len(labels) - 1)]
    candidates = [skin.reshape(-1, 3), palm]
    jacobians = [jac_skin.reshape(k * m, 3, -1), jac_palm]
    if kind == "precision":  # a fingertip's row is also over its pad point
        groups.insert(0, np.arange(len(points)))
        candidates.insert(0, points)
        jacobians.insert(0, jac)
    candidates = np.vstack(candidates)
    ids = np.arange(len(candidates)) + (PRECISION_IDS if kind == "precision" else 0)
    cp, best = group_contact_distance(obj, candidates, np.concatenate(groups), backend, ids=ids, far=far)
    point_jac = np.concatenate(jacobians)[best]
    sc = obj.scaled_contacts(points, backend=backend)
    if smoothing is not None and positive_scalar(smoothing, "smoothing (mm)", zero=True):
        normals, jac_n = smoothed_normals(obj, sc.contact, sc.piece, smoothing)
        jac_normal = jac_n @ sc.jac_contact
    else:
        normals, jac_normal = sc.normal, sc.jac_normal
    sq = q_distance(sc.contact, normals, mu=mu, edges=edges, center=obj.center,
                    torque_scale=_torque_scale(obj, torque_scale), backend=backend, checked=True)
    # d g_sQ / d p_i through the contact carried back to the object and its normal
    grad_sq = np.einsum("ia,iab->ib", sq.grad_points, sc.jac_contact) + np.einsum("ia,iab->ib", sq.grad_normals, jac_normal)
    return Status(
        g=np.append(cp.value, sq.value),
        J=np.vstack([np.einsum("ka,kab->kb", cp.grad, point_jac), np.einsum("ia,iab->b", grad_sq, jac)]),
        labels=labels,
        contact=contact,
        segment_rows=segment_rows,
        points=points,
        nearest=cp.nearest,
        normals=cp.normal,
        pieces=cp.piece,
        row_points=candidates[best],
        point_jac=point_jac,
        lp_solves=cp.lp_solves + sc.lp_solves + sq.lp_solves,
    )


def contact_quality(obj, status, contact, *, mu=0.3, edges=8, backend="native", smoothing=None, torque_scale=None):
    """g_Q of the contacts and its gradient with respect to u: the row that improves a grasp's margin.

    Each row in ``contact`` touches at the foot of its hand point on the
    supporting plane of its nearest object point (the orthogonal projection
    on the facet), with the smoothed surface's normal there
    (`smoothed_normals`; the facet normal if ``smoothing`` is None). A
    contact slides on the surface as its hand point moves: its derivative is
    the hand point's motion projected on the plane, ``(I - n n^T) dp/du``.

    Parameters
    ----------
    obj : GraspObject
    status : Status
    contact : (n,) bool
        The rows in contact.
    mu, edges : float, int
    backend : str
    smoothing : float, optional
        Normal smoothing length (mm).
    torque_scale : float, optional
        mm; default the object's ``torque_scale`` (the planner's attempts
        pass `steering_scale`).

    Returns
    -------
    value : float
        The Q distance of the contacts.
    gradient : (len(u),) float
        Its derivative with respect to u.
    """
    n, pieces = status.normals[contact], status.pieces[contact]
    p, b = status.row_points[contact], status.nearest[contact]
    x = p - np.einsum("ij,ij->i", p - b, n)[:, None] * n  # the hand point's foot on the facet plane
    if smoothing is not None and positive_scalar(smoothing, "smoothing (mm)", zero=True):
        normals, jac_n = smoothed_normals(obj, x, pieces, smoothing)
    else:
        normals, jac_n = n, np.zeros((len(x), 3, 3))
    q = q_distance(x, normals, mu=mu, edges=edges, center=obj.center, torque_scale=_torque_scale(obj, torque_scale),
                   backend=backend, checked=True)
    slide = (np.eye(3) - n[:, :, None] * n[:, None, :]) @ status.point_jac[contact]  # (c, 3, nu)
    grad_x = q.grad_points + np.einsum("ia,iab->ib", q.grad_normals, jac_n)
    return q.value, np.einsum("ia,iab->b", grad_x, slide)
