"""Closing open meshes before decomposition: welding seams and capping holes, or a clear refusal.

A mesh that is not watertight has no inside, so it cannot be decomposed into convex
solids. `close_mesh` repairs it where that is sound and says what it changed:

1. clean-up (trimesh): exact duplicate vertices merged, duplicate and degenerate
   faces dropped;
2. seams welded (manifold3d's ``Mesh.merge``): vertices along open edges that
   coincide within ``WELD_TOLERANCE`` of the mesh's size are joined, which closes
   cracks left by exporters that duplicate vertices with round-off;
3. holes capped: every loop of open edges that lies in a plane (no vertex farther
   than ``PLANARITY`` of the loop's size from its best-fit plane) and does not cross
   itself there is triangulated in that plane (``manifold3d.triangulate``), the
   cap wound to match the surface. A box without its lid gets its lid back; a cup
   without its top becomes a closed cup.

The result must be a closed, consistently oriented 2-manifold (checked by building a
``manifold3d.Manifold`` from it) with a positive volume, and the caps at most
``MAX_CAP_FRACTION`` of its surface. Anything else is refused with a `ValueError`
(`RepairError`) that says why (a loop that is not planar or crosses itself, open boundaries that
touch at a vertex, edges shared by more than two faces, a surface that would be
mostly cap), rather than guessed at.

`orient_outward` turns a closed mesh wound inward (or inconsistently) outward: its normals must
point out of the solid for the planner's tests against the true surface. `simplify` gives a closed
mesh with fewer faces within a tolerance of it (those tests on a large scan). `separate_parts`
finds the parts of a mesh that no face joins and the gap between them (a file holding several
objects, or a scan with a loose fragment); `drop_debris` removes the parts of negligible volume that lie
apart from the rest (a scan's specks) or enclose nothing (a ground plane, a label). `union_of_bodies` joins the closed shells of a mesh that pass through
each other (an assembly exported as one mesh) into the surface of the solid they enclose.
"""

from __future__ import annotations

import numpy as np
import trimesh

class RepairError(ValueError):
    """An open mesh that `close_mesh` cannot close soundly; ``reason`` says why, the message names the mesh.

    Parameters
    ----------
    what : str
        The mesh's name.
    reason : str
        Why it cannot be closed.
    """

    def __init__(self, what: str, reason: str):
        self.what, self.reason = what, reason
        super().__init__(f"{what} is not watertight and cannot be closed soundly: {reason}. Close it in a mesh editor")


#: A hole's loop is planar when no vertex is farther than this fraction of the loop's
#: diameter from its best-fit plane.
PLANARITY = 0.1
#: Seams are welded where open-edge vertices lie within this fraction of the mesh's size of
#: each other (1 um on a 100 mm object: exporter round-off, not a gap in the model).
WELD_TOLERANCE = 1e-5
#: The caps may make up at most this fraction of the closed surface's area.
MAX_CAP_FRACTION = 0.5


#: What `orient_outward` did when it made a copy, in words (the loader and `GraspObject` warn with it).
TURNED_OUTWARD = ("its faces were wound inward or inconsistently (their normals pointed into the solid); they were "
                  "turned outward")


def orient_outward(mesh: trimesh.Trimesh):
    """A watertight mesh wound consistently with its faces facing out: ``mesh`` itself if it is, else a fixed copy.

    Exporters sometimes write a closed surface wound inward (a negative
    volume) or with some faces flipped; its normals then point into the
    solid, and every test against it (the planner's depth in the true mesh,
    the surface samples of its seeds) reads inside as outside. Each body of
    the mesh is wound consistently and turned outward
    (``trimesh.repair.fix_normals``).

    Parameters
    ----------
    mesh : trimesh.Trimesh

    Returns
    -------
    oriented : trimesh.Trimesh
        ``mesh`` when it is not watertight (`close_mesh` orients what it
        closes) or already outward, else an outward copy.
    changed : bool
        Whether a copy was made.

    Examples
    --------
    >>> import trimesh
    >>> box = trimesh.creation.box(extents=[60.0, 50.0, 40.0])
    >>> box.faces = box.faces[:, ::-1]  # every face wound the other way: inside out
    >>> fixed, changed = orient_outward(box)
    >>> changed, round(float(fixed.volume)), round(float(box.volume))
    (True, 120000, -120000)
    """
    if not mesh.is_watertight or (mesh.is_winding_consistent and mesh.volume > 0):
        return mesh, False
    fixed = mesh.copy()
    trimesh.repair.fix_normals(fixed, multibody=True)
    return fixed, True


