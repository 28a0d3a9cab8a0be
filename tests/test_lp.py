"""LP backends: registry, solution object, dual sign convention, statuses."""

import numpy as np
import pytest

import synergrasp as sg
from synergrasp.lp import CSC, Backend, LPSolution
from synergrasp.lp.base import csc_arrays, optimality_gaps


def random_lp(rng, m=5, n=12):
    A = rng.normal(size=(m, n))
    b = A @ rng.random(n)
    c = rng.random(n) + 0.1
    return c, A, b


def test_registry_lists_all_four_backends():
    assert sg.lp.available_backends() == ["highs", "native", "clarabel", "cvxpy"]


def test_unknown_backend_lists_available():
    with pytest.raises(ValueError, match="available.*highs"):
        sg.lp.get_backend("gurobi")
    with pytest.raises(ValueError, match="unknown LP backend"):
        sg.pseudo_distance([[0.0, 0.0]], [[1.0, 0.0]], backend="nope")


def test_backend_instances_are_reused():
    assert sg.lp.get_backend("highs") is sg.lp.get_backend("highs")


def test_solution_fields_and_dual_convention(backend, rng):
    c, A, b = random_lp(rng)
    be = sg.lp.get_backend(backend)
    sol = be.solve(c, A, b)
    assert isinstance(sol, LPSolution) and sol.status == "optimal" and sol.backend == backend
    assert sol.x.shape == (12,) and sol.y.shape == (5,)
    assert np.allclose(A @ sol.x, b, atol=1e-8) and (sol.x >= -1e-9).all()
    assert sol.objective == pytest.approx(c @ sol.x)
    assert sol.solve_time > 0 and sol.iterations >= 0
    # y = d objective / d b, checked by central differences on every row
    for r in range(len(b)):
        e = np.zeros_like(b)
        e[r] = 1e-5
        fd = (be.solve(c, A, b + e).objective - be.solve(c, A, b - e).objective) / 2e-5
        assert sol.y[r] == pytest.approx(fd, rel=1e-4, abs=1e-6)
    # dual feasibility: reduced costs c - A^T y >= 0
    assert (c - A.T @ sol.y >= -1e-7).all()


def test_backends_agree(rng):
    c, A, b = random_lp(rng, 6, 20)
    sols = [sg.lp.get_backend(name).solve(c, A, b) for name in sg.lp.available_backends()]
    for sol in sols[1:]:
        assert sol.objective == pytest.approx(sols[0].objective, abs=1e-7)
        assert np.allclose(sol.y, sols[0].y, atol=1e-6)


@pytest.mark.parametrize("c, A, b, value", [
    ([1.0], [[1.0]], [1e21], 1e21),  # a huge right-hand side
    ([1.0, 1.0], [[1.0, -1.0]], [2e-9], 2e-9),  # a tiny one
    ([1e-9, 2e-9], [[1.0, 1.0]], [1.0], 1e-9),  # tiny costs
])
def test_an_answer_on_badly_scaled_data_is_right_or_not_called_optimal(backend, c, A, b, value):
    """Solvers' tolerances are absolute: on such data HiGHS, Clarabel and cvxpy returned wrong optima as optimal
    (1e19 for 1e21, x = 0 breaking the row, twice the least cost). Each answer is now checked, whatever backend."""
    sol = sg.lp.get_backend(backend).solve(c, A, b)
    if sol.optimal:
        assert sol.objective == pytest.approx(value, rel=1e-6)
        assert max(optimality_gaps(np.array(c), np.array(A), np.array(b), sol.x, sol.y).values()) <= 1e-6
    else:
        assert sol.status == "failed" and np.isnan(sol.objective)
    unchecked = sg.lp.get_backend(backend).solve(c, A, b, verify=False)  # the library's own, scaled LPs
    assert unchecked.status in ("optimal", "failed")


