"""Grasps built by construction, whose physics is known: checks of the simulation itself.

- `pinch_grasp`: a box between the thumb and index fingertips, their round
  tips on opposite faces (two opposed soft-finger contacts: it holds).
- `ball_pinch`: a ball between the same fingertips, for a hand of the thumb
  and the index alone (it holds; without either finger it does not).
- `hand_without`: the same hand with fingers removed.

Built from the hand's kinematics alone (no planner), so they do not change
when the planner does.
"""

from __future__ import annotations

import itertools

import numpy as np
import trimesh

from .._checks import as_vector, positive_scalar
from ..hand import SynergyHand, rotation_xyz
from ..objects import GraspObject

__all__ = ["pinch_grasp", "ball_pinch", "hand_without", "PINCH_Z"]

#: Synergies of the pinches (the paper's hand): the centres of the thumb and index tips about 78 mm apart.
PINCH_Z = (0.2, 0.3)


def _pinch(hand, position, angles, gap):
    """The hand, the pinch configuration, the centres of the thumb's and index's round tips, and the free length.

    The free length is what the object may fill between the tips: their
    centres' distance less a finger radius and ``gap`` on each side.
    """
    hand = SynergyHand.default() if hand is None else hand
    if not isinstance(hand, SynergyHand):
        raise TypeError(f"hand must be a SynergyHand (None: the paper's hand), got {type(hand).__name__} {hand!r}")
    if hand.n_syn != len(PINCH_Z):
        raise ValueError(f"these grasps are built for a hand with {len(PINCH_Z)} synergies, {hand.name!r} has {hand.n_syn}")
    if isinstance(gap, (bool, np.bool_)) or not isinstance(gap, (int, float, np.integer, np.floating)) \
            or not np.isfinite(gap):
        raise ValueError(f"gap must be a finite number of mm (negative: the fingertips overlap the object), got {gap!r}")
    u = np.r_[as_vector(position, "position (mm)", 3), as_vector(angles, "angles (rad)", 3), PINCH_Z]
    missing = [name for name in ("T", "I") if name not in hand.finger_names]
    if missing:
        raise ValueError(f"a pinch is between the thumb 'T' and the index 'I'; hand {hand.name!r} has no finger "
                         f"{missing} (its fingers: {hand.finger_names})")
    geo = hand.segments(u)
    last = {chain: ends[1] for chain, ends in zip(hand.point_chains("power")[:-1], geo.capsules)}
    a, b = last[hand.finger_names.index("T")], last[hand.finger_names.index("I")]
    free = np.linalg.norm(b - a) - 2.0 * (hand.finger_radius + gap)
    if free <= 0.0:
        room = np.linalg.norm(b - a) - 2.0 * hand.finger_radius
        raise ValueError(f"gap {gap:g} mm leaves no room between the fingertips ({room:.1f} mm between their round "
                         f"ends): choose a gap under {room / 2.0:.1f} mm")
    return hand, u, a, b, free


def pinch_grasp(hand=None, *, position=(0.0, 0.0, 0.0), angles=(0.0, 0.0, 0.0), gap=1.0, side=20.0):
    """A box pinched between the thumb and index fingertips.

    The box's two end faces are perpendicular to the line between the centres
    of the two fingertips' round ends, ``finger_radius + gap`` mm from them,
    so each fingertip touches a face with the face's normal: the two
    contacts are exactly opposed.

    Parameters
    ----------
    hand : SynergyHand, optional
        Default: the paper's hand (two synergies).
    position, angles : (3,) float
        Pose of the palm (mm, XYZ Euler angles in rad).
    gap : float
        Distance (mm) of each face from its fingertip; negative, the
        fingertips cut that far into the faces. Less than half the room
        between the fingertips.
    side : float
        Side (mm) of the box's square cross-section, > 0.

    Returns
    -------
    u : (8,) float
        The configuration, synergies `PINCH_Z`.
    box : GraspObject

    Raises
    ------
    TypeError
        If ``hand`` is not a SynergyHand.
    ValueError
        If the hand has other than two synergies or no thumb ``T`` and index
        ``I``, or a size, gap or pose is out of range.

    Examples
    --------
    >>> u, box = pinch_grasp()
    >>> box
    GraspObject('pinched box', 1 pieces, 26 x 64 x 30 mm, L=33.0)
    """
    hand, u, a, b, length = _pinch(hand, position, angles, gap)
    side = positive_scalar(side, "side (mm of the box's cross-section)")
    axis = (b - a) / np.linalg.norm(b - a)
    across = np.cross(axis, rotation_xyz(u[3:6])[:, 2])  # one side along the palm, the other across it
    across /= np.linalg.norm(across)
    frame = np.c_[axis, across, np.cross(axis, across)]
    centre = (a + b) / 2.0
    corners = [centre + frame @ (np.array(s) * [length / 2, side / 2, side / 2])
               for s in itertools.product((-1, 1), repeat=3)]
    return u, GraspObject([np.array(corners)], name="pinched box")


