"""The native backend (a dense simplex per independent block): optimality certificates, blocks, warm starts."""

import numpy as np
import pytest
import scipy.linalg

import synergrasp as sg
from synergrasp.lp.native import NativeBackend


def kkt_error(c, A, b, sol):
    """The largest violation of the optimality conditions of ``min c x, A x = b, x >= 0`` by (x, y)."""
    x, y = sol.x, sol.y
    reduced = c - A.T @ y
    return max(np.abs(A @ x - b).max(), -x.min(), -reduced.min(), abs(reduced @ x))


def random_lps(seed, count):
    """Feasible, infeasible and unbounded LPs, some with integer data (ties and degenerate vertices)."""
    rng = np.random.default_rng(seed)
    for _ in range(count):
        m, n = int(rng.integers(1, 8)), int(rng.integers(1, 20))
        A = rng.normal(size=(m, n))
        kind = rng.integers(3)
        if kind == 2:
            A = np.round(2 * A)
        x0 = np.abs(rng.normal(size=n)) * (rng.random(n) < 0.5)
        b = rng.normal(size=m) if kind == 1 else A @ x0
        c = rng.normal(size=n) if rng.random() < 0.6 else np.abs(rng.normal(size=n))
        if kind == 2:
            c = np.round(2 * c)
        yield c, A, b


def test_random_lps_optimal_with_certificate_and_statuses_as_highs():
    """Each optimum is certified by its own primal and dual (feasible, complementary), and the status and
    optimal value are HiGHS's."""
    native, highs = NativeBackend(), sg.lp.get_backend("highs")
    statuses = set()
    for c, A, b in random_lps(0, 400):
        ours, ref = native.solve(c, A, b), highs.solve(c, A, b)
        assert ours.status == ref.status
        statuses.add(ours.status)
        if ours.optimal:
            assert kkt_error(c, A, b, ours) < 1e-8 * (1 + np.abs(A).max() * (1 + np.abs(ours.x).max()))
            assert ours.objective == pytest.approx(ref.objective, rel=1e-9, abs=1e-9)
    assert statuses == {"optimal", "infeasible", "unbounded"}


def test_beale_cycling_example_terminates_at_the_optimum():
    """Beale's LP, on which Dantzig's rule with the lowest-index ties cycles: Bland's rule after a run of
    degenerate pivots ends it, at the optimum 5/4 (maximised; x = (3/4, 0, 0, 1, 0, 1, 0))."""
    c = -np.array([0.0, 0.0, 0.0, 0.75, -20.0, 0.5, -6.0])
    A = np.array([[1.0, 0.0, 0.0, 0.25, -8.0, -1.0, 9.0],
                  [0.0, 1.0, 0.0, 0.5, -12.0, -0.5, 3.0],
                  [0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 0.0]])
    b = np.array([0.0, 0.0, 1.0])
    sol = NativeBackend().solve(c, A, b, basic=np.array([True, True, True, False, False, False, False]))
    assert sol.status == "optimal" and sol.objective == pytest.approx(-1.25, abs=1e-12)
    assert np.allclose(sol.x, [0.75, 0.0, 0.0, 1.0, 0.0, 1.0, 0.0], atol=1e-12)
    assert kkt_error(c, A, b, sol) < 1e-12


def test_independent_blocks_are_solved_as_separate_lps():
    """Rows of three blocks interleaved (and their columns shuffled) give each block's own optimum and duals."""
    rng = np.random.default_rng(3)
    blocks = []
    for m, n in ((4, 9), (2, 5), (4, 12)):
        A = rng.normal(size=(m, n))
        blocks.append((rng.random(n) + 0.1, A, A @ rng.random(n)))
    A = scipy.linalg.block_diag(*(blk[1] for blk in blocks))
    c, b = np.concatenate([blk[0] for blk in blocks]), np.concatenate([blk[2] for blk in blocks])
    rows, cols = rng.permutation(len(b)), rng.permutation(len(c))
    whole = NativeBackend().solve(c[cols], A[rows][:, cols], b[rows])
    x, y = np.empty(len(c)), np.empty(len(b))
    x[cols], y[rows] = whole.x, whole.y
    highs = sg.lp.get_backend("highs")
    r0 = c0 = 0
    for cb, Ab, bb in blocks:
        alone = highs.solve(cb, Ab, bb)
        m, n = Ab.shape
        assert np.allclose(x[c0:c0 + n], alone.x, atol=1e-9) and np.allclose(y[r0:r0 + m], alone.y, atol=1e-9)
        r0, c0 = r0 + m, c0 + n


