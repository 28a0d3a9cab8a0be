"""`replay_reach`: an executable reach run in MuJoCo with the object free: does the hand push it away before closing?

The palm follows the reach (`synergrasp.PlanResult.path`: the approach from
the pre-grasp, then the close, or both at once), the fingers' servos its synergies, and then
the synergies squeeze as in the hold test (`synergrasp.physics.validate`).
The object is a free body that nothing holds or damps: every contact on the
way moves it. The `Replay` says how far it moved by the time the hand had
closed, and after the squeeze.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np

from .._checks import as_points, positive_scalar
from ..planner import PlanResult, hand_and_object
from .protocol import protocol as make_protocol
from .simulate import mujoco_module, simulate_reach
from .validate import check_match, squeeze_targets

__all__ = ["Replay", "replay_reach"]

#: Slowest replay speed (mm/s) taken: the CPU time grows as 1 / speed (the default, 100 mm/s, takes about a second).
MIN_SPEED = 5.0


@dataclass(frozen=True)
class Replay:
    """A reach replayed in MuJoCo (`replay_reach`).

    Attributes
    ----------
    moved : (k,) float
        Displacement of the object's centre (mm) from its planned pose when
        the hand reaches each row of the path.
    turned : (k,) float
        Rotation of the object (degrees), likewise.
    moved_before_closed, turned_before_closed : float
        The last entries: how far the object moved and turned before the
        hand had closed on it (at the grasp).
    moved_after_squeeze, turned_after_squeeze : float
        After the squeeze and settling.
    first_contact : int
        The row of the path the hand was moving to when it first touched the
        object (0: touching at the start; -1: it never did before the
        squeeze).
    contact_bodies : list of str
        Hand geoms touching the object at the end.
    outcome : str
        ``"done"``, or ``"unstable"`` (MuJoCo's instability warning or an
        explosion; the measurements stop there, NaN after).
    reason : str
    speed : float
        Speed of the hand's fastest point along the path (mm/s).
    duration : float
        Simulated time (s).
    squeeze_z : (n_syn,) float
        Synergy targets of the squeeze.
    protocol : dict
        The `Protocol` used (friction, contact softness, servos, squeeze).
    object_name, hand_name : str
    cpu_time : float
        CPU time of the replay (s).
    """

    moved: np.ndarray
    turned: np.ndarray
    first_contact: int
    moved_after_squeeze: float
    turned_after_squeeze: float
    contact_bodies: list
    outcome: str
    reason: str
    speed: float
    duration: float
    squeeze_z: np.ndarray
    protocol: dict
    object_name: str = ""
    hand_name: str = ""
    cpu_time: float = 0.0

    @property
    def moved_before_closed(self) -> float:
        """Displacement (mm) of the object when the hand has closed at the grasp."""
        return float(self.moved[-1])

    @property
    def turned_before_closed(self) -> float:
        """Rotation (degrees) of the object when the hand has closed at the grasp."""
        return float(self.turned[-1])


def replay_reach(result_or_path, obj, *, hand=None, preset="synergrasp", speed=100.0, backend="native",
                 **protocol) -> Replay:
    """Replay an executable reach in MuJoCo with the object free: approach, close, squeeze.

    Parameters
    ----------
    result_or_path : PlanResult or (k, 6 + n_syn) array_like
        A plan result with an executable reach (`PlanResult.path`; checked
        against ``obj`` and ``hand`` as `synergrasp.validate` checks it), or a
        path (pre-grasp first, grasp last, e.g. `synergrasp.planner.Reach.path`).
    obj : GraspObject
        The object, at the pose it was planned in.
    hand : SynergyHand, optional
        Default: ``SynergyHand.default()``.
    preset : {"synergrasp", "dexgraspbench"} or Protocol
        Contact, servo and squeeze settings (see `synergrasp.physics.PRESETS`);
        the pushes of the hold test are not part of a replay.
    speed : float
        Speed (mm/s) of the hand's fastest capsule end or palm corner along
        the path.
    backend : str
        LP backend of the squeeze's contact queries.
    **protocol
        Fields of `synergrasp.physics.Protocol` to change.

    Returns
    -------
    Replay

    Raises
    ------
    ImportError
        If MuJoCo is not installed (``pip install "synergrasp[sim]"``).
    TypeError
        If ``obj`` is not a GraspObject or ``hand`` not a SynergyHand.
    ValueError
        A result without an executable reach or from another object or hand,
        a path that does not fit the hand (or whose synergies lie outside its
        limits), a grasp that touches nothing (no squeeze), a ``speed`` below
        `MIN_SPEED` (5 mm/s), a replay of more than
        `synergrasp.physics.protocol.MAX_STEPS` time steps, or a bad protocol
        setting.

    Examples
    --------
    >>> import synergrasp as sg
    >>> from synergrasp.physics import replay_reach
    >>> cup = sg.objects.get("cup")
    >>> result = sg.plan(cup, "precision")
    >>> replay = replay_reach(result, cup)
    >>> replay.outcome, len(replay.moved) == len(result.path)
    ('done', True)
    >>> bool(replay.moved_before_closed < 5.0)          # mm: the hand did not knock the cup away
    True
    """
    start = time.process_time()
    mujoco_module()  # MuJoCo missing: said first
    hand = hand_and_object(hand, obj)
    settings = make_protocol(preset, **protocol)
    if isinstance(result_or_path, PlanResult):
        if len(result_or_path.path) == 0:
            raise ValueError("the result has no executable reach (no grasp was found, or it was planned with "
                             "executable_reach=False): nothing to replay")
        check_match(result_or_path, obj, hand, settings.contact_distance)
        path = np.asarray(result_or_path.path, dtype=float)
    else:
        path = result_or_path
    path = as_points(path, "path", dim=hand.n_u)
    speed = positive_scalar(speed, "speed")
    if speed < MIN_SPEED:
        raise ValueError(f"speed {speed:g} mm/s is slower than {MIN_SPEED:g} mm/s: the replay's simulated time grows as "
                         "1 / speed (at 0.1 mm/s, about a minute of CPU). speed is in mm/s (default 100), not m/s")
    hand.check_synergies(path[:, 6:], "the path's synergies")
    z, _ = squeeze_targets(hand, obj, path[-1], settings.squeeze, settings.contact_distance, backend)
    squeezed = np.r_[path[-1, :6], z]
    measured = simulate_reach(hand, obj, path, hand.joint_angles(squeezed), settings, speed)
    return Replay(speed=speed, squeeze_z=z, protocol=settings.to_dict(), object_name=obj.name, hand_name=hand.name,
                  cpu_time=time.process_time() - start, **measured)
