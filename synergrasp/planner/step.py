"""The resolved-rate step of the planner: paper Eq. 16 with task priority and limits.

In normalised coordinates (palm position divided by the object's size, so that
every column of the Jacobian is dimensionless) the paper's damped least-squares
step is ``du = J^T (J J^T + lambda I)^-1 dg`` with ``lambda = 1e-5`` when the
smallest eigenvalue of ``J J^T`` is below 1e-5, else 0 (the paper's W^-1 is
the normalisation). The planner applies it with two priority levels
(Siciliano and Slotine's task-priority scheme): the sQ row and the rows of
penetrating hand points first (a power attempt's sQ row only while no row
penetrates), then the other contact rows in their null space. Synergy variables at a limit that the step
would push past are frozen and the step recomputed.
"""

from __future__ import annotations

import numpy as np

from ..hand import LIMIT_TOLERANCE

#: Damping and eigenvalue threshold of paper Eq. 16.
DAMPING = 1e-5


def dls(J, e):
    """Damped least-squares solution of ``J du = e`` (paper Eq. 16).

    Parameters
    ----------
    J : (m, k) float
    e : (m,) float

    Returns
    -------
    du : (k,) float
    pinv : (k, m) float
        The damped pseudo-inverse ``J^T (J J^T + lambda I)^-1``.
    """
    A = J @ J.T
    lam = DAMPING if np.linalg.eigvalsh(A)[0] < DAMPING else 0.0
    pinv = J.T @ np.linalg.inv(A + lam * np.eye(len(A)))
    return pinv @ e, pinv


def priority_step(J1, e1, J2, e2):
    """Two-level task-priority step: task 1 exactly (damped), task 2 in its null space.

    Parameters
    ----------
    J1 : (m1, k) float
    e1 : (m1,) float
    J2 : (m2, k) float
    e2 : (m2,) float

    Returns
    -------
    (k,) float
    """
    d1, pinv1 = dls(J1, e1)
    null = np.eye(J1.shape[1]) - pinv1 @ J1
    d2, _ = dls(J2 @ null, e2 - J2 @ d1)
    return d1 + null @ d2


def limited_step(J, e, z, limits, first):
    """Priority step that respects the synergy limits (active set on the synergy columns).

    Parameters
    ----------
    J : (m, k) float
        Normalised Jacobian.
    e : (m,) float
        Requested change of the (normalised) status.
    z : (s,) float
        Current synergy variables (the last s columns of J).
    limits : (s, 2) float
        Their lower and upper bounds.
    first : (m,) bool
        Rows of the first-priority task; the others are solved in its null space.

    Returns
    -------
    (k,) float
        Normalised step.
    """
    k, s = J.shape[1], len(z)
    free = np.ones(k, bool)
    at_low, at_high = z <= limits[:, 0] + LIMIT_TOLERANCE, z >= limits[:, 1] - LIMIT_TOLERANCE
    for _ in range(s + 1):
        Jf = J * free
        du = priority_step(Jf[first], e[first], Jf[~first], e[~first]) if (~first).any() else dls(Jf, e)[0]
        blocked = (at_low & (du[-s:] < 0)) | (at_high & (du[-s:] > 0))
        blocked &= free[-s:]
        if not blocked.any():
            return du
        free[-s:] &= ~blocked
    return du
