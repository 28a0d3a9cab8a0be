"""Where the planner's attempts start: poses placed by the object's geometry.

* `pinch_seeds` (precision grasps): pairs of opposed surface points whose
  distance the hand can span, those a fingertip reaches without going into
  a recess of the object (`recess`) first; the thumb and the index/middle
  fingers are put on either side of a pair, the hand opened a little wider
  than the pair and rolled about it so that the hand stays out of the
  object, then moved back along the palm normal: the attempt reaches in and
  closes.
* `wrap_seeds` (power grasps): the palm laid on surface points, rolled about
  their normal, with the synergies on a grid; the poses where most phalanges
  touch and none cuts in (screened on the object's `DistanceGrid`, then
  checked exactly) come first: a pose that already makes a grasp as soon as
  it is checked, the others a batch at a time, by their grasp quality.
* `direction_starts`: the hand in front of the object along its principal axes
  and the diagonals between them, palm facing its centre, then the same turned
  a quarter turn about the approach (the precision starts after the pinch
  seeds). `power_schedule`: the same directions, each with two pre-shapes (the
  power starts after the wrap seeds).
* `start_configuration`: one such pose from a given direction.
"""

from __future__ import annotations

import itertools
import json
from dataclasses import dataclass

import numpy as np
from scipy.spatial.transform import Rotation

from .._checks import as_points, as_vector, finite_scalar, integer, positive_scalar
from .._jit import clock, kernel
from .._vectors import sphere_directions
from ..hand import rotation_xyz
from ..objects.mesh_queries import MeshQueries
from .clearance import hand_and_object
from .status import grasp_status, hand_penetration, principal_axes
from .stop import check_grasp

#: Largest angle (deg) between one point's inward normal and the other's outward normal in a pair.
PAIR_ANGLE = 30.0
#: Half-angle (deg) of the cone about a surface point's normal in which `recess` looks for the way out.
RECESS_CONE = 60.0


#: Rolls (rad) of the hand about the approach of `direction_starts`, each over all the directions in turn.
DIRECTION_ROLLS = (0.0, np.pi / 2)
#: Directions of `recess`.
_DIRECTIONS = sphere_directions(64)
#: Surface points sampled per plan for the pairs.
PAIR_SAMPLES = 200
#: Rolls of the hand about a pair's axis tried for each seed.
ROLLS = 12
#: Pair width (mm) tried first: pairs are taken in order of their width's distance from it plus their
#: axis's distance from the object's centre plus their points' `recess`.
PAIR_WIDTH = 65.0
#: Surface points where a wrap seed lays the palm, per plan.
WRAP_SAMPLES = 64
#: Rolls of the palm about the surface normal tried at each point.
WRAP_ROLLS = 8
#: Synergy values per synergy on the wrap seeds' grid (between the hand's limits).
WRAP_GRID = 5
#: Most synergy values on the wrap seeds' grid (the paper's hand: 5 x 5; more synergies get fewer values each).
WRAP_GRID_POINTS = 128
#: Gap (mm) between the palm point and the surface in a wrap seed.
WRAP_STANDOFF = 2.0
#: Wrap seeds per batch (a batch checks at most four times as many poses).
WRAP_SEEDS = 12
#: Palm orientations with ``|R[0, 2]|`` (the sine of the second XYZ Euler angle) above this are not used
#: as starts: near the angles' lock their Jacobian is singular.
GIMBAL = 0.95


@dataclass(frozen=True)
class Start:
    """One start of an attempt.

    Attributes
    ----------
    u : (6 + n_syn,) float
        The start configuration.
    kind : str
        How it was placed: ``"pinch"`` (a pair of opposed surface points),
        ``"direction"``, ``"wide"`` or ``"cupped"`` (power pre-shapes), or
        ``"given"`` (the caller's ``u0``).
    detail : dict
        Its placement: the pair and its width, or the direction.
    """

    u: np.ndarray
    kind: str
    detail: dict


