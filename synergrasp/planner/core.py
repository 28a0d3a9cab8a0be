"""The reach-to-grasp planner: paper Fig. 6 and Eqs. 12-16, made to converge.

One attempt iterates from a start pose:

1. status g = [cP of each hand point ; g_sQ] and its Jacobian (status.py);
2. stop when the paper's criterion holds (stop.py);
3. the requested change: e = g_t - g with the paper's target g_t = [0 ... 0, -1],
   except that the sQ row asks each step for ``sq_step`` less than its current
   value (a moving target) instead of the unreachable -1 at once; rows are
   brought to comparable scales (cP divided by the object's size);
4. the step of Eq. 16 with two priorities: sQ first, the contacts in its null
   space (step.py); the synergy limits are respected;
5. adaptive step length: a trust radius on the normalised step, grown when the
   linear model predicts the change of the status well and shrunk when not.

If an attempt stalls (the status stops improving) the next start of a
schedule is tried: approach directions in the order of `APPROACHES`, and after
the first two attempts every other one with a stand-off (`STANDOFF_APPROACHES`)
(power grasps: `power_schedule`, two pre-shapes in turn, no stand-off),
up to ``restarts`` attempts or ``max_iter`` iterations in all. A plan that
finds no grasp goes through the schedule a second time: a precision plan after
``band_after`` iterations, with a contact band instead of the target
(``contact_band``); a power plan once its attempts are spent, with the
synergies held while reaching (``power_held_pass``). A grasp that
meets the criterion with a phalanx too deep in the object is not dropped at
once: that finger's hand points are asked to back off by the depth and the
iteration goes on (``backoffs`` times).
"""

from __future__ import annotations

import os
import time
from dataclasses import asdict, dataclass, replace

import numpy as np
from scipy.spatial.transform import Rotation

from .. import objects
from .._checks import as_vector
from ..hand import SynergyHand, rotation_xyz
from ..lp import get_backend
from .result import PlanResult
from .status import capsule_rows, grasp_status
from .step import limited_step
from .stop import check_grasp

GRASPS = ("precision", "power")
#: Objects thinner than this (mm) are refused: most likely a mesh in metres.
MIN_WIDTH = 2.0

#: Approach directions tried after the caller's, in order (object centre to hand): sorted by how
#: often a single attempt from them ended in a verified precision grasp over the household and
#: paper objects (benchmarks/household.py), the side and side-above directions first.
APPROACHES = (
    (0.0, 1.0, 0.0), (1.0, 0.0, 0.5), (-1.0, 0.0, 0.5), (1.0, -1.0, 1.0), (0.0, -1.0, 0.0), (1.0, 1.0, 1.0),
    (-1.0, -1.0, 1.0), (-1.0, 1.0, 1.0), (-1.0, 1.0, -1.0), (1.0, 1.0, -1.0), (0.0, 0.0, 1.0), (0.0, 0.0, -1.0),
)
#: Approach directions of the attempts with a stand-off: the diagonals from above first, which
#: the plain attempts try late.
STANDOFF_APPROACHES = (
    (-1.0, 1.0, 1.0), (1.0, 1.0, 1.0), (-1.0, -1.0, 1.0), (0.0, 1.0, 0.0), (1.0, 1.0, -1.0), (1.0, -1.0, 1.0),
    (0.0, 0.0, 1.0), (-1.0, 0.0, 0.5), (1.0, 0.0, 0.5), (0.0, -1.0, 0.0), (0.0, 0.0, -1.0), (-1.0, 1.0, -1.0),
)
#: Approach directions of power grasps from the cupped pre-shape (``power_preshape``), in order:
#: sorted by how often a single power attempt from them ended in a verified grasp over the 44
#: household objects and the paper's four (benchmarks/household.py); the diagonals from above first.
POWER_APPROACHES = (
    (-1.0, 1.0, 1.0), (1.0, -1.0, 1.0), (-1.0, -1.0, 1.0), (1.0, 1.0, 1.0), (-1.0, 1.0, -1.0), (1.0, 1.0, -1.0),
    (0.0, 0.0, 1.0), (-1.0, 0.0, 0.5), (1.0, 0.0, 0.5), (0.0, -1.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, -1.0),
)
#: Approach directions of power grasps from the wide pre-shape (``power_wide_preshape``), ordered
#: the same way.
POWER_WIDE_APPROACHES = (
    (1.0, 1.0, -1.0), (1.0, 1.0, 1.0), (0.0, 0.0, 1.0), (-1.0, 1.0, 1.0), (1.0, 0.0, 0.5), (0.0, 1.0, 0.0),
    (-1.0, 0.0, 0.5), (-1.0, -1.0, 1.0), (0.0, 0.0, -1.0), (-1.0, 1.0, -1.0), (1.0, -1.0, 1.0), (0.0, -1.0, 0.0),
)
#: Attempts without a stand-off before the schedule alternates.
PLAIN_FIRST = 2