def close_mesh(mesh: trimesh.Trimesh, what: str = "mesh"):
    """A closed (watertight) version of an open mesh, and what was done to it.

    Parameters
    ----------
    mesh : trimesh.Trimesh
        A mesh with finite vertices that is not watertight.
    what : str
        The mesh's name in messages.

    Returns
    -------
    closed : trimesh.Trimesh
        Watertight, consistently wound, outward facing.
    report : dict
        ``removed_faces`` (duplicate or degenerate), ``welded_vertices``,
        ``holes_filled``, ``cap_area`` (mm^2 of new surface), ``cap_fraction``
        (of the closed surface), ``volume`` (mm^3, of the closed mesh) and
        ``method`` (``"capped"`` if holes were filled, else ``"welded"``, or
        ``"cleaned"`` when dropping duplicate faces was enough).

    Raises
    ------
    RepairError
        (a ValueError) If the mesh cannot be closed soundly; ``reason`` says why.

    Examples
    --------
    A 60 mm cube without its top face gets it back:

    >>> import trimesh
    >>> box = trimesh.creation.box(extents=[60.0, 60.0, 60.0])
    >>> open_box = trimesh.Trimesh(box.vertices, box.faces[box.face_normals[:, 2] < 0.5])
    >>> closed, report = close_mesh(open_box, "open box")
    >>> closed.is_watertight, report["holes_filled"], round(report["cap_area"]), round(report["volume"])
    (True, 1, 3600, 216000)
    """
    work = trimesh.Trimesh(np.asarray(mesh.vertices, dtype=float), np.asarray(mesh.faces), process=True)
    keep = work.unique_faces() & work.nondegenerate_faces()
    removed = int((~keep).sum())
    if removed:
        work.update_faces(keep)
        work.remove_unreferenced_vertices()
    report = {"removed_faces": removed, "welded_vertices": 0, "holes_filled": 0, "cap_area": 0.0}
    if len(work.faces) == 0:
        raise RepairError(what, "none of its faces has an area")
    counts = np.bincount(_edge_use(work.edges_sorted))
    shared = int((counts > 2).sum())
    if shared:
        raise RepairError(what, f"{shared} edges are shared by more than two faces (non-manifold)")
    if not work.is_watertight:
        welded = _weld(work)
        if welded is not None:
            work, report["welded_vertices"] = welded
    if not work.is_watertight:
        work, caps = _cap_holes(work, what)
        report["holes_filled"], report["cap_area"] = len(caps), float(sum(caps))
    manifold = _manifold(work)
    if manifold is None:
        raise RepairError(what, "its faces do not close into a consistently oriented surface")
    volume = float(manifold.volume())
    if volume < 0:
        work.invert()
        volume = -volume
    if volume <= 0:
        raise RepairError(what, "it encloses no volume once its holes are capped (a sheet or loose triangles, "
                                "not the surface of a solid)")
    report["cap_fraction"] = report["cap_area"] / float(work.area)
    if report["cap_fraction"] > MAX_CAP_FRACTION:
        raise RepairError(what, f"it is mostly open: the caps would make {report['cap_fraction']:.0%} of the closed "
                                f"surface (at most {MAX_CAP_FRACTION:.0%}), a solid guessed rather than modelled")
    report["volume"] = volume
    report["method"] = "capped" if report["holes_filled"] else "welded" if report["welded_vertices"] else "cleaned"
    return work, report


