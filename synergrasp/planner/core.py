"""`plan`: attempts from the object's geometry until one ends in a grasp accepted on the true surface.

``method="gradient"`` (the default) is the paper's planner, below;
``method="annealing"`` the GraspIt!-style baseline of
`synergrasp.planner.annealing`, with its own options and the same result.

A plan tries the starts of `synergrasp.planner.starts` in turn (precision:
pairs of opposed surface points, then directions around the object; power:
the palm laid on the surface with the fingers closed around it, then
directions with two pre-shapes), one attempt each (`run_attempt`), until an
attempt ends in an accepted grasp (the paper's criterion, no phalanx too
deep, force-closed with a margin on the object's true surface), or
``restarts`` attempts, ``max_iter`` iterations or ``time_limit`` seconds are
spent. The returned search trajectory is the successful attempt's (or the
last one's); the motion to execute is the grasp's `executable_reach`.

A plan starts its LPs cold (the backend's and the object's warm starts and
the pseudo-distance's regimes are dropped first): the same inputs give the
same plan bit for bit, whatever was planned before in the process (up to
its time limit).
"""

from __future__ import annotations

import itertools
import os
import time
from dataclasses import replace
from types import SimpleNamespace

import numpy as np

from .. import objects
from .._jit import clock
from .._checks import as_vector
from ..hand import SynergyHand, grasp_kind
from ..lp import get_backend
from ..pseudo_distance import reset_regime_memory
from .annealing import anneal, with_history
from .attempt import Outcome, run_attempt
from .options import GRASPS, MAX_START_DISTANCE, AnnealingOptions, PlannerOptions
from .reach import executable_reach, widest_opening
from .result import PlanResult
from .starts import (Start, opposed_widths, preshape, smallest_pinch, start_configuration, starts,
                     widest_pinch)
from .status import SLENDER, axial_radius, slender, steering_scale
from .stop import CRITERION

#: Keywords of `synergrasp.objects.load` that a plan of a file path might be given by mistake.
_LOADING = ("scale", "name", "max_parts", "max_vertices", "cache", "center", "torque_scale")
#: Objects thinner than this (mm) are refused: a mesh in metres when it is also small overall, else a sheet or a wire.
MIN_WIDTH = 2.0
#: The planners by name, with their options' class.
METHODS = {"gradient": PlannerOptions, "annealing": AnnealingOptions}


def hand_opening(hand):
    """The hand's largest opening: the farthest a fingertip gets from the thumb tip (mm), at `widest_opening`.

    Parameters
    ----------
    hand : SynergyHand

    Returns
    -------
    float
    """
    tips = hand.points(np.r_[np.zeros(6), widest_opening(hand)], "precision")
    return float(np.linalg.norm(tips[1:] - tips[0], axis=1).max())


def _pinch_words(hand):
    """The fingertips of a pinch (the first finger against the second and third), named for a message."""
    words = {"T": "thumb", "I": "index", "M": "middle"}
    first, second, third = (words.get(name, repr(name)) for name in hand.finger_names[:3])
    return f"the {first} and the {second} and {third} fingertips"


def _thinnest_pinch(hand, opts):
    """The thinnest object (mm) a pinch can hold: `smallest_pinch` less the contact band's far edge on either side.

    Returns
    -------
    thinnest, pinch, band : float
        It, the smallest pinch, and ``opts.contact_band[1]`` (the farthest
        from the surface the steering brings a pad).
    """
    pinch, band = smallest_pinch(hand), opts.contact_band[1]  # (the first computes once per hand: ~0.2 s)
    return pinch - 2.0 * band, pinch, band


class ObjectRefused(ValueError):
    """The hand cannot hold the object (too large for its opening, too thin or too small for its fingertips): `plan`
    refuses it before any attempt, with the measured reason. A `ValueError`, so that a bad argument and a refused
    object are both caught as one; catch this class to tell them apart."""


