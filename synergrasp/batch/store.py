"""The output folder of a batch: result files, what is done, the summary table, one run at a time.

Layout of ``OUT``::

    OUT/results/KEY/object.json            where the object came from (source, scale)
    OUT/results/KEY/GRASP.json             a finished plan: one PlanResult (PlanResult.save)
    OUT/results/KEY/GRASP.validation.json  its physics validation, if asked for (Validation.save)
    OUT/results/KEY/GRASP.failed.json      a task that gave no PlanResult: its status and reason
    OUT/summary.csv                        one row per task, rebuilt from the files above
    OUT/warnings.log                       warnings raised while loading, planning or validating

``KEY`` names the object (see `synergrasp.batch.tasks`). Every file is written to a
temporary file in the same folder, then renamed over its final name
(`synergrasp._files.atomic_path`), so a file under its final name is always whole: an
interrupted run leaves no partial result. A task is done when its result or failure file
exists (and, when validation is asked for, a successful plan's validation file). A run holds
a lock on ``OUT/.lock`` (released by the system when its process ends, however it ends), so
two runs never write one folder at the same time, and a run that holds it may remove the
temporary files a killed run left behind.
"""

from __future__ import annotations

import csv
import io
import json
import math
import os
import re
from contextlib import contextmanager
from dataclasses import asdict, dataclass, field
from pathlib import Path

import numpy as np

from .._checks import as_path
from .._files import atomic_path, writable_folder
from ..planner.result import PlanResult

#: Columns of ``summary.csv``, in order. ``held`` and ``physics`` (the validation's outcome)
#: are empty for a task without a validation; ``hand`` (the planning hand's `SynergyHand.identity`)
#: for a task without a PlanResult.
COLUMNS = (
    "object", "grasp", "status", "success", "reason", "q", "sq", "time_s", "iterations", "attempts",
    "contacts", "penetration_mm", "lp_solves", "backend", "held", "physics", "object_name", "file", "hand",
)
#: Values of the ``status`` column: a PlanResult was written (``planned``, whether or not it
#: found a grasp), or the task gave none.
STATUSES = ("planned", "load error", "plan error", "timeout", "worker lost")
_FAILURE_FORMAT = "synergrasp.BatchFailure/1"
#: Temporary files of `atomic_path`: ``.STEM.XXXXXXXX.tmpSUFFIX``.
_TEMPORARY = re.compile(r"^\..+\.[0-9a-f]{8}\.tmp(\.\w+)?$")

try:
    import fcntl
except ImportError:  # not on POSIX: runs are not locked against each other
    fcntl = None


@dataclass
class TaskFailure:
    """A task that gave no PlanResult.

    Attributes
    ----------
    status : str
        ``"load error"`` (the object could not be loaded), ``"plan error"`` (the
        planner raised), ``"timeout"`` (the plan exceeded the time limit) or
        ``"worker lost"`` (the workers running it died too often).
    reason : str
        What went wrong, in words (the exception's type and message).
    time_s : float
        Time spent before the task gave up (s).
    warnings : list of str
        Warnings raised while loading the object or planning.
    """

    status: str
    reason: str
    time_s: float = 0.0
    warnings: list = field(default_factory=list)


