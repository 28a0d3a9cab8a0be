"""The grasp object: a union of convex pieces with a centre and a torque scale."""

from __future__ import annotations

import warnings
from dataclasses import fields
from functools import cached_property

import fcl
import numpy as np
import trimesh

from .._checks import as_vector, numeric, positive_scalar
from .broad_phase import PieceIndex
from .collision import Penetration, penetration
from .contact_distance import ContactDistance, check_points, contact_distance
from .convex import ConvexPiece
from .distance_grid import DistanceGrid
from .mesh_queries import TREE_FACES, MeshQueries
from .point_surface import PointSurface
from .repair import TURNED_OUTWARD, orient_outward, simplify
from .scaled_contacts import ScaledContacts, scaled_contacts


#: A mesh with more faces than this is simplified for the planner's tests against the true surface (`GraspObject.surface`);
#: a mesh that stays larger is queried without trimesh's R-tree (`MeshQueries`).
SURFACE_FACES = TREE_FACES
#: How far (mm) that simplified surface may lie from the mesh.
SURFACE_TOLERANCE = 0.1
#: Largest ``|R R^T - I|`` entry of a transform's rotation taken as a rotation by `GraspObject.transformed` (then
#: made exactly orthonormal): single-precision poses and rounded quaternions are off by up to about 1e-6.
RIGID_TOLERANCE = 1e-5
#: A given torque scale must lie within this factor of the object's bounding radius (a value in other units is refused).
TORQUE_SCALE_RANGE = 100.0
#: A given ``center`` must have its neighbours this far (a fraction of the object's size) along each axis inside too:
#: not on the surface (a point between two pieces is inside).
CENTER_DEPTH = 1e-6
#: Most points a cP or sQ query answers at once: its LP data grow with the points (300,000 at once need about 6.6 GiB),
#: so a larger set is answered in parts of this many, the results joined.
QUERY_CHUNK = 10_000


def _in_chunks(query, obj, points, backend):
    """``query(obj, points, backend)`` (`contact_distance`, `scaled_contacts`), in parts of `QUERY_CHUNK` points."""
    if not (isinstance(points, np.ndarray) and points.ndim == 2 and len(points) > QUERY_CHUNK):
        return query(obj, points, backend)
    parts = [query(obj, points[i:i + QUERY_CHUNK], backend) for i in range(0, len(points), QUERY_CHUNK)]
    joined = {f.name: sum(getattr(r, f.name) for r in parts) if f.name == "lp_solves"
              else np.concatenate([getattr(r, f.name) for r in parts]) for f in fields(parts[0])}
    return type(parts[0])(**joined)