@pytest.mark.parametrize("c, A, b, status, x", [
    ([0.0, 0.0, 0.0], [[1.0, 1.0, 1.0], [1.0, 1.0, 1.0]], [1.0, 1.0], "optimal", None),  # no costs: any feasible x
    ([1.0, 2.0], np.zeros((0, 2)), np.zeros(0), "optimal", [0.0, 0.0]),  # no rows
    ([1.0, -2.0], np.zeros((0, 2)), np.zeros(0), "unbounded", None),
    (np.zeros(0), np.zeros((1, 0)), [0.0], "optimal", []),  # no columns (HiGHS said "Empty", iterations 1688481120)
    (np.zeros(0), np.zeros((1, 0)), [1.0], "infeasible", None),
    ([1.0, 1.0], [[1e15, 1.0]], [1e15], "optimal", [1.0, 0.0]),  # an entry of 1e15 (HiGHS refused it: "Empty")
    # b = 0, optimum x = 0: Clarabel's x of 1e-24 was judged against its own size ("off by 1 (bounds), 2 (gap)")
    ([1.0, 1.0], [[1.0, -1.0]], [0.0], "optimal", [0.0, 0.0]),
    ([1.0, 2.0, 3.0], [[1.0, -1.0, 0.0], [0.0, 1.0, -1.0]], [0.0, 0.0], "optimal", [0.0, 0.0, 0.0]),
    # no feasible point and no dual one: Clarabel and cvxpy said "unbounded" (the dual is infeasible too)
    ([-1.0, 0.0, 0.0], [[1.0, -1.0, 0.0], [0.0, 0.0, 0.0]], [0.0, 1.0], "infeasible", None),
    ([0.3, -0.35, -1.9], [[-0.45, 0.0, 0.0], [0.55, 0.0, 0.0], [-0.08, 0.0, -0.59]], [2.9, 2.2, 2.0], "infeasible", None),
])
def test_lps_without_costs_rows_or_columns_are_answered_by_every_backend(backend, c, A, b, status, x):
    """Such LPs were "failed" on some backends: a feasibility problem's interior-point duals of round-off read as a
    duality gap, HiGHS refused an LP without columns or with an entry of 1e15."""
    sol = sg.lp.get_backend(backend).solve(c, A, b)
    assert sol.status == status, sol.message
    if status == "optimal":
        assert np.allclose(np.asarray(A) @ sol.x, b) and (sol.x >= -1e-9).all() and sol.iterations >= 0
        if x is not None:
            np.testing.assert_allclose(sol.x, x, atol=1e-9)


def test_optimality_gaps_of_an_exact_and_of_wrong_answers():
    c, A, b = np.array([1.0, 2.0]), np.array([[1.0, 1.0]]), np.array([1.0])
    assert optimality_gaps(c, A, b, np.array([1.0, 0.0]), np.array([1.0])) == {
        "rows": 0.0, "bounds": 0.0, "reduced costs": 0.0, "gap": 0.0}
    gaps = optimality_gaps(c, A, b, np.array([0.0, 1.0]), np.array([2.0]))  # feasible, not optimal
    assert gaps["rows"] == 0.0 and gaps["reduced costs"] == pytest.approx(0.5) and gaps["gap"] == 0.0
    assert optimality_gaps(c, sg.lp.CSC([0, 1, 2], [0, 0], [1.0, 1.0], (1, 2)), b, np.array([2.0, 0.0]),
                           np.array([1.0]))["rows"] == pytest.approx(0.5)  # a CSC matrix alike


def test_infeasible_and_unbounded_are_statuses(backend):
    be = sg.lp.get_backend(backend)
    infeasible = be.solve([1.0, 1.0], [[1.0, 1.0]], [-1.0])
    assert infeasible.status == "infeasible" and np.isnan(infeasible.objective)
    unbounded = be.solve([-1.0, 0.0], [[1.0, -1.0]], [0.0])
    assert unbounded.status == "unbounded"


def test_an_infeasible_block_makes_the_lp_infeasible_beside_an_unbounded_column(backend):
    """x0 = -1 has no solution with x0 >= 0; the free column x1 of negative cost must not make it 'unbounded'."""
    assert sg.lp.get_backend(backend).solve([0.0, -1.0], [[1.0, 0.0]], [-1.0]).status == "infeasible"