def simplify(mesh: trimesh.Trimesh, tolerance: float):
    """A closed mesh with fewer faces whose surface is everywhere within ``tolerance`` of the original.

    manifold3d's ``Manifold.simplify``: it keeps a subset of the vertices and
    moves no surface by more than ``tolerance``. A finely tessellated scan
    of 300,000 faces keeps about 5,000-15,000 at 0.1 mm.

    Parameters
    ----------
    mesh : trimesh.Trimesh
        A closed, consistently oriented mesh.
    tolerance : float
        Largest distance (mm) the surface may move.

    Returns
    -------
    trimesh.Trimesh or None
        The simplified mesh, or None if ``mesh`` is not a closed oriented
        2-manifold (manifold3d refuses it).

    Examples
    --------
    >>> import trimesh
    >>> ball = trimesh.creation.icosphere(subdivisions=6, radius=30.0)
    >>> coarse = simplify(ball, 0.1)
    >>> len(ball.faces), len(coarse.faces) < len(ball.faces) // 4, coarse.is_watertight
    (81920, True, True)
    """
    built = _manifold(mesh)
    if built is None:
        return None
    out = built.simplify(float(tolerance)).to_mesh64()
    return trimesh.Trimesh(np.asarray(out.vert_properties)[:, :3], np.asarray(out.tri_verts), process=False)


#: Spacing (mesh units, mm) of the surface samples with which `separate_parts` measures the gaps, and
#: the bounds of their number.
PART_SPACING = 3.0
PART_SAMPLES = (2000, 20000)
#: Largest number of parts, the largest by area, between which `separate_parts` measures the gaps.
MAX_PARTS = 32


def separate_parts(mesh: trimesh.Trimesh):
    """How many parts a mesh has that no face joins, and the widest gap that must be bridged to join them.

    Parts are the connected components of the faces through shared vertex
    positions (a triangle soup whose corners coincide is one part). The gap
    between two parts is the smallest distance between points of their
    surfaces: their vertices and samples about `PART_SPACING` apart (at
    least and at most `PART_SAMPLES` in all), so it is exact for parts that
    touch at a vertex and otherwise within about the spacing. The parts are
    joined by the shortest gaps first (a minimum spanning tree) and the
    widest of those is returned: 0 for parts that touch or overlap, like a
    handle modelled apart from a mug's body; the distance between two
    objects saved in one file. A part inside another closed part (the wall
    of a cavity) is not apart from it. Only the `MAX_PARTS` largest parts
    by area are measured.

    Parameters
    ----------
    mesh : trimesh.Trimesh

    Returns
    -------
    parts : int
        Number of parts.
    gap : float
        The widest gap joining them (mesh units); 0 for one part.

    Examples
    --------
    >>> import trimesh
    >>> a = trimesh.creation.box((10.0, 10.0, 10.0))
    >>> parts, gap = separate_parts(trimesh.util.concatenate([a, a.copy().apply_translation([30.0, 0.0, 0.0])]))
    >>> parts, round(gap, 6)
    (2, 20.0)
    """
    vertices = np.asarray(mesh.vertices, dtype=float)
    face_label = _part_labels(mesh)
    parts = np.unique(face_label)
    if len(parts) < 2:
        return int(len(parts)), 0.0
    area = np.bincount(face_label, weights=mesh.area_faces)
    measured = parts[np.argsort(-area[parts], kind="stable")][:MAX_PARTS]
    measured = measured[~_enclosed(mesh, face_label, measured)]  # a cavity's wall is not a part apart
    if len(measured) < 2:
        return int(len(parts)), 0.0
    count = int(np.clip(area.sum() / PART_SPACING**2, *PART_SAMPLES))
    samples, sampled = trimesh.sample.sample_surface(mesh, count, seed=0)
    points = np.vstack([vertices[np.asarray(mesh.faces).reshape(-1)], samples])
    point_label = np.r_[np.repeat(face_label, 3), face_label[sampled]]
    return int(len(parts)), joining_gap([points[point_label == label] for label in measured])


