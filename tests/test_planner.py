"""The planner: status Jacobian, stop criteria, end-to-end plans verified independently."""

import warnings

import numpy as np
import pytest
import trimesh

import synergrasp as sg
import synergrasp.objects as so
from synergrasp.hand import SynergyHand
from synergrasp.planner import PlanResult, attempt_schedule, check_grasp, grasp_status, plan, power_schedule, start_configuration
from synergrasp.planner.core import sq_request
from synergrasp.planner import core
from synergrasp.planner.status import Status, capsule_rows, segment_distance

from .conftest import BACKENDS
from .test_quality import origin_strictly_inside


@pytest.fixture(scope="module")
def hand():
    return SynergyHand.default()


@pytest.fixture(scope="module")
def ellipsoid():
    return so.ellipsoid()


@pytest.fixture(scope="module")
def goblet_plan():
    return plan(so.goblet(), "precision")


def near_start(hand, obj, approach=(0.0, 1.0, 0.0), distance=110.0):
    return start_configuration(hand, obj, approach, distance) + np.r_[np.zeros(6), 0.1, -0.2]


@pytest.mark.parametrize("kind", ["precision", "power"])
def test_status_jacobian_matches_finite_differences(hand, ellipsoid, kind):
    u = near_start(hand, ellipsoid)
    smoothing = 5.0
    st = grasp_status(hand, ellipsoid, u, kind, smoothing=smoothing)
    h = np.r_[np.full(3, 1e-4), np.full(5, 1e-6)]
    for k in range(len(u)):
        up, um = u.copy(), u.copy()
        up[k] += h[k]
        um[k] -= h[k]
        fd = (grasp_status(hand, ellipsoid, up, kind, smoothing=smoothing).g
              - grasp_status(hand, ellipsoid, um, kind, smoothing=smoothing).g) / (2 * h[k])
        scale = np.maximum(np.abs(fd), 1e-3)
        assert np.all(np.abs(st.J[:, k] - fd) <= 1e-4 * scale + 1e-6), (k, st.J[:, k], fd)


def test_a_power_row_is_the_deepest_skin_point_of_its_segment(hand, ellipsoid, backend):
    u = near_start(hand, ellipsoid, distance=60.0)
    skin, palm, jac_skin, jac_palm = hand.skin_and_jacobian(u)
    rows = segment_distance(ellipsoid, skin, palm, jac_skin, jac_palm, backend)
    every = ellipsoid.contact_distance(skin.reshape(-1, 3), backend=backend).value.reshape(skin.shape[:2])
    np.testing.assert_allclose(rows.value[:-1], every.min(axis=1), atol=1e-6)
    np.testing.assert_allclose(rows.value[-1], ellipsoid.contact_distance(palm[None], backend=backend).value[0], atol=1e-6)
    # some phalanx dips in with its skin while its power point (the palmar middle) is still outside
    mid = every[:, 4]
    assert np.any((rows.value[:-1] < 0) & (mid > 0)) and (rows.value < 0).any()


def test_power_rows_see_a_phalanx_end_in_the_object(hand, ellipsoid):
    u = near_start(hand, ellipsoid, distance=60.0)
    st = grasp_status(hand, ellipsoid, u, "power")
    depth = ellipsoid.penetration(hand.segments(u).capsules, hand.finger_radius).depths
    assert (depth > 5.0).any() and np.all(st.g[:-2][depth > 5.0] < 0.0)  # a phalanx 5 mm deep reads as penetrating


