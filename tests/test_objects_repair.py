"""Closing open meshes (synergrasp.objects.repair): what is capped, welded or refused, and why."""

import numpy as np
import pytest
import trimesh

from synergrasp.objects.repair import PART_SPACING, RepairError, close_mesh, separate_parts


def box():
    return trimesh.creation.box(extents=[60.0, 60.0, 60.0])


def without(mesh, drop):
    return trimesh.Trimesh(mesh.vertices, mesh.faces[~drop])


def test_box_without_one_or_two_faces_gets_them_back():
    b = box()
    for drop, holes in ((b.face_normals[:, 2] > 0.5, 1), (np.abs(b.face_normals[:, 2]) > 0.5, 2)):
        closed, report = close_mesh(without(b, drop), "box")
        assert closed.is_watertight and closed.is_winding_consistent
        assert report["holes_filled"] == holes and report["cap_area"] == pytest.approx(3600.0 * holes)
        assert report["volume"] == pytest.approx(216000.0) and closed.volume == pytest.approx(216000.0)
        assert report["cap_fraction"] == pytest.approx(holes / 6)


def test_round_holes_are_triangulated_in_their_plane():
    can = trimesh.creation.cylinder(radius=30.0, height=80.0, sections=48)
    closed, report = close_mesh(without(can, can.face_normals[:, 2] > 0.5), "can")  # no lid
    assert report["holes_filled"] == 1 and closed.volume == pytest.approx(can.volume)
    assert report["cap_area"] == pytest.approx(can.area_faces[can.face_normals[:, 2] > 0.5].sum())
    ball = trimesh.creation.icosphere(subdivisions=3, radius=40.0)
    drop = np.zeros(len(ball.faces), dtype=bool)
    drop[np.random.default_rng(0).choice(len(ball.faces), 5, replace=False)] = True  # five pinholes
    closed, report = close_mesh(without(ball, drop), "ball")
    assert report["holes_filled"] == 5 and closed.volume == pytest.approx(ball.volume)


def test_a_non_convex_planar_hole_is_capped_without_overlap():
    """An L-shaped prism without its top: a fan from one vertex would cover the notch; the cap must not."""
    prism = _extrude(np.array([[0, 0], [60, 0], [60, 20], [20, 20], [20, 60], [0, 60]], dtype=float), 40.0)
    closed, report = close_mesh(without(prism, prism.face_normals[:, 2] > 0.5), "L prism")
    assert report["holes_filled"] == 1 and report["cap_area"] == pytest.approx(60 * 20 + 20 * 40)
    assert closed.volume == pytest.approx((60 * 20 + 20 * 40) * 40.0)


def _extrude(outline, height):
    """A closed prism over a counter-clockwise polygon (triangulated with manifold3d)."""
    import manifold3d

    n = len(outline)
    bottom, top = np.c_[outline, np.zeros(n)], np.c_[outline, np.full(n, height)]
    tris = np.asarray(manifold3d.triangulate([outline]))
    faces = [tris[:, ::-1], tris + n]
    for i in range(n):
        j = (i + 1) % n
        faces.append([[i, j, n + j], [i, n + j, n + i]])
    mesh = trimesh.Trimesh(np.vstack([bottom, top]), np.vstack(faces))
    assert mesh.is_watertight and mesh.volume > 0
    return mesh


def test_cracked_seams_are_welded():
    """A triangle soup (every face with its own vertices, off by exporter round-off) is welded shut."""
    b = box()
    rng = np.random.default_rng(1)
    soup = trimesh.Trimesh(b.vertices[b.faces].reshape(-1, 3) + 1e-7 * rng.normal(size=(36, 3)),
                           np.arange(36).reshape(-1, 3), process=False)
    assert not soup.is_watertight
    closed, report = close_mesh(soup, "soup")
    assert report["method"] == "welded" and report["welded_vertices"] > 0 and report["holes_filled"] == 0
    assert closed.volume == pytest.approx(216000.0)


def test_duplicate_faces_are_dropped():
    b = box()
    closed, report = close_mesh(trimesh.Trimesh(b.vertices, np.vstack([b.faces, b.faces[:1]])), "box")
    assert report["method"] == "cleaned" and report["removed_faces"] == 1 and closed.is_watertight


