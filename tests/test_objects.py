"""synergrasp.objects: built-ins, cP, sQ contacts and capsule penetration."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

import synergrasp as sg
import synergrasp.objects as so
from synergrasp.objects import facets
from synergrasp.objects.contact_distance import cp_bounds, group_contact_distance
from synergrasp.objects.distance_grid import DistanceGrid
from synergrasp.planner import forget_warm_starts
from tests.conftest import BACKENDS, assert_gradient, central_difference

Q = sg.regular_simplex(3)


def gauge(x):
    """Gauge of the default regular simplex: -3 min_k q_k . x."""
    return -3.0 * np.min(Q @ np.asarray(x, dtype=float))


def box(half=10.0, center=(0.0, 0.0, 0.0)):
    corners = np.array(np.meshgrid([-1, 1], [-1, 1], [-1, 1])).reshape(3, -1).T
    return half * corners + np.asarray(center)


def ray_exit_box(p, direction, half):
    """Largest r with p + r * direction inside the cube [-half, half]^3 (p inside)."""
    with np.errstate(divide="ignore"):
        t = np.where(direction > 0, (half - p) / direction, np.where(direction < 0, (-half - p) / direction, np.inf))
    return t.min()


@pytest.fixture(scope="module")
def goblet():
    return so.goblet()


@pytest.fixture(scope="module")
def ellipsoid():
    return so.ellipsoid()


@pytest.fixture(scope="module")
def cube():
    return so.GraspObject([box(10.0)], name="cube")


def around(obj, n, rng, gap=(0.5, 40.0)):
    """n points gap mm off the object's surface along outward normals."""
    mesh = obj.to_mesh()
    import trimesh

    pts, face = trimesh.sample.sample_surface(mesh, n, seed=int(rng.integers(1 << 30)))
    return pts + rng.uniform(*gap, size=(n, 1)) * mesh.face_normals[face]


# --------------------------------------------------------------------------- built-ins


@pytest.mark.parametrize("name", list(so.BUILTINS))
def test_builtins_are_sized_for_a_hand(name):
    obj = so.get(name)
    assert isinstance(obj, so.GraspObject) and obj.name.startswith(name)
    assert 60 <= obj.size <= 170
    assert obj.contains([obj.center])[0], "the sQ rays need the centre inside"
    assert obj.torque_scale == pytest.approx(max(np.linalg.norm(v - obj.center, axis=1).max() for v in obj.pieces))
    assert obj.mesh is not None and obj.mesh.is_watertight
    # the pieces tile the solid: their volumes add up to the polygonal solid's
    assert obj.volume == pytest.approx(obj.mesh.volume, rel=1e-6)


def test_builtin_sizes():
    cup, bell, goblet = so.cup(), so.bell(), so.goblet()
    assert cup.extents == pytest.approx([75, 75, 80], abs=0.5)
    assert cup.n_pieces > 1  # flared: non-convex
    assert bell.extents[:2] == pytest.approx([90, 90], abs=0.5) and bell.n_pieces > 3
    assert goblet.extents == pytest.approx([76, 76, 160], abs=0.5) and goblet.n_pieces == 3


def test_ellipsoid_is_accurate_to_half_a_mm(ellipsoid):
    assert ellipsoid.n_pieces == 1
    assert ellipsoid.center == pytest.approx([0, 0, 0])
    assert ellipsoid.torque_scale == pytest.approx(50.0)
    v = ellipsoid.pieces[0]
    assert np.sum((v / [30, 40, 50]) ** 2, axis=1) == pytest.approx(1.0)  # vertices on the surface
    assert ellipsoid.info["max_gap"] <= 0.5
    # cP from outside along the axes: the Euclidean gap is within the faceting
    rng = np.random.default_rng(0)
    d = rng.normal(size=(50, 3))
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    surface = d / np.sqrt(np.sum((d / [30, 40, 50]) ** 2, axis=1, keepdims=True))
    assert (ellipsoid.contains(surface * 0.99)).all()
    assert not ellipsoid.contains(surface * 1.0 + 0.5 * d).any()


def test_get_and_errors():
    assert so.get("GOBLET").name == "goblet"
    with pytest.raises(ValueError, match="not a built-in"):
        so.get("teapot")
    with pytest.raises(ValueError, match="no volume"):
        so.GraspObject([[[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]]])
    with pytest.raises(ValueError, match="empty"):
        so.GraspObject([])
    with pytest.raises(ValueError, match="NaN"):
        so.GraspObject([box() * np.nan])


def test_revolve_cuts_at_convex_kinks():
    # an hourglass: two cones tip to tip are two convex pieces
    hourglass = so.revolve([[20, 0], [5, 20], [20, 40]], name="hourglass")
    assert hourglass.n_pieces == 2
    # a barrel (concave profile) is one convex piece
    barrel = so.revolve([[10, 0], [15, 10], [16, 20], [15, 30], [10, 40]])
    assert barrel.n_pieces == 1
    with pytest.raises(ValueError, match="strictly increasing"):
        so.revolve([[10, 0], [10, 0]])
    with pytest.raises(ValueError, match="negative"):
        so.revolve([[10, 0], [-1, 5], [10, 10]])


def test_a_tolerance_finer_than_the_shapes_are_built_to_is_refused():
    """revolve(tolerance=1e-9) ran for over ten minutes (a ring of millions of sides); the ellipsoid stopped at its
    finest polytope without saying that the tolerance was not met."""
    spool = [[30.0, 0.0], [20.0, 50.0], [30.0, 100.0]]
    with pytest.raises(ValueError, match=r"tolerance 1e-09 mm is finer .* largest radius \(30 mm\), 0.003 mm"):
        so.revolve(spool, tolerance=1e-9)
    with pytest.raises(ValueError, match=r"largest semi-axis \(50 mm\), 0.005 mm"):
        so.ellipsoid(tolerance=0.004)
    finest = so.ellipsoid(tolerance=so.MIN_TOLERANCE * 50.0)  # the finest accepted is met
    assert finest.info["max_gap"] <= so.MIN_TOLERANCE * 50.0
    assert so.revolve(spool, tolerance=so.MIN_TOLERANCE * 30.0).info["ring_sides"] <= 300