def _check_object(obj, hand):
    """The object as a GraspObject, refused early when the hand cannot hold it."""
    if isinstance(obj, (str, os.PathLike)):
        obj = objects.get(obj)
    elif not isinstance(obj, objects.GraspObject):
        hint = ("; a mesh in memory becomes one with sg.objects.from_mesh(mesh)" if hasattr(obj, "vertices") else
                "; a point cloud becomes one with sg.objects.from_points(points)" if isinstance(obj, (np.ndarray, list, tuple))
                else "")
        raise TypeError(f"obj must be a GraspObject, a built-in name or a file path, got {type(obj).__name__}{hint}")
    width, opening = obj.width, hand_opening(hand)
    if width < MIN_WIDTH:
        if obj.size < objects.loading.SIZE_RANGE[0]:  # small every way: most likely in metres
            raise ObjectRefused(
                f"{obj.name} is too small to grasp: its smallest width is {width:.3g} mm "
                f"(less than {MIN_WIDTH:g} mm). Is it in metres? Load it with sg.objects.load(path, scale=1000)."
            )
        raise ObjectRefused(
            f"{obj.name} is too thin to grasp: it is {width:.3g} mm thin, less than the {MIN_WIDTH:g} mm "
            f"the fingertips need between them, while it is {obj.size:.0f} mm long (a sheet or a wire: its units "
            "are plausible, its shape is not one this hand can hold)"
        )
    if width > opening:
        raise ObjectRefused(
            f"{obj.name} is too large for the hand: its smallest width is {width:.0f} mm "
            f"but the hand opens at most {opening:.0f} mm between thumb and fingertips. "
            + ("Check the object's units (sg.objects.load(path, scale=...)) or use a larger hand file."
               if obj.size > objects.loading.SIZE_RANGE[1] else "Use a larger hand file.")
        )
    return obj


def _given_start(u0, hand, obj):
    """``u0`` as a start configuration, refused when its palm is farther from the object than any start or its Euler
    angles go beyond a turn (degrees, most likely)."""
    u0 = as_vector(u0, "u0", hand.n_u)
    far = float(np.linalg.norm(u0[:3] - obj.center))
    if far > MAX_START_DISTANCE:
        raise ValueError(f"u0 places the palm {far:.4g} mm from {obj.name}'s centre, farther than {MAX_START_DISTANCE:g} "
                         "mm (the largest start_distance): start the hand near the object (coordinates in mm)")
    angles = u0[3:6]
    if np.abs(angles).max() > 2.0 * np.pi:
        raise ValueError(f"u0's Euler angles {np.round(angles, 3).tolist()} go beyond 2 pi: they are radians (degrees? "
                         "np.radians(...) converts them; np.angle(np.exp(1j * a)) brings radians into (-pi, pi])")
    return np.r_[u0[:6], hand.clip_synergies(u0[6:], "u0's synergies")]


def _options(method, options, values):
    """The plan's options of ``method``: ``options`` (or the defaults) with ``values`` replaced."""
    if method not in METHODS:
        raise ValueError(f"unknown method {method!r}; known: {sorted(METHODS)}")
    kind = METHODS[method]
    if options is None:
        options = kind()
    elif not isinstance(options, kind):
        raise TypeError(f"options of method={method!r} must be an instance of {kind.__name__}, got {type(options).__name__}")
    unknown = sorted(set(values) - set(kind.names()))
    for other, other_kind in METHODS.items():
        theirs = [name for name in unknown if name in other_kind.names()]
        if theirs:
            raise ValueError(f"options {theirs} belong to method={other!r}, not to method={method!r}; "
                             f"its options: {kind.names()}")
    how = ("sg.plan(sg.objects.load(path, scale=1000), grasp) for a file in metres (scale=10: centimetres; "
           f"sg.objects.load's options: {', '.join(_LOADING)})")
    if "units" in unknown:
        raise ValueError(f"'units' is the command line's --units, not a planner option: in Python a file's units are "
                         f"the scale it is loaded with: {how}")
    loading = [name for name in unknown if name in _LOADING]
    if loading:
        raise ValueError(f"{loading} {'is an option' if len(loading) == 1 else 'are options'} of loading the "
                         f"object, not of planning: load it first, e.g. {how}")
    if unknown:
        raise ValueError(f"unknown planner options {unknown}; known for method={method!r}: {kind.names()}")
    return replace(options, **values) if values else options


