"""PlanResult files: atomic saves, and loads that check every field and name the file and the field."""

import json
import os
import re
import warnings
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np
import pytest

import synergrasp as sg
from synergrasp import viz
from synergrasp._files import atomic_path, writable_folder
from synergrasp.planner import status_rows

DOCS = Path(__file__).resolve().parents[1] / "docs"


@pytest.fixture(scope="module")
def failed_plan():
    """A plan that finds no grasp in three short attempts."""
    return sg.plan("ellipsoid", "precision", max_iter=12, iterations_per_attempt=4)


@pytest.fixture
def saved(failed_plan, tmp_path):
    path = failed_plan.save(tmp_path / "plan.json")
    return path, json.loads(path.read_text())


def test_the_plan_result_page_labels_every_status_row(monkeypatch, tmp_path):
    """docs/howto/plan-result.md: its example runs, and its legend has one entry per cP row of the status."""
    monkeypatch.chdir(tmp_path)
    page = (DOCS / "howto" / "plan-result.md").read_text()
    names = {}
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # e.g. matplotlib's warning of a legend with more labels than lines
        exec(re.search(r"```python\n(.*?)```", page, re.S).group(1), names)
    result, top = names["result"], names["top"]
    rows = status_rows(names["hand"], result.grasp)[0]
    assert result.status.shape[1] == len(rows) + 1 == 17 and result.target.shape == (17,)
    assert [t.get_text() for t in top.get_legend().get_texts()] == rows and len(top.get_lines()) == len(rows)
    plt.close("all")


def test_getting_started_shows_what_the_goblet_plan_prints():
    page = (DOCS / "getting-started.md").read_text()
    result = sg.plan(sg.objects.get("goblet"), "precision")
    assert f"# True, {result.reason!r}" in page
    assert f"# {result.contact_labels}, {result.final_q:.4f}" in page
    assert f"final g: {result.status.shape[1] - 1} cP rows" in page


def test_plan_takes_a_name_or_a_path(tmp_path):
    by_name = sg.plan("ellipsoid", "precision", max_iter=3)
    assert by_name.object_name == "ellipsoid 30/40/50" and by_name.iterations == 3
    cloud = tmp_path / "ball.npy"
    t = np.random.default_rng(0).normal(size=(400, 3))
    np.save(cloud, 35.0 * t / np.linalg.norm(t, axis=1, keepdims=True))
    by_path = sg.plan(cloud, "precision", max_iter=3)
    assert by_path.object_name == "ball.npy" and sg.plan(str(cloud), "precision", max_iter=3).object_name == "ball.npy"
    with pytest.raises(ValueError, match="unknown object 'teapot'"):
        sg.plan("teapot")


def test_a_plan_from_a_numpy_approach_saves_and_loads(tmp_path):
    """The approach is recorded as plain numbers, whatever the array's dtype."""
    for approach in (np.array([1, 0, 0]), np.array([0.0, 1.0, 0.0], dtype=np.float32)):
        result = sg.plan("ellipsoid", "precision", approach=approach, max_iter=3)
        loaded = sg.PlanResult.load(result.save(tmp_path / "plan.json"))
        assert loaded.attempts[0]["direction"] == approach.astype(float).tolist()


def test_a_path_under_the_home_folder_is_expanded(failed_plan, tmp_path, monkeypatch):
    """``result.save("~/plan.json")`` said "the folder '~' does not exist": '~' is the home folder, on save and load."""
    monkeypatch.setenv("HOME", str(tmp_path))
    path = failed_plan.save("~/plan.json")
    assert path == tmp_path / "plan.json" and path.is_file()
    assert sg.PlanResult.load("~/plan.json").reason == failed_plan.reason