def test_transformed(goblet):
    R = np.array([[0, -1, 0], [1, 0, 0], [0, 0, 1.0]])
    M = np.eye(4)
    M[:3, :3], M[:3, 3] = R, [100, 0, 0]
    moved = goblet.transformed(M)
    p = np.array([[50.0, 10.0, 120.0]])
    assert moved.center == pytest.approx(R @ goblet.center + [100, 0, 0])
    assert moved.contains(p @ R.T + [100, 0, 0])[0] == goblet.contains(p)[0]
    # the simplex gauge is not rotation invariant, but it is translation invariant
    shifted = np.eye(4)
    shifted[:3, 3] = [5, -3, 2]
    t = goblet.transformed(shifted)
    assert t.contact_distance(p + [5, -3, 2]).value == pytest.approx(goblet.contact_distance(p).value, abs=1e-7)
    with pytest.raises(ValueError, match="rigid"):
        goblet.transformed(np.diag([2.0, 1, 1, 1]))
    # a pose in single precision (R R^T off by about 1e-7) is taken as the nearest rotation; an exact one as given
    turn = Rotation.from_euler("xyz", [0.3, -0.7, 1.1]).as_matrix()
    single = np.eye(4)
    single[:3, :3], single[:3, 3] = turn.astype(np.float32), [100, 0, 0]
    assert np.abs(single[:3, :3] @ single[:3, :3].T - np.eye(3)).max() > 1e-9
    near = goblet.transformed(single)
    exact = np.eye(4)
    exact[:3, :3], exact[:3, 3] = turn, [100, 0, 0]
    np.testing.assert_allclose(near.center, goblet.transformed(exact).center, atol=1e-4)
    piece = near.convex[0].vertices - near.center
    np.testing.assert_allclose(np.sort(np.linalg.norm(piece, axis=1)),
                               np.sort(np.linalg.norm(goblet.convex[0].vertices - goblet.center, axis=1)), rtol=1e-9)
    assert np.array_equal(goblet.transformed(M).convex[0].vertices,
                          goblet.convex[0].transformed(R, np.array([100.0, 0, 0])).vertices)  # exact: as given


# --------------------------------------------------------------------------- cP


def test_cp_closed_forms_on_a_cube(cube, backend):
    # outside along +z: b - p points along -z, a vertex direction of Q: gauge = Euclidean
    # outside along -z: b - p along +z, opposite a vertex: gauge = 3 x Euclidean
    pts = np.array([[0, 0, 25.0], [0, 0, -25.0], [1.0, -2.0, 14.0]])
    r = cube.contact_distance(pts, backend=backend)
    assert r.value[:2] == pytest.approx([15.0, 45.0], abs=1e-7)
    assert r.value[2] == pytest.approx(4.0, abs=1e-7)  # straight above the top face, 4 mm
    assert r.nearest[0] == pytest.approx([0, 0, 10], abs=1e-6)
    assert r.normal[0] == pytest.approx([0, 0, -1], abs=1e-7)  # inward
    assert r.grad[1] == pytest.approx([0, 0, -3], abs=1e-7)
    assert not r.inside.any()


def test_cp_point_to_point_closed_form(backend):
    # a tiny piece around b: the value tends to gauge(b - p)
    rng = np.random.default_rng(3)
    for _ in range(5):
        b, p = rng.normal(size=3) * 20, rng.normal(size=3) * 20
        tiny = so.GraspObject([box(1e-4, b)])
        r = tiny.contact_distance([p], backend=backend)
        assert r.value[0] == pytest.approx(gauge(b - p), abs=1e-3)


def test_cp_inside_cube_closed_form(cube, backend):
    rng = np.random.default_rng(4)
    pts = rng.uniform(-9.5, 9.5, size=(12, 3))
    r = cube.contact_distance(pts, backend=backend)
    expected = [-min(ray_exit_box(p, -q, 10.0) for q in Q) for p in pts]
    assert r.value == pytest.approx(expected, abs=1e-7)
    assert r.inside.all()
    assert r.value[np.argmin(np.abs(pts).max(axis=1))] < 0


def test_cp_matches_core_pseudo_distance(goblet, backend):
    rng = np.random.default_rng(5)
    pts = np.vstack([around(goblet, 12, rng), goblet.center + rng.normal(size=(4, 3)) * 5])
    r = goblet.contact_distance(pts, backend=backend)
    for i, p in enumerate(pts):
        per_piece = [sg.pseudo_distance([p], V, backend=backend) for V in goblet.pieces]
        best = min(per_piece, key=lambda x: x.value)
        # the same LP, posed in other coordinates (pseudo_distance's about the pair's centre): an interior-point
        # backend's answers agree to its tolerance, 1e-8 of the value
        assert r.value[i] == pytest.approx(best.value, rel=1e-8, abs=1e-7)
        if not r.degenerate[i]:
            assert r.grad[i] == pytest.approx(best.grad_a[0], abs=1e-6)
    assert (r.value[-4:] < 0).all() and r.inside[-4:].all()
    if sg.lp.get_backend(backend).max_columns is None:  # all blocks in one LP
        assert r.lp_solves == 1


def test_cp_sign_and_continuity_across_the_surface(goblet, backend):
    # walk along an outward normal through the bowl's surface
    p0 = np.array([0.0, 0.0, goblet.center[2]])
    direction = np.array([1.0, 0.3, 0.1])
    direction /= np.linalg.norm(direction)
    s = np.linspace(20.0, 50.0, 61)
    r = goblet.contact_distance(p0 + s[:, None] * direction, backend=backend)
    inside = goblet.contains(p0 + s[:, None] * direction)
    assert (np.sign(r.value[inside]) <= 0).all() and (r.value[~inside] > 0).all()
    assert inside[0] and not inside[-1]
    # continuous: the value changes at most 3x (gauge bound) the step
    assert np.abs(np.diff(r.value)).max() <= 3.0 * (s[1] - s[0]) + 1e-9
    k = np.argmax(~inside)
    assert abs(r.value[k]) <= 3 * (s[1] - s[0]) and abs(r.value[k - 1]) <= 3 * (s[1] - s[0])


def test_cp_gradients_match_finite_differences(goblet, ellipsoid, backend):
    rng = np.random.default_rng(6)
    for obj in (goblet, ellipsoid):
        pts = np.vstack([around(obj, 6, rng), obj.center + rng.normal(size=(2, 3)) * 4])
        r = obj.contact_distance(pts, backend=backend)
        for i in np.nonzero(~r.degenerate)[0]:
            f = lambda p: obj.contact_distance(p[None], backend=backend).value[0]  # noqa: E731
            assert_gradient(r.grad[i], central_difference(f, pts[i], h=1e-5), rtol=1e-5, atol=1e-7)


def test_group_cp_is_the_group_minimum_and_warm_starts_change_nothing(backend):
    """`group_contact_distance`: the smallest cP of each group; warm starts from the last bases keep every value."""
    rng = np.random.default_rng(21)
    obj = so.goblet()
    pts = np.vstack([around(obj, 30, rng, gap=(-3, 25)), obj.center + rng.normal(size=(6, 3)) * 4])
    groups = np.repeat(np.arange(12), 3)
    for step in range(3):  # the same points moving a little: later calls start from remembered bases
        moved = pts + step * 0.3
        r, best = group_contact_distance(obj, moved, groups, backend)
        alone = obj.contact_distance(moved, backend=backend)  # no memory
        for g in range(12):
            rows = np.flatnonzero(groups == g)
            assert r.value[g] == pytest.approx(alone.value[rows].min(), abs=1e-7)
            assert best[g] in rows and alone.value[best[g]] == pytest.approx(r.value[g], abs=1e-7)
            if not r.degenerate[g]:
                assert r.grad[g] == pytest.approx(alone.grad[best[g]], abs=1e-6)
    assert (len(obj.index.memory) > 0) == sg.lp.get_backend(backend).basis_hints  # only simplex backends use them


