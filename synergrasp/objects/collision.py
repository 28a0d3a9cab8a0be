"""Capsules (the hand's phalanges) and a box (its palm) against an object: penetration depths by python-fcl.

The depth of a shape is fcl's signed distance (GJK/EPA) to the object's
pieces: the translation that frees it from one convex piece. A shape's
distance to the object comes from fcl's own broad phase (a dynamic AABB
tree, `PieceIndex.fcl_manager`); whether it touches the object, from fcl's
collision test against the pieces whose bounding boxes come within
`TOUCH_PAD` of its own; only a shape that reaches the object is measured
against each piece.
"""

from __future__ import annotations

from dataclasses import dataclass

import fcl
import numpy as np

from .._checks import positive_scalar
from .._vectors import cross

#: Slack (mm) of the bounding-box test that picks the pieces a penetrating shape is measured against.
BOX_PAD = 1e-6
#: Slack (mm) of the bounding-box test that picks the pieces a shape is tested for contact with (``clear=False``):
#: wide enough to keep every piece fcl's own collision test could find touching it.
TOUCH_PAD = 1.0
#: Largest capsule radius (mm) `penetration` takes: phalanges are a few to tens of mm thick (fcl's signed distance
#: to a capsule of 1000 mm takes seconds, of 3000 mm over a minute).
MAX_RADIUS = 500.0
_EYE = np.eye(3)


@dataclass(frozen=True)
class Penetration:
    """Result of `GraspObject.penetration` (capsules, and optionally a box, against the object).

    The k entries of the per-shape arrays are the capsules in their order,
    then the box if one was given (k = capsules + 1).

    Attributes
    ----------
    depth : float
        Deepest penetration depth over all capsules (mm), 0 if none collides.
    index : int
        Index of the deepest capsule, -1 if none collides.
    depths : (k,) float
        Penetration depth of each capsule (0 when clear).
    distances : (k,) float
        Signed distance of each capsule to the object (negative = penetration).
    piece : int
        Piece the deepest capsule penetrates most, -1 if none.
    witnesses : (k, 2, 3) float
        For each penetrating capsule, fcl's witness points in the piece it
        penetrates most: the capsule's point deepest in the object, then the
        object's point deepest in the capsule (the translation from the first
        to the second frees the capsule, its length is the depth); NaN for the
        capsules that do not penetrate.

    Notes
    -----
    The depth is fcl's signed distance (GJK/EPA), the translation that frees
    the capsule from one convex piece; for a capsule through several pieces it
    is the largest such depth, a lower bound of the depth into the union.
    """

    depth: float
    index: int
    depths: np.ndarray
    distances: np.ndarray
    piece: int
    witnesses: np.ndarray

    @property
    def collision(self) -> bool:
        """True when some capsule penetrates the object."""
        return self.index >= 0


def _frames(z):
    """(k, 3, 3) rotations whose z axes are the unit rows of ``z`` (k, 3); x is normal to the axis least aligned with z."""
    x = cross(np.eye(3)[np.argmin(np.abs(z), axis=1)], z)
    x /= np.sqrt(np.einsum("ij,ij->i", x, x))[:, None]
    return np.stack([x, cross(z, x), z], axis=2)


def _box(box):
    """``(centre (3,), axes (3, 3), half_extents (3,))`` of a box as float arrays, checked."""
    try:
        centre, axes, half = (np.asarray(a, dtype=float) for a in box)
    except (TypeError, ValueError) as exc:
        raise TypeError("box must be (centre (3,), axes (3, 3), half_extents (3,)) of numbers") from exc
    if centre.shape != (3,) or axes.shape != (3, 3) or half.shape != (3,):
        raise ValueError(f"box must be (centre (3,), axes (3, 3), half_extents (3,)), got shapes "
                         f"{centre.shape}, {axes.shape}, {half.shape}")
    if not (np.isfinite(centre).all() and np.isfinite(axes).all() and np.isfinite(half).all()):
        raise ValueError("box contains NaN or inf")
    if (half <= 0).any():
        raise ValueError(f"box half_extents must be > 0, got {half.tolist()}")
    if not (np.abs(axes.T @ axes - _EYE) <= 1e-9 + 1e-5 * _EYE).all() or np.linalg.det(axes) < 0:
        raise ValueError("box axes must be a rotation matrix (orthonormal columns, determinant +1)")
    return centre, axes, half


def _overlapping(lower, upper, boxes, pad):
    """(k, J) bool: whether each of k boxes ``[lower, upper]`` (k, 3) comes within ``pad`` of each of J ``boxes`` (J, 2, 3)."""
    return ((lower[:, None] <= boxes[None, :, 1] + pad) & (upper[:, None] >= boxes[None, :, 0] - pad)).all(axis=2)


def _touches(shape, pieces):
    """fcl's collision test of one shape against pieces in turn, as its broad phase's callback runs it."""
    request, result = fcl.CollisionRequest(), fcl.CollisionResult()
    for piece in pieces:
        fcl.collide(piece, shape, request, result)
        if result.is_collision:
            return True
    return False


