"""The baseline planner: GraspIt!-style eigengrasp simulated annealing over u, then the auto-grasp.

``plan(obj, grasp, method="annealing")`` searches the same configuration u
(palm position, XYZ Euler angles, the two synergies) as the gradient planner
by simulated annealing, as GraspIt!'s eigengrasp planner does (M. Ciocarlie
and P. Allen, "Hand posture subspaces for dexterous robotic grasping", IJRR
28(7), 2009; the schedule of GraspIt!'s ``SimAnn``, ``ANNEAL_DEFAULT``):

* the energy of a configuration is GraspIt!'s contact energy: the mean over
  the hand's virtual contacts (the hand points of the grasp type) of their
  distance to the surface (|cP|, mm) plus ``alignment * (1 - cos)`` of the
  angle between the contact's normal (out of the hand's skin,
  `contact_normals`) and the object's inward normal at its nearest point;
  a configuration whose phalanx capsules or palm reach into the object is
  illegal;
* neighbours are drawn variable by variable in the normalised coordinates
  (position in object sizes, angles in rad, synergies), with Ingber's
  distribution at the current temperature, ``y = T ((1 + 1/T)^v - 1)``,
  ``v = |2U - 1|``, signed, times a largest jump of one unit; the angles
  wrap, the other variables are redrawn until within bounds;
* the temperature of step k is ``t0 exp(-cooling k^(1/dims))`` from
  ``k = k0``; a neighbour of higher energy is accepted with probability
  ``exp(energy_scale (E_old - E_new) / T)``;
* every state the search moves to with an energy below
  ``autograsp_energy``, and not within ``autograsp_spacing`` of a state
  auto-grasped before, is auto-grasped (`autograsp`: the synergies close
  until the hand is blocked by the object) and judged by the gradient
  planner's acceptance (`judge_grasp`); the search stops at the first
  accepted grasp.

The trajectory is the sequence of states the search moved to, then the
auto-grasp's closing.
"""

from __future__ import annotations

import math
import sys
import time
from dataclasses import replace

import numpy as np

from .._jit import clock
from .attempt import AttemptResult, Outcome, judge_grasp
from .status import grasp_status, hand_penetration, read_only
from .stop import check_grasp

#: Default energy (mm) below which a state is auto-grasped, by grasp type (`AnnealingOptions.autograsp_energy`).
AUTOGRASP_ENERGY = {"precision": 25.0, "power": 40.0}
#: Bisections of the last closing step of the auto-grasp.
BISECTIONS = 3
#: Redraws of a variable's neighbour before it is clipped into its bounds.
REDRAWS = 100


def contact_normals(hand, u, kind):
    """Unit normals of the hand's virtual contacts, out of the skin (towards where the object should be).

    A finger point's normal is its palmar offset from its phalanx's axis
    (the hand points sit ``hand.contact_offset`` mm from the axis); the
    palm point's is the palm's normal (its z axis).

    Parameters
    ----------
    hand : SynergyHand
    u : (6 + n_syn,) float
    kind : {"precision", "power"}

    Returns
    -------
    (n, 3) float
        One row per hand point of ``kind`` (`SynergyHand.points`).

    Examples
    --------
    In the mean pose the thumb tip's pad faces the fingers (+y in the palm frame):

    >>> from synergrasp import SynergyHand
    >>> n = contact_normals(SynergyHand.default(), np.zeros(8), "precision")
    >>> n.shape, bool(n[0, 1] > 0.5)
    ((5, 3), True)
    """
    points = hand.points(u, kind)
    geo = hand.segments(u)
    palm = geo.palm_axes[:, 2]
    if kind == "precision":
        last = {chain: i for i, chain in enumerate(hand.point_chains("power")[:-1])}  # each finger's distal segment
        axis = geo.capsules[[last[chain] for chain in hand.point_chains(kind)], 1]
        offsets = points - axis
    else:
        offsets = np.vstack([points[:-1] - geo.capsules.mean(axis=1), palm])
    norms = np.linalg.norm(offsets, axis=1, keepdims=True)
    return np.where(norms > 1e-9, offsets / np.maximum(norms, 1e-12), palm)