class GraspObject:
    """An object to grasp: a union of convex pieces, its centre c and torque scale L (mm).

    Parameters
    ----------
    pieces : sequence of (k_i, 3) array_like or ConvexPiece
        The convex pieces, each given by any points (its convex hull is used).
    center : (3,) array_like, optional
        Reference point c for torques and for the sQ scaling. Default: the
        volume centroid of the pieces (the mesh's centre of mass when a
        watertight ``mesh`` is given). When that point is outside the pieces
        (a torus), c is moved inside them: to the point a quarter of the way
        from the pieces' surface point nearest the centroid towards the
        centroid of the piece it lies on. The sQ rays need c inside the
        pieces. Where the pieces fill a cavity or a hole of the mesh (a mug's
        inside, often), the centre of mass there is inside the pieces and
        stays, outside the mesh itself.
    torque_scale : float, optional
        Characteristic length L (mm) dividing torques in the wrenches,
        within a factor of `TORQUE_SCALE_RANGE` (100) of the default: the
        radius of the bounding sphere about c, ``max |v - c|`` over all
        vertices (the semi-axis c = 50 mm for the paper's ellipsoid).
    name : str
        Display name.
    mesh : trimesh.Trimesh, optional
        The surface the pieces approximate: shown, sampled for the
        precision seeds and used to judge a grasp on the true surface. A
        watertight mesh wound inward is replaced by a copy turned outward
        (`synergrasp.objects.repair.orient_outward`), with a warning.
    points : (n, 3) array_like, optional
        Points on the surface the pieces approximate, for an object without
        a mesh (a point cloud, `synergrasp.objects.from_points`): a grasp is
        judged on the surface they sample (`point_surface`).
    info : dict, optional
        Provenance (source file, method, cache use...).

    Attributes
    ----------
    convex : tuple of ConvexPiece
        The pieces with their planes and fcl geometry.
    index : PieceIndex
        The pieces stacked for the hand-point queries (`synergrasp.objects.broad_phase`).
    center : (3,) float
    torque_scale : float
    radius : float
        Radius of the bounding sphere about the centre, ``max |v - c|`` over
        the pieces' vertices (mm): the object's size, which normalises the
        planner's steps (the default ``torque_scale``).
    name : str
    mesh : trimesh.Trimesh or None
    points : (n, 3) float or None
    point_surface : PointSurface or None
        The surface ``points`` sample.
    info : dict

    Raises
    ------
    ValueError
        If there are no pieces, or a piece is non-finite or has no volume; a
        ``center`` outside the object, or a ``torque_scale`` far from its size;
        ``points`` that are not a finite (n, 3) array of at least 16 distinct
        rows (`PointSurface`), that do not lie on the pieces' outline (their
        extent not within a factor of 2 of the pieces', or farther than a
        tenth of it outside them: other units or another frame), or given
        with a mesh; a mesh off the pieces' outline in the same way.
    TypeError
        If ``pieces`` is not a list of vertex arrays, or ``mesh`` not a trimesh.Trimesh.

    Examples
    --------
    A 60 x 50 x 90 mm box as one convex piece, given by its corners:

    >>> import itertools
    >>> import numpy as np
    >>> from synergrasp.objects import GraspObject
    >>> corners = np.array(list(itertools.product([-30.0, 30.0], [-25.0, 25.0], [-45.0, 45.0])))
    >>> box = GraspObject([corners], name="box")
    >>> box
    GraspObject('box', 1 pieces, 60 x 50 x 90 mm, L=59.6)
    >>> box.contains([[0.0, 0.0, 0.0], [0.0, 0.0, 50.0]]).tolist()
    [True, False]
    """

    def __init__(self, pieces, *, center=None, torque_scale=None, name: str = "object", mesh=None, points=None,
                 info=None):
        if isinstance(pieces, np.ndarray) and pieces.ndim == 2:
            pieces = [pieces]
        if pieces is None or isinstance(pieces, (str, bytes, dict)) or not hasattr(pieces, "__iter__"):
            raise TypeError(f"pieces must be a list of (k, 3) vertex arrays (the object's convex pieces), got "
                            f"{type(pieces).__name__}")
        pieces = list(pieces)
        if not pieces:
            raise ValueError("pieces is empty: an object needs at least one convex piece")
        self.convex = tuple(
            p if isinstance(p, ConvexPiece) else ConvexPiece(p, name=f"pieces[{i}]") for i, p in enumerate(pieces)
        )
        self.name = str(name)
        if mesh is not None and not isinstance(mesh, trimesh.Trimesh):
            raise TypeError(f"mesh must be a trimesh.Trimesh (the object's true surface) or None, got "
                            f"{type(mesh).__name__}")
        if isinstance(mesh, trimesh.Trimesh):
            mesh, turned = orient_outward(mesh)
            if turned:
                warnings.warn(f"{self.name}: {TURNED_OUTWARD} (in a copy)", UserWarning, stacklevel=2)
        self.mesh = mesh
        if points is not None and mesh is not None:
            raise ValueError("give an object a mesh or surface points, not both: the mesh is its true surface")
        #: The surface ``points`` sample (`PointSurface`), None without points.
        self.point_surface = None if points is None else PointSurface(points)
        if info is not None and not isinstance(info, dict):
            raise TypeError(f"info must be a dict (provenance of the object), got {type(info).__name__}")
        self.info = dict(info or {})
        self.index = PieceIndex(self.convex)
        if self.points is not None:
            self._check_surface(self.points, "points")
        if self.mesh is not None:
            self._check_surface(self.mesh.vertices[:: max(1, len(self.mesh.vertices) // 2000)], "mesh")
        if center is None:
            self.center = self._default_center()
        else:
            self.center = as_vector(center, "center", 3).copy()
            around = self.center + CENTER_DEPTH * self.size * np.vstack([np.eye(3), -np.eye(3)])
            if not self.contains(np.vstack([self.center, around])).all():  # (on a face, rays along it have no exit)
                raise ValueError(
                    f"center {self.center.round(3).tolist()} is outside {self.name} or on its surface: torques are "
                    "taken about it and the sQ rays start there, so it must be inside; omit it to use the default "
                    "(the volume centroid, moved inside if needed)"
                )
        self.radius = radius = float(max(np.linalg.norm(p.vertices - self.center, axis=1).max() for p in self.convex))
        if torque_scale is None:
            self.torque_scale = radius
        else:
            self.torque_scale = positive_scalar(torque_scale, "torque_scale")
            if not radius / TORQUE_SCALE_RANGE <= self.torque_scale <= radius * TORQUE_SCALE_RANGE:
                raise ValueError(
                    f"torque_scale {self.torque_scale:g} is far from the size of {self.name}: it is a length in the "
                    f"object's units (mm), and the default, the radius of its bounding sphere about the centre, is "
                    f"{radius:.3g} mm (a value in metres, such as 0.04, is 40 mm). Give one within a factor of "
                    f"{TORQUE_SCALE_RANGE:g} of it, or omit it"
                )
        self.center.setflags(write=False)

    # ----------------------------------------------------------------- geometry

    @property
    def pieces(self) -> list[np.ndarray]:
        """Vertex arrays of the convex pieces, ``[(k_i, 3) float, ...]``."""
        return [p.vertices for p in self.convex]

    @property
    def n_pieces(self) -> int:
        """Number of convex pieces."""
        return len(self.convex)

    @cached_property
    def bounds(self) -> np.ndarray:
        """(2, 3) float: axis-aligned bounding box ``[min, max]``."""
        allv = np.vstack(self.pieces)
        return np.array([allv.min(axis=0), allv.max(axis=0)])

    @cached_property
    def hull_planes(self) -> np.ndarray:
        """(f, 4) float: facet planes ``[n, o]`` of the convex hull of all the pieces (``n . x + o <= 0`` inside).

        The hull of at most 128 of the pieces' vertices (farthest-point sampled): on or a little inside the full hull.
        """
        return ConvexPiece(np.vstack(self.pieces), name=f"{self.name} hull", max_vertices=128).planes

    @cached_property
    def distance_grid(self) -> DistanceGrid:
        """The pieces' signed-distance bound on a grid around the object (`DistanceGrid`), built on first use."""
        return DistanceGrid(self.index, self.bounds)

    @cached_property
    def surface(self):
        """The mesh the planner tests the true surface on: ``mesh``, simplified when it is large (None without a mesh).

        The precision seeds cast rays into it, and an accepted grasp's
        contacts and depth are judged on it. A mesh of at most
        `SURFACE_FACES` faces is used as it is; a larger closed one is
        simplified (`synergrasp.objects.repair.simplify`) to a surface within
        `SURFACE_TOLERANCE` mm of it, a few thousand faces, built on first use
        (about a second for 300,000 faces): on a fine scan those tests would
        otherwise take seconds each. A large mesh that cannot be simplified
        (not a closed manifold) is used as it is, and queried without trimesh's
        R-tree (`surface_queries`).

        Returns
        -------
        trimesh.Trimesh or None
        """
        if self.mesh is None or len(self.mesh.faces) <= SURFACE_FACES:
            return self.mesh
        coarse = simplify(self.mesh, SURFACE_TOLERANCE)
        return self.mesh if coarse is None else coarse

    @cached_property
    def surface_queries(self):
        """Ray, nearest-point and signed-distance queries on `surface`, built on first use.

        Returns
        -------
        MeshQueries or None
            None without a mesh.
        """
        return None if self.surface is None else MeshQueries(self.surface)

    @cached_property
    def mesh_excess(self) -> float:
        """How far the mesh sticks out of the pieces (mm, >= 0; 0 without a mesh).

        The largest signed-distance bound of the pieces (`PieceIndex.min_plane_bound`)
        at the mesh's vertices. A simplified hull's facets cut inside the surface
        between its vertices, so a shape can be deeper in the mesh than in the
        pieces, by about this much at most: the planner measures the depth in the
        mesh (`synergrasp.planner.stop.mesh_depth`) of the shapes deeper in the
        pieces than its limit less this.
        """
        if self.mesh is None:
            return 0.0
        return max(0.0, float(self.index.min_plane_bound(np.asarray(self.mesh.vertices, dtype=float)).max()))

    @property
    def extents(self) -> np.ndarray:
        """(3,) float: bounding-box side lengths (mm)."""
        return self.bounds[1] - self.bounds[0]

    @property
    def points(self) -> np.ndarray | None:
        """(n, 3) float: the distinct surface points (read-only), None without points."""
        return None if self.point_surface is None else self.point_surface.points

    def _check_surface(self, points, what):
        """Refuse a true surface (``what``: its points or a sample of its mesh's vertices) off the pieces' outline.

        The points span at least half the pieces, or a quarter for a camera view's (``info["swept"]``:
        its pieces swept away from the camera as far again as the view is deep, up to 1 + sqrt(3)
        times the points' span); units wrong by 10, 25.4 or 1000 stay refused.
        """
        spread = float(np.ptp(points, axis=0).max())
        outside = float(self.index.min_plane_bound(points).max())
        low = 0.25 if "swept" in self.info else 0.5
        if not low * self.size <= spread <= 2.0 * self.size or outside > 0.1 * self.size:
            raise ValueError(
                f"the {what} of {self.name} span {spread:.3g} mm and lie up to {max(outside, 0.0):.3g} mm "
                f"outside its pieces, which span {self.size:.3g} mm: give the {what} in the pieces' units (mm) and "
                "frame"
            )

    @property
    def size(self) -> float:
        """Largest bounding-box side (mm)."""
        return float(self.extents.max())

    @cached_property
    def width(self) -> float:
        """An upper bound of the object's smallest width (mm): its least extent along its hull's normals.

        Measured on the object's own surface, the vertices of `surface` (its
        mesh, simplified to within `SURFACE_TOLERANCE` when large; else its
        surface points, else its pieces' vertices): the pieces of a concave
        object can stick out of it by a few mm (a pot with a handle, 158 mm
        across, read 161 mm on its pieces). Taken along the facet normals of
        the hull of at most 128 of those vertices (farthest-point sampled) and
        the coordinate axes. A convex solid is thinnest along a facet normal
        (a box, a slab, a cylinder: then this is exact, however the object is
        turned) or across two of its edges (a tetrahedron: then this reads
        more, up to twice the width of a flat one). The bounding box's
        smallest side grows when the object is turned: a 60 x 200 x 300 mm box
        turned about two axes by 45 degrees spans 292 mm or more along every
        axis, and is 60 mm wide.

        Examples
        --------
        >>> import trimesh
        >>> from synergrasp import objects
        >>> box = objects.from_mesh(trimesh.creation.box((60.0, 200.0, 300.0)), cache=False)
        >>> turned = box.transformed(trimesh.transformations.euler_matrix(np.pi / 4, np.pi / 4, 0.0))
        >>> round(float(turned.extents.min())), round(turned.width)
        (292, 60)
        """
        if self.mesh is None and self.points is None:
            vertices, planes = np.vstack(self.pieces), self.hull_planes
        else:
            vertices = np.asarray(self.surface.vertices if self.mesh is not None else self.points, dtype=float)
            planes = ConvexPiece(vertices, name=f"{self.name} surface hull", max_vertices=128).planes
        directions = np.vstack([planes[:, :3], np.eye(3)])
        return float(min(np.ptp(vertices @ block.T, axis=0).min()
                         for block in np.array_split(directions, -(-len(directions) // 256))))

    @cached_property
    def length(self) -> float:
        """The largest side of the object's smallest enclosing box, whatever its orientation (mm).

        The box is trimesh's `oriented_bounds` of the pieces' vertices: it
        turns with the object, so this does not depend on how the object is
        turned, where the bounding box's largest side (`size`) does (a 37 x 30
        x 21 mm box turned at random spans up to 52 mm along an axis).

        Examples
        --------
        >>> import trimesh
        >>> from synergrasp import objects
        >>> box = objects.from_mesh(trimesh.creation.box((37.0, 30.0, 21.0)), cache=False)
        >>> turned = box.transformed(trimesh.transformations.euler_matrix(0.4, 0.5, 0.6))
        >>> round(turned.size, 1), round(turned.length, 1)
        (50.0, 37.0)
        """
        return float(np.max(trimesh.bounds.oriented_bounds(np.vstack(self.pieces))[1]))

    @property
    def volume(self) -> float:
        """Sum of the pieces' volumes (mm^3; overlapping pieces count twice, and pieces that fill a cavity or a hole
        count it: a mug's reads more than its mesh's ``mesh.volume``)."""
        return float(sum(p.volume for p in self.convex))

    def __repr__(self) -> str:
        ext = " x ".join(f"{e:.0f}" for e in self.extents)
        return f"GraspObject({self.name!r}, {self.n_pieces} pieces, {ext} mm, L={self.torque_scale:.1f})"

    def contains(self, points) -> np.ndarray:
        """Whether each point is inside (or on) some piece.

        Parameters
        ----------
        points : (n, 3) array_like

        Returns
        -------
        (n,) bool
        """
        return self.index.inside(check_points(points))

    def _default_center(self) -> np.ndarray:
        if isinstance(self.mesh, trimesh.Trimesh) and self.mesh.is_watertight and self.mesh.volume > 0:
            g = np.asarray(self.mesh.center_mass, dtype=float)
        else:
            vol = np.array([p.volume for p in self.convex])
            g = (vol[:, None] * np.array([p.centroid for p in self.convex])).sum(axis=0) / vol.sum()
        margin = 1e-3 * float(np.ptp(np.vstack([p.vertices for p in self.convex]), axis=0).max())
        bounds = self.index.plane_bounds(g[None])[0]
        if bounds.min() <= -margin:
            return g
        if bounds.min() <= margin:  # on the skin of a piece (a cut between pieces): step into that piece
            piece = self.convex[int(np.argmin(bounds))]
            return g + 0.25 * (piece.centroid - g)
        # the centroid is outside the object: move it inside
        query = fcl.CollisionObject(fcl.Sphere(0.0), fcl.Transform(g))
        request = fcl.DistanceRequest(enable_nearest_points=True)
        best = (np.inf, None, None)
        for piece in self.convex:
            result = fcl.DistanceResult()
            dist = fcl.distance(query, piece.fcl, request, result)
            if dist < best[0]:
                best = (dist, np.asarray(result.nearest_points[1], dtype=float), piece)
        _, nearest, piece = best
        return nearest + 0.25 * (piece.centroid - nearest)

    def piece_meshes(self) -> list[trimesh.Trimesh]:
        """The convex pieces as trimesh meshes (outward-wound hulls)."""
        return [trimesh.Trimesh(p.vertices, p.facets, process=False) for p in self.convex]

    def to_mesh(self) -> trimesh.Trimesh:
        """``mesh`` if there is one, else the pieces' hulls concatenated (for display)."""
        if self.mesh is not None:
            return self.mesh
        return trimesh.util.concatenate(self.piece_meshes())

    def transformed(self, matrix) -> "GraspObject":
        """A copy moved by a rigid transform.

        Parameters
        ----------
        matrix : (4, 4) array_like
            Homogeneous rigid transform (rotation and translation). A
            rotation within `RIGID_TOLERANCE` of orthonormal (a pose in single
            precision, a quaternion rounded to six digits) is taken as the
            nearest rotation.

        Returns
        -------
        GraspObject
            Pieces, centre, mesh and points moved; same torque scale and name.

        Raises
        ------
        ValueError
            If ``matrix`` is not a finite 4x4 rigid transform.
        """
        try:
            M = numeric(matrix)  # (complex numbers, text and booleans are not real numbers)
        except (TypeError, ValueError, OverflowError):
            raise TypeError(f"matrix must be a (4, 4) array of real numbers, got {type(matrix).__name__}") from None
        if M.shape != (4, 4):
            raise ValueError(f"matrix must be a (4, 4) homogeneous transform, got shape {M.shape}")
        if not np.isfinite(M).all():
            raise ValueError("matrix must be a finite (4, 4) homogeneous transform: it contains NaN or inf")
        R, t = M[:3, :3], M[:3, 3]
        error = float(np.abs(R @ R.T - np.eye(3)).max())
        if not (error <= RIGID_TOLERANCE and np.linalg.det(R) > 0 and np.allclose(M[3], [0, 0, 0, 1])):
            raise ValueError(
                f"matrix must be a rigid transform: a rotation with det +1 (R R^T differs from I by {error:.2g}; at "
                f"most {RIGID_TOLERANCE:g} is taken as the nearest rotation; det {np.linalg.det(R):.3g}), last row "
                f"[0, 0, 0, 1] (got {M[3].tolist()}). Scale the object with scale= when loading it, not here"
            )
        if error > 1e-12:  # the nearest rotation (an exact one is kept as given, bit for bit)
            u, _, vt = np.linalg.svd(R)
            R = u @ vt
            M = np.vstack([np.column_stack([R, t]), [0.0, 0.0, 0.0, 1.0]])
        mesh = None
        if self.mesh is not None:
            mesh = self.mesh.copy()
            mesh.apply_transform(M)
        return GraspObject(
            [p.transformed(R, t) for p in self.convex],
            center=R @ self.center + t,
            torque_scale=self.torque_scale,
            name=self.name,
            mesh=mesh,
            points=None if self.points is None else self.points @ R.T + t,
            info=self.info,
        )

    # ----------------------------------------------------------------- queries

    def contact_distance(self, points, backend="native") -> ContactDistance:
        """cP: pseudo-distance from each hand point to the object, with gradients.

        For each point p the pseudo-distance between A = {p} and every
        candidate piece B (paper Eqs. 1-3, default regular simplex), the
        minimum over the pieces: > 0 outside, 0 on the surface, < 0 inside.
        python-fcl's distances and the pieces' planes prune the pieces that
        cannot be the minimiser (see the documentation's "Contact distance
        (cP)" page); all the LPs of the call are solved as one block-diagonal LP
        (of at most `QUERY_CHUNK` points: a larger set is answered in parts).

        Parameters
        ----------
        points : (n, 3) array_like
            Hand points (mm).
        backend : str or synergrasp.lp.Backend
            LP backend.

        Returns
        -------
        ContactDistance
            ``value`` (n,), ``grad`` (n, 3), ``nearest`` (n, 3),
            ``normal`` (n, 3), ``piece``, ``inside``, ``degenerate``,
            ``candidates``, ``lp_solves``.

        Raises
        ------
        ValueError
            If ``points`` is not a finite (n, 3) array, a point lies farther
            than `synergrasp.objects.contact_distance.MAX_REACH` (1 km) beyond
            the object's size from its centre, or the backend is unknown.
        synergrasp.lp.LPError
            If the backend fails to solve the LP.

        Examples
        --------
        A point 10 mm above the pole of the paper's ellipsoid (semi-axes 30, 40,
        50 mm) and one at its centre:

        >>> import synergrasp as sg
        >>> obj = sg.objects.get("ellipsoid")
        >>> r = obj.contact_distance([[0.0, 0.0, 60.0], [0.0, 0.0, 0.0]])
        >>> r.value.round(2).tolist(), r.inside.tolist()
        ([10.0, -32.85], [False, True])
        >>> round(float(r.grad[0, 2]), 6), (r.nearest[0].round(6) + 0.0).tolist()  # moving up increases cP
        (1.0, [0.0, 0.0, 50.0])

        The pole is a vertex of the pieces' facets, so the derivative there is
        one-sided (``degenerate``): which neighbouring facet's gradient and
        normal come back depends on the LP backend's optimal vertex.

        >>> r.degenerate.tolist()
        [True, True]
        """
        return _in_chunks(contact_distance, self, points, backend)

    def scaled_contacts(self, points, backend="native") -> ScaledContacts:
        """sQ contacts: scale the object about its centre until it touches each hand point.

        For each point p, ``t = max {t : c + t (p - c) in a piece}`` (in closed
        form from the exit facet's plane when the ray leaves one piece through
        the inside of one facet, else one LP per piece the ray leaves last,
        ``max t s.t. c + t (p - c) = sum lambda_v v, sum lambda = 1``), the
        scale ``s = 1 / t``, the contact
        carried back to the object's scale ``c + t (p - c)`` (on its surface),
        and the inward normal from the LP dual. The planner's
        ``g_sQ = q_distance(contact, normal, center=obj.center,
        torque_scale=obj.torque_scale)`` chains its point gradient through
        ``jac_contact`` (``jac_normal`` is zero almost everywhere).

        Parameters
        ----------
        points : (n, 3) array_like
            Hand points (mm), none at the centre.
        backend : str or synergrasp.lp.Backend
            LP backend.

        Returns
        -------
        ScaledContacts
            ``scale`` (n,), ``contact`` (n, 3), ``normal`` (n, 3),
            ``point`` (n, 3), ``grad_scale`` (n, 3), ``jac_contact`` (n, 3, 3),
            ``jac_normal`` (n, 3, 3), ``piece``, ``inside``, ``degenerate``,
            ``lp_solves``.

        Raises
        ------
        ValueError
            If ``points`` is not a finite (n, 3) array, a point coincides with
            the centre or lies farther than
            `synergrasp.objects.contact_distance.MAX_REACH` (1 km) beyond the
            object's size from it, or a ray misses the object (centre outside
            it).
        synergrasp.lp.LPError
            If the backend fails to solve the LP.

        Examples
        --------
        The paper's ellipsoid (50 mm to its pole) scaled about its centre until
        it touches a point 100 mm above the centre, and one 25 mm above it:

        >>> import synergrasp as sg
        >>> obj = sg.objects.get("ellipsoid")
        >>> s = obj.scaled_contacts([[0.0, 0.0, 100.0], [0.0, 0.0, 25.0]])
        >>> s.scale.round(6).tolist(), s.inside.tolist()
        ([2.0, 0.5], [False, True])
        >>> (s.contact.round(6) + 0.0).tolist()        # both carried back to the pole
        [[0.0, 0.0, 50.0], [0.0, 0.0, 50.0]]
        """
        return _in_chunks(scaled_contacts, self, points, backend)

    def penetration(self, segments, radius, box=None, *, clear=True) -> Penetration:
        """Deepest penetration of capsules (hand links), and of a box (the palm), into the object, by python-fcl.

        Parameters
        ----------
        segments : (k, 2, 3) array_like
            End points of the capsules' axes (mm).
        radius : float or (k,) array_like
            Capsule radii (mm), > 0.
        box : tuple, optional
            ``(centre (3,), axes (3, 3), half_extents (3,))`` of a box (mm; its
            axes a rotation's columns), measured after the capsules.
        clear : bool
            Measure the distance of the shapes that do not touch the object
            too (default). False: those read +inf, and only the shapes that
            touch a piece (fcl's collision test) are measured: about half
            the time at the hand's poses in power plans.

        Returns
        -------
        Penetration
            ``depth`` (mm, 0 if none), ``index`` of the deepest shape (-1 if
            none), per-shape ``depths`` and signed ``distances`` (the box
            last), ``piece``, ``witnesses``.

        Raises
        ------
        ValueError
            If ``segments`` is not a finite (k, 2, 3) array, a radius is not > 0
            or above `synergrasp.objects.collision.MAX_RADIUS` (500 mm), or ``box``
            is not a finite box with positive half extents and a rotation.
        TypeError
            If ``box`` is not a tuple of three numeric arrays, or a radius is a bool.

        Examples
        --------
        A 20 mm cube whose corner region holds a box 2 mm deep:

        >>> import numpy as np, trimesh
        >>> from synergrasp import objects
        >>> cube = objects.from_mesh(trimesh.creation.box((20.0, 20.0, 20.0)), cache=False)
        >>> far = [[[100.0, 0.0, 0.0], [120.0, 0.0, 0.0]]]
        >>> pen = cube.penetration(far, 5.0, box=([0.0, 0.0, 15.0], np.eye(3), [4.0, 4.0, 7.0]))
        >>> pen.index, round(pen.depth, 6)      # the box (entry 1) is 2 mm inside the top face
        (1, 2.0)
        """
        return penetration(self, segments, radius, box, clear=clear)

