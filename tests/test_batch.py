"""Batch planning on Dask (synergrasp.batch): tasks, result files, failures, interrupts, reports.

The Dask tests run on LocalClusters on the loopback interface. Expected plans are computed
here with ``sg.plan`` directly, on a freshly loaded object and a new backend instance.
"""

import csv
import json
import logging
import os
import re
import signal
import subprocess
import sys
import threading
import time
import warnings
from pathlib import Path

import distributed
import numpy as np
import pytest
import trimesh

import synergrasp as sg
from synergrasp.batch import COLUMNS, ResultStore, TaskFailure, expand, grasp_summary, local_cluster, run, write_report
from synergrasp.cli import main
from synergrasp.pseudo_distance import reset_regime_memory

ROOT = Path(__file__).resolve().parents[1]
@pytest.fixture(scope="module")
def cluster():
    with local_cluster(2) as local:
        yield local


@pytest.fixture(autouse=True)
def cache(tmp_path, monkeypatch):
    monkeypatch.setenv("SYNERGRASP_CACHE", str(tmp_path / "cache"))


def expected_plan(source, grasp, **options):
    """The plan of a task computed without the batch code, as in a new process (fresh object, new backend)."""
    reset_regime_memory()
    backend = type(sg.lp.get_backend())()  # the default backend
    return sg.plan(sg.objects.get(source), grasp, backend=backend, **options)


def assert_same_plan(path, expected):
    """The result file at ``path`` is the plan ``expected``, bit for bit but for the timings."""
    got = sg.PlanResult.load(path)
    assert (got.success, got.reason, got.iterations, got.total_iterations, got.contact_labels, got.lp_solves) == (
        expected.success, expected.reason, expected.iterations, expected.total_iterations, expected.contact_labels,
        expected.lp_solves)
    as_text = lambda attempts: json.dumps(attempts, sort_keys=True, default=np.ndarray.tolist)  # noqa: E731 (NaN == NaN)
    assert as_text(got.attempts) == as_text(expected.attempts)
    for name in ("u", "trajectory", "status", "q_history", "contact_points", "contact_normals"):
        assert np.array_equal(getattr(got, name), getattr(expected, name), equal_nan=True), name


def result_files(out):
    return sorted(p.relative_to(out).as_posix() for p in Path(out).glob("results/**/*.json")
                  if p.name != "object.json" and not p.name.startswith("."))  # not temporary files


def read_summary(out):
    with open(Path(out) / "summary.csv", newline="") as handle:
        return list(csv.DictReader(handle))


# --------------------------------------------------------------------------- tasks


def test_expand_names_files_and_folders(tmp_path):
    folder = tmp_path / "meshes"
    (folder / "kitchen").mkdir(parents=True)
    (folder / ".hidden").mkdir()
    for path in (folder / "box.stl", folder / "kitchen" / "mug.obj", folder / ".hidden" / "x.stl",
                 folder / "notes.txt", tmp_path / "ball.ply"):
        path.write_text("x")
    tasks = expand(["ellipsoid", str(tmp_path / "ball.ply"), folder, "ellipsoid"], ["power", "precision"])
    assert [(t.key, t.grasp) for t in tasks] == [
        ("ellipsoid", "power"), ("ellipsoid", "precision"), ("ball.ply", "power"), ("ball.ply", "precision"),
        ("meshes/box.stl", "power"), ("meshes/box.stl", "precision"),
        ("meshes/kitchen/mug.obj", "power"), ("meshes/kitchen/mug.obj", "precision"),
    ]
    assert tasks[2].source == str((tmp_path / "ball.ply").resolve())
    assert tasks[6].source == str((folder / "kitchen" / "mug.obj").resolve())
    assert expand("teapot")[0].source == "teapot"  # kept as given: its load fails on a worker
    with pytest.raises(TypeError, match="a built-in name or a path, got bytes"):  # (its bytes were taken one by one)
        expand(b"cup")
    once = expand([folder / "kitchen" / "mug.obj", folder, "cup", "CUP"])  # each object once, under its first key
    assert [t.key for t in once] == ["mug.obj", "meshes/box.stl", "cup"]


def test_expand_warns_of_an_empty_folder(tmp_path):
    (tmp_path / "empty").mkdir()
    with pytest.warns(UserWarning, match="holds no object file"), pytest.raises(ValueError, match="no objects to plan"):
        expand([tmp_path / "empty"])


# --------------------------------------------------------------------------- result files


