"""synergrasp.objects loading: file formats, point clouds, decomposition cache, bad input."""

import json
import warnings

import numpy as np
import pytest
import trimesh

from benchmarks.one_sided import camera_view
from synergrasp.objects.point_surface import PointSurface

import synergrasp as sg
import synergrasp.objects as so
from synergrasp.objects import decompose, loading
from synergrasp.planner import PlannerOptions


@pytest.fixture(autouse=True)
def cache(tmp_path, monkeypatch):
    """Every test gets its own decomposition cache."""
    folder = tmp_path / "cache"
    monkeypatch.setenv("SYNERGRASP_CACHE", str(folder))
    return folder


def box_mesh():
    return trimesh.creation.box((30.0, 40.0, 50.0))


def hourglass_mesh():
    """A small watertight non-convex solid (two cones tip to tip, capped)."""
    profile = np.array([[0, 0], [20, 0], [20, 10], [8, 15], [8, 25], [20, 30], [20, 40], [0, 40.0]])
    mesh = trimesh.creation.revolve(profile, sections=24)
    if mesh.volume < 0:
        mesh.invert()
    return mesh


def ellipsoid_cloud(n=2000, seed=0):
    rng = np.random.default_rng(seed)
    d = rng.normal(size=(n, 3))
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    return d * [30.0, 40.0, 50.0]


def torus_cloud(n=4000, seed=0):
    torus = trimesh.creation.torus(major_radius=40.0, minor_radius=10.0, major_sections=64, minor_sections=24)
    return trimesh.sample.sample_surface(torus, n, seed=seed)[0]


# --------------------------------------------------------------------------- formats


@pytest.mark.parametrize("ext", [".obj", ".stl", ".ply", ".off", ".glb"])
def test_mesh_formats_round_trip(tmp_path, ext):
    path = tmp_path / f"box{ext}"
    box_mesh().export(path)
    obj = so.load(path)
    assert obj.name == path.name and obj.info["method"] == "hull" and obj.n_pieces == 1
    assert obj.extents == pytest.approx([30, 40, 50])
    assert obj.volume == pytest.approx(60000.0)
    assert obj.center == pytest.approx([0, 0, 0], abs=1e-9)
    assert obj.mesh is not None
    assert obj.contact_distance([[0, 0, 40.0]]).value[0] > 0


@pytest.mark.parametrize("ext", [".ply", ".xyz", ".npy", ".npz"])
def test_point_cloud_formats_round_trip(tmp_path, ext):
    pts = ellipsoid_cloud()
    path = tmp_path / f"cloud{ext}"
    if ext == ".ply":
        trimesh.PointCloud(pts).export(path)
    elif ext == ".xyz":
        np.savetxt(path, pts)
    elif ext == ".npy":
        np.save(path, pts)
    else:
        np.savez(path, points=pts)
    obj = so.load(path)
    assert obj.info["method"] == "hull" and obj.n_pieces == 1 and obj.mesh is None
    assert obj.bounds == pytest.approx(np.array([pts.min(axis=0), pts.max(axis=0)]), abs=1e-6)
    assert len(obj.pieces[0]) <= 256
    assert obj.contains([[0, 0, 0], [0, 0, 45.0]]).all()


def test_npz_mesh_and_get_by_path(tmp_path):
    mesh = box_mesh()
    path = tmp_path / "box.npz"
    np.savez(path, vertices=mesh.vertices, faces=mesh.faces)
    obj = so.get(path)
    assert obj.info["method"] == "hull" and obj.volume == pytest.approx(60000.0)


def test_from_mesh_and_from_points_directly():
    scene = trimesh.Scene([box_mesh()])
    assert so.from_mesh(scene, name="boxed").name == "boxed"
    obj = so.from_points(ellipsoid_cloud(), max_vertices=64)
    assert len(obj.pieces[0]) == 64
    with pytest.raises(TypeError, match="Trimesh"):
        so.from_mesh(np.zeros((4, 3)))


def test_scale_is_applied(tmp_path):
    path = tmp_path / "box_m.stl"
    mesh = box_mesh()
    mesh.apply_scale(0.001)  # a file in metres
    mesh.export(path)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # in mm now: no size warning
        obj = so.load(path, scale=1000)
    assert obj.extents == pytest.approx([30, 40, 50])
    assert obj.mesh.extents == pytest.approx([30, 40, 50])


# --------------------------------------------------------------------------- decomposition and cache


def t_handle():
    """A 450 mm handle: a bar and a cross bar, both 30 mm thick."""
    bar, cross = trimesh.creation.box((450.0, 30.0, 30.0)), trimesh.creation.box((30.0, 150.0, 30.0))
    return trimesh.boolean.union([bar, cross.apply_translation([210.0, 0.0, 0.0])])


def test_a_large_object_is_remeshed_on_voxels_no_wider_than_voxel_pitch(monkeypatch):
    """On CoACD's 20 voxels the handle's bars are 1.3 voxels thick and its pieces stick out of them by about 7 mm, more
    than the contact threshold: a grasp of the pieces is not one of the handle. Voxels of at most VOXEL_PITCH keep them
    within 4 mm, and a precision plan's contacts lie on the true surface."""
    mesh = t_handle()
    off = {}
    for pitch in (1e9, loading.VOXEL_PITCH):  # 1e9: the 20 voxels of COACD_PARAMS
        monkeypatch.setattr(loading, "VOXEL_PITCH", pitch)
        obj = so.from_mesh(mesh, cache=False)
        off[pitch] = trimesh.proximity.closest_point(mesh, obj.index.vertices)[1].max()
    assert off[1e9] > 5.0 and off[loading.VOXEL_PITCH] < 4.0
    result = sg.plan(obj, "precision")
    assert result.success and trimesh.proximity.closest_point(mesh, result.contact_points)[1].max() < 5.0


def test_non_convex_mesh_is_decomposed_and_cached(tmp_path, cache, monkeypatch):
    path = tmp_path / "hourglass.obj"
    mesh = hourglass_mesh()
    mesh.export(path)
    first = so.load(path)
    assert first.info["method"] == "coacd" and first.info["cache"] == "miss"
    assert first.info["volume_ratio"] < 0.97
    assert 2 <= first.n_pieces <= 16
    assert list(cache.glob("*.npz")), "the decomposition was stored"
    # the pieces cover the mesh (CoACD's remeshing is within about a mm)
    assert (first.index.plane_bounds(mesh.vertices).min(axis=1) <= 1.5).all()
    # the waist is not filled in as a hull would
    assert not first.contains([[18.0, 0, 20.0]])[0]

    def fail(*args, **kwargs):
        raise AssertionError("decomposition run again despite the cache")

    monkeypatch.setattr(loading, "_decompose", fail)
    second = so.load(path)
    assert second.info["cache"] == "hit"
    for a, b in zip(first.pieces, second.pieces):
        assert a == pytest.approx(b)
    # the same file at another scale reuses the same entry
    scaled = so.load(path, scale=2.0)
    assert scaled.info["cache"] == "hit" and scaled.extents == pytest.approx(2 * first.extents)
    # a changed file is a different entry: decomposed again (here failing, so the hull with a warning)
    mesh.apply_translation([1.0, 0, 0])
    mesh.export(path)
    with pytest.warns(UserWarning, match="despite the cache"):
        changed = so.load(path)
    assert changed.info["cache"] == "miss" and changed.info["method"].startswith("hull")
    monkeypatch.undo()  # the fallback was not cached: with CoACD back, it decomposes again
    monkeypatch.setenv("SYNERGRASP_CACHE", str(cache))
    assert so.load(path).info["method"] == "coacd"


def two_boxes(gap):
    """Two 40 mm cubes ``gap`` mm apart, in one mesh: CoACD's remeshing loops on gaps of about one voxel."""
    a, b = trimesh.creation.box((40.0, 40.0, 40.0)), trimesh.creation.box((40.0, 40.0, 40.0))
    return trimesh.util.concatenate([a, b.apply_translation([0.0, 0.0, 40.0 + gap])])


