"""Built-in objects (mm): the paper's ellipsoid and turned household objects.

Solids of revolution are given by a profile, radius r against height z along
the +z axis, and cut into convex pieces at the profile's convex kinks: the
solid ``{sqrt(x^2 + y^2) <= r(z)}`` is convex exactly where r(z) is concave, so
each maximal run of non-increasing slopes dr/dz becomes one convex piece (the
hull of its rings of vertices). Adjacent pieces share their cut ring, so the
union of the pieces is the polygonal solid of revolution of the profile, with
no gaps. The smooth profiles are approximated to ``tolerance`` mm: part by the
polyline through the profile's knots, part by the polygons of the rings.

The built-ins are solid: a real cup or bell is hollow, but a hand grasps
them from outside, and a solid keeps the object's centre inside it, which the
sQ rays need (see the documentation's "Scaled Q distance (sQ)" page).
"""

from __future__ import annotations

import numpy as np
import trimesh

from .._checks import as_points, positive_scalar
from .grasp_object import GraspObject

#: Default largest gap (mm) between a built-in shape's polytope pieces and its smooth surface.
TOLERANCE = 0.5
#: Share of ``tolerance`` given to the profile polyline (the rest goes to the ring polygons).
_PROFILE_SHARE = 0.4
#: Finest ``tolerance`` accepted, relative to the shape's largest radius or semi-axis: a ring of about 290
#: sides, an ellipsoid's polytope of 40 962 vertices (finer ones took minutes to build, and no grasp needs them).
MIN_TOLERANCE = 1e-4


def _fine_enough(tol: float, size: float, what: str) -> None:
    """Refuse a tolerance (mm) below `MIN_TOLERANCE` times ``size`` (mm), the shape's largest ``what``."""
    if tol < MIN_TOLERANCE * size:
        raise ValueError(f"tolerance {tol:g} mm is finer than synergrasp builds a shape to: at least {MIN_TOLERANCE:g} "
                         f"of its largest {what} ({size:g} mm), {MIN_TOLERANCE * size:.3g} mm")


def _simplify(profile: np.ndarray, tol: float) -> np.ndarray:
    """Douglas-Peucker simplification of an open polyline (keeps both ends)."""
    keep = np.zeros(len(profile), dtype=bool)
    keep[[0, -1]] = True
    stack = [(0, len(profile) - 1)]
    while stack:
        i, j = stack.pop()
        if j <= i + 1:
            continue
        a, b = profile[i], profile[j]
        ab = b - a
        rel = profile[i + 1 : j] - a
        t = np.clip(rel @ ab / (ab @ ab), 0.0, 1.0)
        dist = np.linalg.norm(rel - t[:, None] * ab, axis=1)
        k = int(np.argmax(dist))
        if dist[k] > tol:
            keep[i + 1 + k] = True
            stack += [(i, i + 1 + k), (i + 1 + k, j)]
    return profile[keep]


def _convex_runs(r: np.ndarray, z: np.ndarray) -> list[tuple[int, int]]:
    """Knot ranges [i0, i1] on which the piecewise-linear r(z) is concave."""
    slope = np.diff(r) / np.diff(z)
    runs, start = [], 0
    for i in range(1, len(slope)):
        if slope[i] > slope[i - 1] + 1e-9 * (1.0 + abs(slope[i - 1])):
            runs.append((start, i))
            start = i
    runs.append((start, len(r) - 1))
    return runs


def _ring_sides(r_max: float, tol: float) -> int:
    """Sides (a multiple of 4, >= 8) of a regular polygon of circumradius r_max within tol of its circle."""
    if r_max <= tol:
        return 8
    sides = np.pi / np.arccos(1.0 - tol / r_max)
    return max(8, int(4 * np.ceil(sides / 4.0)))