def test_store_rows_come_from_the_result_files(tmp_path):
    store = ResultStore(tmp_path / "out")
    store.check_writable()
    result = sg.plan(sg.objects.get("ellipsoid"), "precision")
    store.write_result("ellipsoid", "precision", result)
    store.write_result("cup", "power", TaskFailure("timeout", "no result within the time limit of 1 s", 1.5))
    rows, unreadable = store.scan()
    assert unreadable == [] and [(r["object"], r["grasp"], r["status"]) for r in rows] == [
        ("cup", "power", "timeout"), ("ellipsoid", "precision", "planned")]
    row = rows[1]
    assert (row["success"], row["reason"], row["iterations"], row["q"], row["sq"], row["contacts"]) == (
        True, result.reason, result.iterations, float(result.q_history[-1]), float(result.status[-1, -1]),
        len(result.contact_labels))
    assert rows[0]["time_s"] == 1.5 and rows[0]["reason"].startswith("no result within")
    # a retry that produced a plan replaces the failure record
    store.write_result("cup", "power", result)
    assert not store.failure_path("cup", "power").exists()
    assert [r["status"] for r in store.scan()[0]] == ["planned", "planned"]
    # a damaged file is reported, not read as a result
    store.result_path("cup", "power").write_text('{"success": tru')
    rows, unreadable = store.scan()
    assert [r["object"] for r in rows] == ["ellipsoid"] and unreadable == [store.result_path("cup", "power")]
    store.write_summary(rows)
    assert [(r["object"], r["grasp"], r["success"]) for r in read_summary(store.out)] == [
        ("ellipsoid", "precision", str(result.success))]
    # other damage is set aside alike, not a crash of the whole scan: a folder under a result's name, a failure
    # record of a time that is not seconds, a result of lists nested 1e5 deep (RecursionError), one without targets
    store.result_path("cup", "power").unlink()
    store.result_path("bowl", "power").mkdir(parents=True)
    for grasp, time_s in (("precision", float("nan")), ("power", [1])):
        store.write_result("mug", grasp, TaskFailure("timeout", "no result", 1.0))
        data = json.loads(store.failure_path("mug", grasp).read_text())
        store.failure_path("mug", grasp).write_text(json.dumps({**data, "time_s": time_s}))
    store.result_path("deep", "power").parent.mkdir(parents=True)
    store.result_path("deep", "power").write_text("[" * 100_000 + "]" * 100_000)
    saved = json.loads(store.result_path("ellipsoid", "precision").read_text())
    store.result_path("flat", "power").parent.mkdir(parents=True)
    store.result_path("flat", "power").write_text(json.dumps({**saved, "target": [], "status": [[]] * len(saved["status"])}))
    rows, unreadable = store.scan()
    assert [r["object"] for r in rows] == ["ellipsoid"]
    assert sorted(unreadable) == sorted([store.result_path("bowl", "power"), store.failure_path("mug", "precision"),
                                         store.failure_path("mug", "power"), store.result_path("deep", "power"),
                                         store.result_path("flat", "power")])


def test_a_script_without_the_main_guard_is_told_to_add_it(tmp_path):
    """Without ``if __name__ == "__main__":`` the workers import the script again and run it: there `run` says to add
    the guard, and the script itself ends with the same advice (not only distributed's "Nanny failed to start")."""
    code = f"import synergrasp as sg\nsg.batch.run(['ellipsoid'], ['precision'], {str(tmp_path / 'a')!r}, workers=1, progress=False)\n"
    with pytest.raises(RuntimeError, match="worker process imported your script again .* put the call under"):
        exec(compile(code, "script.py", "exec"), {"__name__": "__mp_main__"})  # as a spawned worker runs it
    assert not (tmp_path / "a").exists()  # refused before anything is written
    script = tmp_path / "script.py"
    script.write_text(code.replace("'a'", "'b'"))
    done = subprocess.run([sys.executable, str(script)], capture_output=True, text=True, timeout=120, cwd=tmp_path)
    assert done.returncode != 0
    assert "put the call under `if __name__" in done.stderr  # a worker's error
    assert done.stderr.rstrip().endswith("otherwise see the workers' errors printed above")  # the script's own


def test_output_folder_is_checked_before_the_scheduler(tmp_path):
    blocker = tmp_path / "file"
    blocker.write_text("x")
    # ValueError about the folder, not the ConnectionError of the silent scheduler
    with pytest.raises(ValueError, match="cannot write to the output folder"):
        run(["ellipsoid"], ["precision"], blocker / "out", scheduler="tcp://127.0.0.1:9", progress=False)
    if Path("/proc").is_dir():  # not writable even by root
        with pytest.raises(ValueError, match="choose a writable folder"):
            run(["ellipsoid"], ["precision"], "/proc", scheduler="tcp://127.0.0.1:9", progress=False)


def test_a_run_holds_the_folder_and_clears_killed_writers_temporaries(tmp_path):
    store = ResultStore(tmp_path)
    store.check_writable()
    (store.results / "cup").mkdir()
    stale = [store.results / "cup" / ".precision.0123abcd.tmp.json", tmp_path / ".summary.89abcdef.tmp.csv"]
    kept = [store.results / "cup" / ".notes.txt", tmp_path / ".lock"]
    for path in stale + kept:
        path.write_text("x")
    with store.lock():
        assert not any(p.exists() for p in stale) and all(p.exists() for p in kept)
        with pytest.raises(ValueError, match=rf"another batch \(process {os.getpid()}\) is writing to"):
            with ResultStore(tmp_path).lock():
                pass
    with ResultStore(tmp_path).lock():  # released at the end of the block
        pass


def test_grasp_summary_closed_form():
    rows = [{"grasp": "precision", "status": "planned", "success": k % 2 == 0, "time_s": float(k)} for k in range(1, 11)]
    rows.append({"grasp": "precision", "status": "plan error", "success": False, "time_s": 0.5})
    s, = grasp_summary(rows)
    assert (s["tasks"], s["success"], s["failed"], s["timeouts"]) == (11, 5, 1, 0)
    assert s["rate"] == pytest.approx(5 / 11)
    assert s["median_s"] == pytest.approx(5.5) and s["p90_s"] == pytest.approx(9.1)  # linear interpolation
    assert s["plans_per_s"] == pytest.approx(10 / 55)