def test_coacd_in_its_child_process_gives_coacds_own_parts():
    """The same mesh and parameters give the parts of coacd.run_coacd called here, bit for bit."""
    import coacd

    mesh = hourglass_mesh()
    params = {**loading.COACD_PARAMS, "max_convex_hull": 8, "max_ch_vertex": 64}
    coacd.set_log_level("error")
    here = coacd.run_coacd(coacd.Mesh(np.asarray(mesh.vertices, dtype=float), np.asarray(mesh.faces, dtype=np.int64)),
                           **params)
    child = decompose.run_coacd(mesh.vertices, mesh.faces, params, time_limit=120.0)
    assert len(child) == len(here) >= 2
    for ours, theirs in zip(child, here):
        np.testing.assert_array_equal(ours, np.asarray(theirs[0], dtype=float))


def test_a_decomposition_past_its_time_limit_is_stopped_and_the_mesh_clustered(monkeypatch):
    """CoACD never finishes two cubes 10 mm apart: the child is killed at the time limit, and the object is made of
    clusters of the solid the surface encloses, with a warning that names the limit; it covers both cubes."""
    with pytest.raises(decompose.DecompositionTimeout, match="within 1 s"):
        decompose.run_coacd(two_boxes(10.0).vertices, two_boxes(10.0).faces, dict(loading.COACD_PARAMS), time_limit=1.0)
    monkeypatch.setattr(loading, "DECOMPOSITION_TIME_LIMIT", 1.0)
    with pytest.warns(UserWarning, match="did not finish within 1 s.*DECOMPOSITION_TIME_LIMIT"):
        obj = so.from_mesh(two_boxes(10.0), cache=False)
    assert "CoACD timed out" in obj.info["method"]
    assert obj.contains([[0.0, 0.0, 0.0], [0.0, 0.0, 50.0]]).all() and obj.extents == pytest.approx([40, 40, 90], abs=1)


def test_a_cached_timeout_is_decomposed_again_under_a_longer_limit(monkeypatch):
    monkeypatch.setattr(loading, "DECOMPOSITION_TIME_LIMIT", 1.0)
    with pytest.warns(UserWarning, match="the next load tries CoACD again"):
        first = so.from_mesh(two_boxes(10.0))
    assert first.info["cache"] == "miss" and "CoACD timed out" in first.info["method"]
    assert so.from_mesh(two_boxes(10.0)).info["cache"] == "hit"  # the same limit: the clusters are kept
    monkeypatch.setattr(loading, "DECOMPOSITION_TIME_LIMIT", 1.5)
    with pytest.warns(UserWarning, match="did not finish within 1.5 s"):
        assert so.from_mesh(two_boxes(10.0)).info["cache"] == "miss"  # a longer limit: CoACD again


def test_a_failing_decomposition_process_says_why():
    with pytest.raises(RuntimeError, match="CoACD failed: .*no_such_setting"):
        decompose.run_coacd(box_mesh().vertices, box_mesh().faces, {"no_such_setting": 1}, time_limit=60.0)


def test_vertices_no_face_uses_are_not_part_of_the_object():
    """A stray vertex 5 m away, in a mesh made without trimesh's processing, neither inflates the object nor its grid."""
    ball = trimesh.creation.icosphere(3, 40.0)
    clean = so.from_mesh(ball, cache=False)
    stray = so.from_mesh(trimesh.Trimesh(np.r_[ball.vertices, [[5000.0, 0.0, 0.0]]], ball.faces, process=False), cache=False)
    assert stray.extents == pytest.approx(clean.extents) and stray.volume == pytest.approx(clean.volume)


def test_duplicate_faces_are_dropped_without_talk_of_holes():
    ball = trimesh.creation.icosphere(2, 40.0)
    doubled = trimesh.Trimesh(ball.vertices, np.r_[ball.faces, ball.faces[:5]], process=False)
    with pytest.warns(UserWarning, match="needed repair: 5 duplicate or degenerate faces dropped") as caught:
        obj = so.from_mesh(doubled, cache=False)
    assert not any("hole" in str(w.message) for w in caught)
    assert obj.volume == pytest.approx(so.from_mesh(ball, cache=False).volume)


def test_a_gltf_whose_buffer_changed_is_not_read_from_the_cache(tmp_path):
    """The key is the geometry read, not the .gltf's text: a buffer rewritten with the same counts and bounds (a cube,
    then the cube with a corner pushed in) gave the first file's pieces back as a cache hit."""
    cube = trimesh.creation.box((40.0, 40.0, 40.0))
    dented = cube.copy()
    dented.vertices[np.argmax(dented.vertices.sum(axis=1))] *= 0.5  # (20, 20, 20) -> (10, 10, 10): bounds unchanged
    folder = tmp_path / "g"
    folder.mkdir()
    loaded = []
    for mesh in (cube, dented):
        files = trimesh.exchange.gltf.export_gltf(trimesh.Scene(mesh))
        for name, data in files.items():
            (folder / name).write_bytes(data)
        loaded.append(so.load(folder / "model.gltf", max_parts=1))
    assert [o.info["cache"] for o in loaded] == ["miss", "miss"]
    assert loaded[0].contains([[18.0, 18.0, 18.0]])[0] and not loaded[1].contains([[18.0, 18.0, 18.0]])[0]


def test_cache_can_be_disabled(cache):
    obj = so.from_points(ellipsoid_cloud(), cache=False)
    assert obj.info["cache"] == "disabled" and not cache.exists()


def test_non_convex_point_cloud_is_clustered():
    pts = torus_cloud()
    obj = so.from_points(pts)
    assert obj.info["method"].startswith("kmeans") and obj.n_pieces >= 4
    assert not obj.contains([[0.0, 0.0, 0.0]])[0], "the hole stays empty"
    assert obj.contains([[40.0, 0.0, 0.0], [0.0, -40.0, 0.0]]).all(), "the ring is solid"
    assert obj.contains([obj.center])[0]
    # every cloud point is in (or within a mm of) a piece
    assert (obj.index.plane_bounds(pts).min(axis=1) <= 1.0).all()
    again = so.from_points(pts)
    assert again.info["cache"] == "hit" and again.n_pieces == obj.n_pieces


def test_convex_cloud_is_one_hull():
    obj = so.from_points(ellipsoid_cloud(300))
    assert obj.n_pieces == 1 and obj.info["method"] == "hull"


# --------------------------------------------------------------------------- warnings and bad input


def test_size_warnings():
    small = box_mesh()
    small.apply_scale(0.001)
    with pytest.warns(UserWarning, match="scale=1000"):
        so.from_mesh(small)
    big = box_mesh()
    big.apply_scale(100.0)
    with pytest.warns(UserWarning, match="scale=0.1"):
        so.from_mesh(big)
    with pytest.warns(UserWarning, match="scale=1000"):
        so.from_points(ellipsoid_cloud() / 1000)


def open_box(extents=(30.0, 40.0, 50.0)):
    """A box without its top face (two triangles)."""
    mesh = trimesh.creation.box(extents)
    return trimesh.Trimesh(mesh.vertices, mesh.faces[mesh.face_normals[:, 2] < 0.5])


def test_open_mesh_is_capped_and_the_repair_reported(tmp_path):
    path = tmp_path / "open.stl"
    open_box().export(path)
    with pytest.warns(UserWarning, match=r"not watertight: 1 hole\(s\) capped with 4800 mm\^2 of new surface"):
        obj = so.load(path, scale=2.0)
    repair = obj.info["repair"]
    assert repair["method"] == "capped" and repair["holes_filled"] == 1
    assert repair["cap_area"] == pytest.approx(4 * 30 * 40) and repair["volume"] == pytest.approx(8 * 30 * 40 * 50)
    assert repair["cap_fraction"] == pytest.approx(1200 / 9400)
    assert not obj.info["watertight"] and obj.mesh.is_watertight
    assert obj.info["method"] == "hull" and obj.n_pieces == 1  # the box it was, not a cloud of walls
    assert obj.extents == pytest.approx([60, 80, 100]) and obj.volume == pytest.approx(8 * 30 * 40 * 50)