def test_capsule_rows_see_a_phalanx_through_a_plate_and_match_finite_differences(hand):
    """Phalanges through an 8 mm plate read shallow at their skin points; their capsules' rows read the full depth."""
    plate = so.from_mesh(trimesh.creation.box((200.0, 200.0, 8.0)), cache=False)
    u = np.r_[np.zeros(3), 0.15, -0.1, 0.05, 0.3, -0.2]
    u[:3] = -hand.segments(u).capsules[4].mean(axis=0) + [0.0, 0.0, 1.5]  # the index's middle phalanx in the plate
    skin = grasp_status(hand, plate, u, "power")
    pen = plate.penetration(hand.segments(u).capsules, hand.finger_radius)
    st = capsule_rows(hand, plate, u, skin, pen)
    deeper = (pen.distances < 0) & (pen.distances < skin.g[:-2])
    assert deeper.sum() >= 3 and pen.distances[4] < -8.0 and deeper[4]
    np.testing.assert_array_equal(st.g[:-2][deeper], pen.distances[deeper])
    np.testing.assert_array_equal(st.g[:-2][~deeper], skin.g[:-2][~deeper])  # the others keep their skin rows
    np.testing.assert_array_equal(st.g[-2:], skin.g[-2:])
    rows = np.flatnonzero(deeper)
    h = np.r_[np.full(3, 1e-4), np.full(5, 1e-6)]
    for k in range(len(u)):
        up, um = u.copy(), u.copy()
        up[k] += h[k]
        um[k] -= h[k]
        at = lambda v: plate.penetration(hand.segments(v).capsules, hand.finger_radius).distances[rows]  # noqa: E731
        fd = (at(up) - at(um)) / (2 * h[k])
        np.testing.assert_allclose(st.J[rows, k], fd, rtol=1e-5, atol=1e-5 * np.abs(st.J).max())
    assert capsule_rows(hand, so.ellipsoid(), start_configuration(hand, so.ellipsoid()), skin) is skin  # nothing deeper


def test_an_attempt_watches_the_capsules_once_a_phalanx_was_too_deep(monkeypatch):
    """The ellipsoid's power attempt meets the criterion with a phalanx too deep, then watches the capsules."""
    obj = so.ellipsoid()
    calls = []
    rows = core.capsule_rows
    monkeypatch.setattr(core, "capsule_rows", lambda hand, o, u, st, pen=None: calls.append(pen) or rows(hand, o, u, st, pen))
    r = plan(obj, "power")
    verify(r, obj)
    assert len(calls) >= 2 and calls[0].depth > 3.0  # first when the criterion met a deep phalanx, then while wrapping
    calls.clear()
    plan(obj, "power", power_capsule_rows=False, max_iter=60)
    assert not calls


def test_a_power_attempt_holds_a_good_enough_sq(monkeypatch):
    """Below power_sq_hold the sQ row asks to keep g_sQ, not for sq_step less; above it, for sq_step less."""
    obj = so.ellipsoid()
    asked = []
    step = core.limited_step

    def spy(J, e, z, limits, first):
        asked.append(e[-1])  # the sQ row's (scaled) error: target - g_sQ
        return step(J, e, z, limits, first)

    monkeypatch.setattr(core, "limited_step", spy)
    r = plan(obj, "power", restarts=1, max_iter=60)
    sq = r.status[: len(asked), -1]
    held, pulled = sq < -0.05, sq >= -0.05
    assert held.any() and pulled.any()
    np.testing.assert_array_equal(np.asarray(asked)[held], 0.0)
    np.testing.assert_allclose(np.asarray(asked)[pulled], -0.1)
    asked.clear()
    r = plan(obj, "power", restarts=1, max_iter=60, power_sq_hold=None)
    assert np.all(np.asarray(asked)[r.status[: len(asked), -1] > -0.9] == pytest.approx(-0.1))


def test_power_starts_keep_every_phalanx_clear_of_the_object(hand):
    box = so.from_mesh(trimesh.creation.box((120.0, 120.0, 130.0)), cache=False)
    for direction, wide in power_schedule()[:6]:
        u = core._power_start(hand, box, direction, core.PlannerOptions(), np.array([-1.0, 1.0] if wide else [0.0, 1.0]), wide)
        geo = hand.segments(u)
        assert box.penetration(geo.capsules, geo.radius).distances.min() >= 5.0 - 1e-6