def test_every_attempt_keeps_its_status_trace(failed_plan, saved):
    assert not failed_plan.success and len(failed_plan.attempts) == 3
    for attempt in failed_plan.attempts:
        assert np.shape(attempt["status"]) == (attempt["iterations"] + 1, failed_plan.status.shape[1])
    np.testing.assert_array_equal(failed_plan.attempts[-1]["status"], failed_plan.status)  # the returned reach
    back = sg.PlanResult.load(saved[0])
    assert back.attempts == failed_plan.attempts


def test_the_status_figure_of_a_failed_plan_shows_every_attempt(failed_plan):
    lengths = [len(a["status"]) for a in failed_plan.attempts]
    fig = viz.status_figure(failed_plan)
    try:
        sq = [line for line in fig.axes[1].lines if line.get_label() == "$g_{sQ}$"][0]
        x, y = sq.get_data()
        assert np.isnan(y).sum() == len(lengths) - 1  # one break between consecutive attempts
        expected = np.concatenate([np.r_[np.asarray(a["status"])[:, -1], np.nan] for a in failed_plan.attempts])[:-1]
        np.testing.assert_array_equal(y, expected)
        assert np.nanmax(x) == sum(lengths) - 1
        assert "attempts 1-3" in fig.axes[0].get_title()
    finally:
        plt.close(fig)
    last = viz.status_figure(failed_plan, attempts="last")
    try:
        assert len(last.axes[1].lines[0].get_xdata()) == lengths[-1]
    finally:
        plt.close(last)
    with pytest.raises(ValueError, match="attempts must be 'all', 'last' or None"):
        viz.status_figure(failed_plan, attempts="first")


@pytest.mark.parametrize("field, value, message", [
    ("u", "garbage", "field 'u' must be an array of numbers of shape \\(n,\\), got 'garbage'"),
    ("u", [1.0, 2.0], "field 'u' must be a configuration"),
    ("success", "maybe", "field 'success' must be true or false, got 'maybe'"),
    ("iterations", -3, "field 'iterations' must be an integer >= 0, got -3"),
    ("iterations", 2.5, "field 'iterations' must be an integer >= 0"),
    ("trajectory", [[0.0] * 8], "field 'trajectory' must be of shape \\(iterations \\+ 1, len\\(u\\)\\)"),
    ("status", [[1.0, 2.0]], "field 'status' must be of shape"),
    ("target", "x", "field 'target' must be an array of numbers of shape \\(n,\\)"),
    ("q_history", [0.0], "field 'q_history' must be 5 numbers"),
    ("trajectory", "x", "field 'trajectory' must be an array of numbers, got 'x'"),
    ("contact_points", [[0.0, 0.0, 0.0]], "field 'contact_points' must be of shape"),
    ("contact_normals", [[np.nan, 0.0, 1.0]] * 5, "field 'contact_normals' must be finite numbers"),
    ("contact_labels", "T0", "field 'contact_labels' must be a list of strings"),
    ("penetration", -1.0, "field 'penetration' must be a finite number >= 0.0"),
    ("time_s", "fast", "field 'time_s' must be a finite number"),
    ("lp_solves", True, "field 'lp_solves' must be an integer >= 0"),
    ("backend", 3, "field 'backend' must be a string"),
    ("reason", None, "field 'reason' must be a string"),
    ("grasp", "pinch", "field 'grasp' must be 'precision' or 'power'"),
    ("object_name", ["x"], "field 'object_name' must be a string"),
    ("hand", 7, "field 'hand' must be a string"),
    ("options", [], "field 'options' must be an object"),
    ("attempts", {}, "field 'attempts' must be a list"),
    ("attempts", [3], "field 'attempts\\[0\\]' must be an object"),
    ("attempts", [{"iterations": "4", "reason": "x"}], "field 'attempts\\[0\\].iterations' must be an integer"),
    ("attempts", [{"iterations": 4}], "field 'attempts\\[0\\].reason' must be a string"),
    ("attempts", [{"iterations": 1, "reason": "x", "status": [[0.0]]}], "field 'attempts\\[0\\].status' must be"),
    ("attempts", [{"iterations": 4, "iterations_run": 3, "reason": "x"}],
     "field 'attempts\\[0\\].iterations_run' must be an integer >= its iterations \\(4\\), got 3"),
    ("attempts", [{"iterations": 0, "reason": "x", "status": [[True] * 6]}], "field 'attempts\\[0\\].status' must be"),
    ("trajectory", [[0.0] * 7] * 5, "field 'trajectory' must be of shape .* \\(its rows of 7 numbers, u of 8\\)"),
])
def test_load_checks_every_field_and_names_it(saved, field, value, message):
    path, data = saved
    data[field] = value
    path.write_text(json.dumps(data))
    with pytest.raises(ValueError, match=message) as info:
        sg.PlanResult.load(path)
    assert str(info.value).startswith(f"{path}: ")


