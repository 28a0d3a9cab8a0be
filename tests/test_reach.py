"""The executable reach: dense clearance checks, the repaired approach, and the plan's path, checked independently.

Bad input of these entry points is in the catalogue (tests/catalogue.py).

The independent reference is ``benchmarks/reach_sampling.py``: sample points on the capsule axes and
the palm box's faces against the object's true mesh with trimesh (no fcl, no convex pieces).
"""

import csv
import importlib.util
import itertools
import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import trimesh
from scipy.spatial.transform import Rotation

import synergrasp as sg
import synergrasp.objects as so
from synergrasp.physics import PINCH_Z
from synergrasp.planner import (HandClearance, PlanResult, clearance_labels, executable_reach, hand_clearance,
                                open_synergies, path_clearance, retreat_directions, widest_opening)

_SPEC = importlib.util.spec_from_file_location(
    "reach_sampling", Path(__file__).resolve().parents[1] / "benchmarks" / "reach_sampling.py")
reach_sampling = importlib.util.module_from_spec(_SPEC)
_SPEC.loader.exec_module(reach_sampling)
sampled_clearance = reach_sampling.sampled_clearance

HAND = sg.SynergyHand.default()
TOLERANCE = 3.0


# ---------------------------------------------------------------------- scenes built by construction


def tips(z):
    """Centres of the thumb's and index's round tips at synergies z (palm frame)."""
    geo = HAND.segments(np.r_[np.zeros(6), z])
    last = {label[0]: ends[1] for label, ends in zip(geo.labels, geo.capsules)}
    return last["T"], last["I"]


def pinch_synergies(width, gap=1.0):
    """Synergies whose thumb and index tips leave ``gap`` mm either side of a plate ``width`` mm thick."""
    target = width + 2.0 * (HAND.finger_radius + gap)
    closed, open_ = np.array([1.0, -0.8]), np.array(PINCH_Z)  # tips 18 mm and 78 mm apart
    for _ in range(60):
        mid = 0.5 * (closed + open_)
        t, i = tips(mid)
        closed, open_ = (mid, open_) if np.linalg.norm(i - t) < target else (closed, mid)
    return 0.5 * (closed + open_)


def pinch_pose(z, axis, normal, centre):
    """The configuration whose thumb-to-index line is ``axis``, palm normal towards ``normal``, tips centred on ``centre``."""
    t, i = tips(z)
    a_loc = (i - t) / np.linalg.norm(i - t)
    m_loc = np.array([0.0, 0.0, 1.0]) - a_loc[2] * a_loc
    a_w = np.asarray(axis, float)
    m_w = np.asarray(normal, float) - np.dot(normal, a_w) * a_w
    frames = [np.c_[a, m / np.linalg.norm(m), np.cross(a, m / np.linalg.norm(m))] for a, m in ((a_loc, m_loc), (a_w, m_w))]
    rot = frames[1] @ frames[0].T
    return np.r_[np.asarray(centre, float) - rot @ ((t + i) / 2.0), Rotation.from_matrix(rot).as_euler("XYZ"), z]


@pytest.fixture(scope="module")
def plate():
    """A 4 mm plate, 120 x 120 mm, its edge on the plane x = 0; the thumb and index pinch the edge from x < 0."""
    mesh = trimesh.creation.box((120.0, 120.0, 4.0))
    mesh.apply_translation([60.0, 0.0, 0.0])
    obj = so.from_mesh(mesh, cache=False)
    return obj, pinch_pose(pinch_synergies(4.0), (0.0, 0.0, 1.0), (1.0, 0.0, 0.0), (6.0, 0.0, 0.0))


