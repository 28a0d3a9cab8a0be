"""The validation protocol: every setting of the simulated hold test, and its two presets.

The documentation's "Physics validation" page explains each setting and why it has its value.
"""

from __future__ import annotations

import math
import numbers
import warnings
from dataclasses import asdict, dataclass, fields, replace

from ..planner.options import MAX_FRICTION

__all__ = ["Protocol", "PRESETS", "protocol", "DIRECTIONS"]

#: The six push directions, in the order of `Validation.displacement` (world axes).
DIRECTIONS = ("-x", "+x", "-y", "+y", "-z", "+z")

_REFERENCES = ("settled", "planned")
#: Time steps (s) coarser than this change verdicts (a 2 ms step changes some of the physics study's): a warning says so.
COARSE_TIMESTEP = 0.001
#: Most time steps a protocol may simulate (squeeze, settle and six pushes): about 15 s on one core.
MAX_STEPS = 5_000_000
#: MuJoCo's range for solimp's dmin and dmax (it clamps values outside it).
SOLIMP_RANGE = (0.0001, 0.9999)


@dataclass(frozen=True)
class Protocol:
    """Settings of the simulated hold test (SI units unless named otherwise).

    Attributes
    ----------
    name : str
        The preset these settings come from, and the settings changed from
        it (``"dexgraspbench (mu=0.3)"``); ``"custom"`` for changes to
        settings of another name.
    mu : float
        Sliding friction coefficient of every contact.
    torsional_friction : float
        Torsional friction coefficient (m); 0 gives point contacts with
        Coulomb friction (MuJoCo ``condim`` 3), the planner's contact model;
        > 0 soft-finger contacts (``condim`` 4).
    density : float
        Object density (kg/m^3); its mass is the density times the volume of
        its convex pieces. Ignored when ``mass`` is given.
    mass : float or None
        Object mass (kg) whatever its size, as the anchors set it.
    acceleration : float
        The push is ``mass * acceleration`` (N): the object's weight.
    push_time : float
        Duration of the push along each direction (s).
    max_displacement : float
        Largest displacement of the object's centre (mm) that still counts as held.
    max_rotation : float
        Largest rotation of the object (degrees) that still counts as held.
    max_penetration : float
        Deepest overlap of the hand and the object at the planned
        configuration (mm, as MuJoCo measures it) that is simulated; a deeper
        one fails without simulation.
    measure_from : {"settled", "planned"}
        Pose the push's displacement and rotation are measured from: the pose
        after the squeeze and settling, or the planned pose (so the shift the
        squeeze causes counts as well).
    squeeze : float
        How far the synergies close past the planned configuration: the mean
        distance (mm) the hand points in contact would move into the object.
    contact_distance : float
        Hand points closer than this to the object (mm, the planner's cP)
        are the contacts that set the squeeze direction.
    kp : float
        Stiffness of the joint position servos (N m/rad).
    joint_damping : float
        Viscous damping of each finger joint (N m s/rad).
    squeeze_time : float
        Time over which the servo targets move to the squeezed configuration (s).
    settle_time : float
        Time the grasp then settles before the pushes (s).
    settle_damping : float
        Time constant (s) of the viscous damping on the object while the
        fingers close and settle (removed for the pushes).
    max_speed : float
        An object faster than this (m/s) beyond what the push alone explains
        (``acceleration`` times the push's elapsed time) makes the run
        unstable.
    timestep : float
        Integration step (s).
    solref : (2,) float
        MuJoCo contact ``solref`` (time constant s, damping ratio).
    solimp : (3,) float
        MuJoCo contact ``solimp``.
    impratio : float
        MuJoCo's ratio of frictional to normal constraint impedance.
    noslip_iterations : int
        MuJoCo's noslip solver iterations.
    """

    name: str = "synergrasp"
    mu: float = 0.3
    torsional_friction: float = 0.001
    density: float = 1000.0
    mass: float | None = None
    acceleration: float = 9.81
    push_time: float = 2.0
    max_displacement: float = 10.0
    max_rotation: float = 10.0
    max_penetration: float = 5.0
    measure_from: str = "settled"
    squeeze: float = 10.0
    contact_distance: float = 5.0
    kp: float = 5.0
    joint_damping: float = 0.1
    squeeze_time: float = 0.2
    settle_time: float = 0.3
    settle_damping: float = 0.02
    max_speed: float = 5.0
    timestep: float = 0.001
    solref: tuple = (0.005, 1.0)
    solimp: tuple = (0.5, 0.99, 0.0001)
    impratio: float = 10.0
    noslip_iterations: int = 2

    def __post_init__(self):
        if not isinstance(self.name, str):
            raise ValueError(f"protocol setting name must be a string (the preset it derives from, or your own), "
                             f"got {self.name!r}")
        positive = ("mu", "density", "acceleration", "push_time", "max_displacement", "max_rotation",
                    "squeeze", "contact_distance", "kp", "squeeze_time", "max_speed", "timestep", "impratio")
        unbounded = ("max_displacement", "max_rotation", "max_speed", "max_penetration")  # inf: no such check
        for name in positive:
            value = getattr(self, name)
            if not _real(value) or not value > 0 or (name not in unbounded and value == math.inf):
                raise ValueError(f"protocol setting {name} must be a {'' if name in unbounded else 'finite '}number > 0, "
                                 f"got {value!r}")
        for name in ("torsional_friction", "joint_damping", "settle_time", "settle_damping", "max_penetration"):
            value = getattr(self, name)
            if not _real(value) or not value >= 0 or (name not in unbounded and value == math.inf):
                raise ValueError(f"protocol setting {name} must be a {'' if name in unbounded else 'finite '}number >= 0, "
                                 f"got {value!r}")
        if self.mu > MAX_FRICTION:
            raise ValueError(f"protocol setting mu must be at most {MAX_FRICTION:g} (as the planner's), got {self.mu!r}: "
                             "friction coefficients of real materials are below about 1.5")
        if self.mass is not None and (not _real(self.mass) or not 0 < self.mass < math.inf):
            raise ValueError(f"protocol setting mass must be None or a finite number > 0 (kg), got {self.mass!r}")
        if self.measure_from not in _REFERENCES:
            raise ValueError(f"protocol setting measure_from must be one of {_REFERENCES}, got {self.measure_from!r}")
        if (isinstance(self.noslip_iterations, bool) or not isinstance(self.noslip_iterations, numbers.Integral)
                or self.noslip_iterations < 0):
            raise ValueError(f"protocol setting noslip_iterations must be an int >= 0, got {self.noslip_iterations!r}")
        object.__setattr__(self, "noslip_iterations", int(self.noslip_iterations))
        if self.timestep > COARSE_TIMESTEP:
            warnings.warn(f"protocol timestep {self.timestep:g} s is coarser than {COARSE_TIMESTEP:g} s: verdicts change "
                          "with it there (the phalanges are light for the servos; 1 ms, the default, agrees with "
                          "0.5 ms, 2 ms changes some)", UserWarning, stacklevel=3)
        for name, size in (("solref", 2), ("solimp", 3)):
            value = getattr(self, name)
            if (not isinstance(value, (tuple, list)) or len(value) != size
                    or not all(_real(v) and math.isfinite(v) for v in value)):
                raise ValueError(f"protocol setting {name} must be {size} finite numbers, got {value!r}")
            object.__setattr__(self, name, tuple(float(v) for v in value))
        if self.timestep > self.push_time:
            raise ValueError(f"protocol setting timestep ({self.timestep} s) is longer than push_time ({self.push_time} s)")
        ref, imp = self.solref, self.solimp
        if not (ref[0] > 0 and ref[1] > 0 or ref[0] < 0 and ref[1] < 0):
            raise ValueError(f"protocol setting solref must be two numbers > 0 (MuJoCo's time constant in s and damping "
                             f"ratio) or two < 0 (stiffness and damping, negated), got {ref!r}: MuJoCo replaces a mixed "
                             "or zero pair by its default")
        if not (SOLIMP_RANGE[0] <= imp[0] <= SOLIMP_RANGE[1] and SOLIMP_RANGE[0] <= imp[1] <= SOLIMP_RANGE[1]
                and imp[2] > 0):
            raise ValueError(f"protocol setting solimp must be (dmin, dmax, width) with dmin and dmax in "
                             f"[{SOLIMP_RANGE[0]:g}, {SOLIMP_RANGE[1]:g}] and width > 0 (m), as MuJoCo reads them, "
                             f"got {imp!r}")
        steps = (self.squeeze_time + self.settle_time + len(DIRECTIONS) * self.push_time) / self.timestep
        if steps > MAX_STEPS:
            raise ValueError(f"this protocol simulates {steps:.3g} time steps (squeeze_time + settle_time + "
                             f"{len(DIRECTIONS)} x push_time, over timestep), more than the {MAX_STEPS:.0e} synergrasp "
                             "runs (about 15 s on one core; the default takes 12,500): use a coarser timestep or "
                             "shorter times")

    def to_dict(self) -> dict:
        """The settings as a JSON-serialisable dict (``Protocol(**d)`` rebuilds them)."""
        data = asdict(self)
        data["solref"], data["solimp"] = list(self.solref), list(self.solimp)
        return data