def revolve(
    profile, *, name: str = "solid of revolution", tolerance: float = TOLERANCE, center=None, torque_scale=None
) -> GraspObject:
    """A solid of revolution about the z axis, cut into convex slabs.

    Parameters
    ----------
    profile : (m, 2) array_like
        Knots ``(r, z)`` from bottom to top: radius r >= 0 (mm) at height z,
        z strictly increasing. The solid is closed by flat discs at both ends
        (an end with r = 0 is a pole). Dense samples of a smooth curve are
        fine: the profile is simplified to ``tolerance``.
    name : str
        Object name.
    tolerance : float
        Largest deviation (mm) of the polygonal solid from the smooth one;
        at least `MIN_TOLERANCE` times the largest radius.
    center : (3,) array_like, optional
        Reference point; default the volume centroid (on the axis).
    torque_scale : float, optional
        Default: the bounding-sphere radius about the centre.

    Returns
    -------
    GraspObject
        One convex piece per concave run of the profile, with its trimesh
        ``mesh`` (the same polygonal solid, watertight).

    Raises
    ------
    ValueError
        If the profile is not (m, 2) with m >= 2, has a negative radius, a
        non-increasing z, or no volume, or ``tolerance`` is not positive or
        below `MIN_TOLERANCE` times the largest radius.

    Examples
    --------
    A spool, 100 mm tall, 60 mm across at the ends and 40 mm at its waist: the
    waist is a convex kink of the profile, so it comes in two convex pieces.

    >>> import synergrasp as sg
    >>> spool = sg.objects.revolve([[30.0, 0.0], [20.0, 50.0], [30.0, 100.0]], name="spool")
    >>> spool
    GraspObject('spool', 2 pieces, 60 x 60 x 100 mm, L=58.3)
    >>> spool.contains([[0.0, 0.0, 50.0], [25.0, 0.0, 50.0]]).tolist()
    [True, False]
    """
    prof = as_points(profile, "profile", dim=2)
    tol = positive_scalar(tolerance, "tolerance")
    prof = prof.copy()
    prof[np.abs(prof[:, 0]) <= 1e-6 * np.abs(prof[:, 0]).max(), 0] = 0.0  # poles of sampled curves
    r, z = prof[:, 0], prof[:, 1]
    if len(prof) < 2:
        raise ValueError("profile needs at least 2 knots (r, z)")
    if (r < 0).any():
        raise ValueError(f"profile has negative radii at knots {np.nonzero(r < 0)[0].tolist()}")
    if (np.diff(z) <= 0).any():
        raise ValueError("profile heights z must be strictly increasing from bottom to top")
    if not (r[1:-1] > 0).all() or r.max() <= 0:
        raise ValueError("profile radii must be > 0 between the end knots; the solid has no volume otherwise")
    _fine_enough(tol, float(r.max()), "radius")
    prof = _simplify(prof, _PROFILE_SHARE * tol)
    r, z = prof[:, 0], prof[:, 1]
    sides = _ring_sides(float(r.max()), (1.0 - _PROFILE_SHARE) * tol)
    angle = 2.0 * np.pi * np.arange(sides) / sides
    circle = np.column_stack([np.cos(angle), np.sin(angle)])

    def ring(i):
        if r[i] == 0:
            return np.array([[0.0, 0.0, z[i]]])
        return np.column_stack([r[i] * circle, np.full(sides, z[i])])

    pieces = [np.vstack([ring(i) for i in range(i0, i1 + 1)]) for i0, i1 in _convex_runs(r, z)]
    line = np.vstack([[0.0, z[0]], prof, [0.0, z[-1]]])
    line = line[np.r_[True, np.any(np.diff(line, axis=0) != 0, axis=1)]]  # drop repeated pole knots
    mesh = trimesh.creation.revolve(line[::-1], sections=sides)
    if mesh.volume < 0:
        mesh.invert()
    return GraspObject(
        pieces,
        name=name,
        mesh=mesh,
        center=mesh.center_mass if center is None else center,
        torque_scale=torque_scale,
        info={"source": "builtin", "method": "revolve", "profile_knots": len(prof), "ring_sides": sides},
    )