def contact_energy(hand, obj, u, grasp, alignment=50.0, *, backend="native"):
    """GraspIt!'s contact energy of ``u`` (mm): distance to the surface plus normal misalignment, per hand point.

    ``mean_i |cP_i| + alignment * (1 - c_i . n_i)``: cP of hand point i
    (`GraspObject.contact_distance`), ``c_i`` its normal (`contact_normals`),
    ``n_i`` the object's inward normal at its nearest point. A configuration
    with a hand point, a phalanx capsule or the palm's centre inside the
    object is illegal: inf.

    Parameters
    ----------
    hand : SynergyHand
    obj : GraspObject
    u : (6 + n_syn,) float
    grasp : {"precision", "power"}
        Whose hand points are the virtual contacts.
    alignment : float
        Weight (mm) of the misalignment.
    backend : str or Backend

    Returns
    -------
    energy : float
    lp_solves : int

    Examples
    --------
    >>> from synergrasp import SynergyHand, objects
    >>> from synergrasp.planner import start_configuration
    >>> hand, obj = SynergyHand.default(), objects.ellipsoid()
    >>> far, _ = contact_energy(hand, obj, start_configuration(hand, obj, distance=200.0), "precision")
    >>> near, _ = contact_energy(hand, obj, start_configuration(hand, obj, distance=140.0), "precision")
    >>> bool(near < far)
    True
    """
    points = hand.points(u, grasp)
    cp = obj.contact_distance(points, backend=backend)
    geo = hand.segments(u)
    if cp.value.min() < 0.0 or obj.penetration(geo.capsules, geo.radius).collision \
            or obj.contains(geo.palm_center[None]).any():
        return math.inf, cp.lp_solves
    align = 1.0 - np.einsum("ij,ij->i", contact_normals(hand, u, grasp), cp.normal)
    return float(np.mean(np.abs(cp.value) + alignment * align)), cp.lp_solves


def temperature(options, k):
    """GraspIt!'s (Ingber's) cooling schedule: ``t0 exp(-cooling k^(1/dims))``.

    Examples
    --------
    >>> from synergrasp.planner import AnnealingOptions
    >>> f"{temperature(AnnealingOptions(), 30000):.3g}"
    '9.36e-06'
    """
    # (at least the smallest normal float: a schedule that underflows to 0 would divide by it)
    return max(options.t0 * math.exp(-options.cooling * k ** (1.0 / options.dims)), sys.float_info.min)


def neighbour_steps(rng, T, n):
    """``n`` draws of Ingber's neighbour distribution at temperature ``T``, in [-1, 1].

    ``y = sign(2U - 1) T ((1 + 1/T)^|2U - 1| - 1)``, U uniform on [0, 1]:
    mostly steps of order ``sqrt(T)``, with a heavy tail up to 1.

    Parameters
    ----------
    rng : numpy.random.Generator
    T : float
    n : int

    Returns
    -------
    (n,) float
    """
    w = 2.0 * rng.random(n) - 1.0
    return np.sign(w) * T * np.expm1(np.abs(w) * math.log1p(1.0 / T))


class _Search:
    """The annealing's state space and energy for one plan (normalised coordinates x = u / scale)."""

    def __init__(self, hand, obj, grasp, options, backend):
        self.hand, self.obj, self.grasp, self.opts, self.backend = hand, obj, grasp, options, backend
        n_u = hand.n_u
        self.scale = np.r_[np.full(3, obj.radius), np.ones(n_u - 3)]
        lo, hi = obj.bounds
        margin = options.position_margin
        self.low = np.r_[(lo - margin) / obj.radius, np.full(3, -math.pi), hand.synergy_limits[:, 0]]
        self.high = np.r_[(hi + margin) / obj.radius, np.full(3, math.pi), hand.synergy_limits[:, 1]]
        self.circular = np.r_[np.zeros(3, bool), np.ones(3, bool), np.zeros(n_u - 6, bool)]
        self.evaluations, self.lp_solves = 0, 0

    def energy(self, u):
        """`contact_energy` of ``u``, counted."""
        self.evaluations += 1
        energy, solves = contact_energy(self.hand, self.obj, u, self.grasp, self.opts.alignment, backend=self.backend)
        self.lp_solves += solves
        return energy

    def neighbour(self, rng, u, T):
        """A neighbour of ``u``: each variable moved by Ingber's distribution (largest jump: one normalised unit)."""
        x = u / self.scale
        new = x + neighbour_steps(rng, T, len(x))
        for _ in range(REDRAWS):
            wrap = self.circular & ((new < self.low) | (new > self.high))
            new[wrap] = self.low[wrap] + np.mod(new[wrap] - self.low[wrap], self.high[wrap] - self.low[wrap])
            out = (new < self.low) | (new > self.high)
            if not out.any():
                break
            new[out] = x[out] + neighbour_steps(rng, T, int(out.sum()))
        return np.clip(new, self.low, self.high) * self.scale

    def status(self, u):
        """The gradient planner's status and criterion at ``u``."""
        opts = self.opts
        st = grasp_status(self.hand, self.obj, u, self.grasp, mu=opts.mu, edges=opts.edges, backend=self.backend)
        chk = check_grasp(self.obj, st, self.grasp, eps_c=opts.eps_c, mu=opts.mu, edges=opts.edges, backend=self.backend)
        self.lp_solves += st.lp_solves + chk.lp_solves
        return st, chk