def joining_gap(groups) -> float:
    """The widest gap that must be bridged to join groups of points into one.

    The groups are joined by their shortest gaps first (a minimum spanning
    tree of the smallest distances between their points), and the widest of
    those gaps is returned.

    Parameters
    ----------
    groups : list of (n_i, 3) float
        At least two groups, each of at least one point.

    Returns
    -------
    float
        0 when the groups touch or overlap.

    Examples
    --------
    >>> import numpy as np
    >>> joining_gap([np.zeros((1, 3)), np.array([[5.0, 0, 0]]), np.array([[25.0, 0, 0]])])
    20.0
    """
    from scipy.sparse.csgraph import minimum_spanning_tree
    from scipy.spatial import cKDTree

    trees = [cKDTree(group) for group in groups]
    gaps = np.zeros((len(trees), len(trees)))
    for i in range(len(trees)):
        for j in range(i + 1, len(trees)):
            gaps[i, j] = trees[j].query(trees[i].data, k=1)[0].min()
    return float(minimum_spanning_tree(np.triu(np.maximum(gaps, 1e-300), 1)).toarray().max())  # (0 is no edge)


def drop_debris(mesh: trimesh.Trimesh, fraction: float, gap: float):
    """The mesh without its debris: parts of negligible volume that lie apart from the rest or enclose nothing.

    Parts are those of `separate_parts`. A part is small when the volume of
    its convex hull is at most ``fraction`` of the largest part's (a flat
    part has none). A small part is debris when its surface comes no nearer
    than ``gap`` to the surface of the parts that are not small (a speck or a
    stray triangle of a scan, which would make the object larger than it is
    and its decomposition coarser), or when it is flat and open (a ground
    plane, a label or a stray triangle, which encloses nothing and whose
    edges would be capped as holes of the object). A small part near the
    rest that is closed or has some depth (a knob, a button, a knob's open
    cap) is kept.

    Parameters
    ----------
    mesh : trimesh.Trimesh
        A mesh with finite vertices.
    fraction : float
        Largest hull volume of a small part, as a fraction of the largest
        part's; 0 keeps every part.
    gap : float
        Least distance of closed debris from the rest (mesh units).

    Returns
    -------
    kept : trimesh.Trimesh
        ``mesh`` itself when no part is debris, else a copy without the debris.
    dropped : list of dict
        Per part dropped: ``faces`` (its number of faces), ``size`` (its
        largest bounding-box side), ``distance`` (from the rest's surface;
        mesh units) and ``open`` (whether it encloses nothing: a flat sheet,
        when it lies within ``gap``).

    Examples
    --------
    A 60 mm box, a speck of radius 1 mm 300 mm away, and a 200 mm square sheet the box stands on:

    >>> import trimesh
    >>> speck = trimesh.creation.icosphere(subdivisions=0, radius=1.0).apply_translation([300.0, 0.0, 0.0])
    >>> sheet = trimesh.Trimesh([[-100, -100, -30], [100, -100, -30], [100, 100, -30], [-100, 100, -30]],
    ...                         [[0, 1, 2], [0, 2, 3]])
    >>> kept, dropped = drop_debris(trimesh.util.concatenate([trimesh.creation.box((60.0, 60.0, 60.0)), speck, sheet]),
    ...                             1e-3, 10.0)
    >>> len(kept.faces), [(d["faces"], round(d["size"], 1), round(d["distance"]), d["open"]) for d in dropped]
    (12, [(2, 200.0, 0, True), (20, 1.7, 269, False)])
    """
    from scipy.spatial import ConvexHull, QhullError

    if fraction <= 0.0 or mesh.body_count < 2:  # (vertices joined by edges: one body is one part)
        return mesh, []
    label = _part_labels(mesh)
    parts = np.unique(label)
    if len(parts) < 2:
        return mesh, []
    faces = np.asarray(mesh.faces)
    vertices = np.asarray(mesh.vertices, dtype=float)

    def hull_volume(part):
        try:
            return ConvexHull(vertices[np.unique(faces[label == part])]).volume
        except (QhullError, ValueError):  # flat, or too few points
            return 0.0

    volume = np.array([hull_volume(part) for part in parts])
    if volume.max() <= 0.0:  # every part flat: no body to measure debris against
        return mesh, []
    small = parts[volume <= fraction * volume.max()]
    if len(small) == 0:
        return mesh, []
    rest = ~np.isin(label, small)
    body = trimesh.Trimesh(vertices, faces[rest], process=False)
    body_points = vertices[np.unique(faces[rest])]
    keep, dropped = rest.copy(), []
    for part in small:
        mine = label == part
        piece = trimesh.Trimesh(vertices, faces[mine])  # (merged: a closed part whose corners are repeated is closed)
        near = np.vstack([piece.vertices, piece.triangles_center])
        distance = float(trimesh.proximity.closest_point(body, near)[1].min())
        if distance > 0.0:  # the rest's corners near the part against it: two surfaces meet at a corner of either
            reach = min(distance, gap)
            low, high = near.min(axis=0) - reach, near.max(axis=0) + reach
            close = body_points[((body_points >= low) & (body_points <= high)).all(axis=1)]
            if len(close):
                distance = min(distance, float(trimesh.proximity.closest_point(piece, close)[1].min()))
        is_open = not piece.is_watertight
        if distance > gap or (is_open and volume[parts == part][0] <= 0.0):
            dropped.append({"faces": int(mine.sum()), "size": float(np.ptp(near, axis=0).max()), "distance": distance,
                            "open": is_open})
        else:
            keep |= mine
    if not dropped:
        return mesh, []
    kept = trimesh.Trimesh(vertices, faces[keep], process=False)
    kept.remove_unreferenced_vertices()
    return kept, dropped


