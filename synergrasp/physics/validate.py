"""`validate`: check a planned grasp (or any configuration) in MuJoCo, and the squeeze it uses."""

from __future__ import annotations

import os
import time
import warnings

import numpy as np
import trimesh

from ..hand import POINT_KINDS, rotation_xyz
from ..lp import get_backend
from ..planner import PlanResult, forget_warm_starts, hand_and_object
from .protocol import protocol as make_protocol
from .result import Validation
from .simulate import mujoco_module, simulate

__all__ = ["validate", "squeeze_targets", "check_match"]

#: Farthest ``retreat`` (mm): far beyond any hand's reach, the palm is simply away from the object.
MAX_RETREAT = 1000.0


def check_match(result, obj, hand, tolerance):
    """Check that a plan result belongs to this object and this hand.

    Parameters
    ----------
    result : PlanResult
    obj : GraspObject
    hand : SynergyHand
    tolerance : float
        Largest distance (mm) of the result's contact points from the surface
        of the object's convex pieces, where the planner put them.

    Raises
    ------
    ValueError
        If the result records another hand (`PlanResult.hand`), the
        configuration does not fit the hand, the contact labels are not the
        hand's, or the contacts lie off the object's surface.

    Warns
    -----
    UserWarning
        If the result records another object's name (`PlanResult.object_name`)
        while its contacts lie on this object's surface: a similar object
        passes the test above.
    """
    if not hand.made(result.hand):
        raise ValueError(f"the result was planned with hand {result.hand!r}, not with this hand {hand.identity!r} (the "
                         "name and a digest of its definition): pass the planning hand as hand= "
                         "(SynergyHand.from_file of its hand file)")
    u = np.asarray(result.u, dtype=float)
    if u.shape != (hand.n_u,):
        raise ValueError(f"the result's configuration u has {u.size} entries but hand {hand.name!r} takes {hand.n_u} "
                         f"({hand.u_labels}): a result planned with another hand? Pass that hand as hand=")
    labels = set(hand.point_labels(result.grasp if result.grasp in POINT_KINDS else "precision"))
    foreign = sorted(set(result.contact_labels) - labels)
    if foreign:
        raise ValueError(f"the result's contacts {foreign} are not {result.grasp} points of hand {hand.name!r} "
                         f"({sorted(labels)}): a result planned with another hand? Pass that hand as hand=")
    if len(result.contact_points):
        points = np.asarray(result.contact_points, dtype=float).reshape(-1, 3)
        gap = np.min([trimesh.proximity.closest_point(piece, points)[1] for piece in obj.piece_meshes()], axis=0)
        if gap.max() > tolerance:
            which = ("another scale or pose of it" if result.object_name == obj.name else
                     f"another object ({result.object_name!r}), another pose of it or another scale")
            raise ValueError(
                f"the result's contact points lie up to {gap.max():.1f} mm from the surface of {obj.name!r} (more than "
                f"{tolerance:g} mm): it was planned for {which} (an object file in metres or centimetres is loaded "
                "with scale=1000 or 10, as it was for the plan)")
    if result.object_name != obj.name:
        warnings.warn(f"the result was planned for an object named {result.object_name!r}, not {obj.name!r}: its "
                      f"contacts lie within {tolerance:g} mm of this object's surface, so it is simulated on it; check "
                      "that this is the object it was planned for", UserWarning, stacklevel=3)


def _check_arguments(result_or_u, obj) -> None:
    """Refuse, with what to do instead, a file path or a name where `validate` takes objects in memory."""
    if isinstance(result_or_u, (str, os.PathLike)):
        raise TypeError(f"result_or_u must be a PlanResult or a configuration u, got the {type(result_or_u).__name__} "
                        f"{str(result_or_u)!r}: read a saved result first, sg.PlanResult.load(path)")
    if isinstance(obj, (str, os.PathLike)):
        raise TypeError(f"obj must be a GraspObject, got the {type(obj).__name__} {str(obj)!r}: load the object first, "
                        f"sg.objects.get({str(obj)!r}) (with the scale it was planned at)")
    if isinstance(obj, PlanResult):
        raise TypeError("obj must be a GraspObject, got a PlanResult: the result comes first, validate(result, obj)")


class NoContact(ValueError):
    """A configuration with no hand point near enough to the object to squeeze it: not a grasp of it."""