@pytest.fixture(scope="module")
def hollow_cup():
    """A cup with a 4 mm wall (inner radius 34 mm, 80 mm high), its rim pinched from above: thumb outside, index inside."""
    sides, r_in, r_out, height = 48, 34.0, 38.0, 80.0
    profile = np.array([[0.0, 0.0], [r_out, 0.0], [r_out, height], [r_in, height], [r_in, 5.0], [0.0, 5.0]])
    mesh = trimesh.creation.revolve(profile, sections=sides)
    angle = 2 * np.pi * np.arange(sides + 1) / sides

    def ring(r, z):
        return np.c_[r * np.cos(angle), r * np.sin(angle), np.full(sides + 1, z)]

    pieces = [np.vstack([ring(r_out, 0.0)[:-1], ring(r_out, 5.0)[:-1]])]  # the bottom
    pieces += [np.vstack([ring(r, z)[k : k + 2] for r in (r_in, r_out) for z in (5.0, height)]) for k in range(sides)]
    obj = so.GraspObject(pieces, name="hollow cup", mesh=mesh)
    return obj, pinch_pose(pinch_synergies(r_out - r_in), (-1.0, 0.0, 0.0), (0.0, 0.0, -1.0), (36.0, 0.0, 72.0))


def independent_along(obj, path, step=1.0):
    """The independent clearance of every row of ``path`` and of poses between rows (the hand moving <= ``step`` mm)."""
    values = [sampled_clearance(HAND, obj.mesh, path[0]).min()]
    for a, b in zip(path[:-1], path[1:]):
        ends = [np.vstack([g.capsules.reshape(-1, 3), g.palm_corners]) for g in (HAND.segments(a), HAND.segments(b))]
        n = max(1, int(np.ceil(np.linalg.norm(ends[1] - ends[0], axis=1).max() / step)))
        values += [sampled_clearance(HAND, obj.mesh, a + (b - a) * k / n).min() for k in range(1, n + 1)]
    return np.array(values)


# ---------------------------------------------------------------------- the clearance


def near_poses(obj, count, rng, low=-2.5, high=8.0):
    """Random configurations whose clearance from obj is in [low, high] mm (the hand moved in from afar)."""
    check, poses = HandClearance(HAND, obj), []
    while len(poses) < count:
        direction = rng.normal(size=3)
        direction /= np.linalg.norm(direction)
        u = np.r_[obj.center + 250.0 * direction, rng.uniform(-np.pi, np.pi, 3), rng.uniform(-1.0, 1.0, 2)]
        target = rng.uniform(low, high)
        far, near = 0.0, 250.0  # moved this far towards the centre: clearance(far) > target > clearance(near)
        if check.at(np.r_[obj.center, u[3:]])[0] > target:
            continue
        for _ in range(40):
            mid = 0.5 * (far + near)
            pose = u.copy()
            pose[:3] -= mid * direction
            far, near = (mid, near) if check.at(pose)[0] > target else (far, mid)
        pose = u.copy()
        pose[:3] -= far * direction
        poses.append(pose)
    return poses


@pytest.mark.parametrize("name", ["bell", "goblet", "hollow cup"])
def test_the_clearance_equals_an_independent_dense_check(name, hollow_cup, rng):
    """fcl's signed distance of every capsule and of the palm box within 0.5 mm of trimesh on sampled points."""
    obj = hollow_cup[0] if name == "hollow cup" else so.get(name)
    compared = 0
    for u in near_poses(obj, 5, rng):
        ours = hand_clearance(HAND, obj, u)
        theirs = sampled_clearance(HAND, obj.mesh, u)
        both = np.isfinite(theirs) & (ours > -TOLERANCE)  # deeper, fcl's depth (a translation) is another measure
        np.testing.assert_allclose(ours[both], theirs[both], atol=0.5)
        compared += both.sum()
        assert ours.min() <= 8.0 + 1e-6  # the pose is near the object
    assert compared >= 15


def test_capsule_gradients_match_finite_differences(rng):
    """On a box (large faces: the distance's second derivative is small, where a fine mesh's facets make it jump)."""
    obj = so.from_mesh(trimesh.creation.box((60.0, 80.0, 100.0)), cache=False)
    check = HandClearance(HAND, obj)
    compared = 0
    for u in near_poses(obj, 4, rng, low=-2.0, high=6.0):
        shapes, distances, grad = check.gradients(u, 10.0)
        np.testing.assert_allclose(distances, check.shapes(u)[shapes], atol=1e-9)
        h = np.r_[np.full(3, 1e-2), np.full(5, 1e-4)]  # hand points move ~0.01 mm: above fcl's 1e-6 tolerance
        for j in range(8):
            step = np.zeros(8)
            step[j] = h[j]
            fd = (check.shapes(u + step)[shapes] - check.shapes(u - step)[shapes]) / (2 * h[j])
            scale = np.maximum(np.abs(fd), 1.0)
            assert np.all(np.abs(grad[:, j] - fd) <= 1e-3 * scale), (j, grad[:, j], fd)
        compared += len(shapes)
    assert compared >= 4