def _sample(f, z0, z1, n=400):
    z = np.linspace(z0, z1, n)
    return np.column_stack([f(z), z])


def ellipsoid(a: float = 30.0, b: float = 40.0, c: float = 50.0, *, tolerance: float = TOLERANCE) -> GraspObject:
    """The paper's test object: an ellipsoid with semi-axes a, b, c along x, y, z (mm).

    One convex piece: an icosphere mapped onto the ellipsoid, subdivided until
    the inscribed polytope is within ``tolerance`` mm of the surface
    (a 642-vertex polytope, 0.21 mm, for the default 30/40/50 mm).

    Parameters
    ----------
    a, b, c : float
        Semi-axes (mm).
    tolerance : float
        Largest gap (mm) between the polytope's faces and the ellipsoid; at
        least `MIN_TOLERANCE` times the largest semi-axis.

    Returns
    -------
    GraspObject
        Centre at the origin, torque scale ``max(a, b, c)``.

    Raises
    ------
    ValueError
        If a semi-axis or ``tolerance`` is not a positive number, or
        ``tolerance`` is below `MIN_TOLERANCE` times the largest semi-axis.

    Examples
    --------
    >>> import synergrasp as sg
    >>> obj = sg.objects.ellipsoid()          # the paper's object, semi-axes 30, 40, 50 mm
    >>> obj
    GraspObject('ellipsoid 30/40/50', 1 pieces, 60 x 80 x 100 mm, L=50.0)
    >>> len(obj.pieces[0]), bool(obj.info["max_gap"] < 0.5)   # vertices, faceting error (mm)
    (642, True)
    >>> sg.objects.ellipsoid(40, 40, 40).extents.round(1).tolist()   # a 40 mm sphere
    [80.0, 80.0, 80.0]
    """
    axes = np.array([positive_scalar(a, "a"), positive_scalar(b, "b"), positive_scalar(c, "c")])
    tol = positive_scalar(tolerance, "tolerance")
    _fine_enough(tol, float(axes.max()), "semi-axis")
    for level in range(1, 7):
        sphere = trimesh.creation.icosphere(subdivisions=level)
        vertices = sphere.vertices * axes
        gap = _ellipsoid_gap(vertices, sphere.faces, axes)
        if gap <= tol:
            break
    mesh = trimesh.Trimesh(vertices, sphere.faces, process=False)
    return GraspObject(
        [vertices],
        name=f"ellipsoid {a:g}/{b:g}/{c:g}",
        mesh=mesh,
        center=np.zeros(3),
        info={"source": "builtin", "method": "icosphere", "subdivisions": level, "max_gap": gap, "semi_axes": axes},
    )


def _ellipsoid_gap(vertices, faces, axes) -> float:
    """Largest normal gap between an inscribed polytope's faces and the ellipsoid (first order)."""
    tri = vertices[faces]
    pts = np.concatenate([tri.mean(axis=1), 0.5 * (tri + np.roll(tri, 1, axis=1)).reshape(-1, 3)])
    g = np.sqrt(((pts / axes) ** 2).sum(axis=1))
    grad = pts / axes**2 / g[:, None]
    return float(((1.0 - g) / np.linalg.norm(grad, axis=1)).max())


def cup(*, tolerance: float = TOLERANCE) -> GraspObject:
    """A drinking cup: 80 mm tall, 75 mm across the rim, 54 mm at the base (solid).

    The body flares from the base to a rounded rim bead; the flare (r(z)
    convex) makes it non-convex, so it comes in several slabs.

    Parameters
    ----------
    tolerance : float
        Largest gap (mm) between the pieces and the smooth surface (see `revolve`).

    Returns
    -------
    GraspObject

    Examples
    --------
    >>> cup().n_pieces
    6
    """
    body = lambda z: 27.0 + 9.5 * ((z - 4.0) / 72.0) ** 1.6  # noqa: E731
    foot = np.array([[25.5, 0.0], [26.6, 0.6], [27.0, 2.0], [27.0, 4.0]])
    bead = np.array([[36.9, 77.0], [37.5, 78.2], [37.5, 79.2], [36.8, 80.0]])
    profile = np.vstack([foot, _sample(body, 4.0, 76.0, 200)[1:], bead])
    return revolve(profile, name="cup", tolerance=tolerance)


