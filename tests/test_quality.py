"""Friction cones, contact wrenches and the Q distance (paper Eqs. 4-10)."""

import warnings

import numpy as np
import pytest

import synergrasp as sg

from .conftest import BACKENDS, assert_gradient, central_difference


def sphere_grasp(rng, n, radius=40.0, noise=0.0):
    P = rng.normal(size=(n, 3))
    P = radius * P / np.linalg.norm(P, axis=1)[:, None]
    N = -P / radius + noise * rng.normal(size=(n, 3))
    return P, N


def box_grasp(rng, n, half=(30.0, 20.0, 15.0)):
    half = np.asarray(half)
    face = rng.integers(0, 6, size=n)
    axis, sign = face % 3, np.where(face < 3, 1.0, -1.0)
    P = (rng.random((n, 3)) * 2 - 1) * half
    P[np.arange(n), axis] = sign * half[axis]
    N = np.zeros((n, 3))
    N[np.arange(n), axis] = -sign
    return P, N


def origin_strictly_inside(W, margin=1e-9):
    """Independent force-closure test by linear programming (not qhull, not the library's LPs).

    The origin is strictly inside conv(W) in R^6 when the wrenches span R^6 and some convex
    combination of ALL of them with every weight positive is zero: maximise t subject to
    sum_i l_i w_i = 0, sum_i l_i = 1, l_i >= t (scipy.optimize.linprog); strictly inside
    when t > margin and W has rank 6 (with positive weights on every wrench the origin is in
    the relative interior of conv(W), which is all of it exactly when the rank is 6).
    """
    from scipy.optimize import linprog

    W = np.asarray(W, dtype=float)
    k = len(W)
    if k < 7 or np.linalg.matrix_rank(W - W.mean(axis=0)) < 6:
        return False
    # variables (l_1..l_k, t); l_i - t >= 0 written as -l_i + t <= 0
    c = np.r_[np.zeros(k), -1.0]
    A_eq = np.r_[np.c_[W.T, np.zeros(6)], [np.r_[np.ones(k), 0.0]]]
    b_eq = np.r_[np.zeros(6), 1.0]
    A_ub = np.c_[-np.eye(k), np.ones(k)]
    res = linprog(c, A_ub=A_ub, b_ub=np.zeros(k), A_eq=A_eq, b_eq=b_eq,
                  bounds=[(0, None)] * k + [(None, None)], method="highs")
    if res.status == 2:  # infeasible: the origin is not in conv(W) at all
        return False
    assert res.status == 0, res.message
    return bool(-res.fun > margin)


def test_cone_edges():
    N = np.array([[0.0, 0.0, 2.0], [1.0, 1.0, 0.0], [0.3, -0.2, 0.9]])
    d = sg.friction_cone_edges(N, mu=0.4, edges=6)
    nhat = N / np.linalg.norm(N, axis=1)[:, None]
    assert d.shape == (3, 6, 3)
    assert np.allclose(np.einsum("ija,ia->ij", d, nhat), 1.0)  # Eq. 4
    tangential = d - nhat[:, None, :]
    assert np.allclose(np.linalg.norm(tangential, axis=2), 0.4)
    assert np.allclose(tangential.sum(axis=1), 0.0)  # evenly spread around the normal


def test_wrenches_are_contact_major_with_scaled_torques():
    P = np.array([[10.0, 0.0, 0.0], [0.0, 20.0, 0.0]])
    N = np.array([[-1.0, 0.0, 0.0], [0.0, -1.0, 0.0]])
    c = np.array([1.0, 2.0, 3.0])
    W = sg.contact_wrenches(P, N, mu=0.3, edges=4, center=c, torque_scale=5.0)
    d = sg.friction_cone_edges(N, mu=0.3, edges=4)
    assert W.shape == (8, 6)
    assert np.allclose(W[:4, :3], d[0]) and np.allclose(W[4:, :3], d[1])
    assert np.allclose(W[5, 3:], np.cross(P[1] - c, d[1, 1]) / 5.0)


