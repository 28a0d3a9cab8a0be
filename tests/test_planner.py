"""The planner: status rows and Jacobians, stop criteria, starts, attempts, plans verified independently."""

import itertools
import sys
import warnings
from dataclasses import replace

import numpy as np
import pytest
import trimesh

import synergrasp as sg
import synergrasp.objects as so
from synergrasp.hand import SynergyHand, rotation_xyz
from synergrasp.planner import (
    AnnealingOptions,
    Outcome,
    PlannerOptions,
    PlanResult,
    check_grasp,
    forget_warm_starts,
    grasp_status,
    pinch_seeds,
    plan,
    power_schedule,
    principal_directions,
    recess,
    run_attempt,
    smallest_pinch,
    sq_request,
    start_configuration,
    starts,
    status_rows,
    wrap_seeds,
)
from synergrasp.lp import get_backend
from synergrasp.planner import attempt as attempt_module
from synergrasp.planner.core import hand_opening
from synergrasp.planner.clearance import HandClearance
from synergrasp.planner.starts import DIRECTION_ROLLS, surface_samples
from synergrasp.planner.status import Status, capsule_rows, contact_quality, hand_penetration, palm_face_point
from synergrasp.planner.stop import mesh_depth, surface_check

from .conftest import BACKENDS
from .test_quality import origin_strictly_inside


@pytest.fixture(scope="module")
def hand():
    return SynergyHand.default()


@pytest.fixture(scope="module")
def ellipsoid():
    return so.ellipsoid()


@pytest.fixture(scope="module")
def box():
    return so.from_mesh(trimesh.creation.box((60.0, 50.0, 90.0)), name="box", cache=False)


@pytest.fixture(scope="module")
def goblet_plan():
    return plan(so.goblet(), "precision")


def near_start(hand, obj, approach=(0.0, 1.0, 0.0), distance=110.0):
    return start_configuration(hand, obj, approach, distance) + np.r_[np.zeros(6), 0.1, -0.2]


def finite_difference(f, u, h=None):
    h = np.r_[np.full(3, 1e-4), np.full(len(u) - 3, 1e-6)] if h is None else h
    columns = []
    for k in range(len(u)):
        up, um = u.copy(), u.copy()
        up[k] += h[k]
        um[k] -= h[k]
        columns.append((f(up) - f(um)) / (2 * h[k]))
    return np.stack(columns, axis=-1)


@pytest.mark.parametrize("name", ["ellipsoid", "bell"])
def test_smoothed_normals_jacobian_matches_finite_differences(name):
    """d normal / d x of the log-sum-exp smoothed surface against central differences, on every piece."""
    from synergrasp.planner.status import smoothed_normals

    obj = so.get(name)
    rng = np.random.default_rng(5)
    pieces = np.arange(obj.n_pieces).repeat(2)
    x = np.array([obj.pieces[j].mean(axis=0) for j in pieces]) + rng.normal(size=(len(pieces), 3)) * 15.0
    normals, jac = smoothed_normals(obj, x, pieces, 5.0)
    assert np.allclose(np.linalg.norm(normals, axis=1), 1.0)
    h = 1e-5
    for a in range(3):
        e = np.zeros(3)
        e[a] = h
        fd = (smoothed_normals(obj, x + e, pieces, 5.0)[0] - smoothed_normals(obj, x - e, pieces, 5.0)[0]) / (2 * h)
        assert np.abs(jac[:, :, a] - fd).max() <= 1e-6 * max(1.0, np.abs(fd).max())


# --------------------------------------------------------------------------- status


@pytest.mark.parametrize("kind", ["precision", "power"])
def test_status_jacobian_matches_finite_differences(hand, ellipsoid, kind):
    u = near_start(hand, ellipsoid)
    st = grasp_status(hand, ellipsoid, u, kind, smoothing=5.0)
    fd = finite_difference(lambda v: grasp_status(hand, ellipsoid, v, kind, smoothing=5.0).g, u)
    scale = np.maximum(np.abs(fd), 1e-3)
    assert np.all(np.abs(st.J - fd) <= 1e-4 * scale + 1e-6)


def test_status_rows_of_the_two_grasp_types(hand):
    labels, contact, segment_rows = status_rows(hand, "precision")
    assert labels[:5] == ["T0", "I0", "M0", "R0", "L0"] and labels[-1] == "P" and len(labels) == 16
    assert contact.tolist() == [True] * 5 + [False] * 11  # the fingertips count, the rest keep clear
    segments = hand.point_labels("power")[:-1]
    for label, row in zip(segments, segment_rows):  # a distal phalanx is its fingertip's row
        assert labels[row] == (f"{label[0]}0" if label[1] == "3" else label)
    labels, contact, segment_rows = status_rows(hand, "power")
    assert labels == segments + ["P"] and contact.all() and segment_rows.tolist() == list(range(15))
    labels.append("X"), contact.fill(False), segment_rows.fill(-1)  # each call's rows are its own
    labels, contact, segment_rows = status_rows(hand, "power")
    assert labels == segments + ["P"] and contact.all() and segment_rows.tolist() == list(range(15))


@pytest.mark.parametrize("kind", ["precision", "power"])
def test_every_row_is_the_deepest_of_its_skin_points(hand, ellipsoid, backend, kind):
    u = near_start(hand, ellipsoid, distance=60.0)
    st = grasp_status(hand, ellipsoid, u, kind, backend=backend)
    skin, palm, _, _ = hand.skin_and_jacobian(u, kind)
    each = ellipsoid.contact_distance(skin.reshape(-1, 3), backend=backend).value.reshape(skin.shape[:2]).min(axis=1)
    if kind == "precision":  # a fingertip's row: its pad point or its distal phalanx, whichever is deeper
        pads = ellipsoid.contact_distance(hand.points(u, "precision"), backend=backend).value
        np.testing.assert_array_equal(st.segment_rows[[2, 5, 8, 11, 14]], np.arange(5))
        np.testing.assert_allclose(st.g[:5], np.minimum(pads, each[[2, 5, 8, 11, 14]]), atol=1e-6)
    others = [i for i, lab in enumerate(hand.point_labels("power")[:-1]) if kind == "power" or lab[1] != "3"]
    np.testing.assert_allclose(st.g[st.segment_rows[others]], each[others], atol=1e-6)
    face = palm_face_point(hand, ellipsoid, u)
    palm_cp = ellipsoid.contact_distance(np.vstack([palm, face]), backend=backend).value.min()
    np.testing.assert_allclose(st.g[-2], palm_cp, atol=1e-6)  # the palm row: P, the rim of the palm box, the face point


def small_ball_under_the_palm(hand, gap):
    """A 24 x 20 x 16 mm ellipsoid ``gap`` mm in front of the palm's face, between its skin samples, and the pose."""
    u = np.r_[np.zeros(6), 0.1, -0.2]
    u[3:6] = [0.05, -0.03, 0.02]  # tilted: one vertex is nearest the face
    center, axes = hand.palm_box(u)
    h = hand.palm_half_extents
    ball = so.ellipsoid(12.0, 10.0, 8.0)
    offset = center + axes @ [0.5 * h[0], -0.5 * h[1], h[2]]
    support = np.vstack(ball.pieces) @ axes[:, 2]
    shift = offset - ball.center + axes[:, 2] * (gap + ball.center @ axes[:, 2] - support.min())
    return ball.transformed(trimesh.transformations.translation_matrix(shift)), u


@pytest.mark.parametrize("kind", ["precision", "power"])
def test_the_palm_row_sees_a_small_object_between_its_skin_samples(hand, kind):
    ball, u = small_ball_under_the_palm(hand, gap=2.0)
    palm = hand.skin_and_jacobian(u, kind)[1]
    face = palm_face_point(hand, ball, u)
    mesh = ball.to_mesh()
    assert trimesh.proximity.closest_point(mesh, palm)[1].min() > 15.0  # every sample reads it far off
    assert trimesh.proximity.closest_point(mesh, face)[1][0] == pytest.approx(2.0, abs=0.1)
    st = grasp_status(hand, ball, u, kind)
    sampled = ball.contact_distance(palm).value.min()
    assert st.g[-2] == pytest.approx(ball.contact_distance(face).value[0]) and st.g[-2] < sampled - 10.0
    center, axes = hand.palm_box(u)
    local = (face[0] - center) @ axes  # the row's derivative: the face point carried by the palm

    def carried(v):
        c, a = hand.palm_box(v)
        return ball.contact_distance((c + a @ local)[None]).value[0]

    np.testing.assert_allclose(st.J[-2], finite_difference(carried, u), rtol=1e-4, atol=1e-6)


def test_the_palm_row_sees_a_bar_across_the_palm_between_its_skin_samples(hand):
    """A 300 mm bar across the whole face, 2 mm off it: no vertex lies over the face, an edge does."""
    u = np.r_[0.0, 0.0, 0.0, 0.05, -0.03, 0.02, 0.1, -0.2]
    center, axes = hand.palm_box(u)
    h = hand.palm_half_extents
    pose = np.eye(4)
    pose[:3, :3] = axes
    pose[:3, 3] = center + axes @ [0.0, 0.5 * h[1], h[2] + 2.0 + 4.0]  # along the palm's x, between two rows of samples
    bar = so.from_mesh(trimesh.creation.box((300.0, 8.0, 8.0)), cache=False).transformed(pose)
    local = (bar.index.vertices - center) @ axes
    assert not (np.abs(local[:, 0]) <= h[0]).any()  # every vertex lies beyond the face's extent
    face = palm_face_point(hand, bar, u)
    mesh = bar.to_mesh()
    samples = hand.skin_and_jacobian(u, "power")[1]
    assert trimesh.proximity.closest_point(mesh, samples)[1].min() > 15.0
    assert trimesh.proximity.closest_point(mesh, face)[1][0] == pytest.approx(2.0, abs=1e-6)
    st = grasp_status(hand, bar, u, "power")
    sampled = bar.contact_distance(samples).value.min()
    assert st.g[-2] == pytest.approx(bar.contact_distance(face).value[0]) and st.g[-2] < sampled - 10.0


def test_of_equally_deep_points_the_face_point_is_the_one_nearest_the_palms_centre(hand):
    """A cube's face parallel to the palm, 2 mm off: every corner over the face is as deep; the nearest to the centre."""
    u = np.r_[np.zeros(6), 0.1, -0.2]
    center, axes = hand.palm_box(u)
    h = hand.palm_half_extents
    for turn in (0.0, 0.5 * np.pi, np.pi):  # the cube's vertices in other orders
        pose = np.eye(4)
        pose[:3, :3] = axes @ trimesh.transformations.rotation_matrix(turn, [0.0, 0.0, 1.0])[:3, :3]
        pose[:3, 3] = center + axes @ [10.0, -5.0, h[2] + 2.0 + 10.0]  # its face spans x 0..20, y -15..5 over the palm
        cube = so.from_mesh(trimesh.creation.box((20.0, 20.0, 20.0)), cache=False).transformed(pose)
        local = (palm_face_point(hand, cube, u)[0] - center) @ axes
        np.testing.assert_allclose(local, [0.0, 5.0, h[2]], atol=1e-9)


def test_no_face_point_when_nothing_lies_over_the_palm(hand):
    ball, u = small_ball_under_the_palm(hand, gap=2.0)
    u[:3] += 200.0 * hand.palm_box(u)[1][:, 0]  # slid 200 mm sideways: the ball is beside the palm
    assert palm_face_point(hand, ball, u).shape == (0, 3)


def test_the_palm_row_sees_a_corner_of_the_palm_box_in_the_object(hand, box):
    u = np.zeros(hand.n_u)
    geo = hand.segments(u)
    corner = geo.palm_center + geo.palm_axes @ (geo.palm_half_extents * [1.0, 1.0, 1.0])
    u[:3] = np.array([-30.0, -25.0, 45.0]) - corner + [4.0, 4.0, -4.0]  # that corner 4 mm inside a corner of the box
    st = grasp_status(hand, box, u, "power")
    p_only = box.contact_distance(hand.points(u, "power")[-1:]).value[0]
    assert p_only > 5.0 and st.g[-2] < -1.0  # the palm point is outside, the palm box is not