def test_load_refuses_a_result_that_contradicts_itself(tmp_path):
    """Edited by hand, a result loaded and was validated as a grasp it never was: u moved 50 mm from the trajectory's
    end, a pre-grasp apart from the reach's start, a grasp without contacts, a normal of length 5, true for a number."""
    path = sg.plan("ellipsoid", "precision").save(tmp_path / "grasp.json")
    good = json.loads(path.read_text())
    moved = [good["u"][0] + 50.0] + good["u"][1:]
    edits = [
        ({"u": moved}, "field 'u' must be the last row of trajectory"),
        ({"u": good["u"][:7]}, "field 'trajectory' must be of shape .* \\(its rows of 8 numbers, u of 7\\)"),
        ({"pregrasp": [good["pregrasp"][0] + 5.0] + good["pregrasp"][1:]}, "field 'path' must be the reach from pregrasp"),
        ({"contact_labels": [], "contact_points": [], "contact_normals": []},
         "field 'contact_labels' must be two contacts or more for a grasp"),
        ({"contact_normals": [[5.0 * v for v in n] for n in good["contact_normals"]]}, "field 'contact_normals' must be unit"),
        ({"u": [True] + good["u"][1:]}, "field 'u' must be an array of numbers"),
    ]
    for edit, message in edits:
        path.write_text(json.dumps({**good, **edit}))
        with pytest.raises(ValueError, match=message):
            sg.PlanResult.load(path)
    path.write_text(json.dumps(good))
    assert sg.PlanResult.load(path).success
    # a reach that was not collision-free was cut short of u before 2026-11-30: such a file loads
    short = {**good, "path": good["path"][:-1], "clearance": good["clearance"][:-1], "collision_free": False}
    path.write_text(json.dumps(short))
    assert len(sg.PlanResult.load(path).path) == len(good["path"]) - 1


def test_a_file_saved_before_surface_q_and_held_loads_with_their_defaults(saved):
    path, data = saved
    del data["surface_q"], data["held"]
    path.write_text(json.dumps(data))
    again = sg.PlanResult.load(path)
    assert np.isnan(again.surface_q) and again.held is None


def test_load_names_the_file_for_missing_fields_and_bad_files(saved, tmp_path):
    path, data = saved
    del data["u"]
    path.write_text(json.dumps(data))
    with pytest.raises(ValueError, match=r"plan.json lacks the fields \['u'\]: a file edited by hand, or .* plan it again"):
        sg.PlanResult.load(path)
    path.write_text(json.dumps({**data, "format": "synergrasp.PlanResult/2"}))
    with pytest.raises(ValueError, match="is a PlanResult of format 'synergrasp.PlanResult/2', which this version"):
        sg.PlanResult.load(path)
    path.write_text("{not json")
    with pytest.raises(ValueError, match="cannot read a PlanResult from .*plan.json"):
        sg.PlanResult.load(path)
    path.write_text(json.dumps({"format": "something else"}))
    with pytest.raises(ValueError, match="plan.json is not a saved synergrasp PlanResult"):
        sg.PlanResult.load(path)
    with pytest.raises(FileNotFoundError, match="missing.json"):
        sg.PlanResult.load(tmp_path / "missing.json")


