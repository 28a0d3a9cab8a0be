"""The synergrasp command line."""

import json
import re

import numpy as np
import pytest
import trimesh

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
    differs = f"{saved['surface_q']:.4f}" != f"{saved['q_history'][-1]:.4f}"  # the Q it was accepted on, beside g_Q
    assert (f"(Q on the true surface, which it was accepted on: {saved['surface_q']:+.4f})" in out) == differs
    for name in ("ellipsoid_precision_status.png", "ellipsoid_precision_poses.png"):
        assert (tmp_path / name).stat().st_size > 10_000


def test_plan_prints_the_q_a_grasp_was_accepted_on_where_it_differs_from_g_q(tmp_path, capsys):
    """A 70 mm ball's piece is its mesh's hull cut to 256 vertices: a grasp's Q on the mesh differs from g_Q on the
    piece, and the printed line gave g_Q alone (-0.0008 beside q_accept -0.01 for a user's object)."""
    ball = tmp_path / "ball.stl"
    trimesh.creation.icosphere(subdivisions=3, radius=35.0).export(ball)
    assert main(["plan", "--object", str(ball), "--grasp", "power", "--out", str(tmp_path), "--quiet",
                 "--no-animation"]) == 0
    saved = json.loads((tmp_path / "ball_stl_power.json").read_text())
    assert f"{saved['surface_q']:.4f}" != f"{saved['q_history'][-1]:.4f}"
    assert f"(Q on the true surface, which it was accepted on: {saved['surface_q']:+.4f})" in capsys.readouterr().out


def test_plan_without_animation_removes_an_earlier_runs_animation(tmp_path, capsys):
    stale = [tmp_path / "ellipsoid_precision_reach.gif", tmp_path / "ellipsoid_precision_grasp.html"]
    for f in stale:
        f.write_text("an earlier plan")
    assert main(["plan", "--object", "ellipsoid", "--out", str(tmp_path), "--quiet", "--no-animation"]) == 0
    assert not any(f.exists() for f in stale)
    assert "removed an earlier run's ellipsoid_precision_reach.gif, ellipsoid_precision_grasp.html" in capsys.readouterr().err


def test_a_plan_interrupted_before_its_animation_leaves_no_earlier_one(tmp_path, monkeypatch):
    """Interrupted while its GIF is made, a rerun left the earlier run's GIF and page beside its own result."""
    from synergrasp import viz

    stale = [tmp_path / "ellipsoid_precision_reach.gif", tmp_path / "ellipsoid_precision_grasp.html"]
    for f in stale:
        f.write_text("an earlier plan")

    def interrupted(*args, **kwargs):
        raise KeyboardInterrupt

    monkeypatch.setattr(viz, "animate", interrupted)
    main(["plan", "--object", "ellipsoid", "--out", str(tmp_path), "--quiet"])
    assert (tmp_path / "ellipsoid_precision.json").is_file() and not any(f.exists() for f in stale)


def test_plan_says_how_long_the_kernels_compiled(tmp_path, capsys, monkeypatch):
    """The first plan after an install spends seconds in numba's compilation: the output says how many (here a
    clock, perf_counter less the compilation, that lost 5 s during the plan)."""
    import time

    import synergrasp.planner

    calls = []

    def clock():
        calls.append(None)
        return time.perf_counter() - (5.0 if len(calls) > 1 else 0.0)

    monkeypatch.setattr(synergrasp.planner, "clock", clock)
    assert main(["plan", "--object", "ellipsoid", "--out", str(tmp_path), "--quiet", "--no-animation"]) == 0
    out = capsys.readouterr().out
    printed = re.search(r"numba compiled the library's kernels for ([\d.]+) s of this run's ([\d.]+) s", out)
    assert printed and float(printed.group(1)) == pytest.approx(5.0, abs=0.05)
    assert re.search(r"time [\d.]+ s \(with part of numba's compilation, below\), \d+ LP solves", out)