def test_cp_rejects_bad_points(goblet):
    with pytest.raises(ValueError, match=r"\(n, 3\)"):
        goblet.contact_distance([1.0, 2.0, 3.0])
    with pytest.raises(ValueError, match="dimension 2"):
        goblet.contact_distance([[1.0, 2.0]])
    with pytest.raises(ValueError, match="NaN"):
        goblet.contact_distance([[1.0, np.nan, 3.0]])
    with pytest.raises(ValueError, match="empty"):
        goblet.contact_distance(np.zeros((0, 3)))
    with pytest.raises(ValueError, match="unknown LP backend"):
        goblet.contact_distance([[0, 0, 300.0]], backend="simplex-by-hand")


@pytest.mark.skipif(len(BACKENDS) < 2, reason="needs two backends")
def test_backends_agree(goblet):
    rng = np.random.default_rng(7)
    pts = np.vstack([around(goblet, 10, rng), goblet.center + rng.normal(size=(3, 3)) * 4])
    ref = goblet.contact_distance(pts, backend=BACKENDS[0])
    sref = goblet.scaled_contacts(pts, backend=BACKENDS[0])
    for name in BACKENDS[1:]:
        r = goblet.contact_distance(pts, backend=name)
        assert r.value == pytest.approx(ref.value, abs=1e-7)
        ok = ~ref.degenerate
        assert r.grad[ok] == pytest.approx(ref.grad[ok], abs=1e-7)
        s = goblet.scaled_contacts(pts, backend=name)
        assert s.scale == pytest.approx(sref.scale, abs=1e-7)
        assert s.contact == pytest.approx(sref.contact, abs=1e-6)
        ok = ~sref.degenerate
        assert s.normal[ok] == pytest.approx(sref.normal[ok], abs=1e-7)


def _random_object(seed):
    """A few random convex pieces (random point sets) scattered in a 100 mm box."""
    rng = np.random.default_rng(seed)
    pieces = []
    for _ in range(rng.integers(2, 6)):
        centre = rng.uniform(-40, 40, size=3)
        pieces.append(centre + rng.normal(size=(int(rng.integers(6, 15)), 3)) * rng.uniform(3, 15, size=3))
    return so.GraspObject(pieces), rng


def _probe_points(obj, rng, n):
    """n points around a random object, the first two inside or near its first piece."""
    pts = rng.uniform(-70, 70, size=(n, 3))
    pts[:2] = obj.pieces[0].mean(axis=0) + rng.normal(size=(2, 3))
    return pts


@settings(max_examples=40, deadline=None)
@given(seed=st.integers(0, 2**31 - 1))
def test_broad_phase_pruning_never_changes_the_value(seed):
    obj, rng = _random_object(seed)
    pts = _probe_points(obj, rng, 6)
    r = obj.contact_distance(pts)
    best = [min((sg.pseudo_distance([p], V) for V in obj.pieces), key=lambda x: x.value) for p in pts]
    brute = np.array([b.value for b in best])
    assert r.value == pytest.approx(brute, abs=1e-7 * (1 + np.abs(brute).max()))
    assert (r.candidates >= 1).all() and (r.candidates <= obj.n_pieces).all()
    for i, b in enumerate(best):
        if not (r.degenerate[i] or b.degenerate):
            assert r.grad[i] == pytest.approx(b.grad_a[0], abs=1e-7)


def test_points_on_the_surface_between_pieces(backend):
    # fcl reports a point it finds on a piece as colliding (distance -1); the broad phase
    # must still keep that piece. Points on the cup's rim, where two slabs meet, and on
    # the flat cut between two of its slabs.
    cup = sg.objects.cup()
    rim = np.array([[32.35326495677755, -18.01677625537442, 77.5703330116028]])
    top = cup.bounds[1, 2]
    cut = [v for v in np.vstack(cup.pieces) if abs(v[2] - top) > 1.0 and abs(v[2] - cup.bounds[0, 2]) > 1.0][0]
    r = cup.contact_distance(np.vstack([rim, cut]), backend=backend)
    assert (np.abs(r.value) < 1e-6).all()
    brute = [min(sg.pseudo_distance([p], V, backend=backend).value for V in cup.pieces) for p in (rim[0], cut)]
    assert r.value == pytest.approx(brute, abs=1e-7)


@settings(max_examples=40, deadline=None)
@given(seed=st.integers(0, 2**31 - 1))
def test_cp_bounds_bracket_the_value(seed):
    obj, rng = _random_object(seed)
    pts = _probe_points(obj, rng, 8)
    lower, upper = cp_bounds(obj, pts)
    value = obj.contact_distance(pts).value
    tol = 1e-7 * (1 + np.abs(value))
    assert np.all(lower <= value + tol) and np.all(value <= upper + tol)
    assert np.all(np.isfinite(upper)) and np.isfinite(lower).any()


def _grouped(seed, n, n_groups):
    """A random object, n points around it in n_groups groups (each with a point), and each point's cP."""
    obj, rng = _random_object(seed)
    pts = _probe_points(obj, rng, n)
    groups = rng.integers(0, n_groups, size=n)
    groups[:n_groups] = np.arange(n_groups)
    return obj, rng, pts, groups, obj.contact_distance(pts).value


@settings(max_examples=30, deadline=None)
@given(seed=st.integers(0, 2**31 - 1))
def test_group_pruning_keeps_every_group_minimiser(seed):
    """`PieceIndex.group_probe` drops only points that cannot attain their group's smallest cP."""
    obj, _, pts, groups, value = _grouped(seed, 12, 4)
    rows, probe, floor = obj.index.group_probe(pts, groups)
    assert (probe.P == pts[rows]).all()
    for g in range(4):
        members = np.flatnonzero(groups == g)
        best = value[members].min()
        kept = np.intersect1d(members, rows)
        assert len(kept) and value[kept].min() == pytest.approx(best, abs=1e-7 * (1 + abs(best)))
        assert floor[g] <= best + 1e-7 * (1 + abs(best))  # a lower bound of the group's cP


@settings(max_examples=30, deadline=None)
@given(seed=st.integers(0, 2**31 - 1))
def test_groups_beyond_far_are_dropped_only_when_their_cp_is_beyond_it(seed):
    """`group_probe(..., far)`: a dropped group's cP exceeds its ``far``; the groups kept lose no point."""
    obj, rng, pts, groups, value = _grouped(seed, 16, 6)
    smallest = np.array([value[groups == g].min() for g in range(6)])
    far = np.r_[np.inf, rng.uniform(0.0, 40.0, size=5)]
    rows, _, floor = obj.index.group_probe(pts, groups, far)
    exact_rows, _, _ = obj.index.group_probe(pts, groups)
    dropped = np.setdiff1d(np.arange(6), groups[rows])
    assert 0 not in dropped  # an infinite far never drops
    for g in dropped:
        assert floor[g] > far[g] and smallest[g] >= floor[g] - 1e-7 * (1 + abs(floor[g]))
    kept = np.isin(groups, groups[rows])
    assert np.array_equal(rows, exact_rows[kept[exact_rows]])  # the groups kept lose no point