class ResultStore:
    """The output folder of a batch (layout in the module docstring).

    Parameters
    ----------
    out : str or Path
        The folder; created by `check_writable`.
    """

    def __init__(self, out):
        if isinstance(out, (str, bytes)) and not out:
            raise ValueError("the output folder is an empty name (an unset variable?): name a folder, '.' for the "
                             "current one")
        self.out = as_path(out, "the output folder (out)")
        self.results = self.out / "results"
        self.summary_path = self.out / "summary.csv"
        self.warnings_path = self.out / "warnings.log"
        self._protocols = {}  # (key, grasp) -> the protocol of the validation file `scan` read

    def result_path(self, key: str, grasp: str) -> Path:
        """File of the PlanResult of task (``key``, ``grasp``)."""
        return self.results / key / f"{grasp}.json"

    def failure_path(self, key: str, grasp: str) -> Path:
        """File of the failure record of task (``key``, ``grasp``)."""
        return self.results / key / f"{grasp}.failed.json"

    def validation_path(self, key: str, grasp: str) -> Path:
        """File of the physics validation of task (``key``, ``grasp``)."""
        return self.results / key / f"{grasp}.validation.json"

    def check_writable(self) -> None:
        """Create the folder and ``results/`` if needed and check that files can be written there.

        Raises
        ------
        ValueError
            If the folder cannot be created or written, or the name of ``summary.csv`` or
            ``warnings.log`` is taken by something that is not a file; the message names it and the reason.
        """
        writable_folder(self.out, "output folder")
        writable_folder(self.results, "output folder")
        for path in (self.summary_path, self.warnings_path):  # (found after every plan, else)
            if path.exists() and not path.is_file():
                raise ValueError(f"'{path}' is not a file, and the batch writes its {path.name} there: move it away "
                                 "or write to another output folder")

    @contextmanager
    def lock(self):
        """Hold the folder's lock for the block, and remove the temporary files of killed runs.

        Raises
        ------
        ValueError
            If another run holds the lock (the message gives its process id).
        """
        if fcntl is None:
            yield
            return
        with open(self.out / ".lock", "a+", encoding="utf-8") as handle:
            try:
                fcntl.flock(handle, fcntl.LOCK_EX | fcntl.LOCK_NB)
            except BlockingIOError:
                handle.seek(0)
                raise ValueError(f"another batch ({handle.read().strip() or 'a process'}) is writing to "
                                 f"'{self.out}'; wait for it to end or choose another output folder") from None
            handle.truncate(0)
            handle.write(f"process {os.getpid()}")
            handle.flush()
            for path in self.out.rglob(".*"):
                if _TEMPORARY.match(path.name):
                    path.unlink(missing_ok=True)
            try:
                yield
            finally:
                fcntl.flock(handle, fcntl.LOCK_UN)

    def write_object(self, key: str, source: str, scale: float) -> None:
        """Record where object ``key`` comes from (``results/KEY/object.json``)."""
        path = self.results / key / "object.json"
        path.parent.mkdir(parents=True, exist_ok=True)
        _write_text(path, json.dumps({"source": source, "scale": scale}))

    def object_source(self, key: str) -> tuple[str, float] | None:
        """(source, scale) recorded for object ``key``, or None if there is no readable record."""
        try:
            data = json.loads((self.results / key / "object.json").read_text())
            return str(data["source"]), float(data["scale"])
        except (OSError, ValueError, KeyError, TypeError):
            return None

    def write_result(self, key: str, grasp: str, outcome, validation=None) -> Path:
        """Write a task's outcome (and validation) and drop a failure record it replaces.

        Parameters
        ----------
        key, grasp : str
            The task.
        outcome : PlanResult or TaskFailure
        validation : Validation, optional
            The plan's physics validation, written before the plan.

        Returns
        -------
        Path
            The file of the outcome.
        """
        path = self.failure_path(key, grasp) if isinstance(outcome, TaskFailure) else self.result_path(key, grasp)
        path.parent.mkdir(parents=True, exist_ok=True)
        if validation is not None:
            self.write_validation(key, grasp, validation)
        elif not isinstance(outcome, TaskFailure):  # a new plan: an earlier plan's validation is not its own
            self.validation_path(key, grasp).unlink(missing_ok=True)
            self._protocols.pop((key, grasp), None)
        if isinstance(outcome, TaskFailure):
            record = {"format": _FAILURE_FORMAT, "object": key, "grasp": grasp, **asdict(outcome)}
            return _write_text(path, json.dumps(record, indent=1))
        outcome.save(path)
        self.failure_path(key, grasp).unlink(missing_ok=True)
        return path

    def write_validation(self, key: str, grasp: str, validation) -> Path:
        """Write the physics validation of task (``key``, ``grasp``) (``Validation.save``)."""
        path = validation.save(self.validation_path(key, grasp))
        self._protocols.pop((key, grasp), None)  # (read back from the file when asked: its form, JSON's)
        return path

    def validation_protocol(self, key: str, grasp: str) -> dict | None:
        """The protocol settings task (``key``, ``grasp``) was validated with.

        Parameters
        ----------
        key, grasp : str
            The task.

        Returns
        -------
        dict or None
            The validation file's ``protocol`` (`synergrasp.physics.Validation.protocol`), or None if the task
            was not validated or its file cannot be read. As `scan` read it, if it did and the file was not
            written since (a batch's start reads each validation file once).
        """
        from ..physics.result import Validation

        if (key, grasp) in self._protocols:
            return self._protocols[key, grasp]
        try:
            return Validation.load(self.validation_path(key, grasp)).protocol
        except (OSError, ValueError, TypeError, KeyError):
            return None

    def log_warnings(self, key: str, grasp: str, messages) -> None:
        """Append a task's warnings to ``warnings.log`` (one line each)."""
        if messages:
            with open(self.warnings_path, "a", encoding="utf-8") as handle:
                handle.writelines(f"{key} {grasp}: {' '.join(str(m).split())}\n" for m in messages)

    def scan(self):
        """Read every result and failure record under ``results/``.

        A task with both a PlanResult and a failure record (a retry that
        succeeded) counts by its PlanResult.

        Returns
        -------
        rows : list of dict
            One row per task, the columns of `COLUMNS`, sorted by object and grasp.
        unreadable : list of Path
            Files under a final name that are not a valid record (never written
            by `write_result`; e.g. edited by hand or damaged on disk).
        """
        from ..physics.result import Validation

        rows, unreadable = {}, []
        if not self.results.is_dir():
            return [], []
        for path in sorted(self.results.rglob("*.json")):
            if path.name.startswith(".") or path.name == "object.json" or path.name.endswith(".validation.json"):
                continue
            key = path.parent.relative_to(self.results).as_posix()
            failed = path.name.endswith(".failed.json")
            grasp = path.name[: -len(".failed.json")] if failed else path.stem
            if not failed:
                try:
                    row = _plan_row(key, grasp, PlanResult.load(path), path.relative_to(self.out))
                except (OSError, ValueError, TypeError, KeyError):  # (OSError: a folder under a result's name)
                    unreadable.append(path)
                    continue
                checked = self.validation_path(key, grasp)
                if checked.is_file():
                    try:  # a damaged validation is the one set aside (and the plan validated again), not the plan
                        validation = Validation.load(checked)
                        row.update(held=bool(validation.held), physics=validation.outcome)
                        self._protocols[key, grasp] = validation.protocol
                    except (OSError, ValueError, TypeError, KeyError):
                        unreadable.append(checked)
                        self._protocols.pop((key, grasp), None)
                rows[key, grasp] = row
                continue
            if (key, grasp) in rows or self.result_path(key, grasp).is_file():
                continue
            try:
                data = json.loads(path.read_text())
                if data.get("format") != _FAILURE_FORMAT or data.get("status") not in STATUSES:
                    raise ValueError("not a failure record")
                rows[key, grasp] = _failure_row(key, grasp, data, path.relative_to(self.out))
            except (OSError, ValueError, TypeError, AttributeError, RecursionError):
                unreadable.append(path)
        return [rows[k] for k in sorted(rows)], unreadable

    def write_summary(self, rows) -> Path:
        """Write ``summary.csv`` from `scan`'s rows.

        Returns
        -------
        Path
        """
        buffer = io.StringIO()
        writer = csv.DictWriter(buffer, fieldnames=COLUMNS, lineterminator="\n")
        writer.writeheader()
        writer.writerows(rows)
        return _write_text(self.summary_path, buffer.getvalue())