def test_a_mesh_wound_inward_is_turned_outward(tmp_path):
    """A closed box exported inside out (negative volume, normals into the solid) loads as the box, facing out."""
    mesh = trimesh.creation.box((60.0, 50.0, 70.0))
    mesh.invert()
    path = tmp_path / "inside_out.stl"
    mesh.export(path)
    with pytest.warns(UserWarning, match="wound inward or inconsistently.*turned outward"):
        obj = so.load(path)
    assert obj.mesh.volume == pytest.approx(60 * 50 * 70) and obj.mesh.is_winding_consistent
    assert obj.volume == pytest.approx(60 * 50 * 70)
    centres = obj.mesh.triangles_center - obj.center  # every face normal points away from the centre
    assert np.all(np.einsum("ij,ij->i", obj.mesh.face_normals, centres) > 0)


def test_a_mesh_of_separate_objects_is_one_object_with_a_warning():
    """Two balls 150 mm apart in one file: planned as one rigid object, and the loader says so; touching parts do not warn."""
    ball = trimesh.creation.icosphere(radius=25.0)
    apart = trimesh.util.concatenate([ball.copy().apply_translation([-100.0, 0, 0]), ball.copy().apply_translation([100.0, 0, 0])])
    with pytest.warns(UserWarning, match=r"two balls is 2 separate parts, some 150 mm from the rest: they are planned as one "
                                         r"rigid object\. To grasp one of them, load it alone: its parts are "
                                         r"mesh\.split\(only_watertight=False\)"):  # a mesh in memory: no file
        obj = so.from_mesh(apart, name="two balls", cache=False)
    assert obj.n_pieces == 2
    cube = trimesh.creation.box((40.0, 40.0, 40.0))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        so.from_mesh(trimesh.util.concatenate([cube, cube.copy().apply_translation([40.0, 0, 0])]), name="two cubes", cache=False)


def test_a_grasp_object_given_a_mesh_wound_inward_keeps_an_outward_copy():
    mesh = trimesh.creation.box((60.0, 50.0, 70.0))
    mesh.invert()
    with pytest.warns(UserWarning, match=r"inside-out box: its faces were wound inward .* turned outward \(in a copy\)"):
        obj = so.GraspObject([mesh.vertices], mesh=mesh, name="inside-out box")
    assert obj.mesh.volume == pytest.approx(60 * 50 * 70) and mesh.volume == pytest.approx(-60 * 50 * 70)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # an outward mesh is kept as it is, without a warning
        box = trimesh.creation.box((60.0, 50.0, 70.0))
        assert so.GraspObject([box.vertices], mesh=box).mesh is box


def test_a_large_mesh_is_tested_on_a_simplified_surface_within_the_tolerance():
    """A 81,920-face ball: the planner's surface keeps a few thousand faces, closed, within 0.1 mm of the mesh;
    a mesh of at most SURFACE_FACES faces is its own surface."""
    from synergrasp.objects.grasp_object import SURFACE_FACES, SURFACE_TOLERANCE

    fine = trimesh.creation.icosphere(subdivisions=6, radius=30.0)
    obj = so.from_mesh(fine, cache=False)
    surface = obj.surface
    assert len(fine.faces) > SURFACE_FACES >= len(surface.faces) and surface.is_watertight
    gap = np.abs(trimesh.proximity.signed_distance(surface, fine.vertices[::40]))
    assert gap.max() <= SURFACE_TOLERANCE + 1e-6
    assert np.abs(trimesh.proximity.signed_distance(fine, surface.vertices)).max() <= SURFACE_TOLERANCE + 1e-6
    small = so.from_mesh(trimesh.creation.icosphere(subdivisions=3, radius=30.0), cache=False)
    assert small.surface is small.mesh


def test_stray_points_of_a_scan_are_dropped_with_a_warning():
    """Three stray points 150-250 mm from a 60 x 50 x 70 mm box's cloud: dropped, the box is what is left."""
    box = trimesh.creation.box((60.0, 50.0, 70.0))
    points = trimesh.sample.sample_surface(box, 3000, seed=0)[0]
    strays = np.array([[200.0, 0.0, 0.0], [0.0, 250.0, 0.0], [-180.0, 30.0, 90.0]])
    with pytest.warns(UserWarning, match="3 stray point\\(s\\) dropped"):
        obj = so.from_points(np.vstack([points, strays]), cache=False)
    assert obj.n_pieces == 1 and obj.extents == pytest.approx([60.0, 50.0, 70.0], abs=0.5)


@pytest.mark.parametrize("count", [100, 400, 5000])
def test_a_random_sample_of_a_surface_has_no_strays(count):
    """Points drawn at random on a ball (uneven spacing, as any random sample): none is taken for a stray."""
    ball = trimesh.creation.icosphere(3, 30.0)
    for seed in range(3):
        points = trimesh.sample.sample_surface(ball, count, seed=seed)[0]
        with warnings.catch_warnings():
            warnings.simplefilter("error")  # no "stray points" warning
            obj = so.from_points(points, cache=False)
        assert obj.n_pieces == 1 and obj.extents == pytest.approx([60.0, 60.0, 60.0], abs=6.0)


@pytest.mark.parametrize("direction", [(1.0, 0.2, 0.3), (0.39, -0.88, 0.26)])
def test_one_camera_view_is_swept_away_from_the_camera_with_a_warning(direction):
    """One camera view of a cylinder: its voxels enclose nothing and some of its k-means clusters were flat (dropped,
    so the load failed with "give the points in the pieces' units"); it is the hull of the points swept away from the
    camera as far again as the view is deep (what the camera did not see is solid), with a warning that names the
    camera's side. The whole cylinder's cloud hides about half its points along any line: not a view, no warning."""
    cylinder = trimesh.creation.cylinder(radius=30.0, height=90.0, sections=64)
    direction = np.asarray(direction) / np.linalg.norm(direction)
    points = camera_view(cylinder, direction, np.random.default_rng(0))  # the benchmark's camera
    with pytest.warns(UserWarning, match=r"is one camera view, seen from \((-?[01]\.[0-9]+, ){2}-?[01]\.[0-9]+\): along "
                                         r"that line [0-9]+% of its points lie behind others.* swept [0-9]+ mm away "
                                         r".* scan the object from several sides"):
        obj = so.from_points(points, cache=False)
    assert obj.info["method"] == "hull of a cloud seen from one side, swept away from the camera" and obj.n_pieces == 1
    camera = np.asarray(obj.info["camera"])
    assert camera @ direction > 0.7 and obj.info["hidden"] <= so.loading.ONE_VIEW  # (any line it hides little along)
    depth = np.ptp(points @ camera)
    assert obj.info["swept"] == pytest.approx(depth)
    assert obj.index.min_plane_bound(points).max() < 1.0  # the pieces, of 256 vertices at most, cover the view
    behind = points - 0.9 * depth * camera  # the view moved back 90 % of the sweep: inside the solid
    assert obj.contains(behind).mean() > 0.95 and not obj.contains(points + 0.1 * depth * camera).any()
    whole = trimesh.sample.sample_surface(cylinder, 3000, seed=0)[0]
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        obj = so.from_points(whole, cache=False)
    assert np.linalg.norm(obj.point_surface.net_normal(obj.contains)) < 0.02 and "camera" not in obj.info
    assert PointSurface(whole).view_direction()[1] > 1.5 * so.loading.ONE_VIEW  # (0.26)


