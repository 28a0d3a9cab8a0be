"""Every script in examples/ runs headless and says what it claims (so an example cannot rot).

Each example runs as a subprocess, ``python examples/NAME.py --out TMP``, with a timeout; the
test checks its exit status and, where the output has a claim in it, the claim. A new example
without an entry in CHECKS still runs (exit status 0 and no traceback). ``paper_experiments.py``
takes minutes: it runs with ``--quick`` (one case). No example may change a file of the
repository (they write under ``--out``; only ``--docs`` regenerates the documentation).
"""

import json
import os
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import synergrasp as sg

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
ROOT = EXAMPLES.parent
TIMEOUT = 120  # s per example; each takes a few seconds


def number(pattern, text):
    """The float captured by ``pattern`` in ``text`` (the test fails if it is not there)."""
    match = re.search(pattern, text)
    assert match, f"no match for {pattern!r} in:\n{text}"
    return float(match.group(1))


def check_grasp_quality(out, stdout):
    q = number(r"Q distance = ([-+.\d]+)", stdout)
    assert q < 0 and "force closure" in stdout
    dual = number(r"dual ([-+.\de]+),", stdout)
    fd = number(r"finite difference ([-+.\de]+)", stdout)
    assert abs(dual - fd) <= 1e-5 * max(abs(fd), 1e-3)
    new = number(r"gradient step: Q = ([-+.\d]+)", stdout)
    assert new < q and "improved" in stdout
    assert (out / "grasp_quality.png").stat().st_size > 0


def check_pseudo_distance_polytopes(out, stdout):
    assert number(r"separated: .*value\s+([-+.\d]+)", stdout) > 0
    assert abs(number(r"touching: .*value\s+([-+.\d]+)", stdout)) < 1e-3
    assert number(r"overlapping: .*value\s+([-+.\d]+)", stdout) < 0
    assert number(r"where not degenerate: ([-+.\de]+)", stdout) < 1e-6
    assert (out / "pseudo_distance_polytopes.png").stat().st_size > 0


def check_plan_cup(out, stdout):
    assert stdout.startswith("GraspObject('cup'") and "\nsuccess: stop criterion met" in stdout
    result = sg.PlanResult.load(out / "cup_precision.json")
    assert result.success and result.object_name == "cup" and result.final_q < 0
    assert "same final configuration: True" in stdout
    for name in ("cup_precision_status.png", "cup_precision_poses.png"):
        assert (out / name).stat().st_size > 0


def check_plan_mesh_file(out, stdout):
    assert "loaded GraspObject('capsule.stl'" in stdout and "method 'hull'" in stdout
    assert "\nsuccess: stop criterion met" in stdout
    result = sg.PlanResult.load(out / "capsule_stl_precision.json")
    assert result.success and result.final_q < 0
    assert (out / "capsule_stl_precision_poses.png").stat().st_size > 0


def check_compare_backends(out, stdout):
    rows = (out / "compare_backends.csv").read_text().splitlines()
    names = [row.split(",")[0] for row in rows[1:]]
    assert names == sg.lp.available_backends()
    for row in rows[1:]:
        backend, q, ms, *diffs = row.split(",")
        assert float(q) < 0 and float(ms) > 0, row
        assert max(float(d) for d in diffs) < 1e-6, row


def check_add_a_hand(out, stdout):
    data = json.loads((out / "long_fingers.json").read_text())
    hand = sg.SynergyHand.from_file(out / "long_fingers.json")
    paper = sg.SynergyHand.default()
    assert data["name"] == hand.name == "long_fingers"
    u = np.zeros(paper.n_u)
    moved = np.linalg.norm(hand.points(u) - paper.points(u), axis=1)
    assert moved[0] == 0 and (moved[1:] > 10).all()                 # thumb unchanged, fingers longer
    assert "paper_hand: success" in stdout and "long_fingers:" in stdout
    assert (out / "long_fingers_poses.png").stat().st_size > 0


def check_synergy_plane(out, stdout):
    assert (out / "synergy_plane.png").stat().st_size > 0