def plan(obj, grasp="precision", *, method="gradient", options=None, backend="native", u0=None, approach=None, hand=None,
         progress=None, validate=False, **option_values) -> PlanResult:
    """Plan a reach-to-grasp motion (paper Sec. 3.2) for the synergy hand.

    Parameters
    ----------
    obj : GraspObject, str or os.PathLike
        The object (``synergrasp.objects``), or a built-in name or a file
        path as `synergrasp.objects.get` takes them.
    grasp : {"precision", "power"}
        Fingertip pinch, or a grasp with the phalanges and the palm.
    method : {"gradient", "annealing"}
        ``"gradient"``: the paper's resolved-rate planner. ``"annealing"``:
        the GraspIt!-style eigengrasp simulated annealing baseline
        (`synergrasp.planner.annealing`): one search from ``u0`` (or the
        start from ``approach``, default +y), accepted by the same test; its
        trajectory is the sequence of states the search moved to, then the
        auto-grasp's closing, and ``time_s`` the search's time (the status
        of each row is computed after it).
    options : PlannerOptions or AnnealingOptions, optional
        Settings of ``method`` (default ``PlannerOptions()``, respectively
        ``AnnealingOptions()``).
    backend : str or synergrasp.lp.Backend
        LP backend: a name of `synergrasp.lp.available_backends` or an
        instance.
    u0 : (n_u,) float, optional
        Start configuration: one attempt from it (its synergies clipped to
        their limits, with a warning, if they lie outside; its Euler angles
        in radians, each at most 2 pi in size).
    approach : (3,) float, optional
        Direction from the object's centre to the start of the first attempt
        (`start_configuration`); the plan's own starts follow.
    hand : SynergyHand, optional
        Default: ``SynergyHand.default()``.
    progress : callable, optional
        Called as ``progress(check, status)`` after every iteration (with
        ``method="annealing"``: after every auto-grasp, the only steps that
        evaluate a grasp), with read-only copies (`read_only`) of the
        iteration's `GraspCheck` and `Status`. Its own time counts in
        ``time_limit``.
    validate : bool or dict
        Also test every accepted grasp in MuJoCo (`synergrasp.validate`; a
        dict gives its protocol settings) and keep searching, through
        further attempts, until one holds. The result records both verdicts
        (``success`` and ``held``); if no grasp holds within the budget, the
        first accepted one is returned with ``held`` False; a grasp the
        simulation refuses (`synergrasp.physics.NoContact`) counts as not
        held. A validation starts its LPs cold (`forget_warm_starts`), and so
        do the attempts after it. Needs the ``sim`` extra.
    **option_values
        Fields of the method's options class, replacing those of ``options``.

    Returns
    -------
    PlanResult

    Raises
    ------
    TypeError
        If ``obj`` is not an object, a name or a path, ``options`` not the
        method's options class, ``hand`` not a SynergyHand or ``progress``
        not callable.
    ValueError
        Unknown object name, grasp type or method (the message lists the
        methods), an option of the other method (named), an option out of its range, bad
        ``u0`` or ``approach`` (or both given), unknown backend.
    ObjectRefused
        A `ValueError`: an object the hand cannot hold (too small, too thin, or
        wider than its opening).

    Examples
    --------
    >>> from synergrasp import objects
    >>> result = plan(objects.ellipsoid(), "precision")
    >>> result.success, len(result.contact_labels) >= 3, result.final_q < 0
    (True, True, True)
    """
    if isinstance(grasp, str) and grasp.lower() in GRASPS:
        grasp = grasp.lower()  # "Power" as objects.get("Cup") takes any case
    grasp_kind(grasp, "grasp")
    opts = _options(method, options, option_values)
    if u0 is not None and approach is not None:
        raise ValueError("give u0 or approach, not both: u0 is the start itself, approach the direction a start is "
                         "placed along")
    solver = get_backend(backend)
    hand = SynergyHand.default() if hand is None else hand
    if not isinstance(hand, SynergyHand):
        raise TypeError(f"hand must be a SynergyHand (e.g. SynergyHand.from_file(path)), got {type(hand).__name__}")
    if len(hand.finger_names) < 3:
        raise ValueError(f"hand {hand.name!r} has {len(hand.finger_names)} finger chain(s); the planner needs a thumb "
                         "(the first chain) and at least two fingers to oppose it")
    if progress is not None and not callable(progress):
        raise TypeError(f"progress must be callable as progress(check, status), got {type(progress).__name__}")
    if grasp == "power" and method == "gradient":
        preshape(hand, opts.power_wide_preshape), preshape(hand, opts.power_preshape)  # checked before planning
    obj = _check_object(obj, hand)
    if grasp == "precision" and method == "gradient" and obj.size < objects.loading.SIZE_RANGE[0]:
        thinnest, pinch, band = _thinnest_pinch(hand, opts)
        if obj.size < thinnest:
            raise ObjectRefused(
                f"{obj.name} is too small for a pinch: it is at most {obj.size:.3g} mm across, while "
                f"{_pinch_words(hand)} close to no less than {pinch:.0f} mm apart, and a pad must come within "
                f"{band:g} mm of it on either side (contact_band). Is it in other units? Load it with "
                "sg.objects.load(path, scale=...) (25.4 for inches, 1000 for metres)."
            )
    forget_warm_starts(solver, obj)
    t0 = time.perf_counter()
    deadline = None if opts.time_limit is None else clock() + opts.time_limit  # compilation not counted
    if not isinstance(validate, (bool, dict)):
        raise TypeError(f"validate must be True, False or a dict of protocol settings, got {type(validate).__name__}")
    if method == "annealing":
        start = _given_start(u0, hand, obj) if u0 is not None else start_configuration(
            hand, obj, (0.0, 1.0, 0.0) if approach is None else as_vector(approach, "approach", 3), opts.start_distance,
            opts.start_clearance, palm_centred=grasp == "power")
        result, record, held = anneal(hand, obj, grasp, start, opts, backend=solver, deadline=deadline,
                                      progress=progress, physics=_validator(validate, obj, hand, solver))
        attempts, solves = [record], result.lp_solves
        return _result(result, attempts, held, solves, t0, hand, obj, grasp, opts, solver, validate, result.reason)
    if u0 is not None:
        queue = iter([Start(_given_start(u0, hand, obj), "given", {})])
    else:
        queue = starts(hand, obj, grasp, opts, backend=solver, deadline=deadline)
        if approach is not None:
            direction = as_vector(approach, "approach", 3)
            wide = grasp == "power" and opts.power_wide_preshape is not None  # as the power starts: wide, else cupped
            first = start_configuration(hand, obj, direction, opts.start_distance, opts.start_clearance,
                                        palm_centred=wide)
            if grasp == "power":
                first[6:] = preshape(hand, opts.power_wide_preshape if wide else opts.power_preshape)
            queue = itertools.chain([Start(first, "direction", {"direction": direction.tolist(), "turn": 0.0})], queue)
    physics = _validator(validate, obj, hand, solver)
    total, solves, attempts, result, held, fallback = 0, 0, [], None, None, None
    for start in itertools.islice(queue, opts.restarts):
        budget = min(opts.iterations_per_attempt, opts.max_iter - total)
        if budget <= 0 or (attempts and deadline is not None and clock() > deadline):
            break  # (a first attempt past the deadline ends at once, saying so)
        result = run_attempt(hand, obj, grasp, start.u, opts, backend=solver, budget=budget, deadline=deadline,
                             progress=progress)
        total += result.iterations_run
        solves += result.lp_solves
        record = {"start": start.u.tolist(), "kind": start.kind, **start.detail, "outcome": result.outcome.name.lower(),
                  "reason": result.reason, "iterations": result.iterations, "iterations_run": result.iterations_run,
                  "status": result.status.tolist()}
        attempts.append(record)
        if result.success and physics is not None:
            verdict = physics(result.trajectory[-1])
            record.update(held=verdict.held, physics=verdict.reason)
            held = verdict.held
            if not held:
                fallback = fallback or (result, held)
                continue
        if result.success or result.outcome is Outcome.BUDGET:
            break
    if result is None:
        raise ValueError("the plan made no attempt: every start was skipped (max_iter or time_limit too small?)")
    if fallback is not None and not (result.success and held):
        result, held = fallback  # no grasp held: the first accepted one
    timed_out = deadline is not None and clock() > deadline and total < opts.max_iter  # (its time, not max_iter)
    failure = None if result.success else _failure(attempts, grasp, hand, obj, opts, backend=solver.name,
                                                   timed_out=timed_out)
    suffix = f"; {len(attempts)} attempts, {total} iterations in all" if len(attempts) > 1 else ""
    return _result(result, attempts, held, solves, t0, hand, obj, grasp, opts, solver, validate, failure, suffix)


