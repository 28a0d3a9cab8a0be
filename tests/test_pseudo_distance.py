"""Pseudo-distance (paper Eqs. 1-3): closed forms, continuity, derivatives, invariances, bad input."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

import synergrasp as sg
from synergrasp.lp import Backend

from .conftest import BACKENDS, assert_gradient, central_difference


def gauge(Q, x):
    """Closed form for the regular simplex: gauge_Q(x) = -d min_k q_k . x."""
    return -Q.shape[1] * (Q @ x).min()


@pytest.mark.parametrize("d", [2, 3, 4, 6, 7])
def test_regular_simplex(d):
    Q = sg.regular_simplex(d)
    assert Q.shape == (d + 1, d)
    assert np.allclose(np.linalg.norm(Q, axis=1), 1.0)
    G = Q @ Q.T
    assert np.allclose(G[~np.eye(d + 1, dtype=bool)], -1.0 / d)
    assert np.allclose(Q.sum(axis=0), 0.0)


@pytest.mark.parametrize("d", [2, 3, 6])
def test_point_to_point_is_the_gauge(backend, rng, d):
    Q = sg.regular_simplex(d)
    for _ in range(5):
        a, b = rng.normal(size=d), rng.normal(size=d)
        r = sg.pseudo_distance(a[None], b[None], backend=backend)
        assert r.kind == "separation"
        assert r.value == pytest.approx(gauge(Q, b - a), abs=1e-7)
        # the paper's order: separation measures b - a, so swapping changes the value
        assert sg.pseudo_distance(b[None], a[None], backend=backend).value == pytest.approx(gauge(Q, a - b), abs=1e-7)
        # norm bounds ||x|| <= gauge <= d ||x||
        assert np.linalg.norm(b - a) - 1e-9 <= r.value <= d * np.linalg.norm(b - a) + 1e-9


def test_point_to_simplex_closed_form(backend, rng):
    """B = c - t Q: separation max(0, gauge(c - p) - t); from the centre, penetration -t."""
    Q = sg.regular_simplex(3)
    c, t = np.array([1.0, -2.0, 0.5]), 2.0
    B = c - t * Q
    for _ in range(5):
        p = c + rng.normal(size=3) * 6
        expected = gauge(Q, c - p) - t
        if expected < 0.1:
            continue
        r = sg.pseudo_distance(p[None], B, backend=backend)
        assert r.kind == "separation" and r.value == pytest.approx(expected, abs=1e-7)
    inside = sg.pseudo_distance(c[None], B, backend=backend)
    assert inside.kind == "penetration" and inside.value == pytest.approx(-t, abs=1e-7)
    assert inside.degenerate  # all d+1 directions tie


def test_scaling_the_simplex_divides_the_value(backend, rng):
    A, B = rng.normal(size=(4, 3)), rng.normal(size=(5, 3)) + 2.0
    Q = sg.regular_simplex(3)
    for shift in (2.0, 0.2):  # separated and overlapping
        B2 = B - 2.0 + shift
        base = sg.pseudo_distance(A, B2, backend=backend).value
        assert sg.pseudo_distance(A, B2, simplex=3.0 * Q, backend=backend).value == pytest.approx(base / 3.0, abs=1e-8)


@pytest.mark.parametrize("c", [1e-12, 1e-3, 1e9, 1e13, 1e300])
def test_a_simplex_of_any_size_divides_the_value_solved_cold(backend, c):
    """At 1e9 the LPs' tolerances did not fit the simplex: wrong values that depended on the warm start (the
    value after a call at size 1 was right); at 1e-12 a regular simplex was refused as degenerate."""
    from synergrasp.pseudo_distance import reset_regime_memory

    Q = sg.regular_simplex(2)
    for A, B, expected in (([[0.0, 0.0], [1.0, 0.0]], [[3.0, 0.0]], 2.0 * np.sqrt(3.0)),  # apart: the gauge of (2, 0)
                           ([[0.0, 0.0], [4.0, 0.0], [2.0, 4.0]], [[2.0, 1.0]], None)):  # overlapping
        reset_regime_memory()
        base = sg.pseudo_distance(A, B, backend=backend)
        sg.lp.get_backend(backend).forget()
        reset_regime_memory()
        scaled = sg.pseudo_distance(A, B, simplex=c * Q, backend=backend)
        assert scaled.kind == base.kind
        assert scaled.value * c == pytest.approx(base.value if expected is None else expected, rel=1e-7)
        assert np.allclose(scaled.grad_a * c, base.grad_a, atol=1e-6)
        assert np.allclose(scaled.grad_b * c, base.grad_b, atol=1e-6)
        assert np.allclose(scaled.normal_b, base.normal_b, atol=1e-6)


def test_a_repeated_vertex_is_degenerate_on_every_backend(backend):
    """An interior-point solver splits the weight between a point's two copies: as many positive weights as
    rows, but not a vertex of the LP (moving one copy toward B changes the value, away from it does not)."""
    r = sg.pseudo_distance([[0.0, 0.0], [0.0, 0.0]], [[1.0, -3.0]], backend=backend)
    single = sg.pseudo_distance([[0.0, 0.0]], [[1.0, -3.0]], backend=backend)
    assert r.value == pytest.approx(single.value, abs=1e-7) and r.degenerate and not single.degenerate


def test_touching_squares_a_simplex_backend_gives_the_one_sided_derivative(backend):
    """Two squares sharing an edge: the value moves at the same rate (2/sqrt(3)) whichever way B slides along x. A
    simplex backend returns that rate; an interior-point one the centre of the optimal face, whose gradient is not a
    one-sided derivative (as documented): both flag the LP degenerate."""
    A = np.array([[-1.0, -1.0], [1.0, -1.0], [-1.0, 1.0], [1.0, 1.0]])
    B = A + [2.0, 0.0]
    r = sg.pseudo_distance(A, B, backend=backend)
    h = 1e-3  # (the value is linear on either side: an interior-point solver's round-off of 1e-10 is 1e-7 of a step)
    ahead = (sg.pseudo_distance(A, B + [h, 0.0], backend=backend).value - r.value) / h
    behind = (r.value - sg.pseudo_distance(A, B - [h, 0.0], backend=backend).value) / h
    assert ahead == pytest.approx(2 / np.sqrt(3), rel=1e-5) and behind == pytest.approx(2 / np.sqrt(3), rel=1e-5)
    assert r.degenerate and abs(r.value) < 1e-8
    if sg.lp.get_backend(backend).vertex_solutions:
        assert r.grad_b.sum(axis=0) == pytest.approx([2 / np.sqrt(3), 0.0], abs=1e-7)


@pytest.mark.parametrize("flat", [1e-8, 1e-9])
def test_a_simplex_too_flat_for_the_solvers_is_refused(flat):
    """Flattened to 1e-9 of its size, a simplex around the origin made HiGHS call the always-feasible separation LP
    infeasible and Clarabel return a value 27 % off: refused, with its condition number."""
    with pytest.raises(ValueError, match="simplex is degenerate or nearly so: .* condition number"):
        sg.pseudo_distance(np.eye(3), np.eye(3) + 3.0, simplex=sg.regular_simplex(3) * [1.0, 1.0, flat])


def test_a_simplex_flattened_to_a_millionth_still_agrees_on_every_backend(backend):
    """The flattest simplex accepted by a wide margin: every backend gives the native value to 1e-8."""
    Q = sg.regular_simplex(3) * [1.0, 1.0, 1e-6]
    value = sg.pseudo_distance(np.eye(3), np.eye(3) + 3.0, simplex=Q, backend=backend).value
    assert value == pytest.approx(sg.pseudo_distance(np.eye(3), np.eye(3) + 3.0, simplex=Q, backend="native").value,
                                  rel=1e-8)


def test_sets_too_large_for_the_penetration_lp_are_refused_before_it_is_built():
    rng = np.random.default_rng(0)
    with pytest.raises(ValueError, match=r"301 \+ 301 points in 300 dimensions make a penetration LP of 5.46e\+07"):
        sg.pseudo_distance(rng.normal(size=(301, 300)), rng.normal(size=(301, 300)))


def test_continuity_across_touching(backend):
    cube = np.array(np.meshgrid([0, 1], [0, 1], [0, 1])).reshape(3, -1).T.astype(float)
    values = []
    for s in np.linspace(-0.3, 0.3, 13):
        values.append(sg.pseudo_distance(cube, cube + [1.0 + s, 0.2, 0.1], backend=backend).value)
    values = np.array(values)
    assert values[0] < 0 and values[-1] > 0
    assert np.abs(values[6]) < 1e-7  # touching
    assert np.abs(np.diff(values)).max() < 0.2  # no jump (steps of 0.05 in s, gauge <= 3 |x|)
    assert (np.diff(values) > 0).all()


def test_witness_points_and_normal(backend):
    cube = np.array(np.meshgrid([0, 1], [0, 1], [0, 1])).reshape(3, -1).T.astype(float)
    p = np.array([[0.5, 0.4, 3.0]])
    r = sg.pseudo_distance(p, cube, backend=backend)
    assert np.allclose(r.point_a, p[0])
    assert r.point_b[2] == pytest.approx(1.0)  # on the top face
    assert np.allclose(r.normal_b, [0, 0, -1], atol=1e-7)  # inward normal of the top face
    inside = sg.pseudo_distance(np.array([[0.5, 0.45, 0.9]]), cube, backend=backend)
    assert inside.kind == "penetration" and inside.value < 0


@pytest.mark.parametrize("scale", [3.0, 0.2])  # A apart from B, and A inside it
def test_moving_b_along_its_normal_increases_the_value(backend, rng, scale):
    """The docstring said the value increases along -normal_b: it decreases there."""
    for _ in range(6):
        A, B = rng.normal(size=(1, 3)) * scale, rng.normal(size=(6, 3))
        r = sg.pseudo_distance(A, B, backend=backend)
        if r.degenerate:
            continue
        moved = sg.pseudo_distance(A, B + 1e-4 * r.normal_b, backend=backend).value
        assert moved - r.value == pytest.approx(1e-4 * r.grad_b.sum(axis=0) @ r.normal_b, rel=1e-3)
        assert r.grad_b.sum(axis=0) @ r.normal_b > 0


@pytest.mark.parametrize("shift", [3.0, 0.0])
def test_gradients_match_finite_differences(backend, rng, shift):
    for _ in range(2):
        A = rng.normal(size=(8, 3))
        B = rng.normal(size=(8, 3)) + shift
        r = sg.pseudo_distance(A, B, backend=backend)
        assert r.kind == ("separation" if shift > 1 else "penetration")
        assert not r.degenerate
        ga = central_difference(lambda X: sg.pseudo_distance(X, B, backend=backend).value, A)
        gb = central_difference(lambda X: sg.pseudo_distance(A, X, backend=backend).value, B)
        assert_gradient(r.grad_a, ga)
        assert_gradient(r.grad_b, gb)


def test_gradients_in_higher_dimension(backend, rng):
    A, B = rng.normal(size=(8, 6)), rng.normal(size=(3, 6)) + 0.3
    r = sg.pseudo_distance(A, B, backend=backend)
    ga = central_difference(lambda X: sg.pseudo_distance(X, B, backend=backend).value, A)
    assert_gradient(r.grad_a, ga)


def test_all_backends_agree(rng):
    for shift in (3.0, 0.3):
        A, B = rng.normal(size=(7, 3)), rng.normal(size=(9, 3)) + shift
        results = [sg.pseudo_distance(A, B, backend=name) for name in BACKENDS]
        for r in results[1:]:
            assert r.value == pytest.approx(results[0].value, abs=1e-7)
            assert np.allclose(r.grad_a, results[0].grad_a, atol=1e-6)
            assert np.allclose(r.grad_b, results[0].grad_b, atol=1e-6)


def test_degenerate_vertex_direction_is_flagged():
    Q = sg.regular_simplex(3)
    r = sg.pseudo_distance(np.zeros((1, 3)), Q[:1] * 2.0)
    assert r.value == pytest.approx(2.0)  # along a vertex the gauge is the norm
    assert r.degenerate
    assert np.isfinite(r.grad_a).all()


def test_nearly_coplanar_touching_sets(backend):
    # A sliver 1e-7 thick with B on it: the unscaled HiGHS simplex runs into numerical
    # trouble here; every backend must still return ~0 and not raise.
    A = np.array([[0, -1.5436589, 1e-7], [0, 1e-7, 1e-7], [1e-7, 1, 3], [0, -1.95845851, 1e-7], [1e-7, 1e-7, 1e-7]])
    for shift in (0.0, 1.9):
        assert sg.pseudo_distance(A + shift, np.zeros((1, 3)) + shift, backend=backend).value == pytest.approx(0.0, abs=1e-6)


def test_a_point_a_nanometre_off_a_segments_end(backend):
    # found by the property test below: the penetration LP's blocks mix entries of 1e-9 and 1, and the
    # native simplex once reported one of them failed instead of feasible within its tolerance
    A, B = np.full((1, 3), -1e-9), np.array([[1.0, 0.0, 0.0], [0.0, 0.0, 0.0]])
    assert sg.pseudo_distance(A, B, backend=backend).value == pytest.approx(0.0, abs=1e-7)


def test_nearly_degenerate_sets_are_solved_as_highs_solves_them():
    """Points on a lattice of 1 with offsets of 1e-9 and 1e-12 (coincident, nearly collinear and nearly
    touching sets): the native backend's LPs fail on none of them (it once failed on about 2 %) and agree
    with HiGHS."""
    rng = np.random.default_rng(0)
    values = np.array([0.0, 1e-9, -1e-9, 1e-12, 1.0, -1.0, 0.5, 2.0, -3.0])
    for _ in range(800):
        A, B = (rng.choice(values, size=(int(rng.integers(1, 6)), 3)) for _ in range(2))
        shift = rng.choice(values, 3)
        ours = sg.pseudo_distance(A + shift, B + shift)
        assert ours.value == pytest.approx(sg.pseudo_distance(A + shift, B + shift, backend="highs").value, abs=1e-7)


points = arrays(np.float64, st.tuples(st.integers(1, 5), st.just(3)), elements=st.floats(-5, 5))


@settings(max_examples=25, deadline=None)
@given(A=points, B=points, shift=arrays(np.float64, 3, elements=st.floats(-10, 10)))
def test_translation_invariance(A, B, shift):
    base = sg.pseudo_distance(A, B).value
    assert sg.pseudo_distance(A + shift, B + shift).value == pytest.approx(base, abs=1e-7)


@settings(max_examples=25, deadline=None)
@given(A=points, B=points, seed=st.integers(0, 1000))
def test_permutation_invariance(A, B, seed):
    perm = np.random.default_rng(seed)
    base = sg.pseudo_distance(A, B)
    moved = sg.pseudo_distance(perm.permutation(A), perm.permutation(B))
    assert moved.value == pytest.approx(base.value, abs=1e-7)


@pytest.mark.parametrize(
    "A, B, kwargs, error, match",
    [
        ([[np.nan, 0.0]], [[1.0, 0.0]], {}, ValueError, "A contains NaN"),
        ([[0.0, 0.0]], [[np.inf, 0.0]], {}, ValueError, "B contains NaN or inf"),
        ([0.0, 0.0], [[1.0, 0.0]], {}, ValueError, r"A must have shape \(n, d\)"),
        ([[0.0, 0.0]], [[1.0, 0.0, 0.0]], {}, ValueError, "B has points of dimension 3, expected 2"),
        (np.zeros((0, 2)), [[1.0, 0.0]], {}, ValueError, "A is empty"),
        ([[0.0]], [[1.0]], {}, ValueError, "at least 2"),
        ([["a", "b"]], [[1.0, 0.0]], {}, TypeError, "A must be a numeric array"),
        ([[0.0, 0.0]], [[1.0, 0.0]], {"simplex": [[1, 0], [0, 1], [1, 1]]}, ValueError, "origin strictly inside"),
        ([[0.0, 0.0]], [[1.0, 0.0]], {"simplex": [[1, 0], [0, 1]]}, ValueError, "d\\+1 = 3 vertices"),
        ([[0.0, 0.0]], [[1.0, 0.0]], {"simplex": [[1, 0], [2, 0], [-1, 0]]}, ValueError, "degenerate"),
        ([[0.0, 0.0]], [[1.0, 0.0]], {"backend": "mosek"}, ValueError, "available"),
    ],
)
def test_bad_input(A, B, kwargs, error, match):
    with pytest.raises(error, match=match):
        sg.pseudo_distance(A, B, **kwargs)


def test_solver_failure_raises_library_error():
    class Infeasible(Backend):
        def _solve(self, c, A, b):
            return "infeasible", None, None, 3, "claims infeasible"

    with pytest.raises(sg.lp.LPError, match="status 'infeasible'"):
        sg.pseudo_distance([[0.0, 0.0]], [[1.0, 0.0]], backend=Infeasible(name="broken"))


def test_the_order_of_the_two_regimes_does_not_change_the_result(backend, rng):
    """Calls alternate between separated and overlapping sets of the same shapes."""
    A = rng.normal(size=(6, 3))
    cases = [rng.normal(size=(5, 3)) + shift for shift in (0.0, 4.0, 0.0, 0.0, 4.0, 4.0, 0.0)]
    first = [sg.pseudo_distance(A, B, backend=backend) for B in cases]
    again = [sg.pseudo_distance(A, B, backend=backend) for B in reversed(cases)][::-1]
    for r, s in zip(first, again):
        assert r.kind == s.kind and r.value == pytest.approx(s.value, abs=1e-9)
        assert np.allclose(r.grad_a, s.grad_a, atol=1e-7) and 1 <= r.lp_solves <= 3
    assert {r.kind for r in first} == {"separation", "penetration"}


def test_a_failed_penetration_attempt_falls_back_to_separation(rng):
    """Tried first, the penetration LP may stop short of proving infeasibility (HiGHS: Unknown)."""

    class NoProofOfInfeasibility(Backend):
        def _solve(self, c, A, b):
            status, x, y, iterations, message = sg.lp.get_backend("highs")._solve(c, A, b)
            return ("failed", None, None, iterations, "Unknown") if status == "infeasible" else (status, x, y, iterations, message)

    backend = NoProofOfInfeasibility(name="flaky")
    A = rng.normal(size=(7, 3))
    overlapping = sg.pseudo_distance(A, rng.normal(size=(4, 3)), backend=backend)
    assert overlapping.kind == "penetration"
    B = rng.normal(size=(4, 3)) + 5.0
    apart = sg.pseudo_distance(A, B, backend=backend)  # penetration is tried first and "fails"
    assert apart.kind == "separation" and apart.lp_solves == 2
    assert apart.value == pytest.approx(sg.pseudo_distance(A, B).value, abs=1e-9)


def test_the_optimum_is_what_pseudo_distance_builds_its_result_from(backend, rng):
    from synergrasp.pseudo_distance import optimum

    for shift in (0.0, 3.0):  # overlapping, then apart
        A, B = rng.normal(size=(6, 3)), rng.normal(size=(5, 3)) + shift
        r = sg.pseudo_distance(A, B, backend=backend)
        opt = optimum(A, B, backend=backend)
        assert opt.kind == r.kind and opt.value == pytest.approx(r.value, abs=1e-9)
        if not r.degenerate:
            assert -opt.alpha[:, None] * opt.dual == pytest.approx(r.grad_a, abs=1e-7)
            assert opt.beta[:, None] * opt.dual == pytest.approx(r.grad_b, abs=1e-7)
    with pytest.raises(ValueError, match="dimension"):
        optimum([[0.0, 0.0]], [[1.0, 0.0, 0.0]])


@pytest.mark.parametrize("extent", [1e2, 1e4, 1e6, 1e10])
def test_the_value_is_accurate_to_round_off_of_the_extent(extent, backend):
    """Two segments of length ``extent`` on a line, their ends 1 apart, solved cold: the value is sqrt(3) (the regular
    simplex's gauge along the line) to 1e-9 of the extent up to 1e6; at 1e10, where the gap is 1e-10 of the extent,
    it reads as touching (0) or comes out right, or a backend that cannot solve it says so: never another number."""
    from synergrasp.pseudo_distance import reset_regime_memory

    solver = sg.lp.get_backend(backend)
    solver.forget()  # a cold start (a warm one can resolve a gap a cold one reads as 0)
    reset_regime_memory()  # (the separation LP first, whatever the tests before solved)
    try:
        value = sg.pseudo_distance([[0.0, 0.0], [extent, 0.0]], [[-extent, 0.0], [-1.0, 0.0]], backend=solver).value
    except sg.lp.LPError:
        assert extent > 1e6  # (cvxpy's Clarabel at 1e10)
        return
    if extent <= 1e6:
        assert value == pytest.approx(np.sqrt(3.0), abs=1e-9 * extent)
    else:
        assert value == pytest.approx(0.0, abs=1e-9) or value == pytest.approx(np.sqrt(3.0), abs=1e-6)


@pytest.mark.parametrize("offset", [3e4, 2e5, 5e5, 5e7])
def test_sets_far_from_the_origin_have_the_value_they_have_at_it(offset, backend):
    """A 50 mm cube and a turned one overlapping it, moved far from the origin together: the value and gradients are
    translation invariant (the native solver read overlapping sets as touching, 0, from about 1e5 mm on, when they
    were solved where they lie)."""
    from scipy.spatial.transform import Rotation

    from synergrasp.pseudo_distance import reset_regime_memory

    cube = 50.0 * np.array(np.meshgrid([0, 1], [0, 1], [0, 1])).reshape(3, -1).T
    turned = Rotation.from_rotvec([0.1, 0.2, 0.3]).apply(cube - 25.0) + [50.0, 32.0, 28.0]  # (no symmetry: one dual)
    near = sg.pseudo_distance(cube, turned, backend=backend)
    solver = sg.lp.get_backend(backend)
    solver.forget()
    reset_regime_memory()  # the separation LP first: the order that read them as touching
    far = sg.pseudo_distance(cube + offset, turned + offset, backend=solver)
    assert far.kind == near.kind == "penetration" and near.value < -30.0 and not near.degenerate
    assert far.value == pytest.approx(near.value, rel=1e-8)
    np.testing.assert_allclose(far.grad_a, near.grad_a, atol=1e-6)
    np.testing.assert_allclose(far.grad_b, near.grad_b, atol=1e-6)