def start_configuration(hand, obj, approach=(0.0, 1.0, 0.0), distance=150.0, clearance=None, palm_centred=False,
                        roll=0.0):
    """A start in front of the object: mean pose, palm facing the object's centre.

    The palm is ``distance`` mm from the centre along ``approach`` (farther if
    ``clearance`` asks for it) and faces it; the hand is rolled about the
    approach so that the thumb-to-fingers direction (the palm's y axis) lies
    across the object's thinnest extent orthogonal to the approach. An
    approach within 18 degrees of the x axis is tilted up by 19 degrees: with
    the palm normal along x the XYZ Euler angles are in gimbal lock. ``roll``
    turns the hand further about the approach.

    Parameters
    ----------
    hand : SynergyHand
    obj : GraspObject
    approach : (3,) float
        Direction from the object's centre to the hand.
    distance : float
        mm.
    clearance : float, optional
        If given, the palm is moved back until the fingertips' mean depth in
        front of the palm is at least this (mm) beyond the object's farthest
        point along ``approach``.
    palm_centred : bool
        Face the object's centre with the palm's centre instead of the
        fingertips' centroid.
    roll : float
        Angle (rad) the hand is turned about its palm normal (which points
        at the object) from the roll above: right-handed, so clockwise seen
        from the hand.

    Returns
    -------
    (6 + n_syn,) float

    Examples
    --------
    >>> from synergrasp import SynergyHand, objects
    >>> u = start_configuration(SynergyHand.default(), objects.ellipsoid(), (0.0, 0.0, 1.0))
    >>> u.shape
    (8,)
    """
    hand = hand_and_object(hand, obj)
    a = as_vector(approach, "approach", 3)
    if not np.abs(a).max() > 0.0:
        raise ValueError("approach must be a non-zero direction (object centre to hand)")
    distance = positive_scalar(distance, "distance (mm)")
    roll = finite_scalar(roll, "roll", "a finite angle in radians")
    clearance = None if clearance is None else positive_scalar(clearance, "clearance (mm)", zero=True)
    a = a / np.abs(a).max()  # first to order 1: the norm of a vector of 1e300 overflows, of 1e-200 underflows
    a = a / np.linalg.norm(a)
    if abs(a[0]) > 0.95:  # palm normal along x: the XYZ Euler angles would start in gimbal lock
        a = a + np.array([0.0, 0.0, 0.35])
        a /= np.linalg.norm(a)
    z = -a
    extents = np.array(obj.extents, dtype=float)
    along = np.abs(a)
    candidates = np.eye(3) - np.outer(z, z)  # world axes projected off the approach
    usable = np.linalg.norm(candidates, axis=1) > 0.5
    order = np.lexsort((along, np.where(usable, extents, np.inf)))
    y = candidates[order[0]] / np.linalg.norm(candidates[order[0]])
    R = np.column_stack([np.cross(y, z), y, z]) @ rotation_xyz([0.0, 0.0, roll])
    u = np.r_[np.zeros(6), np.zeros(hand.n_syn)]
    tips = hand.points(u, "precision")
    aim = np.zeros(3) if palm_centred else np.array([tips[:, 0].mean(), tips[:, 1].mean(), 0.0])
    if clearance is not None:  # the fingertips start outside the object, however long it is along the approach
        reach = max(float(np.max((p.vertices - obj.center) @ a)) for p in obj.convex)
        distance = max(distance, reach + float(tips[:, 2].mean()) + clearance)
    u[:3] = obj.center + a * distance - R @ aim
    u[3:6] = Rotation.from_matrix(R).as_euler("XYZ")
    return u


def principal_directions(obj):
    """Directions around an object from its principal axes: the 6 axis directions, then the 8 diagonals.

    Parameters
    ----------
    obj : GraspObject

    Returns
    -------
    (14, 3) float
        Unit directions from the object's centre, the shortest axis first
        (the hand faces the object's widest side first).

    Examples
    --------
    >>> from synergrasp import objects
    >>> principal_directions(objects.ellipsoid())[0].round(3).tolist()   # the 30 mm semi-axis
    [1.0, 0.0, 0.0]
    """
    axes = principal_axes(obj)
    directions = [s * a for a in axes for s in (1.0, -1.0)]
    directions += [axes.T @ np.array(signs) / np.sqrt(3.0) for signs in itertools.product((1.0, -1.0), repeat=3)]
    return np.array(directions)