@pytest.mark.parametrize(
    "argv, message",
    [
        (["plan", "--object", "teapot"], "unknown object 'teapot'"),
        (["plan", "--backend", "gurobi"], "unknown LP backend 'gurobi'"),
        (["plan", "--object", "."], "object '.' is a folder: give a mesh or point-cloud file in it"),
        (["demo", "--mu", "-1"], "mu must be a finite number > 0"),
        (["plan", "--object", ""], "the object name is empty: give a built-in"),
    ],
)
def test_bad_input_is_a_clear_error(tmp_path, capsys, argv, message):
    assert main(argv + (["--out", str(tmp_path), "--quiet"] if argv[0] == "plan" else [])) == 2
    assert message in capsys.readouterr().err


def test_demo_prints_no_negative_zero_beside_not_force_closed(capsys):
    """Two opposite contacts: Q is -1e-17, which is no force closure; "-0.0000" read as a grasp."""
    assert main(["demo", "--contacts", "2"]) == 0
    assert "Q distance = +0.0000 (not force-closed)" in capsys.readouterr().out


def test_bad_approach_is_rejected_by_the_parser(capsys):
    with pytest.raises(SystemExit):
        build_parser().parse_args(["plan", "--approach", "1,2"])
    assert "expected three numbers" in capsys.readouterr().err


def test_an_approach_that_starts_with_a_minus_sign_is_taken_as_given(tmp_path, capsys):
    """``--approach -1,0,0`` (a value argparse took for an option: "expected one argument") and ``--approach=-1,0,0``
    start the plan from that direction; a plain negative number stays an argument error."""
    for given in (["--approach", "-1,0,0"], ["--approach=-1,0,0"], ["--appr", "-1,0,0"], ["--a", "-1,0,0"]):
        out = tmp_path / given[0].replace("=", "_")
        assert main(["plan", "--object", "cup", *given, "--max-iter", "2", "--out", str(out), "--no-animation",
                     "--quiet"]) == 1
        first = json.loads((out / "cup_precision.json").read_text())["attempts"][0]
        assert first["kind"] == "direction" and first["direction"] == [-1.0, 0.0, 0.0]
    with pytest.raises(SystemExit):
        main(["plan", "--approach", "-1"])
    assert "expected three numbers x,y,z, got '-1'" in capsys.readouterr().err


def test_version(capsys):
    import synergrasp as sg

    with pytest.raises(SystemExit) as exc:
        main(["--version"])
    assert exc.value.code == 0 and capsys.readouterr().out.strip() == f"synergrasp {sg.__version__}"


def test_python_dash_m_synergrasp_is_the_command_line(capsys, monkeypatch):
    import runpy

    import synergrasp as sg

    monkeypatch.setattr("sys.argv", ["synergrasp", "--version"])
    with pytest.raises(SystemExit) as exc:
        runpy.run_module("synergrasp", run_name="__main__")
    assert exc.value.code == 0 and capsys.readouterr().out.strip() == f"synergrasp {sg.__version__}"


def write_capsule_cloud(path, scale=1.0):
    """Points on a capsule 70 mm wide and 130 mm long, times ``scale`` (0.001: in metres), as .xyz or .npy."""
    points = trimesh.sample.sample_surface(trimesh.creation.capsule(height=60.0, radius=35.0), 1500, seed=0)[0] * scale
    if path.suffix == ".npy":
        np.save(path, points)
    else:
        np.savetxt(path, points)
    return path


@pytest.mark.parametrize("units", [["--units", "m"], ["--scale", "1000"]])
def test_scale_and_units(tmp_path, capsys, units):
    path = write_capsule_cloud(tmp_path / "capsule_m.xyz", scale=0.001)
    out = tmp_path / "out"
    assert main(["plan", "--object", str(path), "--out", str(out), "--quiet", "--no-animation"]) == 2
    err = capsys.readouterr().err                                 # in metres, without the factor:
    assert "too small to grasp" in err and "on the command line: --units m" in err
    assert main(["plan", "--object", str(path), *units, "--max-iter", "2", "--out", str(out), "--quiet", "--no-animation"]) == 1
    assert json.loads((out / "capsule_m_xyz_precision.json").read_text())["iterations"] == 2
    assert main(["plan", "--object", "cup", *units, "--out", str(out), "--quiet"]) == 2
    assert "applies to object files" in capsys.readouterr().err