def test_default_center_and_torque_scale():
    P, N = sphere_grasp(np.random.default_rng(0), 4)
    r = sg.q_distance(P * [1, 1, 0.5], N)
    assert np.allclose(r.center, 0.0)
    assert r.torque_scale == pytest.approx(np.linalg.norm(P * [1, 1, 0.5], axis=1).max())
    assert r.simplex.shape == (7, 6) and r.wrenches.shape == (32, 6)


@pytest.mark.parametrize("n, noise", [(5, 0.1), (3, 0.3), (2, 0.2)])
def test_gradients_match_finite_differences(backend, n, noise):
    rng = np.random.default_rng(n)
    P, N = sphere_grasp(rng, n, noise=noise)
    P = P + rng.normal(size=P.shape)
    r = sg.q_distance(P, N, backend=backend)
    L = r.torque_scale
    gp = central_difference(lambda X: sg.q_distance(X, N, torque_scale=L, backend=backend).value, P)
    gn = central_difference(lambda X: sg.q_distance(P, X, torque_scale=L, backend=backend).value, N)
    assert_gradient(r.grad_points, gp)
    assert_gradient(r.grad_normals, gn)


def test_backends_agree_on_values_and_gradients():
    rng = np.random.default_rng(7)
    for n in (2, 3, 5, 16):
        P, N = sphere_grasp(rng, n, noise=0.2)
        results = [sg.q_distance(P, N, backend=name) for name in BACKENDS]
        for r in results[1:]:
            assert r.value == pytest.approx(results[0].value, abs=1e-7)
            assert np.allclose(r.grad_points, results[0].grad_points, atol=1e-6)
            assert np.allclose(r.grad_normals, results[0].grad_normals, atol=1e-6)


def test_two_point_contacts_are_never_force_closed(backend):
    rng = np.random.default_rng(3)
    for _ in range(10):
        P, N = sphere_grasp(rng, 2, noise=0.3)
        assert not sg.q_distance(P, N, backend=backend).force_closure
    antipodal = sg.q_distance([[0, 0, 40.0], [0, 0, -40.0]], [[0, 0, -1.0], [0, 0, 1.0]], backend=backend)
    assert antipodal.value == pytest.approx(0.0, abs=1e-8)  # cannot resist torque about the axis


@pytest.mark.parametrize("n, low, high", [(3, -0.25, -0.1), (5, -0.3, -0.15)])
def test_well_spread_contacts_with_friction_are_force_closed(backend, n, low, high):
    t = 2 * np.pi * np.arange(n) / n
    P = 40.0 * np.c_[np.cos(t), np.sin(t), np.zeros(n)]
    r = sg.q_distance(P, -P, backend=backend)
    assert r.force_closure and low < r.value < high
    # with vanishing friction, normals through the centre resist no torque about it: no margin left
    assert sg.q_distance(P, -P, mu=1e-9, backend=backend).value > -1e-6


def test_the_independent_check_on_closed_forms():
    cross = np.r_[np.eye(6), -np.eye(6)]  # the 12 signed unit wrenches: the origin is their centre
    assert origin_strictly_inside(cross)
    assert not origin_strictly_inside(cross[:-1])  # without -e6 the origin lies on the facet w6 = 0
    assert not origin_strictly_inside(cross + [0, 0, 0, 0, 0, 1.0001])  # shifted off the origin
    assert not origin_strictly_inside(np.r_[cross[:, :5], -cross[:, :5]] @ np.eye(5, 6))  # spans 5 dimensions only
    simplex = sg.regular_simplex(6)  # 7 vertices around the origin, inradius 1/6
    assert origin_strictly_inside(simplex) and not origin_strictly_inside(simplex[:6])
    assert origin_strictly_inside(simplex + 0.9 * simplex[0] / 6)  # the facet opposite q0 moved to 1/60 of the origin
    assert not origin_strictly_inside(simplex + 1.1 * simplex[0] / 6)  # ... and past it