@dataclass(frozen=True)
class PlannerOptions:
    """Settings of `plan` (all have working defaults).

    Attributes
    ----------
    eps_c : float
        Contact threshold (mm), paper: 5.
    mu : float
        Friction coefficient, paper: 0.3.
    edges : int
        Friction cone edges, paper: 8.
    sq_step : float
        Decrease of g_sQ requested per iteration (the moving sQ target).
        Precision grasps ask at most the trust radius times the norm of the
        (normalised) gradient of g_sQ, the decrease the linear model promises
        for a step within the radius.
    contact_target : float
        Target cP of the hand points (mm). The paper's 0 puts the skin points
        on the surface, where solver and faceting errors push fingers in;
        the middle of the contact band [0, eps_c) keeps them in contact
        without penetrating.
    smoothing : float
        Normal smoothing length for sQ, as a fraction of the object's torque
        scale (see `synergrasp.planner.status.smoothed_normals`).
    radius : float
        Initial trust radius of the normalised step (position in object sizes,
        angles in rad, synergies in units).
    radius_max, radius_min : float
        Bounds of the trust radius; an attempt whose radius stays at
        ``radius_min`` for ``stall_window`` iterations has stalled.
    stall_window : int
        Iterations without progress (a lower merit: the contact errors plus
        g_sQ floored at -0.1) that end an attempt.
    crawl_window, crawl_fraction : int, float
        An attempt whose best merit fell by less than ``crawl_fraction`` of
        (its size + 0.1) over the last ``crawl_window`` iterations has stalled
        too (it creeps: fingers hovering with sQ far from negative). 0 turns
        this test off.
    touch_window : int
        A precision attempt in which no fingertip has come within ``eps_c``
        of the surface (or of its stand-off) after this many iterations has
        stalled too: the hand hovers in front of the object. 0 turns this
        test off.
    iterations_per_attempt : int
        Iteration cap of one attempt.
    restarts : int
        Number of attempts of one pass over the schedule (the caller's
        approach first); ``max_iter`` caps their iterations in all.
    start_distance : float
        Distance (mm) of the start pose from the object's centre.
    start_clearance : float
        The start pose is moved back along the approach, if needed, until the
        fingertips are this far (mm) in front of the object's farthest point
        along the approach: a long object approached along its length does not
        start with the fingers inside it.
    max_penetration : float
        Deepest penetration of a phalanx capsule into the object (mm) allowed
        in the final grasp. A grasp that meets the paper's criterion with a
        phalanx deeper than this (the status vector watches only the hand
        points, not the phalanges between them) is rejected and the next
        approach direction is tried.
    backoffs : int
        How often an attempt whose grasp meets the criterion with a phalanx
        deeper than ``max_penetration`` goes on with that finger's hand points
        asked to stand off the surface by the phalanx's depth (added to their
        contact target), before the grasp is rejected.
    standoff : float
        Extra contact target (mm) of the attempts with a stand-off while the
        predicted grasp is poor: ``standoff * clip(g_sQ, 0, 1)``. The fingertips
        stay clear of the near side of the object until sQ says they surround
        it, instead of landing on it (a local minimum of sQ); spheres need it.
    power_phases : bool
        Power grasps only: reach with the palm, then wrap. While the palm point
        is not in contact the finger rows are left out of the step (except
        those of penetrating segments, kept in the first priority level) and
        the synergies hold their pre-shape (see ``power_free_reach``), so the
        open hand is carried palm first to the surface; once the palm touches, its row joins the first
        priority level and keeps it on the surface while the synergies close
        the fingers. A grasp meeting the criterion with a phalanx deeper than
        ``max_penetration`` does not stop the attempt: the iteration goes on
        and the penetrating segments' rows push the phalanx out.
    power_preshape : tuple of float or None
        Synergy values of the default start poses of a power grasp (one per
        synergy): (0, 1) cups the paper's hand open (the second synergy opens
        the fingers). None keeps the mean pose (z = 0). Ignored when ``u0``
        is given.
    power_wide_preshape : tuple of float or None
        Pre-shape of every other default power start, the first included:
        (-1, 1) opens the paper's hand widest, its fingers nearly flat. Its
        attempts come from `POWER_WIDE_APPROACHES` with the palm centred on
        the object (`start_configuration`), the cupped ones' from
        `POWER_APPROACHES` (see `power_schedule`). None: cupped starts only.
    power_free_reach : bool
        While reaching, the synergies are free for the rows of the first
        priority level (sQ and any penetrating phalanx): the hand is shaped
        by the predicted grasp on the way, and a phalanx that dips into the
        object is pushed out by the synergies as well as by the hand's pose.
        The finger contact rows still wait for the palm. False: the
        synergies hold the pre-shape until the palm touches (True: the first
        pass; see ``power_held_pass`` for the second).
    contact_band : (2,) float or None
        Precision grasps only: the attempts of the second pass over the
        schedule (see ``band_after``), instead of asking every fingertip for
        ``contact_target``, accept any cP in the band ``[low, high]`` mm
        (shifted like the target by a stand-off or back-off): a fingertip
        inside it is left out of the step, one outside it is pulled to the
        band's nearer edge. Five fingertips moved by two synergies cannot all
        sit at one distance from a round surface (the contact rows' Jacobian
        is then nearly singular and the attempt stalls with the thumb just
        outside ``eps_c``); the band lets them settle where they can. (1, 4.5)
        roughly doubles single-attempt success on spheres and round fruit but
        lowers it on cylinders and boxes, hence a second pass rather than the
        first (see the planner docs). None: the target only, one pass.
    band_after : int
        Precision grasps: iterations (over all attempts) after which a plan
        that has not found a grasp with ``contact_target`` starts the schedule
        again with ``contact_band``, until ``max_iter``. 0: the band from the
        first attempt.
    power_held_pass : bool
        Power grasps with ``power_free_reach``: when the schedule's attempts
        (``restarts``) are spent without a grasp and iterations are left, go
        through the schedule again with the synergies held at the pre-shape
        while reaching (``power_free_reach=False``). Some objects are grasped
        only one way: the held reach gets a cereal box (60 x 190 x 270 mm)
        that the free reach misses from the first five starts.
    power_sq_hold : float or None
        Power grasps: once g_sQ is below this, the sQ row asks only to keep
        its value instead of ``sq_step`` less. The predicted grasp is then
        good enough, and a row still pulling sQ towards -1 (first priority
        level) took the step from the palm and finger rows: attempts stalled
        with g_sQ near -0.13 and the palm or the fingers short of the
        surface. None: the moving target all the way.
    power_capsule_rows : bool
        Power grasps with ``power_phases``: once an attempt has met the
        criterion with a phalanx capsule deeper than ``max_penetration``, its
        segment rows watch the capsules as well as the skin points while the
        palm touches: a capsule deeper in the object than its skin points read
        (an edge or a thin plate cutting in between them) gets its signed
        distance as its row (`synergrasp.planner.status.capsule_rows`), so the
        step pushes that phalanx out. One fcl query per wrap iteration, paid
        only by the attempts that need it.
    """

    eps_c: float = 5.0
    mu: float = 0.3
    edges: int = 8
    sq_step: float = 0.1
    contact_target: float = 3.5
    smoothing: float = 0.1
    radius: float = 0.05
    radius_max: float = 0.2
    radius_min: float = 0.002
    stall_window: int = 12
    iterations_per_attempt: int = 120
    restarts: int = 24
    start_distance: float = 150.0
    max_penetration: float = 3.0
    backoffs: int = 2
    standoff: float = 20.0
    crawl_window: int = 30
    crawl_fraction: float = 0.05
    touch_window: int = 30
    start_clearance: float = 5.0
    power_phases: bool = True
    power_preshape: tuple | None = (0.0, 1.0)
    power_wide_preshape: tuple | None = (-1.0, 1.0)
    power_free_reach: bool = True
    contact_band: tuple | None = (1.0, 4.5)
    band_after: int = 600
    power_held_pass: bool = True
    power_sq_hold: float | None = -0.05
    power_capsule_rows: bool = True


