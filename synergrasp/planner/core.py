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

If an attempt stalls (the trust radius collapses, or the status stops
improving) the next approach direction is tried, up to ``restarts`` attempts.
"""

from __future__ import annotations

import time
from dataclasses import asdict, dataclass, replace

import numpy as np
from scipy.spatial.transform import Rotation

from .._checks import as_vector
from ..hand import SynergyHand
from ..lp import get_backend
from .result import PlanResult
from .status import grasp_status
from .step import limited_step
from .stop import check_grasp

GRASPS = ("precision", "power")
#: Objects thinner than this (mm) are refused: most likely a mesh in metres.
MIN_WIDTH = 2.0

#: Approach directions tried after the caller's, in order (object centre to hand).
APPROACHES = (
    (0.0, 1.0, 0.0), (-1.0, 1.0, 1.0), (1.0, -1.0, 1.0), (0.0, 0.0, 1.0), (-1.0, 0.0, 0.5), (1.0, 0.0, 0.5),
    (1.0, 1.0, 1.0), (-1.0, -1.0, 1.0), (0.0, -1.0, 0.0), (0.0, 0.0, -1.0), (1.0, 1.0, -1.0), (-1.0, 1.0, -1.0),
)


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
        Iterations without progress that end an attempt.
    iterations_per_attempt : int
        Iteration cap of one attempt.
    restarts : int
        Number of approach directions tried (the caller's first).
    start_distance : float
        Distance (mm) of the start pose from the object's centre.
    max_penetration : float
        Deepest penetration of a phalanx capsule into the object (mm) allowed
        in the final grasp. A grasp that meets the paper's criterion with a
        phalanx deeper than this (the status vector watches only the hand
        points, not the phalanges between them) is rejected and the next
        approach direction is tried.
    power_phases : bool
        Power grasps only: reach with the palm, then wrap. While the palm point
        is not in contact the finger rows are left out of the step (except
        those of penetrating segments, kept in the first priority level) and
        the synergies hold their pre-shape, so the open hand is carried palm
        first to the surface; once the palm touches, its row joins the first
        priority level and keeps it on the surface while the synergies close
        the fingers. A grasp meeting the criterion with a phalanx deeper than
        ``max_penetration`` does not stop the attempt: the iteration goes on
        and the penetrating segments' rows push the phalanx out.
    power_preshape : tuple of float or None
        Synergy values of the default start poses of a power grasp (one per
        synergy): (0, 1) cups the paper's hand open (the second synergy opens
        the fingers). None keeps the mean pose (z = 0). Ignored when ``u0``
        is given.
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
    stall_window: int = 20
    iterations_per_attempt: int = 120
    restarts: int = 12
    start_distance: float = 150.0
    max_penetration: float = 3.0
    power_phases: bool = True
    power_preshape: tuple | None = (0.0, 1.0)


def start_configuration(hand, obj, approach=(0.0, 1.0, 0.0), distance=150.0):
    """The default start: mean pose, palm facing the object's centre.

    The palm is ``distance`` mm from the centre along ``approach`` and faces it;
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
    aim = np.array([tips[:, 0].mean(), tips[:, 1].mean(), 0.0])
    u[:3] = obj.center + a * distance - R @ aim
    u[3:6] = phi
    return u


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


