"""The result of a reach-to-grasp plan, with a lossless JSON round trip."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from .._records import load_record, save_record

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
    status : (k+1, 6) or (k+1, 17) float
        Status vector g at every iteration: cP of each hand point (mm), then g_sQ.
    target : (6,) or (17,) float
        Target status ``[0 ... 0, -1]``.
    q_history : (k+1,) float
        g_Q (Q distance of the real contacts) at every iteration; NaN with
        fewer than two contacts.
    contact_points : (c, 3) float
        Final contacts on the object surface (mm).
    contact_normals : (c, 3) float
        Their unit normals, pointing into the object.
    contact_labels : list of str
        Which hand point each contact is (``"T0"``, ``"I2"``, ``"P"``, ...).
    penetration : float
        Deepest penetration of a hand segment into the object in the final pose (mm).
    time_s : float
        Wall-clock planning time (s).
    lp_solves : int
        LP solver calls made.
    backend : str
        LP backend used.
    grasp : str
        ``"precision"`` or ``"power"``.
    object_name : str
        Name of the grasped object.
    options : dict
        Planner settings used.
    attempts : list of dict
        Every attempt made, in order: ``start`` (its start configuration),
        ``standoff`` (mm), ``pass`` (1, or 2 for the second pass over the
        schedule), ``band`` (the contact band of a precision plan's second
        pass, else None), ``iterations`` and ``reason`` (why it ended).
        An attempt that stalls is followed by one from another approach
        direction; the trajectory is the last one's.
    pregrasp : (6 + n_syn,) float
        The first configuration of ``path``: the hand open and clear of the
        object (NaN when no grasp was found).
    path : (p, 6 + n_syn) float
        The executable reach to the final grasp (`executable_reach`):
        approach from ``pregrasp`` with the hand open, then close; dense
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
        ``depth`` and ``deepest`` (the deepest penetration along the path
        and its capsule or ``"palm"``), ``grasp_depth`` and
        ``grasp_shape`` (the grasp's own), ``source``, ``direction``,
        ``retreat``, ``opening``, ``candidates``, ``margin``,
        ``tolerance``, ``cpu_time``. Empty when no grasp was found.

    Examples
    --------
    >>> import synergrasp as sg
    >>> result = sg.plan(sg.objects.get("ellipsoid"), "precision")
    >>> result.success, result.grasp, result.contact_labels
    (True, 'precision', ['T0', 'I0', 'R0', 'L0'])
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
    options: dict = field(default_factory=dict)
    attempts: list = field(default_factory=list)
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
        """Iterations over all attempts."""
        return sum(a["iterations"] for a in self.attempts) if self.attempts else self.iterations

    @property
    def final_q(self) -> float:
        """g_Q of the final grasp."""
        return float(self.q_history[-1])

    @property
    def final_sq(self) -> float:
        """g_sQ of the final configuration."""
        return float(self.status[-1, -1])

    def save(self, path) -> Path:
        """Write the result as JSON (arrays as nested lists; floats round-trip exactly).

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
        ValueError
            If the file is not a saved PlanResult.

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
        data = load_record(cls, path, _FORMAT, _ARRAYS)
        data["path"] = data["path"].reshape(-1, data["u"].size)  # an empty path reads back as shape (0,)
        return cls(**data)