def start_configuration(hand, obj, approach=(0.0, 1.0, 0.0), distance=150.0, clearance=None, palm_centred=False):
    """The default start: mean pose, palm facing the object's centre.

    The palm is ``distance`` mm from the centre along ``approach`` (farther if
    ``clearance`` asks for it) and faces it;
    the hand is rolled about the approach so that the thumb-to-fingers direction
    (the palm's y axis) lies across the object's thinnest extent orthogonal to
    the approach, as a person pre-shapes a pinch. An approach within 18 degrees
    of the x axis is tilted up by 19 degrees: with the palm normal along x the
    XYZ Euler angles are in gimbal lock (phi2 = +-90 degrees) and the
    orientation columns of the Jacobian lose rank.

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
        fingertips' centroid (the wide power pre-shape's starts: the palm
        lands near the middle of a face, the fingers reach past its edge).

    Returns
    -------
    (6 + n_syn,) float

    Examples
    --------
    >>> from synergrasp import objects
    >>> u = start_configuration(SynergyHand.default(), objects.ellipsoid(), (0.0, 0.0, 1.0))
    >>> u.shape
    (8,)
    """
    a = as_vector(approach, "approach", 3)
    if np.linalg.norm(a) < 1e-9:
        raise ValueError("approach must be a non-zero direction (object centre to hand)")
    a = a / np.linalg.norm(a)
    if abs(a[0]) > 0.95:  # palm normal along x: the XYZ Euler angles would start in gimbal lock
        a = a + np.array([0.0, 0.0, 0.35])
        a /= np.linalg.norm(a)
    z = -a
    extents = np.array(obj.extents, dtype=float)
    along = np.abs(np.eye(3) @ a)
    candidates = np.eye(3) - np.outer(np.eye(3) @ z, z)  # world axes projected off the approach
    usable = np.linalg.norm(candidates, axis=1) > 0.5
    order = np.lexsort((along, np.where(usable, extents, np.inf)))
    y = candidates[order[0]]
    y /= np.linalg.norm(y)
    R = np.column_stack([np.cross(y, z), y, z])
    phi = Rotation.from_matrix(R).as_euler("XYZ")
    u = np.r_[np.zeros(6), np.zeros(hand.n_syn)]
    tips = hand.points(u, "precision")
    aim = np.zeros(3) if palm_centred else np.array([tips[:, 0].mean(), tips[:, 1].mean(), 0.0])
    if clearance is not None:  # the fingertips start outside the object, however long it is along the approach
        reach = max(float(np.max((p.vertices - obj.center) @ a)) for p in obj.convex)
        distance = max(distance, reach + float(tips[:, 2].mean()) + clearance)
    u[:3] = obj.center + a * distance - R @ aim
    u[3:6] = phi
    return u


