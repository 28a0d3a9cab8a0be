"""The synergrasp command line."""

import json
import re

import numpy as np
import pytest

from synergrasp.cli import build_parser, main


def test_help_of_every_subcommand(capsys):
    for argv in ([], ["plan"], ["demo"]):
        with pytest.raises(SystemExit) as exc:
            main(argv + ["--help"])
        assert exc.value.code == 0
    out = capsys.readouterr().out
    assert "--object" in out and "--grasp" in out and "--approach" in out and "--contacts" in out


def test_plan_writes_the_result_and_figures(tmp_path, capsys):
    code = main(["plan", "--object", "ellipsoid", "--out", str(tmp_path), "--quiet", "--no-animation"])
    out = capsys.readouterr().out
    assert code == 0 and out.startswith("success")
    saved = json.loads((tmp_path / "ellipsoid_precision.json").read_text())
    assert saved["success"] and saved["grasp"] == "precision"
    clearance = np.array(saved["clearance"])
    printed = re.search(r"executable reach: (\d+) poses, clearance ([-\d.]+) mm at the pre-grasp, smallest ([-+\d.]+) mm; "
                        r"(collision-free|not collision-free)", out)
    assert printed and int(printed.group(1)) == len(saved["path"]) == len(clearance)
    assert float(printed.group(2)) == round(clearance[0], 1) and float(printed.group(3)) == round(clearance.min(), 1)
    assert (printed.group(4) == "collision-free") == saved["collision_free"]
    for name in ("ellipsoid_precision_status.png", "ellipsoid_precision_poses.png"):
        assert (tmp_path / name).stat().st_size > 10_000


@pytest.mark.parametrize(
    "argv, message",
    [
        (["plan", "--object", "teapot"], "unknown object 'teapot'"),
        (["plan", "--backend", "gurobi"], "unknown LP backend 'gurobi'"),
        (["demo", "--mu", "-1"], "mu must be a finite number > 0"),
    ],
)
def test_bad_input_is_a_clear_error(tmp_path, capsys, argv, message):
    assert main(argv + (["--out", str(tmp_path), "--quiet"] if argv[0] == "plan" else [])) == 2
    assert message in capsys.readouterr().err


def test_bad_approach_is_rejected_by_the_parser(capsys):
    with pytest.raises(SystemExit):
        build_parser().parse_args(["plan", "--approach", "1,2"])
    assert "expected three numbers" in capsys.readouterr().err