def test_capsule_rows_see_a_phalanx_through_a_plate_and_match_finite_differences(hand):
    """Phalanges through an 8 mm plate read shallow at their skin points; their capsules' rows read the full depth."""
    plate = so.from_mesh(trimesh.creation.box((200.0, 200.0, 8.0)), cache=False)
    u = np.r_[np.zeros(3), 0.15, -0.1, 0.05, 0.3, -0.2]
    u[:3] = -hand.segments(u).capsules[4].mean(axis=0) + [0.0, 0.0, 1.5]  # the index's middle phalanx in the plate
    skin = grasp_status(hand, plate, u, "power")
    pen = hand_penetration(hand, plate, u)
    assert pen.distances[-1] > 0  # the palm box is clear of the plate
    st = capsule_rows(hand, plate, u, skin, pen)
    deeper = (pen.distances[:15] < 0) & (pen.distances[:15] < skin.g[:15])
    assert deeper.sum() >= 3 and pen.distances[4] < -8.0 and deeper[4]
    np.testing.assert_array_equal(st.g[:15][deeper], pen.distances[:15][deeper])
    np.testing.assert_array_equal(st.g[:15][~deeper], skin.g[:15][~deeper])  # the others keep their skin rows
    np.testing.assert_array_equal(st.g[15:], skin.g[15:])
    rows = np.flatnonzero(deeper)
    fd = finite_difference(lambda v: plate.penetration(hand.segments(v).capsules, hand.finger_radius).distances[rows], u)
    np.testing.assert_allclose(st.J[rows], fd, rtol=1e-5, atol=1e-5 * np.abs(st.J).max())
    far = start_configuration(hand, so.ellipsoid())
    clear = grasp_status(hand, so.ellipsoid(), far, "power")
    assert capsule_rows(hand, so.ellipsoid(), far, clear) is clear  # nothing penetrates: the status itself


@pytest.mark.parametrize("kind", ["precision", "power"])
def test_capsule_rows_see_the_palm_box_pushed_into_a_side_and_match_finite_differences(hand, box, kind):
    """The palm box's side 6 mm into the box, tilted: its back edge is deeper than the front face's rim the skin points sample."""
    u = np.r_[np.zeros(3), 0.0, 0.3, 0.2, 0.3, -0.2]
    geo = hand.segments(u)
    side = geo.palm_center + geo.palm_axes @ [geo.palm_half_extents[0], 0.0, 0.0]  # centre of the +x side face
    u[:3] = np.array([-30.0, 0.0, 0.0]) - side + [6.0, 0.0, 0.0]  # the side's centre 6 mm inside the box's -x face
    skin = grasp_status(hand, box, u, kind)
    pen = hand_penetration(hand, box, u)
    st = capsule_rows(hand, box, u, skin, pen)
    palm = len(st.labels) - 1
    assert pen.distances[-1] < -6.0 and skin.g[palm] > pen.distances[-1] + 1.0
    assert st.g[palm] == pen.distances[-1]
    fd = finite_difference(lambda v: hand_penetration(hand, box, v).distances[-1], u)
    np.testing.assert_allclose(st.J[palm], fd, rtol=1e-5, atol=1e-6)
    assert not fd[6:].any()  # the palm does not move with the synergies


def test_a_power_grasp_of_a_box_keeps_the_palm_box_out(hand, box):
    """Accepted grasps have the palm box, not only the phalanges, within max_penetration of the object."""
    r = plan(box, "power")
    verify(r, box)
    depth = -HandClearance(hand, box).shapes(r.u)[-1]
    assert depth <= PlannerOptions().max_penetration + 1e-6


def test_the_contact_quality_gradient_matches_finite_differences(hand, box):
    """g_Q of contacts sliding on flat faces: the tangent-projected point Jacobian is exact there."""
    u = plan(box, "precision", refine_iterations=0).u
    st = grasp_status(hand, box, u, "precision")
    contact = st.contact & (st.g[:-1] < 5.0)
    assert contact.sum() >= 3

    def value(v):
        return contact_quality(box, grasp_status(hand, box, v, "precision"), contact)[0]

    q, grad = contact_quality(box, st, contact)
    fd = finite_difference(value, u, h=np.r_[np.full(3, 1e-3), np.full(len(u) - 3, 1e-5)])
    np.testing.assert_allclose(grad, fd, rtol=1e-3, atol=1e-4 * np.abs(fd).max())


# --------------------------------------------------------------------------- stop criteria


def fake_status(hand, kind, cp, sq=0.0):
    """A status whose rows in contact (cP < 5) lie evenly around a sphere's equator."""
    labels, contact, segment_rows = status_rows(hand, kind)
    cp = np.asarray(cp, dtype=float)
    n = len(cp)
    inside = (cp < 5.0) & contact
    t = np.zeros(n)
    t[inside] = 2 * np.pi * np.arange(inside.sum()) / max(inside.sum(), 1)
    nearest = 40.0 * np.c_[np.cos(t), np.sin(t), np.zeros(n)]
    return Status(g=np.r_[cp, sq], J=np.zeros((n + 1, 8)), labels=labels, contact=contact, segment_rows=segment_rows,
                  points=nearest, nearest=nearest, normals=-nearest / 40, pieces=np.zeros(n, int),
                  row_points=nearest, point_jac=np.zeros((n, 3, 8)), lp_solves=0)


def test_precision_stop_criterion(hand, ellipsoid):
    rows = np.full(16, 30.0)
    rows[:3] = [1.0, 2.0, 3.0]
    three = check_grasp(ellipsoid, fake_status(hand, "precision", rows), "precision")
    assert three.n_contacts == 3 and three.q < -0.1 and three.done  # 3 contacts need Q < -0.1
    rows[5] = 1.0  # a middle phalanx touching does not count as a contact
    assert check_grasp(ellipsoid, fake_status(hand, "precision", rows), "precision").n_contacts == 3
    rows[-1] = 2.0  # the palm touches: not a pinch
    assert not check_grasp(ellipsoid, fake_status(hand, "precision", rows), "precision").done
    rows[-1] = -20.0  # the palm inside the object: not a pinch either
    assert not check_grasp(ellipsoid, fake_status(hand, "precision", rows), "precision").done
    rows[-1], rows[2] = 30.0, 6.0
    far = check_grasp(ellipsoid, fake_status(hand, "precision", rows), "precision")
    assert far.n_contacts == 2 and not far.done


def test_three_fingertips_close_a_grasp_when_only_three_can_reach(hand, ellipsoid):
    """Three fingertips at 0, 100 and 260 degrees around the equator: force-closed with g_Q about -0.08, short of the
    paper's -0.1 for three contacts. On an object only the thumb, index and middle fingertips reach (steered = 3)
    that stops; with four or five steered it does not, and two contacts never do."""
    rows = np.full(16, 30.0)
    rows[:3] = [1.0, 2.0, 3.0]
    status = fake_status(hand, "precision", rows)
    t = np.radians([0.0, 100.0, 260.0])
    nearest = status.nearest.copy()
    nearest[:3] = 40.0 * np.c_[np.cos(t), np.sin(t), np.zeros(3)]
    status = replace(status, nearest=nearest, points=nearest, row_points=nearest, normals=-nearest / 40.0)
    paper = check_grasp(ellipsoid, status, "precision")
    assert paper.n_contacts == 3 and -0.1 < paper.q < -0.05 and not paper.done
    assert check_grasp(ellipsoid, status, "precision", steered=3).done
    assert not any(check_grasp(ellipsoid, status, "precision", steered=k).done for k in (4, 5))
    rows[2] = 6.0
    two = fake_status(hand, "precision", rows)
    assert not any(check_grasp(ellipsoid, two, "precision", steered=k).done for k in (1, 2, 3))


def test_power_stop_criterion_needs_the_palm(hand, ellipsoid):
    cp = np.full(16, 1.0)
    assert check_grasp(ellipsoid, fake_status(hand, "power", cp), "power").done
    cp[-1] = 9.0  # the palm away from the object: not a power grasp
    chk = check_grasp(ellipsoid, fake_status(hand, "power", cp), "power")
    assert not chk.palm and not chk.done and chk.q < 0


def test_the_surface_check_judges_on_the_mesh_not_on_the_pieces():
    surface = _bowl_mesh()
    bowl = so.GraspObject([surface.vertices], mesh=surface, name="bowl")  # one piece, the hull: it covers the hollow
    over_the_hollow = [[0.0, 0.0, 0.0]]  # on the hull's top face, over the bowl's inside
    assert surface_check(bowl, over_the_hollow, [[0.0, 0.0, -1.0]]).gap > 40.0
    t = 2 * np.pi * np.arange(5) / 5
    rim = np.c_[47.5 * np.cos(t), 47.5 * np.sin(t), np.zeros(5)]
    s = surface_check(bowl, rim, -rim / 47.5)  # five contacts on the rim, pressing inwards
    assert s.gap < 3.0 and s.points.shape == (5, 3) and np.all(np.isfinite(s.normals))


def test_mesh_depth_of_capsules_at_a_box_face_closed_form():
    box = so.from_mesh(trimesh.creation.box((100.0, 100.0, 100.0)), cache=False)  # top face at z = 50
    along = lambda z: [[-20.0, 5.0, z], [20.0, 5.0, z]]  # noqa: E731
    axes = np.array([along(55.0), along(70.0), along(49.0), [[0.0, 0.0, 43.0], [0.0, 0.0, 80.0]]])
    # radius less the axis's height over the face, floored at 0; an axis into the box: its end's depth plus the radius
    np.testing.assert_allclose(mesh_depth(box, axes, 8.0), [3.0, 0.0, 9.0, 15.0], atol=1e-9)
    assert box.mesh_excess == 0.0  # the box is its own hull
    with pytest.raises(ValueError, match=r"\(k, 2, 3\)"):
        mesh_depth(box, axes[0], 8.0)
    with pytest.raises(ValueError, match="finite"):
        mesh_depth(box, np.where(axes == 80.0, np.nan, axes), 8.0)
    with pytest.raises(ValueError, match="radius"):
        mesh_depth(box, axes, 0.0)
    with pytest.raises(ValueError, match="no mesh"):
        mesh_depth(sg.objects.GraspObject([box.pieces[0]]), axes, 8.0)


def test_mesh_excess_is_how_far_the_mesh_sticks_out_of_a_coarse_hull():
    fine = trimesh.creation.icosphere(subdivisions=4, radius=40.0)
    coarse = trimesh.creation.icosphere(subdivisions=1, radius=40.0)
    ball = sg.objects.GraspObject([coarse.vertices], mesh=fine)
    outside = -trimesh.proximity.signed_distance(coarse, fine.vertices)  # trimesh: positive inside
    assert 0.95 * outside.max() <= ball.mesh_excess <= outside.max() + 1e-9
    assert sg.objects.GraspObject([coarse.vertices]).mesh_excess == 0.0


def _bowl_mesh():
    """A hemispherical bowl, 100 mm across and 5 mm thick, open at the top (z > 0)."""
    shell = trimesh.creation.icosphere(subdivisions=3, radius=50.0).difference(
        trimesh.creation.icosphere(subdivisions=3, radius=45.0), engine="manifold")
    lid = trimesh.creation.box((150.0, 150.0, 100.0))
    lid.apply_translation((0.0, 0.0, 50.0))
    return shell.difference(lid, engine="manifold")


def test_the_surface_check_of_a_point_cloud_judges_on_its_points():
    surface = _bowl_mesh()
    points = trimesh.sample.sample_surface(surface, 20000, seed=0)[0]
    bowl = so.GraspObject([points], points=points, name="bowl cloud")  # one piece, the hull: it covers the hollow
    assert surface_check(bowl, [[0.0, 0.0, 0.0]], [[0.0, 0.0, -1.0]]).gap > 40.0  # over the hollow: no surface
    t = 2 * np.pi * np.arange(5) / 5
    side = np.c_[50.0 * np.cos(t), 50.0 * np.sin(t), np.full(5, -10.0)]
    side *= (51.0 / np.linalg.norm(side, axis=1))[:, None]  # 1 mm outside the bowl's outer sphere
    s = surface_check(bowl, side, -side / 51.0)
    _, gap, face = trimesh.proximity.closest_point(surface, side)
    np.testing.assert_allclose(s.gap, gap.max(), atol=0.1)
    truth = -surface.face_normals[face]
    assert np.degrees(np.arccos(np.clip(np.einsum("ij,ij->i", s.normals, truth), -1, 1))).max() < 3.0
    # the plain pieces (no points) would take the hull's contacts and normals as they are
    assert surface_check(so.GraspObject([points]), [[0.0, 0.0, 0.0]], [[0.0, 0.0, -1.0]]).gap == 0.0