@pytest.mark.parametrize("units, given", [(["--units", "m"], "--units m"), (["--scale", "1000"], "--scale 1000")])
def test_a_file_in_mm_read_with_a_unit_option_is_told_to_drop_it(tmp_path, capsys, units, given):
    """A file already in mm, read with --units m: the advice names the option it was given, not that option again."""
    path = write_capsule_cloud(tmp_path / "capsule.xyz")
    assert main(["plan", "--object", str(path), *units, "--out", str(tmp_path / "out"), "--quiet"]) == 2
    err = capsys.readouterr().err
    assert f"(on the command line: it was read with {given}; drop it if the file is in mm" in err
    assert "(on the command line: --units m or cm" not in err


def test_loading_a_file_says_what_it_is_doing(tmp_path, capsys):
    """A file's decomposition can take a minute: the command says so before, and what it made after."""
    path = write_capsule_cloud(tmp_path / "capsule.npy")
    argv = ["plan", "--object", str(path), "--max-iter", "2", "--out", str(tmp_path / "out"), "--no-animation"]
    assert main(argv) == 1
    err = capsys.readouterr().err
    assert f"loading {path} (a mesh or cloud new to the cache is cut into convex pieces first)" in err
    assert "capsule.npy: 1 convex piece(s) (hull, cache " in err
    assert main([*argv, "--quiet"]) == 1 and "loading" not in capsys.readouterr().err
    assert main(["plan", "--object", "cup", "--max-iter", "2", "--out", str(tmp_path / "out"), "--no-animation"]) == 1
    assert "loading" not in capsys.readouterr().err  # a built-in object is ready at once
    assert main(["plan", "--object", "elipsoid", "--out", str(tmp_path / "out")]) == 2
    assert "loading" not in capsys.readouterr().err  # a misspelt name is no file to load


@pytest.mark.parametrize("argv, message", [
    (["--scale", "0"], "expected a finite number > 0"),
    (["--scale", "nan"], "expected a finite number > 0"),
    (["--units", "inch"], "invalid choice: 'inch'"),
    (["--scale", "10", "--units", "m"], "not allowed with argument"),
    (["--max-iter", "0"], "expected an integer > 0"),
    (["--time-limit", "-1"], "expected a finite number > 0"),
    (["--time-limit", "inf"], "expected a finite number > 0, got 'inf'"),
    (["--approach", "1,nan,0"], "expected three finite numbers"),
])
def test_bad_arguments_exit_2(capsys, argv, message):
    with pytest.raises(SystemExit) as exc:
        main(["plan", *argv])
    assert exc.value.code == 2 and message in capsys.readouterr().err


def test_unwritable_out_is_found_before_planning(tmp_path, capsys, monkeypatch):
    import synergrasp.planner

    planned = []
    monkeypatch.setattr(synergrasp.planner, "plan", lambda *a, **k: planned.append(1))
    blocker = tmp_path / "results"
    blocker.write_text("a file where the folder should be")
    for out in (blocker, blocker / "sub"):
        assert main(["plan", "--out", str(out), "--quiet"]) == 2
        err = capsys.readouterr().err
        assert err.startswith("synergrasp: error: cannot write to the output folder (--out)") and str(out) in err
    assert planned == []


