"""The planner's settings, `PlannerOptions`, each checked when the options are made."""

from __future__ import annotations

import math
from dataclasses import dataclass, fields

import numpy as np

#: Grasp types the planner knows.
GRASPS = ("precision", "power")


def _number(value, name, low=None, high=None, *, integer=False, open_low=False, allow_none=False):
    """``value`` as a float (or int) within ``[low, high]`` (``(low, high]`` with ``open_low``), else a ValueError naming it."""
    if value is None and allow_none:
        return None
    kind = "an integer" if integer else "a number"
    span = f"{'(' if open_low else '['}{'-inf' if low is None else low}, {'inf' if high is None else high}]"
    ok_type = isinstance(value, (int, np.integer)) if integer else isinstance(value, (int, float, np.integer, np.floating))
    if isinstance(value, (bool, np.bool_)) or not ok_type or not math.isfinite(float(value)):
        none = " or None" if allow_none else ""
        raise ValueError(f"PlannerOptions.{name} must be {kind} in {span}{none}, got {value!r}")
    if (low is not None and (value < low or (open_low and value == low))) or (high is not None and value > high):
        raise ValueError(f"PlannerOptions.{name} must be in {span}, got {value!r}")
    return int(value) if integer else float(value)


def _flag(value, name):
    if not isinstance(value, (bool, np.bool_)):
        raise ValueError(f"PlannerOptions.{name} must be True or False, got {value!r}")
    return bool(value)


def _values(value, name, what, size=None):
    """Finite numbers (``size`` of them, if given) as a tuple, or None."""
    if value is None:
        return None
    try:
        arr = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        arr = None
    if arr is None or arr.ndim != 1 or not len(arr) or (size and len(arr) != size) or not np.all(np.isfinite(arr)):
        raise ValueError(f"PlannerOptions.{name} must be {what} or None, got {value!r}")
    return tuple(float(x) for x in arr)


@dataclass(frozen=True)
class PlannerOptions:
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
    stall_window : int
        An attempt whose merit (the contact errors plus g_sQ floored at -0.1)
        has not improved in this many iterations has stalled.
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
        Most attempts of a plan.
    max_iter : int
        Most iterations of a plan, over all its attempts.
    time_limit : float or None
        Most wall-clock seconds of a plan (checked every iteration); None: no limit.
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
        object allowed in a final grasp. An attempt that meets the criterion
        with a deeper shape goes on with the capsules and the palm box watched
        (`synergrasp.planner.status.capsule_rows`) until it is out.
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
        are free for the first priority level (sQ and penetrating phalanges);
        False holds them at the pre-shape.
    power_sq_hold : float or None
        Power grasps: once g_sQ is below this, the sQ row asks only to keep
        its value, and the palm and contact rows get the step. None: the
        moving target all the way.
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
    clearance: float = 0.5
    sq_step: float = 0.1
    smoothing: float = 0.1
    radius: float = 0.05
    radius_min: float = 0.002
    radius_max: float = 0.2
    stall_window: int = 12
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
        set_(self, "mu", _number(self.mu, "mu", 0, 10.0))
        set_(self, "edges", _number(self.edges, "edges", 3, 64, integer=True))
        set_(self, "contact_target", _number(self.contact_target, "contact_target", 0, self.eps_c))
        band = _values(self.contact_band, "contact_band", f"(low, high) mm with 0 <= low < high <= eps_c ({self.eps_c:g})", 2)
        if band is None or not 0 <= band[0] < band[1] <= self.eps_c:
            raise ValueError(f"PlannerOptions.contact_band must be (low, high) mm with 0 <= low < high <= eps_c "
                             f"({self.eps_c:g}), got {self.contact_band!r}")
        set_(self, "contact_band", band)
        set_(self, "clearance", _number(self.clearance, "clearance", 0, self.eps_c))
        set_(self, "sq_step", _number(self.sq_step, "sq_step", 0, 1.0, open_low=True))
        set_(self, "smoothing", _number(self.smoothing, "smoothing", 0, 1.0))
        set_(self, "radius_min", _number(self.radius_min, "radius_min", 0, 1.0, open_low=True))
        set_(self, "radius_max", _number(self.radius_max, "radius_max", self.radius_min, 10.0))
        set_(self, "radius", _number(self.radius, "radius", self.radius_min, self.radius_max))
        for name, low in (("stall_window", 1), ("crawl_window", 0), ("touch_window", 0), ("iterations_per_attempt", 1),
                          ("restarts", 1), ("max_iter", 1), ("refine_iterations", 0)):
            set_(self, name, _number(getattr(self, name), name, low, None, integer=True))
        set_(self, "q_accept", _number(self.q_accept, "q_accept", -10.0, 0.0))
        set_(self, "q_margin", _number(self.q_margin, "q_margin", -10.0, self.q_accept))
        set_(self, "crawl_fraction", _number(self.crawl_fraction, "crawl_fraction", 0, 1.0))
        set_(self, "time_limit", _number(self.time_limit, "time_limit", 0, None, open_low=True, allow_none=True))
        for name in ("max_penetration", "start_clearance", "seed_opening", "seed_retreat"):
            set_(self, name, _number(getattr(self, name), name, 0, 1000.0))
        set_(self, "start_distance", _number(self.start_distance, "start_distance", 0, 10000.0, open_low=True))
        for name in ("power_preshape", "power_wide_preshape"):
            set_(self, name, _values(getattr(self, name), name, "one finite value per synergy"))
        set_(self, "power_free_reach", _flag(self.power_free_reach, "power_free_reach"))
        set_(self, "executable_reach", _flag(self.executable_reach, "executable_reach"))
        set_(self, "power_sq_hold", _number(self.power_sq_hold, "power_sq_hold", -10.0, 10.0, allow_none=True))
        set_(self, "seed", _number(self.seed, "seed", 0, None, integer=True))

    @classmethod
    def names(cls) -> list[str]:
        """The option names, in order."""
        return [f.name for f in fields(cls)]

    def as_dict(self) -> dict:
        """The options as plain JSON values (tuples as lists)."""
        return {f.name: list(v) if isinstance(v := getattr(self, f.name), tuple) else v for f in fields(self)}