def test_a_views_points_may_span_a_quarter_of_its_swept_pieces_but_not_a_tenth():
    """A camera view of a Lego brick (64 mm of points) swept into pieces of 131 mm was refused with "give the points in
    the pieces' units": a sweep spans up to 1 + sqrt(3) times its points. Points of a swept view down to a quarter of
    the pieces' span are taken; other points need half; a tenth (in cm beside pieces in mm) is refused."""
    box = trimesh.creation.box((60.0, 60.0, 60.0))
    pieces = [np.vstack([box.vertices, box.vertices + [75.0, 0.0, 0.0]])]  # the box swept 75 mm along +x: 135 mm
    face = trimesh.sample.sample_surface(box, 2000, seed=0)[0]
    face = face[face[:, 0] < -29.9]  # the side the camera saw
    face = np.vstack([face, [[-30.0, y, z] for y in (-30.0, 30.0) for z in (-30.0, 30.0)]])
    obj = so.GraspObject(pieces, points=face, info={"swept": 75.0})
    assert obj.size == pytest.approx(135.0) and np.ptp(obj.points, axis=0).max() == pytest.approx(60.0)  # 0.44
    far = [np.vstack([box.vertices, box.vertices + [140.0, 0.0, 0.0]])]  # swept 140 mm: 200 mm, 0.3
    assert so.GraspObject(far, points=face, info={"swept": 140.0}).size == pytest.approx(200.0)
    with pytest.raises(ValueError, match="give the points in the pieces' units"):
        so.GraspObject(pieces, points=face)  # not a swept view: half at least
    with pytest.raises(ValueError, match="give the points in the pieces' units"):
        so.GraspObject([box.vertices * 10.0], points=face, info={"swept": 0.0})  # a tenth of the span


def test_open_box_cloud_is_the_whole_box():
    """The cloud of a box without its lid: the opening is closed across, the solid is the box."""
    mesh = open_box()
    points = np.vstack([mesh.vertices, trimesh.sample.sample_surface(mesh, 2500, seed=0)[0]])
    obj = so.from_points(points, cache=False)
    assert obj.n_pieces == 1 and obj.volume == pytest.approx(30 * 40 * 50, rel=2e-3)  # within half a voxel
    assert obj.contains([[0.0, 0.0, 20.0], [0.0, 0.0, 0.0]]).all()


def test_mesh_that_cannot_be_capped_is_closed_on_a_voxel_grid():
    """Two boxes sharing an edge (non-manifold) and open on top: closed as the solid their surface encloses."""
    a, b = open_box((40.0, 40.0, 40.0)), open_box((40.0, 40.0, 40.0))
    b.apply_translation([40.0, 40.0, 0.0])
    with pytest.warns(UserWarning, match=r"cannot be capped \(1 edges are shared by more than two faces.*voxel grid"):
        obj = so.from_mesh(trimesh.util.concatenate([a, b]), name="two boxes", cache=False)
    assert obj.info["repair"]["method"] == "voxel closing" and obj.info["method"].startswith("voxel closing")
    assert obj.contains([[0.0, 0.0, 0.0], [40.0, 40.0, 0.0], [0.0, 0.0, 15.0]]).all()  # the open boxes are filled
    assert not obj.contains([[40.0, 0.0, 0.0], [0.0, 40.0, 0.0]]).any()  # the empty quadrants stay empty
    assert obj.info["repair"]["filled_volume"] == pytest.approx(2 * 40.0**3, rel=0.25)


def test_open_surface_that_encloses_nothing_is_refused():
    """Half a tube (an arch): its edge loop is not planar, and it encloses no volume."""
    tube = trimesh.creation.cylinder(radius=30.0, height=80.0, sections=48)
    keep = (np.abs(tube.face_normals[:, 2]) < 0.5) & (tube.triangles_center[:, 1] > 0)
    arch = trimesh.Trimesh(tube.vertices, tube.faces[keep])
    with pytest.raises(ValueError, match=r"arch is not watertight and cannot be capped \(a hole's edge loop .* is not "
                       r"planar.*encloses no volume on a voxel grid either"):
        so.from_mesh(arch, name="arch", cache=False)


@pytest.mark.parametrize("ext", [".obj", ".stl", ".ply", ".off"])
def test_non_finite_vertex_in_a_file_is_refused(tmp_path, ext):
    """The loader sees the NaN vertex (trimesh's processing would drop it with its faces) and gives from_mesh's error."""
    mesh = trimesh.creation.icosphere(subdivisions=2, radius=30.0)
    vertices = mesh.vertices.copy()
    vertices[3] = np.nan
    with pytest.raises(ValueError, match=r"mesh vertices contains NaN or inf at rows \[3\]"):
        so.from_mesh(trimesh.Trimesh(vertices, mesh.faces, process=False))
    path = tmp_path / f"ball{ext}"
    if ext == ".obj":  # trimesh's exporters write NaN differently per format: write the OBJ by hand
        path.write_text("".join(f"v {x} {y} {z}\n" for x, y, z in vertices) + "".join(f"f {a} {b} {c}\n" for a, b, c in mesh.faces + 1))
    else:
        trimesh.Trimesh(vertices, mesh.faces, process=False).export(path)
    with pytest.raises(ValueError, match=rf"ball\{ext} vertices contains NaN or inf"):
        so.load(path, cache=False)


def test_bad_point_clouds():
    with pytest.raises(ValueError, match="empty"):
        so.from_points(np.zeros((0, 3)))
    with pytest.raises(ValueError, match="NaN or inf"):
        so.from_points([[0, 0, 0], [1, 0, 0], [0, np.inf, 0], [0, 0, 1]])
    with pytest.raises(ValueError, match="no volume.*plane"):
        so.from_points(np.c_[np.random.default_rng(0).uniform(size=(50, 2)) * 40, np.zeros(50)])
    with pytest.raises(ValueError, match="no volume.*line"):
        so.from_points(np.outer(np.arange(10.0), [1, 2, 3]))
    with pytest.raises(ValueError, match="no volume"):
        so.from_points([[0, 0, 0], [1, 0, 0], [0, 1, 0]])
    with pytest.raises(ValueError, match=r"dimension 2"):
        so.from_points(np.ones((10, 2)))
    with pytest.raises(ValueError, match="scale"):
        so.from_points(ellipsoid_cloud(), scale=0)


def test_bad_meshes(tmp_path):
    flat = trimesh.Trimesh([[0, 0, 0], [50, 0, 0], [50, 50, 0], [0, 50, 0]], [[0, 1, 2], [0, 2, 3]])
    with pytest.raises(ValueError, match="no volume"):
        so.from_mesh(flat)
    path = tmp_path / "flat.obj"
    flat.export(path)
    with pytest.raises(ValueError, match="flat.obj has no volume"):
        so.load(path)
    with pytest.raises(ValueError, match="no faces"):
        so.from_mesh(trimesh.Trimesh(vertices=np.eye(3)))


def test_bad_files(tmp_path):
    with pytest.raises(FileNotFoundError, match="missing.obj"):
        so.load(tmp_path / "missing.obj")
    unknown = tmp_path / "object.abc"
    unknown.write_text("1 2 3\n")
    with pytest.raises(ValueError, match=r"object\.abc.*\.obj.*\.stl") as info:
        so.load(unknown)
    assert all(ext in str(info.value) for ext in so.SUPPORTED_FORMATS)
    garbage = tmp_path / "garbage.stl"
    garbage.write_bytes(b"\x00\x01garbage" * 7)
    with pytest.raises(ValueError, match="garbage.stl"):
        so.load(garbage)
    text = tmp_path / "words.xyz"
    text.write_text("these are not numbers\n")
    with pytest.raises(ValueError, match="could not read .*words.xyz"):
        so.load(text)
    empty = tmp_path / "empty.npy"
    np.save(empty, np.zeros((0, 3)))
    with pytest.raises(ValueError, match="empty"):
        so.load(empty)
    keys = tmp_path / "keys.npz"
    np.savez(keys, a=np.ones(3), b=np.ones(3))
    with pytest.raises(ValueError, match="keys.npz.*'points'"):
        so.load(keys)