def direction_starts(hand, obj, options):
    """Direction starts of a precision plan (`principal_directions`, `start_configuration`).

    The hand from each direction in turn, then from each again turned a
    quarter turn about the approach (the thumb-to-fingers axis along the
    object's other side): a plan whose pinch seeds and first directions
    fail goes on with other starts while its budget lasts.

    Parameters
    ----------
    hand : SynergyHand
    obj : GraspObject
    options : PlannerOptions

    Yields
    ------
    Start
    """
    for roll in DIRECTION_ROLLS:
        for d in principal_directions(obj):
            u = start_configuration(hand, obj, d, options.start_distance, options.start_clearance, roll=roll)
            yield Start(u, "direction", {"direction": d.round(6).tolist(), "turn": round(roll, 6)})


def surface_samples(obj, count, seed):
    """Points on the object's surface with their outward normals, and the exit of the inward ray from each.

    The surface is the object's true surface when it has a mesh
    (`GraspObject.surface`), else the hulls of its pieces.

    Parameters
    ----------
    obj : GraspObject
    count : int
    seed : int

    Returns
    -------
    points, normals, exits, exit_normals : (m, 3) float
        The samples whose inward ray leaves the object (m <= count), the
        outward normals, where each ray leaves and the outward normal there.
    """
    import trimesh

    count = integer(count, "count", 1, "surface points")
    if count > MAX_SURFACE_SAMPLES:
        raise ValueError(f"count must be at most {MAX_SURFACE_SAMPLES:.0e} surface points, got {count}")
    seed = integer(seed, "seed", 0)
    queries = obj.surface_queries if obj.surface is not None else MeshQueries(obj.to_mesh())
    mesh = queries.mesh
    points, faces = trimesh.sample.sample_surface(mesh, count, seed=seed)
    normals = mesh.face_normals[faces]
    exits, rays, triangles = queries.first_hits(points - 1e-3 * normals, -normals)
    return points[rays], normals[rays], exits, mesh.face_normals[triangles]


#: Most points `surface_samples` draws (each is a ray cast into the surface).
MAX_SURFACE_SAMPLES = 1_000_000

#: The fingers (chain indices) whose fingertips' centroid opposes the thumb tip in a pinch: index and middle.
PARTNERS = (1, 2)


def _aperture_table(hand, steps=41):
    """Synergy values on a grid and the fingertips' pad points there: (k, n_syn) and (k, n_fingers, 3)."""
    z = hand.synergy_grid(steps)
    return z, np.array([hand.points(np.r_[np.zeros(6), zi], "precision") for zi in z])


class _Apertures:
    """The hand's thumb-to-fingers openings and its fingertips' spread, computed once per hand."""

    def __init__(self, hand):
        if len(hand.finger_names) < 1 + max(PARTNERS):
            raise ValueError(f"a pinch opposes the thumb (the first finger) to the second and third; hand {hand.name!r} "
                             f"has {len(hand.finger_names)} finger(s): {hand.finger_names}")
        self.z, tips = _aperture_table(hand)
        self.thumb, self.partner = tips[:, 0], tips[:, list(PARTNERS)].mean(axis=1)
        self.width = np.linalg.norm(self.partner - self.thumb, axis=1)
        self.spread = np.linalg.norm(tips - tips[:, [PARTNERS[0]]], axis=2).min(axis=0)
        self.spread[[0, *PARTNERS]] = 0.0

    def synergies(self, width):
        """The grid synergies whose opening is nearest ``width``, nearest the mean pose among near ties."""
        cost = np.abs(self.width - width) + 2.0 * np.linalg.norm(self.z, axis=1)
        k = int(np.argmin(cost))
        return k, abs(self.width[k] - width)


_APERTURES = {}


def _per_hand(cache, hand, build):
    """``build(hand)``, computed once per hand definition: every plan gets its own copy of the
    default hand, so the tables are keyed by the hand file's fields, not by the object."""
    key = json.dumps(hand.to_dict(), sort_keys=True)
    if key not in cache:
        if len(cache) >= 8:
            cache.pop(next(iter(cache)))
        cache[key] = build(hand)
    return cache[key]


def _apertures(hand):
    return _per_hand(_APERTURES, hand, _Apertures)


def smallest_pinch(hand):
    """The nearest the thumb tip and the index/middle fingertips' centroid come (mm), over the synergy box.

    The fingertips' pad points of `SynergyHand.points` on a 41 x 41 grid of
    the synergies: a pinch pair narrower than this cannot be held between
    those pads (the paper's hand: about 15 mm).

    Parameters
    ----------
    hand : SynergyHand

    Returns
    -------
    float

    Examples
    --------
    >>> from synergrasp import SynergyHand
    >>> round(smallest_pinch(SynergyHand.default()), 1)
    15.1
    """
    return float(_apertures(hand).width.min())


