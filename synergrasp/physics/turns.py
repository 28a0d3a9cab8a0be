"""A grasp validated with the whole scene turned: how far its verdict depends on the world frame.

`validate` pushes the object along the world's six axis directions. Turning
the scene, object and hand together, by one of the 24 rotations that map the
axes onto the axes (`AXIS_TURNS`) permutes those pushes among themselves, so
the test is the same; only the simulation's arithmetic differs (the contacts'
order, the solver's sweeps), and for a grasp near a threshold that decides.
`validate_turns` validates a grasp at several such turns: the share that
held says how far to trust the verdict.
"""

from __future__ import annotations

import itertools
import warnings

import numpy as np
from scipy.spatial.transform import Rotation

from .._checks import as_vector
from ..hand import rotation_xyz
from ..planner import PlanResult
from .validate import validate


def _axis_turns():
    turns = [np.eye(3)[list(order)] * np.array(signs)[:, None]
             for order in itertools.permutations(range(3)) for signs in itertools.product((1.0, -1.0), repeat=3)]
    return np.array([R for R in turns if np.linalg.det(R) > 0])


#: (24, 3, 3) float: the rotations that map the axes onto the axes, the identity first.
AXIS_TURNS = _axis_turns()


def turned_scene(obj, u, rotation):
    """An object and a hand configuration turned together about the origin.

    Parameters
    ----------
    obj : GraspObject
    u : (6 + n_syn,) array_like
        Hand configuration ``[px, py, pz, phi1, phi2, phi3, z...]`` (mm, rad).
    rotation : (3, 3) array_like
        A rotation matrix.

    Returns
    -------
    GraspObject, (6 + n_syn,) float
        The object turned (`GraspObject.transformed`) and the configuration
        whose palm is turned likewise (position and XYZ Euler angles; the
        synergies unchanged).

    Examples
    --------
    >>> import synergrasp as sg
    >>> obj, hand = sg.objects.get("ellipsoid"), sg.SynergyHand.default()
    >>> u = sg.planner.start_configuration(hand, obj)
    >>> moved, v = turned_scene(obj, u, AXIS_TURNS[5])
    >>> bool(np.allclose(hand.points(v, "precision"), hand.points(u, "precision") @ AXIS_TURNS[5].T))
    True
    """
    R = np.asarray(rotation, dtype=float)
    M = np.eye(4)
    M[:3, :3] = R
    moved = obj.transformed(M)  # (checks that R is a rotation)
    v = as_vector(u, "u").copy()
    v[:3] = R @ v[:3]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # (angles at their lock: the rotation is still exact)
        v[3:6] = Rotation.from_matrix(R @ rotation_xyz(v[3:6])).as_euler("XYZ")
    return moved, v


def validate_turns(result_or_u, obj, turns=6, **settings) -> list:
    """`validate` a grasp as planned, then with the scene turned by the next of `AXIS_TURNS`.

    Parameters
    ----------
    result_or_u : PlanResult or (6 + n_syn,) array_like
        As for `validate` (a PlanResult is checked against ``obj`` and the
        hand once, unturned).
    obj : GraspObject
    turns : int
        Validations, 1 to 24: the grasp as planned, then turned by
        ``AXIS_TURNS[1:turns]``.
    **settings
        Keywords of `validate` (``hand``, ``preset``, ``retreat``,
        ``backend`` and protocol fields).

    Returns
    -------
    list of Validation
        One per turn, the unturned first. ``sum(v.held for v in ...)`` is how
        many held.

    Raises
    ------
    ValueError
        If ``turns`` is not an integer from 1 to 24; and as `validate`.
    """
    if isinstance(turns, bool) or not isinstance(turns, (int, np.integer)) or not 1 <= turns <= len(AXIS_TURNS):
        raise ValueError(f"turns must be an integer from 1 to {len(AXIS_TURNS)} (the rotations that map the axes onto "
                         f"the axes), got {turns!r}")
    first = validate(result_or_u, obj, **settings)
    u = result_or_u.u if isinstance(result_or_u, PlanResult) else result_or_u
    return [first] + [validate(v, moved, **settings)
                      for moved, v in (turned_scene(obj, u, R) for R in AXIS_TURNS[1:turns])]