def test_an_open_box_is_grasped_like_the_closed_one(tmp_path):
    """A 60 mm box without its lid, from a file and as a point cloud, is the closed box and is grasped like it."""
    closed = trimesh.creation.box(extents=[60.0, 60.0, 60.0])
    lidless = trimesh.Trimesh(closed.vertices, closed.faces[closed.face_normals[:, 2] < 0.5])
    path = tmp_path / "open_box.stl"
    lidless.export(path)
    with pytest.warns(UserWarning, match="1 hole"):
        from_file = so.load(path, cache=False)
    cloud = np.vstack([lidless.vertices, trimesh.sample.sample_surface(lidless, 2500, seed=0)[0]])
    objects = (so.from_mesh(closed, cache=False), from_file, so.from_points(cloud, cache=False))
    np.testing.assert_allclose(np.sort(objects[1].pieces[0], axis=0), np.sort(objects[0].pieces[0], axis=0))  # the same box
    assert abs(objects[1].mesh.volume - closed.volume) < 1e-6 * closed.volume
    plans = [sg.plan(obj, "precision") for obj in objects]
    for r, obj in zip(plans, ("closed", "open file", "open cloud")):
        assert r.success, f"{obj}: {r.reason}"
    assert plans[1].total_iterations <= 2 * plans[0].total_iterations + 60  # the file's pieces are the closed box's
    # the cloud's pieces are its own clusters' hulls, a slightly different box, and its grasp must touch the faces
    # the cloud samples (its surface), not the missing lid: within half the budget
    assert plans[2].total_iterations <= PlannerOptions().max_iter // 2
    assert trimesh.proximity.closest_point(lidless, plans[2].contact_points)[1].max() <= PlannerOptions().eps_c


def test_a_path_under_the_home_folder_is_expanded(tmp_path, monkeypatch):
    monkeypatch.setenv("HOME", str(tmp_path))
    trimesh.creation.box((40.0, 50.0, 60.0)).export(tmp_path / "box.stl")
    for obj in (so.load("~/box.stl", cache=False), so.get("~/box.stl", cache=False)):
        assert np.ptp(obj.index.vertices, axis=0) == pytest.approx([40.0, 50.0, 60.0])


def test_a_scene_s_point_cloud_left_out_is_named(tmp_path):
    box = trimesh.creation.box((40.0, 50.0, 60.0))
    cloud = trimesh.PointCloud(np.random.default_rng(0).uniform(100.0, 120.0, (50, 3)))
    scene = trimesh.Scene([box, cloud])
    with pytest.warns(UserWarning, match=r"1 of the scene's geometries have no faces \(PointCloud\) and are left out"):
        obj = so.from_mesh(scene, cache=False)
    assert np.ptp(obj.index.vertices, axis=0) == pytest.approx([40.0, 50.0, 60.0])  # the box alone
    scene.export(tmp_path / "scene.glb")
    with pytest.warns(UserWarning, match="left out"):
        so.load(tmp_path / "scene.glb", cache=False)


# --------------------------------------------------------------------------- shells that overlap, debris, outliers


def l_block():
    """Two closed boxes that pass through each other (one STL of an assembly), and the L-shaped solid they enclose."""
    a = trimesh.creation.box((60.0, 30.0, 30.0))
    b = trimesh.creation.box((30.0, 60.0, 30.0)).apply_translation([10.0, 10.0, 0.0])
    return trimesh.util.concatenate([a, b]), trimesh.boolean.union([a, b])


def test_closed_shells_that_overlap_are_joined_not_taken_as_their_hull():
    """The L-block's volume counts the 30 x 30 x 30 mm overlap twice (more than its hull's): it is not convex, and
    its empty corner is not part of the object."""
    mesh, solid = l_block()
    with pytest.warns(UserWarning, match=r"L-block: its closed shells pass through each other \(2\.7e\+04 mm\^3 lies "
                                         r"inside more than one.*joined into the solid they enclose, 8\.1e\+04 mm\^3"):
        obj = so.from_mesh(mesh, name="L-block")
    assert obj.info["method"] == "coacd" and obj.info["volume_ratio"] == pytest.approx(81000 / 94500)
    assert obj.info["repair"] == {"method": "union", "overlap": pytest.approx(27000), "volume": pytest.approx(81000)}
    assert obj.mesh.volume == pytest.approx(solid.volume) and obj.mesh.is_watertight
    corner = [[-15.0, 22.0, 0.0]]  # 7 mm from the L, in its empty corner
    assert not obj.contains(corner)[0] and not obj.mesh.contains(corner)[0]
    assert trimesh.proximity.closest_point(solid, obj.index.vertices)[1].max() < 3.0


def test_shells_that_only_graze_each_other_are_joined_without_a_warning():
    """Two 40 mm cubes that share a 0.01 mm slab (compound shapes of boxes are often built so): joined quietly."""
    a = trimesh.creation.box((40.0, 40.0, 40.0))
    b = a.copy().apply_translation([39.99, 0.0, 0.0])
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        obj = so.from_mesh(trimesh.util.concatenate([a, b]), name="two cubes", cache=False)
    assert obj.info["repair"]["method"] == "union" and obj.info["repair"]["overlap"] == pytest.approx(16.0, rel=1e-3)
    assert obj.info["method"] == "hull" and obj.mesh.volume == pytest.approx(128000 - 16.0)


def test_a_mesh_with_more_volume_than_its_hull_is_not_taken_as_its_hull(monkeypatch):
    """A surface that passes through itself where its shells cannot be joined: decomposed, with a warning."""
    monkeypatch.setattr(loading, "union_of_bodies", lambda mesh: (mesh, 0.0))
    with pytest.warns(UserWarning, match=r"its volume is 1\.14 times its convex hull's, which no solid's is"):
        obj = so.from_mesh(l_block()[0], name="L-block")
    assert obj.info["method"] == "coacd" and not obj.contains([[-15.0, 22.0, 0.0]])[0]


def test_a_cavity_is_not_joined_to_the_shell_around_it():
    outer = trimesh.creation.icosphere(3, 40.0)
    inner = trimesh.creation.icosphere(3, 30.0)
    inner.invert()
    hollow = trimesh.util.concatenate([outer, inner])
    assert so.repair.union_of_bodies(hollow) == (hollow, 0.0)


def test_a_speck_of_debris_far_from_the_object_is_dropped_with_a_warning(tmp_path):
    """A 60 x 50 x 90 mm box and a 2 mm speck 300 mm away: the box, exactly, not a coarser decomposition of both."""
    box = trimesh.creation.box((60.0, 50.0, 90.0))
    speck = trimesh.creation.icosphere(subdivisions=0, radius=1.0).apply_translation([300.0, 0.0, 0.0])
    with pytest.warns(UserWarning, match=r"box: 1 loose fragment\(s\) dropped as debris \(20 faces 1\.7 mm across, "
                                         r"closed, 269 mm from the rest\): each has at most 0\.1% of the largest part's"):
        obj = so.from_mesh(trimesh.util.concatenate([box, speck]), name="box")
    assert obj.info["method"] == "hull" and obj.extents == pytest.approx([60.0, 50.0, 90.0])
    assert obj.torque_scale == pytest.approx(so.from_mesh(box, cache=False).torque_scale)
    # read as metres the speck is 0.27 mm from the box, not debris: the same file at scale 0.001 keeps it
    path = tmp_path / "scan.stl"
    trimesh.util.concatenate([box, speck]).export(path)
    with pytest.warns(UserWarning) as record:
        assert so.load(path, scale=0.001).extents[0] > 0.3
    assert not any("debris" in str(w.message) for w in record)


def test_an_open_part_with_depth_on_the_object_is_kept():
    """A knob modelled as an open cap (no base) on a box's top: small and open, but not flat, and on the box: part
    of the object (kept, its rim capped), not a sheet beside it."""
    ball = trimesh.creation.icosphere(subdivisions=2, radius=4.0)
    cap = trimesh.Trimesh(ball.vertices, ball.faces[ball.triangles_center[:, 2] > 0.0]).apply_translation([0, 0, 30.0])
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        obj = so.from_mesh(trimesh.util.concatenate([trimesh.creation.box((60.0, 60.0, 60.0)), cap]), cache=False)
    assert obj.mesh.bounds[1, 2] == pytest.approx(34.0, abs=0.1) and not any("debris" in str(w.message) for w in caught)


