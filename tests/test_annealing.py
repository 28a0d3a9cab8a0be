"""The annealing baseline (plan(..., method="annealing")): its parts, its grasp, and the dispatch by method."""

import math

import numpy as np
import pytest

import synergrasp as sg
from synergrasp import SynergyHand, objects
from synergrasp.planner import AnnealingOptions, PlannerOptions, annealing, start_configuration
from synergrasp.planner.status import hand_penetration


@pytest.fixture(scope="module")
def hand():
    return SynergyHand.default()


def test_schedule_is_graspits_default():
    """T(k) = 1e6 exp(-7 k^(1/8)) from k = 30000, recomputed here from the formula."""
    opts = AnnealingOptions()
    assert (opts.t0, opts.k0, opts.cooling, opts.dims, opts.energy_scale) == (1e6, 30000, 7.0, 8, 1e-6)
    for k in (30000, 35000):
        assert annealing.temperature(opts, k) == pytest.approx(1e6 / math.e ** (7.0 * k ** 0.125), rel=1e-12)
    assert annealing.temperature(opts, 40000) < annealing.temperature(opts, 30000)


def test_neighbour_distribution_matches_ingbers_law():
    """P(|y| <= a) = log(1 + a/T) / log(1 + 1/T) for Ingber's distribution (inverse of its sampling law)."""
    rng, T = np.random.default_rng(1), 1e-4
    y = annealing.neighbour_steps(rng, T, 200_000)
    assert np.abs(y).max() <= 1.0 and abs(np.mean(y > 0) - 0.5) < 0.01
    for a in (1e-4, 1e-2, 0.3):
        expected = math.log1p(a / T) / math.log1p(1.0 / T)
        assert np.mean(np.abs(y) <= a) == pytest.approx(expected, abs=0.005)


def test_contact_normals_are_the_pads_offsets(hand):
    """Each fingertip's normal is the unit offset of its pad point from the distal phalanx's end."""
    u = np.array([10.0, -5.0, 3.0, 0.3, -0.2, 0.5, 0.4, -0.3])
    n = annealing.contact_normals(hand, u, "precision")
    tips, ends = hand.points(u, "precision"), hand.segments(u).capsules[[2, 5, 8, 11, 14], 1]
    np.testing.assert_allclose(np.linalg.norm(n, axis=1), 1.0)
    np.testing.assert_allclose(tips - ends, hand.contact_offset * n, atol=1e-9)
    power = annealing.contact_normals(hand, u, "power")
    np.testing.assert_allclose(power[-1], sg.hand.rotation_xyz(u[3:6])[:, 2], atol=1e-12)  # the palm's normal


def test_energy_is_contact_distance_plus_alignment(hand):
    """A ball: the distance term against the Euclidean distances (cP lies in [e, 3 e]), the alignment term's weight."""
    ball = objects.ellipsoid(35.0, 35.0, 35.0)
    u = start_configuration(hand, ball, (0.0, 1.0, 0.0), distance=120.0)
    e = np.linalg.norm(hand.points(u, "precision") - ball.center, axis=1) - 35.0  # Euclidean, up to the facets
    distance, solves = annealing.contact_energy(hand, ball, u, "precision", alignment=0.0)
    assert e.mean() - 0.5 <= distance <= 3.0 * e.mean() and solves >= 1
    weighted = annealing.contact_energy(hand, ball, u, "precision", alignment=50.0)[0]
    cp = ball.contact_distance(hand.points(u, "precision"))
    misalignment = 1.0 - np.einsum("ij,ij->i", annealing.contact_normals(hand, u, "precision"), cp.normal)
    assert weighted - distance == pytest.approx(50.0 * misalignment.mean(), rel=1e-9)
    assert 0.0 <= misalignment.min() and misalignment.max() <= 2.0
    inside = u.copy()
    inside[:3] += ball.center - hand.points(u, "precision")[1]  # the index tip at the centre
    assert annealing.contact_energy(hand, ball, inside, "precision")[0] == math.inf


