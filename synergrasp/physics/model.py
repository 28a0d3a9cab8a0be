"""The MuJoCo model of a grasp: the synergy hand and the object as MJCF.

`grasp_mjcf` writes the scene as an MJCF string; nothing here imports
``mujoco``. Units follow MuJoCo (metres, kilograms, seconds) while
synergrasp's are millimetres: every length is divided by 1000 on the way in.

- The palm is a box welded to the world at the configuration's pose (a static
  body: it does not move however hard the fingers squeeze), or a mocap body
  that a replay moves along a path (``mocap=True``: it still yields to
  nothing).
- Each finger chain is a tree of bodies, one per joint of the hand file. A
  joint whose angle depends on the synergies is a hinge with a position servo;
  a joint that the synergies do not move (the paper's hand: T_ip and the dips,
  fixed at 20 degrees) is built into its body's orientation. Each segment of
  positive length carries a capsule of the hand's ``finger_radius``, named
  like the hand's capsules (``T1``, ``T2``, ..., ``L3``, see
  `synergrasp.hand.HandGeometry`).
- The object is a free body with one mesh geom per convex piece. MuJoCo
  collides the convex hull of each mesh, which is the piece itself: the model
  the planner uses.
- Hand geoms collide with object geoms only (no self-collision).
"""

from __future__ import annotations

from dataclasses import dataclass
from xml.sax.saxutils import quoteattr

import numpy as np

from ..hand import RESERVED_NAMES, rotation_xyz

__all__ = ["GraspScene", "grasp_mjcf", "moving_joints", "mujoco_quat", "PALM", "OBJECT"]

#: Names of the palm's body and box geom, and of the object's body (and prefix of its geoms, ``object/0``,
#: ``object/1``, ...): a hand's joints may not be named so (`synergrasp.hand.RESERVED_NAMES`).
PALM, OBJECT = RESERVED_NAMES
MM = 1e-3


@dataclass(frozen=True)
class GraspScene:
    """An MJCF scene and the names that tie it back to synergrasp.

    Attributes
    ----------
    xml : str
        The MJCF document.
    joints : list of str
        Hinge joints (the hand's moving joints), in the order of the actuators.
    capsules : list of str
        Capsule geoms, in the order of ``SynergyHand.segments(u).labels``.
    pieces : int
        Number of object geoms (one per convex piece), named ``object/<i>``.
    density : float
        Density of the object's geoms (kg/m^3).
    """

    xml: str
    joints: list
    capsules: list
    pieces: int
    density: float


def moving_joints(hand):
    """Names of the joints whose angles depend on the synergies.

    Parameters
    ----------
    hand : SynergyHand

    Returns
    -------
    list of str
        In the order of ``hand.joint_names``.

    Examples
    --------
    >>> from synergrasp import SynergyHand
    >>> moving_joints(SynergyHand.default())[:5]
    ['T_rot', 'T_abd', 'T_mcp', 'I_mcp', 'I_pip']
    """
    base = np.zeros(hand.n_u)
    q0 = hand.joint_angles(base)
    moved = set()
    for i in range(hand.n_syn):
        u = base.copy()
        u[6 + i] = 1.0
        moved |= {name for name, angle in hand.joint_angles(u).items() if angle != q0[name]}
    return [name for name in hand.joint_names if name in moved]


def _attr(name: str) -> str:
    """A hand's joint or point name as a quoted XML attribute value (quotes, ``<`` and ``&`` escaped)."""
    return quoteattr(name)


def _num(value):
    """Shortest text that reads back as the same float."""
    return repr(float(value))


def _vec(values):
    return " ".join(_num(v) for v in values)


def mujoco_quat(rotation):
    """MuJoCo's quaternion ``(w, x, y, z)`` of a rotation matrix.

    Parameters
    ----------
    rotation : (3, 3) float

    Returns
    -------
    tuple of 4 float
    """
    from scipy.spatial.transform import Rotation

    x, y, z, w = Rotation.from_matrix(rotation).as_quat()
    return (w, x, y, z)


def _axis_rotation(axis, angle):
    """Rotation matrix of ``angle`` about the unit ``axis`` (Rodrigues)."""
    k = np.array([[0.0, -axis[2], axis[1]], [axis[2], 0.0, -axis[0]], [-axis[1], axis[0], 0.0]])
    return np.eye(3) + np.sin(angle) * k + (1.0 - np.cos(angle)) * (k @ k)