@pytest.mark.parametrize("offset", [0.0, 0.5, 300.0])
def test_an_open_sheet_beside_the_object_is_debris_and_said_to_be_so(offset):
    """A 200 mm ground plane the box stands on (its corners and face centres are over 30 mm from the box), a label
    sheet 0.5 mm off its side, a stray sheet far away: each encloses nothing. Kept, the plane made a 200 mm object
    and the label was capped as a hole; the warning gave the plane's distance from its corners (36 mm)."""
    box = trimesh.creation.box((60.0, 40.0, 80.0))
    sheet = trimesh.Trimesh([[-100.0, -100.0, -40.0], [100.0, -100.0, -40.0], [100.0, 100.0, -40.0],
                             [-100.0, 100.0, -40.0]], [[0, 1, 2], [0, 2, 3]]).apply_translation([0.0, 0.0, -offset])
    if offset == 0.5:  # a label: 30 x 20 mm, 0.5 mm off the box's +x side
        sheet = trimesh.Trimesh([[30.5, -10.0, -15.0], [30.5, 10.0, -15.0], [30.5, 10.0, 15.0], [30.5, -10.0, 15.0]],
                                [[0, 1, 2], [0, 2, 3]])
    with pytest.warns(UserWarning, match=rf"box: 1 loose fragment\(s\) dropped as debris \(2 faces \d+ mm across, open, "
                                         rf"{offset:g} mm from the rest\).*or is a flat open sheet") as record:
        obj = so.from_mesh(trimesh.util.concatenate([box, sheet]), name="box", cache=False)
    assert obj.extents == pytest.approx([60.0, 40.0, 80.0]) and obj.info["method"] == "hull"
    assert not any("hole(s) capped" in str(w.message) for w in record)


def test_parts_that_are_all_flat_are_not_debris_and_the_mesh_is_refused_as_flat():
    """Two triangles 200 mm apart: no part has a volume to measure debris against; the flat mesh is refused."""
    a = trimesh.Trimesh([[0.0, 0.0, 0.0], [10.0, 0.0, 0.0], [0.0, 10.0, 0.0]], [[0, 1, 2]], process=False)
    b = a.copy().apply_translation([200.0, 0.0, 0.0])
    with pytest.raises(ValueError, match="has no volume: all its points lie on a plane"):
        so.from_mesh(trimesh.util.concatenate([a, b]), cache=False)


def test_a_debris_fraction_of_0_keeps_a_flat_fragment(monkeypatch):
    """The debris warning's advice: DEBRIS_FRACTION = 0 keeps every part, a stray triangle too."""
    monkeypatch.setattr(loading, "DEBRIS_FRACTION", 0.0)
    triangle = trimesh.Trimesh([[170.0, 0.0, 0.0], [175.0, 0.0, 0.0], [170.0, 5.0, 0.0]], [[0, 1, 2]], process=False)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        obj = so.from_mesh(trimesh.util.concatenate([trimesh.creation.box((60.0, 60.0, 60.0)), triangle]), cache=False)
    assert obj.extents[0] > 200.0 and not any("debris" in str(w.message) for w in caught)


def test_a_second_object_or_a_small_part_near_the_object_is_not_debris():
    box = trimesh.creation.box((60.0, 50.0, 90.0))
    ball = trimesh.creation.icosphere(2, 10.0).apply_translation([100.0, 0.0, 0.0])  # 1.6 % of the box's volume
    with pytest.warns(UserWarning, match="2 separate parts"):
        assert so.from_mesh(trimesh.util.concatenate([box, ball])).extents[0] > 130.0  # both (60 mm alone)
    knob = trimesh.creation.icosphere(1, 1.0).apply_translation([36.0, 0.0, 0.0])  # a speck 5 mm from the box
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert so.from_mesh(trimesh.util.concatenate([box, knob])).extents[0] > 66.0  # both


def test_an_isolated_outlier_of_a_scan_is_dropped():
    """One point 35 mm off an 80 mm ball scan: its 8th neighbour is under 10 typical 8th-neighbour distances away, but
    its nearest is over 20 typical nearest-neighbour distances; without the drop the object grows a spike."""
    rng = np.random.default_rng(0)
    points = rng.normal(size=(2000, 3))
    points *= 40.0 / np.linalg.norm(points, axis=1, keepdims=True)
    points += rng.normal(scale=0.3, size=points.shape)
    for scale in (1.0, 1000.0):  # the same scan in metres, scaled: its distances in mm too (they read 0.035 "mm")
        with pytest.warns(UserWarning, match=r"ball scan: 1 stray point\(s\) dropped \(up to 35 mm from the nearest "
                                             r"other point, where the cloud's typical spacing is 1\.5 mm\)"):
            obj = so.from_points(np.vstack([points, [[75.0, 0.0, 0.0]]]) / scale, scale=scale, name="ball scan",
                                 cache=False)
        assert obj.n_pieces == 1 and obj.extents == pytest.approx([80.0, 80.0, 80.0], abs=2.0)


# --------------------------------------------------------------------------- other inputs and messages


@pytest.mark.parametrize("primitive", [trimesh.primitives.Box(extents=[50, 60, 70]), trimesh.primitives.Sphere(radius=30),
                                       trimesh.primitives.Cylinder(radius=30, height=80),
                                       trimesh.primitives.Capsule(radius=20, height=80)])
def test_trimesh_primitives_are_meshes(primitive):
    obj = so.from_mesh(primitive, cache=False)
    assert obj.info["method"] == "hull" and obj.extents == pytest.approx(primitive.extents, abs=0.5)


def test_a_non_finite_vertex_of_an_npz_mesh_is_refused(tmp_path):
    """As in the other mesh files: not dropped with its faces and the hole capped. Duplicate vertices are still merged."""
    mesh = trimesh.creation.icosphere(subdivisions=2, radius=30.0)
    vertices = mesh.vertices.copy()
    vertices[5] = np.nan
    np.savez(tmp_path / "ball.npz", vertices=vertices, faces=mesh.faces)
    with pytest.raises(ValueError, match=r"ball\.npz vertices contains NaN or inf at rows \[5\]"):
        so.load(tmp_path / "ball.npz", cache=False)
    box = trimesh.creation.box((40.0, 50.0, 60.0))
    np.savez(tmp_path / "soup.npz", vertices=box.triangles.reshape(-1, 3), faces=np.arange(36).reshape(12, 3))
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # welded on reading as trimesh does: no "needed repair"
        obj = so.load(tmp_path / "soup.npz", cache=False)
    assert obj.info["method"] == "hull" and obj.info["watertight"]


def test_a_gltf_whose_buffer_file_is_missing_says_so(tmp_path):
    trimesh.creation.box((40.0, 50.0, 60.0)).export(tmp_path / "part.gltf")
    for buffer in tmp_path.glob("*.bin"):
        buffer.unlink()
    with pytest.raises(ValueError, match=r"could not read .*part\.gltf' as a \.gltf file: a file it refers to is "
                                         r"missing: 'gltf_buffer_0\.bin'.*export it as one \.glb"):
        so.load(tmp_path / "part.gltf")


def test_empty_meshes_are_called_empty(tmp_path):
    for mesh in (trimesh.Scene(), trimesh.Trimesh()):
        with pytest.raises(ValueError, match="mesh is empty: it has no vertices and no faces"):
            so.from_mesh(mesh)
    np.savez(tmp_path / "empty.npz", vertices=np.zeros((0, 3)), faces=np.zeros((0, 3), dtype=int))
    with pytest.raises(ValueError, match="empty.npz vertices is empty"):
        so.load(tmp_path / "empty.npz")


@pytest.mark.parametrize("ext", [".stl", ".glb"])
def test_the_advice_for_separate_parts_runs(tmp_path, ext):
    """The warning's way to load one part alone works for a mesh file and for a scene file."""
    ball = trimesh.creation.icosphere(radius=20.0).apply_translation([150.0, 0.0, 0.0])
    path = tmp_path / f"two{ext}"
    trimesh.Scene([trimesh.creation.box((40.0, 40.0, 40.0)), ball]).export(path)
    with pytest.warns(UserWarning, match="separate parts") as record:
        so.load(path, cache=False)
    advice = str(record[-1].message).split("its parts are ")[1]
    parts = eval(advice, {"trimesh": trimesh, "path": str(path)})
    one = so.from_mesh(max(parts, key=lambda part: part.volume), cache=False)
    assert one.extents == pytest.approx([40.0, 40.0, 40.0])