def autograsp(hand, obj, u, grasp, options, backend="native"):
    """Close the hand from ``u`` until the object blocks it, as far as each synergy can.

    The last synergy (z2 of the paper's hand) closes every finger and the
    thumb together (z2 < 0 closes the hand): it falls by ``options.close_step`` while no phalanx capsule is
    deeper than ``options.max_penetration`` in the object, the last step
    refined by bisection. Two synergies cannot stop each finger at its own
    contact as GraspIt!'s auto-grasp does; the other synergies then move,
    each way in turn by the same steps and within the same depth, to the
    value that brings the most hand points of the grasp type within
    ``options.eps_c`` of the surface (the smallest sum of their cP on a tie).

    Parameters
    ----------
    hand : SynergyHand
    obj : GraspObject
    u : (6 + n_syn,) float
        The state to close from.
    grasp : {"precision", "power"}
        Whose hand points count as contacts.
    options : AnnealingOptions
    backend : str or Backend

    Returns
    -------
    (m, 6 + n_syn) float
        The closing configurations, ``u`` excluded; the last one is the grasp
        (empty if the hand cannot close at all).

    Examples
    --------
    The open hand around a ball, its centre between the thumb and middle
    fingertips, closes until a phalanx is 3 mm in:

    >>> from synergrasp import SynergyHand, objects
    >>> from synergrasp.planner import AnnealingOptions
    >>> hand, ball = SynergyHand.default(), objects.ellipsoid(25.0, 25.0, 25.0)
    >>> u = np.r_[np.zeros(6), 0.0, 1.0]
    >>> tips = hand.points(u)
    >>> u[:3] = ball.center - 0.5 * (tips[0] + tips[2])
    >>> path = autograsp(hand, ball, u, "precision", AnnealingOptions())
    >>> bool(path[-1, 7] < 1.0), round(hand_penetration(hand, ball, path[-1]).depth)
    (True, 3)
    """
    path = _close(hand, obj, u, hand.n_u - 1, -1, options)
    last = path[-1] if path else u
    best, best_score = [], _contacts(hand, obj, last, grasp, options, backend)
    for j in range(6, hand.n_u - 1):  # the other synergies, each way
        for sign in (-1, 1):
            walk = _close(hand, obj, last, j, sign, options, bisect=False)
            for i, v in enumerate(walk):
                score = _contacts(hand, obj, v, grasp, options, backend)
                if score > best_score:
                    best, best_score = walk[: i + 1], score
    rows = path + best
    return np.array(rows) if rows else np.zeros((0, hand.n_u))


def _close(hand, obj, u, j, sign, options, bisect=True):
    """Configurations moving synergy ``j`` of ``u`` by steps of ``options.close_step`` towards ``sign`` while the hand fits."""
    lo, hi = hand.synergy_limits[j - 6]
    end = lo if sign < 0 else hi

    def fits(value):
        v = u.copy()
        v[j] = value
        geo = hand.segments(v)
        return obj.penetration(geo.capsules, geo.radius).depth <= options.max_penetration

    values, z = [], u[j]
    while (z - end) * sign < 0:
        nxt = z + sign * options.close_step
        nxt = max(nxt, end) if sign < 0 else min(nxt, end)
        if not fits(nxt):
            if bisect:
                good, bad = z, nxt
                for _ in range(BISECTIONS):
                    mid = 0.5 * (good + bad)
                    good, bad = (mid, bad) if fits(mid) else (good, mid)
                if good != z:
                    values.append(good)
            break
        values.append(nxt)
        z = nxt
    rows = [u.copy() for _ in values]
    for row, value in zip(rows, values):
        row[j] = value
    return rows


def _contacts(hand, obj, u, grasp, options, backend):
    """(hand points within eps_c of the surface, minus the sum of their cP): larger is closer to a grasp."""
    cp = obj.contact_distance(hand.points(u, grasp), backend=backend).value
    near = cp < options.eps_c
    return int(near.sum()), -float(np.abs(cp[near]).sum())


