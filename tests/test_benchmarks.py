"""Benchmark scripts in their quick modes: they run, report what they claim and write only under --out."""

import json

from benchmarks import bench_large_mesh


def test_large_mesh_quick(tmp_path, capsys):
    """A small torus loads (CoACD), plans, and its time and peak memory are reported (no figure asserted)."""
    row = bench_large_mesh.main(["--quick", "--out", str(tmp_path)])
    assert json.loads((tmp_path / "large_mesh.json").read_text()) == row
    assert row["faces"] >= 4000 and row["method"] == "coacd" and row["pieces"] >= 2
    assert row["success"] and row["iterations"] > 0
    assert row["load_s"] > 0 and row["plan_s"] > 0 and row["peak_rss_mb"] > 50
    assert "peak memory" in capsys.readouterr().out


def test_large_mesh_open_torus_cannot_be_capped(tmp_path, capsys):
    """--open: two faces that touch at a vertex removed, so loading closes the torus on a voxel grid."""
    torus = bench_large_mesh.torus(5000, opened=True)
    assert len(torus.faces) == len(bench_large_mesh.torus(5000).faces) - 2 and not torus.is_watertight
    with pytest.raises(SystemExit):
        bench_large_mesh.main(["--open", "--mesh", str(tmp_path / "x.stl"), "--out", str(tmp_path)])
    assert "does not take --mesh" in capsys.readouterr().err


def test_time_limit_quick(capsys):
    """A plan that cannot succeed runs to its limit and stops there (the ratio is reported, not asserted tightly)."""
    from benchmarks import bench_time_limit

    worst = bench_time_limit.main(["--quick"])
    assert worst >= 1.0  # it ran until the limit: the acceptance could not be met
    assert "largest overrun" in capsys.readouterr().out


def test_limits_quick(tmp_path, capsys):
    """The limits benchmark's quick mode plans and verifies one slender shape, its row written."""
    from benchmarks import limits

    rows = limits.main(["--quick", "--out", str(tmp_path)])
    written = [json.loads(line) for line in (tmp_path / "slender_train.jsonl").read_text().splitlines()]
    assert written == json.loads(json.dumps(rows)) and len(rows) == 1
    assert rows[0]["grasp"] == "precision" and rows[0]["torque"] < 0.05  # slender by the planner's measure
    assert rows[0]["verified"] and "precision: 1/1 verified" in capsys.readouterr().out


def test_limits_draws_each_family_as_documented():
    """The seeded sets: the same shapes every time, slender ones 8-28 mm across and 100-300 mm long, thin ones 2-16 mm
    thick (a taper's base) and 120-300 mm long, wide ones 80-160 mm across their narrowest side; the splits differ."""
    from benchmarks import limits

    slender = limits.shapes("slender", 1, 8)
    assert [n for n, _ in slender] == [n for n, _ in limits.shapes("slender", 1, 8)]
    assert [n for n, _ in slender] != [n for n, _ in limits.shapes("slender", 2, 8)]
    for name, mesh in slender:
        thin, _, long = np.sort(mesh.extents)
        assert name.split("_")[0] in limits.FAMILIES["slender"] and 6.9 < thin < 28.1 and 99.9 < long < 300.1  # (a hexagon: 0.87 d across flats)
    for name, mesh in limits.shapes("thin", 1, 8):
        thin, _, long = np.sort(mesh.extents)
        assert name.split("_")[0] in limits.FAMILIES["thin"] and 1.9 < thin < 16.1 and 119.9 < long < 300.1
    for name, mesh in limits.shapes("wide", 1, 8):
        assert name.split("_")[0] in limits.FAMILIES["wide"] and 79.0 < np.sort(mesh.extents)[0] < 160.1


def test_limits_loads_a_slender_object_at_its_diameter_when_asked():
    """``--slender-scale diameter``: a slender object's plan is made with a torque scale of twice its axial radius; a
    thick one keeps its bounding radius; verified on the same mesh either way."""
    from benchmarks import limits

    from synergrasp.planner.status import axial_radius

    rod = trimesh.creation.cylinder(radius=6.0, height=200.0, sections=16)
    row = limits.run(("rod", rod.vertices, rod.faces, "precision", True))
    assert row["torque_scale"] == pytest.approx(2.0 * axial_radius(sg.objects.from_mesh(rod, cache=False)))
    assert row["torque_scale"] == pytest.approx(12.0, abs=0.1) and row["verified"]
    ball = trimesh.creation.icosphere(subdivisions=2, radius=30.0)
    assert limits.run(("ball", ball.vertices, ball.faces, "precision", True))["torque_scale"] == pytest.approx(
        sg.objects.from_mesh(ball, cache=False).radius)