def test_grasp_summary_reads_summary_csv(tmp_path):
    """summary.csv's rows, read back as strings, summarise as the scanned rows do; bad rows are named."""
    rows = [dict.fromkeys(COLUMNS, "") | {"object": f"o{k}", "grasp": "power", "status": "planned",
                                          "success": k != 1, "time_s": float(k), "held": [True, False, ""][k]}
            for k in range(3)]
    rows.append(dict.fromkeys(COLUMNS, "") | {"object": "o3", "grasp": "power", "status": "timeout",
                                              "success": False, "time_s": 9.0})
    store = ResultStore(tmp_path)
    store.write_summary(rows)
    with open(store.summary_path, newline="") as handle:
        read = list(csv.DictReader(handle))
    assert read[1]["success"] == "False" and read[0]["held"] == "True"  # strings: bool("False") is True
    s, = grasp_summary(read)
    assert s == grasp_summary(rows)[0]
    assert (s["success"], s["validated"], s["held"], s["timeouts"], s["median_s"]) == (2, 2, 1, 1, 1.0)
    with pytest.raises(ValueError, match="row 0 of the summary has no success, time_s column"):
        grasp_summary([{"grasp": "power", "status": "planned"}])
    with pytest.raises(ValueError, match="row 1 .* success='yes'.* True or False"):
        grasp_summary([rows[0], rows[1] | {"success": "yes"}])
    assert grasp_summary([rows[2] | {"held": float("nan")}])[0]["validated"] == 0  # pandas reads an empty cell so
    for bad in ({"time_s": "nan"}, {"time_s": -1.0}, {"status": "done"}, {"held": "maybe"}, {"success": [True]}):
        with pytest.raises(ValueError, match="row 0 of the summary has"):
            grasp_summary([rows[0] | bad])


# --------------------------------------------------------------------------- batches on a cluster


@pytest.fixture
def bad_objects(tmp_path):
    garbage = tmp_path / "garbage.stl"
    garbage.write_bytes(b"not a mesh" * 10)
    metres = tmp_path / "box_in_metres.stl"
    trimesh.creation.box((0.06, 0.05, 0.09)).export(metres)
    return garbage, metres


def test_batch_results_failures_and_rerun(tmp_path, cluster, bad_objects):
    garbage, metres = bad_objects
    out = tmp_path / "out"
    objects = ["ellipsoid", "cup", "teapot", garbage, metres]
    report = run(objects, ["precision", "power"], out, scheduler=cluster.scheduler_address, progress=False)
    assert (report.tasks, report.skipped, report.finished, report.workers) == (10, 0, 10, 2)
    for name in ("ellipsoid", "cup"):
        for grasp in ("precision", "power"):
            assert_same_plan(out / "results" / name / f"{grasp}.json", expected_plan(name, grasp))
    rows = {(r["object"], r["grasp"]): r for r in report.rows}
    assert len(rows) == len(report.rows) == 10
    for grasp in ("precision", "power"):
        assert rows["teapot", grasp]["status"] == "load error" and "unknown object 'teapot'" in rows["teapot", grasp]["reason"]
        assert rows["garbage.stl", grasp]["status"] == "load error" and "could not read" in rows["garbage.stl", grasp]["reason"]
        assert rows["box_in_metres.stl", grasp]["status"] == "plan error"
        assert "too small to grasp" in rows["box_in_metres.stl", grasp]["reason"]
    record = json.loads((out / "results" / "box_in_metres.stl" / "power.failed.json").read_text())
    assert record["status"] == "plan error" and "scale=1000" in " ".join(record["warnings"])
    assert "box_in_metres.stl power: box_in_metres.stl is only 0.09 mm across" in (out / "warnings.log").read_text()
    table = read_summary(out)
    assert [(r["object"], r["grasp"]) for r in table] == sorted(rows)  # one row per task, sorted
    assert sum(r["success"] == "True" for r in table) == sum(r["success"] for r in report.rows) == 4

    # a rerun plans nothing and leaves the files alone
    stamps = {p: p.stat().st_mtime_ns for p in out.glob("results/**/*.json")}
    again = run(objects, ["precision", "power"], out, scheduler=cluster.scheduler_address, progress=False)
    assert (again.skipped, again.finished, again.workers) == (10, 0, 0)
    assert {p: p.stat().st_mtime_ns for p in out.glob("results/**/*.json")} == stamps
    # retry_failed plans the six failures again; the metres box with scale=1000 now plans
    retried = run(objects, ["precision", "power"], out, scheduler=cluster.scheduler_address, progress=False,
                  retry_failed=True, scale=1000)
    assert (retried.skipped, retried.finished) == (4, 6)
    rows = {(r["object"], r["grasp"]): r for r in retried.rows}
    assert rows["box_in_metres.stl", "precision"]["status"] == "planned"
    assert not (out / "results" / "box_in_metres.stl" / "precision.failed.json").exists()
    assert rows["teapot", "power"]["status"] == "load error"


def test_a_rerun_at_another_scale_is_refused_before_planning(tmp_path, cluster):
    """Plans at two scales in one folder, with object.json naming only the last, are silently wrong."""
    source = tmp_path / "box_in_cm.stl"
    trimesh.creation.box((6.0, 5.0, 9.0)).export(source)
    out = tmp_path / "out"
    run([source], ["precision"], out, scheduler=cluster.scheduler_address, progress=False, scale=10,
        options={"max_iter": 3})
    stamps = {p: p.stat().st_mtime_ns for p in out.glob("results/**/*.json")}
    for scale, retry in ((1.0, False), (1.0, True), (100.0, False)):
        with pytest.raises(ValueError, match=r"the plans of 'box_in_cm.stl' in '.*out' were made at scale 10, and this "
                                             rf"run's scale is {scale:g}: pass the same scale \(--scale 10\)"):
            run([source], ["precision", "power"], out, scheduler=cluster.scheduler_address, progress=False,
                scale=scale, retry_failed=retry, options={"max_iter": 3})
    assert {p: p.stat().st_mtime_ns for p in out.glob("results/**/*.json")} == stamps  # nothing planned or written
    assert main(["batch", str(source), "--out", str(out), "--scheduler", cluster.scheduler_address, "--quiet",
                 "--max-iter", "3"]) == 2
    again = run([source], ["precision", "power"], out, scheduler=cluster.scheduler_address, progress=False, scale=10,
                options={"max_iter": 3})
    assert (again.skipped, again.finished) == (1, 1)