def widest_pinch(hand):
    """The farthest the thumb tip and the index/middle fingertips' centroid open apart (mm), over the synergy box.

    As `smallest_pinch`, the largest instead: a pinch pair wider than this
    less twice `PlannerOptions.seed_opening` is not a pinch seed.

    Parameters
    ----------
    hand : SynergyHand

    Returns
    -------
    float

    Examples
    --------
    >>> from synergrasp import SynergyHand
    >>> widest_pinch(SynergyHand.default()) > 100.0
    True
    """
    return float(_apertures(hand).width.max())


def pinch_fingertips(hand, obj):
    """The fingertips a precision attempt steers into contact with ``obj``.

    The thumb and its pinch partners (index and middle, `PARTNERS`) always;
    another fingertip when the object is at least as large (the largest
    side of its smallest enclosing box, `GraspObject.length`, whichever way
    it is turned) as the nearest that fingertip comes to the index fingertip
    over the synergy box: on a
    smaller object the fingertips cannot all touch it, and steering them all
    into contact stalls the attempt in a compromise. The others are kept out
    of the object like the other phalanges.

    Parameters
    ----------
    hand : SynergyHand
    obj : GraspObject

    Returns
    -------
    (n_tips,) bool
        One per fingertip, in the order of ``hand.point_labels("precision")``.

    Examples
    --------
    The paper's hand: the ring fingertip comes no nearer than 35 mm to the
    index fingertip, the little fingertip 54 mm.

    >>> import trimesh
    >>> from synergrasp import SynergyHand, objects
    >>> hand = SynergyHand.default()
    >>> pinch_fingertips(hand, objects.ellipsoid()).tolist()
    [True, True, True, True, True]
    >>> ball = objects.from_mesh(trimesh.creation.icosphere(3, 20.0), name="40 mm ball")
    >>> pinch_fingertips(hand, ball).tolist()
    [True, True, True, True, False]
    """
    spread = _apertures(hand).spread
    if np.all(spread * np.sqrt(3.0) <= obj.size):  # the box's largest side is at least size / sqrt(3): no need to fit it
        return np.ones(len(spread), dtype=bool)
    return spread <= obj.length


def pinch_seeds(hand, obj, options):
    """Precision starts from pairs of opposed surface points (see the module docstring).

    Pairs are drawn from `surface_samples` (their inward ray's exit, within
    `PAIR_ANGLE` of opposed normals), those the hand can span with
    ``options.seed_opening`` to spare on either side. They are taken in
    order of a score in mm: how far their width is from `PAIR_WIDTH`, plus
    how far their axis passes from the object's centre, plus how deep either
    point lies in a recess (`recess`: a fingertip reaching into a bowl or a
    channel); pairs too alike to an earlier one (midpoints within 10 mm,
    axes within 20 degrees) are skipped.

    Parameters
    ----------
    hand : SynergyHand
    obj : GraspObject
    options : PlannerOptions

    Yields
    ------
    Start
    """
    apertures = _apertures(hand)
    p1, n1, p2, n2 = surface_samples(obj, PAIR_SAMPLES, options.seed)
    if not len(p1):  # no inward ray leaves the surface (an open sheet): no pairs
        return
    width = np.linalg.norm(p2 - p1, axis=1)
    spare = 2.0 * options.seed_opening
    usable = _pairs(n1, n2, width) & (width + spare <= apertures.width.max())
    axis = (p2 - p1) / np.maximum(width, 1e-9)[:, None]
    offset = obj.center - p1
    off_axis = np.linalg.norm(offset - np.einsum("ij,ij->i", offset, axis)[:, None] * axis, axis=1)
    taken = []
    score = np.abs(width - PAIR_WIDTH) + off_axis + recess(obj, p1, n1) + recess(obj, p2, n2)
    for i in np.flatnonzero(usable)[np.argsort(score[usable], kind="stable")]:
        mid = 0.5 * (p1[i] + p2[i])
        if any(np.linalg.norm(mid - m) < 10.0 and abs(axis[i] @ a) > np.cos(np.radians(20.0)) for m, a in taken):
            continue
        taken.append((mid, axis[i]))
        flip = len(taken) % 2 == 0  # the thumb on either side of the pairs in turn
        a, b = (p2[i], p1[i]) if flip else (p1[i], p2[i])
        u = _straddle(hand, obj, apertures, a, b, width[i] + spare)
        if u is None:
            continue
        back = -rotation_xyz(u[3:6])[:, 2]
        u[:3] += options.seed_retreat * back
        u = _clear(hand, obj, u, back, options.start_clearance)
        yield Start(u, "pinch", {"thumb": a.round(3).tolist(), "finger": b.round(3).tolist(),
                                 "width": round(float(width[i]), 3), "off_axis": round(float(off_axis[i]), 3)})