def union_of_bodies(mesh: trimesh.Trimesh):
    """A closed mesh whose bodies pass through each other, as the surface of their union.

    An assembly exported as one mesh, or a multi-solid STL, is closed shells
    that overlap: the mesh is watertight, but its volume counts the overlap
    once per shell (it can exceed its hull's) and a ray-parity inside test
    reads the overlap as outside. Its bodies (faces joined by shared edges)
    are joined with manifold3d's boolean union. A mesh with a body wound
    inward (a cavity inside another body) is left as it is.

    Parameters
    ----------
    mesh : trimesh.Trimesh
        A watertight mesh wound outward.

    Returns
    -------
    joined : trimesh.Trimesh
        The union's surface, or ``mesh`` itself when no bodies overlap.
    overlap : float
        The volume counted more than once (mesh units cubed): the bodies'
        volumes summed less the union's; 0 when ``mesh`` is returned.

    Examples
    --------
    Two 40 mm cubes that share a 20 x 40 x 40 mm slab:

    >>> import trimesh
    >>> a = trimesh.creation.box((40.0, 40.0, 40.0))
    >>> b = a.copy().apply_translation([20.0, 0.0, 0.0])
    >>> joined, overlap = union_of_bodies(trimesh.util.concatenate([a, b]))
    >>> round(overlap), round(float(joined.volume)), joined.is_watertight
    (32000, 96000, True)
    """
    import manifold3d

    if not mesh.is_watertight or mesh.body_count < 2:
        return mesh, 0.0
    bodies = [_manifold(body) for body in mesh.split(only_watertight=False)]
    if len(bodies) < 2 or any(body is None or body.volume() <= 0 for body in bodies):
        return mesh, 0.0
    total = sum(body.volume() for body in bodies)
    union = manifold3d.Manifold.batch_boolean(bodies, manifold3d.OpType.Add)
    overlap = total - float(union.volume())
    if overlap <= 1e-9 * total:  # round-off: the bodies only touch, or lie apart
        return mesh, 0.0
    out = union.to_mesh64()
    return trimesh.Trimesh(np.asarray(out.vert_properties)[:, :3], np.asarray(out.tri_verts), process=False), overlap


