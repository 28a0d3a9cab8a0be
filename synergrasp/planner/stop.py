"""The stop criteria of the paper (Fig. 6) and the grasp quality of the real contacts."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..quality import q_distance


@dataclass(frozen=True)
class GraspCheck:
    """The real grasp at one iteration.

    Attributes
    ----------
    contact : (n,) bool
        Hand points in contact: cP < eps_c.
    n_contacts : int
        N_c of the paper.
    q : float
        g_Q: Q distance of the contacts at their nearest object points, with
        the object's normals there (NaN without contacts).
    palm : bool
        The palm point is in contact (power grasps need it; precision grasps
        must not end with it, and evaluate it only when the rest of their
        criterion holds).
    done : bool
        The paper's stop criterion holds.
    lp_solves : int
    """

    contact: np.ndarray
    n_contacts: int
    q: float
    palm: bool
    done: bool
    lp_solves: int


def check_grasp(obj, status, kind, *, eps_c=5.0, mu=0.3, edges=8, backend="highs", palm_distance=None) -> GraspCheck:
    """Evaluate the paper's stop criterion at a status.

    Precision: N_c >= 3 and g_Q < -0.1, or N_c >= 4 and g_Q < 0, and no palm
    contact. Power: |g_P| < eps_c first (a palm contact), then N_c >= 4 and
    g_Q < -0.1, or N_c >= 6 and g_Q < 0.

    Parameters
    ----------
    obj : GraspObject
    status : Status
        From `synergrasp.planner.status.grasp_status`.
    kind : {"precision", "power"}
    eps_c : float
        Contact threshold (mm).
    palm_distance : callable, optional
        Returns the cP of the palm point, for precision grasps (power grasps
        carry it as their last hand point). Called only when the rest of the
        precision criterion holds, so the LP it costs is paid only then.

    Returns
    -------
    GraspCheck

    Raises
    ------
    TypeError
        If ``obj`` is not a GraspObject or ``status`` not a Status.

    Examples
    --------
    >>> from synergrasp import SynergyHand, objects
    >>> from synergrasp.planner import grasp_status, start_configuration
    >>> hand, obj = SynergyHand.default(), objects.ellipsoid()
    >>> far = grasp_status(hand, obj, start_configuration(hand, obj), "precision")
    >>> check = check_grasp(obj, far, "precision")
    >>> check.n_contacts, check.done
    (0, False)
    """
    from ..objects import GraspObject
    from .status import Status

    if not isinstance(obj, GraspObject) or not isinstance(status, Status):
        raise TypeError(f"check_grasp takes a GraspObject and a Status (grasp_status), got {type(obj).__name__} "
                        f"and {type(status).__name__}")
    cp = status.g[:-1]
    contact = cp < eps_c
    n_c = int(contact.sum())
    q, solves = np.nan, 0
    if n_c:
        res = q_distance(status.nearest[contact], status.normals[contact], mu=mu, edges=edges,
                         center=obj.center, torque_scale=obj.torque_scale, backend=backend)
        q, solves = res.value, res.lp_solves
    if kind == "power":
        palm = bool(abs(cp[-1]) < eps_c)
        done = palm and ((n_c >= 4 and q < -0.1) or (n_c >= 6 and q < 0))
    else:
        done = (n_c >= 3 and q < -0.1) or (n_c >= 4 and q < 0)
        palm = done and palm_distance is not None and palm_distance() < eps_c
        done = done and not palm
    return GraspCheck(contact, n_c, float(q), palm, bool(done), solves)