def test_a_cloud_grasp_must_be_force_closed_with_the_fitted_and_the_pieces_normals():
    """Five contacts around a ball's cloud: force-closed with its fitted normals; with the pieces' normals given
    all tilted 80 degrees the same way (a normal the cloud cannot confirm), the larger Q is the tilted one's."""
    ball = trimesh.creation.icosphere(4, radius=40.0)
    points = trimesh.sample.sample_surface(ball, 6000, seed=0)[0]
    cloud = so.GraspObject([ball.vertices], points=points, name="ball cloud")
    t = 2 * np.pi * np.arange(5) / 5
    ring = np.c_[np.cos(t), np.sin(t), np.zeros(5)]
    true = surface_check(cloud, 40.0 * ring, -ring)
    tilted = -np.cos(np.radians(80.0)) * ring + [0.0, 0.0, np.sin(np.radians(80.0))]
    q_tilted = sg.q_distance(true.points, tilted, center=cloud.center, torque_scale=cloud.torque_scale).value
    unsure = surface_check(cloud, 40.0 * ring, tilted)
    assert true.q < -0.05 and q_tilted > true.q
    assert unsure.q == pytest.approx(q_tilted, abs=1e-9)
    np.testing.assert_allclose(unsure.normals, true.normals, atol=1e-9)  # the feet's fitted normals either way


def test_mesh_depth_in_a_point_cloud_box_closed_form():
    box = trimesh.creation.box((100.0, 100.0, 100.0))  # top face at z = 50
    points = trimesh.sample.sample_surface_even(box, 20000, seed=0)[0]
    cloud = so.GraspObject([points], points=points)
    along = lambda z: [[-20.0, 5.0, z], [20.0, 5.0, z]]  # noqa: E731
    axes = np.array([along(55.0), along(70.0), along(49.0), [[0.0, 0.0, 43.0], [0.0, 0.0, 80.0]]])
    np.testing.assert_allclose(mesh_depth(cloud, axes, 8.0), [3.0, 0.0, 9.0, 15.0], atol=0.05)


def test_an_object_from_a_cloud_keeps_its_points_and_moves_them():
    rng = np.random.default_rng(1)
    points = rng.normal(size=(600, 3))
    points *= 30.0 / np.linalg.norm(points, axis=1, keepdims=True)
    ball = so.from_points(points, cache=False)
    np.testing.assert_allclose(np.sort(ball.points, axis=0), np.sort(points, axis=0))
    assert ball.point_surface is not None and so.ellipsoid().point_surface is None
    turn = rotation_xyz([0.3, -0.2, 1.1])
    moved = ball.transformed(np.r_[np.c_[turn, [5.0, 0.0, 0.0]], [[0.0, 0.0, 0.0, 1.0]]])
    np.testing.assert_allclose(np.sort(moved.points, axis=0), np.sort(ball.points @ turn.T + [5.0, 0.0, 0.0], axis=0))
    # the points the moved object's surface is judged on are where its pieces went
    np.testing.assert_allclose(moved.point_surface.closest(moved.points[:5], np.ones((5, 3)))[1], 0.0, atol=1e-9)
    with pytest.raises(ValueError, match="not both"):
        so.GraspObject([points], points=points, mesh=trimesh.convex.convex_hull(points))
    with pytest.raises(ValueError, match="give the points in the pieces' units"):
        so.GraspObject([points], points=points / 1000.0)  # metres against pieces in mm
    with pytest.raises(ValueError, match="give the points in the pieces' units"):
        so.GraspObject([points], points=points + [100.0, 0.0, 0.0])  # another frame
    with pytest.raises(ValueError, match="points"):
        so.GraspObject([points], points=points[:, :2])


def test_a_point_surface_ignores_repeated_points_and_counts_a_covered_hollow_as_outside():
    """Points given many times fit the same planes as once; in a bowl's hollow, which the hull covers, the side that
    is inside is not known: no depth there, while a point below the outer wall is inside by its depth."""
    from synergrasp.objects.point_surface import PointSurface

    box = trimesh.creation.box((60.0, 60.0, 60.0))
    points = trimesh.sample.sample_surface_even(box, 3000, seed=0)[0]
    once, repeated = PointSurface(points), PointSurface(np.repeat(points, 16, axis=0))
    assert len(repeated.points) == len(once.points)
    probe = [[5.0, 5.0, 32.0], [0.0, 31.0, 3.0]]
    for a, b in zip(once.closest(probe, [[0.0, 0.0, -1.0], [0.0, -1.0, 0.0]]),
                    repeated.closest(probe, [[0.0, 0.0, -1.0], [0.0, -1.0, 0.0]])):
        np.testing.assert_allclose(a, b)
    surface = _bowl_mesh()
    cloud = trimesh.sample.sample_surface(surface, 20000, seed=0)[0]
    bowl = so.GraspObject([cloud], points=cloud)
    hollow, in_the_wall = [[0.0, 0.0, -20.0], [0.0, 0.0, -35.0]], [[0.0, 0.0, -48.0]]
    assert (bowl.point_surface.signed_distance(hollow, bowl.contains) <= 0.0).all()
    assert trimesh.proximity.signed_distance(surface, in_the_wall)[0] > 0.0  # inside the wall (trimesh: + inside)
    np.testing.assert_allclose(bowl.point_surface.signed_distance(in_the_wall, bowl.contains),
                               trimesh.proximity.signed_distance(surface, in_the_wall), atol=0.5)


def test_a_point_surface_signs_a_normal_by_the_inside_where_the_given_direction_runs_along_the_surface():
    """A contact on a cube's top face whose pieces' normal runs nearly along the face (87 degrees from it, pointing
    slightly up): its sign alone turns the face's normal outward; the inside test turns it into the cube."""
    from synergrasp.objects.point_surface import PointSurface

    box = trimesh.creation.box((60.0, 60.0, 60.0))
    points = trimesh.sample.sample_surface_even(box, 3000, seed=0)[0]
    surface, inside = PointSurface(points), (lambda p: np.abs(p).max(axis=1) < 30.0)  # noqa: E731
    contact, along = [[5.0, 5.0, 30.5]], [[1.0, 0.0, 0.05]]
    np.testing.assert_allclose(surface.closest(contact, along)[2], [[0.0, 0.0, 1.0]], atol=1e-6)  # outward: wrong
    np.testing.assert_allclose(surface.closest(contact, along, inside)[2], [[0.0, 0.0, -1.0]], atol=1e-6)
    clear = [[0.0, 0.0, -1.0]]  # a direction clearly into the object keeps its sign whatever the inside test says
    np.testing.assert_allclose(surface.closest(contact, clear, lambda p: np.zeros(len(p), bool))[2], clear, atol=1e-6)


def test_a_point_surface_refuses_bad_input():
    from synergrasp.objects.point_surface import PointSurface

    with pytest.raises(ValueError, match="at least 16 distinct points"):
        PointSurface(np.zeros((10, 3)))
    with pytest.raises(ValueError, match="to fit planes to, got 1"):
        PointSurface(np.zeros((40, 3)))
    with pytest.raises(ValueError, match="neighbours"):
        PointSurface(np.eye(3), neighbours=2)
    with pytest.raises(ValueError, match="NaN"):
        PointSurface(np.full((20, 3), np.nan))
    with pytest.raises(ValueError, match="one direction per point"):
        PointSurface(np.random.default_rng(0).normal(size=(20, 3))).closest(np.zeros((2, 3)), np.zeros((1, 3)))


def test_a_grasp_planned_on_a_cloud_holds_on_the_surface_it_samples():
    """The grasp of a cloud sampled on a box is force-closed at the box's own faces, its contacts on them."""
    box = trimesh.creation.box((60.0, 50.0, 90.0))
    points = trimesh.sample.sample_surface(box, 3000, seed=0)[0]
    result = sg.plan(so.from_points(points, cache=False), "precision")
    assert result.success
    closest, gap, face = trimesh.proximity.closest_point(box, result.contact_points)
    assert gap.max() <= 5.0
    wrenches = sg.quality.contact_wrenches(closest, -box.face_normals[face], mu=0.3, edges=8, center=np.zeros(3),
                                           torque_scale=float(np.linalg.norm(box.extents)) / 2.0)
    assert origin_strictly_inside(wrenches)


def test_the_hand_stays_out_of_what_one_camera_view_did_not_see():
    """The half of a 70 mm ball's surface samples that face +x, as one camera sees it: its power plan accepted a grasp
    at its 3rd attempt with the fingers wrapped 28 mm deep into the unseen half (two contacts on the hull's flat back,
    pushing along +x), its precision plan one 12 mm deep. Swept away from the camera, the view keeps the hand out: no
    grasp in 6 power attempts, and the precision grasp keeps every phalanx out of the real ball."""
    from benchmarks.reach_sampling import sampled_clearance

    ball = trimesh.creation.icosphere(subdivisions=3, radius=35.0)
    points = trimesh.sample.sample_surface(ball, 3000, seed=1)[0]
    with pytest.warns(UserWarning, match="is one camera view"):
        view = so.from_points(points[points[:, 0] > 0.0], name="half ball", cache=False)
    hand = sg.SynergyHand.default()
    power = sg.plan(view, "power", restarts=6, executable_reach=False)
    assert not power.success or sampled_clearance(hand, ball, power.u).min() > -3.0
    precision = sg.plan(view, "precision", executable_reach=False)
    assert precision.success and sampled_clearance(hand, ball, precision.u).min() > -3.0


def _ball_on_the_middle_fingertip(hand, depth, mesh):
    """A 40 mm ball against the open hand's middle distal phalanx, ``depth`` mm into it by the fine sphere."""
    u = np.zeros(hand.n_u)
    geo = hand.segments(u)
    a, b = geo.capsules[geo.labels.index("M3")]
    side = np.cross(b - a, [1.0, 0.0, 0.0])
    c = 0.5 * (a + b) + side / np.linalg.norm(side) * (40.0 + geo.radius - depth)
    coarse = trimesh.creation.icosphere(subdivisions=1, radius=40.0).vertices + c
    surface = (trimesh.creation.icosphere(subdivisions=4, radius=40.0) if mesh == "fine"
               else trimesh.convex.convex_hull(coarse - c)).apply_translation(c)
    obj = sg.objects.GraspObject([coarse], mesh=surface)
    status = grasp_status(hand, obj, u, "power")
    return obj, u, status, replace(check_grasp(obj, status, "power"), done=True)


def test_a_capsule_deeper_in_the_mesh_than_allowed_is_rejected_though_shallow_in_the_pieces(hand):
    opts = PlannerOptions()
    obj, u, status, check = _ball_on_the_middle_fingertip(hand, 3.3, "fine")
    pieces_depth = hand_penetration(hand, obj, u).depth
    assert pieces_depth < opts.max_penetration < obj.mesh_excess + pieces_depth
    ok, pen, surface = attempt_module.judge_grasp(hand, obj, u, status, check, opts)
    assert not ok and surface is None and pen.depth == pytest.approx(3.3, abs=0.1)  # measured in the mesh
    # the same pieces with their own hull as the mesh: nothing sticks out, the grasp goes on to the surface check
    obj, u, status, check = _ball_on_the_middle_fingertip(hand, 3.3, "hull")
    ok, pen, surface = attempt_module.judge_grasp(hand, obj, u, status, check, opts)
    assert surface is not None and pen.depth == pytest.approx(pieces_depth)
    # shallower in the mesh than the limit: accepted as far as depth goes
    obj, u, status, check = _ball_on_the_middle_fingertip(hand, 2.5, "fine")
    assert attempt_module.judge_grasp(hand, obj, u, status, check, opts)[2] is not None


# --------------------------------------------------------------------------- starts


def test_principal_directions_of_the_ellipsoid(ellipsoid):
    d = principal_directions(ellipsoid)
    assert d.shape == (14, 3)
    np.testing.assert_allclose(np.linalg.norm(d, axis=1), 1.0)
    np.testing.assert_allclose(np.abs(d[[0, 2, 4]]), np.eye(3), atol=1e-9)  # shortest axis (30 mm) first
    np.testing.assert_allclose(d[1], -d[0])


def test_pinch_seeds_straddle_opposed_surface_points(hand, box):
    opts = PlannerOptions(seed_retreat=0.0, start_clearance=0.0)
    seeds = list(pinch_seeds(hand, box, opts))
    assert len(seeds) >= 5 and all(s.kind == "pinch" for s in seeds)
    for s in seeds[:5]:
        thumb_at, finger_at, width = np.array(s.detail["thumb"]), np.array(s.detail["finger"]), s.detail["width"]
        assert min(abs(width - w) for w in (60.0, 50.0, 90.0)) < 1e-6  # across the box
        tips = hand.points(s.u, "precision")
        thumb, fingers = tips[0], tips[1:3].mean(axis=0)
        axis = (finger_at - thumb_at) / width
        shift = 0.5 * (thumb + fingers) - 0.5 * (thumb_at + finger_at)  # the pair's middle, at most moved back
        np.testing.assert_allclose(np.cross(shift, rotation_xyz(s.u[3:6])[:, 2]), 0.0, atol=1e-3)
        assert shift @ rotation_xyz(s.u[3:6])[:, 2] <= 1e-6
        assert (fingers - thumb) @ axis > width + 2 * opts.seed_opening - 5.0  # opened wider than the pair
        np.testing.assert_allclose(np.cross(fingers - thumb, axis), 0.0, atol=1e-6)
    again = list(pinch_seeds(hand, box, opts))
    assert all(np.array_equal(a.u, b.u) for a, b in zip(seeds, again))  # deterministic


