"""The planners' settings, each checked when the options are made: `PlannerOptions` (``method="gradient"``) and `AnnealingOptions` (``method="annealing"``)."""

from __future__ import annotations

import math
from dataclasses import dataclass, fields

import numpy as np

from .._checks import numeric
from ..hand import POINT_KINDS

#: The grasp types the planners know (the hand's point kinds; re-exported by synergrasp.planner).
GRASPS = POINT_KINDS

#: Farthest start of the hand from the object's centre (mm): ``start_distance``'s bound, and a given ``u0``'s.
MAX_START_DISTANCE = 10000.0
#: Largest friction coefficient ``mu`` the planners (and the physics protocol) take.
MAX_FRICTION = 10.0
#: Most attempts of a plan (`PlannerOptions.restarts`).
MAX_RESTARTS = 1_000_000
#: Most neighbours an annealing step draws (`AnnealingOptions.legal_tries`): each costs an energy evaluation.
MAX_LEGAL_TRIES = 1000
#: Smallest synergy step of the auto-grasp's closing (`AnnealingOptions.close_step`): at most about
#: 2 / MIN_CLOSE_STEP collision-checked steps across a synergy's range.
MIN_CLOSE_STEP = 1e-3


def _number(value, name, low=None, high=None, *, integer=False, open_low=False, open_high=False, allow_none=False,
            owner="PlannerOptions", low_from=None, high_from=None):
    """``value`` as a float (or int) within ``[low, high]`` (open at ``open_low`` / ``open_high``), else a ValueError.

    A bound of None: no bound on that side but finiteness; the message's range is open there (``[1, inf)``).
    ``low_from`` / ``high_from``: the names of the options the bounds are (the message names them).
    """
    if value is None and allow_none:
        return None
    kind = "an integer" if integer else "a number"
    lo = "-inf" if low is None else f"{owner}.{low_from} = {low}" if low_from else low
    hi = "inf" if high is None else f"{owner}.{high_from} = {high}" if high_from else high
    span = f"{'(' if open_low or low is None else '['}{lo}, {hi}{')' if open_high or high is None else ']'}"
    ok_type = isinstance(value, (int, np.integer)) if integer else isinstance(value, (int, float, np.integer, np.floating))
    if isinstance(value, (bool, np.bool_)) or not ok_type or not _finite(value):
        none = " or None" if allow_none else ""
        raise ValueError(f"{owner}.{name} must be {kind} in {span}{none}, got {value!r}")
    if ((low is not None and (value < low or (open_low and value == low)))
            or (high is not None and (value > high or (open_high and value == high)))):
        raise ValueError(f"{owner}.{name} must be in {span}, got {value!r}")
    return int(value) if integer else float(value)


def _finite(value) -> bool:
    """Whether a number is finite as a float (an int too large for a float is not)."""
    try:
        return math.isfinite(float(value))
    except OverflowError:
        return False


def _flag(value, name, owner="PlannerOptions"):
    if not isinstance(value, (bool, np.bool_)):
        raise ValueError(f"{owner}.{name} must be True or False, got {value!r}")
    return bool(value)


def _values(value, name, what, size=None, allow_none=True):
    """Finite numbers (``size`` of them, if given) as a tuple, or None (if ``allow_none``)."""
    if value is None and allow_none:
        return None
    try:
        arr = numeric(value)  # (text and booleans are not numbers)
    except (TypeError, ValueError, OverflowError):  # (an int beyond a float's range: not finite)
        arr = None
    if arr is None or arr.ndim != 1 or not len(arr) or (size and len(arr) != size) or not np.all(np.isfinite(arr)):
        raise ValueError(f"PlannerOptions.{name} must be {what}{' or None' if allow_none else ''}, got {value!r}")
    return tuple(float(x) for x in arr)


class _Fields:
    """The option names and their JSON values, shared by the options classes."""

    @classmethod
    def names(cls) -> list[str]:
        """The option names, in order."""
        return [f.name for f in fields(cls)]

    def as_dict(self) -> dict:
        """The options as plain JSON values (tuples as lists)."""
        return {f.name: list(v) if isinstance(v := getattr(self, f.name), tuple) else v for f in fields(self)}


