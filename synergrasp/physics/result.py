"""The result of a physics validation, with a lossless JSON round trip."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from .._records import FieldChecks, load_record, save_record
from .protocol import DIRECTIONS, Protocol

__all__ = ["Validation", "OUTCOMES"]

#: What can happen to a grasp, in the order the protocol tests it.
OUTCOMES = ("held", "penetration", "unstable", "no contact", "slip", "rotation")

_FORMAT = "synergrasp.Validation/1"
_ARRAYS = {"u": (-1,), "squeeze_z": (-1,), "displacement": (-1,), "rotation": (-1,), "contact_points": (-1, 3),
           "contact_normals": (-1, 3), "contact_forces": (-1,), "object_pose": (-1,)}


@dataclass(frozen=True)
class Validation:
    """A grasp tested in MuJoCo: does the hand hold the object when it is pushed?

    Attributes
    ----------
    held : bool
        The object stayed within ``protocol.max_displacement`` and
        ``protocol.max_rotation`` under the push along each of the six
        directions, in a stable simulation.
    outcome : str
        One of `OUTCOMES`: ``"held"``; ``"penetration"`` (the hand overlaps
        the object deeper than ``protocol.max_penetration`` at the planned
        configuration, not simulated); ``"unstable"`` (NaN, MuJoCo's
        instability warning or an explosion); ``"no contact"`` (the hand does
        not touch the object after the squeeze); ``"slip"`` (the object moved
        too far under a push); ``"rotation"`` (it turned too far, without
        moving too far).
    reason : str
        The outcome in words, with the numbers.
    displacement : (6,) float
        Largest displacement of the object's centre (mm) during the push
        along each direction of `DIRECTIONS` (``-x, +x, -y, +y, -z, +z``,
        world axes), from the pose ``protocol.measure_from``. A push stops
        once a threshold is crossed. NaN where not simulated.
    rotation : (6,) float
        Largest rotation of the object (degrees), likewise.
    settle_displacement, settle_rotation : float
        How far the squeeze and settling moved (mm) and turned (degrees) the
        object from its planned pose (NaN if not simulated).
    initial_penetration : float
        Deepest overlap of the hand and the object at the planned
        configuration, as MuJoCo measures it (mm, 0 if none).
    penetration_body : str
        The hand geom of that overlap (``"palm"``, ``"T3"``...), "" if none.
    contact_bodies : list of str
        Hand geom of each contact MuJoCo found after settling.
    contact_pieces : list of int
        The object's convex piece of each contact.
    contact_points : (c, 3) float
        Contact positions (mm, world frame, the object at its settled pose).
    contact_normals : (c, 3) float
        Unit contact normals pointing into the object.
    contact_forces : (c,) float
        Normal force of each contact (N).
    object_mass : float
        Mass of the simulated object (kg).
    object_pose : (7,) float
        Settled pose of the object: its centre (mm) and orientation
        quaternion ``w, x, y, z`` (NaN if not simulated).
    joint_angles : dict of str to float
        Settled angles of the hand's hinges (rad).
    u : (6 + n_syn,) float
        The configuration simulated (the palm moved back by ``retreat``).
    squeeze_z : (n_syn,) float
        The synergy targets of the squeeze.
    retreat : float
        How far (mm) the palm was moved back along its normal after the
        squeeze was set (0, or the distance of a negative control).
    protocol : dict
        The `Protocol` used (`Protocol.to_dict`).
    object_name, hand_name : str
    hand : str
        The hand's `SynergyHand.identity` (its name and a digest of its
        definition); empty in a file saved before validations recorded it.
    cpu_time : float
        CPU time of the validation (s).
    mujoco_version : str
    """

    held: bool
    outcome: str
    reason: str
    displacement: np.ndarray
    rotation: np.ndarray
    settle_displacement: float
    settle_rotation: float
    initial_penetration: float
    penetration_body: str
    contact_bodies: list
    contact_pieces: list
    contact_points: np.ndarray
    contact_normals: np.ndarray
    contact_forces: np.ndarray
    object_mass: float
    object_pose: np.ndarray
    joint_angles: dict
    u: np.ndarray
    squeeze_z: np.ndarray
    retreat: float
    protocol: dict
    object_name: str = ""
    hand_name: str = ""
    hand: str = ""
    cpu_time: float = 0.0
    mujoco_version: str = ""
    directions: tuple = field(default=DIRECTIONS)

    @property
    def held_per_direction(self) -> np.ndarray:
        """(6,) bool : the push along each direction stayed within both thresholds."""
        p = self.settings
        with np.errstate(invalid="ignore"):
            return (self.displacement < p.max_displacement) & (self.rotation < p.max_rotation)

    @property
    def settings(self) -> Protocol:
        """The protocol as a `Protocol`."""
        return Protocol(**self.protocol)

    @property
    def grip_force(self) -> float:
        """Sum of the contact normal forces after settling (N)."""
        return float(np.sum(self.contact_forces))

    def save(self, path) -> Path:
        """Write the validation as JSON (floats round-trip exactly).

        Parameters
        ----------
        path : str or Path
            Output file, conventionally ``*.json``.

        Returns
        -------
        Path
            ``path``.
        """
        return save_record(self, path, _FORMAT, _ARRAYS)

    @classmethod
    def load(cls, path) -> "Validation":
        """Read a validation written by `save`.

        Parameters
        ----------
        path : str or Path

        Returns
        -------
        Validation
            Equal to the saved one.

        Raises
        ------
        ValueError
            If the file is not a saved Validation.
        """
        data = load_record(cls, path, _FORMAT, _ARRAYS, optional=("hand",),
                           missing="a validation an older synergrasp saved lacks the fields added since: validate again")
        return cls(**_checked(data, path))


def _checked(data: dict, path) -> dict:
    """The fields of a loaded Validation (`load_record`), each checked; errors name the file and the field."""
    checks = FieldChecks(data, path)
    out = {"held": checks.flag("held")}
    if data["outcome"] not in OUTCOMES:
        checks.fail("outcome", f"one of {OUTCOMES}")
    if (data["outcome"] == "held") != out["held"]:
        checks.fail("outcome", f"'held' exactly when field 'held' is true (it is {str(out['held']).lower()})")
    out["outcome"] = data["outcome"]
    for name in ("reason", "penetration_body", "object_name", "hand_name", "mujoco_version") + (
            ("hand",) if "hand" in data else ()):
        out[name] = checks.text(name)
    directions = checks.strings("directions", "push directions such as \"-x\"")
    out["directions"] = tuple(directions)
    for name in ("displacement", "rotation"):
        out[name] = data[name]
        if out[name].shape != (len(directions),) or (out[name] < 0).any():
            checks.fail(name, f"{len(directions)} numbers >= 0 or NaN, one per push direction")
    for name in ("settle_displacement", "settle_rotation"):
        out[name] = checks.number(name, 0.0, nan=True)
    for name in ("initial_penetration", "retreat", "cpu_time"):
        out[name] = checks.number(name, 0.0)
    out["object_mass"] = checks.number("object_mass", 0.0)
    bodies, pieces = checks.strings("contact_bodies", "hand geom names"), data["contact_pieces"]
    if not isinstance(pieces, list) or len(pieces) != len(bodies) or not all(
            isinstance(k, int) and not isinstance(k, bool) and k >= 0 for k in pieces):
        checks.fail("contact_pieces", f"{len(bodies)} integers >= 0, one per contact body")
    out["contact_bodies"], out["contact_pieces"] = bodies, pieces
    for name in ("contact_points", "contact_normals", "contact_forces"):
        out[name] = data[name]
        if len(out[name]) != len(bodies):
            checks.fail(name, f"{len(bodies)} rows, one per contact body")
    out["object_pose"] = data["object_pose"]
    if out["object_pose"].shape != (7,):
        checks.fail("object_pose", "7 numbers (the centre and a quaternion w, x, y, z)")
    angles = data["joint_angles"]
    if not isinstance(angles, dict) or not all(isinstance(v, (int, float)) and not isinstance(v, bool)
                                               for v in angles.values()):
        checks.fail("joint_angles", "an object of hinge names and angles (rad)")
    out["joint_angles"] = angles
    out["u"], out["squeeze_z"] = checks.array("u", 1), checks.array("squeeze_z", 1)
    if len(out["u"]) != 6 + len(out["squeeze_z"]) or not len(out["squeeze_z"]):
        checks.fail("u", f"a configuration of 6 + len(squeeze_z) = {6 + len(out['squeeze_z'])} numbers, with "
                         "squeeze_z one number per synergy")
    if not isinstance(data["protocol"], dict):
        checks.fail("protocol", "an object of protocol settings")
    try:
        Protocol(**data["protocol"])
    except (TypeError, ValueError) as exc:
        raise ValueError(f"{path}: field 'protocol' is not a valid protocol: {exc}") from exc
    out["protocol"] = data["protocol"]
    return {name: out[name] for name in data}