def test_batch_command_prints_why_tasks_failed_with_its_flags(tmp_path, cluster, bad_objects, capsys):
    """The reasons in summary.csv give the library's advice (scale=1000); the command prints its own flags."""
    garbage, metres = bad_objects
    out = tmp_path / "out"
    assert main(["batch", str(garbage), str(metres), "--grasp", "precision", "power", "--out", str(out),
                 "--scheduler", cluster.scheduler_address, "--quiet", "--max-iter", "3"]) == 1  # no task gave a plan
    err = capsys.readouterr().err
    assert err.count("synergrasp: garbage.stl: load error: ") == 1  # once per object, not per grasp
    for grasp in ("precision", "power"):
        line, = [x for x in err.splitlines() if x.startswith(f"synergrasp: box_in_metres.stl {grasp}: plan error: ")]
        assert "scale=1000" in line and line.endswith("(on the command line: --units m or cm, or --scale FACTOR)")
    with open(out / "summary.csv", newline="") as handle:
        assert all("on the command line" not in r["reason"] for r in csv.DictReader(handle))
    millimetres = tmp_path / "box_in_mm.stl"  # read with --units m: the advice names that option, not it again
    trimesh.creation.box((60.0, 40.0, 30.0)).export(millimetres)
    assert main(["batch", str(millimetres), "--grasp", "precision", "--out", str(tmp_path / "mm"), "--units", "m",
                 "--scheduler", cluster.scheduler_address, "--quiet", "--max-iter", "3"]) == 1
    line, = [x for x in capsys.readouterr().err.splitlines() if x.startswith("synergrasp: box_in_mm.stl")]
    assert line.endswith("(on the command line: it was read with --units m; drop it if the file is in mm, or give "
                         "other --units or --scale)")


def test_another_file_under_a_key_with_plans_is_refused(tmp_path, cluster):
    """a/thing.stl, then b/thing.stl (another mesh) into the same folder: b's run took a's plan for its own."""
    out = tmp_path / "out"
    for folder, extents in (("a", (60.0, 50.0, 90.0)), ("b", (40.0, 40.0, 100.0))):
        (tmp_path / folder).mkdir()
        trimesh.creation.box(extents).export(tmp_path / folder / "thing.stl")
    run([tmp_path / "a" / "thing.stl"], ["precision"], out, scheduler=cluster.scheduler_address, progress=False,
        options={"max_iter": 3})
    with pytest.raises(ValueError, match=r"the plans of 'thing.stl' in '.*out' were made of .*a/thing.stl, and this "
                                         r"run's 'thing.stl' is .*b/thing.stl: write to another output folder"):
        run([tmp_path / "b" / "thing.stl"], ["precision"], out, scheduler=cluster.scheduler_address, progress=False,
            options={"max_iter": 3})
    (tmp_path / "a" / "thing.stl").rename(tmp_path / "a" / "moved.stl")  # a file moved since is not compared
    again = run([tmp_path / "b" / "thing.stl"], ["precision"], out, scheduler=cluster.scheduler_address,
                progress=False, options={"max_iter": 3})
    assert (again.skipped, again.finished) == (1, 0)


def test_a_damaged_validation_is_set_aside_not_the_plan(tmp_path):
    """A broken validation file beside a good plan made the plan 'unreadable' (renamed and planned again) every run."""
    store = ResultStore(tmp_path)
    store.write_result("ellipsoid", "precision", sg.plan("ellipsoid", "precision", max_iter=3))
    store.validation_path("ellipsoid", "precision").write_text("{broken")
    rows, unreadable = store.scan()
    assert [r["object"] for r in rows] == ["ellipsoid"] and rows[0]["held"] == ""
    assert unreadable == [store.validation_path("ellipsoid", "precision")]


def test_a_worker_loads_a_file_edited_since_its_last_load(tmp_path):
    """A long-lived worker kept a broken file's load failure after the file was fixed (--retry-failed got it back)."""
    from synergrasp.batch.worker import prepare_object

    path = tmp_path / "thing.stl"
    path.write_text("solid broken\nendsolid broken\n")
    failure, _ = prepare_object(str(path))
    assert failure is not None and failure.status == "load error"
    trimesh.creation.box((60.0, 50.0, 90.0)).export(path)
    assert prepare_object(str(path))[0] is None


def test_the_batch_time_limit_replaces_the_planner_s(monkeypatch):
    """--time-limit 100 ended plans at the planner's own 10 s."""
    import synergrasp.batch.worker as worker

    seen = {}
    monkeypatch.setattr(worker, "plan", lambda *args, **kwargs: seen.update(kwargs) or sg.plan(*args, **{**kwargs, "max_iter": 2}))
    worker.plan_task("ellipsoid", "precision", time_limit=100.0)
    assert seen.pop("time_limit") is None
    worker.plan_task("ellipsoid", "precision", time_limit=100.0, options={"time_limit": 3.0})
    assert seen.pop("time_limit") == 3.0
    worker.plan_task("ellipsoid", "precision")
    assert "time_limit" not in seen