def test_the_size_warning_suggests_inches():
    can = trimesh.creation.cylinder(radius=1.5, height=4.0)  # a 3 x 3 x 4 inch can
    with pytest.warns(UserWarning, match=r"metres pass scale=1000 \(centimetres: scale=10, inches: scale=25\.4\)"):
        so.from_mesh(can, cache=False)


@pytest.mark.parametrize("value, hint", [
    (box_mesh(), "got Trimesh: for a trimesh mesh already in memory use sg.objects.from_mesh(mesh)"),
    (np.zeros((10, 3)), "got ndarray: for points already in memory use sg.objects.from_points(points)"),
    (None, "got NoneType"),
    (b"box.stl", "got bytes"),
])
def test_load_takes_a_path_and_names_the_function_for_objects_in_memory(value, hint):
    with pytest.raises(TypeError, match="path must be a file path") as info:
        so.load(value)
    assert str(info.value).endswith(hint)


@pytest.mark.parametrize("value", ["no", None, 0])
def test_cache_must_be_a_bool(tmp_path, value):
    """cache="no" is a true string: it must not turn the cache on silently."""
    path = tmp_path / "box.stl"
    box_mesh().export(path)
    for load in (lambda: so.from_mesh(box_mesh(), cache=value), lambda: so.from_points(ellipsoid_cloud(), cache=value),
                 lambda: so.load(path, cache=value)):
        with pytest.raises(TypeError, match=f"cache must be True or False, got {value!r}"):
            load()
    assert so.from_mesh(box_mesh(), cache=np.bool_(False)).info["cache"] == "disabled"


@pytest.mark.parametrize("name", ["", "  "])
def test_an_empty_object_name_is_not_taken_for_the_current_folder(name):
    with pytest.raises(ValueError, match="the object name is empty: give a built-in"):
        so.get(name)


def test_a_cloud_with_normals_or_colours_reads_its_first_three_columns_and_a_few_points_are_warned_of(tmp_path):
    """x y z nx ny nz as .npy is read like the same columns in .xyz; five points are a convex solid's corners, said
    so (an OBJ of lines alone, which trimesh reads as its vertices, too)."""
    cloud = ellipsoid_cloud(200)
    rows = np.c_[cloud, cloud / np.linalg.norm(cloud, axis=1, keepdims=True)]
    np.save(tmp_path / "n.npy", rows)
    (tmp_path / "n.xyz").write_text("\n".join(" ".join(map(str, p)) for p in rows))
    a, b = so.load(tmp_path / "n.npy", cache=False), so.load(tmp_path / "n.xyz", cache=False)
    np.testing.assert_allclose(a.points, b.points, atol=1e-12)
    assert a.points.shape[1] == 3
    counted = np.c_[np.arange(len(cloud)), cloud]  # a point number first: refused from .npy as from .xyz
    np.save(tmp_path / "i.npy", counted)
    (tmp_path / "i.xyz").write_text("\n".join(" ".join(map(str, p)) for p in counted))
    for name in ("i.npy", "i.xyz"):
        with pytest.raises(ValueError, match="its first column counts the lines .0, 1, 2, ...."):
            so.load(tmp_path / name, cache=False)
    with pytest.warns(UserWarning, match="only 5 distinct points: they are taken as the corners of a convex solid"):
        so.from_points(cloud[:5], cache=False)
    (tmp_path / "lines.obj").write_text("v 0 0 0\nv 50 0 0\nv 0 50 0\nv 0 0 50\nl 1 2\nl 1 3\nl 1 4\n")
    with pytest.warns(UserWarning, match="only 4 distinct points.*an OBJ of lines"):
        so.load(tmp_path / "lines.obj", cache=False)


def test_a_scale_beyond_the_working_range_is_refused_before_anything_overflows(tmp_path):
    """scale=1e300 used to print numpy's overflow warnings before the refusal; now only the refusal, naming the scale."""
    ball = trimesh.creation.icosphere(2, radius=0.035)
    ball.export(tmp_path / "m.stl")
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no RuntimeWarning (nor any other) on the way
        for load in (lambda: so.load(tmp_path / "m.stl", scale=1e300, cache=False),
                     lambda: so.from_mesh(ball, scale=1e300, cache=False),
                     lambda: so.from_points(ball.vertices, scale=1e300, cache=False)):
            with pytest.raises(ValueError, match=r"0.07 across in its own units, 7e\+298 mm at scale 1e\+300: beyond"):
                load()
    # measured after what the loaders drop: a stray point 2 km off a ball in metres is dropped, not the scale refused
    cloud = np.r_[trimesh.sample.sample_surface(ball, 2000, seed=0)[0], [[2000.0, 0.0, 0.0]]]
    with pytest.warns(UserWarning, match="stray"):
        assert so.from_points(cloud, scale=1000.0, cache=False).size == pytest.approx(70.0, abs=2.0)


def test_a_cloud_of_shape_3_by_n_and_an_xyz_header_get_a_hint(tmp_path):
    cloud = ellipsoid_cloud(200)
    np.save(tmp_path / "t.npy", cloud.T)
    with pytest.raises(ValueError, match=r"dimension 200, expected 3 \(an array of shape \(3, n\)\? pass its transpose"):
        so.load(tmp_path / "t.npy")
    (tmp_path / "h.xyz").write_text("x y z\n" + "\n".join(" ".join(map(str, p)) for p in cloud))
    with pytest.raises(ValueError, match="start a header or comment line with #"):
        so.load(tmp_path / "h.xyz")
    (tmp_path / "h.xyz").write_text("# x y z\n" + "\n".join(" ".join(map(str, p)) for p in cloud))
    assert so.load(tmp_path / "h.xyz", cache=False).n_pieces == 1


# --------------------------------------------------------------------------- files as people write them


def test_xyz_with_a_byte_order_mark(tmp_path):
    """A spreadsheet's UTF-8 export starts with an invisible byte-order mark: read as if it were not there."""
    points = ellipsoid_cloud(300)
    for name, sep in (("space.xyz", " "), ("comma.xyz", ",")):
        path = tmp_path / name
        path.write_text("\n".join(sep.join(f"{v:.6f}" for v in p) for p in points), encoding="utf-8-sig")
        assert path.read_bytes()[:3] == b"\xef\xbb\xbf"
        assert so.load(path, cache=False).extents == pytest.approx(np.ptp(points, axis=0), abs=1e-5)


def test_obj_whose_faces_do_not_share_corners_loads_quietly(tmp_path):
    """Each face with its own corners (an export with per-corner texture coordinates): the same closed
    surface once they are merged, so no repair warning."""
    box = trimesh.creation.box((40.0, 50.0, 60.0))
    corners = box.vertices[box.faces].reshape(-1, 3)
    n = len(corners)
    lines = ([f"v {x} {y} {z}" for x, y, z in corners] + [f"vt {i / n} {1 - i / n}" for i in range(n)]
             + [f"f {k}/{k} {k + 1}/{k + 1} {k + 2}/{k + 2}" for k in range(1, n + 1, 3)])
    path = tmp_path / "box_uv.obj"
    path.write_text("\n".join(lines) + "\n")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        obj = so.load(path, cache=False)
    assert obj.info["repair"]["method"] == "cleaned" and obj.info["repair"]["removed_faces"] == 0
    assert obj.n_pieces == 1 and obj.volume == pytest.approx(40.0 * 50.0 * 60.0)


def test_an_object_of_a_few_centimetres_read_as_mm_is_warned_of():
    """A 15 cm bottle written in cm loads 15 mm tall: inside 10-500 mm, but the warning names centimetres."""
    bottle = trimesh.creation.cylinder(radius=3.5, height=15.0)
    with pytest.warns(UserWarning, match=r"15 mm across, small for this hand.*centimetres pass scale=10"):
        so.from_mesh(bottle, cache=False)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        so.from_mesh(bottle, scale=10.0, cache=False)


