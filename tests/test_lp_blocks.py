"""synergrasp.lp.blocks (stacked 4-row LP blocks with basis memory) and HiGHS's in-place updates."""

import itertools

import numpy as np
import pytest

import synergrasp as sg
from synergrasp.lp import Backend, get_backend
from synergrasp.lp.blocks import BasisMemory, Blocks, solve_blocks
from synergrasp.lp.highs import HighsBackend
from solvers.references import TimedBackend

Q = sg.regular_simplex(3)


def random_blocks(rng, n_blocks=7):
    """Separation LP blocks (paper Eq. 1, A = {p}) of random points against random convex point sets."""
    table = rng.normal(size=(60, 3)) * 10.0
    counts = rng.integers(4, 9, size=n_blocks)
    ids = np.concatenate([rng.choice(len(table), c, replace=False) for c in counts])
    P = rng.normal(size=(n_blocks, 3)) * 40.0
    return Blocks.uniform(Q, np.ones(4), table, ids, counts, -1.0, -P, P, keys=np.arange(n_blocks)), P


def test_stacked_blocks_are_the_separate_lps(backend, rng):
    """Each block's value, witness and duals are those of the pseudo-distance LP of its point and vertices alone."""
    blocks, P = random_blocks(rng)
    sol = solve_blocks(get_backend(backend), blocks)
    assert sol.lp_solves == 1
    starts = np.concatenate([[0], np.cumsum(blocks.n_vert)])
    for b in range(len(P)):
        V = blocks.table[blocks.ids[starts[b]:starts[b + 1]]]
        ref = sg.pseudo_distance([P[b]], V, backend="highs")
        if ref.kind != "separation":
            continue
        assert sol.lead_x[4 * b:4 * b + 4].sum() == pytest.approx(ref.value, abs=1e-7)
        assert sol.witness[b] == pytest.approx(ref.point_b, abs=1e-6)
        if not (ref.degenerate or sol.degenerate[b]):
            assert -sol.y[b] == pytest.approx(ref.grad_a[0], abs=1e-6)  # d value / d p = -y


def test_a_column_limit_splits_the_blocks_into_several_lps_with_the_same_results(rng):
    blocks, _ = random_blocks(rng, 12)
    whole = solve_blocks(HighsBackend(), blocks)

    class Narrow(HighsBackend):
        max_columns = 30

    split = solve_blocks(Narrow(), blocks)
    assert whole.lp_solves == 1 and split.lp_solves > 2
    assert split.lead_x == pytest.approx(whole.lead_x, abs=1e-9)
    assert split.witness == pytest.approx(whole.witness, abs=1e-9)
    assert split.y == pytest.approx(whole.y, abs=1e-9)


def test_backend_column_limits_are_backend_attributes():
    assert get_backend("cvxpy").max_columns == 400
    assert get_backend("highs").max_columns is None and Backend.max_columns is None
    assert TimedBackend("cvxpy").max_columns == 400


def test_the_memory_warm_starts_without_changing_the_optimum(rng):
    blocks, _ = random_blocks(rng)
    memory = BasisMemory()
    cold = solve_blocks(HighsBackend(warm_start=False), blocks)
    first = solve_blocks(HighsBackend(), blocks, memory)
    assert len(memory) > 0
    moved = blocks._replace(origin=blocks.origin + 0.5, rhs=blocks.rhs - 0.5)  # the points moved a little
    again = solve_blocks(HighsBackend(), moved, memory)
    reference = solve_blocks(HighsBackend(warm_start=False), moved)
    assert first.lead_x == pytest.approx(cold.lead_x, abs=1e-9)
    assert again.lead_x == pytest.approx(reference.lead_x, abs=1e-9)
    assert again.y == pytest.approx(reference.y, abs=1e-9)


def test_the_memory_replaces_only_the_blocks_it_is_told_of():
    memory, span = BasisMemory(), BasisMemory.SPAN
    memory.remember(np.array([1, 1, 2, 2]) * span + np.array([7, 9, 7, 12]), np.array([True, False, True, True]))
    memory.remember(np.array([2, 2]) * span + np.array([7, 12]), np.array([False, True]))
    assert memory.basic(np.array([1, 2, 2]) * span + np.array([7, 7, 12])).tolist() == [True, False, True]