def test_a_batch_of_another_hand_is_validated_and_drawn_with_it(tmp_path):
    """options={"hand": hand}: the validation was asked for the paper hand (refused on every run), and the report
    drew the paper hand's fingers."""
    from synergrasp.batch.worker import plan_task

    data = sg.SynergyHand.default().to_dict()
    data["name"] = "copy of the paper hand"
    hand = sg.SynergyHand(data)
    result, messages, validation = plan_task("ellipsoid", "precision", options={"hand": hand}, validate="synergrasp")
    assert result.success and result.hand == hand.identity
    assert validation is not None and validation.hand == hand.identity
    assert not any("validation failed" in m for m in messages)
    store = ResultStore(tmp_path)
    store.write_result("ellipsoid", "precision", result, validation)
    store.write_object("ellipsoid", "ellipsoid", 1.0)
    with pytest.warns(UserWarning, match="1 plan.s. of the gallery were made with another hand .copy of the paper hand "
                      "sha256:.* synergrasp report DIR --hand FILE"):  # (the page alone said so)
        page = write_report(tmp_path)  # with the paper hand: the plan is not drawn, and the page says why
    assert "planned with hand copy of the paper hand sha256:" in page.read_text()
    assert not (tmp_path / "report" / "ellipsoid" / "precision.png").exists()
    write_report(tmp_path, hand=hand)
    assert (tmp_path / "report" / "ellipsoid" / "precision.png").exists()


def test_the_batch_and_report_commands_take_a_hand_file(tmp_path, cluster, capsys):
    """`synergrasp batch` and `report` had no --hand (only Python's options={"hand": hand} and hand=)."""
    data = sg.SynergyHand.default().to_dict()
    data["name"] = "copy of the paper hand"
    (tmp_path / "copy.json").write_text(json.dumps(data))
    out = tmp_path / "out"
    assert main(["batch", "cup", "--hand", str(tmp_path / "copy.json"), "--out", str(out), "--scheduler",
                 cluster.scheduler_address, "--quiet"]) == 0
    assert sg.PlanResult.load(out / "results" / "cup" / "precision.json").hand == sg.SynergyHand(data).identity
    assert [r["hand"] for r in read_summary(out)] == [sg.SynergyHand(data).identity]  # summary.csv names it
    assert main(["report", str(out), "--hand", str(tmp_path / "copy.json")]) == 0
    assert (out / "report" / "cup" / "precision.png").exists()
    # the same folder with the paper's hand: its plans were taken as this run's (one folder, plans of two hands)
    capsys.readouterr()
    assert main(["batch", "cup", "ellipsoid", "--out", str(out), "--scheduler", cluster.scheduler_address,
                 "--quiet"]) == 2
    err = capsys.readouterr().err
    assert "the plans of 'cup' in" in err and "were made with hand 'copy of the paper hand sha256:" in err
    assert "pass that hand (--hand FILE)" in err and not (out / "results" / "ellipsoid").exists()


def test_objects_holding_fcl_geometry_plan_on_every_worker(tmp_path, cluster):
    # a torus-shaped cloud: its centroid is in the hole, so loading it builds fcl geometry
    # (which cannot be pickled) to move the centre inside
    torus = trimesh.creation.torus(major_radius=35.0, minor_radius=12.0, major_sections=32, minor_sections=12)
    path = tmp_path / "torus.npy"
    np.save(path, trimesh.sample.sample_surface(torus, 3000, seed=0)[0])
    options = dict(time_limit=None, restarts=3)  # bounded by attempts, not by the clock: the same plan both times
    report = run([path], ["precision", "power"], tmp_path / "out", scheduler=cluster.scheduler_address, progress=False,
                 options=options)
    assert [r["status"] for r in report.rows] == ["planned", "planned"]
    for grasp in ("precision", "power"):
        assert_same_plan(tmp_path / "out" / "results" / "torus.npy" / f"{grasp}.json",
                         expected_plan(str(path), grasp, **options))


def test_time_limit_is_recorded_as_timeout(tmp_path, cluster):
    report = run(["bell"], ["power"], tmp_path, scheduler=cluster.scheduler_address, progress=False, time_limit=0.001)
    row, = report.rows
    assert row["status"] == "timeout" and row["reason"] == "no result within the time limit of 0.001 s"
    assert report.per_grasp[0]["timeouts"] == 1


def test_validation_of_new_and_earlier_plans(tmp_path, cluster):
    out = tmp_path / "out"
    run(["ellipsoid", "cup"], ["precision"], out, scheduler=cluster.scheduler_address, progress=False)
    planned = out / "results" / "ellipsoid" / "precision.json"
    stamp = planned.stat().st_mtime_ns
    # a rerun with validation tests the earlier plans without planning them again, and plans what is new
    report = run(["ellipsoid", "cup", "goblet"], ["precision"], out, scheduler=cluster.scheduler_address,
                 progress=False, validate="synergrasp")
    assert (report.skipped, report.finished) == (0, 3) and planned.stat().st_mtime_ns == stamp
    assert report.revalidated == 2 and "3 now (2 of them planned before and validated now)" in str(report)
    rows = {r["object"]: r for r in report.rows}
    for name in ("ellipsoid", "cup", "goblet"):
        plan = expected_plan(name, "precision")
        reset_regime_memory()
        expected = sg.validate(plan, sg.objects.get(name), backend=type(sg.lp.get_backend())())
        saved = sg.physics.Validation.load(out / "results" / name / "precision.validation.json")
        assert (rows[name]["held"], rows[name]["physics"]) == (saved.held, saved.outcome) == (expected.held, expected.outcome)
        assert np.allclose(saved.displacement, expected.displacement, equal_nan=True)
    assert {r["object"]: r["held"] for r in read_summary(out)} == {n: str(rows[n]["held"]) for n in rows}
    again = run(["ellipsoid", "cup", "goblet"], ["precision"], out, scheduler=cluster.scheduler_address,
                progress=False, validate="synergrasp")
    assert again.finished == 0
    # another preset validates the plans again with it (its validations of the other preset were taken as its own)
    other = run(["ellipsoid"], ["precision"], out, scheduler=cluster.scheduler_address, progress=False,
                validate="dexgraspbench")
    assert (other.finished, other.revalidated) == (1, 1)
    saved = sg.physics.Validation.load(out / "results" / "ellipsoid" / "precision.validation.json")
    assert saved.protocol["name"] == "dexgraspbench" and saved.protocol["mu"] == sg.physics.protocol("dexgraspbench").mu