@dataclass(frozen=True)
class PlannerOptions(_Fields):
    """Settings of `plan`; every one has a working default and is checked on creation.

    Attributes
    ----------
    eps_c : float
        Contact threshold (mm, in cP), paper: 5.
    mu : float
        Friction coefficient, paper: 0.3.
    edges : int
        Friction cone edges, paper: 8.
    contact_target : float
        Power grasps: the cP (mm) every contact row asks for, inside the contact
        band ``[0, eps_c)``: in contact without pressing the phalanges in.
    contact_band : (2,) float
        Precision grasps: a fingertip whose cP lies in ``[low, high]`` (mm) is
        left free by the step, one outside is pulled to the band's nearer
        edge. Five fingertips moved by two synergies cannot all sit at one
        distance from a surface; the band lets them settle where they can.
    band_step : float
        Precision grasps: a step is shortened so that no fingertip inside the
        contact band moves by more than this (mm, to first order): a free
        fingertip is not thrown off the surface or into it by the other rows'
        step.
    clearance : float
        Clearance rows (precision grasps: the phalanges other than the distal
        ones, and the palm) below this cP (mm) are pushed back to it, with
        the first priority.
    sq_step : float
        Decrease of g_sQ requested per iteration (a moving target instead of
        the paper's unreachable -1). Precision grasps ask at most what the
        linear model promises within the trust radius (`sq_request`).
    smoothing : float
        Normal smoothing length of the sQ contacts, as a fraction of the
        object's torque scale (`synergrasp.planner.status.smoothed_normals`).
    radius, radius_min, radius_max : float
        Initial trust radius of the normalised step (position in object
        sizes, angles in rad, synergies in units) and its bounds.
    stall_window : int or (int, int)
        An attempt whose merit (the contact errors plus g_sQ floored at -0.1)
        has not improved in this many iterations has stalled: (precision,
        power), or one number for both. A precision attempt gets more: its
        merit can stand still for longer before its grasp closes.
    crawl_window, crawl_fraction : int, float
        An attempt whose best merit fell by less than ``crawl_fraction`` of
        (its size + 0.1) over the last ``crawl_window`` iterations has
        stalled too (0: no such test).
    touch_window : int
        A precision attempt with no fingertip within ``eps_c`` of the surface
        after this many iterations has stalled (0: no such test).
    iterations_per_attempt : int
        Iteration cap of one attempt.
    restarts : int
        Most attempts of a plan (at most `MAX_RESTARTS`).
    max_iter : int
        Most iterations of a plan, over all its attempts.
    time_limit : float or None
        Most wall-clock seconds of a plan's search (checked every iteration
        and before each pose the power seeds check), not counting numba's
        compilation of the kernels in the first plan after an install
        (`synergrasp.planner.clock`); None: no limit. What has begun runs to
        its end: an iteration, a seed's check (with the cvxpy backend one
        status evaluation can take a few seconds), a grasp found just before
        the limit and simulated (``validate``), and the executable reach of
        the returned grasp (`PlanResult.time_s` is the search's time).
    q_accept : float
        A grasp is accepted when, besides the paper's criterion, its contacts
        moved to the object's true surface have a Q distance below this there
        (`synergrasp.planner.stop.surface_check`): force-closed with a margin.
    q_margin : float
        Once the paper's criterion holds, an attempt refines the grasp
        (`synergrasp.planner.attempt`) until its Q on the true surface is
        below this: the contacts' own g_Q is asked to fall for up to
        ``refine_iterations`` iterations, and the best accepted configuration
        is kept.
    refine_iterations : int
        Most refining iterations of an attempt (0: stop at the criterion, as the paper).
    max_penetration : float
        Deepest penetration (mm) of a phalanx capsule or the palm box into the
        object allowed in a final grasp, in the convex pieces and, for the
        capsules, in the object's true surface (its mesh or points). A power attempt watches the
        capsules and the palm box from its start, a precision attempt once it
        meets the criterion with a deeper shape
        (`synergrasp.planner.status.capsule_rows`), so that a deep shape is
        pushed out.
    start_distance : float
        Distance (mm) of a direction start from the object's centre
        (`start_configuration`).
    start_clearance : float
        A start is moved back until every fingertip (and, for a power start,
        every phalanx capsule) is this far (mm) from the object.
    seed_opening : float
        Precision seeds (`pinch_seeds`): the hand is opened this much (mm)
        wider than the pair of surface points it straddles, on each side.
    seed_retreat : float
        Precision seeds: the start is this far (mm) back along the palm
        normal from the pose straddling the pair.
    power_preshape, power_wide_preshape : (n_syn,) float or None
        Synergy values of the cupped and the wide power starts (see
        `power_schedule`); None: the mean pose, respectively cupped starts
        only.
    power_free_reach : bool
        Power grasps: while reaching (before the palm touches), the synergies
        are free for the first priority level (sQ, or the phalanges in the
        object while any is);
        False holds them at the pre-shape.
    power_sq_hold : float or None
        Power grasps: once g_sQ is below this, the sQ row asks only to keep
        its value, and the palm and contact rows get the step. None: the
        moving target all the way. (g_sQ in `steering_scale`: the object's
        torque scale but on a slender object.)
    executable_reach : bool
        Make the found grasp's executable reach
        (`synergrasp.planner.executable_reach`, with ``max_penetration`` as
        its tolerance): `PlanResult.path`, its ``clearance``, ``pregrasp`` and
        ``collision_free``. False: no path (the plan is a little faster).
    seed : int
        Seed of the random choices of a plan's starts (the surface samples of
        `pinch_seeds`): plans are deterministic.

    Raises
    ------
    ValueError
        On creation, for any field out of its range; the message names the
        field and its allowed range.

    Examples
    --------
    >>> PlannerOptions(time_limit=1.0).time_limit
    1.0
    >>> PlannerOptions(eps_c=-1)
    Traceback (most recent call last):
        ...
    ValueError: PlannerOptions.eps_c must be in (0, 50.0], got -1
    """

    eps_c: float = 5.0
    mu: float = 0.3
    edges: int = 8
    contact_target: float = 3.5
    contact_band: tuple = (1.0, 4.5)
    band_step: float = 1.0
    clearance: float = 0.5
    sq_step: float = 0.1
    smoothing: float = 0.1
    radius: float = 0.05
    radius_min: float = 0.002
    radius_max: float = 0.2
    stall_window: tuple = (20, 16)
    crawl_window: int = 30
    crawl_fraction: float = 0.05
    touch_window: int = 30
    iterations_per_attempt: int = 120
    restarts: int = 40
    max_iter: int = 1500
    time_limit: float | None = 10.0
    q_accept: float = -0.01
    q_margin: float = -0.03
    refine_iterations: int = 15
    max_penetration: float = 3.0
    start_distance: float = 150.0
    start_clearance: float = 5.0
    seed_opening: float = 15.0
    seed_retreat: float = 30.0
    power_preshape: tuple | None = (0.0, 1.0)
    power_wide_preshape: tuple | None = (-1.0, 1.0)
    power_free_reach: bool = True
    power_sq_hold: float | None = -0.05
    executable_reach: bool = True
    seed: int = 0

    def __post_init__(self):
        set_ = object.__setattr__
        set_(self, "eps_c", _number(self.eps_c, "eps_c", 0, 50.0, open_low=True))
        set_(self, "mu", _number(self.mu, "mu", 0, MAX_FRICTION, open_low=True))
        set_(self, "edges", _number(self.edges, "edges", 3, 64, integer=True))
        set_(self, "contact_target", _number(self.contact_target, "contact_target", 0, self.eps_c, open_high=True,
                                             high_from="eps_c"))  # (a row at eps_c is not in contact)
        band = _values(self.contact_band, "contact_band", f"(low, high) mm with 0 <= low < high <= eps_c ({self.eps_c:g})",
                       2, allow_none=False)
        if band is None or not 0 <= band[0] < band[1] <= self.eps_c:
            raise ValueError(f"PlannerOptions.contact_band must be (low, high) mm with 0 <= low < high <= eps_c "
                             f"({self.eps_c:g}), got {self.contact_band!r}")
        set_(self, "contact_band", band)
        set_(self, "clearance", _number(self.clearance, "clearance", 0, self.eps_c, high_from="eps_c"))
        set_(self, "band_step", _number(self.band_step, "band_step", 0, 50.0, open_low=True))
        set_(self, "sq_step", _number(self.sq_step, "sq_step", 0, 1.0, open_low=True))
        set_(self, "smoothing", _number(self.smoothing, "smoothing", 0, 1.0))
        set_(self, "radius_min", _number(self.radius_min, "radius_min", 0, 1.0, open_low=True))
        set_(self, "radius_max", _number(self.radius_max, "radius_max", self.radius_min, 10.0, low_from="radius_min"))
        set_(self, "radius", _number(self.radius, "radius", self.radius_min, self.radius_max, low_from="radius_min",
                                            high_from="radius_max"))
        window = self.stall_window
        if isinstance(window, np.ndarray) and window.ndim == 0:
            window = window.item()
        windows = tuple(window) if isinstance(window, (tuple, list, np.ndarray)) else (window,) * 2
        try:
            windows = tuple(_number(w, "stall_window", 1, None, integer=True) for w in windows)
        except ValueError:
            windows = ()
        if len(windows) != 2:
            raise ValueError(f"PlannerOptions.stall_window must be an integer in [1, inf) or a (precision, power) pair "
                             f"of them, got {self.stall_window!r}")
        set_(self, "stall_window", windows)
        for name, low in (("crawl_window", 0), ("touch_window", 0), ("iterations_per_attempt", 1),
                          ("max_iter", 1), ("refine_iterations", 0)):
            set_(self, name, _number(getattr(self, name), name, low, None, integer=True))
        set_(self, "restarts", _number(self.restarts, "restarts", 1, MAX_RESTARTS, integer=True))
        set_(self, "q_accept", _number(self.q_accept, "q_accept", -10.0, 0.0))
        set_(self, "q_margin", _number(self.q_margin, "q_margin", -10.0, self.q_accept, high_from="q_accept"))
        set_(self, "crawl_fraction", _number(self.crawl_fraction, "crawl_fraction", 0, 1.0))
        set_(self, "time_limit", _number(self.time_limit, "time_limit", 0, None, open_low=True, allow_none=True))
        for name in ("max_penetration", "start_clearance", "seed_opening", "seed_retreat"):
            set_(self, name, _number(getattr(self, name), name, 0, 1000.0))
        set_(self, "start_distance", _number(self.start_distance, "start_distance", 0, MAX_START_DISTANCE, open_low=True))
        for name in ("power_preshape", "power_wide_preshape"):
            set_(self, name, _values(getattr(self, name), name, "one finite value per synergy"))
        set_(self, "power_free_reach", _flag(self.power_free_reach, "power_free_reach"))
        set_(self, "executable_reach", _flag(self.executable_reach, "executable_reach"))
        set_(self, "power_sq_hold", _number(self.power_sq_hold, "power_sq_hold", -10.0, 10.0, allow_none=True))
        set_(self, "seed", _number(self.seed, "seed", 0, None, integer=True))


