"""The stop criteria of the paper (Fig. 6), the grasp quality of the real contacts, and the grasp on the true surface.

`check_grasp` is the paper's criterion on the convex pieces; `surface_check`
moves the contacts to the object's true surface and judges them there, and
`mesh_depth` measures how deep the phalanx capsules are in it (both on
`GraspObject.surface`: the mesh, simplified within 0.1 mm when it is large;
for a point cloud, `GraspObject.point_surface`: planes fitted to the cloud).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .._checks import integer, positive_scalar
from ..hand import grasp_kind
from ..objects import GraspObject
from ..quality import q_distance
from .status import Status


@dataclass(frozen=True)
class SurfaceCheck:
    """A grasp's contacts moved to the object's true surface (`surface_check`).

    Attributes
    ----------
    points : (c, 3) float
        The closest points of the true surface.
    normals : (c, 3) float
        Its inward normals there.
    gap : float
        Largest distance from a claimed contact to the true surface (mm).
    q : float
        Q distance of the contacts on the true surface (NaN with fewer than two); for a point cloud the larger
        of those with the fitted normals and with the pieces' normals.
    """

    points: np.ndarray
    normals: np.ndarray
    gap: float
    q: float


def surface_check(obj, points, normals, *, mu=0.3, edges=8, backend="native") -> SurfaceCheck:
    """The grasp of contacts ``points`` judged on the object's true surface.

    The convex pieces the planner works on cover the object's concavities and
    facet its curves; a grasp is judged on the surface they approximate: the
    object's mesh (`GraspObject.surface`; its closest points and their face
    normals, `GraspObject.surface_queries`), or the surface its points sample (a point cloud,
    `GraspObject.point_surface`: the feet on planes fitted to the nearest
    points, a contact over a gap of the cloud as far as its nearest point).
    An object with neither is its pieces: the contacts and ``normals`` stay
    as they are. A cloud's fitted normals are estimates (near an edge the
    plane blends two faces), so its Q is the larger of the Q distances of the
    feet with the fitted normals and with the pieces' ``normals``: the grasp
    must be force-closed under both.

    Parameters
    ----------
    obj : GraspObject
    points : (c, 3) float
        Contacts on the pieces.
    normals : (c, 3) float
        Their inward normals on the pieces.
    mu, edges : float, int
    backend : str

    Returns
    -------
    SurfaceCheck

    Examples
    --------
    Three contacts 120 degrees apart on a ball's equator, claimed 2 mm outside its surface:

    >>> from synergrasp import objects
    >>> ball = objects.ellipsoid(30.0, 30.0, 30.0)
    >>> t = 2 * np.pi * np.arange(3) / 3
    >>> ring = np.c_[np.cos(t), np.sin(t), np.zeros(3)]
    >>> s = surface_check(ball, 32.0 * ring, -ring)
    >>> round(s.gap, 1), bool(s.q < -0.1)      # 2 mm off; force-closed on the surface
    (2.0, True)
    """
    points = np.asarray(points, dtype=float).reshape(-1, 3)
    normals = np.asarray(normals, dtype=float).reshape(-1, 3)
    if obj.point_surface is not None and len(points):
        closest, gap, inward = obj.point_surface.closest(points, normals, obj.contains)
    elif obj.mesh is None or not len(points):
        closest, gap, inward = points, np.zeros(len(points)), normals
    else:
        closest, gap, triangle = obj.surface_queries.closest(points)
        inward = -obj.surface.face_normals[triangle]
    q = np.nan
    if len(points) >= 2:
        q = q_distance(closest, inward, mu=mu, edges=edges, center=obj.center, torque_scale=obj.torque_scale,
                       backend=backend, checked=True).value
        if obj.point_surface is not None:  # a cloud's normals are estimates: force-closed with the pieces' too
            q = max(q, q_distance(closest, normals, mu=mu, edges=edges, center=obj.center,
                                  torque_scale=obj.torque_scale, backend=backend, checked=True).value)
    return SurfaceCheck(closest, inward, float(gap.max()) if len(gap) else 0.0, float(q))


def mesh_depth(obj, capsules, radius, *, spacing=0.5) -> np.ndarray:
    """Penetration depth of capsules in the object's true surface (mm, >= 0).

    A capsule's depth is its radius plus the largest signed distance into the
    mesh (`GraspObject.surface_queries`, positive inside), or below the planes fitted to a point
    cloud (`PointSurface.signed_distance`), over points along its axis at most
    ``spacing`` apart, floored at 0: the depth of its deepest point, within
    ``spacing / 2``. The convex pieces' depth (python-fcl,
    `GraspObject.penetration`) can be smaller where the true surface sticks
    out of them (`GraspObject.mesh_excess`).

    Parameters
    ----------
    obj : GraspObject
        An object with a mesh (a watertight one for the inside test) or
        surface points.
    capsules : (k, 2, 3) float
        Each capsule's axis end points (mm).
    radius : float
        Capsule radius (mm).
    spacing : float
        Largest distance between axis samples (mm).

    Returns
    -------
    (k,) float

    Raises
    ------
    ValueError
        If the object has neither a mesh nor points (its pieces are then its
        surface: use `GraspObject.penetration`), or ``capsules`` is not
        (k, 2, 3) finite.

    Examples
    --------
    A 16 mm capsule whose axis runs 5 mm outside a box's face and one 20 mm out:

    >>> import trimesh
    >>> from synergrasp import objects
    >>> box = objects.from_mesh(trimesh.creation.box((100.0, 100.0, 100.0)), cache=False)
    >>> axes = np.array([[[-20.0, 0.0, 55.0], [20.0, 0.0, 55.0]], [[-20.0, 0.0, 70.0], [20.0, 0.0, 70.0]]])
    >>> mesh_depth(box, axes, 8.0).round(3).tolist()
    [3.0, 0.0]
    """
    if obj.mesh is None and obj.points is None:
        raise ValueError(f"{obj.name} has no mesh nor points: its convex pieces are its surface, whose penetration "
                         "GraspObject.penetration measures")
    capsules = np.asarray(capsules, dtype=float)
    if capsules.ndim != 3 or capsules.shape[1:] != (2, 3) or not np.isfinite(capsules).all():
        raise ValueError(f"capsules must be a finite (k, 2, 3) array of axis end points, got shape {capsules.shape}")
    radius, spacing = positive_scalar(radius, "radius"), positive_scalar(spacing, "spacing")
    if not len(capsules):
        return np.zeros(0)
    counts = np.maximum(2, np.ceil(np.linalg.norm(capsules[:, 1] - capsules[:, 0], axis=1) / spacing).astype(int) + 1)
    t = np.concatenate([np.linspace(0.0, 1.0, n) for n in counts])[:, None]
    a, b = np.repeat(capsules[:, 0], counts, axis=0), np.repeat(capsules[:, 1], counts, axis=0)
    samples = a + t * (b - a)
    inside = obj.surface_queries.signed_distance(samples) if obj.mesh is not None else \
        obj.point_surface.signed_distance(samples, obj.contains)
    return np.maximum(0.0, np.maximum.reduceat(inside, np.r_[0, np.cumsum(counts)[:-1]]) + radius)


#: The paper's stop criterion per grasp type: (N_c with g_Q < -0.1, N_c with g_Q < 0); N_c counts
#: the fingertips of a precision grasp, the phalanges and the palm of a power grasp.
CRITERION = {"precision": (3, 4), "power": (4, 6)}


@dataclass(frozen=True)
class GraspCheck:
    """The real grasp at one iteration.

    Attributes
    ----------
    contact : (n,) bool
        Status rows in contact: contact rows (`Status.contact`) with cP < eps_c.
    n_contacts : int
        N_c of the paper.
    q : float
        g_Q: Q distance of the contacts at their nearest object points, with
        the object's normals there (NaN without contacts).
    palm : bool
        The palm is in contact, ``|cP| < eps_c`` of the palm row (power grasps
        need it; precision grasps must not end with it).
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


