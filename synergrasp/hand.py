"""The synergy-controlled hand: data file, kinematics, hand points and their Jacobians.

The hand of the paper (Sec. 3.1, Tables 1 and 2) has five serial chains (T, I, M, R, L)
on a rigid palm. Its actuated joints form the pose vector ``Psi``; every joint angle is an
affine function of ``Psi`` (the couplings) and ``Psi`` an affine function of the synergy
variables ``z`` (Eq. 11):

    Psi = mean_pose + synergies @ z          (n_act,)
    q   = coupling @ Psi + offset            (n_joints,)

Everything that describes a hand lives in a JSON file (see the documentation's "Hand file
format" page); the paper's hand ships with the package as ``data/hands/paper_hand.json``,
loaded by `SynergyHand.default`.

Frames and conventions, in millimetres and radians: the palm frame has its origin at the
palm centre, +z along the palm normal (the side the palm faces, towards a grasped object),
+y towards the fingers, +x towards the thumb. A configuration is
``u = [px, py, pz, phi1, phi2, phi3, z1, ..., z_nsyn]``: the palm frame's origin ``p`` in
the world, its orientation as intrinsic X-Y-Z Euler angles, and the synergy variables. A
point with palm coordinates ``x`` is at ``p + R @ x`` in the world, where
``R = Rx(phi1) @ Ry(phi2) @ Rz(phi3)`` (`rotation_xyz`; the same matrix as
``scipy.spatial.transform.Rotation.from_euler("XYZ", phi)``). The palm normal in the world
is ``R[:, 2]``.
"""

from __future__ import annotations

import copy
import difflib
import hashlib
import itertools
import json
import math
import re
import warnings
from dataclasses import dataclass
from functools import cache
from importlib import resources

import numpy as np

from ._checks import as_path, as_points, as_vector, integer, numeric
from ._jit import kernel

__all__ = ["SynergyHand", "HandGeometry", "rotation_xyz", "POINT_KINDS", "IDENTITY", "grasp_kind"]

#: The grasp types: each has its hand points, status rows, stop criterion and planner starts.
POINT_KINDS = ("precision", "power")
#: Joint names a hand file may not use: the physics model (`synergrasp.physics`) names its palm and
#: object bodies so.
RESERVED_NAMES = ("palm", "object")
#: Most points of a grid over the synergy box (`SynergyHand.synergy_grid`): the paper's hand's
#: 41 x 41 grid fits, a hand with many synergies gets fewer values per synergy.
SYNERGY_GRID_POINTS = 2000
#: Most rows `SynergyHand.synergy_grid` builds (``max_points``'s bound).
MAX_GRID_POINTS = 10_000_000
#: Largest length in a hand file (mm): link lengths, the palm's size, and how far a finger's base or the palm's
#: points lie from the palm frame (a hand's parts are within its span; larger values are another unit or a typo).
MAX_HAND_LENGTH = 2000.0
#: Smallest largest side of the palm (mm): a hand file in metres or centimetres has a palm of a few hundredths of a mm
#: or a few mm (the paper hand's is 95 mm).
MIN_PALM_SIDE = 20.0
#: Largest angle in a hand file (rad): a mean pose, a joint offset, a base rotation, and the travel of a joint over a
#: synergy's range (its synergy entry times the range's largest bound). Larger ones are degrees, or a typo.
MAX_ANGLE = 4.0 * np.pi
#: Largest coupling coefficient of a joint to an actuated joint.
MAX_COUPLING = 10.0
#: How far (synergy units) a synergy value may lie outside its limits and still be a pose of the hand (round-off).
LIMIT_TOLERANCE = 1e-9

_DEFAULT_FILE = "paper_hand.json"
#: Skin points of a segment, for the status of a grasp of each kind: fractions along its axis, and
#: angles round it from the palmar side. A power grasp wraps whole phalanges round the object, where
#: a thin wall (a cup's or a bell's lip) can pass through a phalanx between three places along it.
SKIN_ALONG = {"precision": (0.0, 0.5, 1.0), "power": (0.0, 0.25, 0.5, 0.75, 1.0)}
SKIN_AROUND = (-math.pi / 2, 0.0, math.pi / 2)
#: Palm skin points besides the palm point P: the corners and edge midpoints of the palm box's
#: front face, as fractions of its half extents along the palm frame's x and y.
PALM_SKIN = tuple((sx, sy) for sx in (-1.0, 0.0, 1.0) for sy in (-1.0, 0.0, 1.0) if (sx, sy) != (0.0, 0.0))


def _numbers(value) -> bool:
    """Whether ``value`` is a number or (nested) lists or arrays of numbers: no strings, no booleans."""
    if isinstance(value, np.ndarray):
        return value.dtype.kind in "iuf"
    if isinstance(value, (list, tuple)):
        return all(_numbers(v) for v in value)
    return isinstance(value, (int, float, np.integer, np.floating)) and not isinstance(value, (bool, np.bool_))


def grasp_kind(kind, name="kind") -> str:
    """``kind``, a grasp type of `POINT_KINDS` ("precision" or "power"); ValueError naming ``name`` otherwise.

    Parameters
    ----------
    kind : str
        The value to check.
    name : str
        The argument's name, for the message.

    Returns
    -------
    str
        ``kind``.

    Raises
    ------
    ValueError
        If ``kind`` is not one of `POINT_KINDS`.

    Examples
    --------
    >>> grasp_kind("power")
    'power'
    >>> grasp_kind("pinch", "grasp")
    Traceback (most recent call last):
        ...
    ValueError: grasp must be 'precision' or 'power', got 'pinch'
    """
    if not isinstance(kind, str) or kind not in POINT_KINDS:
        raise ValueError(f"{name} must be {' or '.join(map(repr, POINT_KINDS))}, got {kind!r}")
    return kind


def rotation_xyz(phi):
    """Rotation matrix of intrinsic X-Y-Z Euler angles.

    Parameters
    ----------
    phi : (3,) float
        Angles (rad) about x, then the new y, then the newest z.

    Returns
    -------
    (3, 3) float
        ``Rx(phi[0]) @ Ry(phi[1]) @ Rz(phi[2])``.

    Examples
    --------
    The same matrix as scipy's intrinsic ``"XYZ"`` Euler angles:

    >>> from scipy.spatial.transform import Rotation
    >>> R = rotation_xyz([0.1, 0.2, 0.3])
    >>> bool(np.allclose(R, Rotation.from_euler("XYZ", [0.1, 0.2, 0.3]).as_matrix()))
    True
    """
    c1, c2, c3 = (math.cos(a) for a in phi)
    s1, s2, s3 = (math.sin(a) for a in phi)
    return np.array([
        [c2 * c3, -c2 * s3, s2],
        [c1 * s3 + s1 * s2 * c3, c1 * c3 - s1 * s2 * s3, -s1 * c2],
        [s1 * s3 - c1 * s2 * c3, s1 * c3 + c1 * s2 * s3, c1 * c2],
    ])


def _skew(v):
    """Cross-product matrices of vectors, ``(..., 3) -> (..., 3, 3)``."""
    k = np.zeros(v.shape[:-1] + (3, 3))
    k[..., 0, 1], k[..., 0, 2] = -v[..., 2], v[..., 1]
    k[..., 1, 0], k[..., 1, 2] = v[..., 2], -v[..., 0]
    k[..., 2, 0], k[..., 2, 1] = -v[..., 1], v[..., 0]
    return k