@dataclass(frozen=True)
class AnnealingOptions(_Fields):
    """Settings of ``plan(..., method="annealing")``, the eigengrasp simulated annealing baseline.

    The schedule's defaults are GraspIt!'s (``ANNEAL_DEFAULT`` of its
    simulated annealing, Ciocarlie and Allen): the temperature of step k is
    ``t0 * exp(-cooling * k ** (1 / dims))``, starting at ``k = k0``; a
    state of higher energy is accepted with probability
    ``exp(energy_scale * (E_old - E_new) / T)``. See
    `synergrasp.planner.annealing`.

    Attributes
    ----------
    steps : int
        Most annealing steps of a plan (neighbours accepted or refused).
    time_limit : float or None
        Most wall-clock seconds of a plan's search, compilation not counted
        (as for `PlannerOptions`); None: no limit. The status at every row of
        the returned trajectory (`with_history`, about 6 ms a row) and the
        executable reach are computed after it.
    t0, k0, cooling, dims : float, int, float, int
        The temperature schedule (GraspIt!: 1e6, 30000, 7, 8).
    energy_scale : float
        Factor of the energies in the acceptance probability (GraspIt!: 1e-6).
    neighbour_scale : float
        Factor of the temperature of the neighbour distribution (GraspIt!: 1).
    alignment : float
        Weight (mm) of ``1 - cos`` of the angle between a hand point's
        normal and the surface normal in the contact energy (GraspIt!: 50).
    position_margin : float
        The palm stays within the object's bounding box grown by this (mm).
    legal_tries : int
        Neighbours drawn per step until one leaves the hand out of the object
        (GraspIt!: 11; at most `MAX_LEGAL_TRIES`); a step without one is not
        counted.
    autograsp_energy : float or None
        A state the search moves to with an energy below this (mm) is
        auto-grasped: the hand closes (`synergrasp.planner.annealing.autograsp`)
        and the grasp is judged. None: 25 for precision grasps, 40 for power
        grasps (`synergrasp.planner.annealing.AUTOGRASP_ENERGY`; the mean over
        16 power points cannot fall as low as over 5 fingertips).
    autograsp_spacing : float
        ... unless it is closer than this, in normalised coordinates
        (position in object sizes, angles in rad, synergies), to a state
        auto-grasped before.
    close_step : float
        Synergy step (units of z2) of the auto-grasp's closing, from
        `MIN_CLOSE_STEP` to 1.
    eps_c, mu, edges, q_accept, max_penetration : float, float, int, float, float
        The acceptance, as `PlannerOptions`'s: the paper's criterion with
        ``eps_c``, ``mu`` and ``edges``, no phalanx deeper than
        ``max_penetration`` (mm), force-closed on the true surface with
        Q below ``q_accept``.
    start_distance, start_clearance : float
        The start, as `PlannerOptions`'s (`start_configuration`).
    executable_reach : bool
        Make the grasp's executable reach, as `PlannerOptions`'s.
    seed : int
        Seed of the random draws: plans are deterministic.

    Raises
    ------
    ValueError
        On creation, for any field out of its range; the message names the
        field and its allowed range.

    Examples
    --------
    >>> AnnealingOptions(steps=500).steps
    500
    >>> AnnealingOptions(cooling=0)
    Traceback (most recent call last):
        ...
    ValueError: AnnealingOptions.cooling must be in (0, 100.0], got 0
    """

    steps: int = 20000
    time_limit: float | None = 10.0
    t0: float = 1.0e6
    k0: int = 30000
    cooling: float = 7.0
    dims: int = 8
    energy_scale: float = 1.0e-6
    neighbour_scale: float = 1.0
    alignment: float = 50.0
    position_margin: float = 100.0
    legal_tries: int = 11
    autograsp_energy: float | None = None
    autograsp_spacing: float = 0.1
    close_step: float = 0.05
    eps_c: float = 5.0
    mu: float = 0.3
    edges: int = 8
    q_accept: float = -0.01
    max_penetration: float = 3.0
    start_distance: float = 150.0
    start_clearance: float = 5.0
    executable_reach: bool = True
    seed: int = 0

    def __post_init__(self):
        set_, own = object.__setattr__, "AnnealingOptions"

        def number(name, low, high, **kw):
            set_(self, name, _number(getattr(self, name), name, low, high, owner=own, **kw))

        for name in ("steps", "dims"):
            number(name, 1, None, integer=True)
        number("legal_tries", 1, MAX_LEGAL_TRIES, integer=True)
        for name in ("k0", "seed"):
            number(name, 0, None, integer=True)
        number("edges", 3, 64, integer=True)
        number("time_limit", 0, None, open_low=True, allow_none=True)
        for name, high in (("t0", 1e300), ("cooling", 100.0), ("energy_scale", 1e6), ("neighbour_scale", 1e6),
                           ("eps_c", 50.0)):
            number(name, 0, high, open_low=True)
        number("close_step", MIN_CLOSE_STEP, 1.0)
        for name in ("alignment", "position_margin", "autograsp_spacing", "max_penetration", "start_clearance"):
            number(name, 0, 1000.0)
        number("start_distance", 0, MAX_START_DISTANCE, open_low=True)
        number("autograsp_energy", 0, 1e6, open_low=True, allow_none=True)
        number("mu", 0, MAX_FRICTION, open_low=True)
        number("q_accept", -10.0, 0.0)
        set_(self, "executable_reach", _flag(self.executable_reach, "executable_reach", own))
