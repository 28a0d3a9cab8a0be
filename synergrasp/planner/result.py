"""The result of a reach-to-grasp plan, with a lossless JSON round trip."""

from __future__ import annotations

import json
from dataclasses import asdict, dataclass, field, fields
from pathlib import Path

import numpy as np

_ARRAYS = ("u", "trajectory", "status", "target", "q_history", "contact_points", "contact_normals")


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
        Configuration at every iteration, start included.
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
        data = asdict(self)
        for name in _ARRAYS:
            data[name] = np.asarray(data[name]).tolist()
        data["format"] = "synergrasp.PlanResult/1"
        path = Path(path)
        path.write_text(json.dumps(data, indent=1))
        return path

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
        path = Path(path)
        try:
            data = json.loads(path.read_text())
        except (OSError, json.JSONDecodeError) as exc:
            raise ValueError(f"cannot read a PlanResult from {path}: {exc}") from exc
        if not isinstance(data, dict) or data.pop("format", None) != "synergrasp.PlanResult/1":
            raise ValueError(f"{path} is not a saved synergrasp PlanResult")
        names = {f.name for f in fields(cls)}
        missing = names - set(data)
        if missing:
            raise ValueError(f"{path} lacks the fields {sorted(missing)}")
        for name in _ARRAYS:
            data[name] = np.asarray(data[name], dtype=float)
        data["contact_points"] = data["contact_points"].reshape(-1, 3)
        data["contact_normals"] = data["contact_normals"].reshape(-1, 3)
        return cls(**{k: data[k] for k in names})
