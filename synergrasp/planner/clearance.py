"""Clearance of the hand from the object: signed distances of its collision shapes, at poses and along paths.

The hand's collision shapes are its phalanx capsules and its palm box
(`synergrasp.SynergyHand.segments`); the object is the union of its convex
pieces (``GraspObject.convex``). The clearance of a shape is its signed
distance to the object by python-fcl (GJK/EPA): the gap (mm) when it is
apart, minus the penetration depth when it overlaps a piece (the shortest
translation that frees it from the piece it penetrates most). The clearance
of a pose is the smallest over the shapes.

`path_clearance` checks a path densely: between two consecutive
configurations the hand moves along the straight line in ``u``, and that
motion is cut until nothing can cross the object unseen (see its notes).
"""

from __future__ import annotations

from dataclasses import dataclass

import fcl
import numpy as np

from .._checks import as_points, positive_scalar
from ..hand import SynergyHand
from ..objects import GraspObject

__all__ = ["PALM", "HandClearance", "PathClearance", "clearance_labels", "hand_and_object", "hand_clearance", "path_clearance"]

#: Label of the palm box among the hand's collision shapes (the capsules carry their segment's label).
PALM = "palm"
#: Motion bound safety: the chord between two samples of a point is scaled by this to bound its arc.
_ARC = 1.02
#: Deepest bisection of one interval (2**_MAX_DEPTH pieces at most).
_MAX_DEPTH = 16
#: Most pieces (each turning no angle more than ``max_angle``) a checked path may be cut into: about a minute's work.
MAX_PIECES = 100_000


def _bounded(lo, hi, motion):
    """Row ``hi`` with the least clearance the interval from ``lo`` can have where the bisection stopped unresolved.

    No point moves more than ``motion`` between the two rows, so at any pose between them every shape is at least
    ``(lo + hi - motion) / 2`` from the object (its clearance at ``lo`` less the way from ``lo``, and at ``hi`` less
    the way to ``hi``); the row keeps the smaller of that and its own clearance, its slack lowered alike.
    """
    bound = 0.5 * (lo[2] + hi[2] - motion)
    if bound >= hi[2]:
        return hi
    return (hi[0], hi[1], bound, hi[3], hi[4] - (hi[2] - bound))


def hand_and_object(hand, obj):
    """The hand (the paper's if None) and the object, checked: what the functions that take both start with.

    Parameters
    ----------
    hand : SynergyHand or None
    obj : GraspObject

    Returns
    -------
    SynergyHand

    Raises
    ------
    TypeError
        If ``hand`` is not a SynergyHand (or None) or ``obj`` not a GraspObject.
    """
    hand = SynergyHand.default() if hand is None else hand
    if not isinstance(hand, SynergyHand):
        raise TypeError(f"hand must be a SynergyHand, got {type(hand).__name__}")
    if not isinstance(obj, GraspObject):
        raise TypeError(f"obj must be a GraspObject (synergrasp.objects), got {type(obj).__name__}")
    return hand


def clearance_labels(hand):
    """Names of the hand's collision shapes, in the order of `hand_clearance`.

    Parameters
    ----------
    hand : SynergyHand

    Returns
    -------
    list of str
        The capsules' labels (``"T1"``, ..., ``"L3"`` for the paper's hand), then `PALM`.

    Examples
    --------
    >>> from synergrasp import SynergyHand
    >>> labels = clearance_labels(SynergyHand.default())
    >>> len(labels), labels[0], labels[-1]
    (16, 'T1', 'palm')
    """
    return list(hand.segments(np.zeros(hand.n_u)).labels) + [PALM]