@dataclass(frozen=True)
class HandGeometry:
    """Collision and rendering geometry of a hand at one configuration (world frame).

    Attributes
    ----------
    capsules : (k, 2, 3) float
        End points of the phalanx capsules, one per segment of positive length, in the
        order of the power points (T1, T2, T3, I1, ..., L3 for the paper's hand).
    radius : float
        Radius of every capsule (the file's ``finger_radius``).
    labels : list of str
        Name of each capsule (``"T1"``, ...).
    palm_center : (3,) float
        Centre of the palm box.
    palm_axes : (3, 3) float
        Columns are the box's axes (the palm frame's x, y, z) in the world.
    palm_half_extents : (3,) float
        Half sizes of the box along its axes.
    """

    capsules: np.ndarray
    radius: float
    labels: list
    palm_center: np.ndarray
    palm_axes: np.ndarray
    palm_half_extents: np.ndarray

    @property
    def palm_corners(self):
        """(8, 3) float : corners of the palm box, bit ``i`` of the index = sign along axis ``i``."""
        signs = np.array([[(i >> b & 1) * 2 - 1 for b in range(3)] for i in range(8)])
        return self.palm_center + (signs * self.palm_half_extents) @ self.palm_axes.T


class _Spec:
    """Typed access to the raw JSON dictionary; every error names the file and the field."""

    def __init__(self, source):
        self.source = source

    def fail(self, field, problem):
        raise ValueError(f"{self.source}: field '{field}' {problem}")

    def get(self, data, key, field):
        if not isinstance(data, dict) or key not in data:
            self.fail(field, "is missing")
        return data[key]

    def array(self, data, key, field, shape):
        value = self.get(data, key, field)
        if not _numbers(value):  # numpy would read "8" and true as numbers
            self.fail(field, f"must be numbers of shape {shape}, got {value!r}")
        try:
            arr = np.array(value, dtype=float)
        except OverflowError:  # an integer beyond the float range
            self.fail(field, "must be finite")
        except (TypeError, ValueError):
            self.fail(field, f"must be numbers of shape {shape}")
        if arr.ndim != len(shape) or any(n is not None and n != m for n, m in zip(shape, arr.shape)):
            self.fail(field, f"must have shape {shape}, got {arr.shape}")
        if not np.all(np.isfinite(arr)):
            self.fail(field, "must be finite")
        return arr

    def lengths(self, arr, field):
        """``arr`` (mm), refused beyond `MAX_HAND_LENGTH` in size."""
        if np.abs(arr).max(initial=0.0) > MAX_HAND_LENGTH:
            self.fail(field, f"must be at most {MAX_HAND_LENGTH:g} mm in size (a hand's span), got "
                             f"{np.abs(arr).max():.3g}: lengths are in mm")
        return arr

    def angles(self, arr, field):
        """``arr`` (rad), refused beyond `MAX_ANGLE` in size (degrees, most likely)."""
        if np.abs(arr).max(initial=0.0) > MAX_ANGLE:
            self.fail(field, f"must be at most {MAX_ANGLE:.3g} rad in size (two turns), got {np.abs(arr).max():.3g}: "
                             "angles are in radians (degrees?)")
        return arr

    def name_list(self, data, key, field):
        value = self.get(data, key, field)
        if (not isinstance(value, list) or not value
                or not all(isinstance(v, str) and v for v in value) or len(set(value)) != len(value)):
            self.fail(field, "must be a non-empty list of distinct names")
        return value

    def known(self, data, keys, field):
        """Refuse a key that is not one of ``keys`` (a misspelt optional field would be silently ignored)."""
        for key in data if isinstance(data, dict) else ():
            if key not in keys:
                close = difflib.get_close_matches(str(key), keys, n=1)
                where = f"{field}.{key}" if field else str(key)
                self.fail(where, "is not a field of a hand file" + (f" (did you mean '{close[0]}'?)" if close else
                                                                     f"; fields here are {sorted(keys)}"))

    def items(self, data, key, field):
        value = self.get(data, key, field)
        if not isinstance(value, list) or not value:
            self.fail(field, "must be a non-empty list")
        return value


#: The form of a hand's identity (`SynergyHand.identity`, `_digest`): its name and 16 hex digits of a digest.
IDENTITY = re.compile(r".+ sha256:[0-9a-f]{16}")


def _digest(name, data):
    """``"name sha256:<16 hex digits>"`` of a hand definition (`IDENTITY`)."""
    text = json.dumps(data, sort_keys=True, separators=(",", ":"))
    return f"{name} sha256:{hashlib.sha256(text.encode()).hexdigest()[:16]}"


def _numbers_as_floats(data):
    """A hand definition with every number a float and -0.0 as 0.0 (booleans and text kept)."""
    if isinstance(data, dict):
        return {key: _numbers_as_floats(value) for key, value in data.items()}
    if isinstance(data, list):
        return [_numbers_as_floats(value) for value in data]
    if isinstance(data, (int, float)) and not isinstance(data, bool):
        return float(data) + 0.0
    return data


def _plain(data):
    """A deep copy of a hand definition with numpy arrays and numbers as JSON's lists and numbers."""
    if isinstance(data, dict):
        return {key: _plain(value) for key, value in data.items()}
    if isinstance(data, (list, tuple)):
        return [_plain(value) for value in data]
    if isinstance(data, (np.ndarray, np.generic)):
        return data.tolist()
    return copy.deepcopy(data)