def test_the_group_probe_kernel_compiles_once_whatever_far():
    """A second signature of the broad phase's kernel would be compiled in a user's first plan."""
    from synergrasp.objects import broad_phase

    obj = so.ellipsoid()
    pts, groups = np.array([[0.0, 0.0, 70.0], [0.0, 0.0, 60.0], [0.0, 0.0, 52.0]]), np.array([0, 0, 1])
    read_only = np.full(2, 5.0)
    read_only.setflags(write=False)
    for far in (None, [5.0, np.inf], read_only, np.array([5, 9])):
        obj.index.group_probe(pts, groups, far)
    sg.plan(obj, "precision", max_iter=5, executable_reach=False)
    assert len(broad_phase._group_probe.signatures) == 1


def test_far_groups_are_bounded_and_the_others_exact(goblet, backend):
    """`group_contact_distance(..., far)`: beyond far a group is a lower bound with zero gradient; the rest exact."""
    rng = np.random.default_rng(5)
    pts = np.vstack([around(goblet, 6, rng, gap=(1, 4)), around(goblet, 6, rng, gap=(30, 60))])
    groups = np.repeat(np.arange(4), 3)  # two groups near the surface, two far from it
    exact, best = group_contact_distance(goblet, pts, groups, backend)
    forget_warm_starts(sg.lp.get_backend(backend), goblet)
    r, r_best = group_contact_distance(goblet, pts, groups, backend, far=np.full(4, 10.0))
    assert (exact.value[:2] < 10.0).all() and (exact.value[2:] > 10.0).all()
    assert r.value[:2] == pytest.approx(exact.value[:2], abs=1e-9) and r.grad[:2] == pytest.approx(exact.grad[:2], abs=1e-7)
    assert np.array_equal(r_best[:2], best[:2]) and (r.piece[:2] >= 0).all()
    assert ((r.value[2:] > 10.0) & (r.value[2:] <= exact.value[2:] + 1e-9)).all()  # a lower bound, beyond far
    assert (r.grad[2:] == 0.0).all() and np.isnan(r.nearest[2:]).all() and (r.piece[2:] == -1).all()
    assert r_best[2:].tolist() == [6, 9]  # a bounded group's first point
    assert r.lp_solves <= exact.lp_solves


def test_plane_bounds_are_each_pieces_signed_distance_bound(goblet):
    pts = goblet.center + np.random.default_rng(2).normal(size=(20, 3)) * 40.0
    expected = np.column_stack([p.signed_distance_bound(pts) for p in goblet.convex])
    assert goblet.index.plane_bounds(pts) == pytest.approx(expected, abs=1e-9)


def test_min_plane_bound_is_the_smallest_piece_bound_exactly_and_nan_for_nan(goblet):
    # points along a line (coherent, as the grid's nodes are) and scattered ones, inside and out
    line = goblet.center + np.linspace(-80.0, 80.0, 200)[:, None] * [0.3, 0.2, 0.93]
    scattered = goblet.center + np.random.default_rng(3).normal(size=(300, 3)) * 40.0
    pts = np.vstack([line, scattered])
    expected = np.column_stack([p.signed_distance_bound(pts) for p in goblet.convex]).min(axis=1)
    got = goblet.index.min_plane_bound(pts)
    assert (got < 0).any() and (got > 0).any()
    assert np.array_equal(got, goblet.index.plane_bounds(pts).min(axis=1))
    assert got == pytest.approx(expected, abs=1e-9)
    assert np.isnan(goblet.index.min_plane_bound([[np.nan, 0.0, 0.0], [0.0, np.inf, 0.0]])).all()


def test_inside_is_being_within_every_facet_of_some_piece_and_false_for_nan(goblet):
    """`PieceIndex.inside` (`contains`) leaves a piece at its first facet with the point outside: its verdicts are
    the signs of the pieces' full bounds (a non-finite point, which `contains` refuses, is outside)."""
    rng = np.random.default_rng(5)
    pts = np.vstack([goblet.center + rng.normal(size=(400, 3)) * 40.0,
                     np.vstack(goblet.pieces) + rng.normal(size=(len(np.vstack(goblet.pieces)), 3)) * 0.5])
    expected = np.column_stack([p.signed_distance_bound(pts) <= 0 for p in goblet.convex]).any(axis=1)
    got = goblet.contains(pts)
    assert got.dtype == bool and 0 < got.sum() < len(got)
    assert np.array_equal(got, expected)
    assert not goblet.index.inside(np.array([[np.nan, 0.0, 0.0], [0.0, np.inf, 0.0], [0.0, 0.0, -np.inf]])).any()


def test_farthest_point_subset_takes_the_farthest_point_each_time():
    """Farthest-point sampling by its definition: from the six extremes along the axes, each next point the one
    farthest from those taken (the first of equals); coordinates on a coarse grid make many ties."""
    from synergrasp.objects.convex import farthest_point_subset

    rng = np.random.default_rng(6)
    for points in (rng.normal(size=(300, 3)) * 30.0, np.round(rng.normal(size=(300, 3)) * 2.0)):
        taken = list(dict.fromkeys(np.sort(np.r_[points.argmin(axis=0), points.argmax(axis=0)]).tolist()))
        while len(taken) < 40:
            gaps = ((points[:, None, :] - points[taken][None]) ** 2).sum(axis=2).min(axis=1)
            taken.append(int(np.flatnonzero(gaps == gaps.max())[0]))
        assert farthest_point_subset(points, 40).tolist() == sorted(taken)
    assert farthest_point_subset(points, 500).tolist() == list(range(300))  # fewer points than asked: all


def test_broad_phase_prunes_far_pieces(goblet):
    # beside the bowl the foot is far: only the bowl is solved
    r = goblet.contact_distance([[45.0, 0.0, 120.0]])
    assert r.candidates[0] == 1 and r.piece[0] == 2


# --------------------------------------------------------------------------- sQ


def test_sq_contacts_lie_on_the_surface_and_the_ray(ellipsoid, backend):
    rng = np.random.default_rng(8)
    pts = np.vstack([around(ellipsoid, 8, rng, gap=(1, 80)), rng.normal(size=(3, 3)) * 5])
    s = ellipsoid.scaled_contacts(pts, backend=backend)
    # on the polytope's surface, within the faceting of the ellipsoid
    level = np.sqrt(np.sum((s.contact / [30, 40, 50]) ** 2, axis=1))
    assert ((level <= 1 + 1e-9) & (level >= 1 - 0.5 / 30)).all()
    # on the ray from the centre, at the scale
    c = ellipsoid.center
    assert (s.contact - c) == pytest.approx((pts - c) / s.scale[:, None], abs=1e-8)
    assert s.point == pytest.approx(pts)
    assert (s.inside == (s.scale < 1)).all() and s.inside[-3:].all()
    # the normal points inward and supports the piece at the contact
    assert np.sum(s.normal * (c - s.contact), axis=1).min() > 0
    V = ellipsoid.pieces[0]
    support = (V @ s.normal.T).min(axis=0)
    assert support == pytest.approx(np.sum(s.normal * s.contact, axis=1), abs=1e-7)
    assert s.jac_normal == pytest.approx(0.0)