def test_small_objects_quick(tmp_path, capsys):
    """The 50 mm sphere (about the benchmark's smallest object) is grasped, and its row is written under --out."""
    from benchmarks import small_objects

    rows = small_objects.main(["--quick", "--out", str(tmp_path)])
    written = [json.loads(line) for line in (tmp_path / "small_objects.jsonl").read_text().splitlines()]
    assert written == rows and len(rows) == 1
    assert rows[0]["success"] and rows[0]["attempts"] >= 1 and rows[0]["shape"] == "sphere"
    assert "precision: 1/1 grasped" in capsys.readouterr().out


def test_power_reach_quick(tmp_path, capsys):
    """With the palm on a 30 mm ball at most 2 phalanges reach it (no power grasp); on the cup, enough for one."""
    import csv

    from benchmarks import power_reach

    rows = power_reach.main(["--quick", "--out", str(tmp_path)])
    with open(tmp_path / "power_reach.csv", newline="") as fh:
        written = list(csv.DictReader(fh))
    assert [r["name"] for r in rows] == [r["name"] for r in written] == ["30 mm ball", "cup"]
    ball, cup = (r["most_phalanges"] for r in rows)
    assert 0 <= ball <= 2 and cup >= 4  # the paper's power criterion needs the palm and 3 phalanges
    assert f"at most {ball} phalanges" in capsys.readouterr().out


def test_torus_has_the_faces_asked_for():
    mesh = bench_large_mesh.torus(330_000)
    assert 320_000 <= len(mesh.faces) <= 340_000 and mesh.is_watertight


def test_first_plan_quick(tmp_path, capsys):
    """The first process compiles into an empty cache; the second finds every kernel there and writes nothing."""
    from benchmarks import bench_first_plan

    row = bench_first_plan.main(["--quick", "--out", str(tmp_path)])
    assert json.loads((tmp_path / "first_plan.json").read_text()) == row
    first, second = row["cache_files"]
    assert first > 10 and second == first  # the second process compiled nothing new
    for run in (row["cold"], row["warm"]):
        assert list(run) == ["import", "first plan", "second plan"]
        assert all(wall > 0 and cpu > 0 for wall, cpu in run.values())
    assert "files in the cache" in capsys.readouterr().out


# --------------------------------------------------------------------------- generalisation benchmark

from types import SimpleNamespace  # noqa: E402

import zipfile  # noqa: E402

import numpy as np  # noqa: E402
import pytest  # noqa: E402
import trimesh  # noqa: E402

import synergrasp as sg  # noqa: E402
from benchmarks import generalise, objectset, verification  # noqa: E402


def test_the_benchmark_has_over_200_objects_in_a_fixed_split_by_shape():
    entries = objectset.catalogue()
    names = [e.name for e in entries]
    assert len(entries) >= 200 and len(set(names)) == len(names)
    assert {e.source for e in entries} == {"household", "urdf", "procedural"}
    by_base = {}
    for e in entries:
        by_base.setdefault(e.base, set()).add(e.split)
    assert all(len(splits) == 1 for splits in by_base.values())  # both sizes of a shape in one split
    counts = {s: sum(e.split == s for e in entries) for s in objectset.SPLITS}
    assert min(counts.values()) >= 100
    assert [e.name for e in objectset.select("test")] == [e.name for e in entries if e.split == "test"]
    assert [e.split for e in objectset.catalogue()] == [e.split for e in entries]  # the same split every time


def test_a_sweep_of_urdf_sizes_keeps_each_shape_in_its_split(tmp_path, capsys):
    swept = objectset.select("train", ["urdf/"], urdf_sizes=(60.0,))
    usual = objectset.select("train", ["urdf/"])
    assert {e.base for e in swept} == {e.base for e in usual} and all(e.name.endswith("@60") for e in swept)
    obj = swept[0].make()
    assert obj.mesh.extents.max() == pytest.approx(60.0)
    for argv, message in ((["--urdf-sizes", "0"], "argument --urdf-sizes: expected a finite number > 0"), (["--urdf-sizes", "60", "--docs"], "--docs writes")):
        with pytest.raises(SystemExit):
            generalise.main([*argv, "--out", str(tmp_path)])
        assert message in capsys.readouterr().err


