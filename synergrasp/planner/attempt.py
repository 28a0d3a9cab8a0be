"""One attempt of the planner: the resolved-rate iteration from one start (paper Fig. 6, Eqs. 15-16).

Each iteration:

1. the status g (cP rows and g_sQ) and its Jacobian (`grasp_status`);
2. stop when the paper's criterion holds with no phalanx capsule and not the
   palm box deeper than ``max_penetration`` (`check_grasp`,
   `hand_penetration`); a power attempt watches its capsules and palm box
   from its start (`capsule_rows`: a shape deeper than its skin points read
   gets its depth as its row, which pushes it out), a precision attempt once
   it meets the criterion with a deeper shape;
3. the requested change of the status, in rows of comparable scale (cP
   divided by the object's size): contact rows towards their target
   (precision: into the contact band; power: ``contact_target``), clearance
   rows that are too close back to ``clearance`` (a precision attempt on an
   object too small for all five fingertips, `pinch_fingertips`, keeps the
   others clear like the phalanges), and the sQ row a step
   ``sq_step`` below its value (a moving target); while a precision
   attempt's g_sQ predicts a closed grasp and the fingertips touching (at
   least three) are not closed, that row is their own g_Q instead
   (`contact_quality`, as in the refinement below);
4. the step of Eq. 16 with two priorities, sQ and every penetrating or too
   close row first (a power attempt's sQ only while no row penetrates: the
   hand gets out of the object before it closes further), the contact rows
   in their null space (`limited_step`),
   within the synergy limits and a trust radius that grows when the linear
   model predicts the change well and shrinks when not; a precision step is
   shortened so that no fingertip inside the contact band moves by more
   than ``band_step`` (to first order).

A power attempt first reaches with the palm (the finger rows only keep the
fingers out of the object, the synergies shaped by the first level), then
wraps once the palm touches.

A grasp is accepted when the criterion holds, no phalanx capsule and not the
palm box is deeper than ``max_penetration`` (in the convex pieces, and the
capsules also in the object's true surface, its mesh or points,
`mesh_depth`), and its contacts, moved to the object's true surface
(`surface_check`), are within ``eps_c`` of it and force-closed there with a
Q distance below ``q_accept``. Once the criterion holds, the attempt refines
the grasp for up to ``refine_iterations`` more iterations, until its Q on
the true surface is below ``q_margin``: the sQ row gives way to the g_Q of
the contacts themselves (`contact_quality`), asked to fall, and the best
accepted configuration is returned. An attempt ends with an `Outcome`.
"""

from __future__ import annotations

import enum
from dataclasses import dataclass, replace

import numpy as np

from .._jit import clock
from .starts import pinch_fingertips
from .status import (Status, capsule_rows, contact_quality, grasp_status, hand_penetration, read_only, status_rows,
                     steering_scale)
from .step import limited_step
from .stop import CRITERION, GraspCheck, SurfaceCheck, check_grasp, mesh_depth, surface_check


class Outcome(enum.Enum):
    """How an attempt ended (the value is the words for a user).

    An attempt whose refinement ends without an accepted grasp ends in `SURFACE` when some refining
    iteration was judged on the true surface (its Q or the contacts' gap failed there), else in
    `PENETRATION` (the criterion held only with a phalanx or the palm box too deep in the object).
    """

    GRASP = "stop criterion met"
    NO_TOUCH = "stalled: no fingertip reached the surface"
    STALLED = "stalled: no progress"
    CRAWLED = "stalled: the merit falls too slowly"
    CAP = "iteration cap of the attempt reached"
    BUDGET = "the plan's iterations or time ran out"
    PENETRATION = "grasp rejected: the hand penetrates the object"
    SURFACE = "grasp rejected: on the object's true surface, its Q not below q_accept or its contacts off it"