def opposed_widths(obj, seed=0):
    """How far apart the object's opposed surface points are: the widths the pinch seeds are drawn from.

    The samples of `surface_samples` (`PAIR_SAMPLES` of them) whose inward
    ray leaves the object within `PAIR_ANGLE` of the opposed normal, more
    than 1 mm further on.

    Parameters
    ----------
    obj : GraspObject
    seed : int
        Of the surface samples (`PlannerOptions.seed`).

    Returns
    -------
    (k,) float
        mm; empty when no two surface points face each other.

    Examples
    --------
    >>> import trimesh
    >>> from synergrasp import objects
    >>> box = objects.from_mesh(trimesh.creation.box((40.0, 160.0, 160.0)), cache=False)
    >>> bool(abs(opposed_widths(box).min() - 40.0) < 1e-6)
    True
    """
    p1, n1, p2, n2 = surface_samples(obj, PAIR_SAMPLES, seed)
    width = np.linalg.norm(p2 - p1, axis=1)
    return width[_pairs(n1, n2, width)]


def _pairs(n1, n2, width):
    """(m,) bool: the samples and exits that make a pair: outward normals opposed within `PAIR_ANGLE`, more than
    1 mm apart."""
    return (np.einsum("ij,ij->i", n1, n2) < -np.cos(np.radians(PAIR_ANGLE))) & (width > 1.0)


def recess(obj, points, normals):
    """How deep in a recess of the object each surface point lies (mm): 0 on its convex hull.

    The shortest way out to the hull's surface along the directions within
    `RECESS_CONE` of the point's outward normal (the way a fingertip comes
    in): a point inside a bowl near its rim is a few mm deep, one at its
    bottom as deep as the bowl.

    Parameters
    ----------
    obj : GraspObject
    points, normals : (m, 3) float
        Surface points and their unit outward normals.

    Returns
    -------
    (m,) float

    Raises
    ------
    ValueError
        If ``points`` or ``normals`` is not an (m, 3) array of finite numbers, their shapes differ, or a
        normal is not of unit length.
    """
    points, normals = as_points(points, "points", dim=3), as_points(normals, "normals", dim=3)
    if normals.shape != points.shape:
        raise ValueError(f"recess needs one normal per point: points has shape {points.shape}, normals {normals.shape}")
    length = np.linalg.norm(normals, axis=1)
    if len(length) and np.abs(length - 1.0).max() > 1e-6:
        raise ValueError(f"recess needs unit normals; rows {np.flatnonzero(np.abs(length - 1.0) > 1e-6)[:10].tolist()} have "
                         f"lengths such as {length[np.argmax(np.abs(length - 1.0))]:.3g}: divide them by their lengths")
    planes = obj.hull_planes
    gap = np.maximum(-(points @ planes[:, :3].T + planes[:, 3]), 0.0)  # (m, f): how far inside each facet
    facing = _DIRECTIONS @ planes[:, :3].T  # (d, f)
    slowness = np.where(facing > 1e-9, 1.0 / np.maximum(facing, 1e-9), 1e12)  # a facet not ahead is never reached
    within = normals @ _DIRECTIONS.T >= np.cos(np.radians(RECESS_CONE))  # (m, d)
    way_out = np.full(len(points), np.inf)
    _way_out(gap, slowness, within, way_out)
    return way_out


@kernel
def _way_out(gap, slowness, within, way_out):
    """``way_out[i] = min`` over the directions ``d`` within the cone of point i of ``min_f gap[i, f] * slowness[d, f]``."""
    for i in range(len(gap)):
        best = way_out[i]
        for d in range(len(slowness)):
            if not within[i, d]:
                continue
            for f in range(gap.shape[1]):
                best = min(best, gap[i, f] * slowness[d, f])
            if best == 0.0:  # gaps are >= 0 and slownesses > 0: nothing is shorter
                break
        way_out[i] = best