def _caller_first(directions, approach):
    """The directions as float tuples, the caller's approach (if any) first and not repeated."""
    order = [tuple(float(x) for x in d) for d in directions]
    if approach is None:
        return order
    a = tuple(float(x) for x in approach)
    return [a] + [d for d in order if not (np.allclose(np.cross(d, a), 0) and np.dot(d, a) > 0)]


def attempt_schedule(approach=None, standoff=20.0, directions=APPROACHES):
    """The starts tried in turn: approach directions and the stand-off of each attempt.

    The caller's approach (if any) and then ``directions`` without a stand-off for the
    first `PLAIN_FIRST` attempts; then attempts alternate between the rest of
    ``directions`` and `STANDOFF_APPROACHES`, the latter with ``standoff`` and half
    of it in turn (which one works varies from object to object). A direction
    equal to the caller's is not repeated without a stand-off.

    Parameters
    ----------
    approach : (3,) float, optional
        The caller's first direction (object centre to hand).
    standoff : float
        Largest stand-off (mm) of the alternate attempts (0: none).
    directions : sequence of (3,) float
        The plain attempts' directions in order (`plan` passes `APPROACHES`;
        power grasps have their own `power_schedule`).

    Returns
    -------
    list of ((3,) float, float)
        Direction and stand-off of each attempt.

    Examples
    --------
    >>> schedule = attempt_schedule()
    >>> [s for _, s in schedule[:5]]
    [0.0, 0.0, 0.0, 20.0, 0.0]
    """
    plain = _caller_first(directions, approach)
    schedule = [(d, 0.0) for d in plain[:PLAIN_FIRST]]
    rest = [(d, 0.0) for d in plain[PLAIN_FIRST:]]
    aside = [(tuple(d), float(standoff) * (1.0 if k % 2 == 0 else 0.5)) for k, d in enumerate(STANDOFF_APPROACHES)] if standoff > 0 else []
    for k in range(max(len(rest), len(aside))):
        schedule += rest[k : k + 1] + aside[k : k + 1]
    return schedule


def power_schedule(approach=None, wide=True):
    """The starts of a power plan: approach directions and the pre-shape of each attempt.

    Attempts alternate between the wide pre-shape (from `POWER_WIDE_APPROACHES`,
    first, the palm's centre facing the object's centre) and the cupped one
    (from `POWER_APPROACHES`, the fingertips facing it): which one closes on
    an object varies from object to object. The caller's approach, if any, comes
    first in both orders.

    Parameters
    ----------
    approach : (3,) float, optional
        The caller's first direction (object centre to hand).
    wide : bool
        Alternate with the wide pre-shape; False: cupped starts only.

    Returns
    -------
    list of ((3,) float, bool)
        Direction of each attempt, and whether it starts from the wide pre-shape.

    Examples
    --------
    >>> [w for _, w in power_schedule()[:4]]
    [True, False, True, False]
    """
    orders = [_caller_first(d, approach) for d in ((POWER_WIDE_APPROACHES, POWER_APPROACHES) if wide else (POWER_APPROACHES,))]
    flags = (True, False) if wide else (False,)
    return [(d, flag) for pair in zip(*orders) for d, flag in zip(pair, flags)]


def hand_opening(hand):
    """The hand's largest opening: the farthest a fingertip gets from the thumb tip (mm).

    Taken over the corners and centre of the synergy box.

    Parameters
    ----------
    hand : SynergyHand

    Returns
    -------
    float
    """
    lo, hi = hand.synergy_limits[:, 0], hand.synergy_limits[:, 1]
    corners = np.array(np.meshgrid(*[(a, 0.5 * (a + b), b) for a, b in zip(lo, hi)])).reshape(hand.n_syn, -1).T
    widest = 0.0
    for z in corners:
        tips = hand.points(np.r_[np.zeros(6), z], "precision")
        widest = max(widest, float(np.linalg.norm(tips[1:] - tips[0], axis=1).max()))
    return widest