def test_many_outliers_are_kept_with_a_warning_that_names_them():
    """Up to 5 % of isolated points are dropped as a scan's outliers; more are kept, and the warning says so."""
    rng = np.random.default_rng(1)
    surface = ellipsoid_cloud(2000)
    few, many = rng.uniform(-500.0, 500.0, (40, 3)), rng.uniform(-500.0, 500.0, (150, 3))
    with pytest.warns(UserWarning, match="40 stray point"):
        dropped = so.from_points(np.vstack([surface, few]), cache=False)
    assert dropped.extents == pytest.approx(np.ptp(surface, axis=0), abs=1e-6)
    with pytest.warns(UserWarning, match=r"1[45]\d points \([67]\.\d% of the cloud\) lie apart.*If they are a scan's outliers"):
        so.from_points(np.vstack([surface, many]), max_parts=1, cache=False)


def test_a_cloud_of_two_objects_is_warned_of():
    """Two balls 50 mm apart in one cloud: one rigid object, as for a mesh of two parts, with a warning
    that measures the gap; the same balls touching, and a sparse cloud of one ball, give none."""
    rng = np.random.default_rng(0)

    def ball(x, n):
        p = rng.normal(size=(n, 3))
        return 30.0 * p / np.linalg.norm(p, axis=1, keepdims=True) + [x, 0.0, 0.0]

    with pytest.warns(UserWarning, match=r"2 separate groups of points, some 5\d mm from the rest.*pass its points alone"):
        so.from_points(np.vstack([ball(0.0, 1500), ball(110.0, 1500)]), cache=False)
    for points in (np.vstack([ball(0.0, 1500), ball(60.0, 1500)]), ball(0.0, 80)):
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            so.from_points(points, cache=False)


def test_xyz_with_a_point_number_column_is_refused(tmp_path):
    """``id x y z`` lines would read the point number as x: refused, naming the column; x y z nx ny nz is read."""
    points = ellipsoid_cloud(300)
    numbered = tmp_path / "numbered.xyz"
    numbered.write_text("\n".join(f"{i + 1} {x} {y} {z}" for i, (x, y, z) in enumerate(points)))
    with pytest.raises(ValueError, match=r"first column counts the lines \(1, 2, 3, \.\.\.\): a point number, not x"):
        so.load(numbered, cache=False)
    with_normals = tmp_path / "normals.xyz"
    with_normals.write_text("\n".join(f"{x} {y} {z} 0 0 1" for x, y, z in points))
    assert so.load(with_normals, cache=False).extents == pytest.approx(np.ptp(points, axis=0), abs=1e-9)


def test_a_thin_wall_of_boxes_merged_at_their_edges_is_closed_on_a_finer_grid(tmp_path):
    """20 bricks of 20 x 10 x 10 mm in staggered rows, saved as STL (their corners merged, so edges are shared by
    four faces): not closable by capping, and at the default grid (2.75 mm) the 10 mm wall has no inside; a finer
    grid closes it, with the wall's extents and about its volume."""
    bricks = [trimesh.creation.box((20.0, 10.0, 10.0)).apply_translation((10.0 * (row % 2) + 20.0 * k + 10.0, 5.0,
                                                                            10.0 * row + 5.0))
              for row in range(4) for k in range(5)]
    path = tmp_path / "wall.stl"
    trimesh.util.concatenate(bricks).export(path)
    with pytest.warns(UserWarning, match=r"non-manifold.*closed on a voxel grid instead"):
        wall = so.load(path, cache=False)
    assert wall.extents == pytest.approx([110.0, 10.0, 40.0], abs=0.5)
    assert wall.info["repair"]["filled_volume"] == pytest.approx(20 * 2000.0, rel=0.2)
    assert not wall.contains([[5.0, 5.0, 15.0]])[0], "the notch of a staggered row stays empty"


def test_a_scale_that_brings_a_file_into_range_is_applied_before_its_pieces_are_made(tmp_path):
    """A cylinder stored in 10 nm units (1e7 across) loaded with scale=1e-5: 100 mm, not refused as 1e7 mm across
    with advice (a scale) that did not help; the same for its points."""
    mesh = trimesh.creation.cylinder(radius=30.0, height=100.0).apply_scale(1e5)
    mesh.export(tmp_path / "nm.stl")
    obj = so.load(tmp_path / "nm.stl", scale=1e-5, cache=False)
    np.testing.assert_allclose(obj.extents, [60.0, 60.0, 100.0], rtol=1e-6)
    assert obj.info["scale"] == 1e-5
    cloud = so.from_points(trimesh.sample.sample_surface(mesh, 2000, seed=0)[0], scale=1e-5, cache=False)
    assert cloud.extents.max() == pytest.approx(100.0, rel=0.05) and cloud.info["scale"] == 1e-5
    with pytest.raises(ValueError, match="1e\\+07 mm across, outside"):  # without the scale: refused as before
        so.load(tmp_path / "nm.stl", cache=False)


def test_a_file_read_as_less_than_it_holds_is_refused(tmp_path):
    """A truncated ASCII PLY, OFF or OBJ loaded as a fragment (part of a ball, half a torus) with a warning about holes; a
    glTF whose geometry trimesh does not decode (Draco) lost that part as 'debris'. Each is now refused, saying why."""
    ball = trimesh.creation.icosphere(subdivisions=3, radius=35.0)
    raw = trimesh.exchange.ply.export_ply(ball, encoding="ascii")
    (tmp_path / "cut.ply").write_bytes(raw[: int(len(raw) * 0.7)])
    with pytest.raises(ValueError, match=r"cut\.ply.*holds .* of its 1280 faces its header declares: the file is truncated"):
        so.load(tmp_path / "cut.ply", cache=False)
    text = trimesh.exchange.off.export_off(trimesh.creation.torus(40.0, 12.0))
    (tmp_path / "cut.off").write_text(text[: int(len(text) * 0.8)])
    with pytest.raises(ValueError, match="its header declares: the file is truncated"):
        so.load(tmp_path / "cut.off", cache=False)
    text = trimesh.exchange.obj.export_obj(ball)  # cut in a face line, then in a vertex line
    face, vertex = text.index("\nf ", len(text) // 2) + 4, text.index("\nv ") + 8
    for name, end, line in (("cut.obj", face, "a face needs 3 vertices"), ("cutv.obj", vertex, "a vertex needs 3 coordinates")):
        (tmp_path / name).write_text(text[:end])  # (read as a mesh with a hole, or as 'points of dimension 1')
        with pytest.raises(ValueError, match=rf"{name}.*its last line .* is cut short \({line}\): the file is truncated"):
            so.load(tmp_path / name, cache=False)
    files = trimesh.exchange.gltf.export_gltf(trimesh.Scene(ball))
    gltf = json.loads(files["model.gltf"])
    files["model.gltf"] = json.dumps({**gltf, "extensionsUsed": ["KHR_draco_mesh_compression"]}).encode()
    for name, data in files.items():
        (tmp_path / name).write_bytes(data)
    with pytest.raises(ValueError, match="uses KHR_draco_mesh_compression, which the glTF reader does not decode"):
        so.load(tmp_path / "model.gltf", cache=False)
    corners = trimesh.creation.box((40.0, 40.0, 40.0)).vertices  # faces as triangle strips: read as a point cloud
    (tmp_path / "strips.ply").write_text(
        f"ply\nformat ascii 1.0\nelement vertex {len(corners)}\nproperty float x\nproperty float y\nproperty float z\n"
        "element tristrips 1\nproperty list int int vertex_indices\nend_header\n"
        + "".join(f"{x} {y} {z}\n" for x, y, z in corners) + "10 0 1 2 3 4 5 6 7 0 1\n")
    with pytest.raises(ValueError, match="its faces are triangle strips"):
        so.load(tmp_path / "strips.ply", cache=False)
    raw = trimesh.exchange.ply.export_ply(ball, encoding="ascii")  # whole: loads
    (tmp_path / "whole.ply").write_bytes(raw)
    assert so.load(tmp_path / "whole.ply", cache=False).extents.max() == pytest.approx(70.0, rel=0.01)
