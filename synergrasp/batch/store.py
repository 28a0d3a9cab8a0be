"""The output folder of a batch: result files, atomic writes, what is done, the summary table.

Layout of ``OUT``::

    OUT/results/KEY/object.json          where the object came from (source, scale)
    OUT/results/KEY/GRASP.json           a finished plan: one PlanResult (PlanResult.save)
    OUT/results/KEY/GRASP.failed.json    a task that gave no PlanResult: its status and reason
    OUT/summary.csv                      one row per task, rebuilt from the files above
    OUT/warnings.log                     warnings raised while loading or planning, per task

``KEY`` names the object (see `synergrasp.batch.tasks`). Every file is written to a
temporary file in the same folder, then renamed over its final name (``os.replace``), so
a file under its final name is always whole: an interrupted run leaves no partial result.
A task is done when one of its two files exists.
"""

from __future__ import annotations

import csv
import io
import json
import os
import socket
from dataclasses import asdict, dataclass, field
from pathlib import Path

import numpy as np

from ..planner.result import PlanResult

#: Columns of ``summary.csv``, in order.
COLUMNS = (
    "object", "grasp", "status", "success", "reason", "q", "sq", "time_s", "iterations", "attempts",
    "contacts", "penetration_mm", "lp_solves", "backend", "object_name", "file",
)
#: Values of the ``status`` column: a PlanResult was written (``planned``, whether or not it
#: found a grasp), or the task gave none.
STATUSES = ("planned", "load error", "plan error", "timeout", "worker lost")
_FAILURE_FORMAT = "synergrasp.BatchFailure/1"
_TMP = ".tmp"


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


def write_atomic(path, content) -> Path:
    """Write a file through a temporary file in the same folder and a rename (``os.replace``).

    Parameters
    ----------
    path : str or Path
        Final file name; its folder is created if needed.
    content : str or callable
        The text, or a function that writes the file at the path it is given
        (e.g. ``PlanResult.save``).

    Returns
    -------
    Path
        ``path``, which holds either its old content or all of the new one, never
        a part: a process killed mid-write leaves at most a hidden temporary file
        (``.NAME.HOST-PID.tmp``), which `ResultStore.check_writable` removes later.
        The content is flushed to disk (``os.fsync``) before the rename.

    Examples
    --------
    >>> import tempfile
    >>> from pathlib import Path
    >>> folder = Path(tempfile.mkdtemp())
    >>> write_atomic(folder / "a" / "b.txt", "hello").read_text()
    'hello'
    >>> sorted(p.name for p in (folder / "a").iterdir())     # no temporary file left
    ['b.txt']
    """
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(f".{path.name}.{_writer_id()}{_TMP}")
    try:
        if callable(content):
            content(tmp)
        else:
            tmp.write_text(content, encoding="utf-8")
        with open(tmp, "rb") as handle:  # on disk before it takes the final name
            os.fsync(handle.fileno())
        os.replace(tmp, path)
    finally:
        tmp.unlink(missing_ok=True)
    return path


def _writer_id() -> str:
    return f"{socket.gethostname()}-{os.getpid()}"