def test_sq_cube_closed_form(cube, backend):
    s = cube.scaled_contacts([[0, 0, 40.0], [20, 10, 0.0], [0, 5, 5.0]], backend=backend)
    assert s.scale == pytest.approx([4.0, 2.0, 0.5])
    assert s.contact[0] == pytest.approx([0, 0, 10])
    assert s.normal[0] == pytest.approx([0, 0, -1])
    assert s.normal[1] == pytest.approx([-1, 0, 0])
    assert s.degenerate[2]  # the ray leaves through an edge
    # d scale / d p for the +z face: s = p_z / 10
    assert s.grad_scale[0] == pytest.approx([0, 0, 0.1])


def test_sq_derivatives_match_finite_differences(goblet, ellipsoid, backend):
    rng = np.random.default_rng(9)
    for obj in (goblet, ellipsoid):
        pts = np.vstack([around(obj, 6, rng), obj.center + rng.normal(size=(2, 3)) * 6])
        s = obj.scaled_contacts(pts, backend=backend)
        for i in np.nonzero(~s.degenerate)[0]:
            scale = lambda p: obj.scaled_contacts(p[None], backend=backend).scale[0]  # noqa: E731
            assert_gradient(s.grad_scale[i], central_difference(scale, pts[i], h=1e-5))
            for a in range(3):
                contact = lambda p: obj.scaled_contacts(p[None], backend=backend).contact[0, a]  # noqa: E731
                assert_gradient(s.jac_contact[i, a], central_difference(contact, pts[i], h=1e-5))


@pytest.mark.parametrize("name", ["cup", "goblet", "cube"])
def test_sq_closed_form_equals_the_lp(name, cube, goblet, backend, monkeypatch):
    """The exit-facet closed form (coplanar triangles included) gives the LP's contacts and normals."""
    obj = {"cup": so.cup(), "goblet": goblet, "cube": cube}[name]
    rng = np.random.default_rng(11)
    pts = np.vstack([around(obj, 12, rng, gap=(1, 60)), obj.center + rng.normal(size=(3, 3)) * 4])
    closed = obj.scaled_contacts(pts, backend=backend)
    if name != "cube":  # faces of these meshes are split into coplanar triangles
        assert closed.lp_solves == 0
    monkeypatch.setattr(facets, "CLOSED_FORM", False)
    lp_only = obj.scaled_contacts(pts, backend=backend)
    assert lp_only.lp_solves >= 1
    assert closed.scale == pytest.approx(lp_only.scale, rel=1e-7)
    assert closed.normal == pytest.approx(lp_only.normal, abs=1e-6)
    assert closed.jac_contact == pytest.approx(lp_only.jac_contact, rel=1e-6, abs=1e-6)
    assert (closed.degenerate <= lp_only.degenerate).all()  # closed form only where the LP's basis is unique


@pytest.mark.parametrize("name", ["cup", "goblet", "cube"])
def test_cp_penetration_closed_form_equals_the_lp(name, cube, goblet, backend, monkeypatch):
    """Inside a piece, the exit point of each ray p - rho q_k in closed form gives the LP's values, gradients and witnesses."""
    obj = {"cup": so.cup(), "goblet": goblet, "cube": cube}[name]
    rng = np.random.default_rng(12)
    inside = obj.center + rng.normal(size=(40, 3)) * 0.2 * obj.extents
    pts = inside[obj.contains(inside)][:12]
    closed = obj.contact_distance(pts, backend=backend)
    assert closed.inside.all() and len(pts) >= 8
    monkeypatch.setattr(facets, "CLOSED_FORM", False)
    lp_only = obj.contact_distance(pts, backend=backend)
    assert lp_only.lp_solves >= 1
    assert closed.value == pytest.approx(lp_only.value, abs=1e-7)
    sure = ~lp_only.degenerate  # ties between directions k: either witness is right
    assert (closed.degenerate == lp_only.degenerate).all() and sure.sum() >= 6
    assert closed.nearest[sure] == pytest.approx(lp_only.nearest[sure], abs=1e-6)
    assert closed.grad[sure] == pytest.approx(lp_only.grad[sure], abs=1e-6)
    assert closed.normal[sure] == pytest.approx(lp_only.normal[sure], abs=1e-6)
    # the witness is where the active ray leaves the object: on its surface, |value| mm from p
    assert np.abs(obj.contact_distance(closed.nearest, backend=backend).value).max() < 1e-6
    assert np.linalg.norm(pts - closed.nearest, axis=1) == pytest.approx(-closed.value, rel=1e-9)


def test_sq_q_distance_chain(goblet):
    """g_sQ's gradient with respect to the hand points through jac_contact (the planner's chain)."""
    rng = np.random.default_rng(10)
    pts = around(goblet, 5, rng, gap=(10, 30))
    s = goblet.scaled_contacts(pts)
    assert not s.degenerate.any()
    q = sg.q_distance(s.contact, s.normal, center=goblet.center, torque_scale=goblet.torque_scale)
    grad = np.einsum("iab,ia->ib", s.jac_contact, q.grad_points)

    def g(P):
        t = goblet.scaled_contacts(P.reshape(-1, 3))
        return sg.q_distance(t.contact, t.normal, center=goblet.center, torque_scale=goblet.torque_scale).value

    if not q.degenerate:
        assert_gradient(grad, central_difference(g, pts.ravel(), h=1e-5).reshape(-1, 3), rtol=1e-4)


def test_sq_errors(cube):
    with pytest.raises(ValueError, match="centre"):
        cube.scaled_contacts([[1.0, 1.0, 1.0], [0.0, 0.0, 0.0]])
    with pytest.raises(ValueError, match=r"center \[30.0, 0.0, 0.0\] is outside object or on its surface: .* must be inside"):
        so.GraspObject([box(10.0)], center=[30.0, 0, 0])
    with pytest.raises(ValueError, match="on its surface"):  # a corner: rays along its faces had no exit (sQ inf, NaN)
        so.GraspObject([box(10.0)], center=[10.0, 10.0, 10.0])
    with pytest.raises(ValueError, match=r"\(n, 3\)"):
        cube.scaled_contacts([[1.0, 2.0, 3.0, 4.0]])


def test_centre_moved_inside_for_a_ring():
    ring = so.revolve([[30, 0], [40, 5], [30, 10]])  # a solid disc with a bulge: convex pieces
    assert ring.contains([ring.center])[0]
    # two separate boxes: the centroid between them is outside, the centre is moved into one
    pair = so.GraspObject([box(5, (-20, 0, 0)), box(5, (20, 0, 0))])
    assert pair.contains([pair.center])[0]


# --------------------------------------------------------------------------- capsules