def _straddle(hand, obj, apertures, thumb_at, fingers_at, opening):
    """The configuration whose thumb tip and index/middle centroid straddle two points ``opening`` apart, rolled clear.

    Of `ROLLS` rolls about the pair's axis, the one with the fewest skin points
    of the hand inside the object, the palm facing away from the object's
    centre on a tie. None if the hand cannot open that wide.
    """
    k, miss = apertures.synergies(opening)
    if miss > 5.0:
        return None
    z, thumb, partner = apertures.z[k], apertures.thumb[k], apertures.partner[k]
    axis = (fingers_at - thumb_at) / np.linalg.norm(fingers_at - thumb_at)
    hand_axis = (partner - thumb) / np.linalg.norm(partner - thumb)
    align = Rotation.align_vectors([axis], [hand_axis])[0]
    middle = 0.5 * (thumb_at + fingers_at)
    rolls = np.linspace(0.0, 2.0 * np.pi, ROLLS, endpoint=False)
    R = (Rotation.from_rotvec(rolls[:, None] * axis) * align).as_matrix()  # (ROLLS, 3, 3)
    us = [np.r_[middle - r @ (0.5 * (thumb + partner)), euler, z]
          for r, euler in zip(R, Rotation.from_matrix(R).as_euler("XYZ"))]
    skins = [hand.skin_and_jacobian(u)[:2] for u in us]
    inside = obj.contains(np.vstack([np.vstack([skin.reshape(-1, 3), palm]) for skin, palm in skins]))
    inside = inside.reshape(ROLLS, -1).sum(axis=1)
    outward = [float(r[:, 2] @ (middle - obj.center)) for r in R]  # palm normal along centre -> pair: palm on the far side
    return us[min(range(ROLLS), key=lambda i: (int(inside[i]), outward[i]))]


def _clear(hand, obj, u, back, clearance):
    """``u`` moved along ``back`` until every phalanx capsule is ``clearance`` mm from the object (at most 20 steps)."""
    for _ in range(20):
        geo = hand.segments(u)
        need = clearance - float(obj.penetration(geo.capsules, geo.radius).distances.min())
        if need <= 0.0:
            break
        u = u.copy()
        u[:3] += back * (need + 1e-6)
    return u


def _wrap_table(hand, steps=WRAP_GRID, fractions=6):
    """The synergy grid and, at each of its values, the hand's screening points in the palm frame.

    Returns
    -------
    z : (g, n_syn) float
    points : (g, k + p + k * fractions, 3) float
        The power points of the k phalanges, the palm's p skin points (the
        palm point first), then points along every phalanx capsule's axis.
    k, p : int
    """
    z = hand.synergy_grid(steps, max_points=WRAP_GRID_POINTS)
    along = np.linspace(0.0, 1.0, fractions)[:, None, None]
    points = []
    for zi in z:
        u = np.r_[np.zeros(6), zi]
        skin, palm, _, _ = hand.skin_and_jacobian(u)
        capsules = hand.segments(u).capsules
        axis = (capsules[None, :, 0] * (1.0 - along) + capsules[None, :, 1] * along).reshape(-1, 3)
        points.append(np.vstack([hand.points(u, "power")[:-1], palm, axis]))
    return z, np.array(points), len(skin), len(palm)


_WRAP_TABLES = {}


def roll_frames(normals, rolls):
    """Palm orientations facing along ``-normal``, rolled about it: (m * rolls, 3, 3), columns x, y, z.

    Parameters
    ----------
    normals : (m, 3) float
        Unit outward normals.
    rolls : int
        Rolls per normal, evenly spaced over a turn.

    Returns
    -------
    (m * rolls, 3, 3) float
        Rotation matrices, the rolls of each normal in turn; their z column
        is ``-normal``.
    """
    z = -normals
    a = np.cross(z, np.where(np.abs(z[:, :1]) < 0.9, [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]))
    a /= np.linalg.norm(a, axis=1, keepdims=True)
    b = np.cross(z, a)
    angle = np.linspace(0.0, 2.0 * np.pi, rolls, endpoint=False)[None, :, None]
    y = np.cos(angle) * a[:, None] + np.sin(angle) * b[:, None]  # (m, rolls, 3)
    z = np.broadcast_to(z[:, None], y.shape)
    return np.stack([np.cross(y, z), y, z], axis=-1).reshape(-1, 3, 3)