def penetration(obj, segments, radius, box=None, *, clear=True) -> Penetration:
    """Deepest capsule (and box) penetration; see `GraspObject.penetration`."""
    if not isinstance(clear, (bool, np.bool_)):  # clear="no" would be true
        raise TypeError(f"clear must be True or False, got {clear!r}")
    try:
        seg = np.asarray(segments, dtype=float)
    except (TypeError, ValueError) as exc:
        raise TypeError(f"segments must be a numeric (k, 2, 3) array, got {type(segments).__name__}") from exc
    if seg.ndim != 3 or seg.shape[1:] != (2, 3) or len(seg) == 0:
        raise ValueError(f"segments must have shape (k, 2, 3) (end points of k capsule axes), got {seg.shape}")
    if not np.isfinite(seg).all():
        raise ValueError("segments contains NaN or inf")
    k = len(seg)
    if isinstance(radius, (bool, np.bool_)):
        raise TypeError(f"radius must be a number or an array of ({k},) numbers, got bool")
    try:
        r = np.asarray(radius, dtype=float)
    except (TypeError, ValueError):
        raise TypeError(f"radius must be a number or an array of ({k},) numbers, got {type(radius).__name__}") from None
    if r.ndim == 0:
        r = np.full(k, positive_scalar(float(r), "radius"))
    elif r.shape != (k,):
        raise ValueError(f"radius must be a number or shape ({k},), got shape {r.shape}")
    elif not (np.isfinite(r).all() and (r > 0).all()):
        raise ValueError("radius must be finite and > 0 for every capsule")
    if r.max() > MAX_RADIUS:
        raise ValueError(f"a capsule radius of {r.max():g} mm is more than the {MAX_RADIUS:g} mm a hand's phalanx could "
                         "have (the distance queries then take minutes): give radii in mm")
    axes = seg[:, 1] - seg[:, 0]
    lengths = np.sqrt(np.einsum("ij,ij->i", axes, axes))
    point = lengths <= 1e-12
    lower = np.minimum(seg[:, 0], seg[:, 1]) - r[:, None]  # the shapes' axis-aligned bounding boxes
    upper = np.maximum(seg[:, 0], seg[:, 1]) + r[:, None]
    if box is not None:
        box = _box(box)
        reach = np.abs(box[1]) @ box[2]
        lower, upper = np.vstack([lower, box[0] - reach]), np.vstack([upper, box[0] + reach])
    n_shapes = len(lower)
    boxes = obj.index.boxes
    meets = _overlapping(lower, upper, boxes, BOX_PAD)
    rotations = _frames(axes / np.where(point, 1.0, lengths)[:, None] + point[:, None] * [0.0, 0.0, 1.0])
    centres = 0.5 * (seg[:, 0] + seg[:, 1])

    def shape(i):  # the fcl object of shape i
        if i == k:
            return fcl.CollisionObject(fcl.Box(*(2.0 * box[2])), fcl.Transform(box[1], box[0]))
        if point[i]:
            return fcl.CollisionObject(fcl.Sphere(float(r[i])), fcl.Transform(np.eye(3), centres[i]))
        return fcl.CollisionObject(fcl.Capsule(float(r[i]), float(lengths[i])), fcl.Transform(rotations[i], centres[i]))

    request = fcl.DistanceRequest(enable_signed_distance=True)
    distances = np.full(n_shapes, np.inf)
    deepest_piece = np.full(n_shapes, -1)
    witnesses = np.full((n_shapes, 2, 3), np.nan)
    touch = None if clear else _overlapping(lower, upper, boxes, TOUCH_PAD)
    for i in range(n_shapes) if clear else np.flatnonzero(touch.any(axis=1)):  # a shape near no piece touches none
        fcl_shape = shape(i)
        if clear:
            data = fcl.DistanceData(request=request)
            obj.index.fcl_manager.distance(fcl_shape, data, fcl.defaultDistanceCallback)
            distances[i] = data.result.min_distance
        elif _touches(fcl_shape, [obj.convex[j].fcl for j in np.flatnonzero(touch[i])]):
            distances[i] = -1.0  # only the shapes that touch a piece are measured: fcl's collision test of those near it
        if distances[i] < 0:  # measured against each piece whose bounding box its own meets (the others are apart)
            near = np.flatnonzero(meets[i])
            near = near if len(near) else np.arange(len(boxes))
            results = [fcl.DistanceResult() for _ in near]
            per = [fcl.distance(fcl_shape, obj.convex[j].fcl, request, res) for j, res in zip(near, results)]
            distances[i] = min(per)
            deepest_piece[i] = int(near[np.argmin(per)])
            witnesses[i] = results[int(np.argmin(per))].nearest_points
    depths = np.maximum(-distances, 0.0)
    index = int(np.argmax(depths)) if (depths > 0).any() else -1
    return Penetration(
        depth=float(depths[index]) if index >= 0 else 0.0,
        index=index,
        depths=depths,
        distances=distances,
        piece=int(deepest_piece[index]) if index >= 0 else -1,
        witnesses=witnesses,
    )