def sq_request(sq_step, radius, gradient):
    """Decrease of g_sQ that one precision step asks for: ``sq_step``, or what a step within the trust radius gives.

    A request larger than the linear model can deliver within the radius
    would make the sQ row dominate the direction of the (then truncated)
    step, and the contact rows would get almost nothing of it.

    Parameters
    ----------
    sq_step : float
        The requested decrease per iteration.
    radius : float
        Trust radius of the normalised step.
    gradient : (k,) float
        Gradient of g_sQ with respect to the normalised configuration.

    Returns
    -------
    float
        ``min(sq_step, radius * |gradient|)``.

    Examples
    --------
    >>> sq_request(0.1, 0.01, np.array([3.0, 4.0]))
    0.05
    """
    return min(float(sq_step), float(radius) * float(np.linalg.norm(gradient)))


def _preshape(value, name, hand):
    """A power pre-shape option as synergy values within the limits (the mean pose, zeros, for None)."""
    if value is None:
        return np.zeros(hand.n_syn)
    preshape = np.asarray(value, dtype=float)
    if preshape.shape != (hand.n_syn,) or not np.all(np.isfinite(preshape)):
        instead = "start from the mean pose" if name == "power_preshape" else "try power_preshape only"
        raise ValueError(
            f"{name} must hold one finite value per synergy ({hand.n_syn} for {hand.name}), "
            f"got {value!r}; pass {name}=None to {instead}"
        )
    return np.clip(preshape, hand.synergy_limits[:, 0], hand.synergy_limits[:, 1])


def _starts(hand, obj, grasp, opts, first, preshapes):
    """The start configurations and stand-offs of the attempts in turn, each computed when it is needed.

    ``preshapes`` is (cupped, wide or None) for a power grasp, None for a precision grasp.
    """
    if grasp == "precision":
        for d, standoff in attempt_schedule(first, opts.standoff)[: opts.restarts]:
            yield start_configuration(hand, obj, d, opts.start_distance, opts.start_clearance), standoff
        return
    cupped, wide = preshapes
    for d, is_wide in power_schedule(first, wide is not None)[: opts.restarts]:
        yield _power_start(hand, obj, d, opts, wide if is_wide else cupped, is_wide), 0.0


def _power_start(hand, obj, direction, opts, preshape, wide):
    """A power start: `start_configuration` from ``direction`` (palm-centred for the wide pre-shape), synergies at ``preshape``.

    The pre-shape moves the fingers from where `start_configuration` cleared
    them; the hand is then moved back along its palm normal until every
    phalanx capsule is ``start_clearance`` mm from the object (a wide open
    hand in front of a large object can start with fingers inside it).
    """
    u = start_configuration(hand, obj, direction, opts.start_distance, opts.start_clearance, palm_centred=wide)
    u[6:] = preshape
    back = -rotation_xyz(u[3:6])[:, 2]  # the palm normal reversed: away from the object
    for _ in range(20):
        need = opts.start_clearance - float(_phalanx_penetration(hand, obj, u).distances.min())
        if need <= 0.0:
            break
        u[:3] += back * (need + 1e-6)
    return u


def _phalanx_penetration(hand, obj, u):
    """`GraspObject.penetration` of the hand's phalanx capsules at configuration u."""
    geo = hand.segments(u)
    return obj.penetration(geo.capsules, geo.radius)


def _contact_goal(cp, target, band, offset):
    """What the contact rows ask for (mm): ``target + offset``, or cP clipped to the shifted ``band`` if there is one."""
    if band is None:
        return target + offset
    low, high = band
    return np.clip(cp, low + offset, high + offset)