def retreat_distance(value) -> float:
    """``validate``'s ``retreat`` as a float, checked.

    Parameters
    ----------
    value : float
        Distance (mm) the palm is moved back along its normal.

    Returns
    -------
    float

    Raises
    ------
    ValueError
        If it is not a number from 0 to `MAX_RETREAT` (text and booleans are not numbers).
    """
    try:
        if isinstance(value, (str, bytes, bool, np.bool_)):  # "40" or True would read as a distance
            raise TypeError(type(value).__name__)
        retreat = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"retreat must be a finite number of mm, got {value!r}") from None
    if not np.isfinite(retreat):
        raise ValueError(f"retreat must be a finite number of mm, got {value!r}")
    if retreat < 0:
        raise ValueError(f"retreat must be >= 0 mm (the palm is moved back, away from the object), got {value!r}")
    if retreat > MAX_RETREAT:
        raise ValueError(f"retreat must be at most {MAX_RETREAT:g} mm (a negative control a hand's length back), got "
                         f"{value!r}: is it in mm?")
    return retreat


def squeeze_targets(hand, obj, u, squeeze, contact_distance, backend="native"):
    """The synergies closed a step past ``u``: each contact pushed into the object.

    The hand points (fingertips, phalanx and palm points) closer than
    ``contact_distance`` to the object are the contacts; if none is, or none
    moves with the synergies (the palm point alone), the skin points of the
    phalanges and the palm (`SynergyHand.skin_and_jacobian`, where the
    planner also reads contacts; the point of the palm's face that the
    planner reads besides, `palm_face_point`, moves with no synergy and would
    add nothing to the step), labelled by their segment. The direction of the
    step in synergy space is ``g = sum_i J_i^T n_i``, the steepest increase of
    the contacts' motion into the object (``J_i`` = d point_i / d z, ``n_i``
    the object's inward normal at the point nearest to it), and its length
    makes that motion ``squeeze`` mm on average over the contacts. Its cP
    queries start cold (`forget_warm_starts`), so the squeeze does not depend
    on what was solved before.

    Parameters
    ----------
    hand : SynergyHand
    obj : GraspObject
    u : (6 + n_syn,) float
    squeeze : float
        Mean motion of the contacts into the object (mm).
    contact_distance : float
        Contact threshold (mm, cP).
    backend : str
        LP backend of the cP queries.

    Returns
    -------
    z : (n_syn,) float
        The squeezed synergy values (``u``'s own if the synergies cannot
        move the contacts, e.g. when the palm point is the only one).
    labels : list of str
        The contacts' hand points.

    Raises
    ------
    NoContact
        If no hand point is within ``contact_distance`` of the object.

    Examples
    --------
    A box pinched between the thumb and index fingertips, squeezed by 10 mm:

    >>> import synergrasp as sg
    >>> from synergrasp.physics import pinch_grasp
    >>> hand = sg.SynergyHand.default()
    >>> u, box = pinch_grasp(hand)
    >>> z, labels = squeeze_targets(hand, box, u, 10.0, 5.0)
    >>> labels                            # the two fingertips and the index's distal phalanx
    ['T0', 'I0', 'I3']
    >>> bool(z[1] < u[7])                 # z2 decreases: the hand closes
    True
    """
    forget_warm_starts(get_backend(backend), obj)  # its LPs start cold: the same squeeze in any process
    points, jacobians, labels = [], [], []
    for kind in POINT_KINDS:
        p, jac = hand.points_and_jacobian(u, kind)
        points.append(p)
        jacobians.append(jac[:, :, 6:])
        labels += hand.point_labels(kind)
    points, jacobians = np.vstack(points), np.vstack(jacobians)
    near = obj.contact_distance(points, backend=backend)
    contact = near.value < contact_distance
    if not np.abs(jacobians[contact]).any():  # the planner also reads contacts anywhere on a phalanx's skin
        skin, palm, skin_jac, palm_jac = hand.skin_and_jacobian(u)
        points = np.vstack([skin.reshape(-1, 3), palm])
        jacobians = np.vstack([skin_jac.reshape(-1, 3, hand.n_u), palm_jac])[:, :, 6:]
        labels = [segment for segment in hand.point_labels("power")[:-1] for _ in range(skin.shape[1])]
        labels += ["P"] * len(palm)
        near = obj.contact_distance(points, backend=backend)
        contact = near.value < contact_distance
    if not contact.any():
        raise NoContact(
            f"no hand point is within {contact_distance:g} mm of {obj.name!r} (the nearest has a contact distance cP of "
            f"{near.value.min():.1f}, which reads mm near the surface and more than the distance away from it): "
            "this configuration does not grasp the object (another object, or the hand is not at its grasp)")
    normals, jac = near.normal[contact], jacobians[contact]
    direction = np.einsum("ia,iak->k", normals, jac)
    rate = float(np.einsum("ia,iak,k->i", normals, jac, direction).mean())  # mm per unit step, = |direction|^2 / n
    step = direction * (squeeze / rate) if rate > 1e-9 else np.zeros(hand.n_syn)  # e.g. the palm point alone
    return u[6:] + step, [lab for lab, c in zip(labels, contact) if c]