def test_generalise_plans_clouds_sampled_on_the_objects_and_verifies_them_on_the_meshes(tmp_path, capsys):
    # (no time limit: the box's cloud is grasped at its 24th attempt, past the 10 s on a loaded machine)
    generalise.main(["--quick", "--grasp", "power", "--cloud", "2000", "--option", "time_limit=None", "--out", str(tmp_path)])
    rows = [json.loads(line) for line in (tmp_path / "test_power.jsonl").read_text().splitlines()]
    assert [r["name"] for r in rows] == list(generalise.QUICK) and all(r["success"] for r in rows)
    assert all(r["verified"] == (r["gap"] <= verification.GAP and r["closed"] and r["depth"] <= verification.DEPTH
                                 and r["palm_depth"] <= verification.DEPTH) for r in rows)
    assert all(r["overhang"] > 0.0 for r in rows)  # the clouds' pieces measured against the meshes
    for argv, message in ((["--cloud", "50"], "at least 100"), (["--cloud", "2000", "--docs"], "--docs writes"),
                          (["--noise", "0.5"], "needs --cloud"), (["--cloud", "2000", "--noise", "-1"], "must be >= 0")):
        with pytest.raises(SystemExit):
            generalise.main([*argv, "--out", str(tmp_path)])
        assert message in capsys.readouterr().err


def test_generalise_poses_each_object_its_own_way_and_verifies_it_there(tmp_path, capsys):
    """--pose: a uniform rotation and a 150 mm move per object, fixed by the seed and the name; plans verified on the
    moved mesh."""
    a, b = generalise.pose("urdf/013@80", 1), generalise.pose("urdf/013@80", 1)
    np.testing.assert_array_equal(a, b)
    assert not np.allclose(a, generalise.pose("urdf/013@120", 1)) and not np.allclose(a, generalise.pose("urdf/013@80", 2))
    np.testing.assert_allclose(a[:3, :3] @ a[:3, :3].T, np.eye(3), atol=1e-12)
    assert np.linalg.det(a[:3, :3]) == pytest.approx(1.0) and np.linalg.norm(a[:3, 3]) == pytest.approx(generalise.SHIFT)
    generalise.main(["--quick", "--grasp", "precision", "--pose", "1", "--out", str(tmp_path)])
    rows = [json.loads(line) for line in (tmp_path / "test_precision.jsonl").read_text().splitlines()]
    assert [r["name"] for r in rows] == list(generalise.QUICK) and all(r["verified"] for r in rows)
    assert all(r["pose"] == 1 for r in rows)
    for argv, message in ((["--pose", "1", "--docs"], "--docs writes"), (["--pose", "-1"], "must be a seed >= 0")):
        with pytest.raises(SystemExit):
            generalise.main([*argv, "--out", str(tmp_path)])
        assert message in capsys.readouterr().err


def test_procedural_objects_are_seeded():
    a, b = objectset.select("all", ["procedural/blob_2"])[0].make(), objectset.select("all", ["procedural/blob_2"])[0].make()
    np.testing.assert_array_equal(a.mesh.vertices, b.mesh.vertices)
    assert a.mesh.is_watertight and 10.0 < a.size < 200.0


def test_verification_is_on_the_true_surface():
    box = sg.objects.from_mesh(trimesh.creation.box((60.0, 50.0, 90.0)), name="box", cache=False)
    r = sg.plan(box, "precision")
    assert verification.verify(r, box)["verified"]
    off = SimpleNamespace(success=True, u=r.u, contact_points=r.contact_points + [0.0, 0.0, 100.0])
    assert not verification.verify(off, box)["verified"] and verification.verify(off, box)["gap"] > 5.0
    one_side = SimpleNamespace(success=True, u=r.u, contact_points=[[30.0, y, z] for y in (-10, 10) for z in (-10, 10)])
    check = verification.verify(one_side, box)  # four contacts on one face: on the surface, not force-closed
    assert check["gap"] < 1e-9 and not check["closed"] and not check["verified"]
    into = r.u + np.r_[0.5 * (box.center - r.u[:3]), np.zeros(len(r.u) - 3)]  # the hand halfway to the centre
    deep = verification.verify(SimpleNamespace(success=True, u=into, contact_points=r.contact_points), box)
    assert deep["closed"] and max(deep["depth"], deep["palm_depth"]) > 3.0 and not deep["verified"]