class SynergyHand:
    """A synergy-controlled hand: kinematics, hand points and analytic Jacobians.

    Build it with `default` (the paper's hand) or `from_file`.

    Attributes
    ----------
    name : str
        The hand's name from its file.
    n_syn : int
        Number of synergies; a configuration ``u`` has ``6 + n_syn`` entries.
    actuated_names : list of str
        Names of the actuated joints, the entries of the pose ``Psi``.
    mean_pose : (n_act,) float
        ``Psi`` at ``z = 0`` (rad).
    synergies : (n_act, n_syn) float
        Synergy matrix, one column per synergy (rad per unit of ``z``).
    synergy_limits : (n_syn, 2) float
        Lower and upper bound of each synergy variable, for the planner to clip to. The
        kinematics accept any ``z``.
    joint_names : list of str
        All joints, fixed ones included, chain by chain from the palm outwards (the order of
        `joint_angles`; 16 for the paper's hand: its 11 moving joints and T_ip and the
        4 dips, fixed at 20 degrees).
    finger_names : list of str
        Name of each chain (``"T", "I", "M", "R", "L"``).
    finger_radius : float
        Radius of the phalanx capsules (mm).
    contact_offset : float
        Distance (mm) of the finger points from the segment axes, towards the palmar side
        (the side a segment moves to when its joint flexes): with the finger radius, the
        points lie on the skin where a phalanx touches an object. 0 puts them on the axes.
    palm_point : (3,) float
        The power grasp's palm point P in the palm frame.
    palm_half_extents : (3,) float
        Half sizes of the palm box along the palm frame's axes.
    source : str
        The file the hand was read from.

    Examples
    --------
    >>> import numpy as np
    >>> from synergrasp import SynergyHand
    >>> hand = SynergyHand.default()
    >>> hand.n_syn, hand.n_u, hand.finger_names
    (2, 8, ['T', 'I', 'M', 'R', 'L'])
    >>> hand.pose(np.zeros(hand.n_u)).tolist() == hand.mean_pose.tolist()   # z = 0: the mean pose
    True
    """

    def __init__(self, data, source="<dict>"):
        """Build a hand from a parsed hand-file dictionary (see `from_file`)."""
        spec = _Spec(source)
        self._data = _plain(data)
        self.source = str(source)
        if not isinstance(data, dict):
            spec.fail("<root>", "must be a JSON object")
        spec.known(data, ("name", "description", "actuated", "mean_pose", "synergies", "synergy_limits",
                          "finger_radius", "contact_offset", "palm", "fingers"), "")
        name = spec.get(data, "name", "name")
        if not isinstance(name, str) or not name:
            spec.fail("name", f"must be a non-empty string, got {name!r}")
        self.name = name
        self.actuated_names = spec.name_list(data, "actuated", "actuated")
        n_act = len(self.actuated_names)
        self.mean_pose = spec.array(data, "mean_pose", "mean_pose", (n_act,))
        self.synergies = spec.array(data, "synergies", "synergies", (n_act, None))
        self.n_syn = self.synergies.shape[1]
        if self.n_syn < 1:
            spec.fail("synergies", "must have at least one column")
        if not self.synergies.any():
            spec.fail("synergies", "are all zero: no synergy moves a joint, so the hand cannot close")
        self.synergy_limits = spec.array(data, "synergy_limits", "synergy_limits", (self.n_syn, 2))
        if np.any(self.synergy_limits[:, 0] >= self.synergy_limits[:, 1]):
            spec.fail("synergy_limits", "must have lower < upper in every row")
        spec.angles(self.mean_pose, "mean_pose")
        travel = np.abs(self.synergies) * np.abs(self.synergy_limits).max(axis=1)  # (n_act, n_syn), rad
        if travel.max() > MAX_ANGLE:
            i, j = np.unravel_index(np.argmax(travel), travel.shape)
            spec.fail(f"synergies[{i}][{j}]", f"moves joint {self.actuated_names[i]!r} by {travel[i, j]:.3g} rad over "
                      f"synergy {j + 1}'s range {self.synergy_limits[j].tolist()}, more than {MAX_ANGLE:.3g} rad (two "
                      "turns): synergy entries are radians per unit of the synergy")
        self.finger_radius = float(spec.array(data, "finger_radius", "finger_radius", ()))
        if self.finger_radius <= 0:
            spec.fail("finger_radius", "must be positive")
        self.contact_offset = float(spec.array(data, "contact_offset", "contact_offset", ())) if "contact_offset" in data else 0.0
        if not 0 <= self.contact_offset <= self.finger_radius:
            spec.fail("contact_offset", f"must be between 0 (the segment axes) and finger_radius, {self.finger_radius:g} "
                      f"(the skin), got {self.contact_offset:g}: farther, the hand points would be in the air")
        if not isinstance(data.get("description", ""), str):
            spec.fail("description", f"must be a string, got {data['description']!r}")
        palm = spec.get(data, "palm", "palm")
        spec.known(palm, ("center", "size", "point"), "palm")
        self._palm_center = spec.lengths(spec.array(palm, "center", "palm.center", (3,)), "palm.center")
        self.palm_half_extents = 0.5 * spec.lengths(spec.array(palm, "size", "palm.size", (3,)), "palm.size")
        if np.any(self.palm_half_extents <= 0):
            spec.fail("palm.size", "must be positive")
        if 2.0 * self.palm_half_extents.max() < MIN_PALM_SIDE:
            spec.fail("palm.size", f"is at most {2.0 * self.palm_half_extents.max():.3g} mm, less than {MIN_PALM_SIDE:g} mm: "
                      "a hand file's lengths are in mm (is it in metres or centimetres?)")
        self.palm_point = spec.lengths(spec.array(palm, "point", "palm.point", (3,)), "palm.point")
        if self.finger_radius > 2.0 * self.palm_half_extents.max():
            spec.fail("finger_radius", f"must be smaller than the palm's largest side, "
                      f"{2.0 * self.palm_half_extents.max():g} mm, got {self.finger_radius:g}: a finger thicker "
                      "than the palm is not a hand (another unit, such as um for mm?)")
        face = self._palm_center[2] + self.palm_half_extents[2]
        self._palm_skin = np.array([[self._palm_center[0] + sx * self.palm_half_extents[0],
                                     self._palm_center[1] + sy * self.palm_half_extents[1], face] for sx, sy in PALM_SKIN])
        self._load_chains(spec, spec.items(data, "fingers", "fingers"))
        self._precompute()

    def _load_chains(self, spec, fingers):
        """Read the chains into arrays padded to the longest chain (pads: zero-length joints)."""
        act_index = {n: i for i, n in enumerate(self.actuated_names)}
        chains = []
        for f, finger in enumerate(fingers):
            fld = f"fingers[{f}]"
            spec.known(finger, ("name", "base", "joints"), fld)
            fname = spec.get(finger, "name", f"{fld}.name")
            if not isinstance(fname, str) or not fname:
                spec.fail(f"{fld}.name", "must be a non-empty string")
            base = spec.get(finger, "base", f"{fld}.base")
            spec.known(base, ("position", "rotation_xyz"), f"{fld}.base")
            joints = []
            for j, joint in enumerate(spec.items(finger, "joints", f"{fld}.joints")):
                jf = f"{fld}.joints[{j}]"
                spec.known(joint, ("name", "axis", "length", "coupling", "offset"), jf)
                jname = spec.get(joint, "name", f"{jf}.name")
                if not isinstance(jname, str) or not jname:
                    spec.fail(f"{jf}.name", "must be a non-empty string")
                axis = spec.array(joint, "axis", f"{jf}.axis", (3,))
                if np.abs(axis).max() > 1e150:  # its length would overflow
                    spec.fail(f"{jf}.axis", f"must be a direction of moderate length (its length overflows), got "
                              f"{axis.tolist()}: a unit vector will do")
                if np.linalg.norm(axis) < 1e-9:
                    spec.fail(f"{jf}.axis", "must be a non-zero vector")
                length = float(spec.lengths(spec.array(joint, "length", f"{jf}.length", ()), f"{jf}.length"))
                if length < 0:
                    spec.fail(f"{jf}.length", "must be >= 0")
                if length > 0 and np.linalg.norm(np.cross(axis / np.linalg.norm(axis), [0.0, 1.0, 0.0])) < 1e-6:
                    spec.fail(f"{jf}.axis", "must not be along the link (the joint frame's y axis) for a link of "
                                            "positive length: the link's palmar side, where it flexes to, is undefined")
                coupling = spec.get(joint, "coupling", f"{jf}.coupling")
                if not isinstance(coupling, dict):
                    spec.fail(f"{jf}.coupling", "must be an object {actuated joint name: coefficient}")
                row = np.zeros(len(act_index))
                for key in coupling:
                    if key not in act_index:
                        spec.fail(f"{jf}.coupling.{key}", f"is not an actuated joint {self.actuated_names}")
                    row[act_index[key]] = spec.array(coupling, key, f"{jf}.coupling.{key}", ())
                    if abs(row[act_index[key]]) > MAX_COUPLING:
                        spec.fail(f"{jf}.coupling.{key}", f"must be at most {MAX_COUPLING:g} in size (the joint turns by "
                                  f"it times the actuated joint's angle), got {row[act_index[key]]:g}")
                offset = float(spec.angles(spec.array(joint, "offset", f"{jf}.offset", ()), f"{jf}.offset"))
                joints.append((jname, axis / np.linalg.norm(axis), length, row, offset))
            if not any(j[2] > 0 for j in joints):
                spec.fail(f"{fld}.joints", "must contain a segment of positive length")
            chains.append((fname,
                           spec.lengths(spec.array(base, "position", f"{fld}.base.position", (3,)), f"{fld}.base.position"),
                           rotation_xyz(spec.angles(spec.array(base, "rotation_xyz", f"{fld}.base.rotation_xyz", (3,)),
                                                    f"{fld}.base.rotation_xyz")),
                           joints))
        self.finger_names = [c[0] for c in chains]
        self.joint_names = [j[0] for c in chains for j in c[3]]
        for field, names in (("fingers[].name", self.finger_names), ("fingers[].joints[].name", self.joint_names)):
            if len(set(names)) != len(names):
                spec.fail(field, "must be unique")
        reserved = sorted(set(self.joint_names) & set(RESERVED_NAMES))
        if reserved:
            spec.fail("fingers[].joints[].name", f"must not be {' or '.join(map(repr, RESERVED_NAMES))} (the physics "
                                                 f"model's palm and object bodies), got {reserved}: rename them")

        n_c, n_j = len(chains), max(len(c[3]) for c in chains)
        self._base_pos = np.array([c[1] for c in chains])                  # (n_c, 3)
        self._base_rot = np.array([c[2] for c in chains])                  # (n_c, 3, 3)
        self._axes = np.tile([1.0, 0.0, 0.0], (n_c, n_j, 1))               # (n_c, n_j, 3)
        self._lengths = np.zeros((n_c, n_j))
        self._coupling = np.zeros((n_c, n_j, len(act_index)))
        self._offset = np.zeros((n_c, n_j))
        self._real = np.zeros((n_c, n_j), bool)                            # not padding
        for c, (_, _, _, joints) in enumerate(chains):
            for j, (_, axis, length, row, offset) in enumerate(joints):
                self._axes[c, j], self._lengths[c, j] = axis, length
                self._coupling[c, j], self._offset[c, j] = row, offset
                self._real[c, j] = True

    def _precompute(self):
        """Constant arrays for the vectorised kinematics: point selectors and Jacobian masks."""
        n_c, n_j = self._lengths.shape
        self._k1 = _skew(self._axes)                                       # Rodrigues terms
        self._k2 = self._k1 @ self._k1
        # joint angles are affine in z: q = q_z @ z + q_0, shapes (n_c, n_j, n_syn) and (n_c, n_j);
        # padding joints have zero rows, so they never move and never enter a Jacobian
        self._q_z = self._coupling @ self.synergies
        self._q_0 = self._coupling @ self.mean_pose + self._offset

        # Nodes: each chain's base and the end of each of its links, then the palm point and the palm skin.
        palm = n_c * (n_j + 1)  # the palm point's node, then the palm skin's
        self._palm_nodes = np.vstack([self.palm_point, self._palm_skin])  # in the palm frame
        node = np.arange(palm).reshape(n_c, n_j + 1)
        segments = [(c, k + 1, j) for c in range(n_c) for k, j in enumerate(np.flatnonzero(self._lengths[c] > 0))]
        self._segment_nodes = np.array([[node[c, j], node[c, j + 1]] for c, _, j in segments])
        points = {  # kind -> (label, {node: weight}, chain, number of joints upstream)
            "precision": [(f"{f}0", {node[c, -1]: 1.0}, c, n_j) for c, f in enumerate(self.finger_names)],
            "power": [(f"{self.finger_names[c]}{k}", {node[c, j]: 0.5, node[c, j + 1]: 0.5}, c, j + 1)
                      for c, k, j in segments]
                     + [("P", {palm: 1.0}, 0, 0)],
            # the two ends of every capsule (on the axis), for collision avoidance
            "_capsules": [(f"{self.finger_names[c]}{k}{end}", {node[c, j + e]: 1.0}, c, j + 1)
                          for c, k, j in segments for e, end in ((0, "a"), (1, "b"))],
        }
        for grasp, along in SKIN_ALONG.items():  # points on the skin of every segment, then of the palm
            points[f"_skin_{grasp}"] = (
                [(f"{self.finger_names[c]}{k}", {node[c, j]: 1.0 - t, node[c, j + 1]: t}, c, j + 1)
                 for c, k, j in segments for t in along for _ in SKIN_AROUND]
                + [("P", {palm + i: 1.0}, 0, 0) for i in range(1 + len(PALM_SKIN))])
        # the palmar side of link j: where its far end moves when joint j flexes, axis_j x e_y
        palmar = np.cross(self._axes, [0.0, 1.0, 0.0])
        palmar /= np.maximum(np.linalg.norm(palmar, axis=-1, keepdims=True), 1e-12)
        last = [int(np.flatnonzero(self._lengths[c] > 0)[-1]) for c in range(n_c)]
        links = {  # kind -> per point (chain, link) carrying the palmar offset, None for the palm point
            "precision": [(c, last[c]) for c in range(n_c)],
            "power": [(c, j) for c, _, j in segments] + [None],
            "_capsules": [None] * (2 * len(segments)),
        }
        for grasp, along in SKIN_ALONG.items():
            links[f"_skin_{grasp}"] = ([(c, j, around) for c, _, j in segments for _ in along for around in SKIN_AROUND]
                                       + [None] * (1 + len(PALM_SKIN)))
        self._kinds = {}
        for kind, rows in points.items():
            nodes = np.zeros((len(rows), 2), dtype=np.int64)   # each point: up to two nodes and their weights
            weights = np.zeros((len(rows), 2))
            upstream = np.zeros((len(rows), 2), dtype=np.int64)  # its chain and its number of joints upstream
            for i, (_, w, c, n_up) in enumerate(rows):
                nodes[i, :len(w)], weights[i, :len(w)] = list(w), list(w.values())
                upstream[i] = c, n_up
            frame = np.zeros(len(rows), dtype=np.int64)  # index into the (n_c * (n_j + 1)) link frames
            offset = np.zeros((len(rows), 3))       # in that frame
            for i, link in enumerate(links[kind]):
                if link is not None:
                    c, j = link[:2]
                    frame[i] = c * (n_j + 1) + j + 1
                    # fingertips touch with the front of the pad, halfway round the tip's cap
                    side = palmar[c, j] + (np.array([0.0, 1.0, 0.0]) if kind == "precision" else 0.0)
                    if len(link) == 3:  # round the segment from the palmar side towards its joint axis
                        side = np.cos(link[2]) * palmar[c, j] + np.sin(link[2]) * self._axes[c, j]
                    offset[i] = self.contact_offset * side / np.linalg.norm(side)
            self._kinds[kind] = (nodes, weights, [r[0] for r in rows], upstream, frame, offset)
        # a grasp's status needs its points and its skin: one pass of the kinematics for the two
        for grasp in POINT_KINDS:
            self._kinds[f"_{grasp}_and_skin"] = tuple(
                a + b if isinstance(a, list) else np.concatenate([a, b])
                for a, b in zip(self._kinds[grasp], self._kinds[f"_skin_{grasp}"])
            )

    # ------------------------------------------------------------------ construction

    @classmethod
    def default(cls):
        """The paper's hand, from the package data file ``data/hands/paper_hand.json``.

        The file is read and the hand built once per process; each call returns
        its own copy (a tenth of the time of building it), so a caller may change
        the hand it gets without affecting later calls.

        Returns
        -------
        SynergyHand

        Examples
        --------
        >>> hand = SynergyHand.default()
        >>> hand
        SynergyHand('paper_hand', fingers=['T', 'I', 'M', 'R', 'L'], n_act=6, n_syn=2)
        >>> hand.u_labels
        ['px', 'py', 'pz', 'phi1', 'phi2', 'phi3', 'z1', 'z2']
        """
        return copy.deepcopy(cls._built_default())

    @classmethod
    @cache
    def _built_default(cls):
        res = resources.files("synergrasp").joinpath("data", "hands", _DEFAULT_FILE)
        return cls(json.loads(res.read_text(encoding="utf-8")), source=_DEFAULT_FILE)

    @classmethod
    def from_file(cls, path):
        """Load a hand from a JSON hand file.

        The format is described on the documentation's "Hand file format" page.

        Parameters
        ----------
        path : str or pathlib.Path

        Returns
        -------
        SynergyHand

        Raises
        ------
        FileNotFoundError
            If the file does not exist.
        ValueError
            If the file is not valid JSON or a field is missing or malformed; the message
            names the file and the field.

        Examples
        --------
        Save a modified copy of the paper's hand and read it back:

        >>> import json, tempfile
        >>> from pathlib import Path
        >>> data = SynergyHand.default().to_dict()
        >>> data["name"] = "thick_fingers"
        >>> data["finger_radius"] = 10.0
        >>> with tempfile.TemporaryDirectory() as folder:
        ...     path = Path(folder) / "thick_fingers.json"
        ...     _ = path.write_text(json.dumps(data))
        ...     hand = SynergyHand.from_file(path)
        >>> hand.name, hand.finger_radius
        ('thick_fingers', 10.0)
        """
        path = as_path(path, "the hand file")
        if path.is_dir():
            raise FileNotFoundError(f"'{path}' is a folder, not a hand file: give the hand's .json file")
        if not path.is_file():
            raise FileNotFoundError(f"hand file not found: '{path}'")
        try:
            data = json.loads(path.read_text(encoding="utf-8"))
        except (json.JSONDecodeError, UnicodeDecodeError) as err:
            raise ValueError(f"{path}: not valid JSON ({err})") from None
        return cls(data, source=path)

    @property
    def identity(self) -> str:
        """str : The hand's name and a digest of its definition (``"name sha256:<16 hex digits>"``).

        Two hands share it exactly when their definitions (`to_dict`) are equal, however their
        numbers are written (``46`` and ``46.0``, ``-0.0`` and ``0.0``); a `PlanResult` records
        the identity of the hand it was planned with.

        Examples
        --------
        >>> hand = SynergyHand.default()
        >>> data = hand.to_dict()
        >>> data["finger_radius"] = int(data["finger_radius"])
        >>> hand.identity.startswith(hand.name + " sha256:"), SynergyHand(data).identity == hand.identity
        (True, True)
        """
        return _digest(self.name, _numbers_as_floats(self._data))

    def made(self, identity: str) -> bool:
        """Whether a record of the hand ``identity`` (`PlanResult.hand`, `Validation.hand`) is this hand's.

        An empty identity, of a file saved before records kept it, is anyone's; so is the digest of
        the definition as its file wrote its numbers, which records kept before `identity`
        normalised them.

        Examples
        --------
        >>> hand = SynergyHand.default()
        >>> hand.made(hand.identity), hand.made(""), hand.made("other sha256:0123456789abcdef")
        (True, True, False)
        """
        return not identity or identity in (self.identity, _digest(self.name, self._data))

    def to_dict(self):
        """A deep copy of the hand's definition, as read from its file (JSON-serialisable).

        Returns
        -------
        dict
            The fields of the hand file; edit it and pass it to ``SynergyHand(data)`` or save
            it as JSON for `from_file`.
        """
        return copy.deepcopy(self._data)

    # ------------------------------------------------------------------ configuration

    @property
    def n_u(self):
        """int : length of a configuration ``u`` (``6 + n_syn``)."""
        return 6 + self.n_syn

    @property
    def u_labels(self):
        """list of str : names of the entries of ``u``."""
        return ["px", "py", "pz", "phi1", "phi2", "phi3"] + [f"z{i + 1}" for i in range(self.n_syn)]

    def check_u(self, u):
        """``u`` as a finite float vector of this hand's size, or a clear error.

        Parameters
        ----------
        u : (6 + n_syn,) array_like

        Returns
        -------
        (6 + n_syn,) float

        Raises
        ------
        TypeError
            If ``u`` is not numeric.
        ValueError
            If it has another shape, or a NaN or inf entry.
        """
        try:
            u = numeric(u)  # (a float array as it is; text, booleans and complex numbers refused)
        except (TypeError, ValueError, OverflowError):
            raise TypeError(f"u must be a numeric vector of {self.n_u} numbers [p (3), phi (3), z ({self.n_syn})], "
                            f"got {type(u).__name__}") from None
        if u.shape != (self.n_u,):
            raise ValueError(f"u must have shape ({self.n_u},) = [p (3), phi (3), z ({self.n_syn})], "
                             f"got {u.shape}")
        if not np.isfinite(u).all():
            raise ValueError(f"u contains NaN or inf, got {u}")
        return u

    def check_synergies(self, z, what):
        """Refuse synergy values outside the hand's limits (by more than `LIMIT_TOLERANCE`).

        Parameters
        ----------
        z : (n_syn,) or (k, n_syn) float
            Finite values (one pose or k).
        what : str
            What they are, for the message (e.g. "the configuration's synergies").

        Raises
        ------
        TypeError
            If ``z`` is not numeric.
        ValueError
            If it has another shape, a NaN, or a value outside its synergy's limits (the message gives the first
            such pose).
        """
        z = as_points(z, what, dim=self.n_syn) if np.ndim(z) == 2 else as_vector(z, what, self.n_syn)
        lo, hi = self.synergy_limits[:, 0], self.synergy_limits[:, 1]
        outside = (z < lo - LIMIT_TOLERANCE) | (z > hi + LIMIT_TOLERANCE)
        if outside.any():
            first = z if z.ndim == 1 else z[np.flatnonzero(outside.any(axis=1))[0]]
            raise ValueError(f"{what} {first.tolist()} lie outside the hand's limits {self.synergy_limits.tolist()}: "
                             "the hand cannot take that pose (clip them into the limits, as plan() does with a start "
                             "outside them)")

    def clip_synergies(self, z, what):
        """Synergy values within their limits: ``z`` clipped, with a warning naming ``what`` if any lies outside.

        Parameters
        ----------
        z : (n_syn,) float
        what : str
            What the values are, for the warning (e.g. "u0's synergies").

        Returns
        -------
        (n_syn,) float
            A new array.

        Raises
        ------
        TypeError, ValueError
            If ``z`` is not a finite numeric vector of ``n_syn`` values.

        Warns
        -----
        UserWarning
            If a value lies outside its synergy's limits.
        """
        z = as_vector(z, what, self.n_syn)
        lo, hi = self.synergy_limits[:, 0], self.synergy_limits[:, 1]
        clipped = np.clip(z, lo, hi)
        if ((z < lo) | (z > hi)).any():
            warnings.warn(f"{what} {z.tolist()} are outside the synergy limits {self.synergy_limits.tolist()} of "
                          f"{self.name}: clipped to {clipped.tolist()}", UserWarning, stacklevel=4)  # plan's caller
        return clipped

    def _check_kind(self, kind):
        if not isinstance(kind, str) or kind not in self._kinds:  # (the blocks the hand keeps for itself are kinds too)
            grasp_kind(kind)
        return self._kinds[kind]

    def pose(self, u):
        """Actuated joint angles ``Psi = mean_pose + synergies @ z`` (Eq. 11).

        Parameters
        ----------
        u : (6 + n_syn,) float

        Returns
        -------
        (n_act,) float
            In the order of ``actuated_names``.
        """
        return self.mean_pose + self.synergies @ self.check_u(u)[6:]

    def joint_angles(self, u):
        """Angles of every joint, the fixed ones included.

        Parameters
        ----------
        u : (6 + n_syn,) float

        Returns
        -------
        dict of str to float
            Keyed by ``joint_names``, in that order (chain by chain from the palm outwards:
            T_rot, T_abd, T_mcp, T_ip, I_mcp, I_pip, I_dip, ... for the paper's hand).
        """
        q = self._q_z @ self.check_u(u)[6:] + self._q_0
        return dict(zip(self.joint_names, q[self._real].tolist()))

    def point_labels(self, kind):
        """Names of the hand points of a kind.

        Parameters
        ----------
        kind : {"precision", "power"}

        Returns
        -------
        list of str
            ``["T0", "I0", "M0", "R0", "L0"]`` or ``["T1", "T2", "T3", "I1", ..., "L3", "P"]``.
        """
        return list(self._check_kind(kind)[2])

    def point_chains(self, kind):
        """The finger (index into `finger_names`) of each hand point of a kind; -1 for the palm point.

        Parameters
        ----------
        kind : {"precision", "power"}

        Returns
        -------
        (n,) int
            In the order of `point_labels`; labels are the finger's name and a
            number, so a finger of any name is found by this, not by its label.

        Examples
        --------
        >>> SynergyHand.default().point_chains("power")[[0, 3, -1]].tolist()
        [0, 1, -1]
        """
        _, _, labels, upstream, _, _ = self._check_kind(kind)
        return np.where(np.array(labels) == "P", -1, upstream[:, 0])

    # ------------------------------------------------------------------ kinematics

    def _chains(self, z):
        """Forward kinematics in the palm frame.

        Returns
        -------
        rot : (n_c, n_j + 1, 3, 3) float
            Orientation of each chain's base and of each link (after its joint).
        pos : (n_c, n_j + 1, 3) float
            Position of each chain's base and of the end of each link.
        """
        n_c, n_j = self._lengths.shape
        rot, pos = np.empty((n_c, n_j + 1, 3, 3)), np.empty((n_c, n_j + 1, 3))
        _chain_kinematics(np.ascontiguousarray(z, dtype=float), self._q_z, self._q_0, self._k1, self._k2,
                          self._base_rot, self._base_pos, self._lengths, rot, pos)
        return rot, pos

    def _world(self, u, kind, jacobian):
        """Hand points of a kind in the world frame and, if ``jacobian``, their Jacobian (else None)."""
        u = self.check_u(u)
        nodes, weights, _, upstream, frame, offset = self._check_kind(kind)
        rot, pos = self._chains(u[6:])
        n = len(nodes)
        points = np.empty((n, 3))
        jac = np.empty((n, 3, self.n_u)) if jacobian else np.empty((0, 3, self.n_u))
        _hand_points(u, rotation_xyz(u[3:6]), rot, pos, self._palm_nodes, self._axes, self._q_z, nodes, weights,
                     upstream, frame, offset, points, jac)
        return points, (jac if jacobian else None)

    def synergy_grid(self, steps, max_points=SYNERGY_GRID_POINTS):
        """Synergy values on a grid over the synergy box, of at most ``max_points`` points.

        ``steps`` values per synergy, the limits included, in `itertools.product` order; fewer
        values per synergy (down to 2) where ``steps ** n_syn`` would exceed ``max_points``, and
        past that (``2 ** n_syn > max_points``) ``max_points`` points drawn from the 2-value grid
        with a fixed seed: the grid's cost does not grow exponentially with the synergies.

        Parameters
        ----------
        steps : int
            Values per synergy (at least 2).
        max_points : int
            Most rows of the grid (at least 1).

        Returns
        -------
        (g, n_syn) float

        Examples
        --------
        >>> hand = SynergyHand.default()
        >>> hand.synergy_grid(3).tolist()
        [[-1.0, -1.0], [-1.0, 0.0], [-1.0, 1.0], [0.0, -1.0], [0.0, 0.0], [0.0, 1.0], [1.0, -1.0], [1.0, 0.0], [1.0, 1.0]]
        >>> hand.synergy_grid(41).shape, hand.synergy_grid(41, max_points=100).shape
        ((1681, 2), (100, 2))
        """
        per = integer(steps, "steps", 2, "values per synergy")
        max_points = integer(max_points, "max_points", 1, "rows of the grid")
        if max_points > MAX_GRID_POINTS:
            raise ValueError(f"max_points must be at most {MAX_GRID_POINTS:.0e} rows, got {max_points}")
        per = min(per, max(2, int(round(max_points ** (1.0 / self.n_syn))) + 1))  # (then down by round-off only)
        while per > 2 and per**self.n_syn > max_points:
            per -= 1
        lo, hi = self.synergy_limits[:, 0], self.synergy_limits[:, 1]
        levels = [a + np.linspace(0.0, 1.0, per) * (b - a) for a, b in zip(lo, hi)]
        if per**self.n_syn <= max_points:
            return np.array(list(itertools.product(*levels)))
        picks = np.random.default_rng(0).integers(0, per, size=(max_points, self.n_syn))
        return np.array([[levels[j][i] for j, i in enumerate(row)] for row in picks])

    def points(self, u, kind="precision"):
        """Hand points in the world frame.

        Parameters
        ----------
        u : (6 + n_syn,) float
            Configuration ``[px, py, pz, phi1, phi2, phi3, z...]``.
        kind : {"precision", "power"}
            ``"precision"``: the fingertips, T0, I0, M0, R0, L0 (end of each chain's last
            segment). ``"power"``: the midpoint of every segment of positive length, chain by
            chain from the palm out (T1 = thumb metacarpal, T2, T3, I1, I2, I3, ..., L3), then the
            palm point P. Finger points are moved ``contact_offset`` mm to the palmar side of
            their segment.

        Returns
        -------
        (n, 3) float
            ``n = 5`` (precision) or ``16`` (power) for the paper's hand.

        Examples
        --------
        >>> import numpy as np
        >>> hand = SynergyHand.default()
        >>> u = np.zeros(hand.n_u)             # palm frame = world frame, mean pose
        >>> hand.points(u).shape, hand.points(u, "power").shape
        ((5, 3), (16, 3))
        >>> hand.points(u).round(1)[1].tolist()   # the index fingertip I0 (mm)
        [29.4, 79.9, 78.1]
        >>> shifted = u + [10.0, 0, 0, 0, 0, 0, 0, 0]     # move the palm 10 mm along x
        >>> bool(np.allclose(hand.points(shifted) - hand.points(u), [10.0, 0.0, 0.0]))
        True
        """
        return self._world(u, kind, False)[0]

    def points_and_jacobian(self, u, kind="precision"):
        """Hand points and their analytic Jacobian with respect to ``u``.

        Parameters
        ----------
        u : (6 + n_syn,) float
        kind : {"precision", "power"}

        Returns
        -------
        points : (n, 3) float
            As `points`.
        jacobian : (n, 3, 6 + n_syn) float
            ``jacobian[i, :, k] = d points[i] / d u[k]``: identity for ``p``, ``w_k x (R x)``
            for the Euler angles (``w_k`` = the world axis of the k-th elementary rotation),
            ``R sum_j (dq_j/dz) a_j x (x - o_j)`` for the synergies (joint axes ``a_j``
            through ``o_j``, upstream joints only).

        Examples
        --------
        The synergy column of the Jacobian against a central difference:

        >>> import numpy as np
        >>> hand = SynergyHand.default()
        >>> u = np.array([0.0, 0.0, 0.0, 0.1, -0.2, 0.3, 0.5, -0.4])
        >>> points, jac = hand.points_and_jacobian(u)
        >>> jac.shape
        (5, 3, 8)
        >>> du = np.zeros(8)
        >>> du[6] = 1e-6
        >>> numeric = (hand.points(u + du) - hand.points(u - du)) / 2e-6
        >>> bool(np.allclose(jac[:, :, 6], numeric, atol=1e-6))
        True
        """
        return self._world(u, kind, True)

    def points_jacobian(self, u, kind="precision"):
        """Analytic Jacobian of `points` (see `points_and_jacobian`).

        Parameters
        ----------
        u : (6 + n_syn,) float
            Configuration ``[px, py, pz, phi1, phi2, phi3, z...]``.
        kind : {"precision", "power"}
            Which hand points (see `points`).

        Returns
        -------
        (n, 3, 6 + n_syn) float
            ``d points / d u``.
        """
        return self.points_and_jacobian(u, kind)[1]

    def palm_jacobian(self, u, points):
        """Jacobian of world points fixed to the palm (they move with the pose, not the synergies).

        Parameters
        ----------
        u : (6 + n_syn,) float
        points : (n, 3) array_like
            World points at ``u`` (mm), taken as attached to the palm.

        Returns
        -------
        (n, 3, 6 + n_syn) float
            ``d points / d u``: identity for ``p``, ``w_k x (x - p)`` for the
            Euler angles (``w_k`` = the world axis of the k-th elementary
            rotation), zero for the synergies.

        Raises
        ------
        ValueError
            If ``u`` does not fit the hand or ``points`` is not a finite (n, 3) array.
        TypeError
            If ``points`` is not numeric.

        Examples
        --------
        Against a central difference, for the palm box's centre:

        >>> import numpy as np
        >>> hand = SynergyHand.default()
        >>> u = np.array([5.0, -3.0, 20.0, 0.4, -0.7, 1.1, 0.5, -0.4])
        >>> centre = hand.segments(u).palm_center
        >>> jac = hand.palm_jacobian(u, [centre])
        >>> numeric = np.stack([(hand.segments(u + h).palm_center - hand.segments(u - h).palm_center) / 2e-6
        ...                     for h in 1e-6 * np.eye(8)], axis=1)
        >>> bool(np.allclose(jac[0], numeric, atol=1e-6))
        True
        """
        u = self.check_u(u)
        try:
            x = np.asarray(points, dtype=float)
        except (TypeError, ValueError) as exc:
            raise TypeError(f"points must be a numeric (n, 3) array, got {type(points).__name__}") from exc
        if x.ndim != 2 or x.shape[1] != 3 or not np.isfinite(x).all():
            raise ValueError(f"points must be a finite (n, 3) array (world points, mm), got shape {x.shape}")
        phi = u[3:6]
        axes = np.stack([np.array([1.0, 0.0, 0.0]), rotation_xyz([phi[0], 0.0, 0.0])[:, 1],
                         rotation_xyz([phi[0], phi[1], 0.0])[:, 2]])
        jac = np.zeros((len(x), 3, self.n_u))
        jac[:, :, :3] = np.eye(3)
        jac[:, :, 3:6] = np.einsum("kab,nb->nak", _skew(axes), x - u[:3])
        return jac

    def segments_and_jacobian(self, u):
        """Capsule axes of the phalanges and the Jacobians of their end points.

        Parameters
        ----------
        u : (6 + n_syn,) float

        Returns
        -------
        ends : (k, 2, 3) float
            Start and end of every segment's axis (as ``segments(u).capsules``).
        jacobian : (k, 2, 3, 6 + n_syn) float
            ``d ends / d u``; a point ``(1 - s) a + s b`` of a segment moves with
            ``(1 - s) J_a + s J_b``.
        """
        points, jac = self.points_and_jacobian(u, "_capsules")
        return points.reshape(-1, 2, 3), jac.reshape(-1, 2, 3, self.n_u)

    def skin_and_jacobian(self, u, kind="precision"):
        """Points on the skin of every segment and of the palm, with their Jacobians.

        Each segment carries ``len(SKIN_ALONG[kind]) * len(SKIN_AROUND)`` points:
        at the fractions ``SKIN_ALONG[kind]`` of its axis, ``contact_offset`` mm
        from the axis towards the angles `SKIN_AROUND` (0: the palmar side, where
        the power point sits; +-pi/2: the two lateral sides, along the joint
        axis). With ``contact_offset`` equal to the finger radius they lie on
        the phalanx capsule's surface. The palm carries the palm point P and
        the corners and edge midpoints of the palm box's front face (`PALM_SKIN`).

        Parameters
        ----------
        u : (6 + n_syn,) float
        kind : {"precision", "power"}
            The grasp whose status the skin serves: a power grasp's phalanges
            are sampled at five places along their axes, a precision grasp's at three.

        Returns
        -------
        skin : (k, m, 3) float
            The k segments' m skin points, segments in the order of the power points,
            the points of a segment place by place along it, round it at each place.
        palm : (p, 3) float
            The palm's skin points, the palm point P first (p = 9).
        jacobian : (k, m, 3, 6 + n_syn) float
            ``d skin / d u``.
        palm_jacobian : (p, 3, 6 + n_syn) float
            ``d palm / d u``.

        Examples
        --------
        The power points are the palmar skin points halfway along the segments:

        >>> import numpy as np
        >>> hand = SynergyHand.default()
        >>> u = np.array([0.0, 0.0, 0.0, 0.1, -0.2, 0.3, 0.5, -0.4])
        >>> skin, palm, jac, palm_jac = hand.skin_and_jacobian(u)
        >>> skin.shape, jac.shape, hand.skin_and_jacobian(u, "power")[0].shape
        ((15, 9, 3), (15, 9, 3, 8), (15, 15, 3))
        >>> bool(np.allclose(skin[:, 4], hand.points(u, "power")[:-1]))
        True
        """
        return self._split_skin(*self.points_and_jacobian(u, f"_skin_{grasp_kind(kind)}"), kind)

    def points_and_skin(self, u, kind):
        """A grasp's hand points and its skin points with their Jacobians, from one pass of the kinematics.

        Parameters
        ----------
        u : (6 + n_syn,) float
        kind : {"precision", "power"}

        Returns
        -------
        points, jacobian : (n, 3), (n, 3, 6 + n_syn) float
            As ``points_and_jacobian(u, kind)``.
        skin, palm, skin_jacobian, palm_jacobian : (k, m, 3), (p, 3), (k, m, 3, 6 + n_syn), (p, 3, 6 + n_syn) float
            As ``skin_and_jacobian(u, kind)``.

        Examples
        --------
        >>> import numpy as np
        >>> hand = SynergyHand.default()
        >>> u = np.array([0.0, 0.0, 0.0, 0.1, -0.2, 0.3, 0.5, -0.4])
        >>> points, jac, skin, palm, skin_jac, palm_jac = hand.points_and_skin(u, "power")
        >>> bool(np.array_equal(points, hand.points_and_jacobian(u, "power")[0])), skin.shape
        (True, (15, 15, 3))
        """
        kind = grasp_kind(kind)
        points, jac = self.points_and_jacobian(u, f"_{kind}_and_skin")
        n = len(self._kinds[kind][0])
        return (points[:n], jac[:n], *self._split_skin(points[n:], jac[n:], kind))

    def _split_skin(self, points, jac, kind):
        """`skin_and_jacobian`'s arrays from the rows of a ``"_skin_<kind>"`` block and its Jacobian."""
        m, p = len(SKIN_ALONG[kind]) * len(SKIN_AROUND), 1 + len(PALM_SKIN)
        k = (len(points) - p) // m
        return points[:-p].reshape(k, m, 3), points[-p:], jac[:-p].reshape(k, m, 3, self.n_u), jac[-p:]

    def segments(self, u):
        """Capsules of the phalanges and the palm box, in the world frame.

        Parameters
        ----------
        u : (6 + n_syn,) float

        Returns
        -------
        HandGeometry
            One capsule per segment of positive length (radius ``finger_radius``) and the
            palm as an oriented box (``palm.center`` and ``palm.size`` of the file).
        """
        u = self.check_u(u)
        center, rot = self.palm_box(u)
        nodes = u[:3] + np.vstack([self._chains(u[6:])[1].reshape(-1, 3), self.palm_point]) @ rot.T
        return HandGeometry(
            capsules=nodes[self._segment_nodes],
            radius=self.finger_radius,
            labels=self._kinds["power"][2][:-1],
            palm_center=center,
            palm_axes=rot,
            palm_half_extents=self.palm_half_extents.copy(),
        )

    def palm_box(self, u):
        """The palm box's centre and axes in the world frame (its half extents are ``palm_half_extents``).

        Parameters
        ----------
        u : (6 + n_syn,) float

        Returns
        -------
        center : (3,) float
        axes : (3, 3) float
            Columns: the palm frame's x, y and z in the world; z is the outward
            normal of the box's front face (the face the fingers close over).

        Examples
        --------
        >>> import numpy as np
        >>> hand = SynergyHand.default()
        >>> u = np.array([5.0, -3.0, 20.0, 0.4, -0.7, 1.1, 0.5, -0.4])
        >>> center, axes = hand.palm_box(u)
        >>> geo = hand.segments(u)
        >>> bool(np.array_equal(center, geo.palm_center) and np.array_equal(axes, geo.palm_axes))
        True
        """
        u = self.check_u(u)
        rot = rotation_xyz(u[3:6])
        return u[:3] + rot @ self._palm_center, rot

    def __repr__(self):
        return (f"SynergyHand({self.name!r}, fingers={self.finger_names}, "
                f"n_act={len(self.actuated_names)}, n_syn={self.n_syn})")