def test_a_scan_reads_each_validation_file_once(tmp_path, monkeypatch):
    """A validating batch's start read every validation file twice: for the held column (scan) and for the protocol
    it was made with (validation_protocol)."""
    result = sg.plan("ellipsoid", "precision")
    store = ResultStore(tmp_path)
    store.write_result("ellipsoid", "precision", result, sg.validate(result, sg.objects.get("ellipsoid")))
    reads = []
    load = sg.physics.Validation.load
    monkeypatch.setattr(sg.physics.Validation, "load", classmethod(lambda cls, path: reads.append(path) or load(path)))
    store.scan()
    assert store.validation_protocol("ellipsoid", "precision")["name"] == "synergrasp" and len(reads) == 1
    store.write_result("ellipsoid", "precision", result)  # planned again: its earlier validation is dropped
    assert store.validation_protocol("ellipsoid", "precision") is None


def test_a_task_planned_again_drops_the_validation_of_its_earlier_plan(tmp_path):
    """A damaged plan planned again (with another backend) kept the earlier plan's validation beside the new plan,
    and the summary and report showed that verdict for a plan never validated."""
    store = ResultStore(tmp_path)
    store.write_result("ellipsoid", "precision", sg.plan("ellipsoid", "precision", max_iter=3))
    store.validation_path("ellipsoid", "precision").write_text("{}")  # (any file: it is the earlier plan's)
    store.write_result("ellipsoid", "precision", sg.plan("ellipsoid", "precision", max_iter=4))
    assert not store.validation_path("ellipsoid", "precision").exists()
    rows, unreadable = store.scan()
    assert rows[0]["held"] == "" and unreadable == []


def test_killed_worker_is_retried(tmp_path, cluster):
    client = distributed.Client(cluster)
    pids = client.run(os.getpid)
    killed = []

    def kill_a_planning_worker():
        deadline = time.monotonic() + 60
        while not killed and time.monotonic() < deadline:
            for address, keys in client.processing().items():
                if any(str(k).startswith("plan-") for k in keys) and address in pids:
                    os.kill(pids[address], signal.SIGKILL)
                    killed.append(address)
                    return
            time.sleep(0.01)

    killer = threading.Thread(target=kill_a_planning_worker)
    killer.start()
    try:
        report = run(["ellipsoid", "cup"], ["power"], tmp_path, scheduler=cluster.scheduler_address, progress=False)
    finally:
        killer.join()
        client.close()
    assert killed, "no worker was planning"
    assert [r["status"] for r in report.rows] == ["planned", "planned"]
    for name in ("ellipsoid", "cup"):
        assert_same_plan(tmp_path / "results" / name / "power.json", expected_plan(name, "power"))


def test_worker_that_keeps_dying_is_recorded(tmp_path):
    import dask

    with dask.config.set({"distributed.scheduler.allowed-failures": 0}), local_cluster(1) as local, \
            distributed.Client(local) as client:
        pid = next(iter(client.run(os.getpid).values()))

        def kill_when_planning():
            while not any(str(k).startswith("plan-") for keys in client.processing().values() for k in keys):
                time.sleep(0.01)
            os.kill(pid, signal.SIGKILL)

        killer = threading.Thread(target=kill_when_planning)
        killer.start()
        report = run(["cup"], ["power"], tmp_path, scheduler=local.scheduler_address, progress=False)
        killer.join()
    row, = report.rows
    assert row["status"] == "worker lost" and "died" in row["reason"]


def test_a_local_cluster_starts_no_more_workers_than_tasks(tmp_path):
    report = run(["ellipsoid"], ["precision"], tmp_path, workers=4, progress=False)
    assert report.workers == 1 and report.rows[0]["success"]


def test_the_local_workers_run_without_dask_s_profiler_and_memory_trimming():
    """Neither serves anything here (no dashboard) and both cost a plan's CPU time (bench_batch.py measures it)."""
    import dask

    with local_cluster(2) as local, distributed.Client(local) as client:
        seen = client.run(lambda: (dask.config.get("distributed.worker.profile.enabled"),
                                   os.environ.get("MALLOC_TRIM_THRESHOLD_")))
    assert len(seen) == 2 and set(seen.values()) == {(False, None)}


def _worker_log_of(records):
    """In a worker: which of the ``distributed.worker`` log messages ``records`` reach a handler."""
    seen = []
    handler = logging.Handler()
    handler.emit = lambda record: seen.append(record.getMessage())
    log = logging.getLogger("distributed.worker")
    log.addHandler(handler)
    try:
        for message in records:
            log.error(message)
    finally:
        log.removeHandler(handler)
    return seen