@pytest.fixture(scope="module")
def channel():
    """A U-shaped block: a base 100 x 120 x 65 mm with two walls rising 40 mm, a channel 60 mm wide between them."""
    def block(lo, hi):
        return np.array([[x, y, z] for x in (lo[0], hi[0]) for y in (lo[1], hi[1]) for z in (lo[2], hi[2])], float)

    parts = [block((-50, -60, 0), (50, 60, 65)), block((-50, -60, 65), (-30, 60, 105)), block((30, -60, 65), (50, 60, 105))]
    mesh = trimesh.boolean.union([trimesh.convex.convex_hull(p) for p in parts])
    return so.GraspObject(parts, name="channel", mesh=mesh)


def test_recess_is_the_way_out_to_the_hull(channel, box):
    """0 on the hull; on the channel's floor its depth (40 mm, to 2 % with the discrete directions); on a wall inside
    the channel, 25 mm below the top, the way up and out within 60 degrees of its normal: at least 25 / sin 60 mm."""
    points = np.array([[0.0, 0.0, 65.0], [40.0, 0.0, 105.0], [50.0, 0.0, 30.0], [-30.0, 0.0, 80.0]])
    normals = np.array([[0.0, 0.0, 1.0], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [1.0, 0.0, 0.0]])
    depth = recess(channel, points, normals)
    assert 40.0 <= depth[0] <= 40.0 * 1.02
    assert depth[1] == depth[2] == 0.0
    assert 25.0 / np.sin(np.radians(60.0)) <= depth[3] <= 40.0
    p, n, _, _ = surface_samples(box, 100, 0)
    assert np.all(recess(box, p, n) < 1e-9)  # a convex object has no recess


def test_a_mesh_no_inward_ray_leaves_gives_no_pairs_and_the_direction_starts(hand):
    """An object whose mesh is an open sheet (only a box's lid): no inward ray leaves it, so there are no pinch pairs
    and a precision plan starts from the directions, without an error: the 14 directions, then the 14 again a
    quarter turn about each approach (the thumb-to-fingers axis turned, the palm facing the same way)."""
    box = trimesh.creation.box((60.0, 50.0, 70.0))
    lid = trimesh.Trimesh(box.vertices, box.faces[box.face_normals[:, 2] > 0.5])
    obj = so.GraspObject([box.vertices], mesh=lid, name="lid only")
    assert all(a.shape == (0, 3) for a in surface_samples(obj, 50, 0))
    every = list(starts(hand, obj, "precision", PlannerOptions()))
    assert [s.kind for s in every] == ["direction"] * 28
    assert [s.detail["turn"] for s in every] == [0.0] * 14 + [round(np.pi / 2, 6)] * 14
    for first, turned in zip(every[:14], every[14:]):
        assert first.detail["direction"] == turned.detail["direction"]
        R, T = rotation_xyz(first.u[3:6]), rotation_xyz(turned.u[3:6])
        np.testing.assert_allclose(T[:, 2], R[:, 2], atol=1e-12)  # the same approach
        np.testing.assert_allclose(T[:, 1], -R[:, 0], atol=1e-12)  # y turned a quarter turn about it
        tips = [hand.points(u, "precision")[:, :].mean(axis=0) for u in (first.u, turned.u)]
        np.testing.assert_allclose(np.cross(tips[0] - obj.center, R[:, 2]), 0.0, atol=1e-9)  # both aim at the centre
        np.testing.assert_allclose(np.cross(tips[1] - obj.center, R[:, 2]), 0.0, atol=1e-9)
    with pytest.raises(ValueError, match="roll must be a finite angle in radians"):
        start_configuration(hand, obj, roll=float("nan"))


def test_pinch_seeds_keep_out_of_recesses_first(hand, channel):
    """Across the channel's floor is the pair nearest the aperture and the centre; a fingertip would have to reach
    40 mm into the channel, so the pair across the outer walls comes first."""
    seeds = list(pinch_seeds(hand, channel, PlannerOptions()))
    first = np.array([seeds[0].detail["thumb"], seeds[0].detail["finger"]])
    np.testing.assert_allclose(np.sort(np.abs(first[:, 0])), [50.0, 50.0])  # the outer walls
    floor = [k for k, s in enumerate(seeds) if any(abs(q[2] - 65.0) < 1e-6 and abs(q[0]) < 30.0
                                                   for q in (s.detail["thumb"], s.detail["finger"]))]
    assert floor and floor[0] > 0  # a pair across the floor is among the seeds, later


def test_seeds_start_back_from_the_object_with_every_phalanx_clear(hand, box):
    opts = PlannerOptions()
    for s in list(pinch_seeds(hand, box, opts))[:4]:
        geo = hand.segments(s.u)
        assert box.penetration(geo.capsules, geo.radius).distances.min() >= opts.start_clearance - 1e-6


def test_an_object_without_opposed_faces_starts_from_directions(hand):
    corners = np.array([[1.0, 1.0, 1.0], [1.0, -1.0, -1.0], [-1.0, 1.0, -1.0], [-1.0, -1.0, 1.0]]) * 30.0
    tetrahedron = so.GraspObject([corners], name="tetrahedron", mesh=trimesh.convex.convex_hull(corners))
    kinds = [s.kind for s in starts(hand, tetrahedron, "precision", PlannerOptions())]
    assert kinds and set(kinds) == {"direction"} and len(kinds) == 14 * len(DIRECTION_ROLLS) == 28


def test_power_starts_alternate_the_pre_shapes_and_keep_every_phalanx_clear(hand):
    big = so.from_mesh(trimesh.creation.box((120.0, 120.0, 130.0)), cache=False)
    opts = PlannerOptions()
    schedule = list(power_schedule(hand, big, opts))
    assert [s.kind for s in schedule[:4]] == ["wide", "cupped", "wide", "cupped"] and len(schedule) == 28
    for s in schedule[:6]:
        np.testing.assert_array_equal(s.u[6:], opts.power_wide_preshape if s.kind == "wide" else opts.power_preshape)
        geo = hand.segments(s.u)
        assert big.penetration(geo.capsules, geo.radius).distances.min() >= opts.start_clearance - 1e-6


def test_a_wrap_pose_that_is_a_grasp_is_yielded_before_the_rest_of_its_batch_is_checked(hand, monkeypatch):
    module = sys.modules["synergrasp.planner.starts"]
    original, checks = module.check_grasp, []

    def check(*args, **kwargs):  # the third pose checked is declared a grasp
        result = replace(original(*args, **kwargs), done=len(checks) == 2)
        checks.append(result.done)
        return result

    monkeypatch.setattr(module, "check_grasp", check)
    seen = [(s.detail["grasp"], len(checks)) for s in itertools.islice(wrap_seeds(hand, so.cup(), PlannerOptions()), 13)]
    assert seen[0] == (True, 3)  # yielded straight after its own check, before the batch's other poses
    assert [g for g, _ in seen].count(True) == 1 and all(n > 3 for _, n in seen[1:])


def test_the_wrap_seeds_check_no_pose_past_the_plans_deadline(hand):
    """With a slow LP backend a batch of the seeds' checks takes seconds: past the plan's deadline none is made."""
    cup, opts = so.cup(), PlannerOptions()
    assert list(wrap_seeds(hand, cup, opts, deadline=sg.planner.clock() - 1.0)) == []
    assert next(wrap_seeds(hand, cup, opts, deadline=sg.planner.clock() + 600.0)).kind == "wrap"


def test_wrap_seeds_lay_the_palm_on_the_surface_with_no_phalanx_in_the_object(hand):
    cup = so.cup()
    opts = PlannerOptions()
    seeds = list(itertools.islice(wrap_seeds(hand, cup, opts), 24))
    assert len(seeds) == 24 and {s.kind for s in seeds} == {"wrap"}
    batches = [s.detail["batch"] for s in seeds]
    assert batches == sorted(batches) and batches[0] == 0 and batches[-1] >= 1
    assert sum(1 for s in seeds if s.detail["batch"] == 0 and not s.detail["grasp"]) <= 12
    mesh = cup.mesh
    for s in seeds:
        palm = hand.points(s.u, "power")[-1]
        assert trimesh.proximity.closest_point(mesh, [palm])[1][0] < opts.eps_c  # the palm point is on the surface
        # no phalanx capsule (sampled along its axis) is deeper than max_penetration in the true mesh
        geo = hand.segments(s.u)
        a, b = geo.capsules[:, 0], geo.capsules[:, 1]
        t = np.linspace(0.0, 1.0, 7)[:, None, None]
        axis = (a * (1.0 - t) + b * t).reshape(-1, 3)
        depth = geo.radius + trimesh.proximity.signed_distance(mesh, axis).max()  # signed distance: > 0 inside
        assert depth <= opts.max_penetration + 0.5
    checks = [s.detail["g_Q"] for s in seeds]
    met = [check_grasp(cup, grasp_status(hand, cup, s.u, "power"), "power").done for s in seeds]
    for b in set(batches):  # in each batch, the seeds meeting the criterion come first
        in_batch = [m for m, k in zip(met, batches) if k == b]
        assert in_batch == sorted(in_batch, reverse=True)
    assert all(np.isfinite(q) for q in checks)


def test_single_attempts_from_the_first_wrap_seeds_grasp_the_ellipsoid(hand, ellipsoid):
    """Half of the first six wrap seeds grasp the ellipsoid in one attempt of under 60 iterations each."""
    grasped = 0
    for start in itertools.islice(wrap_seeds(hand, ellipsoid, PlannerOptions()), 6):
        r = plan(ellipsoid, "power", u0=start.u, executable_reach=False)
        assert len(r.attempts) == 1  # a given start is the plan's only attempt
        if r.success:
            verify(r, ellipsoid)
            grasped += r.iterations < 60
    assert grasped >= 3


def test_power_plans_start_with_wrap_seeds_then_the_direction_schedule(hand):
    box = so.from_mesh(trimesh.creation.box((60.0, 70.0, 90.0)), cache=False)
    opts = PlannerOptions()
    kinds = [s.kind for s in starts(hand, box, "power", opts)]
    n = kinds.count("wrap")
    assert n >= 1 and kinds[:n] == ["wrap"] * n and kinds[n:] == [s.kind for s in power_schedule(hand, box, opts)]


def test_a_palm_centred_start_faces_the_object_with_the_palm(hand, ellipsoid):
    a = np.array([1.0, 1.0, 1.0]) / np.sqrt(3.0)
    for centred in (True, False):
        u = start_configuration(hand, ellipsoid, a, 150.0, palm_centred=centred)
        off_axis = np.linalg.norm(np.cross(u[:3] - ellipsoid.center, a))  # palm centre off the approach line
        assert (off_axis < 1e-9) == centred
        np.testing.assert_allclose(rotation_xyz(u[3:6])[:, 2], -a, atol=1e-12)  # the palm faces the centre


# --------------------------------------------------------------------------- attempts


def _watched(monkeypatch):
    """The penetrations `capsule_rows` is called with during an attempt (a list filled as it runs)."""
    calls = []
    rows = attempt_module.capsule_rows
    monkeypatch.setattr(attempt_module, "capsule_rows", lambda h, o, u, st, pen=None: calls.append(pen) or rows(h, o, u, st, pen))
    return calls


def test_a_precision_attempt_watches_the_capsules_once_a_phalanx_was_too_deep(monkeypatch, hand):
    goblet = so.goblet()
    start = list(itertools.islice(starts(hand, goblet, "precision", PlannerOptions()), 5))[-1].u  # the fifth
    calls = _watched(monkeypatch)
    r = run_attempt(hand, goblet, "precision", start, PlannerOptions())
    # not from the start: first when the criterion met a phalanx 6.3 mm deep, then at every evaluation
    assert len(calls) < r.iterations and calls[0].depth > 3.0


def test_a_power_attempt_watches_the_capsules_from_its_start(monkeypatch, hand):
    goblet = so.goblet()
    calls = _watched(monkeypatch)
    r = run_attempt(hand, goblet, "power", next(starts(hand, goblet, "power", PlannerOptions())).u, PlannerOptions(),
                    budget=4)
    assert len(calls) == r.iterations + 1 == 5  # the start's evaluation and every step's


