"""The solver comparison harness (solvers/): quick run, one row per backend, agreement asserted."""

import csv

import numpy as np
import pytest

import synergrasp as sg
from solvers import compare
from solvers.references import LinprogBackend, PlainCvxpyBackend, TimedBackend

EXPECTED = sg.lp.available_backends() + ["scipy-linprog", "cvxpy-plain"]


@pytest.fixture(scope="module")
def quick(tmp_path_factory):
    out = tmp_path_factory.mktemp("solver-comparison")
    return compare.main(["--quick", "--quiet", "--out", str(out)])


def test_runs_without_docs_write_outside_the_repository():
    """Without --docs the harness writes under ./bench-out (the committed solvers/results only with --docs)."""
    from solvers import profile_plan

    for module in (compare, profile_plan):
        assert not module.DEFAULT_OUT.is_absolute() and module.DEFAULT_OUT.parts[0] == "bench-out"
        assert module.COMMITTED == compare.ROOT / "solvers" / "results"
    with pytest.raises(SystemExit):
        compare.main(["--quick", "--docs"])  # the committed results only from a full run


def test_summary_has_one_row_per_backend(quick):
    names = [row["backend"] for row in quick["summary"]]
    assert names == EXPECTED
    with open(quick["out"] / "summary.csv") as fh:
        assert [row["backend"] for row in csv.DictReader(fh)] == EXPECTED


def test_lp_table_has_every_backend_once_per_workload(quick):
    for workload in compare.WORKLOADS:
        assert [r["backend"] for r in quick["lp"] if r["workload"] == workload] == EXPECTED
    for row in quick["lp"]:
        assert row["calls"] >= 5 and row["median_ms"] > 0 and row["p95_ms"] >= row["median_ms"]
        assert row["lps_per_call"] >= 1


def test_every_backend_agrees_with_highs(quick):
    for row in quick["lp"]:
        assert row["value_diff"] <= 1e-6, row
        assert not (row["grad_diff"] > compare.GRAD_TOL), row
        assert row["agree"], row
    measured = [r for r in quick["plan"] if r["source"] == "measured"]
    assert {r["backend"] for r in measured} == set(EXPECTED)
    for row in measured:
        assert row["same_verdict"] is True, row


def test_outputs_and_paper_rows(quick):
    out = quick["out"]
    for name in ("lp_level.csv", "plan_level.csv", "summary.csv", "ratios.csv", "solver_ratios.csv", "environment.json",
                 "README.md"):
        assert (out / name).stat().st_size > 0
    assert (out / compare.FIGURE).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    text = (out / "README.md").read_text()
    assert compare.PAPER_LABEL in text and "Target ratios" in text and "in-solver ratios" in text
    paper = [r for r in quick["plan"] if r["source"] == "paper"]
    assert len(paper) == 8 and all(r["backend"] == compare.PAPER_LABEL for r in paper)
    assert [r["target"] for r in quick["ratios"]] == [20.0, 10.0, 10.0, 100.0]
    for row in quick["ratios"][:3]:  # measured splits: the time outside the solver is positive
        assert row["rest_now"] > 0 and np.isfinite(row["rest_allowed"]), row


@pytest.mark.parametrize("slow, fast, target", [(0.37, 0.029, 10.0), (2.4, 0.2, 10.0), (12.0, 0.2, 20.0)])
def test_allowed_rest_is_where_the_ratio_meets_its_target(slow, fast, target):
    rest = compare.allowed_rest(slow, fast, target)
    assert (rest + slow) / (rest + fast) == pytest.approx(target)
    assert (rest * 1.01 + slow) / (rest * 1.01 + fast) < target  # more time outside the solver: below the target


@pytest.mark.parametrize("make", [LinprogBackend, PlainCvxpyBackend])
def test_reference_backends_follow_the_dual_convention(make):
    rng = np.random.default_rng(3)
    A = rng.normal(size=(4, 10))
    b = A @ rng.random(10)
    c = rng.random(10) + 0.1
    ref = sg.lp.get_backend("highs").solve(c, A, b)
    sol = make().solve(c, A, b)
    assert sol.status == "optimal"
    assert sol.objective == pytest.approx(ref.objective, abs=1e-7)
    assert np.allclose(sol.y, ref.y, atol=1e-6)
    assert make().solve([1.0, 1.0], [[1.0, 1.0]], [-1.0]).status == "infeasible"


def test_timed_backend_accumulates_solver_time():
    timed = TimedBackend("highs")
    r = sg.q_distance(*compare.grasp_sequence(5, 1)[0], backend=timed)
    assert timed.lp_calls == r.lp_solves and timed.lp_time > 0 and str(timed) == "highs"
    timed.reset()
    assert timed.lp_calls == 0 and timed.lp_time == 0.0


def test_every_backend_has_a_whole_call_and_an_in_solver_ratio_per_workload(quick):
    rows = quick["solver_ratios"]
    others = [b for b in EXPECTED if b != compare.REFERENCE]
    for workload in compare.WORKLOADS:
        assert [r["backend"] for r in rows if r["workload"] == workload] == others
    assert {r["backend"] for r in rows if r["unit"] == "per plan"} == set(others)
    for r in rows:  # ratios of positive times
        assert r["whole"] > 0 and r["in_solver"] > 0, r


def test_profile_plan_quick_writes_its_tables(tmp_path):
    from solvers import profile_plan

    before, after = profile_plan.main(["--quick", "--out", str(tmp_path)])
    assert before is None and list(after["cases"]) == ["ellipsoid precision"] and after["backend"] == "native"
    case = after["cases"]["ellipsoid precision"]
    assert case["iterations"] > 0 and case["lp_solves"] > 0
    assert 0 < case["lp_cpu_s"] < case["cpu_s"] and 0 < case["lp_time_s"] < case["wall_s"]
    text = (tmp_path / "profile.md").read_text()
    assert "inside Backend.solve" in text and (tmp_path / "profile.csv").stat().st_size > 0
    assert "planned with the `native` LP backend" in text


def test_the_profile_can_import_its_sequences_beside_an_older_package():
    """profile_plan's measuring process imports solvers.compare with the baseline package (427770f) as synergrasp,
    whose command-line module has none of today's helpers: the sequences' modules import them only in their main."""
    import subprocess
    import sys

    code = ("import sys; sys.modules['synergrasp.cli'] = None\n"  # any import of it fails
            "from solvers.compare import grasp_sequence, point_sequence\n")
    run = subprocess.run([sys.executable, "-c", code], cwd=compare.ROOT, capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