def test_penetration_closed_form(cube):
    # capsules along z of radius 2 at x offsets: depth = 10 + 2 - |x| (to push it out sideways)
    segs = np.array([[[x, 0, -30.0], [x, 0, 30.0]] for x in (0.0, 5.0, 11.0, 15.0)])
    r = cube.penetration(segs, 2.0)
    assert r.depths == pytest.approx([12.0, 7.0, 1.0, 0.0], abs=1e-5)
    assert r.depth == pytest.approx(12.0, abs=1e-5) and r.index == 0 and r.collision
    assert r.distances[3] == pytest.approx(3.0, abs=1e-5)
    # the witnesses: the capsule's point deepest in the cube, then the cube's face; their difference frees it
    np.testing.assert_allclose(r.witnesses[1:3, 1] - r.witnesses[1:3, 0], [[7.0, 0, 0], [1.0, 0, 0]], atol=1e-5)
    np.testing.assert_allclose(r.witnesses[1:3, 1, 0], 10.0, atol=1e-5)
    assert np.isnan(r.witnesses[3]).all()


def test_penetration_through_and_beside_the_goblet(goblet):
    through = [[-80.0, 0, 110.0], [80.0, 0, 110.0]]
    beside = [[-80.0, 60.0, 110.0], [80.0, 60.0, 110.0]]
    r = goblet.penetration([beside, through], [8.0, 8.0])
    assert r.index == 1 and r.depth > 30 and r.piece == 2
    assert r.depths[0] == 0.0
    clear = goblet.penetration([beside], 8.0)
    assert not clear.collision and clear.depth == 0.0 and clear.index == -1
    sphere = goblet.penetration([[goblet.center, goblet.center]], 1.0)  # a zero-length capsule
    assert sphere.collision


def test_a_penetrating_shape_is_measured_against_the_deepest_of_all_pieces():
    """Random capsules and a box through a 3 x 3 x 2 stack of 20 mm cubes (18 pieces): each penetrating shape's
    distance and piece are the deepest over every piece measured alone (one-piece objects); ``clear=False`` gives the
    same for the penetrating shapes and +inf for the others."""
    cube = np.array(np.meshgrid([-10.0, 10.0], [-10.0, 10.0], [-10.0, 10.0])).reshape(3, -1).T
    pieces = [cube + [22.0 * i, 22.0 * j, 22.0 * k] for i in range(3) for j in range(3) for k in range(2)]
    stack = so.GraspObject(pieces, name="stack")
    rng = np.random.default_rng(3)
    a = rng.uniform(-20.0, 65.0, (60, 3))
    segments = np.stack([a, a + rng.normal(0.0, 25.0, (60, 3))], axis=1)
    box = ([22.0, 22.0, 11.0], np.eye(3), [30.0, 8.0, 4.0])
    both = stack.penetration(segments, 3.0, box=box)
    only = stack.penetration(segments, 3.0, box=box, clear=False)
    alone = np.array([so.GraspObject([p]).penetration(segments, 3.0, box=box).distances for p in pieces])
    deep = both.distances < 0
    assert 10 < deep.sum() < 55 and deep[-1]  # some of each, the box among the cubes
    np.testing.assert_allclose(both.distances[deep], alone.min(axis=0)[deep], atol=1e-9)
    assert both.piece == int(np.argmin(alone[:, both.index]))
    np.testing.assert_array_equal(only.distances[deep], both.distances[deep])
    assert np.isinf(only.distances[~deep]).all() and (only.distances[~deep] > 0).all()
    assert (only.depth, only.index, only.piece) == (both.depth, both.index, both.piece)
    np.testing.assert_array_equal(only.witnesses, both.witnesses)


def test_penetration_rejects_bad_input(cube):
    with pytest.raises(ValueError, match=r"\(k, 2, 3\)"):
        cube.penetration([[0, 0, 0], [1, 1, 1]], 1.0)
    with pytest.raises(ValueError, match="radius"):
        cube.penetration([[[0, 0, 0], [1, 1, 1]]], -1.0)
    with pytest.raises(ValueError, match="radius"):
        cube.penetration([[[0, 0, 0], [1, 1, 1]]], [1.0, 2.0])


def test_default_centre_on_a_cut_between_pieces_is_inside():
    """Two stacked boxes: the volume centroid lies on their shared face."""
    box = np.array(np.meshgrid([-20, 20], [-30, 30], [-40, 40])).reshape(3, -1).T
    obj = so.GraspObject([box + [100.0, 50.0, 0.0], box + [100.0, 50.0, 80.0]])
    assert obj.contains(obj.center[None])[0]
    assert np.linalg.norm(obj.center - [100.0, 50.0, 40.0]) < 25.0


def test_distance_grid_is_the_signed_distance_of_a_box_inside_and_a_lower_bound_outside():
    corners = np.array([[x, y, z] for x in (-30.0, 30.0) for y in (-25.0, 25.0) for z in (-45.0, 45.0)])
    box = so.GraspObject([corners], name="box")
    grid = box.distance_grid
    rng = np.random.default_rng(0)
    inside = rng.uniform([-29.0, -24.0, -44.0], [29.0, 24.0, 44.0], size=(400, 3))
    exact_inside = -np.min(np.r_[[30.0, 25.0, 45.0]] - np.abs(inside), axis=1)  # closed form: nearest face
    # linear interpolation of a function with unit slope: off by at most the node spacing near the ridges
    np.testing.assert_allclose(grid(inside), exact_inside, atol=grid.spacing)
    outside = rng.uniform(-50.0, 50.0, size=(400, 3)) * [1.0, 1.0, 1.3]
    outside = outside[~box.contains(outside)]
    exact_outside = np.linalg.norm(np.maximum(np.abs(outside) - [30.0, 25.0, 45.0], 0.0), axis=1)
    values = grid(outside)
    # a lower bound of the distance at the nodes; between them the interpolation is off by less than the spacing
    assert np.all(values <= exact_outside + grid.spacing) and np.all(values > 0.0)
    on_axis = np.array([[35.0, 0.0, 0.0], [0.0, -29.0, 10.0], [5.0, 5.0, 52.0]])  # facing one face: exact
    np.testing.assert_allclose(grid(on_axis), [5.0, 4.0, 7.0], atol=1e-9)
    assert grid(np.array([[0.0, 0.0, 500.0]]))[0] == grid.pad  # beyond the grid
    assert grid(np.zeros((2, 4, 3))).shape == (2, 4)


@pytest.mark.parametrize("name", ["goblet", "ellipsoid", "cup"])
def test_distance_grid_nodes_hold_min_plane_bound_bit_for_bit(name):
    # the grid prunes facets and pieces block by block: every node must still read the unpruned value
    obj = so.get(name)

    def unpruned(grid):
        axes = [grid.origin[i] + grid.spacing * np.arange(n) for i, n in enumerate(grid.values.shape)]
        nodes = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, 3)
        return obj.index.min_plane_bound(nodes).reshape(grid.values.shape)

    grid = obj.distance_grid
    assert any(n % 8 for n in grid.values.shape)  # partial blocks at the far sides
    assert (grid.values < 0).any() and (grid.values > 0).any()
    assert np.array_equal(grid.values, unpruned(grid))
    finer = DistanceGrid(obj.index, obj.bounds, pad=3.0, cells=23, min_spacing=0.5)
    assert np.array_equal(finer.values, unpruned(finer))


