"""The result of a reach-to-grasp plan, with a lossless JSON round trip."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from .._records import FieldChecks, holds_bool, load_record, save_record
from ..hand import IDENTITY, POINT_KINDS
from .reach import SOURCES as REACH_SOURCES

_FORMAT = "synergrasp.PlanResult/1"
_ARRAYS = {"u": (-1,), "trajectory": None, "status": None, "target": (-1,), "q_history": (-1,),
           "contact_points": (-1, 3), "contact_normals": (-1, 3), "pregrasp": (-1,), "path": None, "clearance": (-1,)}


@dataclass
class PlanResult:
    """A planned reach-to-grasp motion and its final grasp.

    Attributes
    ----------
    success : bool
        The paper's stop criterion was met (and the final grasp verified).
    reason : str
        Why the iteration stopped, in words.
    iterations : int
        Number k of iterations (steps) of the returned reach (the last attempt).
    u : (6 + n_syn,) float
        Final configuration ``[px, py, pz, phi1, phi2, phi3, z1, z2]`` (mm, rad; 8 entries
        for the paper's two-synergy hand).
    trajectory : (k+1, 6 + n_syn) float
        Configuration at every iteration of the planner's search, start
        included. It is how the grasp was found, not a motion to execute:
        the iteration watches a few points per phalanx, and phalanges may
        pass through the object between them. The motion to execute is
        ``path``.
    status : (k+1, n+1) float
        Status vector g at every iteration: the cP rows (mm; 16 for the paper's
        hand, see `synergrasp.planner.status.status_rows`), then g_sQ.
    target : (n+1,) float
        Target status ``[0 ... 0, -1]``.
    q_history : (k+1,) float
        g_Q (Q distance of the real contacts) at every iteration; NaN
        without contacts (one or two contacts are never force-closed: their
        g_Q is > 0).
    contact_points : (c, 3) float
        Final contacts (mm): the points of the object's convex pieces the
        hand points are nearest to (within a few mm of the true surface where
        the pieces stick out of it; an accepted grasp's contacts moved to the
        true surface are within ``eps_c`` of it, and their Q distance is
        `surface_q`).
    contact_normals : (c, 3) float
        Their unit normals on the pieces, pointing into the object.
    contact_labels : list of str
        Which hand point each contact is (``"T0"``, ``"I2"``, ``"P"``, ...).
    penetration : float
        Deepest penetration of a hand segment (phalanx capsule or palm box)
        into the object's convex pieces in the final pose (mm; python-fcl),
        raised to its depth in the true mesh where that is deeper than
        ``max_penetration`` (an accepted grasp's capsules near the limit are
        measured there too). Where the pieces stick out of the mesh it can
        read more than the depth in the mesh.
    time_s : float
        Wall-clock time of the search (s): the attempts and, with
        ``validate``, their simulations; not the executable reach nor an
        annealing plan's status history, computed after it. Numba's
        compilation in a process's first plan after an install is in it
        (the time limit does not count it).
    lp_solves : int
        LP solver calls made.
    backend : str
        LP backend used.
    grasp : str
        ``"precision"`` or ``"power"``.
    object_name : str
        Name of the grasped object.
    hand : str
        The planning hand's `SynergyHand.identity` (its name and a digest of
        its definition); empty in a file saved before results recorded it.
    options : dict
        Planner settings used.
    attempts : list of dict
        Every attempt made, in order: ``start`` (its start configuration),
        ``kind`` (how the start was placed, `synergrasp.planner.Start`) and
        its placement (``thumb``, ``finger`` and ``width`` of a pinch seed,
        ``direction`` and ``turn`` (rad, about the approach) of a direction start), ``outcome`` (the name of its
        `synergrasp.planner.Outcome`, lower case), ``reason`` (the outcome
        in words), ``iterations`` and ``status`` (its trajectory's steps, to
        the grasp it kept if any, and its status at each), ``iterations_run``
        (those and the refining iterations after the kept grasp, which count
        in ``max_iter``; gradient planner); with ``plan(..., validate=True)`` an accepted grasp's
        ``held`` and ``physics`` (the validation's reason). The trajectory is the successful
        attempt's, or the last one's.
    surface_q : float
        Q distance of the final contacts moved to the object's true surface,
        with its normals there (`synergrasp.planner.stop.surface_check`): the
        grasp's margin as accepted; NaN without a grasp.
    held : bool or None
        With ``plan(..., validate=True)``: whether the returned grasp held in
        the physics validation (`synergrasp.validate`); None when not tested.
    pregrasp : (6 + n_syn,) float
        The first configuration of ``path``: the hand open and clear of the
        object (NaN when no grasp was found).
    path : (p, 6 + n_syn) float
        The executable reach to the final grasp (`executable_reach`):
        approach from ``pregrasp`` with the hand open, then close (or,
        ``reach["source"] == "closing approach"``, close while
        approaching); dense
        enough that between two rows (a straight line in ``u``) no part of
        the hand crosses the object unseen. Empty when no grasp was found.
    clearance : (p,) float
        Smallest signed distance (mm) of the phalanx capsules and the palm
        box to the object at each row of ``path``; negative inside.
    collision_free : bool
        No row of ``path`` is deeper in the object than the planner's
        ``max_penetration`` (False when no grasp was found).
    reach : dict
        How ``path`` was made and checked (`Reach.summary`): ``reason``,
        ``collision_free``, ``depth``, ``deepest`` and ``deepest_row`` (the
        deepest penetration along the path, its capsule or ``"palm"`` and
        its row), ``grasp_depth`` and ``grasp_shape`` (the grasp's own),
        ``source``, ``direction``, ``retreat``, ``candidates``, ``margin``,
        ``tolerance``, ``cpu_time``. Empty when no grasp was found.

    Examples
    --------
    >>> import synergrasp as sg
    >>> result = sg.plan(sg.objects.get("ellipsoid"), "precision")
    >>> result.success, result.grasp, "T0" in result.contact_labels
    (True, 'precision', True)
    >>> result.trajectory.shape == (result.iterations + 1, 8)
    True
    >>> bool(result.final_q < 0)         # the final contacts are force-closed
    True
    >>> result.collision_free, bool((result.path[-1] == result.u).all())   # the reach to execute
    (True, True)
    >>> bool(result.clearance[0] >= 10.0) and bool(result.clearance.min() >= -3.0)   # mm
    True
    """

    success: bool
    reason: str
    iterations: int
    u: np.ndarray
    trajectory: np.ndarray
    status: np.ndarray
    target: np.ndarray
    q_history: np.ndarray
    contact_points: np.ndarray
    contact_normals: np.ndarray
    contact_labels: list
    penetration: float
    time_s: float
    lp_solves: int
    backend: str
    grasp: str = "precision"
    object_name: str = ""
    hand: str = ""
    options: dict = field(default_factory=dict)
    attempts: list = field(default_factory=list)
    surface_q: float = math.nan
    held: bool | None = None
    pregrasp: np.ndarray | None = None
    path: np.ndarray | None = None
    clearance: np.ndarray | None = None
    collision_free: bool = False
    reach: dict = field(default_factory=dict)

    def __post_init__(self):
        n = np.asarray(self.u).size
        if self.pregrasp is None:  # no executable reach (no grasp, or a result built without one)
            self.pregrasp = np.full(n, np.nan)
        if self.path is None:
            self.path = np.zeros((0, n))
        if self.clearance is None:
            self.clearance = np.zeros(0)

    @property
    def total_iterations(self) -> int:
        """Iterations run over all attempts: their trajectories' steps and the refining iterations after a kept grasp
        (``iterations_run`` of an attempt's record, where it has one)."""
        return sum(a.get("iterations_run", a["iterations"]) for a in self.attempts) if self.attempts else self.iterations

    @property
    def final_q(self) -> float:
        """g_Q of the final grasp."""
        return float(self.q_history[-1])

    @property
    def final_sq(self) -> float:
        """g_sQ of the final configuration (torques by `steering_scale`: L, but in a power plan of a slender object)."""
        return float(self.status[-1, -1])

    def save(self, path) -> Path:
        """Write the result as JSON (arrays as nested lists; floats round-trip exactly).

        The file is written atomically: to a temporary file in the same folder,
        then renamed, so an interrupted or failed write leaves no partial file.

        Parameters
        ----------
        path : str or Path
            Output file, conventionally ``*.json``.

        Returns
        -------
        Path
            ``path``.

        Examples
        --------
        A short (capped, unsuccessful) plan, saved and read back:

        >>> import tempfile
        >>> from pathlib import Path
        >>> import synergrasp as sg
        >>> result = sg.plan(sg.objects.get("ellipsoid"), "precision", max_iter=3)
        >>> with tempfile.TemporaryDirectory() as folder:
        ...     path = result.save(Path(folder) / "plan.json")
        ...     again = sg.PlanResult.load(path)
        >>> again.success, again.iterations, again.reason == result.reason
        (False, 3, True)
        >>> bool((again.trajectory == result.trajectory).all())   # floats round-trip exactly
        True
        """
        return save_record(self, path, _FORMAT, _ARRAYS)

    @classmethod
    def load(cls, path) -> "PlanResult":
        """Read a result written by `save`.

        Parameters
        ----------
        path : str or Path
            A file written by `save`.

        Returns
        -------
        PlanResult
            Equal to the saved one (arrays as float ndarrays).

        Raises
        ------
        FileNotFoundError
            If the file does not exist.
        ValueError
            If the file is not a saved PlanResult, or a field is missing or
            has the wrong type, shape or value; the message names the file
            and the field.

        Examples
        --------
        >>> import tempfile
        >>> from pathlib import Path
        >>> import synergrasp as sg
        >>> result = sg.plan(sg.objects.get("ellipsoid"), "precision", max_iter=3)
        >>> with tempfile.TemporaryDirectory() as folder:
        ...     again = sg.PlanResult.load(result.save(Path(folder) / "plan.json"))
        >>> again.u.tolist() == result.u.tolist(), again.object_name
        (True, 'ellipsoid 30/40/50')
        """
        data = load_record(cls, path, _FORMAT, _ARRAYS, optional=("hand", "held", "surface_q"),
                           missing="a file edited by hand, or one an older synergrasp saved before they were "
                                   "added (then plan it again)")
        return cls(**_validated(data, path))


def _validated(data: dict, path) -> dict:
    """The fields of a loaded PlanResult (`load_record`), each checked; errors name the file and the field."""

    checks = FieldChecks(data, path)
    fail, array, integer, number, text = checks.fail, checks.array, checks.integer, checks.number, checks.text

    out = {"success": checks.flag("success")}
    for name in ("reason", "backend", "object_name") + (("hand",) if "hand" in data else ()):
        out[name] = text(name)
    if out.get("hand") and not IDENTITY.fullmatch(out["hand"]):
        fail("hand", "the planning hand's identity, 'NAME sha256:<16 hex digits>' (SynergyHand.identity), or empty")
    if data["grasp"] not in POINT_KINDS:
        fail("grasp", " or ".join(map(repr, POINT_KINDS)))
    out["grasp"] = data["grasp"]
    k = out["iterations"] = integer("iterations")
    out["lp_solves"] = integer("lp_solves")
    out["penetration"] = number("penetration", 0.0)
    out["time_s"] = number("time_s", 0.0)
    if "held" in data:
        if data["held"] is not None and not isinstance(data["held"], bool):
            fail("held", "true, false or null")
        out["held"] = data["held"]
    if "surface_q" in data:
        value = data["surface_q"]
        if value is not None and (isinstance(value, bool) or not isinstance(value, (int, float)) or math.isinf(value)):
            fail("surface_q", "a number, or NaN without a grasp")
        out["surface_q"] = math.nan if value is None else float(value)
    u = out["u"] = array("u", 1)
    if len(u) < 7:
        fail("u", "a configuration of 6 + n_syn >= 7 numbers")
    out["trajectory"] = array("trajectory", 2)
    if out["trajectory"].shape != (k + 1, len(u)):
        rows = (f" (its rows of {out['trajectory'].shape[1]} numbers, u of {len(u)})"
                if len(out["trajectory"]) and out["trajectory"].shape[1] != len(u) else "")
        fail("trajectory", f"of shape (iterations + 1, len(u)) = ({k + 1}, {len(u)}), not {out['trajectory'].shape}{rows}")
    if not np.array_equal(out["trajectory"][-1], u):
        fail("u", "the last row of trajectory (the configuration the plan reached; edited by hand?)")
    out["target"] = array("target", 1)
    m = len(out["target"])
    if m < 2:
        fail("target", "the target of the status rows (at least a contact row and the quality row)")
    out["status"] = array("status", 2)
    if out["status"].shape != (k + 1, m):
        fail("status", f"of shape (iterations + 1, len(target)) = ({k + 1}, {m}), not {out['status'].shape}")
    out["q_history"] = array("q_history", 1, finite=False)  # NaN: no contact
    if out["q_history"].shape != (k + 1,) or np.isinf(out["q_history"]).any():
        fail("q_history", f"{k + 1} numbers (iterations + 1), NaN where there was no contact")
    labels = out["contact_labels"] = checks.strings("contact_labels", "strings")
    for name in ("contact_points", "contact_normals"):
        out[name] = array(name, 2)
        if out[name].shape != (len(labels), 3):
            fail(name, f"of shape ({len(labels)}, 3), one row per contact label")
    if np.abs(np.linalg.norm(out["contact_normals"], axis=1) - 1.0).max(initial=0.0) > 1e-6:
        fail("contact_normals", "unit vectors")
    if out["success"] and len(labels) < 2:
        fail("contact_labels", "two contacts or more for a grasp (success is true)")
    if not isinstance(data["options"], dict):
        fail("options", "an object of planner settings")
    out["options"] = data["options"]
    attempts = data["attempts"]
    if not isinstance(attempts, list):
        fail("attempts", "a list of attempts")
    for i, attempt in enumerate(attempts):
        where = f"attempts[{i}]"
        if not isinstance(attempt, dict):
            raise ValueError(f"{path}: field '{where}' must be an object, got {type(attempt).__name__}")
        iterations = attempt.get("iterations")
        if isinstance(iterations, bool) or not isinstance(iterations, int) or iterations < 0:
            raise ValueError(f"{path}: field '{where}.iterations' must be an integer >= 0, got {iterations!r}")
        run = attempt.get("iterations_run", iterations)
        if isinstance(run, bool) or not isinstance(run, int) or run < iterations:
            raise ValueError(f"{path}: field '{where}.iterations_run' must be an integer >= its iterations "
                             f"({iterations}), got {run!r}")
        if not isinstance(attempt.get("reason"), str):
            raise ValueError(f"{path}: field '{where}.reason' must be a string, got {attempt.get('reason')!r}")
        if "status" in attempt:
            try:
                trace = None if holds_bool(attempt["status"]) else np.asarray(attempt["status"], dtype=float)
            except (TypeError, ValueError):
                trace = None
            if trace is None or trace.shape != (iterations + 1, m):
                raise ValueError(f"{path}: field '{where}.status' must be an array of shape "
                                 f"(iterations + 1, len(target)) = ({iterations + 1}, {m})")
    out["attempts"] = attempts
    # the executable reach: empty without a grasp
    pregrasp = out["pregrasp"] = array("pregrasp", 1, finite=False)  # NaN: no grasp
    if pregrasp.shape != u.shape or np.isinf(pregrasp).any():
        fail("pregrasp", f"{len(u)} numbers (a configuration like u), NaN when no grasp was found")
    reach = array("path", 2) if np.size(data["path"]) else np.zeros((0, len(u)))
    if reach.shape[1:] != (len(u),):
        fail("path", f"an array of shape (p, len(u) = {len(u)})")
    out["path"] = reach
    out["clearance"] = array("clearance", 1)
    if out["clearance"].shape != (len(reach),):
        fail("clearance", f"{len(reach)} numbers, one per row of path")
    out["collision_free"] = checks.flag("collision_free")
    # (a reach that was not collision-free was cut short of u before 2026-11-30)
    if len(reach) and not (np.array_equal(reach[0], pregrasp)
                           and (np.array_equal(reach[-1], u) or not out["collision_free"])):
        fail("path", "the reach from pregrasp (its first row) to u (its last row; edited by hand?)")
    if not isinstance(data["reach"], dict):
        fail("reach", "an object (the summary of the executable reach)")
    summary = out["reach"] = data["reach"]
    if len(reach) and summary.get("source", "approach") not in REACH_SOURCES:
        fail("reach", f"a summary whose source is one of {list(REACH_SOURCES)}, not {summary.get('source')!r}")
    tolerance = summary.get("tolerance")
    if len(reach) and out["collision_free"] and isinstance(tolerance, (int, float)) \
            and out["clearance"].min() < -tolerance:
        fail("collision_free", f"false: the clearance along path goes to {out['clearance'].min():.3g} mm, deeper than "
             f"its tolerance of {tolerance:g} mm (edited by hand?)")
    return {name: out[name] for name in data}