@pytest.mark.parametrize("argv, says", [
    (["--option", "max_iter=0"], "PlannerOptions.max_iter must be in [1, inf), got 0"),  # not "refused" on every row
    (["--option", "foo=1"], "unknown planner options ['foo']"),
    (["--option", "max_iter"], "--option takes NAME=VALUE items"),
    (["--jobs", "0"], "argument --jobs: expected an integer > 0, got '0'"),
    (["--only", "nosuch"], "['nosuch'] name no object of the 'train' split"),
])
def test_generalise_refuses_bad_arguments_before_any_plan(tmp_path, capsys, argv, says):
    with pytest.raises(SystemExit):
        generalise.main(["--split", "train", "--grasp", "precision", "--out", str(tmp_path), *argv])
    assert says in capsys.readouterr().err and not list(tmp_path.iterdir())


def test_generalise_quick(tmp_path, capsys):
    generalise.main(["--quick", "--grasp", "precision", "--out", str(tmp_path)])
    rows = [json.loads(line) for line in (tmp_path / "test_precision.jsonl").read_text().splitlines()]
    assert [r["name"] for r in rows] == list(generalise.QUICK)
    assert all(r["verified"] for r in rows)
    out = capsys.readouterr().out
    assert "precision: 2/2 verified" in out and "median Q on the true surface" in out


def test_holdout_draws_unused_shapes_and_plans_them(tmp_path, capsys):
    """holdout.py: a fixed draw outside the benchmark; the wheel's meshes planned and verified at the given size."""
    from benchmarks import holdout

    rest = holdout.unused_numbers()
    held = {p.stem for p in objectset.URDFS.glob("*.stl")}
    assert len(rest) == 1000 - len(held) - 6 and not held & set(rest) and "000" not in rest
    assert holdout.draw(5) == holdout.draw(5) and set(holdout.draw(5)) <= set(rest)
    with pytest.raises(ValueError, match="--count"):
        holdout.draw(0)
    (k,) = holdout.draw(1)
    wheel = tmp_path / "pybullet-0-py3-none-any.whl"  # a stand-in wheel: one box in the wheel's layout
    box = trimesh.creation.box((2.0, 1.5, 1.0))
    with zipfile.ZipFile(wheel, "w") as z:
        z.writestr(f"pybullet_data/random_urdfs/{k}/{k}.obj", trimesh.exchange.obj.export_obj(box))
    (row,) = holdout.main(["--count", "1", "--size", "90", "--grasp", "precision", "--wheel", str(wheel),
                           "--out", str(tmp_path / "out")])
    assert row["name"] == f"holdout/{k}@90" and row["verified"]
    mesh = trimesh.load(tmp_path / "out" / "meshes" / f"{k}.stl")
    np.testing.assert_allclose(mesh.bounds, box.bounds)
    assert "precision: 1/1 verified" in capsys.readouterr().out
    with pytest.raises(SystemExit, match="has no pybullet_data/random_urdfs"):  # a wheel without the drawn mesh
        holdout.main(["--count", "2", "--wheel", str(wheel), "--out", str(tmp_path / "other")])


def test_holdout_says_what_to_do_when_the_wheel_cannot_be_downloaded(tmp_path, monkeypatch):
    from benchmarks import holdout

    calls = []
    monkeypatch.setattr(holdout.subprocess, "run", lambda command: calls.append(command) or SimpleNamespace(returncode=1))
    with pytest.raises(SystemExit, match="could not download pybullet 3.2.7 .*--wheel"):
        holdout.main(["--count", "1", "--out", str(tmp_path)])
    (command,) = calls
    assert "pybullet==3.2.7" in command and "--no-cache-dir" in command and command[-1] == str(tmp_path)
    with pytest.raises(SystemExit):  # argparse's error for a size that is not a positive number
        holdout.main(["--size", "nan", "--out", str(tmp_path)])
    assert len(calls) == 1  # refused before anything is fetched


def test_single_attempts_writes_every_attempt(tmp_path, capsys):
    from benchmarks import single_attempts

    out = tmp_path / "attempts.jsonl"
    single_attempts.main(["--split", "all", "--only", "household/can", "--starts", "2", "--out", str(out)])
    rows = [json.loads(line) for line in out.read_text().splitlines()]
    assert len(rows) == 2 and {r["start"] for r in rows} == {"pinch"} and all(r["iterations"] > 0 for r in rows)
    ok, spent = sum(r["verified"] for r in rows), sum(r["iterations"] for r in rows)
    out = capsys.readouterr().out
    assert f"{ok}/2 single attempts verified" in out and f"{spent} iterations in all, {spent / max(ok, 1):.0f} per verified" in out
    assert all(r["pose"] is None for r in rows)