def test_distance_grid_posed_reads_the_placed_points_and_cuts_a_set_at_its_first_point_below_its_floor():
    from scipy.spatial.transform import Rotation

    grid = so.cup().distance_grid
    rng = np.random.default_rng(5)
    local = rng.uniform(-60.0, 60.0, size=(4, 30, 3))  # 4 sets of 30 points
    R = Rotation.random(50, random_state=5).as_matrix()
    t = rng.uniform(-20.0, 20.0, size=(50, 3))
    placed = np.einsum("pjk,sik->psij", R, local) + t[:, None, None, :]  # (poses, sets, points, 3)
    values = grid.posed(local, R, t)
    assert values.shape == (50, 4, 30)
    np.testing.assert_allclose(values, grid(placed), rtol=0, atol=1e-9)  # the placement's round-off only
    floors = rng.uniform(-10.0, 10.0, size=30)
    cut = grid.posed(local, R, t, floors)
    below = values < floors
    first = np.where(below.any(axis=2), below.argmax(axis=2), 30)  # each set's first point below its floor
    read = np.arange(30) <= first[..., None]
    assert below.any() and (~below).all(axis=2).any()  # sets cut and sets read whole
    assert np.array_equal(cut[read], values[read]) and np.all(cut[~read] == -np.inf)
    # so the last point is at or above its floor exactly when every point of its set is (what a screen tests)
    assert np.array_equal(cut[..., -1] >= floors[-1], (values >= floors).all(axis=2))
    with pytest.raises(ValueError, match=r"points must have shape \(g, m, 3\)"):
        grid.posed(local[0], R, t)
    with pytest.raises(ValueError, match="rotations and translations"):
        grid.posed(local, R, t[:3])
    with pytest.raises(ValueError, match="floors must have shape"):
        grid.posed(local, R, t, floors[:5])


def test_distance_grid_interpolates_as_scipy_does_and_reads_pad_off_the_grid():
    from scipy.ndimage import map_coordinates

    grid = so.bell().distance_grid
    top = grid.origin + grid.spacing * (np.array(grid.values.shape) - 1)
    points = np.random.default_rng(3).uniform(grid.origin - 20.0, top + 20.0, size=(5000, 3))
    coords = ((points - grid.origin) / grid.spacing).T
    expected = map_coordinates(grid.values, coords, order=1, mode="constant", cval=grid.pad)
    np.testing.assert_allclose(grid(points), expected, rtol=0, atol=1e-9)
    assert np.array_equal(grid(np.array([[np.nan, 0.0, 0.0], [1e9, 0.0, 0.0]])), [grid.pad, grid.pad])
    for bad in (np.zeros((6, 2)), np.zeros((2, 4)), 5.0):  # (6, 2) would read as four points if reshaped
        with pytest.raises(ValueError, match=r"shape \(\.\.\., 3\)"):
            grid(bad)


# --------------------------------------------------------------------------- mesh queries


def _both_ways(mesh, monkeypatch):
    """MeshQueries through trimesh's R-tree, and without it (as for a large mesh)."""
    from synergrasp.objects import mesh_queries

    monkeypatch.setattr(mesh_queries, "TREE_FACES", len(mesh.faces))
    tree = mesh_queries.MeshQueries(mesh)
    monkeypatch.setattr(mesh_queries, "TREE_FACES", 0)
    large = mesh_queries.MeshQueries(mesh)
    assert not tree.large and large.large
    return tree, large


def test_mesh_queries_without_the_tree_agree_with_trimesh(monkeypatch):
    """Random rays from inside and outside a sphere (some miss), and points near and far from it: the same hits,
    nearest points and signed distances."""
    import trimesh

    sphere = trimesh.creation.icosphere(3, 30.0)
    tree, large = _both_ways(sphere, monkeypatch)
    rng = np.random.default_rng(4)
    origins = np.vstack([rng.uniform(-20, 20, (60, 3)), rng.uniform(-80, 80, (60, 3))])
    directions = rng.normal(size=(120, 3)) * rng.uniform(0.5, 3.0, (120, 1))  # not unit
    p, r, t = sphere.ray.intersects_location(origins, directions, multiple_hits=False)  # trimesh's own rays
    p2, r2, t2 = large.first_hits(origins, directions)
    assert np.array_equal(tree.first_hits(origins, directions)[1], r2)  # rays are cast alike on any mesh
    order = np.argsort(r)
    assert 60 < len(r) < 120 and np.array_equal(r[order], r2) and np.array_equal(t[order], t2)
    np.testing.assert_allclose(p2, p[order], atol=1e-9)
    assert np.array_equal(r2[:60], np.arange(60))  # every ray from inside leaves
    assert np.all(np.einsum("ij,ij->i", p2 - origins[r2], directions[r2]) > 0)
    points = np.vstack([rng.normal(size=(200, 3)) * rng.uniform(0, 60, (200, 1)), sphere.vertices[:5]])
    (near, gap, face), (near2, gap2, face2) = tree.closest(points), large.closest(points)
    np.testing.assert_allclose(near2, near, atol=1e-9)
    np.testing.assert_allclose(gap2, gap, atol=1e-9)
    reached = trimesh.triangles.closest_point(sphere.triangles[face2], points)
    np.testing.assert_allclose(np.linalg.norm(reached - points, axis=1), gap, atol=1e-9)  # the face holds the foot
    facing = [np.einsum("ij,ij->i", sphere.face_normals[f], points - near) for f in (face, face2)]
    assert np.all(facing[1] >= facing[0] - 1e-9)  # of faces as near (at a corner), one facing the point at least as
    assert np.mean(face2 == face) > 0.8  # much as trimesh's (which weighs only its two nearest); mostly the same
    signed = large.signed_distance(points)
    np.testing.assert_allclose(signed, tree.signed_distance(points), atol=1e-9)
    radius = np.linalg.norm(points, axis=1)
    far = np.abs(radius - 30.0) > 1.0  # off the faceted ball's shell
    assert far.sum() > 150 and np.array_equal((signed > 0)[far], (radius < 30.0)[far])
    assert np.all(signed[-5:] == 0.0)  # the mesh's own vertices


def test_mesh_queries_on_an_open_mesh_sign_as_trimesh(monkeypatch):
    """A ball with a wavy opening (the meshes the compiled loop is for are open): a point in the hollow under the
    opening is outside, as trimesh's two-way ray test says, where one ray's parity read it inside."""
    import trimesh

    ball = trimesh.creation.icosphere(4, 30.0)
    centres = ball.triangles_center
    keep = centres[:, 2] < 15.0 + 5.0 * np.sin(3.0 * np.arctan2(centres[:, 1], centres[:, 0]))
    bowl = trimesh.Trimesh(ball.vertices, ball.faces[keep])
    assert not bowl.is_watertight
    tree, large = _both_ways(bowl, monkeypatch)
    points = np.random.default_rng(0).uniform(-40.0, 40.0, (3000, 3))
    np.testing.assert_allclose(large.signed_distance(points), tree.signed_distance(points), atol=1e-9)
    hollow = np.array([[0.0, 0.0, 20.0], [5.0, 3.0, 22.0], [-4.0, 2.0, 18.0], [0.0, 0.0, -20.0]])
    assert (np.sign(large.signed_distance(hollow)) == [-1, -1, -1, 1]).all()  # under the opening; under the floor