def test_the_local_workers_drop_only_the_heartbeat_that_fails_as_the_cluster_closes(cluster):
    """CI once failed on it: the in-process scheduler closed while a worker's heartbeat was in flight, and the
    worker printed two tracebacks after the batch had written its summary."""
    from synergrasp.batch.cluster_logs import HEARTBEAT_FAILED

    records = [HEARTBEAT_FAILED, "some other worker error", "Failed to communicate with scheduler (not a heartbeat)"]
    with distributed.Client(cluster) as client:
        seen = client.run(_worker_log_of, records)
    assert len(seen) == 2 and all(got == records[1:] for got in seen.values()), seen
    assert _worker_log_of(records) == records  # (this process's own logger is untouched)


def test_plan_task_pins_blas_to_one_thread(tmp_path):
    env = {k: v for k, v in os.environ.items() if not k.endswith("_NUM_THREADS")}
    code = (
        "import json, threadpoolctl, synergrasp.batch as b\n"
        "before = [i['num_threads'] for i in threadpoolctl.threadpool_info()]\n"
        "outcome, _, _ = b.plan_task('ellipsoid', 'precision', options={'max_iter': 1})\n"
        "after = [i['num_threads'] for i in threadpoolctl.threadpool_info()]\n"
        "print(json.dumps([before, after, outcome.iterations]))\n"
    )
    done = subprocess.run([sys.executable, "-c", code], cwd=ROOT, env=env, capture_output=True, text=True, check=True)
    before, after, iterations = json.loads(done.stdout.strip().splitlines()[-1])
    assert after and set(after) == {1} and iterations == 1
    if (os.cpu_count() or 1) > 1:
        assert max(before) > 1  # the pin changed something


# --------------------------------------------------------------------------- the command line


@pytest.mark.filterwarnings("ignore::pytest.PytestUnraisableExceptionWarning")  # the lost KeyboardInterrupt
def test_ctrl_c_is_kept_in_a_flag_even_where_its_exception_is_lost():
    from synergrasp.batch.runner import _note_interrupts

    outer = signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        requested, arm, restore = _note_interrupts()
        handler = signal.getsignal(signal.SIGINT)
        handler(signal.SIGINT, None)  # not armed (the cluster starting or closing): noted, not raised
        assert requested.is_set()
        requested.clear()
        arm(True)
        with pytest.raises(KeyboardInterrupt):
            handler(signal.SIGINT, None)

        class Finalised:
            def __del__(self):  # a KeyboardInterrupt raised here is printed and dropped by Python
                handler(signal.SIGINT, None)

        requested.clear()
        Finalised()
        assert requested.is_set()
        restore()
        assert signal.getsignal(signal.SIGINT) is signal.default_int_handler
    finally:
        signal.signal(signal.SIGINT, outer)


def test_ctrl_c_that_stops_the_local_workers_starting_is_an_interrupt(tmp_path, monkeypatch, capsys):
    """Ctrl-C in a terminal reaches the local workers too: caught as they start, they fail, and the cluster's start
    raised "Nanny failed to start" (exit 1, with advice for scripts) instead of the interrupt (exit 130)."""
    import synergrasp.batch.runner as runner

    def interrupted_start(*args):
        signal.getsignal(signal.SIGINT)(signal.SIGINT, None)  # the run's handler notes the Ctrl-C
        raise RuntimeError("Nanny failed to start.")

    monkeypatch.setattr(runner, "_connect", interrupted_start)
    outer = signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        assert main(["batch", "ellipsoid", "--out", str(tmp_path), "--quiet"]) == 130
    finally:
        signal.signal(signal.SIGINT, outer)
    err = capsys.readouterr().err
    assert "synergrasp: interrupted" in err and "__main__" not in err


@pytest.mark.parametrize("sig", [signal.SIGINT, signal.SIGTERM])
def test_interrupt_stops_the_command_and_keeps_what_was_written(tmp_path, cluster, sig):
    # the command in its own process, as a user runs it: Ctrl-C (or a polite kill) once a result is written
    command = [sys.executable, "-m", "synergrasp.cli", "batch", "ellipsoid", "cup", "bell", "goblet",
               "--grasp", "precision", "power", "--out", str(tmp_path), "--scheduler", cluster.scheduler_address, "--quiet"]
    batch = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                             # Ctrl-C as in a terminal, also when the suite itself runs where SIGINT is
                             # ignored (a background job of a non-interactive shell)
                             preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    while not result_files(tmp_path) and batch.poll() is None:
        time.sleep(0.01)
    batch.send_signal(sig)
    _, err = batch.communicate(timeout=300)
    assert batch.returncode == 130 and "rerun the same command to plan the rest" in err, err[-2000:]
    written = result_files(tmp_path)
    assert 0 < len(written) < 8
    # the summary table was rebuilt from exactly the results written
    assert [f"results/{r['object']}/{r['grasp']}.json" for r in read_summary(tmp_path)] == written