@pytest.mark.parametrize("closed", [True, False])
def test_library_hull_test_matches_the_independent_one(closed):
    rng = np.random.default_rng(5)
    checked = 0
    for trial in range(60):
        P, N = sphere_grasp(rng, int(rng.integers(3, 6)) if closed else 2, noise=0.3)
        W = sg.contact_wrenches(P, N)
        if abs(sg.q_distance(P, N).value) < 1e-6:  # on the boundary either answer is within round-off
            continue
        assert sg.force_closure_by_hull(W) == origin_strictly_inside(W), f"trial {trial}"
        assert sg.force_closure_by_hull(W * 1e-10) == sg.force_closure_by_hull(W * 1e10) == sg.force_closure_by_hull(W)
        checked += 1
    assert checked >= 40


def test_force_closure_agrees_with_convex_hull():
    rng = np.random.default_rng(2024)
    checked, closed = 0, 0
    for trial in range(140):
        n = int(rng.integers(2, 7))
        P, N = sphere_grasp(rng, n, noise=0.25) if trial % 2 else box_grasp(rng, n)
        r = sg.q_distance(P, N, mu=0.3, edges=8)
        if abs(r.value) < 1e-6:  # on the boundary: either answer is within tolerance
            continue
        assert r.force_closure == origin_strictly_inside(r.wrenches), f"trial {trial}: Q = {r.value}"
        checked += 1
        closed += r.force_closure
    assert checked >= 100 and 20 <= closed <= checked - 20  # both outcomes well represented


@pytest.mark.parametrize(
    "kwargs, error, match",
    [
        ({"normals": [[0, 0, 0.0], [0, 0, 1.0]]}, ValueError, "zero-length rows \\[0\\]"),
        ({"normals": [[0, 0, -1e200], [0, 0, 0.0]]}, ValueError, "zero-length rows \\[1\\]"),  # beside a huge one
        ({"normals": [[0, 0, 1.0]]}, ValueError, "one normal per contact"),
        ({"points": [[0, 0, np.nan], [1, 0, 0]]}, ValueError, "points contains NaN"),
        ({"points": [[0, 0], [1, 0]]}, ValueError, "dimension 2, expected 3"),
        ({"points": np.zeros((0, 3)), "normals": np.zeros((0, 3))}, ValueError, "points is empty"),
        ({"mu": 0.0}, ValueError, "mu must be a finite number > 0"),
        ({"mu": -0.3}, ValueError, "mu must be"),
        ({"edges": 2}, ValueError, "edges must be an integer from 3 to 1000"),
        ({"edges": 4.5}, ValueError, "edges must be an integer"),
        ({"center": [0, 0]}, ValueError, "center must have shape \\(3,\\)"),
        ({"torque_scale": 0.0}, ValueError, "torque_scale must be"),
        ({"torque_scale": 1e-9}, ValueError, "torque_scale 1e-09 is more than 10000 times smaller than the "
                                             "contacts' largest lever arm .*, 10"),
        ({"backend": "glpk"}, ValueError, "unknown LP backend"),
    ],
)
def test_bad_input(kwargs, error, match):
    args = {"points": [[0, 0, 10.0], [0, 0, -10.0]], "normals": [[0, 0, -1.0], [0, 0, 1.0]]}
    args.update(kwargs)
    with pytest.raises(error, match=match):
        sg.q_distance(args.pop("points"), args.pop("normals"), **args)


@pytest.mark.parametrize("scale", [1e-200, 1e-6, 1e6, 1e154, 1e200])
def test_the_q_distance_does_not_depend_on_the_units(scale, backend):
    """Q is scale-invariant with the default torque scale (its square would overflow past about 1e154 or underflow
    below 1e-154); lever arms that overflow are refused."""
    P, N = sphere_grasp(np.random.default_rng(1), 5)
    assert sg.q_distance(P * scale, N, backend=backend).value == pytest.approx(sg.q_distance(P, N, backend=backend).value,
                                                                               rel=1e-9, abs=1e-12)
    with pytest.raises(ValueError, match="lever arms .* overflow"):
        sg.q_distance([[1e308, 0.0, 0.0], [1e308, 1.0, 0.0]], N[:2], center=[-1e308, 0.0, 0.0], backend=backend)