def test_mesh_queries_pick_trimeshs_face_at_edges_and_ignore_unused_vertices(monkeypatch):
    """A point beyond a box's edge is as near two faces: trimesh takes the one facing it most, and so does the large
    path (the contact's normal comes from that face). A vertex no face uses is not a candidate (the k-d tree of every
    vertex found it nearest and read no face)."""
    import trimesh

    box = trimesh.creation.box((40.0, 40.0, 40.0))
    stray = trimesh.Trimesh(np.vstack([box.vertices, [[0.0, 0.0, 60.0]]]), box.faces, process=False)
    tree, large = _both_ways(stray, monkeypatch)
    points = np.array([[25.0, 0.0, 21.0], [21.0, 0.0, 25.0], [0.0, 0.0, 61.0], [30.0, 30.0, 30.0], [5.0, 2.0, 1.0]])
    for a, b in zip(tree.closest(points), large.closest(points)):
        np.testing.assert_allclose(b, a, atol=1e-12)
    np.testing.assert_allclose(stray.face_normals[large.closest(points[:2])[2]], [[1, 0, 0], [0, 0, 1]], atol=1e-12)
    np.testing.assert_allclose(large.signed_distance(points), tree.signed_distance(points), atol=1e-12)
    assert large.closest(points[2:3])[1][0] == pytest.approx(41.0)


def test_mesh_queries_closed_forms(monkeypatch):
    """A 40 mm cube: +x from the centre leaves at x = 20; rays pointing away or passing beside miss; a point over
    an edge or a corner (no face holds its projection: the sign comes from a ray) is outside."""
    import trimesh

    cube = trimesh.creation.box((40.0, 40.0, 40.0))
    _, large = _both_ways(cube, monkeypatch)
    origins = np.array([[0.0, 1.0, 2.0], [0.0, 0.0, 0.0], [50.0, 0.0, 0.0], [50.0, 0.0, 0.0], [50.0, 30.0, 0.0]])
    directions = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, -2.0], [1.0, 0.0, 0.0], [-1.0, 0.0, 0.0], [-1.0, 0.0, 0.0]])
    points, hit, faces = large.first_hits(origins, directions)
    assert hit.tolist() == [0, 1, 3]
    np.testing.assert_allclose(points, [[20.0, 1.0, 2.0], [0.0, 0.0, -20.0], [20.0, 0.0, 0.0]], atol=1e-12)
    np.testing.assert_allclose(cube.face_normals[faces], [[1, 0, 0], [0, 0, -1], [1, 0, 0]], atol=1e-12)
    queries = [[0.0, 0.0, 15.0], [0.0, 0.0, 30.0], [23.0, 24.0, 0.0], [-21.0, -22.0, 25.0], [19.0, -19.5, 19.0]]
    expected = [5.0, -10.0, -5.0, -np.sqrt(1 + 4 + 25), 0.5]
    np.testing.assert_allclose(large.signed_distance(queries), expected, atol=1e-12)
    closest, distance, _ = large.closest(queries)
    np.testing.assert_allclose(closest[2], [20.0, 20.0, 0.0], atol=1e-12)
    np.testing.assert_allclose(distance, np.abs(expected), atol=1e-12)


def test_first_hits_of_coincident_faces_keeps_the_one_the_ray_leaves_by(monkeypatch):
    """A sheet with both sides (two faces on one triangle, opposite normals), and a degenerate face before it."""
    import trimesh

    vertices = [[-10.0, -10.0, 0.0], [10.0, -10.0, 0.0], [0.0, 10.0, 0.0], [0.0, 0.0, -5.0]]
    for faces in ([[0, 1, 2], [0, 2, 1], [3, 3, 3]], [[0, 2, 1], [0, 1, 2], [3, 3, 3]]):
        sheet = trimesh.Trimesh(vertices, faces, process=False)
        _, large = _both_ways(sheet, monkeypatch)
        points, hit, met = large.first_hits([[0.0, 0.0, -8.0], [0.0, 0.0, 8.0]], [[0.0, 0.0, 1.0], [0, 0, -1.0]])
        assert hit.tolist() == [0, 1]
        np.testing.assert_allclose(points, [[0, 0, 0], [0, 0, 0]], atol=1e-12)
        assert sheet.face_normals[met, 2].tolist() == [1.0, -1.0]  # along each ray, whichever face comes first


def test_a_large_open_mesh_is_queried_without_the_tree():
    """An open scan of 52,000 faces whose two holes touch at a vertex (so it can be neither capped nor simplified):
    its surface is the mesh itself, queried without trimesh's R-tree, and a precision grasp of it is accepted on it
    (at 450,000 faces the tree's rays alone took 16 s)."""
    import trimesh

    from synergrasp.objects.mesh_queries import TREE_FACES

    torus = trimesh.creation.torus(40.0, 15.0, major_sections=200, minor_sections=130)
    fan = np.flatnonzero((torus.faces == 1000).any(axis=1))
    apart = [f for f in fan[1:] if len(set(torus.faces[f]) & set(torus.faces[fan[0]])) == 1]
    keep = np.ones(len(torus.faces), dtype=bool)
    keep[[fan[0], apart[0]]] = False
    torus.update_faces(keep)
    with pytest.warns(UserWarning, match="cannot be capped"):
        obj = so.from_mesh(torus, cache=False, name="holey torus")
    assert len(obj.surface.faces) == len(torus.faces) > TREE_FACES and obj.surface_queries.large
    result = sg.plan(obj, "precision")
    assert result.success and result.surface_q < 0
    closest, gap, _ = obj.surface_queries.closest(result.contact_points)
    assert gap.max() < 5.0


def test_many_points_are_answered_in_parts_with_the_same_results(cube, monkeypatch):
    """cP and sQ of more points than QUERY_CHUNK (3e5 points asked for 6.6 GiB at once): the parts' results joined
    are the whole set's, field by field."""
    from synergrasp.objects import grasp_object
    from synergrasp.objects.contact_distance import contact_distance
    from synergrasp.objects.scaled_contacts import scaled_contacts

    points = np.random.default_rng(3).uniform(-30.0, 30.0, (130, 3))
    whole_cp, whole_sq = contact_distance(cube, points), scaled_contacts(cube, points)
    monkeypatch.setattr(grasp_object, "QUERY_CHUNK", 50)
    for joined, whole in ((cube.contact_distance(points), whole_cp), (cube.scaled_contacts(points), whole_sq)):
        for name, value in vars(whole).items():
            if name != "lp_solves":
                np.testing.assert_allclose(getattr(joined, name), value, atol=1e-9, err_msg=name)
        assert joined.lp_solves >= whole.lp_solves