def test_a_precision_attempt_bounds_only_clearance_rows_it_does_not_read(monkeypatch, hand):
    """The far clearance rows of a precision attempt get no LP: each is a lower bound of its exact cP, beyond
    eps_c; the fingertips and the rows the last step's residual reads are exact, so the path is the exact one."""
    cup, opts = so.cup(), PlannerOptions()
    start = list(itertools.islice(starts(hand, cup, "precision", opts), 2))[-1].u
    fars = []
    status = attempt_module.grasp_status
    monkeypatch.setattr(attempt_module, "grasp_status", lambda *a, far=None, **k: fars.append(far) or status(*a, far=far, **k))
    r = run_attempt(hand, cup, "precision", start, opts)
    assert r.success and len(fars) == r.iterations + 1
    bounded = 0
    for u, g, far in zip(r.trajectory, r.status, fars):
        exact = grasp_status(hand, cup, u, "precision").g
        lazy = np.abs(g[:-1] - exact[:-1]) > 1e-9  # (the exact rows to round-off: the LPs start from other bases)
        assert np.isfinite(far[:5]).sum() == 0  # the fingertips are always exact
        assert (np.isfinite(far[lazy])).all() and (g[:-1][lazy] > opts.eps_c).all()
        assert (g[:-1][lazy] <= exact[:-1][lazy] + 1e-9).all()  # a lower bound of the exact cP
        np.testing.assert_allclose(g[:-1][~lazy], exact[:-1][~lazy], rtol=0, atol=1e-9)
        bounded += lazy.sum()
    assert bounded > 5 * r.iterations  # most of the eleven clearance rows, most of the time


def test_a_bounded_row_that_a_penetrating_capsule_replaces_is_exact(monkeypatch, hand):
    """A small box's ring and little fingertips are only kept clear; once the attempt watches the capsules, a capsule
    cuts in while its skin points are beyond eps_c: its row becomes the capsule's signed distance and keeps its skin
    point's nearest point, so the attempt asks for that row exactly (``far`` infinite there: a bounded row has no
    nearest point), and ends as it does with every row exact."""
    box = so.from_mesh(trimesh.creation.box((34.48693061, 28.91172075, 18.39664516)), cache=False)
    opts = PlannerOptions()
    start = list(itertools.islice(starts(hand, box, "precision", opts), 3))[-1].u
    _, contact_rows, segment_rows = status_rows(hand, "precision")
    shape_rows = np.r_[segment_rows, len(contact_rows) - 1]
    penetration, status = attempt_module.hand_penetration, attempt_module.grasp_status
    last, asked = [], []

    def spy_penetration(hand, obj, u, *a, **k):
        last[:] = [np.array(u), penetration(hand, obj, u, *a, **k)]
        return last[1]

    def spy_status(hand, obj, u, *a, far=None, **k):
        if far is not None and last and np.array_equal(last[0], u):  # watched: the capsules were just tested there
            asked.extend(far[shape_rows[last[1].distances < 0.0]].tolist())
        return status(hand, obj, u, *a, far=far, **k)

    monkeypatch.setattr(attempt_module, "hand_penetration", spy_penetration)
    monkeypatch.setattr(attempt_module, "grasp_status", spy_status)
    lazy = run_attempt(hand, box, "precision", start, opts)
    assert asked and np.all(np.isinf(asked))  # the situation arises, and every such row is asked for exactly
    monkeypatch.setattr(attempt_module, "grasp_status", lambda *a, far=None, **k: status(*a, **k))
    exact = run_attempt(hand, box, "precision", start, opts)
    assert lazy.outcome is exact.outcome
    assert np.isfinite(lazy.final.nearest[lazy.check.contact]).all()


def _traced(hand, obj, start, opts, **kwargs):
    """One precision attempt, with the status (and its Jacobian) and check at its start and after every step."""
    trace = []
    r = run_attempt(hand, obj, "precision", start, opts, progress=lambda c, s: trace.append((c, s)), **kwargs)
    first = grasp_status(hand, obj, start, "precision", smoothing=opts.smoothing * obj.torque_scale)
    return r, [(check_grasp(obj, first, "precision"), first)] + trace


def test_a_precision_step_moves_no_fingertip_in_the_band_by_more_than_band_step(hand):
    """To first order (the status's Jacobian): every step, and some steps are shortened to exactly band_step."""
    ellipsoid, opts = so.ellipsoid(), PlannerOptions(band_step=0.5)
    start = next(starts(hand, ellipsoid, "precision", opts)).u
    r, trace = _traced(hand, ellipsoid, start, opts)
    low, high = opts.contact_band
    moves = []
    for (_, st), du in zip(trace, np.diff(r.trajectory, axis=0)):
        held = (st.g[:5] >= low) & (st.g[:5] <= high)
        if held.any():
            moves.append(np.abs(st.J[:5][held] @ du).max())
    assert max(moves) <= 0.5 * (1 + 1e-9)
    assert sum(np.isclose(moves, 0.5, rtol=1e-9)) >= 2  # the limit binds
    free = run_attempt(hand, ellipsoid, "precision", start, replace(opts, band_step=50.0))  # never binds
    n = min(len(free.trajectory), len(r.trajectory))
    assert np.abs(free.trajectory[:n] - r.trajectory[:n]).max() > 0.1  # another path (mm)


def test_a_precision_attempt_closes_its_contacts_by_their_own_q_once_sq_is_closed(monkeypatch, hand):
    """While g_sQ < 0 with at least three fingertips touching and their g_Q > 0, the last row is their g_Q."""
    ellipsoid, opts = so.ellipsoid(), PlannerOptions()
    start = list(itertools.islice(starts(hand, ellipsoid, "precision", opts), 2))[-1].u
    r, trace = _traced(hand, ellipsoid, start, opts)
    closing = [i for i, (c, st) in enumerate(trace) if st.g[-1] < 0 and c.n_contacts >= 3 and c.q > 0]
    done = [i for i, (c, _) in enumerate(trace) if c.done]
    assert r.success and closing and min(closing) < min(done)
    calls = []
    quality = attempt_module.contact_quality
    monkeypatch.setattr(attempt_module, "contact_quality", lambda *a, **k: calls.append(1) or quality(*a, **k))
    # up to the first such step: that step's row and its new status's (the trust region's ratio), none before
    run_attempt(hand, ellipsoid, "precision", start, opts, budget=min(closing) + 1)
    assert len(calls) == 2
    calls.clear()
    monkeypatch.setattr(attempt_module, "CRITERION", {"precision": (6, 6), "power": (4, 6)})  # never six of five
    run_attempt(hand, ellipsoid, "precision", start, opts, budget=min(closing) + 1)
    assert not calls


def test_the_stall_window_is_per_grasp_kind(hand):
    """The cup's second precision start stands still for 12 iterations, then closes its grasp."""
    cup = so.cup()
    pinch = list(itertools.islice(starts(hand, cup, "precision", PlannerOptions()), 2))[-1].u
    short = run_attempt(hand, cup, "precision", pinch, PlannerOptions(stall_window=12))
    default = run_attempt(hand, cup, "precision", pinch, PlannerOptions())  # (20, 16): precision 20
    assert PlannerOptions().stall_window == (20, 16) and PlannerOptions(stall_window=12).stall_window == (12, 12)
    assert short.outcome is Outcome.STALLED and short.reason.endswith("(in 12 iterations)")
    assert default.success and default.iterations > short.iterations
    # the same path until then (to round-off: the LPs start from the bases the first attempt left)
    np.testing.assert_allclose(default.trajectory[: short.iterations + 1], short.trajectory, rtol=0, atol=1e-9)
    stalling = list(itertools.islice(starts(hand, cup, "power", PlannerOptions()), 7))[-1].u  # the seventh power start
    wrap = run_attempt(hand, cup, "power", stalling, PlannerOptions(stall_window=(20, 4)))  # the power window is the second
    assert wrap.outcome is Outcome.STALLED and wrap.reason.endswith("(in 4 iterations)")


def test_a_power_attempt_holds_a_good_enough_sq(monkeypatch):
    """Below power_sq_hold the sQ row asks to keep g_sQ, not for sq_step less; above it, for sq_step less."""
    obj = so.cup()
    asked = []
    step = attempt_module.limited_step

    def spy(J, e, z, limits, first):
        asked.append(e[-1])  # the sQ row's (scaled) error: target - g_sQ
        return step(J, e, z, limits, first)

    monkeypatch.setattr(attempt_module, "limited_step", spy)
    far = next(power_schedule(SynergyHand.default(), obj, PlannerOptions())).u  # reaching from afar: g_sQ falls
    r = plan(obj, "power", u0=far, refine_iterations=0)
    sq = r.status[: len(asked), -1]
    held, pulled = sq < -0.05, sq >= -0.05
    assert held.any() and pulled.any()
    np.testing.assert_array_equal(np.asarray(asked)[held], 0.0)
    np.testing.assert_allclose(np.asarray(asked)[pulled], -0.1)


def test_a_power_hand_in_the_object_gets_out_before_sq_is_asked_first(hand, monkeypatch):
    """A power step puts the sQ row in the first priority level only while no row is inside the object; a
    precision step always does."""
    firsts = []
    step = attempt_module.limited_step

    def spy(J, e, z, limits, first):
        firsts.append(bool(first[-1]))  # the sQ row is the last row passed (always active)
        return step(J, e, z, limits, first)

    monkeypatch.setattr(attempt_module, "limited_step", spy)
    bell, opts = so.bell(), PlannerOptions()
    far = next(power_schedule(hand, bell, opts)).u  # reaching from afar: out of the bell, then rows in it
    r = run_attempt(hand, bell, "power", far, opts)
    inside = (r.status[: len(firsts), :-1] < 0.0).any(axis=1)  # the status each step started from
    assert len(firsts) == r.iterations and inside.any() and not inside.all()
    np.testing.assert_array_equal(firsts, ~inside)
    firsts.clear()
    r = run_attempt(hand, bell, "precision", next(starts(hand, bell, "precision", opts)).u, opts)
    assert len(firsts) >= r.iterations > 0 and all(firsts)  # (a precision attempt returns its best grasp)


def test_an_attempt_whose_fingertips_never_reach_the_surface_ends(hand, ellipsoid):
    far = start_configuration(hand, ellipsoid, (0.0, 1.0, 0.0), 1000.0)  # out of reach in a few iterations
    r = run_attempt(hand, ellipsoid, "precision", far, PlannerOptions(touch_window=5))
    assert r.outcome is Outcome.NO_TOUCH and r.iterations == 5 and not r.success
    assert run_attempt(hand, ellipsoid, "precision", far, PlannerOptions(touch_window=0), budget=8).iterations == 8
    assert run_attempt(hand, ellipsoid, "power", far, PlannerOptions(touch_window=5), budget=8).iterations == 8


def test_refining_raises_the_margin(hand):
    """The cup's first attempt meets the criterion with g_Q = -0.0000: refined, it is accepted with a margin."""
    cup = so.cup()
    start = next(starts(hand, cup, "precision", PlannerOptions())).u
    plain = run_attempt(hand, cup, "precision", start, PlannerOptions(refine_iterations=0))
    refined = run_attempt(hand, cup, "precision", start, PlannerOptions())
    assert plain.outcome is Outcome.SURFACE and plain.check.done and plain.check.q > -0.01
    assert refined.success and refined.surface.q < -0.03 and refined.iterations > plain.iterations


def test_a_refinement_that_never_gets_the_hand_out_ends_in_penetration_not_surface(hand):
    """The bell's third power start (the attempt started cold) meets the criterion with a phalanx or the palm
    deeper than max_penetration and stays so while refining: no grasp was judged on the true surface."""
    bell, cup, opts = so.bell(), so.cup(), PlannerOptions()
    start = list(itertools.islice(starts(hand, bell, "power", opts), 3))[-1].u
    forget_warm_starts(get_backend("native"), bell)
    r = run_attempt(hand, bell, "power", start, opts)
    assert r.outcome is Outcome.PENETRATION and r.surface is None
    depth = float(r.reason.split("(")[1].split(" mm")[0])
    assert depth > opts.max_penetration
    # one that was judged there says what failed last: its Q on the true surface against q_accept
    start = next(starts(hand, cup, "precision", opts)).u
    plain = run_attempt(hand, cup, "precision", start, PlannerOptions(refine_iterations=0))
    assert plain.outcome is Outcome.SURFACE and "on the true surface (q_accept -0.01)" in plain.reason


def test_the_sq_request_is_what_a_step_within_the_radius_can_give():
    grad = np.array([0.0, 3.0, 4.0])
    assert sq_request(0.1, 0.2, grad) == 0.1  # the moving target as asked
    assert sq_request(0.1, 0.01, grad) == pytest.approx(0.05)  # |grad| * radius
    assert sq_request(0.1, 0.2, np.zeros(3)) == 0.0  # a flat sQ: nothing asked, the contact rows steer


# --------------------------------------------------------------------------- plans