def test_single_attempts_turns_the_objects_as_generalise_does(tmp_path, capsys):
    from benchmarks import single_attempts

    can = objectset.select("all", ["household/can"])[0].make()
    moved = generalise.placed(can, "household/can", 1)
    np.testing.assert_allclose(np.linalg.norm(moved.center), generalise.SHIFT, rtol=1e-9)
    assert moved.volume == pytest.approx(can.volume, rel=1e-9)
    out = tmp_path / "attempts.jsonl"
    single_attempts.main(["--split", "all", "--only", "household/can", "--starts", "1", "--pose", "1", "--out", str(out)])
    (row,) = [json.loads(line) for line in out.read_text().splitlines()]
    assert row["pose"] == 1 and row["iterations"] > 0
    assert "precision, all, pose 1, options default: " in capsys.readouterr().out
    with pytest.raises(SystemExit):
        single_attempts.main(["--pose", "-1"])
    assert "must be a seed >= 0" in capsys.readouterr().err
    with pytest.raises(SystemExit):  # a folder for the file: refused before any attempt runs
        single_attempts.main(["--only", "household/can", "--out", str(tmp_path)])
    assert "is a folder: give a file in it" in capsys.readouterr().err


def test_validated_plans_quick(capsys):
    """plan(validate=True) on the ellipsoid's power grasp: the verdict printed is the plan's own."""
    from benchmarks import validated_plans

    (row,) = validated_plans.main(["--quick"])
    assert row["success"] and row["attempts"] >= 1
    assert f"power: {int(row['held'])}/1 hold in simulation" in capsys.readouterr().out


def test_generalise_rows_mode_summarises_an_earlier_run(tmp_path, capsys):
    """--rows plans nothing: the summary of the rows a run wrote, and its figure."""
    rows = [dict(name=f"o{i}", source="procedural", split="test", grasp="precision", success=i < 3, verified=i < 2,
                 time=0.1 * (i + 1), iterations=10 * (i + 1), reason="r", refused=False, q=-0.05, q_true=-0.04, gap=1.0, closed=True, depth=0.5,
                 palm_depth=0.0, collision_free=True, overhang=1.0, attempts=[dict(outcome="stalled", iterations=3)])
            for i in range(4)]
    (tmp_path / "test_precision.jsonl").write_text("".join(json.dumps(r) + "\n" for r in rows))
    generalise.main(["--rows", "--grasp", "precision", "--out", str(tmp_path)])
    out = capsys.readouterr().out
    assert "precision: 2/4 verified (50.0%)" in out and "collision-free executable reach: 3/3" in out
    assert "iterations per plan: median 25, 100 in all" in out
    refused = generalise.plan_row(sg.objects.ellipsoid(400.0, 400.0, 400.0), "precision", {}, name="big", source="x",
                                  split="test")  # the planner refuses it: no iteration
    assert refused["refused"] and refused["iterations"] == 0
    (tmp_path / "test_precision.jsonl").write_text("".join(json.dumps(r) + "\n" for r in rows + [refused]))
    generalise.main(["--rows", "--grasp", "precision", "--out", str(tmp_path)])
    assert "iterations per plan: median 20, 100 in all" in capsys.readouterr().out
    generalise.plot(rows, tmp_path / "figure.png")
    assert (tmp_path / "figure.png").stat().st_size > 10_000