def _write_text(path, text) -> Path:
    with atomic_path(path) as tmp:
        tmp.write_text(text, encoding="utf-8")
    return Path(path)


def _plan_row(key, grasp, result: PlanResult, file) -> dict:
    return {
        "object": key, "grasp": grasp, "status": "planned", "success": bool(result.success),
        "reason": result.reason, "q": result.final_q, "sq": result.final_sq, "time_s": float(result.time_s),
        "iterations": int(result.total_iterations), "attempts": len(result.attempts) or 1,
        "contacts": len(result.contact_labels), "penetration_mm": float(result.penetration),
        "lp_solves": int(result.lp_solves), "backend": result.backend, "held": "", "physics": "",
        "object_name": result.object_name, "file": Path(file).as_posix(), "hand": result.hand,
    }


def _failure_row(key, grasp, data: dict, file) -> dict:
    time_s = data.get("time_s", 0.0)
    if isinstance(time_s, bool) or not isinstance(time_s, (int, float)) or not 0.0 <= time_s < math.inf:
        raise ValueError(f"time_s must be seconds >= 0, got {time_s!r}")
    row = dict.fromkeys(COLUMNS, "")
    row.update(object=key, grasp=grasp, status=data["status"], success=False, reason=str(data.get("reason", "")),
               time_s=float(time_s), file=Path(file).as_posix())
    return row