@pytest.mark.parametrize("indptr, indices, shape, match", [
    ([0, 1, 2], [0, 5], (1, 2), "indices of shape \\(2,\\) from 0 to 5"),  # a row outside the matrix
    ([0, 1], [0, 0], (1, 2), "indptr must be n \\+ 1 = 3"),
    ([0, 2, 1], [0, 0], (1, 2), "non-decreasing"),
    ([1, 1, 2], [0, 0], (1, 2), "from 1 to 2"),
    ([0, 1, 2], [0, -1], (1, 2), "from -1 to 0"),
    ([0.0, 1.0, 2.0], [0, 0], (1, 2), "integer indptr"),
])
@pytest.mark.parametrize("dtype", [np.int32, np.int64])
def test_malformed_csc_is_refused_before_any_solver_sees_it(backend, indptr, indices, shape, match, dtype):
    """A row index outside the matrix crashed the native backend's kernel (a segmentation fault)."""
    indptr = np.asarray(indptr) if np.asarray(indptr).dtype.kind == "f" else np.asarray(indptr, dtype=dtype)
    A = CSC(indptr, np.asarray(indices, dtype=dtype), np.array([1.0, 1.0]), shape)
    with pytest.raises(ValueError, match="CSC.*" + match if "integer" in match else match):
        sg.lp.get_backend(backend).solve([1.0, 1.0], A, [1.0])


def test_csc_of_lists_and_int64_indices_is_solved(backend):
    A = CSC([0, 1, 2], np.array([0, 0], dtype=np.int64), [2.0, 3.0], (1, 2))
    assert sg.lp.get_backend(backend).solve([1.0, 1.0], A, [6.0]).objective == pytest.approx(2.0, abs=1e-7)


def test_a_solver_panic_becomes_failed_status_and_an_interrupt_is_not_caught(backend, monkeypatch):
    """A Rust panic (clarabel's pyo3 PanicException) derives from BaseException, not Exception."""
    be = sg.lp.get_backend(backend)

    class PanicException(BaseException):
        pass

    def panic(c, A, b):
        raise PanicException("index out of bounds")

    monkeypatch.setattr(be, "_solve", panic)
    sol = be.solve([1.0], [[1.0]], [1.0])
    assert sol.status == "failed" and "PanicException: index out of bounds" in sol.message

    def interrupt(c, A, b):
        raise KeyboardInterrupt

    monkeypatch.setattr(be, "_solve", interrupt)
    with pytest.raises(KeyboardInterrupt):
        be.solve([1.0], [[1.0]], [1.0])


def test_solver_exception_becomes_failed_status(backend, monkeypatch):
    be = sg.lp.get_backend(backend)

    def boom(c, A, b):
        raise RuntimeError("solver crashed")

    monkeypatch.setattr(be, "_solve", boom)
    sol = be.solve([1.0], [[1.0]], [1.0])
    assert sol.status == "failed" and "solver crashed" in sol.message


def test_csc_input_matches_dense(backend, rng):
    c, A, b = random_lp(rng)
    A[A < 0] = 0.0
    b = A @ rng.random(12)
    indptr, indices, data = csc_arrays(A)
    csc = CSC(indptr, indices, data, A.shape)
    assert np.allclose(csc.toarray(), A)
    y = rng.normal(size=5)
    assert np.allclose(csc.rmatvec(y), A.T @ y)
    be = sg.lp.get_backend(backend)
    assert be.solve(c, csc, b).objective == pytest.approx(be.solve(c, A, b).objective, abs=1e-9)


@pytest.mark.parametrize(
    "c, A, b, match",
    [
        ([1.0, 1.0], [[1.0, 1.0]], [1.0, 2.0], "mismatched shapes"),
        ([1.0], [[1.0, 1.0]], [1.0], "mismatched shapes"),
        ([np.nan, 1.0], [[1.0, 1.0]], [1.0], "NaN or inf"),
        ([1.0, 1.0], [[np.inf, 1.0]], [1.0], "NaN or inf"),
    ],
)
def test_bad_lp_data(backend, c, A, b, match):
    with pytest.raises(ValueError, match=match):
        sg.lp.get_backend(backend).solve(c, A, b)