def validate(result_or_u, obj, *, hand=None, preset="synergrasp", retreat=0.0, backend="native", **protocol) -> Validation:
    """Test a grasp in MuJoCo: squeeze, settle, then push the object along six directions.

    The protocol (the documentation's "Physics validation" page): the hand is
    placed at the configuration with its palm welded to the world and the
    object free; the synergies close a step further (`squeeze_targets`) while
    the object is damped, and the grasp settles; then, from the settled state
    each time, a force ``mass * acceleration`` pushes the object along -x, +x,
    -y, +y, -z and +z (world axes, no gravity). The grasp holds when the
    object's displacement and rotation stay under the thresholds along every
    direction.

    Parameters
    ----------
    result_or_u : PlanResult or (6 + n_syn,) array_like
        A plan result (checked against ``obj`` and ``hand``) or a
        configuration ``[px, py, pz, phi1, phi2, phi3, z...]`` (mm, rad).
    obj : GraspObject
        The object, at the pose it was planned in.
    hand : SynergyHand, optional
        Default: ``SynergyHand.default()``.
    preset : {"synergrasp", "dexgraspbench"} or Protocol
        Settings to start from (see `synergrasp.physics.PRESETS`).
    retreat : float
        Move the palm this far (mm) back along its normal after the squeeze is
        set: a negative control (40 mm must not hold).
    backend : str
        LP backend of the cP queries (contacts of the squeeze and the check of
        a result's contacts).
    **protocol
        Fields of `synergrasp.physics.Protocol` to change.

    Returns
    -------
    Validation

    Raises
    ------
    ImportError
        If MuJoCo is not installed (``pip install "synergrasp[sim]"``).
    TypeError
        If ``obj`` is not a GraspObject (a name or a file path: load it
        first) or ``hand`` not a SynergyHand, or ``result_or_u`` is a file
        path (read it with `PlanResult.load`).
    ValueError
        A result from another object or hand, a configuration that touches
        nothing or whose synergies lie outside the hand's limits, an unknown
        or out-of-range protocol setting, or a bad ``retreat``.

    Examples
    --------
    A box pinched between the thumb and index fingertips holds; the same
    hand 40 mm further back does not:

    >>> import synergrasp as sg
    >>> from synergrasp.physics import pinch_grasp
    >>> u, box = pinch_grasp()
    >>> check = sg.validate(u, box)
    >>> check.held, check.outcome, check.contact_bodies
    (True, 'held', ['T3', 'I3'])
    >>> bool(check.displacement.max() < 1.0)            # mm, under each of the six pushes
    True
    >>> sg.validate(u, box, retreat=40.0).outcome
    'no contact'
    """
    start = time.process_time()
    mujoco = mujoco_module()
    _check_arguments(result_or_u, obj)
    hand = hand_and_object(hand, obj)
    settings = make_protocol(preset, **protocol)
    retreat = retreat_distance(retreat)
    if isinstance(result_or_u, PlanResult):
        check_match(result_or_u, obj, hand, settings.contact_distance)
        u = np.asarray(result_or_u.u, dtype=float)
        hand.check_synergies(u[6:], "the result's synergies")
    else:
        try:
            u = hand.check_u(result_or_u)
        except TypeError:
            raise TypeError(f"result_or_u must be a PlanResult or a configuration u, got {type(result_or_u).__name__}") from None
        hand.check_synergies(u[6:], "the configuration's synergies")
    try:
        z, _ = squeeze_targets(hand, obj, u, settings.squeeze, settings.contact_distance, backend)
    except NoContact as error:
        if isinstance(result_or_u, PlanResult) and not result_or_u.success:  # say why: the plan has no grasp
            raise NoContact(f"{error}; the plan found no grasp ({result_or_u.reason})") from None
        raise
    placed = u.copy()
    placed[:3] -= retreat * rotation_xyz(u[3:6])[:, 2]
    squeezed = placed.copy()
    squeezed[6:] = z
    measured = simulate(hand, obj, placed, hand.joint_angles(placed), hand.joint_angles(squeezed), settings)
    return Validation(
        held=measured["outcome"] == "held", squeeze_z=z, u=placed, retreat=retreat, protocol=settings.to_dict(),
        object_name=obj.name, hand_name=hand.name, hand=hand.identity, cpu_time=time.process_time() - start,
        mujoco_version=mujoco.__version__, **measured,
    )