def grasp_summary(rows) -> list[dict]:
    """Per grasp type: tasks, grasps found, success rate, failures, plan times, physics verdicts.

    Parameters
    ----------
    rows : list of dict
        Rows of the summary table: `ResultStore.scan`'s, or ``summary.csv``'s
        as `csv.DictReader` reads them (``success`` and ``held`` as the
        strings ``"True"``, ``"False"`` or ``""``; pandas's NaN for an empty
        ``held``). Each needs ``grasp``, ``status``, ``success`` and
        ``time_s``; ``held`` is optional.

    Returns
    -------
    list of dict
        One dict per grasp type (in order of first appearance) with ``grasp``,
        ``tasks``, ``success`` (grasps found), ``rate`` (success / tasks),
        ``failed`` (tasks without a PlanResult), ``timeouts``, ``median_s`` and
        ``p90_s`` (over the plans' own times, NaN without plans),
        ``plans_per_s`` (plans one worker finishes per second: plans / their
        summed time), ``validated`` (grasps tested in MuJoCo) and ``held``
        (of those, the ones that held).

    Raises
    ------
    ValueError
        If a row lacks a column, or a column holds a value it cannot have.

    Examples
    --------
    >>> rows = [{"grasp": "power", "status": "planned", "success": True, "time_s": 1.0, "held": True},
    ...         {"grasp": "power", "status": "planned", "success": False, "time_s": 3.0, "held": ""},
    ...         {"grasp": "power", "status": "timeout", "success": False, "time_s": 9.0, "held": ""}]
    >>> s = grasp_summary(rows)[0]
    >>> s["tasks"], s["success"], round(s["rate"], 3), s["timeouts"], s["median_s"], s["plans_per_s"], s["held"]
    (3, 1, 0.333, 1, 2.0, 0.5, 1)
    """
    rows = [_summary_row(i, r) for i, r in enumerate(rows)]
    out = []
    for grasp in dict.fromkeys(r["grasp"] for r in rows):
        mine = [r for r in rows if r["grasp"] == grasp]
        times = np.array([r["time_s"] for r in mine if r["status"] == "planned"])
        success = sum(r["success"] for r in mine)
        out.append({
            "grasp": grasp, "tasks": len(mine), "success": success, "rate": success / len(mine),
            "failed": sum(r["status"] != "planned" for r in mine),
            "timeouts": sum(r["status"] == "timeout" for r in mine),
            "median_s": float(np.median(times)) if len(times) else float("nan"),
            "p90_s": float(np.percentile(times, 90)) if len(times) else float("nan"),
            "plans_per_s": float(len(times) / times.sum()) if len(times) and times.sum() > 0 else float("nan"),
            "validated": sum(r["held"] is not None for r in mine),
            "held": sum(r["held"] is True for r in mine),
        })
    return out


#: How ``summary.csv`` writes a boolean column (and an empty ``held``), read back.
_FLAGS = {True: True, False: False, "True": True, "False": False}


def _summary_row(i, row) -> dict:
    """The columns `grasp_summary` reads from row ``i``, parsed (``held``: True, False or None)."""
    missing = [c for c in ("grasp", "status", "success", "time_s") if c not in row]
    if missing:
        raise ValueError(f"row {i} of the summary has no {', '.join(missing)} column: give the rows of "
                         "ResultStore.scan or of summary.csv")
    held = row.get("held", "")
    held = "" if isinstance(held, float) and np.isnan(held) else held  # an empty cell, as pandas reads it
    try:
        time_s = float(row["time_s"])
        known = row["success"] in _FLAGS and (held in ("", None) or held in _FLAGS) and row["status"] in STATUSES
    except (TypeError, ValueError):  # not a number, or a value that cannot be looked up (a list)
        time_s, known = float("nan"), False
    if not known or not np.isfinite(time_s) or time_s < 0:
        raise ValueError(
            f"row {i} of the summary has success={row['success']!r}, held={held!r}, status={row['status']!r}, "
            f"time_s={row['time_s']!r}: success and held are True or False (held may be empty), status one of "
            f"{', '.join(STATUSES)}, time_s seconds >= 0"
        )
    return {"grasp": row["grasp"], "status": row["status"], "success": _FLAGS[row["success"]],
            "time_s": time_s, "held": None if held in ("", None) else _FLAGS[held]}