def test_bad_input_makes_no_output_folder(tmp_path, capsys):
    """An unknown object, a folder given as the object, an unknown backend, a missing result to validate: refused
    (exit 2) after the output folder was made, which stayed behind empty."""
    (tmp_path / "a folder").mkdir()
    for argv in (["plan", "--object", "teapot"], ["plan", "--object", str(tmp_path / "a folder")],
                 ["plan", "--backend", "gurobi"], ["validate", str(tmp_path / "none.json"), "--object", "cup"]):
        out = tmp_path / "left" / "deep"
        assert main([*argv, "--out", str(out), "--quiet"] if argv[0] == "plan" else [*argv, "--out", str(out)]) == 2
        assert not (tmp_path / "left").exists(), argv
    capsys.readouterr()


def test_inputs_never_share_output_files(tmp_path, capsys):
    out = tmp_path / "out"
    for name in ("capsule.xyz", "capsule.npy"):
        path = write_capsule_cloud(tmp_path / name)
        assert main(["plan", "--object", str(path), "--max-iter", "2", "--out", str(out), "--quiet", "--no-animation"]) == 1
    capsys.readouterr()
    names = sorted(p.name for p in out.iterdir())
    assert names == ["capsule_npy_precision.json", "capsule_npy_precision_poses.png", "capsule_npy_precision_status.png",
                     "capsule_xyz_precision.json", "capsule_xyz_precision_poses.png", "capsule_xyz_precision_status.png"]
    assert json.loads((out / "capsule_xyz_precision.json").read_text())["object_name"] == "capsule.xyz"


def test_a_failed_plan_reports_every_attempt(tmp_path, capsys):
    code = main(["plan", "--object", "ellipsoid", "--max-iter", "12", "--out", str(tmp_path), "--quiet", "--no-animation"])
    out = capsys.readouterr().out
    assert code == 1 and out.startswith("FAILED: no stable grasp found")
    saved = json.loads((tmp_path / "ellipsoid_precision.json").read_text())
    table = out[out.index("#  start"):].splitlines()
    rows = [line for line in table[1:] if line[:1].isdigit()]
    assert len(rows) == len(saved["attempts"]) >= 1
    for row, attempt in zip(rows, saved["attempts"]):
        assert row.rstrip().endswith(attempt["reason"]) and f" {attempt['iterations']} " in row
        assert row.split()[1] == attempt["kind"]  # how it started (a pinch with its width)
        if attempt["kind"] == "pinch":
            assert f"pinch {attempt['width']:.0f} mm" in row


def test_the_time_limit_reaches_the_planner(tmp_path, capsys):
    """--time-limit is the plan's time_limit: with 1 ms the first attempt ends at once, saying so."""
    code = main(["plan", "--object", "ellipsoid", "--time-limit", "0.001", "--out", str(tmp_path), "--quiet", "--no-animation"])
    saved = json.loads((tmp_path / "ellipsoid_precision.json").read_text())
    assert code == 1 and saved["options"]["time_limit"] == 0.001
    assert len(saved["attempts"]) == 1 and saved["attempts"][0]["reason"].startswith("the plan's iterations or time ran out")


def test_no_solver_banner_on_stdout(tmp_path):
    """Run as a user would: the HiGHS banner must not reach stdout."""
    import os
    import subprocess
    import sys
    from pathlib import Path

    root = Path(__file__).resolve().parents[1]
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(filter(None, [str(root), os.environ.get("PYTHONPATH")])))
    proc = subprocess.run([sys.executable, "-m", "synergrasp.cli", "demo"], capture_output=True, text=True, env=env,
                          cwd=tmp_path, timeout=120)
    assert proc.returncode == 0 and proc.stdout.startswith("5 contacts spread") and "HiGHS" not in proc.stdout