@kernel
def _chain_kinematics(z, q_z, q_0, k1, k2, base_rot, base_pos, lengths, rot, pos):
    """Forward kinematics of the chains into ``rot`` and ``pos`` (see `SynergyHand._chains`).

    Joint angles are affine in the synergies, ``q = q_z z + q_0``; joint j
    turns link j by the Rodrigues rotation ``I + sin q K1 + (1 - cos q) K2``
    (K1 the cross-product matrix of its axis, K2 = K1 K1), and each link runs
    along its own +y: its end is its start plus its length times the frame's
    second column.
    """
    n_c, n_j = lengths.shape
    for c in range(n_c):
        for a in range(3):
            for b in range(3):
                rot[c, 0, a, b] = base_rot[c, a, b]
            pos[c, 0, a] = base_pos[c, a]
        cum0 = cum1 = cum2 = 0.0
        for j in range(n_j):
            q = q_0[c, j]
            for k in range(len(z)):
                q += q_z[c, j, k] * z[k]
            s, cq = np.sin(q), 1.0 - np.cos(q)
            for a in range(3):
                for b in range(3):
                    acc = 0.0
                    for m in range(3):
                        r = k2[c, j, m, b] * cq + k1[c, j, m, b] * s + (1.0 if m == b else 0.0)
                        acc += rot[c, j, a, m] * r
                    rot[c, j + 1, a, b] = acc
            cum0 += lengths[c, j] * rot[c, j + 1, 0, 1]
            cum1 += lengths[c, j] * rot[c, j + 1, 1, 1]
            cum2 += lengths[c, j] * rot[c, j + 1, 2, 1]
            pos[c, j + 1, 0] = cum0 + base_pos[c, 0]
            pos[c, j + 1, 1] = cum1 + base_pos[c, 1]
            pos[c, j + 1, 2] = cum2 + base_pos[c, 2]