class ResultStore:
    """The output folder of a batch (layout in the module docstring).

    Parameters
    ----------
    out : str or Path
        The folder; created by `check_writable`.
    """

    def __init__(self, out):
        self.out = Path(out)
        self.results = self.out / "results"
        self.summary_path = self.out / "summary.csv"
        self.warnings_path = self.out / "warnings.log"

    def result_path(self, key: str, grasp: str) -> Path:
        """File of the PlanResult of task (``key``, ``grasp``)."""
        return self.results / key / f"{grasp}.json"

    def failure_path(self, key: str, grasp: str) -> Path:
        """File of the failure record of task (``key``, ``grasp``)."""
        return self.results / key / f"{grasp}.failed.json"

    def check_writable(self) -> None:
        """Create the folder if needed and write (then remove) a probe file in it.

        Also removes the temporary files that writers of this host left behind
        when they were killed mid-write (their process no longer exists).

        Raises
        ------
        PermissionError
            If the folder cannot be created or written; the message names it.
        """
        try:
            self.results.mkdir(parents=True, exist_ok=True)
            write_atomic(self.out / ".probe", "").unlink()
        except OSError as exc:
            raise PermissionError(
                f"output folder '{self.out}' cannot be created or written ({exc}); choose another output folder"
            ) from None
        host = socket.gethostname()
        for tmp in self.results.rglob(f".*{_TMP}"):
            writer = tmp.name[: -len(_TMP)].rsplit(".", 1)[-1]
            owner, _, pid = writer.rpartition("-")
            if owner == host and pid.isdigit() and not _alive(int(pid)):
                tmp.unlink(missing_ok=True)

    def write_object(self, key: str, source: str, scale: float) -> None:
        """Record where object ``key`` comes from (``results/KEY/object.json``)."""
        write_atomic(self.results / key / "object.json", json.dumps({"source": source, "scale": scale}))

    def object_source(self, key: str) -> tuple[str, float] | None:
        """(source, scale) recorded for object ``key``, or None if there is no readable record."""
        try:
            data = json.loads((self.results / key / "object.json").read_text())
            return str(data["source"]), float(data["scale"])
        except (OSError, ValueError, KeyError, TypeError):
            return None

    def write_result(self, key: str, grasp: str, outcome) -> Path:
        """Write a task's outcome atomically and drop a failure record it replaces.

        Parameters
        ----------
        key, grasp : str
            The task.
        outcome : PlanResult or TaskFailure

        Returns
        -------
        Path
            The file written.
        """
        if isinstance(outcome, PlanResult):
            path = write_atomic(self.result_path(key, grasp), outcome.save)
            self.failure_path(key, grasp).unlink(missing_ok=True)
            return path
        record = {"format": _FAILURE_FORMAT, "object": key, "grasp": grasp, **asdict(outcome)}
        return write_atomic(self.failure_path(key, grasp), json.dumps(record, indent=1))

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
        rows, unreadable = {}, []
        if not self.results.is_dir():
            return [], []
        for path in sorted(self.results.rglob("*.json")):
            if path.name.startswith(".") or path.name == "object.json":
                continue
            key = path.parent.relative_to(self.results).as_posix()
            failed = path.name.endswith(".failed.json")
            grasp = path.name[: -len(".failed.json")] if failed else path.stem
            if not failed:
                try:
                    rows[key, grasp] = _plan_row(key, grasp, PlanResult.load(path), path.relative_to(self.out))
                except (ValueError, TypeError, KeyError):
                    unreadable.append(path)
                continue
            if (key, grasp) in rows or self.result_path(key, grasp).is_file():
                continue
            try:
                data = json.loads(path.read_text())
                if data.get("format") != _FAILURE_FORMAT or data.get("status") not in STATUSES:
                    raise ValueError("not a failure record")
                rows[key, grasp] = _failure_row(key, grasp, data, path.relative_to(self.out))
            except (OSError, ValueError, AttributeError):
                unreadable.append(path)
        return [rows[k] for k in sorted(rows)], unreadable

    def write_summary(self, rows) -> Path:
        """Write ``summary.csv`` (atomically) from `scan`'s rows.

        Returns
        -------
        Path
        """
        buffer = io.StringIO()
        writer = csv.DictWriter(buffer, fieldnames=COLUMNS, lineterminator="\n")
        writer.writeheader()
        writer.writerows(rows)
        return write_atomic(self.summary_path, buffer.getvalue())


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True


def _plan_row(key, grasp, result: PlanResult, file) -> dict:
    return {
        "object": key, "grasp": grasp, "status": "planned", "success": bool(result.success),
        "reason": result.reason, "q": result.final_q, "sq": result.final_sq, "time_s": float(result.time_s),
        "iterations": int(result.total_iterations), "attempts": len(result.attempts) or 1,
        "contacts": len(result.contact_labels), "penetration_mm": float(result.penetration),
        "lp_solves": int(result.lp_solves), "backend": result.backend, "object_name": result.object_name,
        "file": Path(file).as_posix(),
    }


def _failure_row(key, grasp, data: dict, file) -> dict:
    row = dict.fromkeys(COLUMNS, "")
    row.update(object=key, grasp=grasp, status=data["status"], success=False, reason=str(data.get("reason", "")),
               time_s=float(data.get("time_s", 0.0)), file=Path(file).as_posix())
    return row


def grasp_summary(rows) -> list[dict]:
    """Per grasp type: tasks, grasps found, success rate, failures, plan times.

    Parameters
    ----------
    rows : list of dict
        Rows of the summary table (`ResultStore.scan`).

    Returns
    -------
    list of dict
        One dict per grasp type (in order of first appearance) with ``grasp``,
        ``tasks``, ``success`` (grasps found), ``rate`` (success / tasks),
        ``failed`` (tasks without a PlanResult), ``timeouts``, ``median_s`` and
        ``p90_s`` (over the plans' own times, NaN without plans) and
        ``plans_per_s`` (plans one worker finishes per second: plans / their
        summed time).

    Examples
    --------
    >>> rows = [{"grasp": "power", "status": "planned", "success": True, "time_s": 1.0},
    ...         {"grasp": "power", "status": "planned", "success": False, "time_s": 3.0},
    ...         {"grasp": "power", "status": "timeout", "success": False, "time_s": 9.0}]
    >>> s = grasp_summary(rows)[0]
    >>> s["tasks"], s["success"], round(s["rate"], 3), s["timeouts"], s["median_s"], s["plans_per_s"]
    (3, 1, 0.333, 1, 2.0, 0.5)
    """
    out = []
    for grasp in dict.fromkeys(r["grasp"] for r in rows):
        mine = [r for r in rows if r["grasp"] == grasp]
        times = np.array([float(r["time_s"]) for r in mine if r["status"] == "planned"])
        success = sum(bool(r["success"]) for r in mine)
        out.append({
            "grasp": grasp, "tasks": len(mine), "success": success, "rate": success / len(mine),
            "failed": sum(r["status"] != "planned" for r in mine),
            "timeouts": sum(r["status"] == "timeout" for r in mine),
            "median_s": float(np.median(times)) if len(times) else float("nan"),
            "p90_s": float(np.percentile(times, 90)) if len(times) else float("nan"),
            "plans_per_s": float(len(times) / times.sum()) if len(times) and times.sum() > 0 else float("nan"),
        })
    return out