@dataclass(frozen=True)
class AttemptResult:
    """The outcome of one attempt.

    Attributes
    ----------
    outcome : Outcome
    reason : str
        The outcome in words, with its numbers.
    trajectory : (k+1, n_u) float
        Configuration at every iteration, start included.
    status : (k+1, n+1) float
        Status vector at every iteration.
    q_history : (k+1,) float
        g_Q at every iteration (NaN without contacts).
    final : Status
    check : GraspCheck
        The paper's criterion at the last configuration.
    penetration : float
        Deepest penetration of a phalanx capsule or the palm box at the last configuration (mm).
    lp_solves : int
    surface : SurfaceCheck or None
        The grasp judged on the object's true surface (`surface_check`), None without a grasp.
    iterations_run : int or None
        Iterations the attempt ran: `iterations`, plus the refining
        iterations after the grasp it kept (they count in the plan's
        ``max_iter``, and ``progress`` was called for them). None: `iterations`.
    """

    outcome: Outcome
    reason: str
    trajectory: np.ndarray
    status: np.ndarray
    q_history: np.ndarray
    final: Status
    check: GraspCheck
    penetration: float
    lp_solves: int
    surface: SurfaceCheck | None = None
    iterations_run: int | None = None

    def __post_init__(self):
        if self.iterations_run is None:
            object.__setattr__(self, "iterations_run", self.iterations)

    @property
    def iterations(self) -> int:
        """Steps of the returned trajectory (to the grasp kept, if any)."""
        return len(self.trajectory) - 1

    @property
    def success(self) -> bool:
        """The attempt ended in a grasp."""
        return self.outcome is Outcome.GRASP


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


def judge_grasp(hand, obj, u, status, check, options, *, backend="native", penetration=None):
    """Whether a grasp is accepted: the criterion, no part of the hand too deep, force-closed on the true surface.

    The paper's criterion (``check.done``), then no phalanx capsule and not
    the palm box deeper than ``options.max_penetration`` (python-fcl,
    `hand_penetration`), nor a capsule in the object's true surface (`mesh_depth`,
    for the capsules whose depth in the pieces is within
    `GraspObject.mesh_excess` of the limit, every capsule in the pieces for
    a point cloud), then the contacts moved to
    the object's true surface (`surface_check`) within ``options.eps_c`` of
    it with a Q distance below ``options.q_accept``; each test only when the
    previous holds. Both planners accept grasps with it.

    Parameters
    ----------
    hand : SynergyHand
    obj : GraspObject
    u : (6 + n_syn,) float
        The configuration of ``status``.
    status : Status
    check : GraspCheck
        `check_grasp` of ``status``.
    options : PlannerOptions or AnnealingOptions
        Its ``eps_c``, ``mu``, ``edges``, ``q_accept`` and ``max_penetration``.
    backend : str
    penetration : Penetration, optional
        ``hand_penetration(hand, obj, u)``, if already computed.

    Returns
    -------
    accepted : bool
    penetration : Penetration or None
        None when the criterion does not hold (not computed); its ``depth``
        raised to the depth in the true surface when a capsule is deeper than
        the limit there.
    surface : SurfaceCheck or None
        None unless the first two tests hold.
    """
    if not check.done:
        return False, penetration, None
    pen = penetration if penetration is not None else hand_penetration(hand, obj, u)
    if pen.depth > options.max_penetration:
        return False, pen, None
    if obj.mesh is not None or obj.points is not None:  # the capsules that may be deeper in the true surface than
        # in the pieces, measured there (every capsule in the pieces for a cloud: its surface between points is unknown)
        geo = hand.segments(u)
        excess = obj.mesh_excess if obj.mesh is not None else options.max_penetration
        near = np.flatnonzero(pen.depths[:len(geo.capsules)] > options.max_penetration - excess)
        depth = float(mesh_depth(obj, geo.capsules[near], geo.radius).max()) if len(near) else 0.0
        if depth > options.max_penetration:
            return False, replace(pen, depth=depth), None
    surface = surface_check(obj, status.nearest[check.contact], status.normals[check.contact], mu=options.mu,
                            edges=options.edges, backend=backend)
    return surface.gap <= options.eps_c and surface.q < options.q_accept, pen, surface