def fake_status(cp, sq=0.0):
    """A status whose points in contact (cP < 5) are spread evenly around a sphere's equator."""
    cp = np.asarray(cp, dtype=float)
    n = len(cp)
    t = np.zeros(n)
    t[cp < 5.0] = 2 * np.pi * np.arange((cp < 5.0).sum()) / max((cp < 5.0).sum(), 1)
    nearest = 40.0 * np.c_[np.cos(t), np.sin(t), np.zeros(n)]
    return Status(g=np.r_[cp, sq], J=np.zeros((n + 1, 8)), points=nearest, nearest=nearest, normals=-nearest / 40, lp_solves=0)


def test_precision_stop_criterion(ellipsoid):
    three = check_grasp(ellipsoid, fake_status([1.0, 2.0, 3.0, 30.0, 40.0]), "precision", palm_distance=lambda: 50.0)
    assert three.n_contacts == 3 and three.q < -0.1 and three.done  # 3 contacts need Q < -0.1
    assert not check_grasp(ellipsoid, fake_status([1.0, 2.0, 3.0, 30.0, 40.0]), "precision", palm_distance=lambda: 2.0).done  # palm touches
    def unneeded():
        raise AssertionError("the palm is checked only when the rest of the criterion holds")

    far = check_grasp(ellipsoid, fake_status([1.0, 2.0, 6.0, 30.0, 40.0]), "precision", palm_distance=unneeded)
    assert far.n_contacts == 2 and not far.done


def test_power_stop_criterion_needs_the_palm(ellipsoid):
    cp = np.full(16, 1.0)
    assert check_grasp(ellipsoid, fake_status(cp), "power").done
    cp[-1] = 9.0  # palm point P away from the object: not a power grasp
    chk = check_grasp(ellipsoid, fake_status(cp), "power")
    assert not chk.palm and not chk.done and chk.q < 0


def verify(result, obj):
    """Independent checks of a successful plan's final grasp."""
    assert result.success, result.reason
    W = sg.contact_wrenches(result.contact_points, result.contact_normals, center=obj.center, torque_scale=obj.torque_scale)
    assert origin_strictly_inside(W)
    on_surface = obj.contact_distance(result.contact_points).value
    assert np.abs(on_surface).max() < 1e-6
    assert result.penetration <= 3.0


def test_precision_plan_of_the_goblet(goblet_plan):
    r = goblet_plan
    verify(r, so.goblet())
    assert len(r.contact_points) >= 3 and "P" not in r.contact_labels
    assert all(label.endswith("0") for label in r.contact_labels)
    assert r.trajectory.shape == (r.iterations + 1, 8) and r.status.shape == (r.iterations + 1, 6)
    assert np.all(np.abs(r.trajectory[:, 6:]) <= 1.0)  # synergy limits
    assert r.final_q < 0 and r.lp_solves > r.iterations
    assert r.total_iterations == sum(a["iterations"] for a in r.attempts) >= r.iterations


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
    assert len(r.contact_points) >= 3 and "P" not in r.contact_labels
    assert r.total_iterations <= 600


def test_a_sphere_needs_the_stand_off():
    obj = so.ellipsoid(33.0, 33.0, 33.0)
    r = plan(obj, "precision")
    assert r.success and r.attempts[-1]["standoff"] > 0  # the fingertips land on the near side otherwise
    assert all(a["standoff"] == 0 for a in r.attempts[:2])


def test_a_contact_band_lets_the_fingertips_settle_on_a_round_object():
    t = np.linspace(0, np.pi, 25)
    orange = so.revolve(np.c_[37 * np.sin(t), 37 * (1 - np.cos(t))], name="orange")
    assert not plan(orange, "precision", restarts=1, contact_band=None).success  # all five at 3.5 mm: it stalls
    r = plan(orange, "precision", restarts=1, band_after=0)  # the band from the first attempt
    verify(r, orange)
    assert len(r.contact_points) >= 3 and "T0" in r.contact_labels
    assert [a["band"] for a in r.attempts] == [[1.0, 4.5]]