def bell(*, tolerance: float = TOLERANCE) -> GraspObject:
    """A hand bell: flared mouth 90 mm across, body 75 mm tall, handle with a 30 mm knob (solid).

    Total height 132 mm: a flared lip (non-convex), a domed crown, a 12 mm
    thick handle neck and a ball knob on top.

    Parameters
    ----------
    tolerance : float
        Largest gap (mm) between the pieces and the smooth surface (see `revolve`).

    Returns
    -------
    GraspObject

    Examples
    --------
    >>> bell().n_pieces
    9
    """
    z_waist, r_mouth, r_waist = 22.0, 45.0, 30.5
    flare = lambda z: r_waist + (r_mouth - r_waist) * (1.0 - z / z_waist) ** 2  # noqa: E731
    crown = lambda z: np.sqrt(np.clip(1.0 - ((z - z_waist) / 53.0) ** 2, 0.0, None)) * r_waist  # noqa: E731
    lip = np.array([[43.0, 0.0], [45.0, 1.0]])
    body = _sample(flare, 1.2, z_waist, 120)
    dome = _sample(crown, z_waist, 74.0, 200)[1:]
    neck_r, neck_top, knob_r = 6.0, 102.0, 15.0
    knob_c = neck_top + np.sqrt(knob_r**2 - neck_r**2)
    knob = lambda z: np.sqrt(np.clip(knob_r**2 - (z - knob_c) ** 2, 0.0, None))  # noqa: E731
    dome = dome[dome[:, 0] > neck_r + 0.5]
    neck = np.array([[neck_r, dome[-1, 1] + 2.0], [neck_r, neck_top]])
    ball = _sample(knob, neck_top, knob_c + knob_r, 200)[1:]
    profile = np.vstack([lip, body, dome, neck, ball])
    return revolve(profile, name="bell", tolerance=tolerance)


def goblet(*, tolerance: float = TOLERANCE) -> GraspObject:
    """A wine goblet: 160 mm tall, a 76 mm bowl on a 9 mm stem, a 68 mm foot (solid).

    Three convex pieces: a domed foot, the stem and the bowl (half an
    ellipsoid narrowing slightly to a 68 mm rim).

    Parameters
    ----------
    tolerance : float
        Largest gap (mm) between the pieces and the smooth surface (see `revolve`).

    Returns
    -------
    GraspObject

    Examples
    --------
    >>> goblet().n_pieces
    3
    """
    foot = np.array([[34.0, 0.0], [34.0, 2.0], [32.0, 4.0], [27.0, 6.5], [18.0, 9.0], [4.5, 12.0]])
    R, zc, H = 38.0, 110.0, 40.0
    z_join = zc - H * np.sqrt(1.0 - (4.5 / R) ** 2)
    lower = lambda z: R * np.sqrt(np.clip(1.0 - ((z - zc) / H) ** 2, 0.0, None))  # noqa: E731
    upper = lambda z: R - 4.0 * ((z - zc) / 50.0) ** 2  # noqa: E731
    profile = np.vstack([foot, _sample(lower, z_join, zc, 300), _sample(upper, zc, 160.0, 100)[1:]])
    return revolve(profile, name="goblet", tolerance=tolerance)


#: name -> factory of the built-in objects.
BUILTINS = {"ellipsoid": ellipsoid, "cup": cup, "bell": bell, "goblet": goblet}