class HandClearance:
    """The hand's collision shapes against one object, ready for many queries.

    Builds the fcl shapes once (one capsule per phalanx, the palm box) and a
    bounding sphere per convex piece, so that a query visits only the pieces
    that can be nearest: a shape's exact distance to a piece (fcl) is
    computed only while the piece's bounding-sphere bound is below the best
    distance found so far.

    Parameters
    ----------
    hand : SynergyHand
    obj : GraspObject

    Attributes
    ----------
    labels : list of str
        The shapes' names (`clearance_labels`).
    radius : float
        The capsules' radius (mm).

    Raises
    ------
    TypeError
        If ``hand`` is not a SynergyHand or ``obj`` not a GraspObject.

    Examples
    --------
    >>> import numpy as np
    >>> import synergrasp as sg
    >>> check = HandClearance(sg.SynergyHand.default(), sg.objects.get("ellipsoid"))
    >>> u = np.array([0.0, 0.0, 250.0, np.pi, 0.0, 0.0, -1.0, 1.0])   # palm down above the pole
    >>> value, shape = check.at(u)
    >>> round(value, 1), check.labels[shape]     # the open hand's thumb reaches out farthest
    (98.4, 'T3')
    >>> bool(value == check.shapes(u).min())
    True
    """

    def __init__(self, hand, obj):
        self.hand = hand = hand_and_object(hand, obj)
        rest = hand.segments(np.zeros(hand.n_u))
        self.radius = float(rest.radius)
        lengths = np.linalg.norm(rest.capsules[:, 1] - rest.capsules[:, 0], axis=1)
        self._shapes = [fcl.CollisionObject(fcl.Capsule(self.radius, float(length))) for length in lengths]
        self._shapes.append(fcl.CollisionObject(fcl.Box(*(2.0 * rest.palm_half_extents))))
        self._pieces = [piece.fcl for piece in obj.convex]
        self._centres = np.array([0.5 * (p.vertices.min(axis=0) + p.vertices.max(axis=0)) for p in obj.convex])
        self._reach = np.array([np.linalg.norm(p.vertices - c, axis=1).max() for p, c in zip(obj.convex, self._centres)])
        self._request = fcl.DistanceRequest(enable_signed_distance=True)
        self.labels = list(rest.labels) + [PALM]

    def shapes(self, u):
        """Signed distance of every shape to the object at configuration u.

        Parameters
        ----------
        u : (6 + n_syn,) float

        Returns
        -------
        (k + 1,) float
            mm, in the order of ``labels`` (see `hand_clearance`).

        Raises
        ------
        ValueError
            If ``u`` does not fit the hand or is not finite.
        """
        self._place(u)
        bounds = self._bounds()
        return np.array([self._nearest(k, row, np.inf) for k, row in enumerate(bounds)])

    def at(self, u):
        """The clearance of configuration u: the smallest signed distance over the shapes.

        Parameters
        ----------
        u : (6 + n_syn,) float

        Returns
        -------
        value : float
            mm.
        shape : int
            Index into ``labels`` of the shape it belongs to.

        Raises
        ------
        ValueError
            If ``u`` does not fit the hand or is not finite.
        """
        self._place(u)
        return self._smallest()[:2]

    def near(self, u, within):
        """The shapes nearer the object than ``within`` at configuration u, with fcl's witness points.

        Parameters
        ----------
        u : (6 + n_syn,) float
        within : float
            mm.

        Returns
        -------
        shapes : (m,) int
            Indices into ``labels``.
        distances : (m,) float
            Their signed distances (mm).
        on_shape, on_object : (m, 3) float
            fcl's witness points in the piece nearest each shape (or the one
            it penetrates most): apart, the closest points of shape and
            object; overlapping, the shape's point deepest in the piece and
            the piece's point deepest in the shape. Moving the shape along
            ``sign(d) * (on_shape - on_object)`` increases its distance.

        Raises
        ------
        ValueError
            If ``u`` does not fit the hand or is not finite.
        """
        self._place(u)
        bounds = self._bounds()
        rows = []
        for k, row in enumerate(bounds):
            best, witness = within, None
            for piece in np.argsort(row):
                if row[piece] >= best:
                    break
                result = fcl.DistanceResult()
                d = fcl.distance(self._shapes[k], self._pieces[piece], self._request, result)
                if d < best:
                    best, witness = d, result.nearest_points
            if witness is not None:
                rows.append((k, best, *witness))
        shapes, distances, on_shape, on_object = zip(*rows) if rows else ((), (), (), ())
        return (np.array(shapes, dtype=int), np.array(distances, dtype=float),
                np.array(on_shape, dtype=float).reshape(-1, 3), np.array(on_object, dtype=float).reshape(-1, 3))

    def gradients(self, u, within):
        """The phalanx capsules nearer the object than ``within``, their distances and gradients with respect to u.

        A capsule's distance is the distance of its axis segment minus the
        radius, so it changes as its axis point nearest the object (or, when
        it overlaps, the one under its deepest point) moves along the
        direction that frees it: ``grad = n . J``, with ``n`` from fcl's
        witness points (`near`) and ``J`` interpolated between the
        Jacobians of the capsule's ends (`SynergyHand.segments_and_jacobian`).
        The palm box is left out.

        Parameters
        ----------
        u : (6 + n_syn,) float
        within : float
            mm.

        Returns
        -------
        shapes : (m,) int
            Indices into ``labels`` (capsules only).
        distances : (m,) float
            mm.
        gradients : (m, 6 + n_syn) float
            d distance / d u (mm per mm, per rad, per unit of synergy).

        Examples
        --------
        The synergy columns against a central difference:

        >>> import numpy as np
        >>> import synergrasp as sg
        >>> hand, obj = sg.SynergyHand.default(), sg.objects.get("ellipsoid")
        >>> check = HandClearance(hand, obj)
        >>> u = np.array([0.0, -20.0, 95.0, np.pi, 0.0, 0.0, 0.2, 0.1])
        >>> shapes, d, grad = check.gradients(u, 20.0)
        >>> h = np.r_[0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1e-6, 0.0]
        >>> fd = (check.shapes(u + h)[shapes] - check.shapes(u - h)[shapes]) / 2e-6
        >>> bool(np.allclose(grad[:, 6], fd, atol=1e-4))
        True
        """
        shapes, distances, on_shape, on_object = self.near(u, within)
        ends, jac = self.hand.segments_and_jacobian(self.hand.check_u(u))
        keep, rows = [], []
        for i, (k, d, p_s, p_o) in enumerate(zip(shapes, distances, on_shape, on_object)):
            n = np.sign(d) * (p_s - p_o)  # the direction that frees it
            if k >= len(ends) or np.linalg.norm(n) < 1e-9:
                continue
            n /= np.linalg.norm(n)
            a, b = ends[k]
            s = float(np.clip((p_s + self.radius * n - a) @ (b - a) / ((b - a) @ (b - a)), 0.0, 1.0))
            keep.append(i)
            rows.append(n @ ((1.0 - s) * jac[k, 0] + s * jac[k, 1]))
        return shapes[keep], distances[keep], np.array(rows).reshape(-1, self.hand.n_u)

    def along(self, path, *, resolution=0.25, max_angle=0.1, stop_below=None):
        """The clearance along a path, checked densely; see `path_clearance`."""
        path = as_points(path, "path", dim=self.hand.n_u)
        resolution = positive_scalar(resolution, "resolution")
        max_angle = positive_scalar(max_angle, "max_angle")
        floors = None
        if stop_below is not None:
            floors = np.broadcast_to(np.asarray(stop_below, dtype=float), (len(self.labels),)) \
                if np.ndim(stop_below) == 0 else np.asarray(stop_below, dtype=float)
            if floors.shape != (len(self.labels),) or np.isnan(floors).any():
                raise ValueError(f"stop_below must be a number or one per shape ({len(self.labels)}: {self.labels}), "
                                 f"got {stop_below!r}")
        step = resolution * self.radius

        def sample(u):
            points = self._place(u)
            return (u, points, *self._smallest(floors))

        def below(row):  # a shape under its floor: stop there
            return floors is not None and row[4] < 0.0

        if len(path) - 1 > MAX_PIECES:  # (before its pieces are counted, a loop over the rows)
            raise ValueError(f"the path has {len(path)} rows, more than the {MAX_PIECES:.0e} pieces synergrasp checks "
                             "(minutes of fcl queries): give its key poses; the check fills in between them")
        pieces = [_pieces(self.hand, u_a, u_b, max_angle) for u_a, u_b in zip(path[:-1], path[1:])]
        if sum(pieces) > MAX_PIECES:
            raise ValueError(f"the path turns a joint or an Euler angle by {sum(pieces) * max_angle:.3g} rad in all, "
                             f"{sum(pieces):.3g} pieces of at most max_angle = {max_angle:g} rad, more than the "
                             f"{MAX_PIECES:.0e} synergrasp checks (minutes of fcl queries): give a path of plausible "
                             "poses (angles in rad, synergies within their limits) or a larger max_angle")
        rows, given = [sample(path[0])], [True]
        for (u_a, u_b), n in zip(zip(path[:-1], path[1:]), pieces):
            for i in range(1, n + 1):
                if below(rows[-1]):
                    break
                end = sample(u_b if i == n else u_a + (u_b - u_a) * (i / n))
                stack = [(rows[-1], end, 0)]
                while stack and not below(rows[-1]):  # depth first, left half first: rows come in path order
                    lo, hi, depth = stack.pop()
                    motion = _ARC * float(np.linalg.norm(hi[1] - lo[1], axis=1).max())
                    resolved = motion <= step or lo[2] + hi[2] - motion > 0.0
                    if resolved or depth >= _MAX_DEPTH or below(hi):
                        given.append(hi is end and i == n)
                        if not resolved and not below(hi):  # out of depth, not shown clear: a bound, not a sample
                            hi = _bounded(lo, hi, motion)
                        rows.append(hi)
                        continue
                    mid = sample(0.5 * (lo[0] + hi[0]))
                    stack += [(mid, hi, depth + 1), (lo, mid, depth + 1)]
        values = np.array([r[2] for r in rows])
        slack = np.array([r[4] for r in rows])
        return PathClearance(
            path=np.array([r[0] for r in rows]),
            clearance=values,
            closest=np.array([r[3] for r in rows], dtype=int),
            given=np.array(given, dtype=bool),
            labels=list(self.labels),
            slack=slack,
            complete=not any(below(r) for r in rows),
        )

    # ------------------------------------------------------------------ internals

    def _place(self, u):
        """Move the fcl shapes to configuration u; returns the capsule ends and palm corners, (m, 3)."""
        geo = self.hand.segments(self.hand.check_u(u))
        a, b = geo.capsules[:, 0], geo.capsules[:, 1]
        for shape, rotation, centre in zip(self._shapes, _z_along(b - a), 0.5 * (a + b)):
            shape.setTransform(fcl.Transform(rotation, centre))
        self._shapes[-1].setTransform(fcl.Transform(geo.palm_axes, geo.palm_center))
        self._geo = geo
        return np.vstack([geo.capsules.reshape(-1, 3), geo.palm_corners])

    def _bounds(self):
        """(shapes, pieces) float: a lower bound of each placed shape's distance to each piece (bounding spheres)."""
        geo, c = self._geo, self._centres
        a, b = geo.capsules[:, None, 0], geo.capsules[:, None, 1]
        ab = b - a
        t = np.clip(np.einsum("kpi,kpi->kp", c - a, ab) / np.einsum("kpi,kpi->kp", ab, ab), 0.0, 1.0)
        capsule = np.linalg.norm(a + t[..., None] * ab - c, axis=-1) - self.radius
        local = (c - geo.palm_center) @ geo.palm_axes
        box = np.linalg.norm(np.maximum(np.abs(local) - geo.palm_half_extents, 0.0), axis=1)
        return np.vstack([capsule, box[None]]) - self._reach

    def _smallest(self, floors=None):
        """The smallest signed distance over the placed shapes, its shape, and the smallest ``distance - floors``.

        Shapes are visited nearest bound first, and only while their bound can
        lower either minimum. Without ``floors`` the third value is the first.
        """
        bounds = self._bounds()
        lows = bounds.min(axis=1)
        offsets = np.zeros(len(lows)) if floors is None else floors
        best, which, slack = np.inf, -1, np.inf
        for k in np.argsort(lows):
            if lows[k] >= best and lows[k] - offsets[k] >= slack:
                continue
            d = self._nearest(k, bounds[k], max(best, slack + offsets[k]))  # exact below that cap
            if d < best:
                best, which = d, int(k)
            slack = min(slack, d - offsets[k])
        return best, which, slack

    def _nearest(self, shape, bounds, cap):
        """Signed distance of one placed shape to the object, exact when below ``cap`` (nearest pieces first)."""
        best = cap
        for piece in np.argsort(bounds):
            if bounds[piece] >= best:
                break
            best = min(best, fcl.distance(self._shapes[shape], self._pieces[piece], self._request, fcl.DistanceResult()))
        return float(best)