@pytest.mark.parametrize("c, A, b", [
    (np.array([1.0 + 1e-3j, 1.0]), [[1.0, 1.0]], [1.0]),  # the imaginary part was dropped with a ComplexWarning
    ([1.0, 1.0], np.array([[True, True]]), [1.0]),
    ([1.0, 1.0], [[1.0, 1.0]], np.array(["1"])),
    (np.array([1.0, "1"], dtype=object), [[1.0, 1.0]], [1.0]),
    ([1.0, 1.0], sg.lp.CSC([0, 1, 2], [0, 0], np.array([True, True]), (1, 2)), [1.0]),
])
def test_lp_data_of_text_booleans_or_complex_numbers_is_refused(backend, c, A, b):
    with pytest.raises(TypeError, match="arrays of real numbers, not text, booleans or complex numbers"):
        sg.lp.get_backend(backend).solve(c, A, b)


def test_basis_hint_changes_the_path_not_the_optimum(backend, rng):
    c, A, b = random_lp(rng, 6, 20)
    be = sg.lp.get_backend(backend)
    cold = be.solve(c, A, b)
    ours = sg.lp.get_backend("highs").solve(c, A, b).x > 0  # a simplex optimum's basic columns
    for basic in (ours, ~ours, np.zeros(20, bool)):
        warm = be.solve(c, A, b, basic=basic)
        assert warm.objective == pytest.approx(cold.objective, abs=1e-7)
        assert np.allclose(warm.y, cold.y, atol=1e-6)
    if be.basis_hints:  # started at the optimal basis: no simplex iteration left
        assert be.solve(c, A, b, basic=ours).iterations == 0
    with pytest.raises(ValueError, match=r"basic must be an \(20,\) bool array"):
        be.solve(c, A, b, basic=np.ones(19, bool))
    with pytest.raises(ValueError, match="basic must be"):
        be.solve(c, A, b, basic=np.arange(20))


def test_forget_makes_the_next_solve_cold(backend, rng):
    """A second solve of the same LP starts from the kept basis (HiGHS: no simplex iteration); after forget() it is
    solved as by a new instance, to the same optimum."""
    c, A, b = random_lp(rng, 6, 20)
    be = sg.lp.get_backend(backend)
    be.forget()
    cold = be.solve(c, A, b)
    warm = be.solve(c, A, b)
    be.forget()
    again = be.solve(c, A, b)
    fresh = type(be)().solve(c, A, b)
    assert again.objective == pytest.approx(fresh.objective, abs=1e-9) and again.iterations == fresh.iterations
    if be.basis_hints:  # HiGHS keeps the last model and basis: the repeated LP needs no pivot
        assert warm.iterations == 0 < cold.iterations == again.iterations


def test_custom_backend_object_is_accepted():
    class Fixed(Backend):
        def _solve(self, c, A, b):
            return "failed", None, None, 0, "always fails"

    with pytest.raises(sg.lp.LPError, match="'failed'"):
        sg.pseudo_distance([[0.0, 0.0]], [[1.0, 0.0]], backend=Fixed(name="fixed"))


def test_an_answer_the_solver_calls_inaccurate_is_checked_even_without_verify():
    """Clarabel's AlmostSolved and cvxpy's optimal_inaccurate were taken as optimal where the library's own LPs skip
    the answer check (verify=False): a wrong answer so marked comes back failed; unmarked, it is trusted as asked."""
    class Loose(Backend):
        inaccurate = frozenset({"almost"})

        def __init__(self, message):
            super().__init__(name="loose")
            self.message = message

        def _solve(self, c, A, b):  # min x0 + x1, x0 - x1 = 2: the optimum is x = (2, 0), objective 2
            return "optimal", np.array([3.0, 1.0]), np.array([1.0]), 5, self.message

    c, A, b = [1.0, 1.0], [[1.0, -1.0]], [2.0]
    marked = Loose("almost").solve(c, A, b, verify=False)
    assert marked.status == "failed" and "called it optimal (almost)" in marked.message
    assert Loose("solved").solve(c, A, b, verify=False).status == "optimal"
    assert Loose("solved").solve(c, A, b).status == "failed"