def _attempt(hand, obj, kind, u0, opts, backend, budget, progress, standoff=0.0, band=None):
    """One attempt of the iteration from u0, the contact rows asking ``standoff * clip(g_sQ, 0, 1)`` mm more.

    ``band``: the contact band of the attempt (see ``PlannerOptions.contact_band``), None for the target.

    Returns (reason, trajectory, statuses, checks, final status, final penetration depth, lp_solves).
    """
    size = obj.torque_scale
    n_u = len(u0)
    scale_u = np.r_[np.full(3, size), np.ones(n_u - 3)]  # normalised u = u / scale_u
    smoothing = opts.smoothing * size

    watch_capsules = kind == "power" and opts.power_phases and opts.power_capsule_rows
    capsules_seen = False  # an attempt watches the capsules once it has met the criterion with a phalanx too deep

    def evaluate(u):
        nonlocal capsules_seen
        st = grasp_status(hand, obj, u, kind, mu=opts.mu, edges=opts.edges, backend=backend, smoothing=smoothing)
        pen = None
        if capsules_seen and st.g[-2] < opts.eps_c:  # wrapping
            pen = _phalanx_penetration(hand, obj, u)
            st = capsule_rows(hand, obj, u, st, pen)
        # a pinch must not end with the palm on the object
        palm = lambda: float(obj.contact_distance(hand.points(u, "power")[-1:], backend=backend).value[0])  # noqa: E731
        chk = check_grasp(obj, st, kind, eps_c=opts.eps_c, mu=opts.mu, edges=opts.edges, backend=backend,
                          palm_distance=palm if kind == "precision" else None)
        if chk.done and kind == "power" and opts.power_phases:
            # not done while a phalanx is in the object: its penetrating row pushes it out
            if pen is None:
                pen = _phalanx_penetration(hand, obj, u)
            if pen.depth > opts.max_penetration:
                chk = replace(chk, done=False)
                if watch_capsules and not capsules_seen:
                    capsules_seen = True
                    st = capsule_rows(hand, obj, u, st, pen)
        return st, chk

    u = np.array(u0, dtype=float)
    st, chk = evaluate(u)
    n = len(st.g) - 1
    row_scale = np.r_[np.full(n, 1.0 / size), 1.0]
    radius, stalled, best = opts.radius, 0, np.inf
    traj, statuses, checks = [u.copy()], [st.g.copy()], [chk]
    solves = st.lp_solves + chk.lp_solves
    reason = f"iteration cap ({budget}) reached"
    labels = hand.point_labels(kind)
    segments = hand.segments(u).labels
    # the status rows of each phalanx: its own hand point (power) or its finger's tip (precision)
    rows_of = {seg: [i for i, lab in enumerate(labels) if lab == seg] or [i for i, lab in enumerate(labels) if lab[0] == seg[0]]
               for seg in segments}
    backoff, backoffs, depth = np.zeros(n), 0, None
    bests, touched = [], False
    for _ in range(budget):
        if chk.done:
            pen = _phalanx_penetration(hand, obj, u)
            depth = pen.depth
            if depth <= opts.max_penetration or backoffs == opts.backoffs:
                reason = "stop criterion met"
                break
            backoffs += 1  # back the too-deep fingers off by their depth and go on
            for seg, d in zip(segments, pen.depths):
                if d > opts.max_penetration:
                    backoff[rows_of[seg]] = np.maximum(backoff[rows_of[seg]], d)
            best, stalled, bests = np.inf, 0, []
        depth = None
        target = np.r_[_contact_goal(st.g[:-1], opts.contact_target, band, standoff * np.clip(st.g[-1], 0.0, 1.0) + backoff), 0.0]
        sq_step = sq_request(opts.sq_step, radius, st.J[-1] * scale_u) if kind == "precision" else opts.sq_step
        target[-1] = max(-1.0, st.g[-1] - sq_step)
        if kind == "power" and opts.power_sq_hold is not None and st.g[-1] < opts.power_sq_hold:
            target[-1] = st.g[-1]  # predicted good enough: keep it, the contact rows get the step
        first = np.r_[st.g[:-1] < 0.0, True]  # first priority: sQ and penetrating hand points
        active, reaching = np.r_[target[:-1] != st.g[:-1], True], False  # a fingertip inside its band is free
        if kind == "power" and opts.power_phases:
            if st.g[-2] < opts.eps_c:  # wrap: the palm has touched, it stays on the surface
                first[-2] = True
            else:  # reach: the palm leads with the hand held open, the fingers only kept out of the object
                active[:-2] = st.g[:-2] < 0.0
                reaching = True
        e = active * row_scale * (target - st.g)
        J = (active * row_scale)[:, None] * st.J * scale_u
        if reaching and not opts.power_free_reach:
            J[:, 6:] = 0.0  # the synergies keep their pre-shape
        du = limited_step(J[active], e[active], u[6:], hand.synergy_limits, first[active])
        step = np.abs(du).max()
        if step > radius:
            du *= radius / step
        u_new = u + du * scale_u
        u_new[6:] = np.clip(u_new[6:], hand.synergy_limits[:, 0], hand.synergy_limits[:, 1])
        st_new, chk_new = evaluate(u_new)
        solves += st_new.lp_solves + chk_new.lp_solves
        # adaptive step length: compare the achieved with the predicted change of the residual
        before = np.sum(e**2)
        after = np.sum((active * row_scale * (target - st_new.g)) ** 2)
        predicted = np.sum((e - J @ ((u_new - u) / scale_u)) ** 2)
        ratio = (before - after) / max(before - predicted, 1e-15)
        if ratio > 0.75:
            radius = min(1.5 * radius, opts.radius_max)
        elif ratio < 0.25:
            radius = max(0.5 * radius, opts.radius_min)
        u, st, chk = u_new, st_new, chk_new
        traj.append(u.copy())
        statuses.append(st.g.copy())
        checks.append(chk)
        if progress is not None:
            progress(chk, st)
        merit = np.sum((row_scale[:-1] * (st.g[:-1] - _contact_goal(st.g[:-1], opts.contact_target, band, backoff))) ** 2) + max(st.g[-1], -0.1)
        if merit < best - 1e-4:
            best, stalled = merit, 0
        else:
            stalled += 1
        bests.append(best)
        touched = touched or st.g[:-1].min() < opts.eps_c + standoff * np.clip(st.g[-1], 0.0, 1.0)
        if kind == "precision" and opts.touch_window and not touched and len(traj) > opts.touch_window:
            reason = f"stalled (no fingertip reached the surface in {opts.touch_window} iterations)"
            break
        if stalled >= opts.stall_window:
            reason = f"stalled (no progress in {opts.stall_window} iterations)"
            break
        if opts.crawl_window and len(bests) > opts.crawl_window:
            earlier = bests[-1 - opts.crawl_window]
            if earlier - best < opts.crawl_fraction * (abs(earlier) + 0.1):
                reason = f"stalled (merit down less than {opts.crawl_fraction:.0%} in {opts.crawl_window} iterations)"
                break
    if depth is None:
        depth = _phalanx_penetration(hand, obj, u).depth
    if reason == "stop criterion met" and depth > opts.max_penetration:
        reason = f"grasp rejected: a phalanx penetrates the object by {depth:.1f} mm"
    return reason, traj, statuses, checks, st, depth, solves