def test_one_bad_block_decides_the_status():
    good = ([1.0, 1.0], [[1.0, -1.0]], [1.0])
    native = NativeBackend()
    # a second block x2 + x3 = -1 (infeasible), then -x2 unbounded below with x2 - x3 = 0
    A = [[1.0, -1.0, 0.0, 0.0], [0.0, 0.0, 1.0, 1.0]]
    assert native.solve([1.0, 1.0, 0.0, 0.0], A, [1.0, -1.0]).status == "infeasible"
    A = [[1.0, -1.0, 0.0, 0.0], [0.0, 0.0, 1.0, -1.0]]
    assert native.solve([1.0, 1.0, -1.0, 0.0], A, [1.0, 0.0]).status == "unbounded"
    assert native.solve(*good).status == "optimal"
    # an infeasible block wins over an unbounded one, whichever comes first, and over a free column of negative cost
    A = [[1.0, -1.0, 0.0, 0.0, 0.0], [0.0, 0.0, 1.0, -1.0, 0.0], [0.0, 0.0, 0.0, 0.0, 1.0]]
    for b in ([-1.0, 0.0, -1.0], [1.0, 0.0, -1.0]):
        assert native.solve([-1.0, 0.0, 0.0, 0.0, 1.0], A, b).status == "infeasible"
        assert native.solve([0.0, 0.0, -1.0, 0.0, 1.0], A, b).status == "infeasible"
    assert native.solve([0.0, -1.0, 0.0], [[1.0, 0.0, 0.0], [0.0, 0.0, 1.0]], [-1.0, 1.0]).status == "infeasible"


def test_empty_rows_and_columns():
    native = NativeBackend()
    # a column without entries stays at 0 (cost >= 0), or makes the LP unbounded (cost < 0)
    sol = native.solve([1.0, 2.0], [[1.0, 0.0]], [3.0])
    assert sol.optimal and sol.x.tolist() == [3.0, 0.0] and sol.y.tolist() == [1.0]
    assert native.solve([1.0, -2.0], [[1.0, 0.0]], [3.0]).status == "unbounded"
    # a row without entries: 0 = 0 has dual 0; 0 = 1 is infeasible
    sol = native.solve([1.0], [[1.0], [0.0]], [3.0, 0.0])
    assert sol.optimal and sol.y.tolist() == [1.0, 0.0]
    assert native.solve([1.0], [[1.0], [0.0]], [3.0, 1.0]).status == "infeasible"


def test_redundant_rows_keep_an_optimal_certificate():
    """A row repeated (and one that is the sum of two others): the artificial of a redundant row stays basic
    at zero, and the duals still certify the optimum."""
    rng = np.random.default_rng(5)
    A = rng.normal(size=(3, 8))
    A = np.vstack([A, A[0], A[1] + A[2]])
    c, b = rng.random(8) + 0.1, A @ rng.random(8)
    sol = NativeBackend().solve(c, A, b)
    assert sol.optimal and kkt_error(c, A, b, sol) < 1e-9
    assert sol.objective == pytest.approx(sg.lp.get_backend("highs").solve(c, A, b).objective, rel=1e-10)


def test_a_block_infeasible_only_by_its_datas_round_off_is_optimal_as_highs_says():
    """One block of the penetration LP of a point 1e-9 off a segment's end: entries of 1e-9 beside entries
    near 1 leave every basis about 2e-9 below 0, which round-off restarts cannot mend. That is within what
    phase 1 accepts as feasible: the block is optimal (HiGHS agrees), its values clipped to 0."""
    A = np.array([[np.sqrt(2 / 3), 1e-9, 1.0, 0.0], [np.sqrt(2) / 3, 1e-9, 0.0, 0.0], [1 / 3, 1e-9, 0.0, 0.0],
                  [0.0, 1.0, 0.0, 0.0], [0.0, 0.0, 1.0, 1.0]])
    c, b = np.array([-1.0, 0.0, 0.0, 0.0]), np.array([0.0, 0.0, 0.0, 1.0, 1.0])
    ref = sg.lp.get_backend("highs").solve(c, A, b)
    for native in (NativeBackend(), NativeBackend(warm_start=False)):
        sol = native.solve(c, A, b)
        assert sol.optimal and ref.optimal
        assert sol.objective == pytest.approx(ref.objective, abs=1e-8)
        assert sol.x.min() >= 0.0 and np.abs(A @ sol.x - b).max() < 1e-8