@kernel
def _hand_points(u, R, rot, pos, palm_nodes, axes, q_z, nodes, weights, upstream, frame, offset, points, jac):
    """Hand points in the world frame (``points``) and, when ``jac`` has rows, their Jacobian.

    A point is ``p + R x`` with x in the palm frame the weighted sum of its
    nodes (chain nodes from ``pos``, numbered chain by chain; after them the
    palm's, ``palm_nodes``) plus its offset in its link's frame. Its Jacobian: the identity for
    p; ``w_k x (R x)`` for the Euler angles (``w_k`` = x, ``Rx y``, ``Rx Ry z``);
    ``R sum_j (dq_j/dz) a_j x (x - o_j)`` for the synergies, over the joints
    upstream of it (axis ``a_j`` through ``o_j``, the start of link j).
    """
    n_c, n_j1 = pos.shape[0], pos.shape[1]
    n_syn = q_z.shape[2]
    c1, s1 = np.cos(u[3]), np.sin(u[3])
    wanted = jac.shape[0] > 0
    for i in range(len(nodes)):
        x0 = x1 = x2 = 0.0
        for e in range(2):
            node, w = nodes[i, e], weights[i, e]
            if w == 0.0:
                continue
            if node >= n_c * n_j1:  # the palm point or a palm skin point
                k = node - n_c * n_j1
                x0, x1, x2 = x0 + w * palm_nodes[k, 0], x1 + w * palm_nodes[k, 1], x2 + w * palm_nodes[k, 2]
            else:
                nc, nj = node // n_j1, node % n_j1
                x0, x1, x2 = x0 + w * pos[nc, nj, 0], x1 + w * pos[nc, nj, 1], x2 + w * pos[nc, nj, 2]
        fc, fj = frame[i] // n_j1, frame[i] % n_j1
        o0, o1, o2 = offset[i, 0], offset[i, 1], offset[i, 2]
        x0 += rot[fc, fj, 0, 0] * o0 + rot[fc, fj, 0, 1] * o1 + rot[fc, fj, 0, 2] * o2
        x1 += rot[fc, fj, 1, 0] * o0 + rot[fc, fj, 1, 1] * o1 + rot[fc, fj, 1, 2] * o2
        x2 += rot[fc, fj, 2, 0] * o0 + rot[fc, fj, 2, 1] * o1 + rot[fc, fj, 2, 2] * o2
        arm0 = R[0, 0] * x0 + R[0, 1] * x1 + R[0, 2] * x2
        arm1 = R[1, 0] * x0 + R[1, 1] * x1 + R[1, 2] * x2
        arm2 = R[2, 0] * x0 + R[2, 1] * x1 + R[2, 2] * x2
        points[i, 0], points[i, 1], points[i, 2] = u[0] + arm0, u[1] + arm1, u[2] + arm2
        if not wanted:
            continue
        for a in range(3):
            for b in range(3):
                jac[i, a, b] = 1.0 if a == b else 0.0
        # Euler angles: w_k x arm with w = x, (0, c1, s1), the third column of R
        for k in range(3):
            if k == 0:
                w0, w1, w2 = 1.0, 0.0, 0.0
            elif k == 1:
                w0, w1, w2 = 0.0, c1, s1
            else:
                w0, w1, w2 = R[0, 2], R[1, 2], R[2, 2]
            jac[i, 0, 3 + k] = w1 * arm2 - w2 * arm1
            jac[i, 1, 3 + k] = w2 * arm0 - w0 * arm2
            jac[i, 2, 3 + k] = w0 * arm1 - w1 * arm0
        # synergies: sum over the upstream joints of (a_j x (x - o_j)) dq_j/dz, then R
        c, n_up = upstream[i, 0], upstream[i, 1]
        for s in range(n_syn):
            d0 = d1 = d2 = 0.0
            for j in range(n_up):
                g = q_z[c, j, s]
                if g == 0.0:
                    continue
                a0 = rot[c, j, 0, 0] * axes[c, j, 0] + rot[c, j, 0, 1] * axes[c, j, 1] + rot[c, j, 0, 2] * axes[c, j, 2]
                a1 = rot[c, j, 1, 0] * axes[c, j, 0] + rot[c, j, 1, 1] * axes[c, j, 1] + rot[c, j, 1, 2] * axes[c, j, 2]
                a2 = rot[c, j, 2, 0] * axes[c, j, 0] + rot[c, j, 2, 1] * axes[c, j, 1] + rot[c, j, 2, 2] * axes[c, j, 2]
                r0, r1, r2 = x0 - pos[c, j, 0], x1 - pos[c, j, 1], x2 - pos[c, j, 2]
                d0 += (a1 * r2 - a2 * r1) * g
                d1 += (a2 * r0 - a0 * r2) * g
                d2 += (a0 * r1 - a1 * r0) * g
            for a in range(3):
                jac[i, a, 6 + s] = R[a, 0] * d0 + R[a, 1] * d1 + R[a, 2] * d2