def plan(obj, grasp="precision", *, backend="highs", u0=None, max_iter=1500, approach=None, hand=None,
         progress=None, **options) -> PlanResult:
    """Plan a reach-to-grasp motion (paper Sec. 3.2) for the synergy hand.

    Parameters
    ----------
    obj : GraspObject, str or os.PathLike
        The object (``synergrasp.objects``), or a built-in name or a file
        path as `synergrasp.objects.get` takes them.
    grasp : {"precision", "power"}
        Fingertip pinch, or a grasp with the phalanges and the palm.
    backend : str
        LP backend.
    u0 : (8,) float, optional
        Start configuration; default `start_configuration` from ``approach``.
        With ``u0`` given only one attempt is made.
    max_iter : int
        Cap on the total number of iterations over all attempts (of both
        passes, see ``band_after`` and ``power_held_pass``).
    approach : (3,) float, optional
        Direction from the object's centre to the start pose of the first
        attempt; later attempts (after a stall) use `APPROACHES` and
        `STANDOFF_APPROACHES` for a precision grasp (see `attempt_schedule`),
        `POWER_WIDE_APPROACHES` and `POWER_APPROACHES` for a power grasp (see
        `power_schedule`).
    hand : SynergyHand, optional
        Default: ``SynergyHand.default()``.
    progress : callable, optional
        Called as ``progress(check, status)`` after every iteration.
    **options
        Fields of `PlannerOptions`.

    Returns
    -------
    PlanResult

    Raises
    ------
    TypeError
        If ``obj`` is not an object, a name or a path.
    ValueError
        Unknown object name or grasp type, bad ``u0`` or ``approach``, unknown option or backend.

    Examples
    --------
    >>> from synergrasp import objects
    >>> result = plan(objects.ellipsoid(), "precision")
    >>> result.success, len(result.contact_labels) >= 3, result.final_q < 0
    (True, True, True)
    """
    if isinstance(obj, (str, os.PathLike)):
        obj = objects.get(obj)
    elif not isinstance(obj, objects.GraspObject):
        raise TypeError(f"obj must be a GraspObject, a built-in name or a file path, got {type(obj).__name__}")
    if grasp not in GRASPS:
        raise ValueError(f"grasp must be one of {GRASPS}, got {grasp!r}")
    unknown = set(options) - set(PlannerOptions.__dataclass_fields__)
    if unknown:
        raise ValueError(f"unknown planner options {sorted(unknown)}; known: {sorted(PlannerOptions.__dataclass_fields__)}")
    opts = replace(PlannerOptions(), **options)
    if opts.contact_band is not None:
        band = np.asarray(opts.contact_band, dtype=float)
        if band.shape != (2,) or not np.all(np.isfinite(band)) or not 0 <= band[0] < band[1]:
            raise ValueError(
                f"contact_band must be (low, high) mm with 0 <= low < high, got {opts.contact_band!r}. "
                "Pass contact_band=None to use contact_target only."
            )
    if grasp == "power" and "contact_band" in options and opts.contact_band is not None:
        raise ValueError("contact_band is for precision grasps only; power grasps use contact_target")
    if isinstance(opts.band_after, bool) or not isinstance(opts.band_after, (int, np.integer)) or opts.band_after < 0:
        raise ValueError(f"band_after must be an integer >= 0 (iterations), got {opts.band_after!r}")
    if opts.power_sq_hold is not None and (isinstance(opts.power_sq_hold, bool) or not isinstance(opts.power_sq_hold, (int, float))
                                           or not np.isfinite(opts.power_sq_hold)):
        raise ValueError(f"power_sq_hold must be a finite number (a g_sQ value, e.g. -0.05) or None, got {opts.power_sq_hold!r}")
    if not isinstance(opts.power_capsule_rows, (bool, np.bool_)):
        raise ValueError(f"power_capsule_rows must be True or False, got {opts.power_capsule_rows!r}")
    get_backend(backend)
    hand = hand or SynergyHand.default()
    if int(max_iter) < 1:
        raise ValueError(f"max_iter must be >= 1, got {max_iter}")
    width, opening = float(np.min(obj.extents)), hand_opening(hand)
    if width < MIN_WIDTH:
        raise ValueError(
            f"{getattr(obj, 'name', 'the object')} is too small to grasp: its smallest extent is {width:.2g} mm "
            f"(less than {MIN_WIDTH:g} mm). Is it in metres? Load it with sg.objects.load(path, scale=1000)."
        )
    if width > opening:
        raise ValueError(
            f"{getattr(obj, 'name', 'the object')} is too large for the hand: its smallest extent is {width:.0f} mm "
            f"but the hand opens at most {opening:.0f} mm between thumb and fingertips. Check the object's units "
            "(sg.objects.load(path, scale=...)) or use a larger hand file."
        )
    preshapes = None
    if grasp == "power":
        preshapes = (_preshape(opts.power_preshape, "power_preshape", hand),
                     None if opts.power_wide_preshape is None else _preshape(opts.power_wide_preshape, "power_wide_preshape", hand))
    first = as_vector(approach, "approach", 3) if approach is not None else None
    u0 = None if u0 is None else as_vector(u0, "u0", hand.n_u)
    # passes over the schedule: (options, contact band, iterations in all at which the pass ends)
    passes = [(opts, None, max_iter)]
    if grasp == "precision" and opts.contact_band is not None:
        passes = [(opts, None, min(opts.band_after, max_iter)), (opts, tuple(opts.contact_band), max_iter)]
    if grasp == "power" and opts.power_free_reach and opts.power_held_pass:
        passes.append((replace(opts, power_free_reach=False), None, max_iter))
    passes = [p for p in passes if p[2] > 0][: 1 if u0 is not None else None]  # u0: one attempt
    t0 = time.perf_counter()
    total, solves, attempts = 0, 0, []
    for number, (pass_opts, band, end) in enumerate(passes, 1):
        starts = [(u0, 0.0)] if u0 is not None else _starts(hand, obj, grasp, opts, first, preshapes)
        for u_start, standoff in starts:
            budget = min(opts.iterations_per_attempt, end - total)
            if budget <= 0:
                break
            reason, traj, statuses, checks, final, depth, n_solves = _attempt(
                hand, obj, grasp, u_start, pass_opts, backend, budget, progress, standoff, band
            )
            total += len(traj) - 1
            solves += n_solves
            attempts.append({"start": u_start.tolist(), "standoff": standoff, "pass": number,
                             "band": band and list(band), "iterations": len(traj) - 1, "reason": reason,
                             "status": np.array(statuses).tolist()})
            if reason == "stop criterion met":
                break
        if reason == "stop criterion met":
            break
    chk = checks[-1]
    success = reason == "stop criterion met"
    labels = hand.point_labels(grasp)
    if success:
        reason = f"stop criterion met ({chk.n_contacts} contacts, g_Q = {chk.q:.4f})"
    else:
        reason = f"no stable grasp found: {len(attempts)} attempt(s), last {attempts[-1]['reason']}"
    if len(attempts) > 1:
        reason += f"; {len(attempts)} attempts from different approach directions, {total} iterations in all"
    return PlanResult(
        success=bool(success),
        reason=reason,
        iterations=len(traj) - 1,
        u=traj[-1],
        trajectory=np.array(traj),
        status=np.array(statuses),
        target=np.r_[np.zeros(len(statuses[0]) - 1), -1.0],
        q_history=np.array([c.q for c in checks]),
        contact_points=final.nearest[chk.contact],
        contact_normals=final.normals[chk.contact],
        contact_labels=[lab for lab, c in zip(labels, chk.contact) if c],
        penetration=float(depth),
        time_s=time.perf_counter() - t0,
        lp_solves=int(solves),
        backend=get_backend(backend).name,
        grasp=grasp,
        object_name=getattr(obj, "name", ""),
        options={k: list(v) if isinstance(v, tuple) else v for k, v in asdict(opts).items()},  # as JSON keeps them
        attempts=attempts,
    )