def test_a_second_interrupt_while_the_run_closes_keeps_its_report(tmp_path):
    """Two Ctrl-C in a row: the second one, while the run closed its local cluster, escaped as if nothing had been
    planned ("interrupted before planning started; nothing was planned") and no summary was printed."""
    command = [sys.executable, "-m", "synergrasp.cli", "batch", "ellipsoid", "cup", "bell", "goblet",
               "--grasp", "precision", "power", "--out", str(tmp_path), "--workers", "1", "--quiet"]
    batch = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                             preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    while not result_files(tmp_path) and batch.poll() is None:
        time.sleep(0.01)
    batch.send_signal(signal.SIGINT)
    time.sleep(0.2)  # (the local cluster takes about a second to close)
    if batch.poll() is None:
        batch.send_signal(signal.SIGINT)
    out, err = batch.communicate(timeout=300)
    # (130, or the signal itself when the second Ctrl-C lands as Python exits: a shell reports 130 for both)
    assert batch.returncode in (130, -signal.SIGINT), (batch.returncode, err[-3000:])
    assert "nothing was planned" not in err and "Traceback" not in err, err[-3000:]
    assert "rerun the same command to plan the rest" in err and "tasks:" in out
    assert [f"results/{r['object']}/{r['grasp']}.json" for r in read_summary(tmp_path)] == result_files(tmp_path)


def test_a_lost_scheduler_ends_the_run_with_one_message_and_keeps_what_was_written(tmp_path):
    """The scheduler goes away after the first result: the run raises ConnectionError saying so and how to go on,
    the summary table holds exactly the results written, and distributed's client logs no error of its own (a
    remote scheduler lost mid-run printed its reconnection tracebacks before the message)."""
    cluster = distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=False, dashboard_address=None,
                                       silence_logs=False)

    def lose_the_scheduler():
        while not result_files(tmp_path):
            time.sleep(0.02)
        cluster.sync(cluster.scheduler.close)

    threading.Thread(target=lose_the_scheduler, daemon=True).start()
    client_log = logging.getLogger("distributed.client")
    level, logged = client_log.level, []
    handler = logging.Handler(logging.ERROR)
    handler.emit = logged.append
    client_log.addHandler(handler)
    try:
        with pytest.raises(ConnectionError, match="scheduler lost.*rerun the same command to plan the rest"):
            run(["ellipsoid", "cup", "bell", "goblet"], ["precision", "power"], out=tmp_path,
                scheduler=cluster.scheduler_address, progress=False)
    finally:
        client_log.removeHandler(handler)
        cluster.close()
    assert not logged and client_log.level == level
    written = result_files(tmp_path)
    assert 0 < len(written) < 8
    assert [f"results/{r['object']}/{r['grasp']}.json" for r in read_summary(tmp_path)] == written


def test_benchmark_quick_mode_kills_a_run_and_resumes_it(tmp_path):
    """benchmarks/bench_batch.py --quick: a loop, 1 and 2 workers, and a run killed part way then rerun."""
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(ROOT), os.environ.get("PYTHONPATH", "")])}
    done = subprocess.run([sys.executable, str(ROOT / "benchmarks" / "bench_batch.py"), "--quick", "--out", str(tmp_path)],
                          cwd=ROOT, env=env, capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stderr
    out = done.stdout
    assert "same result per task, bit for bit but for the timings (loop, 1 worker, 2 workers): yes (6 of 6)" in out
    for pattern in (r"throughput 2 workers / 1 worker: [\d.]+x", r"overhead .* = [-+][\d.]+ ms per task, [-+][\d.]+ %",
                    r"CPU [\d.]+ s, \d+ minor page faults; without: CPU [\d.]+ s, \d+ page faults"):
        assert re.search(pattern, out), pattern
    killed = re.search(r"interrupt and rerun: killed after (\d) of 6 results; .*: PASS", out)
    assert killed and 0 < int(killed.group(1)) < 6, out
    # checked here too: the resumed run holds exactly the uninterrupted run's results
    resumed, reference = tmp_path / "interrupted", tmp_path / "dask-2"
    assert result_files(resumed) == result_files(reference) == result_files(tmp_path / "loop")
    assert len(result_files(resumed)) == 6
    for name in result_files(resumed):
        assert_same_plan(resumed / name, sg.PlanResult.load(reference / name))
        assert_same_plan(tmp_path / "loop" / name, sg.PlanResult.load(reference / name))
    assert [p.name for p in resumed.rglob(".*")] == [".lock"]  # no temporary file left
    table = read_summary(resumed)
    assert sorted((r["object"], r["grasp"]) for r in table) == sorted(
        (name.split("/")[1], name.split("/")[2][: -len(".json")]) for name in result_files(reference))


# --------------------------------------------------------------------------- report


def test_report_page(tmp_path, cluster):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        run(["ellipsoid", "cup", "teapot"], ["precision"], tmp_path, scheduler=cluster.scheduler_address,
            progress=False)
    assert main(["report", str(tmp_path), "--gallery", "1"]) == 0
    page = (tmp_path / "report.html").read_text()
    assert page.count("<tr class=") == 3  # every task in the table
    assert "unknown object" in page and "results/cup/precision.json" in page
    pictures = list((tmp_path / "report").rglob("*.png"))
    assert len(pictures) == 1 and pictures[0].stat().st_size > 5000  # the gallery holds one plan
    stamp = pictures[0].stat().st_mtime_ns
    write_report(tmp_path, gallery=1)
    assert pictures[0].stat().st_mtime_ns == stamp  # reused, not drawn again
    with pytest.raises(ValueError, match="gallery must be"):
        write_report(tmp_path, gallery=-1)
    (tmp_path / "results" / "cup" / "precision.json").write_text("garbage")  # damaged: named, not counted in silence
    with pytest.warns(UserWarning, match=r"1 result file\(s\) .* could not be read .*results/cup/precision.json"):
        write_report(tmp_path, gallery=0)
    page = (tmp_path / "report.html").read_text()
    assert page.count("<tr class=") == 2 and "1 result file(s) could not be read and are left out" in page