def test_a_result_records_its_hand_and_a_file_without_it_loads(failed_plan, saved):
    path, data = saved
    assert failed_plan.hand == data["hand"] == sg.SynergyHand.default().identity
    assert sg.PlanResult.load(path).hand == failed_plan.hand
    del data["hand"]  # a file saved before results recorded their hand
    path.write_text(json.dumps(data))
    assert sg.PlanResult.load(path).hand == ""


def test_writes_are_atomic(failed_plan, tmp_path, monkeypatch):
    """A write that fails half-way leaves neither a partial file nor a temporary one."""
    target = tmp_path / "plan.json"
    target.write_text("the previous result")
    with pytest.raises(RuntimeError, match="disk full"):
        with atomic_path(target) as tmp:
            tmp.write_text("half of it")
            raise RuntimeError("disk full")
    assert target.read_text() == "the previous result" and [p.name for p in tmp_path.iterdir()] == ["plan.json"]

    def broken_savefig(self, fname, **kwargs):
        with open(fname, "w") as f:
            f.write("partial")
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(plt.Figure, "savefig", broken_savefig)
    with pytest.raises(OSError, match="No space left"):
        viz.plot_status(failed_plan, tmp_path / "status.png")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["plan.json"]


def test_writable_folder(tmp_path):
    assert writable_folder(tmp_path / "a" / "b").is_dir()
    blocker = tmp_path / "file"
    blocker.write_text("")
    with pytest.raises(ValueError, match=r"cannot write to the output folder '.*file' \(it is a file, not a folder\)"):
        writable_folder(blocker)
    with pytest.raises(ValueError, match=r"cannot write to the results folder '.*file/sub' \(not a directory\)"):
        writable_folder(blocker / "sub", "results folder")


def test_atomic_writes_keep_links_and_refuse_what_is_not_a_file(tmp_path):
    """The rename that makes a write atomic must not replace a device or a pipe (as root, saving to /dev/null made it
    a plain file) nor a symbolic link (it replaced the link and left its target as it was)."""
    target = tmp_path / "real" / "target.txt"
    target.parent.mkdir()
    (tmp_path / "link.txt").symlink_to(target)
    with atomic_path(tmp_path / "link.txt") as tmp:
        tmp.write_text("through the link")
    assert (tmp_path / "link.txt").is_symlink() and target.read_text() == "through the link"
    os.mkfifo(tmp_path / "pipe")
    with pytest.raises(ValueError, match="it is not a regular file"):
        with atomic_path(tmp_path / "pipe"):
            pass
    assert not (tmp_path / "pipe").is_file()
    with pytest.raises(IsADirectoryError, match="a name ending with '/' is a folder's"):
        with atomic_path(f"{tmp_path}/new/"):
            pass
    assert sorted(p.name for p in tmp_path.iterdir()) == ["link.txt", "pipe", "real"]
    with pytest.raises(NotADirectoryError, match="'.*link.txt' is a file, not a folder"):
        with atomic_path(tmp_path / "link.txt" / "inside.json"):
            pass
    longest = tmp_path / ("a" * 250 + ".json")  # the longest name a folder takes: its temporary file is shorter
    with atomic_path(longest) as tmp:
        tmp.write_text("long")
    assert longest.read_text() == "long"


def test_a_folder_that_takes_no_file_is_named_by_the_file_asked_for(tmp_path, monkeypatch):
    """The temporary file is what the system refuses; the error names the file the caller gave."""
    def refuse(path, *args):
        raise PermissionError(13, "Permission denied", str(path))

    monkeypatch.setattr(os, "open", refuse)
    with pytest.raises(PermissionError, match=r"cannot write '.*plan.json' \(Permission denied: a file is first"):
        with atomic_path(tmp_path / "plan.json"):
            pass