def _enclosed(mesh, face_label, labels):
    """(len(labels),) bool: the parts whose every corner lies inside another, closed part (a cavity's wall; ray
    parity, whatever the winding)."""
    faces = np.asarray(mesh.faces)
    shells = [trimesh.Trimesh(mesh.vertices, faces[face_label == label]) for label in labels]
    for shell in shells:
        shell.remove_unreferenced_vertices()
    boxes = np.array([shell.bounds for shell in shells])  # (parts, 2, 3)
    out = np.zeros(len(labels), dtype=bool)
    for i, inner in enumerate(shells):
        within = np.flatnonzero((boxes[:, 0] <= boxes[i, 0]).all(axis=1) & (boxes[:, 1] >= boxes[i, 1]).all(axis=1))
        out[i] = any(outer.is_watertight and outer.volume != 0 and bool(outer.contains(inner.vertices).all())
                     for outer in (shells[j] for j in within if j != i and not out[j]))  # boxes first: cheap
    return out


def _part_labels(mesh):
    """The part of each face, (m,) int: connected components of the faces through shared vertex positions
    (corners within ``WELD_TOLERANCE`` of the mesh's size of each other coincide: exporter round-off)."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components
    from scipy.spatial import cKDTree

    vertices = np.asarray(mesh.vertices, dtype=float)
    unique, same = np.unique(vertices, axis=0, return_inverse=True)  # coinciding corners join
    faces = same.reshape(-1)[np.asarray(mesh.faces, dtype=np.int64)]
    n = len(unique)
    size = float(np.ptp(unique, axis=0).max()) if n else 0.0
    near = cKDTree(unique).query_pairs(WELD_TOLERANCE * size, output_type="ndarray") if n else np.empty((0, 2), int)
    edges = np.vstack([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]], near])
    _, labels = connected_components(coo_matrix((np.ones(len(edges)), (edges[:, 0], edges[:, 1])), shape=(n, n)),
                                     directed=False)
    return labels[faces[:, 0]]


def _edge_use(edges_sorted):
    """How many faces use each distinct (sorted) edge."""
    _, inverse = np.unique(edges_sorted, axis=0, return_inverse=True)
    return inverse.ravel()


def _manifold(mesh):
    """A ``manifold3d.Manifold`` of the mesh, or None if it is not a closed oriented 2-manifold."""
    import manifold3d

    built = manifold3d.Manifold(manifold3d.Mesh64(np.ascontiguousarray(mesh.vertices, dtype=float),
                                                  np.ascontiguousarray(mesh.faces, dtype=np.uint64)))
    return built if built.status() == manifold3d.Error.NoError else None


def _weld(mesh):
    """The mesh with its open seams welded, and the number of vertices joined; None if none were.

    manifold3d finds the vertices to join (``Mesh.merge``, on a float32 copy); they are
    joined in the float64 mesh, so the coordinates keep their precision.
    """
    import manifold3d

    size = float(np.ptp(mesh.vertices, axis=0).max())
    m = manifold3d.Mesh(np.ascontiguousarray(mesh.vertices, dtype=np.float32), np.ascontiguousarray(mesh.faces, dtype=np.uint32),
                        tolerance=WELD_TOLERANCE * size)
    if not m.merge() or len(m.merge_from_vert) == 0:
        return None
    target = np.arange(len(mesh.vertices))
    target[np.asarray(m.merge_from_vert, dtype=np.int64)] = np.asarray(m.merge_to_vert, dtype=np.int64)
    welded = trimesh.Trimesh(mesh.vertices, target[mesh.faces], process=False)
    keep = welded.nondegenerate_faces()
    welded.update_faces(keep)
    welded.remove_unreferenced_vertices()
    return welded, len(m.merge_from_vert)


def _boundary_loops(mesh, what):
    """The loops of open edges, each as vertex indices in the order the faces traverse them."""
    edges = mesh.edges  # directed, three per face
    once = trimesh.grouping.group_rows(mesh.edges_sorted, require_count=1)
    directed = edges[once]
    nxt = {}
    for a, b in directed:
        if a in nxt:
            raise RepairError(what, f"two holes touch at vertex {a} ({mesh.vertices[a].round(2).tolist()})")
        nxt[a] = b
    loops, seen = [], set()
    for start in nxt:
        if start in seen:
            continue
        loop, v = [], start
        while v not in seen:
            seen.add(v)
            loop.append(v)
            v = nxt.get(v)
            if v is None:
                raise RepairError(what, "an open boundary does not close into a loop")
        loops.append(np.array(loop))
    return loops


def _cap_holes(mesh, what):
    """The mesh with a planar cap on every hole, and the cap areas; ValueError if a hole cannot be capped."""
    import manifold3d

    faces, areas, vertices = [np.asarray(mesh.faces)], [], np.asarray(mesh.vertices)
    existing = trimesh.grouping.hashable_rows(mesh.edges_sorted)
    for loop in _boundary_loops(mesh, what):
        points = vertices[loop]
        centre = points.mean(axis=0)
        _, _, vt = np.linalg.svd(points - centre)
        size = float(np.ptp(points, axis=0).max())
        off_plane = float(np.abs((points - centre) @ vt[2]).max())
        if off_plane > PLANARITY * size:
            raise RepairError(what, f"a hole's edge loop ({len(loop)} vertices, {size:.3g} mm across) is not planar "
                                    f"({off_plane:.3g} mm off its best-fit plane)")
        # the cap runs along the hole's edges the other way round from the faces that border it
        ring = loop[::-1]
        flat = (vertices[ring] - centre) @ vt[:2].T
        shoelace = 0.5 * float(np.sum(flat[:, 0] * np.roll(flat[:, 1], -1) - np.roll(flat[:, 0], -1) * flat[:, 1]))
        if shoelace < 0:
            flat[:, 1] *= -1.0  # the triangulator wants counter-clockwise polygons; the index order is what matters
        tris = np.asarray(manifold3d.triangulate([np.ascontiguousarray(flat)]), dtype=np.int64).reshape(-1, 3)
        a, b, c = (flat[tris[:, i]] for i in range(3))
        covered = 0.5 * float(np.abs((b - a)[:, 0] * (c - a)[:, 1] - (b - a)[:, 1] * (c - a)[:, 0]).sum())
        if len(tris) != len(ring) - 2 or abs(covered - abs(shoelace)) > 1e-6 * max(abs(shoelace), 1e-12) + 1e-9:
            raise RepairError(what, f"a hole's edge loop crosses itself ({len(loop)} vertices, {size:.3g} mm across)")
        cap = ring[tris]
        chords = trimesh.grouping.hashable_rows(np.sort(np.vstack([cap[:, [0, 1]], cap[:, [1, 2]], cap[:, [2, 0]]]), axis=1))
        rim = trimesh.grouping.hashable_rows(np.sort(np.c_[ring, np.roll(ring, -1)], axis=1))
        if np.isin(chords[~np.isin(chords, rim)], existing).any():
            # a chord of the triangulation is already an edge of the surface (a jagged rim):
            # a fan from a new vertex at the loop's centre instead, if the loop is star-shaped around it
            turn = flat[:, 0] * np.roll(flat[:, 1], -1) - flat[:, 1] * np.roll(flat[:, 0], -1)
            if not (turn > 0).all():
                raise RepairError(what, f"a hole's jagged edge loop ({len(loop)} vertices, {size:.3g} mm across) "
                                        "cannot be triangulated without reusing edges of the surface")
            vertices = np.vstack([vertices, centre])
            cap = np.c_[ring, np.roll(ring, -1), np.full(len(ring), len(vertices) - 1)]
        faces.append(cap)
        areas.append(float(trimesh.triangles.area(vertices[cap]).sum()))
    closed = trimesh.Trimesh(vertices, np.vstack(faces), process=False)
    if not (closed.is_watertight and closed.is_winding_consistent):
        raise RepairError(what, "it is still open after its holes are capped")
    return closed, areas
