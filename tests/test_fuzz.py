"""Fuzzing the entry points users feed their own numbers: q_distance, pseudo_distance, from_points, from_mesh.

Random shapes, NaN and inf, duplicated and collinear points, extreme scales. Every example must end
in a result that makes sense or in a ValueError / TypeError raised by synergrasp itself whose
message names the problem, never in an exception from inside numpy, a solver, qhull or trimesh.
"""

import os
import warnings

import numpy as np
import pytest
import trimesh
from hypothesis import HealthCheck, assume, example, given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

import synergrasp as sg
import synergrasp.objects as so

from .test_catalogue import raised_in_synergrasp

#: Deterministic examples by default; SYNERGRASP_FUZZ_EXAMPLES=N draws N fresh random ones per test (a longer hunt).
HUNT = int(os.environ.get("SYNERGRASP_FUZZ_EXAMPLES", "0"))
FUZZ = settings(deadline=None, derandomize=not HUNT, database=None, max_examples=HUNT or 100,
                suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])

#: Floats a user's data may hold: ordinary values, extreme magnitudes, signed zeros, NaN and inf.
values = st.one_of(
    st.floats(-100.0, 100.0),
    st.floats(allow_nan=True, allow_infinity=True),
    st.sampled_from([0.0, -0.0, 1e-300, -1e300, 1e300, np.nan, np.inf, -np.inf]),
)


def point_sets(min_rows=0, max_rows=8, dims=st.integers(1, 4)):
    return dims.flatmap(lambda d: arrays(np.float64, st.tuples(st.integers(min_rows, max_rows), st.just(d)), elements=values))


def expect_clear(call, *names):
    """Run ``call``; an error must be a ValueError or TypeError of synergrasp's, naming one of ``names``."""
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            return call()
    except (ValueError, TypeError) as exc:
        assert raised_in_synergrasp(exc), f"from inside a dependency: {type(exc).__name__}: {exc}"
        assert any(name in str(exc) for name in names), f"message names none of {names}: {exc}"
        return None


@FUZZ
@given(A=point_sets(), B=point_sets())
@example(A=np.array([[1000001.0, 1000001.0]]), B=np.array([[1000001.0, 1000001.0]]))  # far away, no spread
def test_pseudo_distance_takes_any_arrays(A, B):
    r = expect_clear(lambda: sg.pseudo_distance(A, B), "A ", "B ", "A and B", "pseudo-distance")
    if r is None:
        return
    assert np.isfinite(A).all() and np.isfinite(B).all() and len(A) and len(B) and A.shape[1] == B.shape[1] >= 2
    assert np.isfinite(r.value) and r.grad_a.shape == A.shape and r.grad_b.shape == B.shape
    assert np.isfinite(r.grad_a).all() and np.isfinite(r.grad_b).all()
    assert r.kind == ("separation" if r.value > 0 else "penetration" if r.value < 0 else r.kind)


@FUZZ
@given(seed=st.integers(0, 2**32 - 1), exponent=st.integers(-250, 250), shift=st.floats(-1e6, 1e6),
       na=st.integers(1, 6), nb=st.integers(1, 6), duplicate=st.booleans(), collinear=st.booleans())
def test_pseudo_distance_scales_with_the_data(seed, exponent, shift, na, nb, duplicate, collinear):
    """Any scale: d(sA + t, sB + t) = s d(A, B); duplicated or collinear points change nothing."""
    rng = np.random.default_rng(seed)
    A, B = rng.normal(size=(na, 3)) * 10, rng.normal(size=(nb, 3)) * 10 + rng.normal(size=3) * 30
    if collinear:
        A = np.outer(rng.normal(size=na), [1.0, 2.0, -1.0])
    if duplicate:
        A = np.vstack([A, A[:1]])
    base = sg.pseudo_distance(A, B)
    s = 10.0**exponent
    moved = sg.pseudo_distance(A * s + shift * s, B * s + shift * s)
    assert moved.value == pytest.approx(base.value * s, rel=1e-6, abs=1e-6 * s * (1 + abs(shift)))


normals_or_points = arrays(np.float64, st.tuples(st.integers(0, 6), st.integers(2, 4)), elements=values)


@FUZZ
@given(points=normals_or_points, normals=normals_or_points,
       mu=st.one_of(st.floats(allow_nan=True, allow_infinity=True), st.just(0.3)),
       edges=st.one_of(st.integers(-2, 40), st.just(8)))
def test_q_distance_takes_any_arrays(points, normals, mu, edges):
    r = expect_clear(lambda: sg.q_distance(points, normals, mu=mu, edges=edges), "points", "normals", "mu ", "edges", "torque_scale")
    if r is not None:
        assert np.isfinite(r.value) and r.force_closure == (r.value < -sg.quality.FORCE_CLOSURE_TOL)
        assert np.isfinite(r.grad_points).all() and np.isfinite(r.grad_normals).all()