def wrap_seeds(hand, obj, options, *, backend="native", deadline=None):
    """Power starts with the palm on the object and the fingers closed around it (see the module docstring).

    The palm point is put `WRAP_STANDOFF` mm off each of `WRAP_SAMPLES`
    surface points (`surface_samples`), the palm facing the surface, in
    `WRAP_ROLLS` rolls about the normal, with every synergy value of a
    `WRAP_GRID` grid. Each pose is screened on the object's `DistanceGrid`
    (`DistanceGrid.posed`, which reads a pose no further than its first
    point too deep):
    it is kept when no phalanx axis is nearer the surface than the finger
    radius less ``options.max_penetration`` and no palm skin point deeper
    than ``options.max_penetration``, and scored by the phalanges whose power
    point is within ``options.eps_c`` of the surface (nearer ones count a
    little more). The best pose of each point and roll, in order of score,
    is then checked exactly (python-fcl, `hand_penetration`) and its grasp
    judged (`check_grasp`). A pose that meets the paper's criterion is
    yielded as soon as it is checked (its attempt starts before the rest
    of its batch is checked); the others are yielded in batches: a batch
    ends at `WRAP_SEEDS` poses that pass the exact check and are not yet
    grasps, or at four times as many checked, and its seeds are yielded by
    their Q distance before the next batch is checked.
    The batches go on until every screened pose has been checked, or until
    ``deadline``: the seeds kept so far are then yielded and no more poses
    are checked (with a slow LP backend, a batch's checks can take seconds).

    Parameters
    ----------
    hand : SynergyHand
    obj : GraspObject
    options : PlannerOptions
    backend : str
        LP backend of the grasp checks.
    deadline : float, optional
        `synergrasp.planner.clock` value after which no more poses are
        checked: the plan's ``time_limit``.

    Yields
    ------
    Start
        Of kind ``"wrap"``; ``detail`` has the surface point, the roll, the
        phalanges in contact, the grasp's g_Q, whether the pose already
        meets the criterion (``grasp``) and the batch (0, 1, ...).
    """
    z, local, n_fingers, n_palm = _per_hand(_WRAP_TABLES, hand, _wrap_table)
    palm_point = local[0, n_fingers]
    points, normals, _, _ = surface_samples(obj, WRAP_SAMPLES, options.seed)
    if not len(points):
        return
    R = roll_frames(normals, WRAP_ROLLS)  # (m * rolls, 3, 3)
    t = np.repeat(points + WRAP_STANDOFF * normals, WRAP_ROLLS, axis=0) - R @ palm_point
    # the phalanx axes (which reject most poses) and the palm's skin points first, each with the depth that
    # rejects a pose: a pose and synergy value is read no further than its first point too deep
    n_axes = local.shape[1] - n_fingers - n_palm
    reading = np.r_[n_fingers + n_palm:local.shape[1], n_fingers:n_fingers + n_palm, :n_fingers]
    floors = np.r_[np.full(n_axes, hand.finger_radius - options.max_penetration),
                   np.full(n_palm, -options.max_penetration), np.full(n_fingers, -np.inf)]
    d = obj.distance_grid.posed(local[:, reading], R, t, floors)  # (poses, g, points)
    fingers = d[..., n_axes + n_palm:]
    # the last point with a floor is above it only when no point before it was below its own (see posed), and
    # the XYZ Euler angles of the palm must not be near their lock
    last = n_axes + n_palm - 1
    clear = (d[..., last] >= floors[last]) & (np.abs(R[:, 0, 2]) < GIMBAL)[:, None]
    touching = (fingers < options.eps_c).sum(axis=2)
    score = np.where(clear, touching + 0.1 * np.exp(-np.clip(fingers, 0.0, None) / 10.0).sum(axis=2), -np.inf)
    best = score.argmax(axis=1)  # the best synergies of each pose
    score = score[np.arange(len(score)), best]
    touching = touching[np.arange(len(score)), best]
    order = np.argsort(-score, kind="stable")
    order = order[np.isfinite(score[order])]
    angles = Rotation.from_matrix(R[order]).as_euler("XYZ") if len(order) else np.zeros((0, 3))
    kept, checked, batch = [], 0, 0
    for f, euler in zip(order, angles):
        if deadline is not None and clock() > deadline:
            break
        checked += 1
        u = np.r_[t[f], euler, z[best[f]]]
        if hand_penetration(hand, obj, u).depth <= options.max_penetration:
            status = grasp_status(hand, obj, u, "power", mu=options.mu, edges=options.edges, backend=backend)
            check = check_grasp(obj, status, "power", eps_c=options.eps_c, mu=options.mu, edges=options.edges,
                                backend=backend)
            q = check.q if np.isfinite(check.q) else np.inf
            detail = {"point": points[f // WRAP_ROLLS].round(3).tolist(), "roll": int(f % WRAP_ROLLS),
                      "touching": int(touching[f]), "g_Q": round(float(check.q), 6), "grasp": bool(check.done), "batch": batch}
            if check.done:  # a grasp already: tried before the rest of its batch is checked
                yield Start(u, "wrap", detail)
            else:
                kept.append(((q, -score[f]), Start(u, "wrap", detail)))
        if len(kept) >= WRAP_SEEDS or checked >= 4 * WRAP_SEEDS:  # a batch: its seeds in order, then the next
            yield from _in_order(kept)
            kept, checked, batch = [], 0, batch + 1
    yield from _in_order(kept)


def _in_order(kept):
    """The starts of (key, start) pairs, by key."""
    return [start for _, start in sorted(kept, key=lambda k: k[0])]


def power_schedule(hand, obj, options):
    """Power starts: `principal_directions`, each with the wide pre-shape (palm-centred) and then the cupped one.

    Every start is moved back along its palm normal until every phalanx
    capsule is ``options.start_clearance`` from the object (a wide open hand
    in front of a large object can start with fingers inside it).

    Parameters
    ----------
    hand : SynergyHand
    obj : GraspObject
    options : PlannerOptions

    Yields
    ------
    Start
    """
    shapes = [("wide", options.power_wide_preshape, True)] if options.power_wide_preshape is not None else []
    shapes.append(("cupped", options.power_preshape, False))
    for d in principal_directions(obj):
        for kind, shape, wide in shapes:
            u = start_configuration(hand, obj, d, options.start_distance, options.start_clearance, palm_centred=wide)
            u[6:] = preshape(hand, shape)
            u = _clear(hand, obj, u, -rotation_xyz(u[3:6])[:, 2], options.start_clearance)
            yield Start(u, kind, {"direction": d.round(6).tolist()})


def preshape(hand, value):
    """A pre-shape option as synergy values within the hand's limits.

    Parameters
    ----------
    hand : SynergyHand
    value : sequence of float or None
        One value per synergy; None: the mean pose (zeros).

    Returns
    -------
    (n_syn,) float

    Raises
    ------
    ValueError
        If ``value`` does not have one value per synergy.

    Warns
    -----
    UserWarning
        If a value lies outside the synergy's limits (it is clipped).
    """
    if value is None:
        return np.zeros(hand.n_syn)
    if len(value) != hand.n_syn:
        raise ValueError(f"a power pre-shape needs one value per synergy ({hand.n_syn} for {hand.name}), got {value!r}: "
                         f"give PlannerOptions' power_preshape and power_wide_preshape {hand.n_syn} values each, or "
                         "None (the mean pose, respectively cupped starts only); the defaults are for two synergies")
    return hand.clip_synergies(value, "the power pre-shape's synergies")


def starts(hand, obj, grasp, options, *, backend="native", deadline=None):
    """The starts of a plan in turn: pinch seeds then direction starts (precision), or wrap seeds then `power_schedule`.

    Parameters
    ----------
    hand : SynergyHand
    obj : GraspObject
    grasp : {"precision", "power"}
    options : PlannerOptions
    backend : str
        LP backend of the wrap seeds' grasp checks.
    deadline : float, optional
        `synergrasp.planner.clock` value after which the wrap seeds check no
        more poses (`wrap_seeds`).

    Yields
    ------
    Start
    """
    if grasp == "power":
        yield from wrap_seeds(hand, obj, options, backend=backend, deadline=deadline)
        yield from power_schedule(hand, obj, options)
        return
    yield from pinch_seeds(hand, obj, options)
    yield from direction_starts(hand, obj, options)