def run_attempt(hand, obj, grasp, u0, options, *, backend="native", budget=None, deadline=None, progress=None):
    """Iterate from ``u0`` until a grasp, a stall, the attempt's cap, or the plan's budget.

    Parameters
    ----------
    hand : SynergyHand
    obj : GraspObject
    grasp : {"precision", "power"}
    u0 : (n_u,) float
        Start configuration.
    options : PlannerOptions
    backend : str
        LP backend.
    budget : int, optional
        Most iterations (default ``options.iterations_per_attempt``); a
        smaller one is what is left of the plan's ``max_iter``, and reaching it
        ends the attempt with `Outcome.BUDGET`, not `Outcome.CAP`.
    deadline : float, optional
        `clock` value after which the attempt stops (`Outcome.BUDGET`): seconds
        of ``time.perf_counter()`` less those numba spent compiling.
    progress : callable, optional
        Called as ``progress(check, status)`` after every iteration.

    Returns
    -------
    AttemptResult

    Examples
    --------
    >>> from synergrasp import SynergyHand, objects
    >>> from synergrasp.planner import PlannerOptions, start_configuration
    >>> hand, obj = SynergyHand.default(), objects.ellipsoid()
    >>> r = run_attempt(hand, obj, "precision", start_configuration(hand, obj), PlannerOptions(), budget=3)
    >>> r.outcome, r.iterations
    (<Outcome.BUDGET: "the plan's iterations or time ran out">, 3)
    """
    opts = options
    budget = opts.iterations_per_attempt if budget is None else int(budget)
    size = obj.radius
    n_u = len(u0)
    scale_u = np.r_[np.full(3, size), np.ones(n_u - 3)]  # normalised u = u / scale_u
    smoothing = opts.smoothing * size
    power = grasp == "power"
    steer = steering_scale(obj, opts.mu) if power else obj.torque_scale  # of the rows that steer (g_sQ, own g_Q)
    window = opts.stall_window[1 if power else 0]
    watching = power  # capsules and palm box watched: power from the start, precision once the criterion held with one too deep

    def evaluate(u, far):
        pen = hand_penetration(hand, obj, u) if watching else None
        if pen is not None and far is not None:  # a row that a penetrating shape replaces keeps its skin point's
            far = far.copy()  # nearest point: exact
            far[shape_rows[pen.distances < 0.0]] = np.inf
        st = grasp_status(hand, obj, u, grasp, mu=opts.mu, edges=opts.edges, backend=backend, smoothing=smoothing,
                          far=far, torque_scale=steer)
        if watching:
            st = capsule_rows(hand, obj, u, st, pen)
        chk = check_grasp(obj, st, grasp, eps_c=opts.eps_c, mu=opts.mu, edges=opts.edges, backend=backend,
                          steered=steered)
        return st, chk, pen

    def quality_row(st, chk):
        """The last row: g_sQ, or the contacts' own g_Q while refining or closing them (its value and gradient)."""
        if (refining is None and not closing) or chk.n_contacts < 2:
            return st.g[-1], st.J[-1]
        return contact_quality(obj, st, chk.contact, mu=opts.mu, edges=opts.edges, backend=backend, smoothing=smoothing,
                               torque_scale=steer)

    _, contact_rows, segment_rows = status_rows(hand, grasp)
    contact_rows, shape_rows = contact_rows.copy(), np.r_[segment_rows, len(contact_rows) - 1]  # capsules, palm box
    steered = None
    if not power:  # fingertips a small object leaves out are only kept clear
        reach = pinch_fingertips(hand, obj)
        contact_rows[: len(reach)] &= reach
        steered = int(reach.sum())
    # a precision clearance row is read only when nearer than the clearance (the step) or eps_c (the palm in the
    # criterion): farther, its bound will do, unless the last step's residual reads it
    beyond = None if power else np.where(contact_rows, np.inf, max(opts.clearance, opts.eps_c))
    u = np.array(u0, dtype=float)
    st, chk, pen = evaluate(u, beyond)
    n = len(st.g) - 1
    palm = n - 1
    row_scale = np.r_[np.full(n, 1.0 / size), 1.0]
    radius, stalled, best = opts.radius, 0, np.inf
    traj, statuses, qs = [u.copy()], [st.g.copy()], [chk.q]
    solves = st.lp_solves + chk.lp_solves
    outcome, bests, touched = Outcome.CAP if budget >= opts.iterations_per_attempt else Outcome.BUDGET, [], False
    closing, closed_once = False, False  # precision: g_sQ predicts a closed grasp and the fingertips touching are not closed
    kept, refining = None, None  # the best grasp so far (its index, status, check, penetration); refining iterations
    judged, deep = None, 0.0  # while refining: the last grasp judged on the true surface; the hand's depth otherwise
    for _ in range(budget):
        ok, pen, surface = judge_grasp(hand, obj, u, st, chk, opts, backend=backend, penetration=pen)
        if ok and (kept is None or surface.q < kept[4].q):
            kept = (len(traj) - 1, st, chk, pen, surface)
        if chk.done and pen.depth > opts.max_penetration and not watching:  # watch the capsules from now on
            watching = True
            st = capsule_rows(hand, obj, u, st, pen)
            chk = replace(chk, done=False)
            best, stalled, bests = np.inf, 0, []
        elif chk.done and refining is None:  # the criterion holds: refine the margin (and the grasp on the true surface)
            refining = 0
        if refining is not None:
            if surface is not None:
                judged = surface
            elif chk.done:  # the criterion held with a phalanx or the palm box too deep
                deep = max(deep, pen.depth)
            if (ok and surface.q <= opts.q_margin) or refining >= opts.refine_iterations:
                outcome = (Outcome.GRASP if kept is not None else Outcome.SURFACE if judged is not None
                           else Outcome.PENETRATION)
                break
            refining += 1
        if deadline is not None and clock() > deadline:
            outcome = Outcome.BUDGET
            break
        if not power and refining is None:  # the last row: the contacts' g_Q while sQ is closed and they are not
            closing = bool(st.g[-1] < 0.0 and chk.n_contacts >= CRITERION["precision"][0] and chk.q > 0.0)
            if closing and not closed_once:  # the merit (now of that g_Q) starts afresh, once
                best, stalled, bests, closed_once = np.inf, 0, [], True
        g = st.g[:-1]
        target = np.where(contact_rows, opts.contact_target, opts.clearance)
        active = np.ones(n, bool)
        if grasp == "precision":
            low, high = opts.contact_band
            target[contact_rows] = np.clip(g[contact_rows], low, high)
            active[contact_rows] = target[contact_rows] != g[contact_rows]  # a fingertip inside the band is free
            active[~contact_rows] = g[~contact_rows] < opts.clearance
            sq_step = sq_request(opts.sq_step, radius, st.J[-1] * scale_u)
        else:
            sq_step = opts.sq_step
        quality, quality_jac = quality_row(st, chk)
        if refining is not None:
            sq_step = sq_request(opts.sq_step, radius, quality_jac * scale_u)
        sq_target = max(-1.0, quality - sq_step)
        if power and refining is None and opts.power_sq_hold is not None and quality < opts.power_sq_hold:
            sq_target = quality  # predicted good enough: keep it, the contact rows get the step
        inside = g < np.where(contact_rows, 0.0, opts.clearance)  # rows in or too near the object
        first = np.append(inside, not (power and inside.any()))  # with sQ; a power hand in the object gets out first
        reaching = power and g[palm] >= opts.eps_c
        if power and not reaching:  # wrap: the palm has touched, it stays on the surface
            first[palm] = True
        if reaching:  # reach: the palm leads with the hand held open, the fingers only kept out of the object
            active[:palm] = g[:palm] < 0.0
        active = np.append(active, True)
        goal = np.append(target, sq_target)
        g_rows, J_rows = np.append(st.g[:-1], quality), np.vstack([st.J[:-1], quality_jac])
        e = active * row_scale * (goal - g_rows)
        J = (active * row_scale)[:, None] * J_rows * scale_u
        if reaching and not opts.power_free_reach:
            J[:, 6:] = 0.0  # the synergies keep their pre-shape
        du = limited_step(J[active], e[active], u[6:], hand.synergy_limits, first[active])
        step = np.abs(du).max()
        if step > radius:
            du *= radius / step
        held = contact_rows & ~active[:n]  # precision: the fingertips inside the band move by at most band_step
        if not power and held.any():  # (to first order)
            move = np.abs(st.J[:n][held] @ (du * scale_u)).max()
            if move > opts.band_step:
                du *= opts.band_step / move
        u_new = u + du * scale_u
        u_new[6:] = np.clip(u_new[6:], hand.synergy_limits[:, 0], hand.synergy_limits[:, 1])
        st_new, chk_new, pen_new = evaluate(u_new, None if power else np.where(active[:n], np.inf, beyond))
        solves += st_new.lp_solves + chk_new.lp_solves
        # adaptive step length: compare the achieved with the predicted change of the residual
        before = np.sum(e**2)
        quality_new = quality_row(st_new, chk_new)[0]
        after = np.sum((active * row_scale * (goal - np.append(st_new.g[:-1], quality_new))) ** 2)
        predicted = np.sum((e - J @ ((u_new - u) / scale_u)) ** 2)
        ratio = (before - after) / max(before - predicted, 1e-15)
        if ratio > 0.75:
            radius = min(1.5 * radius, opts.radius_max)
        elif ratio < 0.25:
            radius = max(0.5 * radius, opts.radius_min)
        u, st, chk, pen = u_new, st_new, chk_new, pen_new
        traj.append(u.copy())
        statuses.append(st.g.copy())
        qs.append(chk.q)
        if progress is not None:
            progress(read_only(chk), read_only(st))
        g = st.g[:-1]
        if grasp == "precision":
            miss = g[contact_rows] - np.clip(g[contact_rows], *opts.contact_band)
        else:
            miss = g[contact_rows] - opts.contact_target
        merit = (np.sum((miss / size) ** 2) + np.sum((np.minimum(g[~contact_rows] - opts.clearance, 0.0) / size) ** 2)
                 + max(quality_new if closing else st.g[-1], -0.1))
        if merit < best - 1e-4:
            best, stalled = merit, 0
        else:
            stalled += 1
        bests.append(best)
        if refining is not None:
            continue  # a refinement ends by its own count
        touched = touched or g[contact_rows].min() < opts.eps_c
        if grasp == "precision" and opts.touch_window and not touched and len(traj) > opts.touch_window:
            outcome = Outcome.NO_TOUCH
            break
        if stalled >= window:
            outcome = Outcome.STALLED
            break
        if opts.crawl_window and len(bests) > opts.crawl_window:
            earlier = bests[-1 - opts.crawl_window]
            if earlier - best < opts.crawl_fraction * (abs(earlier) + 0.1):
                outcome = Outcome.CRAWLED
                break
    surface, ran = None, len(traj) - 1
    if kept is not None:  # the best grasp met on the way
        k, st, chk, pen, surface = kept
        outcome, traj, statuses, qs = Outcome.GRASP, traj[: k + 1], statuses[: k + 1], qs[: k + 1]
    elif chk.done and outcome in (Outcome.CAP, Outcome.STALLED, Outcome.CRAWLED):
        outcome = Outcome.PENETRATION
    depth = (pen if pen is not None else hand_penetration(hand, obj, traj[-1])).depth
    reason = _reason(outcome, opts, window, len(traj) - 1, chk, max(depth, deep), judged)
    return AttemptResult(outcome, reason, np.array(traj), np.array(statuses), np.array(qs), st, chk, float(depth), int(solves),
                         surface, ran)


def _reason(outcome, opts, window, iterations, check, depth, judged):
    """An outcome in words, with its numbers (``window``: the attempt's stall window; ``judged``: the last `SurfaceCheck`, or None)."""
    last = "" if judged is None else (f"; the last: Q = {judged.q:.4f} on the true surface (q_accept "
                                      f"{opts.q_accept:g}), contacts up to {judged.gap:.1f} mm off it")
    details = {
        Outcome.GRASP: f"{check.n_contacts} contacts, g_Q = {check.q:.4f}",
        Outcome.NO_TOUCH: f"in {opts.touch_window} iterations",
        Outcome.STALLED: f"in {window} iterations",
        Outcome.CRAWLED: f"less than {opts.crawl_fraction:.0%} in {opts.crawl_window} iterations",
        Outcome.CAP: f"{iterations} iterations",
        Outcome.BUDGET: f"after {iterations} iterations",
        Outcome.PENETRATION: f"{depth:.1f} mm deep",
        Outcome.SURFACE: f"after {opts.refine_iterations} refining iterations{last}",
    }
    return f"{outcome.value} ({details[outcome]})"