def test_autograsp_closes_until_blocked(hand):
    """The open hand around a ball (its centre between the thumb and middle tips) closes until a phalanx is 3 mm in."""
    obj = objects.ellipsoid(25.0, 25.0, 25.0)
    opts = AnnealingOptions()
    u = np.r_[np.zeros(6), 0.0, 1.0]
    tips = hand.points(u, "precision")
    u[:3] = obj.center - 0.5 * (tips[0] + tips[2])
    assert hand_penetration(hand, obj, u).depth == 0.0
    path = annealing.autograsp(hand, obj, u, "precision", opts)
    assert len(path) and np.all(path[:, :6] == u[:6])
    assert path[0, 7] < u[7]  # z2 falls first
    assert hand_penetration(hand, obj, path[-1]).depth <= opts.max_penetration
    assert path[-1, 7] > hand.synergy_limits[1, 0]  # blocked before the limit: one more step goes too deep
    deeper = path[-1].copy()
    deeper[7] -= opts.close_step
    assert hand_penetration(hand, obj, deeper).depth > opts.max_penetration
    assert obj.contact_distance(hand.points(path[-1], "precision")).value.min() < opts.eps_c  # a fingertip touches


def test_annealing_grasps_the_ellipsoid_with_a_fixed_seed():
    """Seed 2 finds an accepted grasp within 3000 steps (no time limit: the same on any machine)."""
    obj = objects.ellipsoid()
    r = sg.plan(obj, "precision", method="annealing", seed=2, steps=3000, time_limit=None)
    assert r.success and r.attempts[0]["kind"] == "annealing" and r.attempts[0]["outcome"] == "grasp"
    assert len(r.contact_labels) >= 3 and r.final_q < 0 and r.surface_q < -0.01
    assert r.penetration <= 3.0 and r.collision_free
    assert r.trajectory.shape == (r.iterations + 1, 8) and r.status.shape == (r.iterations + 1, 17)
    assert np.isfinite(r.status).all() and np.array_equal(r.u, r.trajectory[-1])
    short = [sg.plan(obj, "precision", method="annealing", seed=2, steps=300, time_limit=None, executable_reach=False)
             for _ in range(2)]
    np.testing.assert_array_equal(short[0].trajectory, short[1].trajectory)  # deterministic (a shorter run, twice)
    assert len(short[0].trajectory) > 100
    from benchmarks.generalise import verify

    assert verify(r, obj)["verified"]  # the independent check on the true surface


def test_annealing_without_a_grasp_says_why():
    r = sg.plan("ellipsoid", "power", method="annealing", steps=20, time_limit=None)
    assert not r.success and "annealing: 20 steps" in r.reason
    assert r.attempts[0]["steps"] == 20 and r.attempts[0]["evaluations"] >= 21
    assert np.isfinite(r.status).all() and len(r.path) == 0


def test_unknown_method_lists_the_known_ones():
    with pytest.raises(ValueError, match=r"unknown method 'newton'; known: \['annealing', 'gradient'\]"):
        sg.plan("ellipsoid", method="newton")


@pytest.mark.parametrize("method, name, owner", [("gradient", "cooling", "annealing"), ("gradient", "steps", "annealing"),
                                                 ("annealing", "restarts", "gradient"), ("annealing", "sq_step", "gradient")])
def test_options_of_the_other_method_are_refused_by_name(method, name, owner):
    with pytest.raises(ValueError, match=rf"options \['{name}'\] belong to method='{owner}', not to method='{method}'"):
        sg.plan("ellipsoid", method=method, **{name: 1})


def test_options_object_must_match_the_method():
    with pytest.raises(TypeError, match="options of method='annealing' must be an instance of AnnealingOptions"):
        sg.plan("ellipsoid", method="annealing", options=PlannerOptions())
    with pytest.raises(TypeError, match="must be an instance of PlannerOptions"):
        sg.plan("ellipsoid", options=AnnealingOptions())