def test_the_cvxpy_backend_takes_its_solver_in_any_case_and_refuses_a_missing_one():
    from synergrasp.lp.cvxpy import CvxpyBackend

    for solver in ("clarabel", "CLARABEL", "Clarabel"):
        be = CvxpyBackend(solver=solver)
        assert be.solver_options and be.solve([1.0, 1.0], [[1.0, -1.0]], [2.0]).objective == pytest.approx(2.0)
    assert CvxpyBackend(solver=None).solve([1.0, 1.0], [[1.0, -1.0]], [2.0]).objective == pytest.approx(2.0, abs=1e-6)
    with pytest.raises(ValueError, match="cvxpy has no solver 'NOPE' installed; it has .*CLARABEL"):
        CvxpyBackend(solver="NOPE")


def test_highs_runs_with_a_global_scheduler_of_another_thread_count():
    highspy = pytest.importorskip("highspy")
    from synergrasp.lp.highs import THREADS, HighsBackend

    highspy.Highs.resetGlobalScheduler(True)
    try:
        other = highspy.Highs()  # sets HiGHS's process-wide scheduler up with another count
        other.setOptionValue("output_flag", False)
        other.setOptionValue("threads", THREADS + 1)
        other.run()
        sol = HighsBackend().solve([1.0, 1.0], [[1.0, -1.0]], [2.0])
        assert sol.status == "optimal" and sol.objective == pytest.approx(2.0)
    finally:
        highspy.Highs.resetGlobalScheduler(True)


def test_highs_prints_no_banner_on_stdout():
    """HiGHS writes "Running HiGHS ..." to file descriptor 1 on its first instance; the backend hides it."""
    import subprocess
    import sys

    code = ("import synergrasp as sg\n"
            "print('before')\n"
            "sg.q_distance([[0, 0, 10.0], [0, 0, -10.0]], [[0, 0, -1.0], [0, 0, 1.0]], backend='highs')\n"
            "print('after')\n")
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout == "before\nafter\n"


def test_highs_options_it_refuses_are_refused_at_once():
    """A misspelt option, or a value of the wrong type, left every solve at HiGHS's default silently."""
    from synergrasp.lp.highs import HighsBackend

    with pytest.raises(ValueError, match="HiGHS refuses the option dual_feasibility_tolerence=1e-09"):
        HighsBackend(dual_feasibility_tolerence=1e-9)
    with pytest.raises(ValueError, match="HiGHS refuses the option dual_feasibility_tolerance='tight'"):
        HighsBackend(dual_feasibility_tolerance="tight")
    assert HighsBackend(dual_feasibility_tolerance=1e-9).solve([1.0], [[1.0]], [2.0]).objective == pytest.approx(2.0)


@pytest.mark.parametrize("returned, match", [
    (("Optimal", [1.0], [1.0], 1, ""), "status 'Optimal' and iterations 1; the status must be one of"),
    (("optimal", [1.0], [1.0], None, ""), "status 'optimal' and iterations None"),
    (("optimal", [1.0], [], 1, ""), r"x of shape \(1,\) and y of shape \(0,\) for an LP of 1 rows"),
    (("optimal", [1.0, 0.0], [1.0], 1, ""), r"x of shape \(2,\)"),
])
def test_what_a_custom_backend_returns_is_checked(returned, match):
    """A custom backend's mistakes surfaced far away (an IndexError inside pseudo_distance, advice to change backend)."""

    class Custom(Backend):
        def _solve(self, c, A, b):
            return returned

    with pytest.raises(ValueError, match="backend 'custom': _solve returned " + match):
        Custom(name="custom").solve([1.0], [[1.0]], [1.0])