def test_clearance_labels_and_the_palm():
    labels = clearance_labels(HAND)
    assert labels == HAND.segments(np.zeros(8)).labels + ["palm"]
    # the palm box alone near a large plane: its clearance is its face's height above it
    floor = so.from_mesh(trimesh.creation.box((400.0, 400.0, 10.0)), cache=False)  # top face z = 5
    u = np.array([0.0, 0.0, 200.0, np.pi, 0.0, 0.0, -1.0, 1.0])  # palm down: the 20 mm box spans z = 190 to 210
    d = hand_clearance(HAND, floor, u)
    assert d[-1] == pytest.approx(190.0 - 5.0, abs=1e-6) and d.min() < d[-1]  # the fingers reach lower


def test_a_plate_crossed_between_two_clear_poses_is_seen(plate):
    """The hand moved through the plate along its normal: both ends clear, the dense check finds the crossing."""
    obj, u = plate
    path = np.array([u + [0.0, 0.0, -200.0, 0, 0, 0, 0, 0], u + [0.0, 0.0, 200.0, 0, 0, 0, 0, 0]])
    check = path_clearance(HAND, obj, path)
    assert check.clearance[0] > 10.0 and check.clearance[-1] > 10.0 and check.given[[0, -1]].all()
    assert check.depth > TOLERANCE and check.complete
    assert sampled_clearance(HAND, obj.mesh, check.path[check.deepest]).min() < -TOLERANCE  # independently inside
    # near the plate the checked poses are dense: the hand moves at most resolution * radius between them
    near = (check.clearance[:-1] < 0.0) | (check.clearance[1:] < 0.0)
    moves = [np.linalg.norm(HAND.segments(b).capsules - HAND.segments(a).capsules, axis=-1).max()
             for a, b in zip(check.path[:-1][near], check.path[1:][near])]
    assert max(moves) <= 0.25 * HAND.finger_radius * 1.01
    # an early stop ends at the first pose found below the floor
    early = path_clearance(HAND, obj, path, stop_below=0.0)
    assert not early.complete and early.clearance[-1] < 0.0 and (early.clearance[:-1] >= 0.0).all()


# ---------------------------------------------------------------------- the repaired approach


def test_a_thin_plate_approached_edge_on_is_not_crossed(plate):
    obj, u = plate
    reach = executable_reach(HAND, obj, u)
    assert reach.collision_free and reach.source == "approach" and reach.depth <= TOLERANCE
    assert np.array_equal(reach.path[-1], u) and np.array_equal(reach.path[0], reach.pregrasp)
    assert reach.clearance[0] >= 10.0  # the pre-grasp clears the plate by the margin
    assert abs(reach.direction[2]) < 0.2  # it leaves in the plate's plane, off its edge
    independent = independent_along(obj, reach.path)
    assert independent.min() >= -TOLERANCE
    assert independent.min() == pytest.approx(reach.clearance.min(), abs=0.5)


def test_a_cup_approached_from_above_does_not_pass_through_its_wall(hollow_cup):
    obj, u = hollow_cup
    reach = executable_reach(HAND, obj, u)
    assert reach.collision_free and reach.clearance[0] >= 10.0
    assert reach.direction[2] > 0.7  # the pre-grasp is above the rim
    independent = independent_along(obj, reach.path)
    assert independent.min() >= -TOLERANCE
    assert independent.min() == pytest.approx(reach.clearance.min(), abs=0.5)
    # the same pinch reached from the side passes through the wall, and the check says so
    side = path_clearance(HAND, obj, [u + [-80.0, 0, 0, 0, 0, 0, 0, 0], u])
    assert side.depth > TOLERANCE and sampled_clearance(HAND, obj.mesh, side.path[side.deepest]).min() < -TOLERANCE