def anneal(hand, obj, grasp, u0, options, *, backend="native", deadline=None, progress=None, physics=None):
    """Search from ``u0`` by simulated annealing until an auto-grasped state is accepted, or the budget runs out.

    Parameters
    ----------
    hand : SynergyHand
    obj : GraspObject
    grasp : {"precision", "power"}
    u0 : (6 + n_syn,) float
        The start (it must leave the hand out of the object).
    options : AnnealingOptions
    backend : str or Backend
        LP backend.
    deadline : float, optional
        `clock` value after which the search stops (seconds of
        ``time.perf_counter()`` less those numba spent compiling).
    progress : callable, optional
        Called as ``progress(check, status)`` after every auto-grasp.
    physics : callable, optional
        ``physics(u) -> Validation``; an accepted grasp that does not hold
        lets the search go on (the first accepted one is kept).

    Returns
    -------
    result : AttemptResult
        Its trajectory: the states moved to, then the closing of the
        returned auto-grasp; its status and g_Q: the last row's only (NaN
        before it, see `with_history`).
    record : dict
        The search as one entry of `PlanResult.attempts` (``kind``
        ``"annealing"``, with ``steps``, ``evaluations`` of the energy,
        ``autograsps`` and ``cpu_s``, the search's CPU time).
    held : bool or None
        The physics verdict of the returned grasp (None without ``physics``).
    """
    opts = options
    cpu = time.process_time()
    rng = np.random.default_rng(opts.seed)
    search = _Search(hand, obj, grasp, opts, backend)
    u = np.array(u0, dtype=float)
    energy = search.energy(u)
    moved, tried = [u.copy()], []
    k, steps, autograsps = opts.k0, 0, 0
    threshold = AUTOGRASP_ENERGY[grasp] if opts.autograsp_energy is None else opts.autograsp_energy
    found, fallback, held = None, None, None
    outcome = Outcome.CAP
    while steps < opts.steps:
        if deadline is not None and clock() > deadline:
            outcome = Outcome.BUDGET
            break
        steps += 1
        T = temperature(opts, k)
        for _ in range(opts.legal_tries):
            candidate = search.neighbour(rng, u, T * opts.neighbour_scale)
            e_new = search.energy(candidate)
            if math.isfinite(e_new):
                break
        else:
            continue  # no legal neighbour: the temperature stays (GraspIt!)
        k += 1
        if e_new >= energy and rng.random() >= math.exp(opts.energy_scale * (energy - e_new) / T):
            continue
        u, energy = candidate, e_new
        moved.append(u.copy())
        x = u / search.scale
        if energy >= threshold or any(np.abs(x - t).max() < opts.autograsp_spacing for t in tried):
            continue
        tried.append(x)
        autograsps += 1
        closing = autograsp(hand, obj, u, grasp, opts, backend)
        if not len(closing):
            continue
        st, chk = search.status(closing[-1])
        if progress is not None:
            progress(read_only(chk), read_only(st))
        ok, pen, surface = judge_grasp(hand, obj, closing[-1], st, chk, opts, backend=backend)
        if not ok:
            continue
        verdict = physics(closing[-1]) if physics is not None else None
        candidate_result = (list(moved) + list(closing), st, chk, pen, surface)
        if verdict is None or verdict.held:
            found, held = candidate_result, None if verdict is None else True
            break
        fallback = fallback or candidate_result
    if found is None and fallback is not None:
        found, held = fallback, False
    if found is not None:
        rows, st, chk, pen, surface = found
        outcome = Outcome.GRASP
    else:
        rows, surface = moved, None
        st, chk = search.status(u)
        pen = hand_penetration(hand, obj, u)
    trajectory = np.array(rows)
    statuses = np.full((len(trajectory), len(st.g)), np.nan)  # the search's own record: the last row only
    statuses[-1] = st.g
    qs = np.full(len(trajectory), np.nan)
    qs[-1] = chk.q
    reason = (f"{outcome.value} ({chk.n_contacts} contacts, g_Q = {chk.q:.4f})" if outcome is Outcome.GRASP else
              f"{outcome.value} (annealing: {steps} steps, {autograsps} auto-grasps)")
    result = AttemptResult(outcome, reason, trajectory, statuses, qs, st, chk, float(pen.depth),
                           int(search.lp_solves), surface)
    record = {"start": np.asarray(u0, dtype=float).tolist(), "kind": "annealing", "outcome": outcome.name.lower(),
              "reason": reason, "iterations": len(trajectory) - 1, "steps": steps, "evaluations": search.evaluations,
              "autograsps": autograsps, "cpu_s": time.process_time() - cpu}
    return result, record, held


def with_history(result, hand, obj, grasp, options, *, backend="native"):
    """``result`` with the gradient planner's status vector and g_Q at every row of its trajectory.

    The search evaluates only its energy at the states it moves to; their
    status is computed here, after the search (`plan` does not count it in
    ``time_s``).

    Parameters
    ----------
    result : AttemptResult
        From `anneal`.
    hand : SynergyHand
    obj : GraspObject
    grasp : {"precision", "power"}
    options : AnnealingOptions
    backend : str or Backend

    Returns
    -------
    AttemptResult
    """
    search = _Search(hand, obj, grasp, options, backend)
    statuses, qs = result.status.copy(), result.q_history.copy()
    for i, u in enumerate(result.trajectory[:-1]):
        st, chk = search.status(u)
        statuses[i], qs[i] = st.g, chk.q
    return replace(result, status=statuses, q_history=qs)