def verify(result, obj):
    """The benchmarks' independent check of a plan's final grasp, asserted (`benchmarks/verification.py`, imported
    through generalise.py, which puts its folder on the path: contacts within 5 mm of the true mesh, qhull's verdict at
    its normals, the hand's depth in it by a dense sampled check)."""
    from benchmarks.generalise import verify as independent

    assert result.success, result.reason
    out = independent(result, obj)
    assert out["verified"], out


def test_precision_plan_of_the_goblet(goblet_plan):
    r = goblet_plan
    verify(r, so.goblet())
    assert len(r.contact_points) >= 3 and set(r.contact_labels) <= {"T0", "I0", "M0", "R0", "L0"}
    assert r.trajectory.shape == (r.iterations + 1, 8) and r.status.shape == (r.iterations + 1, 17)
    assert np.all(np.abs(r.trajectory[:, 6:]) <= 1.0)  # synergy limits
    assert r.final_q < 0 and r.lp_solves > r.iterations
    assert r.total_iterations == sum(a["iterations_run"] for a in r.attempts) >= sum(a["iterations"] for a in r.attempts)
    assert r.attempts[-1]["iterations"] == r.iterations
    assert r.attempts[-1]["outcome"] == "grasp" and r.attempts[0]["kind"] == "pinch"


def test_every_iteration_run_is_counted_and_kept_within_max_iter():
    """The goblet's precision grasp is refined after it is met, and the refining iterations after the grasp it keeps
    are not in its trajectory: they count in total_iterations (once per progress call) and in max_iter all the same
    (they were missing from both: 65 iterations reported against 75 run)."""
    calls = []
    r = sg.plan(so.goblet(), "precision", progress=lambda check, status: calls.append(1))
    last = r.attempts[-1]
    assert r.success and last["iterations_run"] > last["iterations"] == r.iterations
    assert len(calls) == r.total_iterations == sum(a["iterations_run"] for a in r.attempts)
    assert f"{r.total_iterations} iterations in all" in r.reason
    capped_calls = []
    capped = sg.plan(so.goblet(), "precision", max_iter=r.total_iterations - 1,
                     progress=lambda check, status: capped_calls.append(1))
    assert len(capped_calls) == capped.total_iterations <= r.total_iterations - 1


def test_power_plan_has_a_palm_contact():
    obj = so.ellipsoid()
    r = plan(obj, "power")
    verify(r, obj)
    assert "P" in r.contact_labels and len(r.contact_points) >= 4
    assert r.status.shape[1] == 17


@pytest.mark.parametrize(
    "obj",
    [so.ellipsoid(33.0, 33.0, 33.0), so.from_mesh(trimesh.creation.box((45.0, 170.0, 22.0)), name="flat bar", cache=False)],
    ids=["sphere", "flat bar"],
)
def test_precision_plan_of_household_shapes(obj):
    r = plan(obj, "precision")
    verify(r, obj)
    assert len(r.contact_points) >= 3


def test_options_come_as_an_object_or_as_keywords(ellipsoid):
    opts = PlannerOptions(max_iter=5, restarts=1)
    a = plan(ellipsoid, "precision", options=opts)
    b = plan(ellipsoid, "precision", max_iter=5, restarts=1)
    c = plan(ellipsoid, "precision", options=PlannerOptions(restarts=1), max_iter=5)
    np.testing.assert_allclose(a.trajectory, b.trajectory, atol=1e-6)  # the LP warm starts differ at round-off
    np.testing.assert_allclose(a.trajectory, c.trajectory, atol=1e-6)
    assert a.options == b.options == c.options and a.options["max_iter"] == 5
    # the plan's own budget ran out, not the attempt's cap of 120 iterations; the grasp type in any case
    assert a.attempts[-1]["outcome"] == "budget" and "the plan's iterations or time ran out" in a.reason
    assert plan(ellipsoid, "Precision", max_iter=5, restarts=1).grasp == "precision"


def test_the_stall_window_pair_comes_as_any_sequence_of_two():
    """A (precision, power) pair as a tuple, a list or a NumPy array (as contact_band takes one); one integer for both."""
    for pair in ((5, 6), [5, 6], np.array([5, 6])):
        assert PlannerOptions(stall_window=pair).stall_window == (5, 6)
    assert PlannerOptions(stall_window=np.int64(7)).stall_window == PlannerOptions(stall_window=np.array(7)).stall_window == (7, 7)
    for bad in (np.array([5, 6, 7]), np.array([[5, 6]]), (5, 0), 2.5):
        with pytest.raises(ValueError, match=r"stall_window must be an integer in \[1, inf\) or a \(precision, power\) pair"):
            PlannerOptions(stall_window=bad)


@pytest.mark.parametrize("field", ["mu", "max_iter", "seed", "time_limit"])
def test_an_integer_too_large_for_a_float_is_refused_by_name(field):
    """10**400 has no float: an OverflowError from inside float() is not the error to give."""
    with pytest.raises(ValueError, match=rf"PlannerOptions.{field} must be an? (number|integer) in"):
        PlannerOptions(**{field: 10**400})
    with pytest.raises(ValueError, match=r"AnnealingOptions.t0 must be a number in"):
        AnnealingOptions(t0=10**400)


def test_a_plan_stops_at_its_time_limit(ellipsoid):
    r = plan(ellipsoid, "power", time_limit=0.05)
    assert not r.success and r.attempts[-1]["outcome"] == "budget" and len(r.attempts) == 1
    assert "ran out" in r.reason


def test_a_small_ball_is_pinched_with_the_fingertips_that_reach_it():
    """On a 40 mm ball the little fingertip (54 mm from the index at the nearest) is only kept clear: the plan
    succeeds in its first attempts, where steering all five fingertips into contact stalled 28 attempts."""
    ball = so.from_mesh(trimesh.creation.icosphere(subdivisions=3, radius=20.0), name="40 mm ball", cache=False)
    hand = SynergyHand.default()
    assert sg.planner.pinch_fingertips(hand, ball).tolist() == [True, True, True, True, False]
    r = plan(ball, "precision")
    assert r.success and len(r.attempts) <= 3 and r.final_q < -0.01
    assert "T0" in r.contact_labels
    assert np.all(np.abs(np.linalg.norm(r.contact_points, axis=1) - 20.0) < 1.0)  # on the ball


def test_a_small_cylinder_is_held_by_the_three_fingertips_that_reach_it():
    """A cylinder 24 mm across and 30 mm long: only the thumb, index and middle fingertips reach it, and three
    contacts force-closed on the true surface end the plan in its first attempts (with the paper's -0.1 for three
    contacts, all 22 attempts failed)."""
    cylinder = so.from_mesh(trimesh.creation.cylinder(radius=12.0, height=30.0, sections=32), name="small cylinder",
                            cache=False)
    hand = SynergyHand.default()
    assert sg.planner.pinch_fingertips(hand, cylinder).tolist() == [True, True, True, False, False]
    r = plan(cylinder, "precision")
    assert r.success and len(r.attempts) <= 3 and r.final_q < 0.0 and r.surface_q < -0.01
    assert {"T0", "I0", "M0"} <= set(r.contact_labels)
    radial = np.linalg.norm(r.contact_points[:, :2], axis=1)
    assert np.all((np.abs(radial - 12.0) < 1.5) | (np.abs(np.abs(r.contact_points[:, 2]) - 15.0) < 1.5))  # on it


def test_the_fingertips_that_reach_an_object_do_not_depend_on_how_it_is_turned():
    """A 37 x 30 x 21 mm box: the ring fingertip (35 mm from the index at the nearest) reaches it. Turned, its bounding
    box's largest side read 37-52 mm and its least 26-37 mm; its smallest enclosing box's largest side stays 37."""
    hand = SynergyHand.default()
    box = so.from_mesh(trimesh.creation.box((37.0, 30.0, 21.0)), name="box", cache=False)
    assert sg.planner.pinch_fingertips(hand, box).tolist() == [True, True, True, True, False]
    for k in range(6):
        turned = box.transformed(trimesh.transformations.random_rotation_matrix(np.random.default_rng(k).random(3)))
        assert turned.length == pytest.approx(37.0) and turned.width == pytest.approx(21.0)
        assert sg.planner.pinch_fingertips(hand, turned).tolist() == [True, True, True, True, False]
    cube = so.from_mesh(trimesh.creation.box((38.0, 38.0, 38.0)), name="cube", cache=False)  # principal axes: any
    for k in range(4):
        turned = cube.transformed(trimesh.transformations.random_rotation_matrix(np.random.default_rng(k).random(3)))
        assert turned.length == pytest.approx(38.0) and turned.width == pytest.approx(38.0)
        assert sg.planner.pinch_fingertips(hand, turned).tolist() == [True, True, True, True, False]
    thin = so.from_mesh(trimesh.creation.box((33.0, 20.0, 10.0)), name="thin", cache=False)
    turned = thin.transformed(trimesh.transformations.euler_matrix(0.0, 0.0, np.pi / 4))
    assert turned.size > 35.0 and sg.planner.pinch_fingertips(hand, turned).tolist() == [True, True, True, False, False]


def test_a_plan_does_not_depend_on_the_plans_made_before_it():
    """Every plan starts its LPs cold: the same plan of the same object, before and after other plans (of it and of
    another object), is bit-identical (the warm starts kept from earlier solves used to move it at round-off)."""
    obj = so.ellipsoid()
    first = plan(obj, "power", executable_reach=False)
    plan(so.cup(), "precision", executable_reach=False)
    plan(obj, "precision", executable_reach=False)
    again = plan(obj, "power", executable_reach=False)
    np.testing.assert_array_equal(first.trajectory, again.trajectory)
    np.testing.assert_array_equal(first.status, again.status)


def test_the_plan_clock_stands_still_while_numba_compiles():
    """The time limit's clock (`clock`) does not count a compilation, and otherwise runs with perf_counter."""
    import time

    import numba

    from synergrasp.planner import clock

    @numba.njit(cache=False)
    def fresh(x):  # never compiled before this test
        total = 0.0
        for i in range(len(x)):
            for j in range(i):
                total += np.sqrt(abs(x[i] - x[j])) * np.sin(x[j])
        return total

    wall, clocked = time.perf_counter(), clock()
    fresh(np.arange(5.0))
    wall, clocked = time.perf_counter() - wall, clock() - clocked
    assert wall - clocked > 0.02 and 0.0 <= clocked < 0.5 * wall  # the compilation took the time, the clock stood
    wall, clocked = time.perf_counter(), clock()
    fresh(np.arange(5.0))
    time.sleep(0.05)
    wall, clocked = time.perf_counter() - wall, clock() - clocked
    assert abs(clocked - wall) < 0.02  # compiled: the clock runs through the 50 ms as perf_counter does


def test_a_failed_plan_says_why_its_attempts_ended(ellipsoid):
    r = plan(ellipsoid, "precision", restarts=2, iterations_per_attempt=3)
    assert not r.success and len(r.attempts) == 2
    assert all(a["outcome"] == "cap" for a in r.attempts)
    assert r.reason.startswith("no stable grasp found in 2 attempt(s)") and "2 iteration cap" in r.reason
    assert "slender" not in r.reason  # (its axis torque: 0.3 x 40 mm / 50 mm = 0.24 of its torque scale)


def test_a_failed_power_plan_says_when_no_wrap_pose_was_free_of_the_object():
    """A 150 mm ball: with the palm on its surface the thumb reaches 18-50 mm into it in every pose screened, so no
    wrap seed is made; the reason only counted the stalls of the direction starts."""
    ball = so.from_mesh(trimesh.creation.icosphere(3, 75.0), name="ball", cache=False)
    r = plan(ball, "power", restarts=2, executable_reach=False)
    assert not r.success and {a["kind"] for a in r.attempts}.isdisjoint({"wrap"})
    assert "no wrap pose (the palm on its surface, the fingers closed around it) was free of it" in r.reason
    assert "no wrap pose" not in plan(so.cup(), "power", restarts=1, max_iter=2, executable_reach=False).reason


def test_a_failed_plan_on_a_slender_object_says_its_q_distance_stays_near_0():
    """A 20 x 300 mm rod: friction at 10 mm from its axis against a torque scale of 150 mm caps every grasp's Q
    distance near -0.02; a plan that fails on it says so, that it steered by the rod's diameter, and what to pass."""
    import trimesh

    from synergrasp.planner.core import axial_torque

    rod = so.from_mesh(trimesh.creation.cylinder(radius=10.0, height=300.0, sections=32), name="rod", cache=False)
    arm, torque = axial_torque(rod, 0.3)
    assert arm == pytest.approx(10.0) and torque == pytest.approx(0.3 * 10.0 / np.hypot(150.0, 10.0))
    r = plan(rod, "power", restarts=1, executable_reach=False)
    assert not r.success and "it is slender: its surface lies at most 10 mm from its long axis" in r.reason
    assert "stays near 0 (of the order of 0.020, near or above the acceptance's q_accept = -0.01)" in r.reason and "Its attempts steered by a torque scale of 20 mm (twice its axial radius)" in r.reason
    assert "torque_scale=20" in r.reason
    assert axial_torque(so.from_mesh(trimesh.creation.cylinder(radius=10.0, height=300.0, sections=32), cache=False,
                                     torque_scale=20.0), 0.3)[1] == pytest.approx(0.15)