@pytest.fixture(scope="module")
def boxed_in(plate):
    """The plate's pinch inside a closed box whose walls are 3 mm from the hand's shapes."""
    _, u = plate
    geo = HAND.segments(u)
    points = np.vstack([geo.capsules.reshape(-1, 3), geo.palm_corners])
    lo, hi = points.min(axis=0) - HAND.finger_radius - 3.0, points.max(axis=0) + HAND.finger_radius + 3.0
    walls = []
    for i, side in itertools.product(range(3), (0, 1)):
        a, b = lo - 5.0, hi + 5.0
        if side == 0:
            b[i] = lo[i]
        else:
            a[i] = hi[i]
        walls.append(np.array(list(itertools.product(*zip(a, b)))))
    return so.GraspObject(walls, name="closed box"), u


@pytest.fixture(scope="module")
def turned_box_wrap():
    """A power grasp of a turned box (its planned u kept here) whose fingers wrap round the box."""
    turn = Rotation.from_quat([0.770622423659, -0.290229664652, -0.250575404063, -0.50903810151])
    mesh = trimesh.creation.box((80.0, 70.0, 50.0))
    mesh.apply_transform(np.r_[np.c_[turn.as_matrix(), np.zeros(3)], [[0.0, 0.0, 0.0, 1.0]]])
    obj = so.from_mesh(mesh, name="turned box", cache=False)
    return obj, np.array([46.241455, -27.591633, 26.487351, -1.830535, -0.226936, 1.507337, 0.49575, 1.0])


def test_a_wrap_the_open_hand_cannot_approach_is_reached_closing_on_the_way(turned_box_wrap):
    """No pre-grasp's approach with the open hand (the grasp's synergies cannot open much: one is at its limit) stays
    within the tolerance, and the approach that closes the hand on the way does."""
    obj, u = turned_box_wrap
    reach = executable_reach(HAND, obj, u)
    assert reach.collision_free and reach.source == "closing approach" and "closing the hand" in reach.reason
    assert np.array_equal(reach.path[0], reach.pregrasp) and np.array_equal(reach.path[-1], u)
    # one straight line in u: every row is on the segment from the pre-grasp to the grasp, in order
    along = (reach.path - reach.pregrasp) @ (u - reach.pregrasp) / np.sum((u - reach.pregrasp) ** 2)
    assert np.allclose(reach.path, reach.pregrasp + along[:, None] * (u - reach.pregrasp), atol=1e-9)
    assert (np.diff(along) > 0).all()
    # independently of fcl and the pieces: the closing approach stays within the tolerance of the true mesh ...
    assert independent_along(obj, reach.path).min() >= -TOLERANCE - 0.5
    # ... where the open hand's approach from the same pre-grasp, then its close, goes deeper than it
    classic = np.array([reach.pregrasp, np.r_[u[:6], reach.pregrasp[6:]], u])
    assert path_clearance(HAND, obj, classic).clearance.min() < -TOLERANCE
    assert independent_along(obj, classic).min() < -TOLERANCE


def test_a_reach_that_cannot_be_made_collision_free_is_reported_with_its_depth_and_shape(boxed_in):
    obj, u = boxed_in
    reach = executable_reach(HAND, obj, u, margin=20.0, budget=12)  # nowhere inside is 20 mm from every wall
    # the whole budget: 12 pre-grasps, each with its approach and its closing approach
    assert not reach.collision_free and reach.grasp_depth == 0.0 and reach.candidates == 24
    assert reach.depth > TOLERANCE and reach.depth == pytest.approx(-reach.clearance.min())
    assert reach.deepest in clearance_labels(HAND) and reach.closest[reach.deepest_row] == reach.deepest
    assert f"{reach.deepest} {reach.depth:.1f} mm deep" in reach.reason and "not collision-free" in reach.reason
    assert hand_clearance(HAND, obj, reach.path[reach.deepest_row]).min() == pytest.approx(-reach.depth)
    # the path reported is checked whole: it ends at the grasp (a check stopped at its first floor ended short of it)
    np.testing.assert_array_equal(reach.path[-1], u)
    assert len(reach.clearance) == len(reach.path)