def test_a_failed_precision_schedule_is_tried_again_with_the_contact_band():
    t = np.linspace(0, np.pi, 25)
    orange = so.revolve(np.c_[37 * np.sin(t), 37 * (1 - np.cos(t))], name="orange")
    r = plan(orange, "precision", restarts=1)  # one attempt per pass: the target's fails, the band's succeeds
    verify(r, orange)
    assert [(a["pass"], a["band"]) for a in r.attempts] == [(1, None), (2, [1.0, 4.5])]
    assert r.attempts[0]["start"] == r.attempts[1]["start"]  # the same schedule again
    capped = plan(orange, "precision", restarts=1, band_after=10)
    assert capped.attempts[0]["iterations"] == 10 and capped.attempts[1]["band"] == [1.0, 4.5]
    assert capped.success


def test_a_failed_power_schedule_is_tried_again_with_the_synergies_held_while_reaching():
    box = so.from_mesh(trimesh.creation.box((60.0, 190.0, 270.0)), name="cereal box", cache=False)
    free_only = plan(box, "power", restarts=5, power_held_pass=False)
    assert not free_only.success and len(free_only.attempts) == 5
    r = plan(box, "power", restarts=5)
    verify(r, box)
    assert [a["pass"] for a in r.attempts] == [1] * 5 + [2] * 5  # the fifth start succeeds with the held reach
    assert r.attempts[0]["start"] == r.attempts[5]["start"]  # the same schedule again
    assert r.options["power_free_reach"]  # the caller's options; only the second pass holds the synergies


def test_a_penetrating_finger_backs_off_instead_of_rejecting_the_grasp():
    obj = so.revolve(np.array([[38.0, 0.0], [41.0, 95.0]]), name="mug body")
    rejected = plan(obj, "precision", restarts=1, backoffs=0, contact_band=None)
    assert not rejected.success and "phalanx penetrates" in rejected.reason
    r = plan(obj, "precision", restarts=1)
    verify(r, obj)
    assert r.iterations > rejected.iterations


def test_an_attempt_whose_fingertips_never_reach_the_surface_ends(hand, ellipsoid):
    far = start_configuration(hand, ellipsoid, (0.0, 1.0, 0.0), 1000.0)  # out of reach in a few iterations
    r = plan(ellipsoid, "precision", u0=far, touch_window=5)
    assert not r.success and r.iterations == 5
    assert "no fingertip reached the surface in 5 iterations" in r.reason
    assert plan(ellipsoid, "precision", u0=far, touch_window=0, max_iter=8).iterations == 8
    assert plan(ellipsoid, "power", u0=far, touch_window=5, max_iter=8).iterations == 8  # precision attempts only


def test_the_sq_request_is_what_a_step_within_the_radius_can_give():
    grad = np.array([0.0, 3.0, 4.0])
    assert sq_request(0.1, 0.2, grad) == 0.1  # the moving target as asked
    assert sq_request(0.1, 0.01, grad) == pytest.approx(0.05)  # |grad| * radius
    assert sq_request(0.1, 0.2, np.zeros(3)) == 0.0  # a flat sQ: nothing asked, the contact rows steer


def test_attempt_schedule():
    plain = attempt_schedule(standoff=0.0)
    assert [d for d, _ in plain] == [tuple(d) for d in sg.planner.APPROACHES] and all(s == 0 for _, s in plain)
    mine = (1.0, 0.0, 0.5)  # one of APPROACHES: first, and not tried again without a stand-off
    schedule = attempt_schedule(mine, 20.0)
    assert schedule[0] == (mine, 0.0)
    assert sum(1 for d, s in schedule if s == 0 and np.allclose(d, mine)) == 1
    assert [s for _, s in schedule[:8]] == [0.0, 0.0, 0.0, 20.0, 0.0, 10.0, 0.0, 20.0]
    assert len(schedule) == len(sg.planner.APPROACHES) + len(sg.planner.STANDOFF_APPROACHES)
    power = attempt_schedule(None, 0.0, sg.planner.POWER_APPROACHES)
    assert [d for d, _ in power] == [tuple(d) for d in sg.planner.POWER_APPROACHES]