def grasp_mjcf(hand, obj, u, *, density, friction, solref, solimp, timestep, joint_damping, kp,
               impratio=10.0, noslip_iterations=2, mocap=False):
    """The MJCF scene of a hand at configuration ``u`` around an object.

    Parameters
    ----------
    hand : SynergyHand
    obj : GraspObject
    u : (6 + n_syn,) float
        Configuration ``[px, py, pz, phi1, phi2, phi3, z...]`` (mm, rad). The
        palm is welded at its pose and the hinges start at their angles.
    density : float
        Density of the object (kg/m^3), giving its mass from the pieces' volume.
    friction : (3,) float
        MuJoCo's ``[sliding, torsional, rolling]`` coefficients, on every geom.
        A torsional coefficient of 0 gives point contacts (``condim`` 3),
        otherwise soft-finger contacts (``condim`` 4).
    solref, solimp : sequence of float
        Contact softness of every geom (MuJoCo's ``solref`` and ``solimp``).
    timestep : float
        Integration step (s).
    joint_damping : float
        Viscous damping of every hinge (N m s/rad).
    kp : float
        Stiffness of the position servos (N m/rad).
    impratio, noslip_iterations : float, int
        MuJoCo's friction-to-normal impedance ratio and noslip iterations
        (elliptic friction cones in any case).
    mocap : bool
        Make the palm a mocap body, placed at ``u`` and moved by
        ``data.mocap_pos`` and ``data.mocap_quat`` (a replay of a path).

    Returns
    -------
    GraspScene
    """
    u = np.asarray(u, dtype=float)
    data = hand.to_dict()
    angles = hand.joint_angles(u)
    moving = set(moving_joints(hand))
    rest = hand.segments(np.zeros(hand.n_u))  # palm frame = world frame
    rot = rotation_xyz(u[3:6])
    condim = 3 if friction[1] == 0 else 4

    lines = [
        f'<mujoco model="synergrasp {hand.name} / {obj.name}">',
        # a zero-length link (the paper's T_rot) has no geom: a tiny mass bound keeps its body valid
        '  <compiler angle="radian" autolimits="true" boundmass="1e-6" boundinertia="1e-12"/>',
        f'  <option timestep="{_num(timestep)}" gravity="0 0 0" cone="elliptic" impratio="{_num(impratio)}" '
        f'noslip_iterations="{int(noslip_iterations)}" integrator="implicitfast"/>',
        "  <default>",
        f'    <geom condim="{condim}" friction="{_vec(friction)}" solref="{_vec(solref)}" solimp="{_vec(solimp)}"/>',
        f'    <joint type="hinge" damping="{_num(joint_damping)}"/>',
        f'    <position kp="{_num(kp)}"/>',
        '    <default class="hand"><geom contype="0" conaffinity="1" rgba="0.85 0.7 0.6 1"/></default>',
        '    <default class="object"><geom type="mesh" contype="1" conaffinity="1" rgba="0.3 0.5 0.8 1"/></default>',
        "  </default>",
        '  <visual><headlight ambient="0.45 0.45 0.45" diffuse="0.6 0.6 0.6"/><global offwidth="1280" offheight="960"/></visual>',
        "  <asset>",
        '    <texture type="skybox" builtin="gradient" rgb1="1 1 1" rgb2="0.75 0.8 0.88" width="64" height="64"/>',
    ]
    for i, piece in enumerate(obj.pieces):
        lines.append(f'    <mesh name="piece{i}" vertex="{_vec(((piece - obj.center) * MM).ravel())}"/>')
    lines += [
        "  </asset>",
        "  <worldbody>",
        '    <light pos="0 0 1" dir="0 0 -1" directional="true"/>',
        f'    <body name="{PALM}" pos="{_vec(u[:3] * MM)}" quat="{_vec(mujoco_quat(rot))}" childclass="hand"'
        + (' mocap="true">' if mocap else ">"),
        f'      <geom name="{PALM}" type="box" pos="{_vec(rest.palm_center * MM)}" '
        f'size="{_vec(rest.palm_half_extents * MM)}"/>',
    ]
    joints, capsules = [], []
    for finger in data["fingers"]:
        depth, segment, previous = 0, 0, None
        pos, frame = np.asarray(finger["base"]["position"], float), rotation_xyz(finger["base"]["rotation_xyz"])
        for joint in finger["joints"]:
            name = joint["name"]
            axis = np.asarray(joint["axis"], float)
            axis = axis / np.linalg.norm(axis)
            indent = "      " + "  " * depth
            if previous is not None:
                pos, frame = np.array([0.0, previous, 0.0]), np.eye(3)
            if name in moving:
                lines.append(f'{indent}<body name={_attr(name)} pos="{_vec(pos * MM)}" quat="{_vec(mujoco_quat(frame))}">')
                lines.append(f'{indent}  <joint name={_attr(name)} axis="{_vec(axis)}"/>')
                joints.append(name)
            else:
                fixed = frame @ _axis_rotation(axis, angles[name])
                lines.append(f'{indent}<body name={_attr(name)} pos="{_vec(pos * MM)}" quat="{_vec(mujoco_quat(fixed))}">')
            length = float(joint["length"])
            if length > 0:
                segment += 1
                label = f'{finger["name"]}{segment}'
                lines.append(f'{indent}  <geom name={_attr(label)} type="capsule" size="{_num(hand.finger_radius * MM)}" '
                             f'fromto="0 0 0 0 {_num(length * MM)} 0"/>')
                capsules.append(label)
            previous, depth = length, depth + 1
        for level in range(depth - 1, -1, -1):
            lines.append("      " + "  " * level + "</body>")
    lines += [
        "    </body>",
        f'    <body name="{OBJECT}" pos="{_vec(obj.center * MM)}" childclass="object">',
        f'      <freejoint name="{OBJECT}"/>',
    ]
    for i in range(obj.n_pieces):
        lines.append(f'      <geom name="{OBJECT}/{i}" mesh="piece{i}" density="{_num(density)}"/>')
    lines += ["    </body>", "  </worldbody>", "  <actuator>"]
    lines += [f'    <position name={_attr(name)} joint={_attr(name)}/>' for name in joints]
    lines += ["  </actuator>", "</mujoco>", ""]
    return GraspScene("\n".join(lines), joints, capsules, obj.n_pieces, float(density))