def test_the_memory_keeps_each_blocks_last_basic_columns(rng):
    """Against a plain model: a dictionary from block key to the set of its last basic columns."""
    memory, model, span = BasisMemory(), {}, BasisMemory.SPAN
    for _ in range(300):
        keys = rng.choice(40, rng.integers(0, 10), replace=False)
        columns = [rng.choice(60, rng.integers(1, 9), replace=False) for _ in keys]
        codes = np.array([k * span + c for k, cs in zip(keys, columns) for c in cs], dtype=np.int64)
        basic = rng.random(len(codes)) < 0.4
        memory.remember(codes, basic)
        for k in keys:
            model[k] = set()
        for code, b in zip(codes, basic):
            if b:
                model[code // span].add(code % span)
        probe = np.array([k * span + c for k in range(40) for c in range(60)], dtype=np.int64)
        expected = [c % span in model.get(c // span, set()) for c in probe]
        assert memory.basic(probe).tolist() == expected
        assert len(memory) == sum(len(v) for v in model.values())


def _sequence(rng, n=12):
    """LPs of one structure (same sparsity pattern), different data: min c x s.t. A x = b, x >= 0."""
    pattern = rng.random((5, 14)) < 0.6
    pattern[:, :5] |= np.eye(5, dtype=bool)
    out = []
    for _ in range(n):
        A = np.where(pattern, rng.normal(size=pattern.shape), 0.0)
        A[:, :5] = np.where(np.eye(5, dtype=bool), np.abs(A[:, :5]) + 1.0, A[:, :5])
        out.append((rng.random(14) + 0.1, A, A @ rng.random(14)))
    return out


def test_highs_solves_a_repeated_structure_in_place_with_the_results_of_a_new_model(rng):
    """Columns swapped in place (and a changed right-hand side applied): the same optimum as a cold solve."""
    seq = _sequence(rng)
    warm, cold = HighsBackend(), HighsBackend(warm_start=False)
    for c, A, b in seq:
        w, r = warm.solve(c, A, b), cold.solve(c, A, b)
        assert w.status == r.status == "optimal"
        assert w.objective == pytest.approx(r.objective, abs=1e-9)
        assert np.allclose(w.y, r.y, atol=1e-8) and np.allclose(A @ w.x, b, atol=1e-9)
    assert warm.in_place == len(seq) - 1 and cold.in_place == 0
    # another structure in between does not disturb the model kept for this one
    other = _sequence(np.random.default_rng(1), 1)[0]
    warm.solve(*other)
    c, A, b = seq[0]
    assert warm.solve(c, A, b).objective == pytest.approx(cold.solve(c, A, b).objective, abs=1e-9)
    assert warm.in_place == len(seq)


def test_an_infeasible_lp_in_place_is_reported_and_the_next_one_solved(rng):
    c, A, _ = _sequence(rng, 1)[0]
    A = np.abs(A)  # non-negative: A x = b >= 0 for x >= 0, so a negative right-hand side is infeasible
    b = A @ rng.random(A.shape[1])
    be, cold = HighsBackend(), HighsBackend(warm_start=False)
    assert be.solve(c, A, b).optimal
    assert be.solve(c, A, -np.ones(len(b))).status == "infeasible"
    assert be.solve(c, A, b).objective == pytest.approx(cold.solve(c, A, b).objective, abs=1e-9)


def test_blocks_example_value_is_the_gauge_closed_form():
    """The doctest's cube: straight above the top face the separation is the Euclidean gap."""
    cube = np.array(list(itertools.product([-10.0, 10.0], repeat=3)))
    p = np.array([[3.0, -2.0, 40.0]])
    sol = solve_blocks(get_backend("highs"), Blocks.uniform(Q, np.ones(4), cube, np.arange(8), [8], -1.0, -p, p))
    assert sol.lead_x.sum() == pytest.approx(30.0, abs=1e-9)