def test_generalise_reports_the_median_of_several_runs(tmp_path, capsys):
    """With rows of three runs, the verified count is the median of the runs' counts; the table marks disagreements."""
    verdicts = [(1, 1, 0, 0), (1, 0, 1, 0), (1, 1, 1, 0)]  # 2, 2 and 3 verified
    rows = [dict(name=f"o{i}", source="urdf", split="test", grasp="power", success=True, verified=bool(v), time=1.0 + k,
                 iterations=40,
                 reason="r", refused=False, q=-0.05, q_true=-0.04, gap=1.0, closed=True, depth=0.5, palm_depth=0.0,
                 collision_free=True, overhang=1.0, attempts=[], run=k)
            for k, verdict in enumerate(verdicts) for i, v in enumerate(verdict)]
    (tmp_path / "test_power.jsonl").write_text("".join(json.dumps(r) + "\n" for r in rows))
    generalise.main(["--rows", "--grasp", "power", "--out", str(tmp_path)])
    out = capsys.readouterr().out
    assert "power: 2/4 verified (50.0%, median of 3 runs: 2, 2, 3), by source: urdf 2/4" in out
    assert "accepted 12 (the 3 runs pooled)" in out and "o3 in run 0" in out
    table = {r["name"]: (verified, seconds) for r, verified, seconds in generalise.per_object(rows)}
    assert table == {"o0": ("yes", 2.0), "o1": ("2/3", 2.0), "o2": ("2/3", 2.0), "o3": ("no", 2.0)}
    with pytest.raises(SystemExit):
        generalise.main(["--runs", "0", "--out", str(tmp_path)])


def test_parts_quick(tmp_path, capsys):
    """Every part is timed over what it names, the rows go under --out, and a second run computes the same seeds,
    trajectories and contact tests (each attempt starts from a plan's cold state)."""
    import csv

    from benchmarks import bench_parts

    rows = bench_parts.main(["--quick", "--out", str(tmp_path)])
    assert [r[0] for r in rows] == ["grid", "pinch", "wrap", "precision", "power", "contact"]
    assert all(count > 0 and ms > 0 for _, count, ms, _ in rows)
    with open(tmp_path / "parts.csv", newline="") as fh:
        assert [w["fingerprint"] for w in csv.DictReader(fh)] == [r[3] for r in rows]
    assert [r[3] for r in bench_parts.main(["--quick", "--out", str(tmp_path)])] == [r[3] for r in rows]
    assert "ms per iteration" in capsys.readouterr().out


def test_one_sided_quick(tmp_path, capsys):
    """The whole cloud of the first train object is not warned of, its camera view is, and rows go under --out."""
    from benchmarks import one_sided

    rows = one_sided.main(["--quick", "--out", str(tmp_path)])
    written = [json.loads(line) for line in (tmp_path / "one_sided_train.jsonl").read_text().splitlines()]
    assert written == rows and [r["cloud"] for r in rows] == ["whole", "view 1"]
    assert rows[0]["net"] < 0.1 and not rows[0]["warned"]
    assert rows[1]["net"] > 0.3 and rows[1]["warned"]
    assert "camera views: 1, warned as seen from one side 1" in capsys.readouterr().out


# --------------------------------------------------------------------------- the scripts' shared argument types

from pathlib import Path  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
SCRIPT_MODULES = sorted(f"{p.parent.name}.{p.stem}" for folder in ("benchmarks", "solvers") for p in (ROOT / folder).glob("*.py")
                        if "type=output_folder" in p.read_text())


@pytest.mark.parametrize("module", SCRIPT_MODULES)
def test_an_output_folder_that_is_a_file_is_a_usage_error(module, tmp_path, capsys):
    """Every benchmark's --out: a file there is refused by argparse (exit 2) before any work, not by a traceback after it."""
    import importlib

    (tmp_path / "file").write_text("x")
    with pytest.raises(SystemExit) as exit_:
        importlib.import_module(module).main(["--out", str(tmp_path / "file")])
    assert exit_.value.code == 2
    assert "cannot write to the output folder" in capsys.readouterr().err


def test_script_inputs_that_are_not_what_they_claim_are_usage_errors(tmp_path, capsys):
    """holdout's --wheel that is no zip file, household's --meshes that is no folder, revalidate's folder that is missing."""
    from benchmarks import holdout, household, revalidate

    (tmp_path / "notes.whl").write_text("not a zip file")
    cases = [(holdout.main, ["--count", "1", "--wheel", str(tmp_path / "notes.whl"), "--out", str(tmp_path / "o")],
              "is not a wheel (a zip file)"),
             (household.main, ["--meshes", str(tmp_path / "missing")], "is not a folder: name a folder of mesh"),
             (revalidate.main, [str(tmp_path / "missing")], "is not a folder: name the --out folder of a physics_study")]
    for main, argv, says in cases:
        with pytest.raises(SystemExit) as exit_:
            main(argv)
        assert exit_.value.code == 2 and says in capsys.readouterr().err
    with pytest.raises(SystemExit, match="holds no validated plan"):  # a folder, but not a study's
        revalidate.main([str(tmp_path), "--set", "paper"])