def check_setting_names(names, also=()):
    """Refuse names that are neither fields of `Protocol` nor in ``also`` (a caller's own keywords).

    Parameters
    ----------
    names : iterable of str
    also : tuple of str
        Further names the caller takes beside the protocol's settings.

    Raises
    ------
    ValueError
        Naming the unknown ones and listing the known.
    """
    known = {f.name for f in fields(Protocol)}
    unknown = set(names) - known - set(also)
    if unknown:
        raise ValueError(f"unknown protocol settings {sorted(unknown)}; settings are "
                         f"{sorted((known - {'name'}) | set(also))}")


def _real(value) -> bool:
    """A real number (not a bool, not NaN)."""
    return isinstance(value, numbers.Real) and not isinstance(value, bool) and not math.isnan(value)


#: The presets: the project's own (default) and settings like DexGraspBench's (BODex, ICRA 2025).
PRESETS = {
    "synergrasp": Protocol(),
    "dexgraspbench": Protocol(
        name="dexgraspbench", mu=0.6, torsional_friction=0.02, mass=0.1, acceleration=10.0,
        max_displacement=50.0, max_rotation=15.0, max_penetration=10.0, measure_from="planned",
    ),
}


def protocol(preset="synergrasp", **settings) -> Protocol:
    """A preset's settings, with some of them changed.

    Parameters
    ----------
    preset : str or Protocol
        A name in `PRESETS` (``"synergrasp"``, the default, or
        ``"dexgraspbench"``) or a `Protocol`.
    **settings
        Fields of `Protocol` to change; unless a name is given, the name
        becomes the preset's with the settings that differ from it.

    Returns
    -------
    Protocol

    Raises
    ------
    ValueError
        An unknown preset or setting, or a setting out of its range.

    Examples
    --------
    >>> protocol().mu, protocol("dexgraspbench").mu
    (0.3, 0.6)
    >>> p = protocol("dexgraspbench", mu=0.3)
    >>> p.name, p.mu, p.mass
    ('dexgraspbench (mu=0.3)', 0.3, 0.1)
    >>> protocol(p, mass=0.2).name, protocol(p, mu=0.6).name
    ('dexgraspbench (mass=0.2, mu=0.3)', 'dexgraspbench')
    """
    if isinstance(preset, Protocol):
        base = preset
    elif isinstance(preset, str) and preset in PRESETS:
        base = PRESETS[preset]
    else:
        raise ValueError(f"unknown protocol preset {preset!r}; presets are {sorted(PRESETS)} (or pass a Protocol)")
    check_setting_names(settings)
    if not settings:
        return base
    changed = replace(base, **settings)
    return changed if "name" in settings else replace(changed, name=_named(changed, base.name))


def _named(settings, name):
    """The name of ``settings`` made from those of the preset ``name`` (as `protocol` names them)."""
    preset = PRESETS.get(name.split(" (")[0])
    if preset is None:
        return "custom"
    changes = [f"{f.name}={getattr(settings, f.name)!r}" for f in fields(Protocol)
               if f.name != "name" and getattr(settings, f.name) != getattr(preset, f.name)]
    return preset.name + (f" ({', '.join(sorted(changes))})" if changes else "")