def test_ctrl_c_and_a_closed_pipe_end_the_command_with_a_line_not_a_traceback(tmp_path, capsys, monkeypatch):
    """Ctrl-C during a plan printed a 30-line traceback (exit 130 all the same); `synergrasp plan ... | head -1`
    exited 2, "error: [Errno 32] Broken pipe", in 3 of 5 runs, after its files were written."""
    import os
    import subprocess
    import sys
    from pathlib import Path

    import synergrasp.planner

    def interrupted(*args, **kwargs):
        raise KeyboardInterrupt

    monkeypatch.setattr(synergrasp.planner, "plan", interrupted)
    assert main(["plan", "--out", str(tmp_path), "--quiet"]) == 130
    assert capsys.readouterr().err == "synergrasp: interrupted\n"
    root = Path(__file__).resolve().parents[1]
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(filter(None, [str(root), os.environ.get("PYTHONPATH")])))
    proc = subprocess.Popen([sys.executable, "-m", "synergrasp.cli", "demo"], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, env=env, cwd=tmp_path)
    proc.stdout.close()  # the reader is gone before the first line
    err = proc.stderr.read()
    assert proc.wait(timeout=120) == 141 and err == "", err


def test_exit_codes_are_documented(capsys):
    from synergrasp.cli import EXIT_CODES

    assert sorted(EXIT_CODES) == [0, 1, 2, 130, 141]
    for argv in ([], ["plan"], ["demo"], ["validate"], ["batch"]):
        with pytest.raises(SystemExit):
            main(argv + ["--help"])
        text = " ".join(capsys.readouterr().out.split())
        assert all(f"{code} {' '.join(meaning.split())}" in text for code, meaning in EXIT_CODES.items())


def test_output_folder_and_positive_are_usage_errors(tmp_path):
    """The argparse types the example and benchmark scripts share: a folder is made, a file or a bad number refused."""
    import argparse

    from synergrasp.cli import output_folder, positive

    assert output_folder(str(tmp_path / "a" / "b")) == tmp_path / "a" / "b" and (tmp_path / "a" / "b").is_dir()
    (tmp_path / "file").write_text("x")
    with pytest.raises(argparse.ArgumentTypeError, match="it is a file, not a folder"):
        output_folder(str(tmp_path / "file"))
    with pytest.raises(argparse.ArgumentTypeError, match="empty name"):
        output_folder("")
    assert positive(int)("3") == 3 and positive(float)("0.5") == 0.5
    for kind, text in [(int, "0"), (int, "-2"), (int, "1.5"), (float, "nan"), (float, "inf"), (float, "0")]:
        with pytest.raises(argparse.ArgumentTypeError, match="> 0"):
            positive(kind)(text)


def test_plan_takes_a_hand_file(tmp_path, capsys):
    """`synergrasp validate` took --hand and errors advised it, but `synergrasp plan` had no --hand."""
    import json

    from synergrasp import SynergyHand, PlanResult

    data = SynergyHand.default().to_dict()
    data.update(name="thick", finger_radius=9.0)
    (tmp_path / "thick.json").write_text(json.dumps(data))
    assert main(["plan", "--object", "cup", "--hand", str(tmp_path / "thick.json"), "--out", str(tmp_path / "out"),
                 "--quiet", "--no-animation"]) == 0
    saved = PlanResult.load(tmp_path / "out" / "cup_precision.json")
    assert saved.success and saved.hand == SynergyHand(data).identity
    assert main(["plan", "--hand", str(tmp_path / "none.json"), "--out", str(tmp_path / "out")]) == 2
    assert "hand file not found" in capsys.readouterr().err


def test_the_plan_gif_animates_the_reach_to_execute(tmp_path):
    """A successful plan's GIF shows the executable reach, one frame per row of its path (pre-grasp to grasp), not
    the planner's iteration."""
    from PIL import Image

    from synergrasp import PlanResult

    main(["plan", "--object", "ellipsoid", "--out", str(tmp_path), "--quiet"])
    result = PlanResult.load(tmp_path / "ellipsoid_precision.json")
    assert len(result.path) != len(result.trajectory)  # (the frames tell the two apart)
    with Image.open(tmp_path / "ellipsoid_precision_reach.gif") as gif:
        assert gif.n_frames == min(len(result.path), 120)