def ball_pinch(hand=None, *, position=(0.0, 0.0, 0.0), angles=(0.0, 0.0, 0.0), gap=1.0):
    """A ball between the thumb and index fingertips.

    The ball's centre is midway between the centres of the two fingertips'
    round ends and its radius leaves ``gap`` mm to each: the two contacts are
    opposed through its centre. Held by a hand of these two fingers only (see
    `hand_without`): with the paper's five fingers, the middle finger closes
    on the ball too and pushes it off the line of the pinch.

    Parameters
    ----------
    hand : SynergyHand, optional
        Default: the paper's hand; it must have a thumb ``T`` and an index ``I``.
    position, angles : (3,) float
        Pose of the palm (mm, rad).
    gap : float
        Distance (mm) of the ball from each fingertip; negative, the
        fingertips cut that far into it. Less than half the room between the
        fingertips.

    Returns
    -------
    u : (8,) float
        The configuration, synergies `PINCH_Z`.
    ball : GraspObject
        A subdivided icosahedron (642 vertices), one convex piece.

    Raises
    ------
    TypeError, ValueError
        As `pinch_grasp`.

    Examples
    --------
    >>> u, ball = ball_pinch()
    >>> ball
    GraspObject('pinched ball', 1 pieces, 60 x 60 x 60 mm, L=29.8)
    """
    hand, u, a, b, diameter = _pinch(hand, position, angles, gap)
    radius = diameter / 2.0
    sphere = trimesh.creation.icosphere(subdivisions=3, radius=radius)
    return u, GraspObject([sphere.vertices + (a + b) / 2.0], name="pinched ball")


def hand_without(hand, *fingers):
    """The hand with fingers removed (their chains and the actuated joints only they used).

    Parameters
    ----------
    hand : SynergyHand
    *fingers : str
        Names in ``hand.finger_names``; at least one finger must remain.

    Returns
    -------
    SynergyHand
        Same synergies on the remaining joints, named ``"<name> without <fingers>"``.

    Raises
    ------
    ValueError
        If the hand has no such finger, or none would remain.

    Examples
    --------
    >>> hand = hand_without(SynergyHand.default(), "T")
    >>> hand.finger_names, hand.n_syn
    (['I', 'M', 'R', 'L'], 2)
    """
    unknown = [f for f in fingers if f not in hand.finger_names]
    if unknown or not fingers:
        raise ValueError(f"hand {hand.name!r} has no finger {unknown or fingers!r}; its fingers are {hand.finger_names}")
    if set(hand.finger_names) <= set(fingers):
        raise ValueError(f"removing {list(fingers)} leaves hand {hand.name!r} without fingers")
    data = hand.to_dict()
    data["fingers"] = [f for f in data["fingers"] if f["name"] not in fingers]
    used = {name for f in data["fingers"] for joint in f["joints"] for name, c in joint["coupling"].items() if c}
    keep = [i for i, name in enumerate(data["actuated"]) if name in used]
    for key in ("actuated", "mean_pose", "synergies"):
        data[key] = [data[key][i] for i in keep]
    removed = ", ".join(fingers)
    data["name"] = f"{hand.name} without {removed}"
    return SynergyHand(data, source=f"{hand.source} without {removed}")