def forget_warm_starts(solver, obj):
    """Start cold, as every plan does: what earlier solves keep for later ones is dropped.

    The backend's kept models and bases, the object's cP bases and the
    pseudo-distance's regimes: a plan (or an attempt run after this call)
    then depends on its inputs only, not on what was solved before it.

    Parameters
    ----------
    solver : synergrasp.lp.Backend
    obj : GraspObject
    """
    solver.forget()
    obj.index.forget()
    reset_regime_memory()


def _result(result, attempts, held, solves, t0, hand, obj, grasp, opts, solver, validate, failure, suffix=""):
    """The PlanResult of a plan's returned attempt: ``failure`` is the reason without a grasp; ``suffix`` ends it."""
    success = result.success
    elapsed = time.perf_counter() - t0
    reason = failure
    if success:
        reason = f"stop criterion met ({result.check.n_contacts} contacts, g_Q = {result.check.q:.4f}"
        if f"{result.surface.q:.4f}" != f"{result.check.q:.4f}":  # the Q the grasp was accepted on, where it differs
            reason += f"; Q on the true surface {result.surface.q:.4f}"
        reason += ")"
        if validate is not False:
            reason += "; it holds in simulation" if held else "; no accepted grasp held in simulation"
    reason += suffix
    if np.isnan(result.status).any():  # the annealing's trajectory: its status after the search, not timed
        result = with_history(result, hand, obj, grasp, opts, backend=solver)
    chk, final = result.check, result.final
    reach = executable_reach(hand, obj, result.trajectory[-1], tolerance=opts.max_penetration) \
        if success and opts.executable_reach else None
    return PlanResult(
        success=bool(success),
        reason=reason,
        iterations=result.iterations,
        u=result.trajectory[-1].copy(),  # (not a view: changing one does not change the other)
        trajectory=result.trajectory,
        status=result.status,
        target=np.r_[np.zeros(len(final.labels)), -1.0],
        q_history=result.q_history,
        contact_points=final.nearest[chk.contact],
        contact_normals=final.normals[chk.contact],
        contact_labels=[lab for lab, c in zip(final.labels, chk.contact) if c],
        penetration=result.penetration,
        time_s=elapsed,
        lp_solves=int(solves),
        backend=solver.name,
        grasp=grasp,
        object_name=obj.name,
        hand=hand.identity,
        options=opts.as_dict(),
        attempts=attempts,
        surface_q=result.surface.q if success else float("nan"),
        held=held if success else None,
        **({} if reach is None else reach.plan_fields()),
    )