def test_power_schedule_alternates_the_pre_shapes():
    schedule = power_schedule()
    assert [d for d, wide in schedule if wide] == [tuple(d) for d in sg.planner.POWER_WIDE_APPROACHES]
    assert [d for d, wide in schedule if not wide] == [tuple(d) for d in sg.planner.POWER_APPROACHES]
    assert [wide for _, wide in schedule[:4]] == [True, False, True, False]
    mine = (0.0, 0.0, 1.0)  # in both orders: first in each, and not repeated
    schedule = power_schedule(mine)
    assert schedule[:2] == [(mine, True), (mine, False)]
    assert sum(1 for d, _ in schedule if np.allclose(d, mine)) == 2 and len(schedule) == 24
    assert all(not wide for _, wide in power_schedule(wide=False))


def test_power_plans_follow_the_power_schedule():
    obj = so.ellipsoid()
    r = plan(obj, "power", restarts=4, iterations_per_attempt=1, power_held_pass=False)
    assert len(r.attempts) == 4
    for attempt, (d, wide) in zip(r.attempts, power_schedule()):
        start = np.array(attempt["start"])
        d = np.array(d) / np.linalg.norm(d)
        offset = start[:3] - obj.center
        assert offset @ d / np.linalg.norm(offset) > 0.9  # the palm starts on the side of that direction
        np.testing.assert_array_equal(start[6:], [-1.0, 1.0] if wide else [0.0, 1.0])


def test_power_plan_reaches_with_the_palm_then_wraps():
    obj = so.goblet()
    r = plan(obj, "power", approach=(0.0, 0.0, 1.0), restarts=1, power_wide_preshape=None, power_free_reach=False)
    verify(r, obj)
    assert "P" in r.contact_labels and len(r.attempts) == 1
    touch = int(np.argmax(r.status[:, -2] < 5.0))  # first palm contact
    assert touch > 0 and np.all(r.trajectory[: touch + 1, 6:] == [0.0, 1.0])  # the pre-shape held while reaching
    assert np.any(r.trajectory[touch + 1 :, 6:] != [0.0, 1.0])  # then the synergies close the fingers


def test_power_reach_with_free_synergies():
    obj = so.goblet()
    r = plan(obj, "power", restarts=1, max_iter=40)
    touch = int(np.argmax(r.status[:, -2] < 5.0))  # first palm contact
    assert touch > 0
    assert np.all(r.trajectory[0, 6:] == [-1.0, 1.0])  # the wide pre-shape first
    assert np.any(r.trajectory[touch, 6:] != [-1.0, 1.0])  # the sQ row shaped the hand on the way


def test_power_plans_without_phases_keep_the_mean_pose_start(hand, ellipsoid):
    r = plan(ellipsoid, "power", max_iter=1, power_phases=False, power_preshape=None, power_wide_preshape=None)
    np.testing.assert_array_equal(r.trajectory[0, 6:], np.zeros(2))


def test_save_load_round_trip(goblet_plan, tmp_path):
    path = goblet_plan.save(tmp_path / "plan.json")
    back = PlanResult.load(path)
    for name in ("u", "trajectory", "status", "target", "q_history", "contact_points", "contact_normals"):
        np.testing.assert_array_equal(getattr(back, name), getattr(goblet_plan, name))
    for name in ("success", "reason", "iterations", "contact_labels", "penetration", "time_s", "lp_solves", "backend", "options", "attempts"):
        assert getattr(back, name) == getattr(goblet_plan, name)


def test_load_rejects_other_files(tmp_path):
    path = tmp_path / "x.json"
    path.write_text("[1, 2]")
    with pytest.raises(ValueError, match="not a saved synergrasp PlanResult"):
        PlanResult.load(path)


def test_first_iterations_agree_on_every_backend(hand):
    obj = so.ellipsoid()
    u0 = near_start(hand, obj)
    runs = {name: plan(obj, "precision", backend=name, u0=u0, max_iter=20) for name in BACKENDS}
    reference = runs["highs"].trajectory
    for name, r in runs.items():
        k = min(len(r.trajectory), len(reference))
        np.testing.assert_allclose(r.trajectory[:k], reference[:k], atol=1e-6, err_msg=name)