def test_a_reach_that_cannot_be_made_collision_free_is_the_least_deep_of_its_candidates(boxed_in):
    """More candidates can only find a shallower best path: the one returned is the least deep of those checked."""
    obj, u = boxed_in
    depths = [executable_reach(HAND, obj, u, margin=20.0, budget=b).depth for b in (1, 3, 4, 12)]
    assert all(later <= earlier + 1e-6 for earlier, later in zip(depths, depths[1:])), depths
    assert depths[-1] < depths[0] - 1.0  # (the fourth pre-grasp's approach is 2 mm shallower than the first's)


def test_a_path_from_no_pre_grasp_is_never_collision_free(turned_box_wrap):
    """With max_retreat too short for the margin, the best path starts at the grasp, within the tolerance of the box
    (2.2 mm in it): not a reach from free space, so not collision-free, and the reason says why."""
    obj, u = turned_box_wrap
    reach = executable_reach(HAND, obj, u, margin=10.0, max_retreat=12.0)
    assert np.isnan(reach.retreat) and reach.clearance.min() >= -TOLERANCE and reach.clearance[0] < 10.0
    assert not reach.collision_free and reach.reason.startswith("not collision-free: no path starts clear")
    assert "no pre-grasp clears the object by the margin of 10 mm within max_retreat 12 mm" in reach.reason


def test_a_margin_no_pre_grasp_clears_is_said(plate):
    """With a margin of 100 mm no retreat within max_retreat (100 mm) clears the plate by it: the reach still comes
    back (the best candidate), and its reason says the margin was not met and how far the path starts."""
    obj, u = plate
    reach = executable_reach(HAND, obj, u, margin=100.0, max_retreat=100.0)
    assert np.isnan(reach.retreat) and reach.clearance[0] < 100.0
    assert f"no pre-grasp clears the object by the margin of 100 mm within max_retreat 100 mm: the path starts " \
           f"{reach.clearance[0]:.1f} mm from it" in reach.reason
    assert "margin" not in executable_reach(HAND, obj, u).reason  # met: nothing said


def test_a_grasp_deeper_than_the_tolerance_is_never_collision_free(plate):
    obj, u = plate
    sunk = u + [0.0, 0.0, 7.0, 0, 0, 0, 0, 0]  # the fingers on the plate's top face pressed 7 mm into it
    reach = executable_reach(HAND, obj, sunk)
    independent = sampled_clearance(HAND, obj.mesh, sunk)
    assert not reach.collision_free and reach.grasp_shape == clearance_labels(HAND)[int(np.argmin(independent))]
    assert reach.grasp_depth == pytest.approx(-independent.min(), abs=0.5)
    assert reach.depth >= reach.grasp_depth > TOLERANCE
    assert f"the grasp itself penetrates the object, {reach.grasp_shape} {reach.grasp_depth:.1f} mm deep" in reach.reason


def test_a_palm_deep_at_the_grasp_does_not_let_the_fingers_sink_on_the_way(plate):
    """The plate plus a block through the palm box: the palm may be as deep as at the grasp, the capsules only 3 mm."""
    obj, u = plate
    geo = HAND.segments(u)
    block = geo.palm_center + (np.array(list(itertools.product((-8.0, 8.0), repeat=3))) @ geo.palm_axes.T)
    both = so.GraspObject([obj.convex[0].vertices, block], name="plate and block")
    reach = executable_reach(HAND, both, u)
    assert not reach.collision_free and reach.grasp_shape == "palm" and reach.grasp_depth > 10.0
    capsules = np.array([hand_clearance(HAND, both, p)[:-1].min() for p in reach.path])
    assert capsules.min() >= -TOLERANCE
    palm = np.array([hand_clearance(HAND, both, p)[-1] for p in reach.path])
    assert palm.min() >= -reach.grasp_depth - TOLERANCE


