"""The planner comparison's quick mode: both methods on the ellipsoid, verified, with their figures and ratios."""

import json

import numpy as np
import pytest

from benchmarks import compare_planners


def test_compare_planners_quick(tmp_path, capsys):
    out = compare_planners.main(["--quick", "--out", str(tmp_path)])
    rows = [json.loads(line) for line in (tmp_path / "rows.jsonl").read_text().splitlines()]
    assert [(r["name"], r["method"]) for r in rows] == [("paper/ellipsoid", "gradient"), ("paper/ellipsoid", "annealing")]
    assert all(r["verified"] for r in rows)  # the annealing's quick options (seed 2, 3000 steps) find a grasp
    gradient, annealing = rows
    assert gradient["evaluations"] >= gradient["iterations"] + 1 and annealing["evaluations"] > annealing["iterations"]
    assert annealing["held"] in (True, False) and gradient["held"] in (True, False)  # tested in MuJoCo
    figures = out["figures"]
    assert figures["all/gradient"]["verified"] == figures["all/annealing"]["verified"] == 1
    ratio = out["ratios"]["speedup"]
    assert ratio == pytest.approx(annealing["cpu"] / gradient["cpu"])  # medians of one plan each
    assert out["ratios"]["paired_ratio"] == pytest.approx(ratio)
    assert out["ratios"]["paired_cases"] == 1
    assert (tmp_path / "planner-comparison.png").stat().st_size > 10_000
    text = capsys.readouterr().out
    assert "times faster" in text and "sum of squared second differences" in text


def test_smoothness_of_known_paths():
    """A straight palm path at constant speed: its length, no rotation, no second differences."""
    traj = np.zeros((11, 8))
    traj[:, 0] = np.linspace(0.0, 100.0, 11)
    s = compare_planners.smoothness(traj, size=50.0)
    assert s["path_mm"] == pytest.approx(100.0) and s["rotation_rad"] == 0.0 and s["jerk"] == pytest.approx(0.0, abs=1e-20)
    traj[5, 0] += 10.0  # one bump of 10 mm = 0.2 object sizes: second differences 0.2, -0.4, 0.2
    assert compare_planners.smoothness(traj, size=50.0)["jerk"] == pytest.approx(0.04 + 0.16 + 0.04)
    turn = np.zeros((3, 8))
    turn[:, 5] = [0.0, 3.0, -3.0]  # a rotation about z by 3 rad, then across the wrap to -3 rad (0.283 rad on)
    s = compare_planners.smoothness(turn, size=1.0)
    assert s["rotation_rad"] == pytest.approx(3.0 + (2 * np.pi - 6.0)) and s["jerk"] == pytest.approx((2 * np.pi - 9.0) ** 2)