def _z_along(axes):
    """Unit quaternions ``(w, x, y, z)`` turning +z onto each axis (shortest arc), (k, 4) from (k, 3)."""
    z = axes / np.linalg.norm(axes, axis=1, keepdims=True)
    q = np.column_stack([1.0 + z[:, 2], -z[:, 1], z[:, 0], np.zeros(len(z))])  # (1 + e_z.z, e_z x z)
    flip = q[:, 0] < 1e-9  # the axis is -z: half a turn about x
    q[flip] = [0.0, 1.0, 0.0, 0.0]
    return q / np.linalg.norm(q, axis=1, keepdims=True)


def hand_clearance(hand, obj, u):
    """Signed distance of each of the hand's collision shapes to the object at one configuration.

    Parameters
    ----------
    hand : SynergyHand
    obj : GraspObject
    u : (6 + n_syn,) float
        Configuration ``[px, py, pz, phi1, phi2, phi3, z...]`` (mm, rad).

    Returns
    -------
    (k + 1,) float
        mm, in the order of `clearance_labels`: each phalanx capsule, then the
        palm box. Positive: the gap to the object; negative: minus the
        penetration depth into the piece the shape penetrates most.

    Raises
    ------
    TypeError
        If ``hand`` is not a SynergyHand or ``obj`` not a GraspObject.
    ValueError
        If ``u`` does not fit the hand or is not finite.

    Examples
    --------
    The open hand 100 mm above the ellipsoid's 50 mm pole, palm down:

    >>> import numpy as np
    >>> import synergrasp as sg
    >>> hand, obj = sg.SynergyHand.default(), sg.objects.get("ellipsoid")
    >>> u = np.array([0.0, 0.0, 150.0, np.pi, 0.0, 0.0, -1.0, 1.0])
    >>> d = hand_clearance(hand, obj, u)
    >>> d.shape, round(float(d[-1]), 1)        # the palm box's face is 10 mm below its centre
    ((16,), 90.0)
    """
    return HandClearance(hand, obj).shapes(u)