def test_first_power_iterations_agree_on_every_backend(hand):
    obj = so.ellipsoid()
    runs = {name: plan(obj, "power", backend=name, approach=(1.0, -1.0, 1.0), max_iter=20) for name in BACKENDS}
    reference = runs["highs"].trajectory
    for name, r in runs.items():
        k = min(len(r.trajectory), len(reference))
        np.testing.assert_allclose(r.trajectory[:k], reference[:k], atol=1e-6, err_msg=name)


def test_a_palm_centred_start_faces_the_object_with_the_palm(hand, ellipsoid):
    a = np.array([1.0, 1.0, 1.0]) / np.sqrt(3.0)
    for centred in (True, False):
        u = start_configuration(hand, ellipsoid, a, 150.0, palm_centred=centred)
        off_axis = np.linalg.norm(np.cross(u[:3] - ellipsoid.center, a))  # palm centre off the approach line
        assert (off_axis < 1e-9) == centred
        np.testing.assert_allclose(sg.hand.rotation_xyz(u[3:6])[:, 2], -a, atol=1e-12)  # the palm faces the centre


def test_the_caller_chooses_the_approach(hand, ellipsoid):
    a = plan(ellipsoid, "precision", approach=(0.0, 0.0, 1.0), max_iter=1)
    u = a.trajectory[0]
    toward = ellipsoid.center - hand.points(u, "power")[-1]
    palm_normal = sg.hand.rotation_xyz(u[3:6])[:, 2]
    assert palm_normal @ toward / np.linalg.norm(toward) > 0.9  # the palm faces the object
    assert hand.points(u, "power")[-1][2] > ellipsoid.center[2] + 50  # from above


@pytest.mark.parametrize(
    "kwargs, match",
    [
        ({"grasp": "pinch"}, "grasp must be one of"),
        ({"u0": [0, 0, np.nan, 0, 0, 0, 0, 0]}, "u0 contains NaN"),
        ({"u0": np.zeros(5)}, r"u0 must have shape \(8,\)"),
        ({"approach": [0, 0, 0]}, "non-zero direction"),
        ({"max_iter": 0}, "max_iter must be >= 1"),
        ({"backend": "simplex"}, "unknown LP backend"),
        ({"stepsize": 3}, "unknown planner options"),
        ({"grasp": "power", "power_preshape": (0.0, 1.0, 0.5)}, "power_preshape must hold one finite value per synergy"),
        ({"grasp": "power", "power_wide_preshape": (np.nan, 1.0)}, "power_wide_preshape must hold one finite value per synergy"),
        ({"contact_band": (4.0, 2.0)}, "contact_band must be"),
        ({"contact_band": (1.0, np.inf)}, "contact_band must be"),
        ({"grasp": "power", "contact_band": (1.0, 4.5)}, "for precision grasps only"),
        ({"band_after": -1}, "band_after must be an integer >= 0"),
        ({"band_after": 2.5}, "band_after must be an integer >= 0"),
        ({"grasp": "power", "power_sq_hold": np.nan}, "power_sq_hold must be a finite number"),
        ({"grasp": "power", "power_sq_hold": "low"}, "power_sq_hold must be a finite number"),
        ({"grasp": "power", "power_capsule_rows": "yes"}, "power_capsule_rows must be True or False"),
    ],
)
def test_bad_input(ellipsoid, kwargs, match):
    with pytest.raises(ValueError, match=match):
        plan(ellipsoid, **kwargs)


def test_an_object_in_metres_is_refused():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        tiny = so.ellipsoid(0.03, 0.04, 0.05)
    with pytest.raises(ValueError, match="too small to grasp.*scale=1000"):
        plan(tiny, "precision")


def test_an_object_the_hand_cannot_hold():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        huge = so.ellipsoid(300.0, 300.0, 300.0)
    with pytest.raises(ValueError, match="too large for the hand"):
        plan(huge, "precision")
