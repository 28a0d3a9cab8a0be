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
import json
import math
from dataclasses import dataclass
from functools import cache
from importlib import resources
from pathlib import Path

import numpy as np

from ._vectors import cross

__all__ = ["SynergyHand", "HandGeometry", "rotation_xyz", "POINT_KINDS"]

POINT_KINDS = ("precision", "power")

_DEFAULT_FILE = "paper_hand.json"
#: Skin points of a segment: fractions along its axis, and angles round it from the palmar side.
SKIN_ALONG = (0.0, 0.5, 1.0)
SKIN_AROUND = (-math.pi / 2, 0.0, math.pi / 2)
#: Palm skin points besides the palm point P: the corners and edge midpoints of the palm box's
#: front face, as fractions of its half extents along the palm frame's x and y.
PALM_SKIN = tuple((sx, sy) for sx in (-1.0, 0.0, 1.0) for sy in (-1.0, 0.0, 1.0) if (sx, sy) != (0.0, 0.0))


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
        try:
            arr = np.array(value, dtype=float)
        except (TypeError, ValueError):
            self.fail(field, f"must be numbers of shape {shape}")
        if arr.ndim != len(shape) or any(n is not None and n != m for n, m in zip(shape, arr.shape)):
            self.fail(field, f"must have shape {shape}, got {arr.shape}")
        if not np.all(np.isfinite(arr)):
            self.fail(field, "must be finite")
        return arr

    def name_list(self, data, key, field):
        value = self.get(data, key, field)
        if (not isinstance(value, list) or not value
                or not all(isinstance(v, str) and v for v in value) or len(set(value)) != len(value)):
            self.fail(field, "must be a non-empty list of distinct names")
        return value

    def items(self, data, key, field):
        value = self.get(data, key, field)
        if not isinstance(value, list) or not value:
            self.fail(field, "must be a non-empty list")
        return value


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
        self._data = copy.deepcopy(data)
        self.source = str(source)
        if not isinstance(data, dict):
            spec.fail("<root>", "must be a JSON object")
        name = spec.get(data, "name", "name")
        self.name = str(name)
        self.actuated_names = spec.name_list(data, "actuated", "actuated")
        n_act = len(self.actuated_names)
        self.mean_pose = spec.array(data, "mean_pose", "mean_pose", (n_act,))
        self.synergies = spec.array(data, "synergies", "synergies", (n_act, None))
        self.n_syn = self.synergies.shape[1]
        if self.n_syn < 1:
            spec.fail("synergies", "must have at least one column")
        self.synergy_limits = spec.array(data, "synergy_limits", "synergy_limits", (self.n_syn, 2))
        if np.any(self.synergy_limits[:, 0] >= self.synergy_limits[:, 1]):
            spec.fail("synergy_limits", "must have lower < upper in every row")
        self.finger_radius = float(spec.array(data, "finger_radius", "finger_radius", ()))
        if self.finger_radius <= 0:
            spec.fail("finger_radius", "must be positive")
        self.contact_offset = float(spec.array(data, "contact_offset", "contact_offset", ())) if "contact_offset" in data else 0.0
        if self.contact_offset < 0:
            spec.fail("contact_offset", "must be >= 0")
        palm = spec.get(data, "palm", "palm")
        self._palm_center = spec.array(palm, "center", "palm.center", (3,))
        self.palm_half_extents = 0.5 * spec.array(palm, "size", "palm.size", (3,))
        if np.any(self.palm_half_extents <= 0):
            spec.fail("palm.size", "must be positive")
        self.palm_point = spec.array(palm, "point", "palm.point", (3,))
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
            fname = spec.get(finger, "name", f"{fld}.name")
            if not isinstance(fname, str) or not fname:
                spec.fail(f"{fld}.name", "must be a non-empty string")
            base = spec.get(finger, "base", f"{fld}.base")
            joints = []
            for j, joint in enumerate(spec.items(finger, "joints", f"{fld}.joints")):
                jf = f"{fld}.joints[{j}]"
                jname = spec.get(joint, "name", f"{jf}.name")
                if not isinstance(jname, str) or not jname:
                    spec.fail(f"{jf}.name", "must be a non-empty string")
                axis = spec.array(joint, "axis", f"{jf}.axis", (3,))
                if np.linalg.norm(axis) < 1e-9:
                    spec.fail(f"{jf}.axis", "must be a non-zero vector")
                length = float(spec.array(joint, "length", f"{jf}.length", ()))
                if length < 0:
                    spec.fail(f"{jf}.length", "must be >= 0")
                coupling = spec.get(joint, "coupling", f"{jf}.coupling")
                if not isinstance(coupling, dict):
                    spec.fail(f"{jf}.coupling", "must be an object {actuated joint name: coefficient}")
                row = np.zeros(len(act_index))
                for key in coupling:
                    if key not in act_index:
                        spec.fail(f"{jf}.coupling.{key}", f"is not an actuated joint {self.actuated_names}")
                    row[act_index[key]] = spec.array(coupling, key, f"{jf}.coupling.{key}", ())
                offset = float(spec.array(joint, "offset", f"{jf}.offset", ()))
                joints.append((jname, axis / np.linalg.norm(axis), length, row, offset))
            if not any(j[2] > 0 for j in joints):
                spec.fail(f"{fld}.joints", "must contain a segment of positive length")
            chains.append((fname,
                           spec.array(base, "position", f"{fld}.base.position", (3,)),
                           rotation_xyz(spec.array(base, "rotation_xyz", f"{fld}.base.rotation_xyz", (3,))),
                           joints))
        self.finger_names = [c[0] for c in chains]
        self.joint_names = [j[0] for c in chains for j in c[3]]
        for field, names in (("fingers[].name", self.finger_names), ("fingers[].joints[].name", self.joint_names)):
            if len(set(names)) != len(names):
                spec.fail(field, "must be unique")

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
        self._q_z_flat = self._q_z.reshape(n_c * n_j, self.n_syn)

        # Nodes: each chain's base and the end of each of its links, then the palm point.
        palm = n_c * (n_j + 1)  # the palm point's node, then the palm skin's
        n_nodes = palm + 1 + len(PALM_SKIN)
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
            # points on the skin of every segment (SKIN_ALONG x SKIN_AROUND), then of the palm
            "_skin": [(f"{self.finger_names[c]}{k}", {node[c, j]: 1.0 - t, node[c, j + 1]: t}, c, j + 1)
                      for c, k, j in segments for t in SKIN_ALONG for _ in SKIN_AROUND]
                     + [("P", {palm + i: 1.0}, 0, 0) for i in range(1 + len(PALM_SKIN))],
        }
        # the palmar side of link j: where its far end moves when joint j flexes, axis_j x e_y
        palmar = np.cross(self._axes, [0.0, 1.0, 0.0])
        palmar /= np.maximum(np.linalg.norm(palmar, axis=-1, keepdims=True), 1e-12)
        last = [int(np.flatnonzero(self._lengths[c] > 0)[-1]) for c in range(n_c)]
        links = {  # kind -> per point (chain, link) carrying the palmar offset, None for the palm point
            "precision": [(c, last[c]) for c in range(n_c)],
            "power": [(c, j) for c, _, j in segments] + [None],
            "_capsules": [None] * (2 * len(segments)),
            "_skin": [(c, j, around) for c, _, j in segments for _ in SKIN_ALONG for around in SKIN_AROUND]
                     + [None] * (1 + len(PALM_SKIN)),
        }
        self._kinds = {}
        for kind, rows in points.items():
            select = np.zeros((len(rows), n_nodes))
            upstream = np.zeros((len(rows), n_c, n_j))
            for i, (_, weights, c, n_up) in enumerate(rows):
                select[i, list(weights)] = list(weights.values())
                upstream[i, c, :n_up] = 1.0
            # dq/dz of the joints upstream of each point: (n, n_c * n_j, n_syn)
            q_z_masked = upstream.reshape(len(rows), -1, 1) * self._q_z_flat
            frame = np.zeros(len(rows), dtype=int)  # index into the (n_c * (n_j + 1)) link frames
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
            self._kinds[kind] = (select, q_z_masked, [r[0] for r in rows], frame, offset)
        # a power grasp's status needs both: one pass of the kinematics for the two
        self._kinds["_power_skin"] = tuple(
            a + b if isinstance(a, list) else np.concatenate([a, b])
            for a, b in zip(self._kinds["power"], self._kinds["_skin"])
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
        path = Path(path)
        if not path.is_file():
            raise FileNotFoundError(f"hand file not found: '{path}'")
        try:
            data = json.loads(path.read_text(encoding="utf-8"))
        except (json.JSONDecodeError, UnicodeDecodeError) as err:
            raise ValueError(f"{path}: not valid JSON ({err})") from None
        return cls(data, source=path)

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

    def _check_u(self, u):
        try:
            if np.iscomplexobj(u):
                raise TypeError("complex")
            u = np.asarray(u, dtype=float)
        except (TypeError, ValueError):
            raise TypeError(f"u must be a numeric vector of {self.n_u} numbers [p (3), phi (3), z ({self.n_syn})], "
                            f"got {type(u).__name__}") from None
        if u.shape != (self.n_u,):
            raise ValueError(f"u must have shape ({self.n_u},) = [p (3), phi (3), z ({self.n_syn})], "
                             f"got {u.shape}")
        if not np.all(np.isfinite(u)):
            raise ValueError(f"u must be finite, got {u}")
        return u

    def _check_kind(self, kind):
        if kind not in self._kinds or (kind.startswith("_") and kind not in ("_capsules", "_skin", "_power_skin")):
            raise ValueError(f"unknown kind of hand points {kind!r}; kinds are {list(POINT_KINDS)}")
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
        return self.mean_pose + self.synergies @ self._check_u(u)[6:]

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
        q = self._q_z @ self._check_u(u)[6:] + self._q_0
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

    # ------------------------------------------------------------------ kinematics

    def _chains(self, z):
        """Forward kinematics in the palm frame.

        Returns
        -------
        nodes : (n_c * (n_j + 1) + 1 + len(PALM_SKIN), 3) float
            Chain bases, link ends, the palm point and the palm skin points.
        frames : (n_c * (n_j + 1), 3, 3) float
            Orientation of each chain's base and of each link (after its joint).
        axes : (n_c * n_j, 3) float
            Joint axes.
        origins : (n_c * n_j, 3) float
            A point on each joint axis.
        """
        q = self._q_z @ z + self._q_0
        s, c = np.sin(q)[..., None, None], np.cos(q)[..., None, None]
        joint_rot = s * self._k1 + (1.0 - c) * self._k2 + np.eye(3)     # (n_c, n_j, 3, 3)
        n_c, n_j = q.shape
        rot = np.empty((n_c, n_j + 1, 3, 3))
        rot[:, 0] = self._base_rot
        for j in range(n_j):
            np.matmul(rot[:, j], joint_rot[:, j], out=rot[:, j + 1])
        palm = n_c * (n_j + 1)
        nodes = np.empty((palm + 1 + len(PALM_SKIN), 3))
        nodes[palm] = self.palm_point
        nodes[palm + 1:] = self._palm_skin
        pos = nodes[:palm].reshape(n_c, n_j + 1, 3)
        pos[:, 0] = self._base_pos
        # each link runs along its own +y: its step is length * the frame's second column
        np.cumsum(self._lengths[..., None] * rot[:, 1:, :, 1], axis=1, out=pos[:, 1:])
        pos[:, 1:] += self._base_pos[:, None]
        axes = (rot[:, :-1] @ self._axes[..., None]).reshape(-1, 3)
        return nodes, axes, pos[:, :-1].reshape(-1, 3), rot.reshape(-1, 3, 3)

    def _local_points(self, z, kind):
        """Hand points of a kind in the palm frame, with the chain geometry for the Jacobian."""
        select, q_z_masked, _, frame, offset = self._check_kind(kind)
        nodes, axes, origins, frames = self._chains(z)
        local = select @ nodes + np.einsum("nab,nb->na", frames[frame], offset)
        return local, axes, origins, q_z_masked

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
        u = self._check_u(u)
        return u[:3] + self._local_points(u[6:], kind)[0] @ rotation_xyz(u[3:6]).T

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
        u = self._check_u(u)
        local, axes, origins, q_z_masked = self._local_points(u[6:], kind)      # (n, 3), ...
        rot = rotation_xyz(u[3:6])
        arm = local @ rot.T
        n = local.shape[0]
        jac = np.empty((n, 3, self.n_u))
        jac[:, :, :3] = np.eye(3)
        c1, s1 = math.cos(u[3]), math.sin(u[3])
        euler_axes = np.array([[1.0, 0.0, 0.0], [0.0, c1, s1], rot[:, 2]])        # x, Rx y, Rx Ry z
        jac[:, :, 3:6] = cross(euler_axes[None], arm[:, None]).transpose(0, 2, 1)
        dq = cross(axes[None], local[:, None] - origins[None])                   # (n, n_joints, 3)
        jac[:, :, 6:] = rot @ (dq.transpose(0, 2, 1) @ q_z_masked)
        return u[:3] + arm, jac

    def points_jacobian(self, u, kind="precision"):
        """Analytic Jacobian of `points`, ``(n, 3, 6 + n_syn)`` (see `points_and_jacobian`)."""
        return self.points_and_jacobian(u, kind)[1]

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

    def skin_and_jacobian(self, u):
        """Points on the skin of every segment and of the palm, with their Jacobians.

        Each segment carries ``len(SKIN_ALONG) * len(SKIN_AROUND)`` points:
        at the fractions `SKIN_ALONG` of its axis, ``contact_offset`` mm from
        the axis towards the angles `SKIN_AROUND` (0: the palmar side, where
        the power point sits; +-pi/2: the two lateral sides, along the joint
        axis). With ``contact_offset`` equal to the finger radius they lie on
        the phalanx capsule's surface. The palm carries the palm point P and
        the corners and edge midpoints of the palm box's front face (`PALM_SKIN`).

        Parameters
        ----------
        u : (6 + n_syn,) float

        Returns
        -------
        skin : (k, m, 3) float
            The k segments' m skin points, segments in the order of the power points.
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
        >>> skin.shape, jac.shape
        ((15, 9, 3), (15, 9, 3, 8))
        >>> bool(np.allclose(skin[:, 4], hand.points(u, "power")[:-1]))
        True
        """
        return self._split_skin(*self.points_and_jacobian(u, "_skin"))

    def power_and_skin(self, u):
        """The power points and the skin points with their Jacobians, from one pass of the kinematics.

        Parameters
        ----------
        u : (6 + n_syn,) float

        Returns
        -------
        points, jacobian : (n, 3), (n, 3, 6 + n_syn) float
            As ``points_and_jacobian(u, "power")``.
        skin, palm, skin_jacobian, palm_jacobian : (k, m, 3), (p, 3), (k, m, 3, 6 + n_syn), (p, 3, 6 + n_syn) float
            As `skin_and_jacobian`.

        Examples
        --------
        >>> import numpy as np
        >>> hand = SynergyHand.default()
        >>> u = np.array([0.0, 0.0, 0.0, 0.1, -0.2, 0.3, 0.5, -0.4])
        >>> points, jac, skin, palm, skin_jac, palm_jac = hand.power_and_skin(u)
        >>> bool(np.array_equal(points, hand.points_and_jacobian(u, "power")[0])), skin.shape
        (True, (15, 9, 3))
        """
        points, jac = self.points_and_jacobian(u, "_power_skin")
        n = len(self._kinds["power"][2])
        return (points[:n], jac[:n], *self._split_skin(points[n:], jac[n:]))

    def _split_skin(self, points, jac):
        """`skin_and_jacobian`'s arrays from the rows of the ``"_skin"`` points and their Jacobian."""
        m, p = len(SKIN_ALONG) * len(SKIN_AROUND), 1 + len(PALM_SKIN)
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
        u = self._check_u(u)
        rot = rotation_xyz(u[3:6])
        nodes = u[:3] + self._chains(u[6:])[0] @ rot.T
        return HandGeometry(
            capsules=nodes[self._segment_nodes],
            radius=self.finger_radius,
            labels=self._kinds["power"][2][:-1],
            palm_center=u[:3] + rot @ self._palm_center,
            palm_axes=rot,
            palm_half_extents=self.palm_half_extents.copy(),
        )

    def __repr__(self):
        return (f"SynergyHand({self.name!r}, fingers={self.finger_names}, "
                f"n_act={len(self.actuated_names)}, n_syn={self.n_syn})")