def test_the_steering_scale_is_a_slender_objects_diameter_and_its_own_torque_scale_otherwise():
    """`steering_scale` by hand: a rod's diameter (friction at 10 mm against a bounding radius of 150 mm: 0.02 < 0.05),
    the object's L for the paper's four objects and for the rod at a friction of 2.4 (mu r = 0.16 R, above 0.05 R);
    never above L."""
    import trimesh

    from synergrasp.planner.status import SLENDER, axial_radius, principal_axes, slender, steering_scale

    rod = so.from_mesh(trimesh.creation.cylinder(radius=10.0, height=300.0, sections=32), cache=False)
    assert axial_radius(rod) == pytest.approx(10.0)
    assert abs(principal_axes(rod)[2] @ [0.0, 0.0, 1.0]) == pytest.approx(1.0)  # the long axis: the cylinder's
    assert steering_scale(rod, 0.3) == pytest.approx(20.0)
    assert steering_scale(rod, 2.4) == rod.torque_scale and not slender(rod, 2.4) and slender(rod, 0.3)
    small = so.from_mesh(trimesh.creation.cylinder(radius=10.0, height=300.0, sections=32), cache=False,
                         torque_scale=12.0)
    assert steering_scale(small, 0.3) == 12.0  # a torque scale below the diameter is kept
    for name in ("ellipsoid", "cup", "bell", "goblet"):
        obj = so.get(name)
        assert 0.3 * axial_radius(obj) >= SLENDER * obj.radius and steering_scale(obj, 0.3) == obj.torque_scale


def test_the_sq_row_weighs_torques_by_the_torque_scale_it_is_given(hand, ellipsoid):
    """`grasp_status(..., torque_scale=L)`'s g_sQ is the Q distance of its scaled contacts with that L, and its
    Jacobian row matches finite differences of it; a bad scale is refused."""
    u = near_start(hand, ellipsoid)
    st = grasp_status(hand, ellipsoid, u, "precision", torque_scale=20.0)
    sc = ellipsoid.scaled_contacts(st.points)
    assert st.g[-1] == pytest.approx(sg.q_distance(sc.contact, sc.normal, torque_scale=20.0).value, abs=1e-12)
    assert st.g[-1] != pytest.approx(grasp_status(hand, ellipsoid, u, "precision").g[-1], abs=1e-6)
    fd = finite_difference(lambda v: grasp_status(hand, ellipsoid, v, "precision", torque_scale=20.0).g[-1], u)
    np.testing.assert_allclose(st.J[-1], fd, rtol=1e-4, atol=1e-6)
    with pytest.raises(ValueError, match="torque_scale"):
        grasp_status(hand, ellipsoid, u, "precision", torque_scale=-1.0)


def test_a_slender_rods_power_grasp_is_planned_and_judged_in_its_own_torque_scale():
    """The 20 x 300 mm rod whose power plan failed after 40 attempts when its attempts steered by L = 150 mm: steered
    by its diameter, it is grasped, verified on the mesh, and its reported Q is in L (qhull's verdict agrees)."""
    import trimesh

    rod = so.from_mesh(trimesh.creation.cylinder(radius=10.0, height=300.0, sections=32), name="rod", cache=False)
    r = plan(rod, "power", executable_reach=False)
    assert r.success and len(r.attempts) <= 10
    verify(r, rod)
    q = sg.q_distance(r.contact_points, r.contact_normals, center=rod.center, torque_scale=rod.torque_scale)
    assert r.final_q == pytest.approx(q.value, abs=1e-9) and -0.03 < q.value < 0.0


def test_the_steps_are_normalised_by_the_objects_size_not_its_torque_scale(hand):
    """A torque scale within its range (a hundredth of the default) changes Q, not how far the palm moves per step:
    the box is grasped (steps normalised by the torque scale moved the palm 0.17 mm per iteration and every attempt
    stalled before a fingertip reached it); a torque scale far above the size is not called slenderness."""
    corners = np.array(list(itertools.product([-25.0, 25.0], [-30.0, 30.0], [-45.0, 45.0])))
    default = so.GraspObject([corners])
    assert default.radius == default.torque_scale == pytest.approx(np.linalg.norm([25.0, 30.0, 45.0]))
    small = so.GraspObject([corners], torque_scale=0.01 * default.radius)
    assert small.radius == default.radius
    assert plan(small, "precision", executable_reach=False).success
    large = plan(so.GraspObject([corners], torque_scale=100.0 * default.radius), "precision", restarts=2,
                 executable_reach=False)
    assert not large.success and "slender" not in large.reason


def test_save_load_round_trip(goblet_plan, tmp_path):
    path = goblet_plan.save(tmp_path / "plan.json")
    back = PlanResult.load(path)
    arrays = ("u", "trajectory", "status", "target", "q_history", "contact_points", "contact_normals", "pregrasp", "path",
              "clearance")
    for name in arrays:
        np.testing.assert_array_equal(getattr(back, name), getattr(goblet_plan, name))
    assert back.surface_q == goblet_plan.surface_q
    others = ("success", "reason", "iterations", "contact_labels", "penetration", "time_s", "lp_solves", "backend", "options",
              "attempts", "grasp", "object_name", "hand", "collision_free", "reach", "held")
    for name in others:
        assert getattr(back, name) == getattr(goblet_plan, name)
    assert set(arrays + others + ("surface_q",)) == set(PlanResult.__dataclass_fields__)  # every field is checked
    assert len(goblet_plan.path) > 1 and goblet_plan.reach


def test_first_iterations_agree_on_every_backend(hand):
    obj = so.ellipsoid()
    u0 = near_start(hand, obj)
    runs = {name: plan(obj, "precision", backend=name, u0=u0, max_iter=20) for name in BACKENDS}
    reference = runs["highs"].trajectory
    for name, r in runs.items():
        k = min(len(r.trajectory), len(reference))
        np.testing.assert_allclose(r.trajectory[:k], reference[:k], atol=1e-6, err_msg=name)


def test_first_power_iterations_agree_on_every_backend():
    obj = so.ellipsoid()
    runs = {name: plan(obj, "power", backend=name, approach=(1.0, -1.0, 1.0), max_iter=20) for name in BACKENDS}
    reference = runs["highs"].trajectory
    for name, r in runs.items():
        k = min(len(r.trajectory), len(reference))
        np.testing.assert_allclose(r.trajectory[:k], reference[:k], atol=1e-6, err_msg=name)


def test_the_caller_chooses_the_approach(hand, ellipsoid):
    a = plan(ellipsoid, "precision", approach=(0.0, 0.0, 1.0), max_iter=1)
    u = a.trajectory[0]
    toward = ellipsoid.center - hand.points(u, "power")[-1]
    palm_normal = rotation_xyz(u[3:6])[:, 2]
    assert palm_normal @ toward / np.linalg.norm(toward) > 0.9  # the palm faces the object
    assert hand.points(u, "power")[-1][2] > ellipsoid.center[2] + 50  # from above


def test_a_power_approach_starts_as_the_power_starts_do():
    """Without the wide pre-shape (power_wide_preshape=None: cupped starts only), an approach's start is cupped, not
    the mean pose (zeros)."""
    cup = so.cup()
    cupped = plan(cup, "power", approach=(0.0, 1.0, 0.0), power_wide_preshape=None, max_iter=1)
    assert cupped.attempts[0]["start"][6:] == list(PlannerOptions().power_preshape)
    wide = plan(cup, "power", approach=(0.0, 1.0, 0.0), max_iter=1)
    assert wide.attempts[0]["start"][6:] == list(PlannerOptions().power_wide_preshape)


def test_progress_gets_read_only_copies(ellipsoid):
    """A callback that edited the status in place changed the plan (success became failure)."""
    seen = []

    def progress(check, status):
        seen.append((check.contact.flags.writeable, status.g.flags.writeable, status.J.flags.writeable))
        with pytest.raises(ValueError, match="read-only"):
            status.g[:] = 0.0

    base = plan(ellipsoid, "precision")
    watched = plan(ellipsoid, "precision", progress=progress)
    assert seen and not any(any(flags) for flags in seen)
    assert watched.success and np.array_equal(watched.trajectory, base.trajectory)


# --------------------------------------------------------------------------- bad input

@pytest.mark.parametrize(
    "kwargs, error, match",
    [
        ({"grasp": "pinch"}, ValueError, "grasp must be 'precision' or 'power', got 'pinch'"),
        ({"u0": [0, 0, np.nan, 0, 0, 0, 0, 0]}, ValueError, "u0 contains NaN"),
        ({"u0": np.zeros(5)}, ValueError, r"u0 must have shape \(8,\)"),
        ({"approach": [0, 0, 0]}, ValueError, "non-zero direction"),
        ({"backend": "simplex"}, ValueError, "unknown LP backend"),
        ({"stepsize": 3}, ValueError, "unknown planner options"),
        ({"options": {"max_iter": 3}}, TypeError, "options of method=.gradient. must be an instance of PlannerOptions"),
        ({"hand": "paper"}, TypeError, "hand must be a SynergyHand"),
        ({"progress": 3}, TypeError, "progress must be callable"),
        ({"grasp": "power", "power_preshape": (0.0, 1.0, 0.5)}, ValueError, "one value per synergy"),
    ],
)
def test_bad_input(ellipsoid, kwargs, error, match):
    with pytest.raises(error, match=match):
        plan(ellipsoid, **kwargs)


def test_synergies_beyond_their_limits_are_clipped_with_a_warning(ellipsoid):
    """A pre-shape or a u0 whose synergies lie outside the hand's limits ([-1, 1]) is clipped, and says so: the
    plan from u0 with its synergies at 1e6 and -1e6 is the plan from u0 with them at 1 and -1."""
    from synergrasp.planner.starts import preshape

    hand = SynergyHand.default()
    with pytest.warns(UserWarning, match=r"pre-shape's synergies \[1000000.0, 0.5\] are outside the synergy limits"
                                         r".*clipped to \[1.0, 0.5\]"):
        np.testing.assert_array_equal(preshape(hand, (1e6, 0.5)), [1.0, 0.5])
    u0 = np.r_[near_start(hand, ellipsoid)[:6], 1e6, -1e6]
    with pytest.warns(UserWarning, match=r"u0's synergies \[1000000.0, -1000000.0\] are outside the synergy limits"
                                         r".*clipped to \[1.0, -1.0\]"):
        wild = plan(ellipsoid, "precision", u0=u0, max_iter=15, executable_reach=False)
    tame = plan(ellipsoid, "precision", u0=np.r_[u0[:6], 1.0, -1.0], max_iter=15, executable_reach=False)
    np.testing.assert_array_equal(wild.trajectory, tame.trajectory)


def test_an_object_in_metres_is_refused():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        tiny = so.ellipsoid(0.03, 0.04, 0.05)
    with pytest.raises(ValueError, match="too small to grasp.*scale=1000"):
        plan(tiny, "precision")


def thin_bowl():
    """A hemispherical shell, 100 mm across with a 4 mm wall: its true mesh, and 24 convex pieces of its patches."""
    outer, inner = trimesh.creation.icosphere(3, 50.0), trimesh.creation.icosphere(3, 46.0)
    lid = trimesh.creation.box((120.0, 120.0, 60.0))
    lid.apply_translation((0.0, 0.0, 30.0))
    bowl = trimesh.boolean.difference([outer, inner, lid], engine="manifold")
    v = bowl.vertices
    sector = np.floor((np.arctan2(v[:, 1], v[:, 0]) + np.pi) / (2 * np.pi) * 8).clip(0, 7)
    band = np.floor(-v[:, 2] / 50.0 * 3).clip(0, 2)
    pieces = [v[(sector == a) & (band == b)] for a in range(8) for b in range(3)]
    return so.GraspObject([p for p in pieces if len(p) >= 4], mesh=bowl, name="thin bowl")