def test_any_hint_reaches_the_optimum_and_the_optimal_one_takes_no_pivot():
    """Hints that give infeasible, singular or partial bases (the warm start then adds one artificial column
    that lifts every negative basic value) all end at the LP's optimum."""
    rng = np.random.default_rng(7)
    native = NativeBackend()
    for _ in range(60):
        m, n = int(rng.integers(2, 7)), int(rng.integers(8, 25))
        A = rng.normal(size=(m, n))
        c, b = rng.random(n) + 0.1, A @ rng.random(n)
        cold = native.solve(c, A, b, basic=np.zeros(n, bool))
        for _ in range(4):
            hint = rng.random(n) < rng.uniform(0.1, 0.6)
            warm = native.solve(c, A, b, basic=hint)
            assert warm.objective == pytest.approx(cold.objective, rel=1e-9, abs=1e-9)
            assert kkt_error(c, A, b, warm) < 1e-8
        assert native.solve(c, A, b, basic=cold.x > 0).iterations == 0


def test_lp_of_the_same_structure_starts_from_the_last_basis_until_forget():
    rng = np.random.default_rng(11)
    A = rng.normal(size=(5, 15))
    c = rng.random(15) + 0.1
    b = A @ rng.random(15)
    native = NativeBackend()
    first = native.solve(c, A, b)
    nearby = native.solve(c, A, b + 1e-6 * rng.normal(size=5))
    assert first.iterations > 0 and nearby.iterations == 0
    native.forget()
    assert native.solve(c, A, b).iterations == first.iterations
    assert NativeBackend(warm_start=False).solve(c, A, b).iterations == first.iterations


def test_nearly_parallel_columns_terminate_from_every_start():
    """An sQ ray LP of a scanned can whose last two columns differ by 8e-6 mm: from one warm start the basis
    went infeasible by round-off at its optimum, and the simplex turned on the spot. Every one of the 64
    starts now ends at HiGHS's optimum."""
    A = np.array([[-16.72908777909464, 18.071418585142712, 14.253554365479541, 14.156467972870754,
                   14.098443807921033, 14.098443807921033],
                  [14.417032051373806, -10.249356576474437, -15.224902420160937, -15.351428276016588,
                   -15.427047082455882, -15.427047082455882],
                  [27.48291891268057, -36.81108201809195, -17.201345459963747, -18.57401445730313,
                   -36.81107438869742, -36.81108201809195],
                  [0.0, 1.0, 1.0, 1.0, 1.0, 1.0]])
    b, c = np.array([0.0, 0.0, 0.0, 1.0]), np.array([-1.0, 0.0, 0.0, 0.0, 0.0, 0.0])
    reference = sg.lp.get_backend("highs").solve(c, A, b).objective
    native = NativeBackend()
    for code in range(64):
        hint = np.array([(code >> k) & 1 for k in range(6)], dtype=bool)
        sol = native.solve(c, A, b, basic=hint)
        assert sol.optimal and sol.objective == pytest.approx(reference, rel=1e-8)


def test_the_kernels_compile_once_whatever_the_index_arrays():
    """Read-only, int64 or dense input reaches the simplex kernel as one type: a second signature would make
    numba compile the largest kernel again in a user's first plan (seconds)."""
    from synergrasp.lp import native
    from synergrasp.lp.base import CSC

    backend = NativeBackend()
    indptr, indices = np.array([0, 1, 2, 3]), np.array([0, 0, 1])
    read_only = [a.astype(np.int32) for a in (indptr, indices)]
    for a in read_only:
        a.setflags(write=False)
    for A in (CSC(indptr, indices, np.array([1.0, 1.0, 1.0]), (2, 3)),
              CSC(*read_only, np.array([1.0, 1.0, 1.0]), (2, 3)),
              np.array([[1.0, 1.0, 0.0], [0.0, 0.0, 1.0]])):
        assert backend.solve([1.0, 2.0, 1.0], A, [1.0, 2.0]).objective == pytest.approx(3.0)
    sg.plan(sg.objects.ellipsoid(), "precision", max_iter=5, executable_reach=False)
    assert len(native._solve_blocks.signatures) == 1 and len(native._blocks.signatures) == 1