def test_a_large_torque_scale_is_taken_and_flattens_the_torques(backend):
    """A torque scale far above the lever arms (an object's radius given for contacts near its centre) is taken, and
    consistent: the torque coordinates shrink as 1/L, so the grasp's Q (its depth in them) falls as 1/L, to 0."""
    P, N = sphere_grasp(np.random.default_rng(1), 5)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # beyond 100 times the lever arms: warned of (the test below)
        q = {L: sg.q_distance(P, N, torque_scale=L, backend=backend).value for L in (4e3, 4e4, 1e12)}
    assert q[4e3] < 0 and q[4e3] * 4e3 == pytest.approx(q[4e4] * 4e4, rel=1e-3)
    assert abs(q[1e12]) < 1e-8


def test_a_torque_scale_in_other_units_than_the_points_is_warned_of():
    """Points in mm with L in metres, or points in metres with L in mm: Q is 1000 times off scale, so a warning says
    so; within a factor of 100 of the largest lever arm (and by default) nothing is said."""
    P = np.array([[40.0, 0, 0], [-20, 35, 0], [-20, -35, 0], [0, 0, 40]])
    N = -P / np.linalg.norm(P, axis=1, keepdims=True)
    for points, L, word in ((P, 0.04, "smaller"), (P / 1000, 40.0, "larger")):
        with pytest.warns(UserWarning, match=f"times {word} than the contacts' largest lever arm"):
            sg.q_distance(points, N, torque_scale=L)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        for L in (None, 0.5, 3000.0):
            sg.q_distance(P, N, torque_scale=L)


def test_contacts_at_the_centre_need_a_torque_scale(backend):
    """Without a torque scale there is none to take; with one, the torques are all 0 and any scale gives the same
    Q: six opposed normals at one point close the forces and no torque, so Q is 0 (the edge of force closure)."""
    with pytest.raises(ValueError, match="pass torque_scale"):
        sg.q_distance([[0, 0, 0.0]], [[0, 0, 1.0]])
    normals = np.vstack([np.eye(3), -np.eye(3)])
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        q = [sg.q_distance(np.ones((6, 3)), normals, center=[1, 1, 1], torque_scale=L, backend=backend).value
             for L in (1e-3, 10.0, 1e6)]
        assert sg.contact_wrenches([[1.0, 2, 3]], [[0, 0, 1.0]], center=[1, 2, 3], torque_scale=10.0)[:, 3:].max() == 0
    assert q == pytest.approx([0.0] * 3, abs=1e-9)


def test_contacts_far_from_the_default_centre_are_warned_of():
    """Without ``center`` the torques are about the origin: contacts 17 m from it give a Q near the
    forces-only value, with a warning; with the centre given, the value of the grasp at the origin."""
    p = np.array([[0.0, 0.0, 40.0], [0.0, 0.0, -40.0], [40.0, 0.0, 0.0]])
    n = -p / np.linalg.norm(p, axis=1, keepdims=True)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        near = sg.q_distance(p, n).value
        centred = sg.q_distance(p + 1e4, n, center=[1e4] * 3).value
    with pytest.warns(UserWarning, match=r"torques are taken about the origin.*Pass center="):
        far = sg.q_distance(p + 1e4, n).value
    assert centred == pytest.approx(near, abs=1e-9) and abs(far) < 0.01 * abs(near)
    with warnings.catch_warnings(record=True) as caught:  # also where the distance's square overflows: no
        warnings.simplefilter("always")                   # overflow warning of numpy's, the library's own instead
        sg.q_distance(p * 1e199 + 1e202, n)
    assert [str(w.message)[:49] for w in caught] == ["the torques are taken about the origin, 1.74e+202"]