def test_a_collision_free_trajectory_is_used_as_it_is_and_one_through_the_object_is_not(plate):
    obj, u = plate
    repaired = executable_reach(HAND, obj, u)
    as_is = executable_reach(HAND, obj, u, trajectory=repaired.path[::3])
    assert as_is.source == "trajectory" and as_is.collision_free and np.array_equal(as_is.path[-1], u)
    through = np.array([u + [0.0, 0.0, -80.0, 0, 0, 0, 0, 0], u])
    other = executable_reach(HAND, obj, u, trajectory=through)
    assert other.source == "approach" and other.collision_free and other.candidates >= 2


def test_the_opening_and_the_retreat_directions(plate):
    obj, u = plate
    check = HandClearance(HAND, obj)
    assert widest_opening(HAND).tolist() == [-1.0, 1.0]
    z = open_synergies(HAND, check, u, 10.0)
    assert check.at(np.r_[u[:6], z])[0] >= check.at(u)[0]  # opening never lowers the clearance
    assert np.all((z >= HAND.synergy_limits[:, 0]) & (z <= HAND.synergy_limits[:, 1]))
    normals = np.array([[0.0, 0.0, 1.0], [0.0, 0.0, -1.0]])  # a pinch: opposed normals
    directions = retreat_directions(HAND, u, u[6:], normals)
    np.testing.assert_allclose(np.linalg.norm(directions, axis=1), 1.0)
    assert abs(directions[1] @ normals[0]) < 1e-9  # slid back: in the plate's plane
    back = -Rotation.from_euler("XYZ", u[3:6]).as_matrix()[:, 2]
    np.testing.assert_allclose(directions[0], back, atol=1e-12)


# ---------------------------------------------------------------------- in the planner


@pytest.fixture(scope="module")
def cup_plan():
    return sg.plan(so.cup(), "precision")


def test_a_plan_returns_its_executable_reach(cup_plan):
    r, obj = cup_plan, so.cup()
    assert r.success and r.path.shape[1] == 8 and np.array_equal(r.path[-1], r.u)
    assert np.array_equal(r.path[0], r.pregrasp) and r.clearance[0] >= 10.0
    assert r.collision_free == bool(r.clearance.min() >= -r.options["max_penetration"])
    assert r.reach["tolerance"] == r.options["max_penetration"] and r.reach["source"] == "approach"
    check = HandClearance(HAND, obj)
    np.testing.assert_allclose([check.at(p)[0] for p in r.path], r.clearance, atol=1e-9)
    shallow = [p for p, c in zip(r.path, r.clearance) if c < 10.0]
    for p in shallow[-3:]:
        ours, theirs = hand_clearance(HAND, obj, p), sampled_clearance(HAND, obj.mesh, p)
        both = np.isfinite(theirs) & (ours > -TOLERANCE)
        np.testing.assert_allclose(ours[both], theirs[both], atol=0.5)
    json.dumps(r.reach)  # the summary is JSON as it is


def test_a_plan_that_allows_no_penetration_gets_a_reach_held_to_none():
    """max_penetration = 0 (no phalanx or palm box into the object) is a valid option, and the executable reach takes
    it as its tolerance."""
    r = sg.plan(so.ellipsoid(), "precision", max_penetration=0.0)
    assert r.success and r.reach["tolerance"] == 0.0
    assert r.collision_free == bool(r.clearance.min() >= 0.0)


def test_a_replay_refuses_the_plan_of_another_object(cup_plan):
    """replay_reach checks a result against the object and the hand as sg.validate does."""
    with pytest.raises(ValueError, match=r"planned for another object \('cup'\)"):
        sg.replay_reach(cup_plan, so.ellipsoid())


def test_the_reach_survives_a_save_and_load(cup_plan, tmp_path):
    back = PlanResult.load(cup_plan.save(tmp_path / "plan.json"))
    for name in ("pregrasp", "path", "clearance"):
        np.testing.assert_array_equal(getattr(back, name), getattr(cup_plan, name))
    assert back.collision_free == cup_plan.collision_free and back.reach == cup_plan.reach