def test_a_failed_plan_on_a_thin_wall_says_the_pinch_cannot_close_on_it(hand):
    """Every pinch pair of a 4 mm shell (and of a 6 mm disc) spans its wall, narrower than the hand's smallest pinch
    (15 mm) less the contact band's far edge (4.5 mm, where the steering brings a pad) on either side: the failure
    says so. A plan that fails for another reason (its iterations ran out on the ellipsoid) does not."""
    assert 14.0 < smallest_pinch(hand) < 16.0
    r = plan(thin_bowl(), "precision", restarts=3, executable_reach=False)
    assert not r.success and all(a["kind"] == "pinch" and a["width"] < 5.0 for a in r.attempts)
    assert ("at most 4 mm apart, while the thumb and the index and middle fingertips close to no less than 15 mm, too "
            "far apart to bring both within 4.5 mm of it (the contact band the pads are steered into; accepted within "
            "5 mm): a wall or sheet too thin for this hand's pinch") in r.reason
    disc = so.from_mesh(trimesh.creation.cylinder(radius=60.0, height=6.0, sections=64), name="disc", cache=False)
    r = plan(disc, "precision", restarts=3, executable_reach=False)  # 6 mm: 15 - 2 x 5 mm would have let it pass
    assert not r.success and "at most 6 mm apart" in r.reason and "too thin for this hand's pinch" in r.reason
    short = plan(so.ellipsoid(), "precision", max_iter=3)
    assert not short.success and "fingertips close to" not in short.reason


def test_a_failed_precision_plan_says_when_the_object_is_too_wide_for_a_pinch(hand):
    """A 150 mm cube's opposed faces are farther apart than the hand's widest pinch (145 mm) less the seeds' spare:
    no pinch seed, and the failure says why with both widths; a 60 mm tetrahedron has no opposed faces at all."""
    from synergrasp.planner import widest_pinch

    cube = so.from_mesh(trimesh.creation.box((150.0, 150.0, 150.0)), name="cube", cache=False)
    r = plan(cube, "precision", restarts=2, executable_reach=False)
    assert not r.success and all(a["kind"] == "direction" for a in r.attempts)
    assert 140.0 < widest_pinch(hand) < 150.0
    assert (f"its opposed surfaces are at least 150 mm apart, and the thumb and the index and middle fingertips open "
            f"at most {widest_pinch(hand):.0f} mm apart") in r.reason
    corners = 60.0 * np.array([[1.0, 1.0, 1.0], [1.0, -1.0, -1.0], [-1.0, 1.0, -1.0], [-1.0, -1.0, 1.0]]) / np.sqrt(8)
    tetra = so.from_mesh(trimesh.convex.convex_hull(corners), name="tetrahedron", cache=False)
    r = plan(tetra, "precision", restarts=2, executable_reach=False)
    assert not r.success and "no two points of its surface face each other" in r.reason
    given = plan(cube, "precision", executable_reach=False, u0=plan(cube, "precision", restarts=1).attempts[0]["start"])
    assert not given.success and "too wide" not in given.reason  # a given start: no seeds were drawn


def test_a_failed_power_plan_says_when_the_fingers_did_not_close_around_the_object():
    """A 25 mm ball is too small for the closed fingers: most power attempts end with every phalanx far from it, and
    the failure says how far; one whose iterations ran out near the ellipsoid does not."""
    ball = so.from_mesh(trimesh.creation.icosphere(subdivisions=3, radius=12.5), name="25 mm ball", cache=False)
    r = plan(ball, "power", restarts=6, executable_reach=False)
    nearest = [min(a["status"][-1][:-2]) for a in r.attempts]
    assert not r.success and sum(d > 5.0 for d in nearest) > 3
    assert f"in {sum(d > 5.0 for d in nearest)} of them no phalanx ended within 5 mm of the object" in r.reason
    assert "the fingers did not close around it" in r.reason
    short = plan(so.ellipsoid(), "power", max_iter=3)
    assert not short.success and "did not close" not in short.reason


def test_a_failed_power_plan_says_when_no_wrap_pose_had_three_phalanges_near_the_object():
    """With the palm on a 20 mm ball no phalanx comes near it: the wrap seeds the plan tried say so; the
    ellipsoid's first wrap seed has three, and a plan stopped after it does not."""
    ball = so.from_mesh(trimesh.creation.icosphere(subdivisions=3, radius=10.0), name="20 mm ball", cache=False)
    r = plan(ball, "power", restarts=4, executable_reach=False)
    touching = [a["touching"] for a in r.attempts if a["kind"] == "wrap"]
    assert not r.success and len(touching) == 4 and max(touching) <= 2
    assert "came within 5 mm of its surface in the wrap poses tried" in r.reason
    assert "may not be able to wrap it (a precision grasp may hold it)" in r.reason
    short = plan(so.ellipsoid(), "power", max_iter=3)
    assert not short.success and short.attempts[0]["kind"] == "wrap" and short.attempts[0]["touching"] >= 3
    assert "wrap poses tried" not in short.reason


def test_a_plan_ended_before_its_first_step_says_that_and_nothing_of_the_object():
    """With time_limit=0.01 the power plan's reason said that no wrap pose was free of the cup and that the fingers did
    not close around it: its time had ended the wrap poses' screen and the attempt before its first step. A plan that
    its time limit ends says so first, with the backend when it is not the default (a cvxpy plan of a user's object
    ran out of the default 10 s in one attempt, and its reason spoke of the object alone)."""
    for grasp, backend in (("precision", "native"), ("power", "highs")):
        r = plan(so.cup(), grasp, time_limit=1e-6, backend=backend)
        assert not r.success and r.total_iterations == 0
        assert "; the plan's time limit (time_limit = 1e-06 s) ended it after 1 attempt(s) and 0 iterations, before " \
               "its iterations ran out (max_iter = 1500): a longer time_limit (None for none)" in r.reason
        assert ("(None for none) or a faster LP backend than highs lets it try more" in r.reason) == (backend == "highs")
        assert r.reason.endswith("; no attempt made a step, so none tells anything of the object")
        assert "wrap pose" not in r.reason and "did not close" not in r.reason
    r = plan(so.cup(), "precision", max_iter=2)  # its iterations ran out, not its time
    assert not r.success and "time limit" not in r.reason and "ran out before the first step" not in r.reason


def test_a_failed_power_plan_points_to_a_precision_grasp_only_where_a_pinch_spans_the_object():
    """A 155 mm cube is wider than the thumb and fingertips open (145 mm): its failed power plan does not suggest a
    precision grasp, which its precision plan has no pinch for (it did)."""
    cube = so.from_mesh(trimesh.creation.box((155.0, 155.0, 155.0)), name="155 mm cube", cache=False)
    r = plan(cube, "power", max_iter=60)
    assert not r.success and "may not be able to wrap it" in r.reason and "precision" not in r.reason


def test_a_failed_power_plan_of_an_object_too_small_for_a_pinch_says_so():
    """A 3 mm cube's power plan pointed to a precision grasp, which is refused for it: it now says the cube is thinner
    than a pinch can hold."""
    cube = so.from_mesh(trimesh.creation.box((3.0, 3.0, 3.0)), name="3 mm cube", cache=False)
    with pytest.raises(ValueError, match="too small for a pinch"):
        plan(cube, "precision")
    r = plan(cube, "power", restarts=4, executable_reach=False)
    assert not r.success and "may not be able to wrap it" in r.reason and "a precision grasp may hold it" not in r.reason
    assert "it is at most 3 mm across, thinner than a pinch of the thumb and the index and middle fingertips can " \
           "hold (6 mm), so a precision grasp is refused too" in r.reason


def test_a_30_mm_ball_has_a_power_grasp_with_the_palm_on_it():
    """The ball touches the palm's face between its nine skin points; the face point sees it (with the nine points
    alone every wrap stalled and the plan failed; a ball this small is at the edge of a power grasp's reach, and the
    ninth attempt finds it)."""
    ball = so.from_mesh(trimesh.creation.icosphere(subdivisions=3, radius=15.0), name="30 mm ball", cache=False)
    r = plan(ball, "power", restarts=10, executable_reach=False)
    assert r.success and "P" in r.contact_labels and r.final_q < -0.01


def test_a_sheet_is_refused_as_too_thin_without_a_units_hint():
    """A card 85 mm long and 1 mm thick is in plausible units: the message says it is too thin, not "metres?"."""
    card = so.from_mesh(trimesh.creation.box((85.0, 54.0, 1.0)), name="card", cache=False)
    with pytest.raises(ValueError, match="card is too thin to grasp: it is 1 mm thin.*85 mm long") as info:
        plan(card, "precision")
    assert "scale=" not in str(info.value)


def test_how_an_object_is_turned_does_not_decide_whether_it_is_refused():
    """The refusals read the object's smallest width, not its bounding box: a 60 mm thick box turned by 45 degrees
    about two axes spans 292 mm along every axis, and was refused as too large for the hand; a card turned so was
    planned (its box is 40 mm thick)."""
    turn = trimesh.transformations.euler_matrix(np.pi / 4, np.pi / 4, 0.0)
    box = so.from_mesh(trimesh.creation.box((60.0, 200.0, 300.0)), name="box", cache=False).transformed(turn)
    assert box.extents.min() > hand_opening(SynergyHand.default()) and box.width == pytest.approx(60.0)
    assert plan(box, "precision", max_iter=2).total_iterations > 0  # planned, not refused
    card = so.from_mesh(trimesh.creation.box((85.0, 54.0, 1.0)), name="card", cache=False).transformed(turn)
    assert card.extents.min() > 30.0
    with pytest.raises(ValueError, match="card is too thin to grasp: it is 1 mm thin"):
        plan(card, "precision")
    rng = np.random.default_rng(0)
    for k in range(5):  # the width of a turned box: its thinnest side, whatever the turn
        turned = box.transformed(trimesh.transformations.random_rotation_matrix(rng.random(3)))
        assert turned.width == pytest.approx(60.0, abs=1e-9)


def test_an_object_the_hand_cannot_hold():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        huge = so.ellipsoid(300.0, 300.0, 300.0)
    with pytest.raises(sg.planner.ObjectRefused, match="too large for the hand"):  # a ValueError of its own kind
        plan(huge, "precision")


def test_the_width_that_decides_a_refusal_is_the_objects_own():
    """A concave object's pieces stick out of it by a few mm: a pot 158 mm across with a handle read 161 mm on its
    pieces and was refused by the hand's 160 mm opening, with a hint to check its units. The width is now measured on
    the mesh (here a 156 mm box whose piece is 164 mm wide), and a refusal of an object of plausible size says to use a
    larger hand, not to check the units."""
    opening = hand_opening(SynergyHand.default())
    mesh, piece = trimesh.creation.box((156.0, 156.0, 200.0)), trimesh.creation.box((164.0, 164.0, 204.0)).vertices
    pot = so.GraspObject([piece], mesh=mesh, name="pot")
    assert so.GraspObject([piece]).width == pytest.approx(164.0) and pot.width == pytest.approx(156.0)
    assert pot.width < opening < 164.0
    assert plan(pot, "power", max_iter=1, executable_reach=False).total_iterations >= 0  # planned, not refused
    wide = so.from_mesh(trimesh.creation.box((170.0, 200.0, 200.0)), name="crate", cache=False)
    with pytest.raises(sg.planner.ObjectRefused, match="170 mm but the hand opens at most 16. mm.*Use a larger hand") as info:
        plan(wide, "power")
    assert "units" not in str(info.value)


def test_an_approach_of_any_magnitude_is_its_direction(hand, ellipsoid):
    """1e300 and 1e-10 times a direction give that direction's start, without an overflow or a refusal."""
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        starts_of = [start_configuration(hand, ellipsoid, k * np.array([1.0, 1.0, 0.0])) for k in (1e300, 1.0, 1e-10)]
    assert all(np.array_equal(s, starts_of[1]) for s in starts_of)
    with pytest.raises(ValueError, match="approach must be a non-zero direction"):
        start_configuration(hand, ellipsoid, (0.0, 0.0, 0.0))


def test_a_success_says_the_q_it_was_accepted_on_where_it_differs_from_g_q():
    """A 70 mm ball's piece is its mesh's hull simplified to 256 vertices (up to 0.7 mm inside the mesh), so its grasps'
    Q on the true surface differs from g_Q on the piece (by 0.02-0.03 here): the reason gives both (it gave g_Q alone,
    which read as a grasp with no margin where g_Q was near 0)."""
    ball = sg.objects.from_mesh(trimesh.creation.icosphere(subdivisions=3, radius=35.0), name="ball", cache=False)
    for grasp in ("precision", "power"):
        r = sg.plan(ball, grasp)
        assert r.success and r.surface_q < -0.01
        assert f"g_Q = {r.final_q:.4f}" in r.reason
        assert f"{r.surface_q:.4f}" != f"{r.final_q:.4f}" and f"Q on the true surface {r.surface_q:.4f}" in r.reason
    goblet = sg.plan(sg.objects.get("goblet"), "precision")  # the same Q both ways: said once
    assert f"{goblet.surface_q:.4f}" == f"{goblet.final_q:.4f}" and "true surface" not in goblet.reason
