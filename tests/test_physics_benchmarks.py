"""The physics benchmark scripts run in their quick modes and say what they measure."""

import csv
import math
import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


def run(script, *args, cwd):
    env = dict(os.environ, MPLBACKEND="Agg", PYTHONPATH=os.pathsep.join(filter(None, [str(ROOT), os.environ.get("PYTHONPATH")])))
    proc = subprocess.run([sys.executable, str(ROOT / "benchmarks" / script), *args], cwd=cwd, env=env,
                          capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    assert "Traceback" not in proc.stderr
    return proc.stdout


def test_bench_validate_quick(tmp_path):
    out = run("bench_validate.py", "--quick", cwd=tmp_path)
    rows = [line for line in out.splitlines() if line.startswith(("box pinch", "ball pinch"))]
    outcomes = {line[:44].strip(): line[45:57].strip() for line in rows}
    assert outcomes == {"box pinch": "held", "box pinch, 40 mm back": "no contact",
                        "ball pinch (thumb and index)": "held"}
    assert "one validation: median" in out and "over 3 cases" in out


@pytest.fixture(scope="module")
def study(tmp_path_factory):
    """One quick run of the study: its folder, output folder and printed text."""
    folder = tmp_path_factory.mktemp("physics_study")
    return folder, folder / "study", run("physics_study.py", "--quick", "--out", str(folder / "study"), cwd=folder)


@pytest.mark.parametrize("grasp", ["precision", "power"])
def test_physics_study_quick(study, grasp):
    tmp_path, out_dir, out = study
    with open(out_dir / "rows.csv") as f:
        rows = list(csv.DictReader(f))
    assert [(r["object"], r["grasp"]) for r in rows] == [("ellipsoid", "precision"), ("ellipsoid", "power")]
    row = next(r for r in rows if r["grasp"] == grasp)
    for variant in ("synergrasp, 40 mm back", "dexgraspbench, 40 mm back"):  # negative controls never hold
        assert row[f"{variant}: held"] == "False"
    assert row["synergrasp: outcome"] in ("held", "penetration", "unstable", "no contact", "slip", "rotation")
    assert f"paper, {grasp}: LP verdict" in out
    assert re.search(r"40 mm back\) held: synergrasp 0/1, overlap ignored ./1, dexgraspbench 0/1", out)
    assert "precision" in out and "recall" in out
    assert (out_dir / "q_vs_held.png").stat().st_size > 0
    assert (out_dir / "cases" / f"paper_ellipsoid_{grasp}" / "synergrasp.json").exists()
    assert not (tmp_path / "bench-out").exists()  # nothing written outside --out


def test_revalidate_finds_the_study_s_own_verdicts(study):
    """The same code validates the quick study's saved plans (the ellipsoid's two) to the verdicts it stored."""
    tmp_path, out_dir, _ = study
    out = run("revalidate.py", str(out_dir), "--set", "paper", cwd=tmp_path)
    for variant in ("synergrasp", "dexgraspbench"):
        assert re.search(rf"^{variant}: 2 validations, held (\d) before and \1 now, 0 outcomes changed", out, re.M), out


def test_squeeze_sweep_quick(tmp_path):
    """The ellipsoid's precision grasp: no squeeze of the four holds at the project's kp (5 N m/rad); stiffer
    servos (25) hold it with some."""
    out = run("squeeze_sweep.py", "--quick", cwd=tmp_path)
    held = {float(kp): int(n) for kp, n in re.findall(r"ellipsoid +kp ([\d.]+): (\d+)/4 squeezes hold", out)}
    assert held[5.0] == 0 and held[25.0] >= 1
    assert not list(tmp_path.iterdir())  # it writes nothing


def test_physics_turns_quick(tmp_path):
    """The ellipsoid's precision grasp validated unturned and turned: it slips either way, as in the physics study."""
    out = run("physics_turns.py", "--quick", cwd=tmp_path)
    assert re.search(r"^ellipsoid +precision +SS +held at 0/2 turns; largest displacement [\d.]+-[\d.]+ mm$", out, re.M), out
    assert "1 of 1 grasps have one verdict at every turn (synergrasp protocol)" in out
    assert not list(tmp_path.iterdir())  # it writes nothing


def test_the_study_s_thresholds_and_roc_areas(monkeypatch):
    """best_threshold on scores whose order is known: a perfect separation, a tie, and a score that says nothing."""
    monkeypatch.syspath_prepend(str(ROOT / "benchmarks"))
    from physics_study import best_threshold, grip_ratio

    perfect = best_threshold([(1.0, False), (2.0, False), (3.0, True), (4.0, True), (float("nan"), True)], below=False)
    assert perfect == dict(t=2.5, tpr=1.0, fpr=0.0, accuracy=1.0, n=4, auc=1.0)
    assert best_threshold([(1.0, True), (2.0, True), (3.0, False)], below=True)["t"] == 2.5
    assert best_threshold([(1.0, True), (1.0, False)], below=False)["auc"] == 0.5  # a tie counts half
    assert best_threshold([(1.0, True), (2.0, True)], below=False) is None  # every grasp held
    row = {"synergrasp": dict(held=True, outcome="held", grip=9.81, mass=0.5)}
    assert grip_ratio(row, "synergrasp") == pytest.approx(2.0)
    assert math.isnan(grip_ratio({"synergrasp": dict(outcome="penetration", grip=0.0, mass=0.5)}, "synergrasp"))


def test_the_study_takes_planner_options_but_writes_the_docs_only_for_the_defaults(monkeypatch, tmp_path, capsys):
    """--option reaches every plan; a bad option fails before any work; --docs refuses a non-default planner."""
    monkeypatch.syspath_prepend(str(ROOT / "benchmarks"))
    import physics_study

    with pytest.raises(SystemExit):
        physics_study.main(["--quick", "--option", "restarts=3", "--docs", "--out", str(tmp_path)])
    assert "drop --option" in capsys.readouterr().err
    with pytest.raises(SystemExit):  # a usage error naming the option, not a traceback
        physics_study.main(["--quick", "--option", "restarts=-1", "--out", str(tmp_path)])
    assert "PlannerOptions.restarts must be in [1, 1000000], got -1" in capsys.readouterr().err
    assert not list(tmp_path.iterdir())  # refused before anything was planned
    seen = []
    monkeypatch.setattr(physics_study, "study_case",
                        lambda *args: seen.append(args[-1]) or dict(lp=False, q=math.nan, note="stub"))
    monkeypatch.setattr(physics_study, "summary", lambda rows, sets: [])
    monkeypatch.setattr(physics_study, "prediction", lambda rows: [])
    monkeypatch.setattr(physics_study, "write_csv", lambda rows, path: path)
    monkeypatch.setattr(physics_study, "plot", lambda rows, path: path)
    physics_study.main(["--quick", "--option", "restarts=3", "--out", str(tmp_path)])
    assert seen == [{"restarts": 3}, {"restarts": 3}]  # the ellipsoid's precision and power plans