@pytest.mark.parametrize("case, reason", [
    ("saddle", "is not planar"),
    ("shared edge", "1 edges are shared by more than two faces"),
    ("mostly open", "mostly open: the caps would make"),
    ("sheet", "encloses no volume"),
])
def test_unsound_repairs_are_refused_with_the_reason(case, reason):
    ball = trimesh.creation.icosphere(subdivisions=3, radius=40.0)
    x, y, z = ball.triangles_center.T
    if case == "saddle":  # a hole whose rim rises and falls around the sphere
        mesh = without(ball, (z > 0) & (np.abs(x * y) / 40 + z > 30))
    elif case == "shared edge":  # two boxes meeting along an edge, both open on top
        a = without(box(), box().face_normals[:, 2] > 0.5)
        b = a.copy()
        b.apply_translation([60.0, 60.0, 0.0])
        mesh = trimesh.util.concatenate([a, b])
    elif case == "mostly open":  # a shallow dish: its cap would be most of the closed surface
        mesh = without(ball, z < 30)
    else:  # a square's front and back (the back cut along the other diagonal): closed, but flat
        mesh = trimesh.Trimesh([[0, 0, 0], [60, 0, 0], [60, 60, 0], [0, 60, 0]], [[0, 1, 2], [0, 2, 3], [1, 0, 3], [1, 3, 2]])
    with pytest.raises(RepairError, match=reason) as info:
        close_mesh(mesh, "part")
    assert isinstance(info.value, ValueError) and str(info.value).startswith("part is not watertight and cannot be closed soundly")
    assert info.value.reason in str(info.value)


def test_separate_parts_and_the_widest_gap_that_joins_them():
    cube = trimesh.creation.box((10.0, 10.0, 10.0))
    at = lambda x: cube.copy().apply_translation([x, 0.0, 0.0])  # noqa: E731
    assert separate_parts(cube) == (1, 0.0)
    assert separate_parts(trimesh.util.concatenate([at(0.0), at(30.0)])) == (2, pytest.approx(20.0))
    assert separate_parts(trimesh.util.concatenate([at(0.0), at(10.0)])) == (1, 0.0)  # corners in common: joined
    parts, gap = separate_parts(trimesh.util.concatenate([at(0.0), at(10.0).apply_translation([0.0, 3.0, 0.0])]))
    assert parts == 2 and gap < PART_SPACING  # face to face, no corner in common: within the samples' spacing
    soup = trimesh.creation.icosphere(radius=20.0)  # every triangle with its own corners: one part
    assert separate_parts(trimesh.Trimesh(soup.triangles.reshape(-1, 3), np.arange(3 * len(soup.faces)).reshape(-1, 3),
                                          process=False)) == (1, 0.0)
    # ... also when an exporter's round-off moved each copy of a corner by about 1e-5 mm (1280 triangles)
    jittered = trimesh.creation.icosphere(3, radius=40.0).triangles.reshape(-1, 3)
    jittered = jittered + np.random.default_rng(0).normal(scale=1e-5, size=jittered.shape)
    assert separate_parts(trimesh.Trimesh(jittered, np.arange(len(jittered)).reshape(-1, 3), process=False)) == (1, 0.0)
    # joined by the shortest gaps first: 5 mm then 80 mm (not the 95 mm between the outer two)
    assert separate_parts(trimesh.util.concatenate([at(0.0), at(15.0), at(105.0)])) == (3, pytest.approx(80.0))
    # a handle that enters the body: parts that overlap are joined
    body = trimesh.creation.cylinder(radius=30.0, height=80.0)
    handle = trimesh.creation.box((30.0, 8.0, 50.0)).apply_translation([35.0, 0.0, 0.0])
    parts, gap = separate_parts(trimesh.util.concatenate([body, handle]))
    assert parts == 2 and gap < 1.0
    # a hollow box (a cavity's wall wound inwards, 10-15 mm inside the outer one) is not two parts apart ...
    outer, cavity = trimesh.creation.box((60.0, 50.0, 70.0)), trimesh.creation.box((30.0, 20.0, 40.0))
    cavity.invert()
    assert separate_parts(trimesh.util.concatenate([outer, cavity])) == (2, 0.0)
    # ... but a box beside it is, and one inside a box that has a hole is not enclosed (its hull is open)
    assert separate_parts(trimesh.util.concatenate([outer, cavity.copy().apply_translation([70.0, 0.0, 0.0])])) == (
        2, pytest.approx(25.0, abs=PART_SPACING))
    holed = outer.copy()
    holed.update_faces(np.arange(len(holed.faces)) > 1)  # two triangles off: not watertight
    assert separate_parts(trimesh.util.concatenate([holed, cavity]))[1] > 5.0