def test_a_plan_without_a_grasp_or_without_the_reach_has_no_path(tmp_path):
    capped = sg.plan(so.ellipsoid(), "precision", max_iter=3)
    skipped = sg.plan(so.ellipsoid(), "precision", executable_reach=False)
    assert not capped.success and skipped.success
    for r in (capped, skipped):
        assert r.path.shape == (0, 8) and r.clearance.shape == (0,) and np.isnan(r.pregrasp).all()
        assert not r.collision_free and r.reach == {}
        back = PlanResult.load(r.save(tmp_path / "plan.json"))
        assert back.path.shape == (0, 8) and np.isnan(back.pregrasp).all()
    with pytest.raises(ValueError, match="executable_reach must be True or False"):
        sg.plan(so.ellipsoid(), "precision", executable_reach="yes")


# ---------------------------------------------------------------------- replayed in MuJoCo


def test_a_replayed_reach_leaves_the_object_where_a_path_through_it_does_not(plate):
    """The plate free in MuJoCo: the repaired reach does not move it before closing; a path through it knocks it away."""
    obj, u = plate
    reach = executable_reach(HAND, obj, u)
    replay = sg.replay_reach(reach.path, obj)
    assert replay.outcome == "done" and len(replay.moved) == len(reach.path)
    assert replay.moved_before_closed < 1.0 and replay.turned_before_closed < 1.0
    through = np.array([u + [0.0, 0.0, -200.0, 0, 0, 0, 0, 0], u])  # up through the plate, hand closed
    knocked = sg.replay_reach(through, obj)
    assert knocked.first_contact == 1 and (knocked.moved_before_closed > 5.0 or knocked.turned_before_closed > 10.0)


# ---------------------------------------------------------------------- the benchmark


def test_the_benchmark_runs_in_its_quick_mode(tmp_path):
    root = Path(__file__).resolve().parents[1]
    env = dict(os.environ, MPLBACKEND="Agg", PYTHONPATH=os.pathsep.join(filter(None, [str(root), os.environ.get("PYTHONPATH")])))
    proc = subprocess.run([sys.executable, str(root / "benchmarks" / "bench_reach.py"), "--quick", "--out", str(tmp_path)],
                          cwd=tmp_path, env=env, capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0 and "Traceback" not in proc.stderr, proc.stdout + proc.stderr
    rows = list(csv.DictReader((tmp_path / "reach.csv").open()))
    assert [(r["object"], r["grasp"]) for r in rows] == [("cup", "precision"), ("cup", "power")]
    for r in rows:  # the collision-free flag agrees with the independent check where the grasp itself is shallow
        deepest = max(float(r["depth_capsules"]), float(r["depth_palm"]))
        if float(r["grasp_depth"]) <= TOLERANCE:
            assert (r["collision_free"] == "True") == (deepest <= TOLERANCE + 0.5)
    assert "deepest point along the returned reach, capsules and palm (independent check)" in proc.stdout
    assert "the phalanx capsules alone: <= 3 mm in" in proc.stdout
    assert "plan time overhead of the repair: median" in proc.stdout


def test_a_long_path_through_a_plate_is_never_read_clear():
    """A hand crossing a 6 mm plate on a straight path 2e7 mm long: the bisection runs out of depth before it resolves
    the crossing, and the interval it could not show clear reads as the least clearance it can have (it read 37 mm,
    depth 0, complete: a collision reported clear)."""
    plate = so.from_mesh(trimesh.creation.box((6.0, 100.0, 100.0)), cache=False)
    across = np.array([0.0, 0.0, 0.0, 0.0, np.pi / 2, 0.0, 0.0, 0.0])
    assert hand_clearance(HAND, plate, across).min() == pytest.approx(-13.0, abs=0.5)  # the pose at the plate
    for half in (1e4, 1e6, 1e7):
        ends = np.array([across, across])
        ends[:, 0] = [-half + 50.0, half + 50.0]
        check = path_clearance(HAND, plate, ends)
        assert check.clearance.min() <= -13.0, half