def _validator(validate, obj, hand, backend):
    """The physics test of a plan's accepted grasps (a function of u -> Validation), or None."""
    if validate is False:
        return None
    from ..physics import NoContact, mujoco_module, protocol, retreat_distance  # noqa: PLC0415 - MuJoCo when asked for
    from ..physics.protocol import check_setting_names  # noqa: PLC0415
    from ..physics import validate as simulate  # noqa: PLC0415

    settings = {} if validate is True else dict(validate)
    named = [key for key in settings if not isinstance(key, str)]
    if named:
        raise TypeError(f"validate's settings are named by strings (as synergrasp.validate's keywords), got {named!r}")
    # MuJoCo missing, an unknown preset or setting: refused now, not after the planning
    mujoco_module()
    own = ("preset", "retreat")  # validate's keywords beside the protocol's settings
    check_setting_names(settings, also=own)
    protocol(settings.get("preset", "synergrasp"), **{k: v for k, v in settings.items() if k not in own})
    retreat_distance(settings.get("retreat", 0.0))
    def check(u):
        try:
            return simulate(u, obj, hand=hand, backend=backend, **settings)
        except NoContact as exc:  # a grasp read on the phalanges' capsules that no hand point squeezes
            return SimpleNamespace(held=False, reason=f"not simulated: {exc}")

    return check


