"""The executable reach of a grasp: a pre-grasp, an approach and a close that keep the hand out of the object.

The planner's iteration (`PlanResult.trajectory`) is a search: it watches a
few points per phalanx, and whole capsules cross the object between them.
`executable_reach` turns a found grasp ``u*`` into a path a robot can run:

1. **open**: the synergies move from ``z*`` away from the object as far as
   that helps (`open_synergies`), or part of the way to the hand's widest
   opening (`widest_opening`, `OPENINGS`);
2. **retreat**: the open hand moves from the grasp's pose along a retreat
   direction (`retreat_directions`: straight back along the palm normal
   first) until every phalanx capsule and the palm box clear the object by
   ``margin``: the pre-grasp;
3. the path is the **approach** (pre-grasp to the grasp's pose, hand open,
   a straight line) then the **close** (synergies to ``z*``), checked
   densely (`synergrasp.planner.clearance.path_clearance`).

Candidates (opening, retreat direction) are tried in turn until one's path
stays within ``tolerance`` of the object everywhere. When none does, their
pre-grasps are tried once more with a **closing approach**: the hand moves
and closes at once, along the straight line in ``u`` from the pre-grasp to
the grasp, so that fingers wrapped around the object reach its sides as
they close rather than sweeping through it open. When none of those does
either, the candidate that goes least beyond ``tolerance`` is returned with
``collision_free=False``, its depth and the shape (capsule or palm) that
goes deepest.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np

from .._checks import as_points, as_vector, integer, positive_scalar
from ..hand import LIMIT_TOLERANCE, rotation_xyz
from .clearance import HandClearance

__all__ = ["OPENINGS", "SOURCES", "Reach", "executable_reach", "open_synergies", "retreat_directions", "widest_opening"]

#: Fractions of the way from the grasp's synergies to the widest opening, tried in turn after `open_synergies`.
OPENINGS = (0.5, 1.0)
#: How far (mm) below its floors the first failing candidate is checked: no path goes that deep, so it is checked whole.
_WHOLE = 1e9
#: How a reach is made (`Reach.source`), each with what a collision-free one's reason says stays clear: the open
#: hand's approach then the close, the hand closing while it approaches, or the planner's iteration as it is.
_STAYS = {"approach": "approach and close stay", "closing approach": "the approach, closing the hand on the way, stays",
          "trajectory": "the iteration stays"}
SOURCES = tuple(_STAYS)


@dataclass(frozen=True)
class Reach:
    """An executable reach-to-grasp path and its safety (`executable_reach`).

    Attributes
    ----------
    path : (k, 6 + n_syn) float
        Configurations from the pre-grasp to the grasp, dense enough that
        between two rows (a straight line in ``u``) no part of the hand
        crosses the object unseen (see `path_clearance`).
    clearance : (k,) float
        Smallest signed distance (mm) of the phalanx capsules and the palm
        box to the object at each row of ``path``: negative inside.
    closest : list of str
        The shape with that distance at each row (``"T3"``, ..., ``"palm"``).
    pregrasp : (6 + n_syn,) float
        The first row of ``path``: the hand open and clear of the object by
        ``margin`` (the iteration's start pose when ``source`` is
        ``"trajectory"``).
    collision_free : bool
        No row of ``path`` is deeper in the object than ``tolerance``.
    depth : float
        Deepest penetration along ``path`` into the object's convex pieces
        (mm, 0 if it never touches).
    deepest : str
        The shape that goes deepest (``""`` if none penetrates).
    deepest_row : int
        Its row of ``path``.
    grasp_depth : float
        Penetration of the grasp itself into the pieces (mm, 0 if clear); a
        path cannot end shallower than that.
    grasp_shape : str
        The shape deepest in the object at the grasp (``""`` if none).
    source : str
        ``"approach"`` (the open hand's approach, then the close),
        ``"closing approach"`` (the hand closing while it approaches: one
        straight line in ``u`` from the pre-grasp to the grasp) or
        ``"trajectory"`` (the planner's iteration, collision-free as it
        is).
    direction : (3,) float
        Retreat direction of the pre-grasp (world, unit; zeros for a
        trajectory).
    retreat : float
        Distance (mm) of the pre-grasp's palm from the grasp's.
    candidates : int
        Candidate paths checked (the trajectory counts as one).
    margin, tolerance : float
        The settings used (mm).
    reason : str
        The outcome in words, with the numbers.
    cpu_time : float
        CPU time of `executable_reach` (s).
    """

    path: np.ndarray
    clearance: np.ndarray
    closest: list
    pregrasp: np.ndarray
    collision_free: bool
    depth: float
    deepest: str
    deepest_row: int
    grasp_depth: float
    grasp_shape: str
    source: str
    direction: np.ndarray
    retreat: float
    candidates: int
    margin: float
    tolerance: float
    reason: str
    cpu_time: float

    def summary(self) -> dict:
        """The scalar fields as a JSON-serialisable dict (what `PlanResult.reach` keeps)."""
        keys = ("collision_free", "depth", "deepest", "deepest_row", "grasp_depth", "grasp_shape", "source",
                "retreat", "candidates", "margin", "tolerance", "reason", "cpu_time")
        out = {k: getattr(self, k) for k in keys}
        out["direction"] = self.direction.tolist()
        return out

    def plan_fields(self) -> dict:
        """The fields of `PlanResult` that hold this reach: ``pregrasp``, ``path``, ``clearance``, ``collision_free``, ``reach``."""
        return dict(pregrasp=self.pregrasp, path=self.path, clearance=self.clearance,
                    collision_free=self.collision_free, reach=self.summary())


def widest_opening(hand):
    """Synergy values of the hand's widest opening: the farthest fingertip from the thumb tip.

    Taken over the corners, edge midpoints and centre of the synergy limits'
    box (`SynergyHand.synergy_grid` of 3 values per synergy). For the paper's hand: (-1, 1), the fingers nearly flat and the thumb
    spread away from them.

    Parameters
    ----------
    hand : SynergyHand

    Returns
    -------
    (n_syn,) float

    Examples
    --------
    >>> from synergrasp import SynergyHand
    >>> widest_opening(SynergyHand.default()).tolist()
    [-1.0, 1.0]
    """
    grid = hand.synergy_grid(3)

    def spread(z):
        tips = hand.points(np.r_[np.zeros(6), z], "precision")
        return float(np.linalg.norm(tips[1:] - tips[0], axis=1).max())

    return grid[int(np.argmax([spread(z) for z in grid]))].copy()


def open_synergies(hand, checker, u, margin, steps=6):
    """Synergies opened from the grasp's by clearance ascent, as far as opening helps.

    At each step the phalanx capsules within 5 mm of the hand's clearance
    (and within ``margin``) give the gradient of their distance with respect
    to the synergies (`HandClearance.gradients`); the direction that increases the smallest of these
    distances fastest (a small LP, within the synergy limits) is followed
    with the longest of a few steps that increases the hand's clearance.
    It stops once the hand clears the object by ``margin``, when no
    direction opens every near phalanx, or when no step helps.

    Parameters
    ----------
    hand : SynergyHand
    checker : HandClearance
        Of the hand and the object.
    u : (6 + n_syn,) float
        The grasp.
    margin : float
        mm.
    steps : int
        Most steps.

    Returns
    -------
    (n_syn,) float
    """
    lo, hi = hand.synergy_limits[:, 0], hand.synergy_limits[:, 1]
    z = u[6:].copy()
    value = checker.at(u)[0]
    for _ in range(steps):
        if value >= margin:
            break
        pose = np.r_[u[:6], z]
        _, _, grads = checker.gradients(pose, min(margin, value + 5.0))
        grads = [g[6:] for g in grads if np.linalg.norm(g[6:]) > 1e-6]
        dz = _ascent(np.array(grads), z, lo, hi) if grads else None
        if dz is None:
            break
        for alpha in (0.4, 0.2, 0.1, 0.05):
            z_try = np.clip(z + alpha * dz, lo, hi)
            v = checker.at(np.r_[u[:6], z_try])[0]
            if v > value + 1e-3:
                z, value = z_try, v
                break
        else:
            break
    return z


def _ascent(grads, z, lo, hi):
    """The step dz (|dz_i| <= 1, within the limits) maximising min(grads @ dz); None if that is not positive."""
    from scipy.optimize import linprog

    m, n = grads.shape
    bounds = [(0.0 if z[i] <= lo[i] + LIMIT_TOLERANCE else -1.0, 0.0 if z[i] >= hi[i] - LIMIT_TOLERANCE else 1.0)
              for i in range(n)]
    res = linprog(np.r_[np.zeros(n), -1.0], A_ub=np.c_[-grads, np.ones(m)], b_ub=np.zeros(m),
                  bounds=bounds + [(None, 1e3)], method="highs")
    if res.status != 0 or -res.fun <= 1e-9:
        return None
    return res.x[:n]


def retreat_directions(hand, u, z_open, normals=()):
    """Directions (world, unit) along which the open hand leaves the grasp's pose, in the order tried.

    The palm normal reversed first (straight back); then straight back slid
    along the object where the hand is near it (its components into the
    object at the near shapes removed: a pinch of a plate's edge leaves in
    the plate's plane); then the fingers' opening direction (the mean
    motion of the fingertips as the synergies open from ``u``'s to
    ``z_open``) and its mean with straight back; then straight back tilted
    towards the wrist, past the fingertips, and to either side (the palm's
    x axis).

    Parameters
    ----------
    hand : SynergyHand
    u : (6 + n_syn,) float
        The grasp.
    z_open : (n_syn,) float
        The pre-grasp's synergies.
    normals : (m, 3) float, optional
        Unit directions away from the object at the shapes near it.

    Returns
    -------
    (j, 3) float
        Unit rows, none repeated.
    """
    rot = rotation_xyz(u[3:6])
    x, y, back = rot[:, 0], rot[:, 1], -rot[:, 2]
    slid = back.copy()
    for _ in range(10):  # alternate projections onto the half-spaces n . d >= 0
        inward = [n for n in normals if n @ slid < -1e-9]
        if not inward:
            break
        for n in inward:
            slid = slid - min(0.0, float(n @ slid)) * n
    tips = hand.points(np.r_[u[:6], z_open], "precision") - hand.points(u, "precision")
    opening = tips.mean(axis=0)
    candidates = [back, slid, opening, opening / max(np.linalg.norm(opening), 1e-12) + back,
                  back - y, back + y, back + x, back - x]
    out = []
    for d in candidates:
        n = np.linalg.norm(d)
        if n > 1e-6 and all(np.dot(d / n, e) < 1.0 - 1e-6 for e in out):
            out.append(d / n)
    return np.array(out)


def executable_reach(hand, obj, u_grasp, trajectory=None, *, margin=10.0, tolerance=3.0, budget=24,
                     openings=OPENINGS, max_retreat=300.0, resolution=0.25) -> Reach:
    """An executable reach to a grasp: pre-grasp, approach and close, checked densely.

    If ``trajectory`` (the planner's iteration, ending at the grasp) is given
    and stays within ``tolerance`` of the object everywhere, it is the path
    as it is. Otherwise candidates are tried in turn. Each opens the hand,
    first by `open_synergies`, then to each fraction of `OPENINGS` of the way
    towards `widest_opening`; and moves the open hand from the grasp's pose
    along a direction of `retreat_directions` until every phalanx capsule
    and the palm box clear the object by ``margin`` (the pre-grasp). Its
    path is the straight approach back to the grasp's pose, then the close
    of the synergies to the grasp's. The first two directions of every
    opening come first, then the others. The first candidate whose path
    stays within ``tolerance`` everywhere is returned. If none does, the
    same pre-grasps are tried with the hand closing while it approaches
    (one straight line in ``u`` to the grasp: fingers that wrap around the
    object pass its sides as they close); if none of those does either,
    the candidate path that goes least below the floors (``tolerance``,
    below) is returned.

    The path can be no shallower than the grasp itself: when the grasp
    penetrates deeper than ``tolerance``, the reach is not collision-free.
    The candidates are then held, shape by shape, to ``tolerance``, or to
    the shape's own depth at the grasp plus ``tolerance`` where that is
    deeper (the palm of a grasp that sinks it into the object may be that
    deep on the way, the fingers no deeper than ``tolerance``).

    Parameters
    ----------
    hand : SynergyHand
    obj : GraspObject
    u_grasp : (6 + n_syn,) float
        The grasp configuration.
    trajectory : (n, 6 + n_syn) float, optional
        A path ending at (or near) the grasp, e.g. `PlanResult.trajectory`.
    margin : float
        Clearance of the pre-grasp (mm).
    tolerance : float
        Deepest penetration allowed along the path (mm): the planner's
        ``max_penetration`` for the grasp itself.
    budget : int
        Most pre-grasps tried (the trajectory not counted); each gives an
        approach and close, then, if none of those is collision-free, a
        closing approach (not where the pre-grasp is the open hand at the
        grasp's pose, or the opening is the grasp's synergies: that path
        is the one already checked).
    openings : sequence of float
        Fractions in [0, 1] of the way from the grasp's synergies to the
        widest opening, tried after `open_synergies`.
    max_retreat : float
        Farthest retreat of the pre-grasp (mm).
    resolution : float
        Of the dense check, as a fraction of the capsule radius (see
        `path_clearance`).

    Returns
    -------
    Reach

    Raises
    ------
    TypeError
        If ``hand`` is not a SynergyHand or ``obj`` not a GraspObject.
    ValueError
        A ``u_grasp`` or ``trajectory`` that does not fit the hand (or a
        ``u_grasp`` whose synergies lie outside its limits), a
        ``margin``, ``max_retreat`` or ``resolution`` that is not a positive
        number, a ``margin`` above ``max_retreat``, a negative ``tolerance``,
        a ``budget`` below 1, or an opening outside [0, 1].

    Examples
    --------
    A precision grasp of the cup, made executable:

    >>> import synergrasp as sg
    >>> from synergrasp.planner import executable_reach
    >>> hand, cup = sg.SynergyHand.default(), sg.objects.get("cup")
    >>> result = sg.plan(cup, "precision")
    >>> reach = executable_reach(hand, cup, result.u)
    >>> reach.collision_free, reach.source, bool(reach.clearance[0] >= 10.0)
    (True, 'approach', True)
    >>> bool(reach.clearance.min() >= -3.0), bool((reach.path[-1] == result.u).all())
    (True, True)
    """
    start = time.process_time()
    checker = HandClearance(hand, obj)
    hand = checker.hand  # (None: the paper's)
    u = as_vector(u_grasp, "u_grasp", hand.n_u)
    hand.check_synergies(u[6:], "u_grasp's synergies")
    margin = positive_scalar(margin, "margin")
    tolerance = positive_scalar(tolerance, "tolerance", zero=True)
    max_retreat = positive_scalar(max_retreat, "max_retreat")
    if margin > max_retreat:
        raise ValueError(f"margin ({margin:g} mm) is more than max_retreat ({max_retreat:g} mm): the open hand's clearance "
                         "grows at most as fast as it moves back from the grasp, so no pre-grasp could clear the object "
                         "by the margin; raise max_retreat or lower the margin")
    positive_scalar(resolution, "resolution")
    budget = integer(budget, "budget", what="pre-grasps")
    try:
        openings = np.atleast_1d(np.asarray(openings, dtype=float))
    except (TypeError, ValueError):
        raise ValueError(f"openings must be fractions in [0, 1], got {openings!r}") from None
    if openings.ndim != 1 or len(openings) == 0 or not np.all((openings >= 0) & (openings <= 1)):
        raise ValueError(f"openings must be fractions in [0, 1] (0: the grasp's synergies, 1: the widest opening), "
                         f"got {openings.tolist()!r}")
    if trajectory is not None:
        trajectory = as_points(trajectory, "trajectory", dim=hand.n_u)

    at_grasp = checker.shapes(u)
    grasp_value, grasp_shape = float(at_grasp.min()), int(np.argmin(at_grasp))
    grasp = dict(grasp_depth=max(0.0, -grasp_value), grasp_shape=checker.labels[grasp_shape] if grasp_value < 0 else "")
    # no shape goes deeper than the tolerance along the path, or than it is at the grasp plus the tolerance
    floors = np.where(at_grasp >= -tolerance, -tolerance, at_grasp - tolerance)

    def reach(check, source, direction=np.zeros(3), retreat=0.0, closing_from=None, failed=False):
        deepest, depth = check.deepest, check.depth
        shape = check.deepest_shape if depth > 0 else ""
        part = _part(source, deepest, check.clearance[-1] <= check.clearance[deepest] + 1e-6, closing_from)
        where = f"{shape} {depth:.1f} mm deep {part} (row {deepest} of {len(check.path)})"
        unplaced = failed and np.isnan(retreat)  # no pre-grasp clear of the object: no reach from free space
        free = bool(check.clearance.min() >= -tolerance) and not unplaced
        paths = f"{tried} candidate path{'s' if tried != 1 else ''}"
        if free:
            reason = (f"collision-free: {_STAYS[source]} within {tolerance:g} mm of the object"
                      + (f"; deepest: {where}" if depth > 0 else ""))
        elif grasp_value < -tolerance:
            reason = (f"not collision-free: the grasp itself penetrates the object, {grasp['grasp_shape']} "
                      f"{grasp['grasp_depth']:.1f} mm deep (more than {tolerance:g} mm); deepest: {where}")
            if failed:
                reason += (f"; none of {paths} keeps every shape within {tolerance:g} mm of its depth at the "
                           "grasp")
        elif check.clearance.min() >= -tolerance:  # within the tolerance, but from no pre-grasp
            reason = f"not collision-free: no path starts clear of the object; the best goes {where}"
        else:
            reason = (f"not collision-free: none of {paths} stays within {tolerance:g} mm of the object; the best "
                      f"goes {where}")
        if unplaced:
            reason += (f"; no pre-grasp clears the object by the margin of {margin:g} mm within max_retreat "
                       f"{max_retreat:g} mm: the path starts {check.clearance[0]:.1f} mm from it")
        return Reach(path=check.path, clearance=check.clearance, closest=[check.labels[i] for i in check.closest],
                     pregrasp=check.path[0].copy(), collision_free=free, depth=depth, deepest=shape, deepest_row=deepest,
                     source=source, direction=np.asarray(direction, float), retreat=float(retreat),
                     candidates=tried, margin=margin, tolerance=tolerance, reason=reason,
                     cpu_time=time.process_time() - start, **grasp)

    tried = 0
    if trajectory is not None:
        tried += 1
        if not np.array_equal(trajectory[-1], u):
            trajectory = np.vstack([trajectory, u])
        check = checker.along(trajectory, resolution=resolution, stop_below=floors)
        if check.complete:
            return reach(check, "trajectory")

    widest = widest_opening(hand)
    shapes = [np.r_[u[:6], open_synergies(hand, checker, u, margin)]]
    shapes += [np.r_[u[:6], u[6:] + s * (widest - u[6:])] for s in openings]
    plans, first = [], []
    for u_open in shapes:
        if any(np.allclose(u_open, v) for v in first):
            continue
        first.append(u_open)
        _, distances, on_shape, on_object = checker.near(u_open, margin)
        away = (np.sign(distances)[:, None] * (on_shape - on_object))
        away = away[np.linalg.norm(away, axis=1) > 1e-9]
        directions = retreat_directions(hand, u, u_open[6:], away / np.linalg.norm(away, axis=1, keepdims=True))
        plans.append([(u_open, d) for d in directions])
    # the first two directions of every opening, then the others in turn
    plans = [p[:2] for p in plans] + [p[2:] for p in plans]
    plans = [c for group in plans for c in group]
    candidates = []
    for u_open, direction in plans[:budget]:
        tried += 1
        pre, retreat = _pregrasp(checker, u_open, direction, margin, max_retreat)
        waypoints = np.array([p for p in (pre, u_open) if not np.array_equal(p, u)] + [u])
        candidates.append((waypoints, direction, retreat, "approach"))
        if retreat is None:  # not clear within max_retreat: no pre-grasp along this direction
            continue
        check = checker.along(waypoints, resolution=resolution, stop_below=floors)
        if check.complete:
            return reach(check, "approach", direction, retreat, _closing_row(check, waypoints))
    # the same pre-grasps, the hand closing while it approaches (one straight line in u to the grasp)
    for waypoints, direction, retreat, _ in list(candidates):
        if retreat is None or retreat == 0.0 or len(waypoints) < 3:  # (the open pose is the pre-grasp or the grasp:
            continue  # the path would be the one above)
        tried += 1
        closing = waypoints[[0, -1]]
        candidates.append((closing, direction, retreat, "closing approach"))
        check = checker.along(closing, resolution=resolution, stop_below=floors)
        if check.complete:
            return reach(check, "closing approach", direction, retreat)
    # none keeps every shape above its floor: the one that comes least below them (those with a pre-grasp first).
    # ``low`` is the best path's least distance above the floors; the first path is checked whole (its floors
    # lowered past any depth), the others stop once they come below the floors raised by ``low``
    best, low = None, -_WHOLE
    for waypoints, direction, retreat, source in sorted(candidates, key=lambda c: c[2] is None):
        if best is not None and retreat is None and best[2] is not None:
            break
        check = checker.along(waypoints, resolution=resolution, stop_below=floors + low)
        if check.complete and (best is None or float(check.slack.min()) > 0.0):
            best, low = (check, waypoints, retreat, direction, source), low + float(check.slack.min())
    check, waypoints, retreat, direction, source = best
    return reach(check, source, direction, np.nan if retreat is None else retreat,
                 _closing_row(check, waypoints) if source == "approach" else None, failed=True)


def _part(source, row, at_grasp, closing_from):
    """Where on a reach of ``source`` its row ``row`` lies, in words.

    ``at_grasp``: the row is as deep as the grasp itself; ``closing_from``: the row of the open hand at the grasp's
    pose, where the close starts (None without a close). That row is the approach's end: the close begins after it.

    >>> _part("approach", 5, False, 5), _part("approach", 6, False, 5), _part("closing approach", 3, False, None)
    ('in the approach', 'in the close', 'in the closing approach')
    """
    if source == "trajectory":
        return "along the iteration"
    if at_grasp:
        return "at the grasp"
    if source == "closing approach":
        return "in the closing approach"
    return "in the approach" if closing_from is None or row <= closing_from else "in the close"


def _closing_row(check, waypoints):
    """Row of the checked path where the close starts (the open hand at the grasp's pose), None without a close."""
    if len(waypoints) < 2 or np.array_equal(waypoints[-2, 6:], waypoints[-1, 6:]):
        return None
    rows = np.flatnonzero(check.given)
    return int(rows[len(waypoints) - 2]) if len(rows) >= len(waypoints) - 1 else None


def _pregrasp(checker, u_open, direction, margin, max_retreat):
    """The open hand moved back along ``direction`` until it clears the object by ``margin``.

    Returns the pre-grasp and the retreat distance (mm), or (the farthest
    pose, None) when ``max_retreat`` is not enough. The clearance grows at
    most as fast as the hand moves, so each step moves by what is missing.
    """
    distance = 0.0
    pose = u_open.copy()
    while distance <= max_retreat:
        pose[:3] = u_open[:3] + distance * direction
        value, _ = checker.at(pose)
        if value >= margin:
            return pose, distance
        distance += max(margin - value, 1.0)
    return pose, None