def _attempt(hand, obj, kind, u0, opts, backend, budget, progress):
    """One attempt of the iteration from u0.

    Returns (reason, trajectory, statuses, checks, final status, final penetration depth, lp_solves).
    """
    size = obj.torque_scale
    n_u = len(u0)
    scale_u = np.r_[np.full(3, size), np.ones(n_u - 3)]  # normalised u = u / scale_u
    smoothing = opts.smoothing * size

    def evaluate(u):
        st = grasp_status(hand, obj, u, kind, mu=opts.mu, edges=opts.edges, backend=backend, smoothing=smoothing)
        # a pinch must not end with the palm on the object
        palm = lambda: float(obj.contact_distance(hand.points(u, "power")[-1:], backend=backend).value[0])  # noqa: E731
        chk = check_grasp(obj, st, kind, eps_c=opts.eps_c, mu=opts.mu, edges=opts.edges, backend=backend,
                          palm_distance=palm if kind == "precision" else None)
        if chk.done and kind == "power" and opts.power_phases:
            # not done while a phalanx is in the object: its pad line, penetrating, pushes it out
            geo = hand.segments(u)
            if obj.penetration(geo.capsules, geo.radius).depth > opts.max_penetration:
                chk = replace(chk, done=False)
        return st, chk

    u = np.array(u0, dtype=float)
    st, chk = evaluate(u)
    n = len(st.g) - 1
    row_scale = np.r_[np.full(n, 1.0 / size), 1.0]
    radius, stalled, best = opts.radius, 0, np.inf
    traj, statuses, checks = [u.copy()], [st.g.copy()], [chk]
    solves = st.lp_solves + chk.lp_solves
    reason = f"iteration cap ({budget}) reached"
    for _ in range(budget):
        if chk.done:
            reason = "stop criterion met"
            break
        target = np.full(n + 1, opts.contact_target)
        target[-1] = max(-1.0, st.g[-1] - opts.sq_step)
        first = np.r_[st.g[:-1] < 0.0, True]  # first priority: sQ and penetrating hand points
        active, reaching = np.ones(n + 1, bool), False
        if kind == "power" and opts.power_phases:
            if st.g[-2] < opts.eps_c:  # wrap: the palm has touched, it stays on the surface
                first[-2] = True
            else:  # reach: the palm leads with the hand held open, the fingers only kept out of the object
                active[:-2] = st.g[:-2] < 0.0
                reaching = True
        e = active * row_scale * (target - st.g)
        J = (active * row_scale)[:, None] * st.J * scale_u
        if reaching:
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
        merit = np.sum((row_scale[:-1] * (st.g[:-1] - opts.contact_target)) ** 2) + max(st.g[-1], -0.1)
        if merit < best - 1e-4:
            best, stalled = merit, 0
        else:
            stalled += 1
        if stalled >= opts.stall_window:
            reason = f"stalled (no progress in {opts.stall_window} iterations)"
            break
    geo = hand.segments(u)
    depth = obj.penetration(geo.capsules, geo.radius).depth
    if reason == "stop criterion met" and depth > opts.max_penetration:
        reason = f"grasp rejected: a phalanx penetrates the object by {depth:.1f} mm"
    return reason, traj, statuses, checks, st, depth, solves


def plan(obj, grasp="precision", *, backend="highs", u0=None, max_iter=600, approach=None, hand=None,
         progress=None, **options) -> PlanResult:
    """Plan a reach-to-grasp motion (paper Sec. 3.2) for the synergy hand.

    Parameters
    ----------
    obj : GraspObject
        The object (``synergrasp.objects``).
    grasp : {"precision", "power"}
        Fingertip pinch, or a grasp with the phalanges and the palm.
    backend : str
        LP backend.
    u0 : (8,) float, optional
        Start configuration; default `start_configuration` from ``approach``.
        With ``u0`` given only one attempt is made.
    max_iter : int
        Cap on the total number of iterations over all attempts.
    approach : (3,) float, optional
        Direction from the object's centre to the start pose of the first
        attempt; later attempts (after a stall) use `APPROACHES`.
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
    ValueError
        Unknown grasp type, bad ``u0`` or ``approach``, unknown option or backend.

    Examples
    --------
    >>> from synergrasp import objects
    >>> result = plan(objects.ellipsoid(), "precision")
    >>> result.success, len(result.contact_labels) >= 3, result.final_q < 0
    (True, True, True)
    """
    if grasp not in GRASPS:
        raise ValueError(f"grasp must be one of {GRASPS}, got {grasp!r}")
    unknown = set(options) - set(PlannerOptions.__dataclass_fields__)
    if unknown:
        raise ValueError(f"unknown planner options {sorted(unknown)}; known: {sorted(PlannerOptions.__dataclass_fields__)}")
    opts = replace(PlannerOptions(), **options)
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
    if grasp == "power" and opts.power_preshape is not None:
        preshape = np.asarray(opts.power_preshape, dtype=float)
        if preshape.shape != (hand.n_syn,) or not np.all(np.isfinite(preshape)):
            raise ValueError(
                f"power_preshape must hold one finite value per synergy ({hand.n_syn} for {hand.name}), "
                f"got {opts.power_preshape!r}; pass power_preshape=None to start from the mean pose"
            )
        preshape = np.clip(preshape, hand.synergy_limits[:, 0], hand.synergy_limits[:, 1])
    if u0 is not None:
        starts = [as_vector(u0, "u0", hand.n_u)]
    else:
        first = [tuple(as_vector(approach, "approach", 3))] if approach is not None else []
        dirs = first + [d for d in APPROACHES if not first or not np.allclose(np.cross(d, first[0]), 0) or np.dot(d, first[0]) < 0]
        starts = [start_configuration(hand, obj, d, opts.start_distance) for d in dirs[: opts.restarts]]
        if grasp == "power" and opts.power_preshape is not None:
            for u_start in starts:
                u_start[6:] = preshape
    t0 = time.perf_counter()
    total, solves, attempts = 0, 0, []
    for u_start in starts:
        budget = min(opts.iterations_per_attempt, max_iter - total)
        if budget <= 0:
            break
        reason, traj, statuses, checks, final, depth, n_solves = _attempt(
            hand, obj, grasp, u_start, opts, backend, budget, progress
        )
        total += len(traj) - 1
        solves += n_solves
        attempts.append({"start": u_start.tolist(), "iterations": len(traj) - 1, "reason": reason})
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