def _failure(attempts, grasp, hand, obj, opts, backend=None, timed_out=False):
    """Why a plan found no grasp, in words: its attempts' outcomes, the commonest first.

    When every pinch seed it tried spanned less than the hand's smallest
    pinch (`smallest_pinch`) less the contact band's far edge
    (``opts.contact_band[1]``, where the steering brings a pad) on either
    side, it says so: the object's opposed surfaces are a wall too thin for
    the pads to reach both. When a precision plan had no pinch seed
    at all, it says why: no two surface points face each other, or those
    that do are too far apart for the hand's widest pinch (`widest_pinch`)
    less ``opts.seed_opening`` on either side. When most power attempts
    ended with every phalanx more than ``eps_c`` from the object, it says
    that and how far they stopped: the fingers did not close around it.
    When no wrap pose passed the screen (`wrap_seeds`), it says so, unless the
    plan's budget ended it (its time also ends the screen). A plan that its
    time limit ended before its iterations ran out (``timed_out``) says so first (with
    ``backend``, the LP backend's name, when not the default), and, if no
    attempt made a step, nothing of the object. When no wrap seed it
    tried had as many phalanges near the surface with the palm on it as
    the paper's power criterion needs (`wrap_seeds`' ``touching``;
    `CRITERION`: the palm and three phalanges with g_Q < -0.1, or five), it
    says so: the
    hand may not be able to wrap the object. When the object is slender
    (`axial_torque` below `SLENDER`), it says that every grasp's Q distance
    stays near 0, that a power plan's attempts steered by its diameter
    (`steering_scale`) and that a torque scale near its diameter would put
    the criterion's margins in those units too. No clock time in it
    (that is `PlanResult.time_s`): the same plan gives the same words.
    """
    counts = {}
    for a in attempts:
        counts[a["outcome"]] = counts.get(a["outcome"], 0) + 1
    words = {o.name.lower(): o.value for o in Outcome}
    parts = ", ".join(f"{n} {words.get(k, k)}" for k, n in sorted(counts.items(), key=lambda kv: -kv[1]))
    reason = f"no stable grasp found in {len(attempts)} attempt(s) ({parts})"
    if timed_out:
        total = sum(a["iterations_run"] for a in attempts)
        reason += (f"; the plan's time limit (time_limit = {opts.time_limit:g} s) ended it after {len(attempts)} "
                   f"attempt(s) and {total} iterations, before its iterations ran out (max_iter = {opts.max_iter}): "
                   "a longer time_limit (None for none)"
                   + (f" or a faster LP backend than {backend}" if backend not in (None, "native") else "")
                   + " lets it try more")
    eps_c, (thinnest, pinch, band) = opts.eps_c, _thinnest_pinch(hand, opts)
    widths = [a["width"] for a in attempts if a["kind"] == "pinch"]
    if grasp == "precision" and not widths and all(a["kind"] == "direction" for a in attempts):
        opposed, widest = opposed_widths(obj, opts.seed), widest_pinch(hand)
        if not len(opposed):
            reason += ("; no two points of its surface face each other, so no pinch seed was tried (the pads "
                       "press on opposed surfaces) and every attempt started from a direction around it")
        elif opposed.min() + 2.0 * opts.seed_opening > widest:
            reason += (f"; its opposed surfaces are at least {opposed.min():.0f} mm apart, and {_pinch_words(hand)} "
                       f"open at most {widest:.0f} mm apart ({opts.seed_opening:g} mm "
                       "to spare on either side for a pinch seed), so no pinch seed was tried and every attempt "
                       "started from a direction around it")
    if widths and max(widths) < thinnest:
        reason += (f"; the opposed surfaces its pinches started from are at most {max(widths):.0f} mm apart, while "
                   f"{_pinch_words(hand)} close to no less than {pinch:.0f} mm, too far "
                   f"apart to bring both within {band:g} mm of it (the contact band the pads are steered into; "
                   f"accepted within {eps_c:g} mm): a wall or sheet too thin for this hand's pinch")
    cut = attempts[-1]["outcome"] == Outcome.BUDGET.name.lower()  # the plan's iterations or time ended it
    if cut and not any(a["iterations"] for a in attempts):
        return reason + "; no attempt made a step, so none tells anything of the object"  # (its time ended it)
    if grasp == "power":
        nearest = np.array([min(a["status"][-1][:-2]) for a in attempts])  # each attempt's nearest phalanx at its end
        apart = nearest > eps_c
        if 2 * apart.sum() > len(attempts):
            reason += (f"; in {apart.sum()} of them no phalanx ended within {eps_c:g} mm of the object (the nearest "
                       f"{np.median(nearest[apart]):.0f} mm off, median): the fingers did not close around it")
        touching = [a["touching"] for a in attempts if a["kind"] == "wrap"]
        if not touching and not cut:  # (the time limit also ends the screening of wrap poses)
            reason += ("; no wrap pose (the palm on its surface, the fingers closed around it) was free of it: in "
                       "every pose screened a phalanx or the palm reached into it, so every attempt started from a "
                       "direction around it")
        few, many = CRITERION["power"]  # contacts with the palm counted
        if touching and max(touching) < few - 1:
            most = {0: "no phalanx", 1: "at most one phalanx"}.get(max(touching), f"at most {max(touching)} phalanges")
            reason += (f"; with the palm on it, {most} came within {eps_c:g} mm of its surface in the wrap poses "
                       f"tried, where a power grasp needs the palm and {few - 1} phalanges (g_Q < -0.1) or "
                       f"{many - 1}: the hand may not be able to wrap it"
                       + (" (a precision grasp may hold it)" if thinnest <= obj.size and obj.width <= widest_pinch(hand)
                          else ""))
    if grasp == "power" and obj.size < thinnest:
        reason += (f"; it is at most {obj.size:.3g} mm across, thinner than a pinch of {_pinch_words(hand)} can hold "
                   f"({thinnest:.0f} mm), so a precision grasp is refused too")
    arm, torque = axial_torque(obj, opts.mu)
    if torque < SLENDER and slender(obj, opts.mu):  # (its Q near 0, and not for a torque scale far above its size)
        steer = steering_scale(obj, opts.mu)
        steered = grasp == "power" and steer < obj.torque_scale
        near = torque <= 2.0 * abs(opts.q_accept)  # (then near or above the acceptance's threshold)
        reason += (f"; it is slender: its surface lies at most {arm:.0f} mm from its long axis, so friction (mu = "
                   f"{opts.mu:g}) resists a torque about that axis of at most {torque:.3f} of its torque scale "
                   f"(L = {obj.torque_scale:.0f} mm) per unit of grip force, and any grasp's Q distance stays near 0 "
                   f"(of the order of {torque:.3f}"
                   + (f", near or above the acceptance's q_accept = {opts.q_accept:g})" if near else ")")
                   + (f". Its attempts steered by a torque scale of {steer:.0f} mm (twice its axial radius), but the "
                      "criterion's margins and Q are in L; a torque scale" if steered else "; a torque scale")
                   + f" near its diameter (torque_scale={2.0 * arm:.0f} when loading or building it, e.g. "
                   f"sg.objects.load(..., torque_scale={2.0 * arm:.0f})) "
                   + ("puts them in those units too" if steered else "weighs those torques as forces at its surface"))
    return reason


def axial_torque(obj, mu):
    """How much torque about its long axis friction can apply to an object, against its torque scale.

    A contact at most ``arm`` mm from the object's long axis
    (`axial_radius`) with a normal force f applies at most
    ``mu * arm * f`` about it.

    Parameters
    ----------
    obj : GraspObject
    mu : float
        Friction coefficient.

    Returns
    -------
    arm : float
        The farthest the object's pieces reach from the axis (mm).
    torque : float
        ``mu * arm / obj.torque_scale``.

    Examples
    --------
    A rod 20 mm thick and 300 mm long (torque scale 150 mm):

    >>> import trimesh
    >>> from synergrasp import objects
    >>> rod = objects.from_mesh(trimesh.creation.cylinder(radius=10.0, height=300.0, sections=32), cache=False)
    >>> [round(v, 3) for v in axial_torque(rod, 0.3)]
    [10.0, 0.02]
    """
    arm = axial_radius(obj)
    return arm, mu * arm / obj.torque_scale