#: Three contacts at the edge of force closure (HiGHS: Q = -0.0): the native simplex cycled in one penetration block
#: (pivots its refactorised basis undid, 1861 of them) and raised LPError.
EDGE_OF_CLOSURE = (
    [["0x1.3f0a87302d75bp+5", "-0x1.8c105f0b7c4f0p+1", "0x1.fe8aa13b47ff2p+5"],
     ["-0x1.1db1d7cde8662p+4", "0x1.1e58d875d97a2p+5", "-0x1.f2ca5d8b83863p+7"],
     ["-0x1.db524f149c064p+4", "-0x1.ac911615c0d82p+4", "-0x1.bac5bca50ef5fp+7"]],
    [["-0x1.2054409ab5866p+5", "0x1.82f5b5b1ed4c0p-2", "0x1.9f3dc64557190p+1"],
     ["0x1.66dd277577435p+4", "-0x1.181f8b360d12dp+5", "0x1.a9012d4b65427p+0"],
     ["0x1.1c83c8c4bf49ep+5", "0x1.a31fb00acda5ep+4", "-0x1.c76daf089ba3cp+0"]],
    "0x1.26c7a7ee045a2p+0")


def test_a_grasp_at_the_edge_of_force_closure_has_q_0_on_the_simplex_backends():
    """Checked independently: scipy's LP of Eq. 1 between the wrenches' hull and the origin gives 0."""
    from scipy.optimize import linprog

    P, N = (np.array([[float.fromhex(v) for v in row] for row in rows]) for rows in EDGE_OF_CLOSURE[:2])
    mu = float.fromhex(EDGE_OF_CLOSURE[2])
    W = sg.contact_wrenches(P, N, mu=mu, center=np.zeros(3), torque_scale=40.0)
    Q, k = sg.regular_simplex(6), len(W)
    A = np.zeros((7, 7 + k))
    A[:6, :7], A[:6, 7:], A[6, 7:] = Q.T, W.T, 1.0
    separation = linprog(np.r_[np.ones(7), np.zeros(k)], A_eq=A, b_eq=np.r_[np.zeros(6), 1.0], bounds=(0, None)).fun
    assert abs(separation) < 1e-9
    for backend in ("native", "highs"):
        q = sg.q_distance(P, N, mu=mu, center=np.zeros(3), torque_scale=40.0, backend=backend)
        assert abs(q.value) < 1e-7, backend


def test_normals_of_any_length_give_the_same_q(backend):
    """The normals are normalised: tiny (1e-13 was refused as zero-length) or huge, the same Q and the same
    derivative along the unit normal."""
    P, N = sphere_grasp(np.random.default_rng(1), 5)
    base = sg.q_distance(P, N, backend=backend)
    for scale in (1e-200, 1e-13, 1e200):
        r = sg.q_distance(P, N * scale, backend=backend)
        assert r.value == pytest.approx(base.value, abs=1e-9)
        assert np.allclose(r.grad_normals * scale, base.grad_normals, atol=1e-7)
    contacts = sg.contact_wrenches(P, np.vstack([N[:1] * 1e-200, N[1:] * 1e200]))
    assert np.allclose(contacts, sg.contact_wrenches(P, N), atol=1e-12)


def test_checked_inputs_give_the_same_result_and_mu_is_still_checked(backend):
    """``checked=True`` (the planner's own contacts) skips the array checks, not the result or mu's check."""
    P, N = sphere_grasp(np.random.default_rng(2), 5, noise=0.2)
    N = N * np.linspace(0.5, 3.0, 5)[:, None]  # normals of other lengths are normalised the same way
    kwargs = dict(mu=0.4, edges=6, center=np.array([1.0, -2.0, 0.5]), torque_scale=45.0, backend=backend)
    for _ in range(2):  # the second round starts from the same warm state (the LP's last basis and regime)
        full, fast = sg.q_distance(P, N, **kwargs), sg.q_distance(P, N, checked=True, **kwargs)
    assert fast.value == full.value and fast.force_closure == full.force_closure
    for name in ("grad_points", "grad_normals", "wrenches", "center"):
        assert np.array_equal(getattr(fast, name), getattr(full, name))
    with pytest.raises(ValueError, match="mu must be"):
        sg.q_distance(P, N, checked=True, **{**kwargs, "mu": -1.0})
    with pytest.raises(ValueError, match="edges must be"):
        sg.q_distance(P, N, checked=True, **{**kwargs, "edges": 2})