@FUZZ
@given(seed=st.integers(0, 2**32 - 1), n=st.integers(1, 6), repeat=st.integers(1, 3), exponent=st.integers(-6, 6),
       collinear=st.booleans())
def test_q_distance_of_real_contacts_at_any_scale(seed, n, repeat, exponent, collinear):
    """Contacts on a sphere (repeated, collinear, tiny or huge): the same Q at every scale, force closure as by the hull."""
    rng = np.random.default_rng(seed)
    P = rng.normal(size=(n, 3))
    if collinear:
        P = np.outer(rng.normal(size=n), [0.0, 0.0, 1.0]) + 1e-3 * rng.normal(size=(n, 3))
    P = np.repeat(P / np.linalg.norm(P, axis=1, keepdims=True), repeat, axis=0) * 40.0
    N = -P
    base = sg.q_distance(P, N)
    scaled = sg.q_distance(P * 10.0**exponent, N)
    assert scaled.value == pytest.approx(base.value, abs=1e-7)
    if abs(base.value) > 1e-6:
        assert base.force_closure == sg.force_closure_by_hull(base.wrenches)


shapes = st.sampled_from(["sphere", "box", "plane", "line", "one point", "duplicates", "random"])


@FUZZ
@given(shape=shapes, n=st.integers(0, 60), exponent=st.integers(-9, 9), seed=st.integers(0, 2**32 - 1),
       poison=st.sampled_from([None, np.nan, np.inf, -np.inf]))
def test_from_points_takes_any_cloud(shape, n, exponent, seed, poison):
    rng = np.random.default_rng(seed)
    pts = rng.normal(size=(n, 3))
    if shape == "sphere":
        pts = pts / np.maximum(np.linalg.norm(pts, axis=1, keepdims=True), 1e-12)
    elif shape == "box":
        pts = np.clip(pts, -1, 1)
    elif shape == "plane":
        pts[:, 2] = 0.0
    elif shape == "line":
        pts = np.outer(pts[:, 0], [1.0, -2.0, 0.5])
    elif shape == "one point":
        pts = np.zeros((n, 3)) + 3.0
    elif shape == "duplicates":
        pts = np.repeat(pts[: max(1, n // 4)], 4, axis=0)
    pts = pts * 30.0 * 10.0**exponent
    if poison is not None and len(pts):
        pts[rng.integers(len(pts)), rng.integers(3)] = poison
    obj = expect_clear(lambda: so.from_points(pts, cache=False), "NaN or inf", "no volume", "empty", "mm across")
    if obj is None:
        return
    assert np.isfinite(pts).all() and obj.n_pieces >= 1
    assert np.isfinite(obj.center).all() and obj.contains([obj.center])[0]
    assert np.isfinite(obj.torque_scale) and obj.torque_scale > 0
    assert obj.extents == pytest.approx(np.ptp(pts, axis=0), rel=1e-9, abs=1e-9 * obj.size)


@settings(FUZZ, max_examples=HUNT or 30)  # a torn mesh is closed on a voxel grid: the slowest case, fewer examples
@given(base=st.sampled_from(["box", "sphere", "cylinder"]), drop=st.floats(0.0, 0.6), seed=st.integers(0, 2**32 - 1),
       exponent=st.integers(-7, 7), duplicate_faces=st.booleans(), poison=st.sampled_from([None, np.nan, np.inf]),
       flip=st.booleans())
def test_from_mesh_takes_any_mesh(base, drop, seed, exponent, duplicate_faces, poison, flip):
    """Meshes with holes torn in them, duplicate or flipped faces, non-finite vertices, any scale."""
    rng = np.random.default_rng(seed)
    mesh = {"box": lambda: trimesh.creation.box((60.0, 40.0, 30.0)),
            "sphere": lambda: trimesh.creation.icosphere(subdivisions=2, radius=30.0),
            "cylinder": lambda: trimesh.creation.cylinder(radius=20.0, height=60.0, sections=16)}[base]()
    faces = mesh.faces[rng.random(len(mesh.faces)) >= drop]
    assume(len(faces) > 0)
    if duplicate_faces:
        faces = np.vstack([faces, faces[: max(1, len(faces) // 5)]])
    if flip:
        faces[0] = faces[0, ::-1]
    vertices = mesh.vertices * 10.0**exponent
    if poison is not None:
        vertices[faces[0, 0], 0] = poison
    broken = trimesh.Trimesh(vertices, faces, process=False)
    obj = expect_clear(lambda: so.from_mesh(broken, name="fuzzed", cache=False), "fuzzed")
    if obj is None:
        return
    assert np.isfinite(vertices).all() and obj.n_pieces >= 1
    assert np.isfinite(obj.center).all() and obj.contains([obj.center])[0] and obj.torque_scale > 0