def check_paper_experiments(out, stdout):
    rows = (out / "paper_experiments.csv").read_text().splitlines()
    assert len(rows) == 2 and rows[1].startswith("ellipsoid,precision,True,True")
    assert "| ellipsoid | precision | yes |" in (out / "paper_experiments.md").read_text()
    for name in ("ellipsoid_precision_status.png", "ellipsoid_precision_poses.png"):
        assert (out / name).stat().st_size > 0


CHECKS = {
    "grasp_quality.py": check_grasp_quality,
    "pseudo_distance_polytopes.py": check_pseudo_distance_polytopes,
    "plan_cup.py": check_plan_cup,
    "plan_mesh_file.py": check_plan_mesh_file,
    "compare_backends.py": check_compare_backends,
    "add_a_hand.py": check_add_a_hand,
    "synergy_plane.py": check_synergy_plane,
    "paper_experiments.py": check_paper_experiments,
}


def arguments(name, out):
    if name == "compare_backends.py":
        return ["--out", str(out), "--seconds", "0.05"]
    if name == "paper_experiments.py":
        return ["--out", str(out), "--quick"]
    return ["--out", str(out)]


SCRIPTS = sorted(p.name for p in EXAMPLES.glob("*.py"))


def repository_files():
    """Size and modification time of every file of the repository outside caches and output folders."""
    skip = {".git", "__pycache__", ".pytest_cache", ".hypothesis", "examples-out", "bench-out", "synergrasp-out", "site"}
    state = {}
    for folder, dirs, files in os.walk(ROOT):
        dirs[:] = [d for d in dirs if d not in skip and not d.endswith(".egg-info")]
        for name in files:
            stat = os.stat(os.path.join(folder, name))
            state[os.path.relpath(os.path.join(folder, name), ROOT)] = (stat.st_size, stat.st_mtime_ns)
    return state


def test_every_example_is_checked():
    assert set(CHECKS) <= set(SCRIPTS), f"checks for missing examples: {set(CHECKS) - set(SCRIPTS)}"


@pytest.mark.parametrize("name", SCRIPTS)
def test_example_runs(name, tmp_path):
    out = tmp_path / "out"
    out.mkdir()
    # the examples import the package under test, not another installed copy
    path = os.pathsep.join(filter(None, [str(EXAMPLES.parent), os.environ.get("PYTHONPATH")]))
    env = dict(os.environ, MPLBACKEND="Agg", SYNERGRASP_CACHE=str(tmp_path / "cache"), PYTHONWARNINGS="default", PYTHONPATH=path)
    before = repository_files()
    proc = subprocess.run([sys.executable, str(EXAMPLES / name), *arguments(name, out)], cwd=tmp_path, env=env,
                          capture_output=True, text=True, timeout=TIMEOUT)
    assert proc.returncode == 0, f"{name} exited with {proc.returncode}:\n{proc.stdout}\n{proc.stderr}"
    assert "Traceback" not in proc.stderr, proc.stderr
    if name in CHECKS:
        CHECKS[name](out, proc.stdout)
    # nothing written outside --out (the default ./examples-out would land in the cwd), no file of the repository changed
    assert not (tmp_path / "examples-out").exists()
    after = repository_files()
    changed = sorted(k for k in before.keys() | after.keys() if before.get(k) != after.get(k))
    assert not changed, f"{name} changed files of the repository: {changed}"


@pytest.mark.parametrize("name", SCRIPTS)
def test_example_has_a_docstring(name):
    text = (EXAMPLES / name).read_text()
    assert text.startswith('"""'), f"{name} should open with a module docstring saying what it shows"


@pytest.mark.parametrize("name", [n for n in SCRIPTS if "type=output_folder" in (EXAMPLES / n).read_text()])
def test_an_output_folder_that_is_a_file_is_a_usage_error(name, tmp_path):
    """--out naming a file: argparse's usage error (exit 2) that says so, before any work, not a traceback."""
    (tmp_path / "file").write_text("x")
    proc = subprocess.run([sys.executable, str(EXAMPLES / name), "--out", str(tmp_path / "file")], cwd=tmp_path,
                          capture_output=True, text=True, timeout=TIMEOUT, env=dict(os.environ, MPLBACKEND="Agg"))
    assert proc.returncode == 2 and "Traceback" not in proc.stderr, proc.stderr
    assert "cannot write to the output folder" in proc.stderr and "it is a file, not a folder" in proc.stderr