@dataclass(frozen=True)
class PathClearance:
    """The clearance along a path, checked densely (`path_clearance`).

    Attributes
    ----------
    path : (m, 6 + n_syn) float
        The configurations checked, in order: the given ones and those
        inserted between them. Between two consecutive rows the hand moves
        along the straight line in ``u``; no part of it comes nearer the
        object there than both ends allow (see `path_clearance`).
    clearance : (m,) float
        Smallest signed distance (mm) of the capsules and the palm box to the
        object at each row of ``path``.
    closest : (m,) int
        Which shape has that distance (an index into ``labels``).
    given : (m,) bool
        The row is one of the given configurations (False: inserted).
    labels : list of str
        The shapes' names (`clearance_labels`).
    slack : (m,) float
        Smallest margin of the shapes above ``stop_below`` at each row
        (mm): ``min_k (distance_k - stop_below_k)``; the clearance itself
        without ``stop_below``.
    complete : bool
        False when the check stopped early at a pose where a shape was below
        its ``stop_below`` (the arrays end there).
    """

    path: np.ndarray
    clearance: np.ndarray
    closest: np.ndarray
    given: np.ndarray
    labels: list
    slack: np.ndarray
    complete: bool = True

    @property
    def deepest(self) -> int:
        """Row of ``path`` with the smallest clearance."""
        return int(np.argmin(self.clearance))

    @property
    def depth(self) -> float:
        """Deepest penetration along the path (mm, 0 if the hand never touches the object)."""
        return max(0.0, -float(self.clearance.min()))

    @property
    def deepest_shape(self) -> str:
        """The shape at the smallest clearance (``"T3"``, ..., `PALM`)."""
        return self.labels[int(self.closest[self.deepest])]