def check_grasp(obj, status, kind, *, eps_c=5.0, mu=0.3, edges=8, backend="native", steered=None) -> GraspCheck:
    """Evaluate the paper's stop criterion at a status.

    Precision: N_c >= 3 and g_Q < -0.1, or N_c >= 4 and g_Q < 0, and no palm
    contact or overlap (N_c counts the fingertips). Power: |g_P| < eps_c first (a palm
    contact), then N_c >= 4 and g_Q < -0.1, or N_c >= 6 and g_Q < 0 (N_c
    counts the phalanges and the palm). The counts are `CRITERION`'s. On an
    object only three fingertips can reach (``steered``: the thumb, index and
    middle, `synergrasp.planner.starts.pinch_fingertips`), N_c >= 3 and
    g_Q < 0 also stops: every fingertip that can touch it then touches it,
    which is what the paper's N_c >= 4 asks of a hand whose five can.

    Parameters
    ----------
    obj : GraspObject
    status : Status
        From `synergrasp.planner.status.grasp_status`.
    kind : {"precision", "power"}
    eps_c : float
        Contact threshold (mm).
    mu : float
        Friction coefficient of the contacts' cones.
    edges : int
        Edges of each cone's polyhedral approximation.
    backend : str or synergrasp.lp.Backend
        LP backend of g_Q.
    steered : int, optional
        Precision only: how many fingertips the attempt steers into contact
        (`pinch_fingertips`); the criterion's second count is at most this,
        and never below its first (3). Default: all of them (the paper's
        criterion).

    Returns
    -------
    GraspCheck

    Raises
    ------
    TypeError
        If ``obj`` is not a GraspObject or ``status`` not a Status.
    ValueError
        If ``kind`` is not "precision" or "power", or not the status's,
        ``eps_c`` is not a positive number, or ``steered`` is given for a power
        grasp or is not an integer >= 1.

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
    if not isinstance(obj, GraspObject) or not isinstance(status, Status):
        raise TypeError(f"check_grasp takes a GraspObject and a Status (grasp_status), got {type(obj).__name__} "
                        f"and {type(status).__name__}")
    grasp_kind(kind)
    if (kind == "power") != bool(status.contact.all()):  # every row of a power status is a contact
        raise ValueError(f"the status is of a {'precision' if kind == 'power' else 'power'} grasp, not a {kind} one: "
                         f"pass the kind it was built for (grasp_status(..., kind))")
    eps_c = positive_scalar(eps_c, "eps_c")
    few, many = CRITERION[kind]
    if steered is not None:
        if kind != "precision":
            raise ValueError("steered counts the fingertips of a precision grasp: leave it out for a power grasp")
        many = max(few, min(many, integer(steered, "steered", what="the fingertips the attempt steers")))
    cp = status.g[:-1]
    contact = (cp < eps_c) & status.contact
    n_c = int(contact.sum())
    q, solves = np.nan, 0
    if n_c:
        res = q_distance(status.nearest[contact], status.normals[contact], mu=mu, edges=edges,
                         center=obj.center, torque_scale=obj.torque_scale, backend=backend, checked=True)
        q, solves = res.value, res.lp_solves
    palm = bool(abs(cp[-1]) < eps_c)
    closed = (n_c >= few and q < -0.1) or (n_c >= many and q < 0)
    done = palm and closed if kind == "power" else cp[-1] >= eps_c and closed  # precision: the palm clear
    return GraspCheck(contact, n_c, float(q), palm, bool(done), solves)