def path_clearance(hand, obj, path, *, resolution=0.25, max_angle=0.1, stop_below=None):
    """The hand's clearance from the object along a path, checked densely.

    Between two consecutive configurations the hand moves along the straight
    line in ``u``. Each such motion is first cut into pieces in which no
    joint angle and no Euler angle changes by more than ``max_angle``; then
    each piece is halved until either

    - the hand moves less than ``resolution`` times the capsule radius
      between its ends (the largest displacement of a capsule end or a palm
      box corner), or
    - its ends are clear enough that nothing can reach the object in
      between: with clearances ``c_a`` and ``c_b`` at the ends and the hand
      moving at most ``m`` in between, no point comes nearer than
      ``(c_a + c_b - m) / 2`` (a point that moves ``s`` changes its distance
      to the object by at most ``s``), and that is > 0.

    So a shape crosses the object only where the hand moves less than
    ``resolution * radius`` between two checked poses, deeper than their
    clearance by at most half that.

    Parameters
    ----------
    hand : SynergyHand
    obj : GraspObject
    path : (n, 6 + n_syn) float
        Configurations in order (n >= 1).
    resolution : float
        Largest motion between two checked poses near the object, as a
        fraction of the capsule radius (0.25: 2 mm for the paper's hand).
    max_angle : float
        Largest change of a joint or Euler angle between two checked poses
        (rad), so that every point moves nearly straight and the chord
        between two poses bounds its path (scaled by 1.02).
    stop_below : float or (k + 1,) float, optional
        Stop at the first pose where a shape's clearance is below this (mm;
        one value for all the shapes, or one per shape in the order of
        `clearance_labels`); the result is then marked incomplete.

    Returns
    -------
    PathClearance

    Raises
    ------
    TypeError
        If ``hand`` is not a SynergyHand, ``obj`` not a GraspObject or
        ``path`` not numeric.
    ValueError
        If ``path`` is not an (n, 6 + n_syn) finite array, ``resolution``
        or ``max_angle`` is not a positive number, or ``stop_below`` is not a
        number or one per shape.

    Examples
    --------
    Two configurations 200 mm either side of the ellipsoid, both clear of it:
    the straight motion between them sweeps the hand through it, and the
    check finds that between the two.

    >>> import numpy as np
    >>> import synergrasp as sg
    >>> hand, obj = sg.SynergyHand.default(), sg.objects.get("ellipsoid")
    >>> left = np.array([-200.0, 0.0, 0.0, np.pi / 2, 0.0, 0.0, 0.0, 0.0])
    >>> right = left + [400.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0]
    >>> check = path_clearance(hand, obj, [left, right])
    >>> check.clearance[[0, -1]].round(1).tolist()      # mm, at the two given poses
    [128.0, 128.0]
    >>> len(check.path) > 2, check.deepest_shape, round(check.depth)
    (True, 'palm', 50)
    """
    return HandClearance(hand, obj).along(path, resolution=resolution, max_angle=max_angle, stop_below=stop_below)


def _pieces(hand, u_a, u_b, max_angle):
    """Number of equal pieces of the straight motion u_a -> u_b in which no joint or Euler angle turns more than max_angle."""
    qa = np.fromiter(hand.joint_angles(u_a).values(), float)
    qb = np.fromiter(hand.joint_angles(u_b).values(), float)
    turn = max(np.abs(qb - qa).max(initial=0.0), np.abs(u_b[3:6] - u_a[3:6]).max())
    return max(1, int(np.ceil(turn / max_angle)))
