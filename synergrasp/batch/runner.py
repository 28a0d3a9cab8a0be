"""Running a batch on Dask: the cluster, the tasks, results written as they arrive.

`run` expands the objects into tasks (`synergrasp.batch.tasks`), skips the tasks whose
results are already in the output folder, and submits the rest to a Dask cluster: a
``LocalCluster`` of one-thread worker processes on this machine, or any running scheduler by
its address. Each object is loaded by one task (`synergrasp.batch.worker.prepare_object`),
which the plans of its grasp types wait for; a worker keeps the objects it loaded. The client
writes each outcome as it arrives (`synergrasp.batch.store`), so an interrupted run loses
only the plans in flight, and a rerun of the same call plans only what is missing.
"""

from __future__ import annotations

import inspect
import json
import logging
import math
import os
import signal
import threading
import time
import uuid
from dataclasses import asdict, dataclass, field
from pathlib import Path

import numpy as np

from .._checks import positive_scalar
from ..lp import get_backend
from ..objects import BUILTINS, ellipsoid
from ..planner import METHODS, PlanResult, plan
from .store import ResultStore, TaskFailure, grasp_summary
from .tasks import expand
from .worker import plan_task, prepare_object

#: Longest wait (s) for a scheduler to answer and have a worker: an hour.
MAX_CONNECT_TIMEOUT = 3600.0


class BatchInterrupted(KeyboardInterrupt):
    """A batch stopped by Ctrl-C (or SIGTERM on the command line); ``report`` says what was written."""

    def __init__(self, report):
        super().__init__("batch interrupted")
        self.report = report


@dataclass
class BatchReport:
    """What a batch run did, and the summary table of its output folder.

    Attributes
    ----------
    out : Path
        The output folder.
    tasks : int
        Tasks of the call (objects times grasp types).
    skipped : int
        Tasks already done before this run (their files were found).
    finished : int
        Tasks finished by this run (a PlanResult or a failure written).
    revalidated : int
        Of the tasks this run took on, those planned by an earlier run and only validated by this one.
    wall_s : float
        Wall-clock time from the first task submitted to the last outcome written (s).
    startup_s : float
        Time to start or reach the cluster (s).
    workers : int
        Worker threads of the cluster when the run started (0 if nothing was planned).
    rows : list of dict
        The summary table (``summary.csv``), every task in the output folder.
    unreadable : list of Path
        Result files found unreadable and moved aside (``*.unreadable``); their tasks were planned again (a
        validation's plan is validated again when the run validates).
    warnings : int
        Warnings logged by this run's tasks (in ``OUT/warnings.log``).
    interrupted : bool
        The run was stopped before every task finished.
    """

    out: Path
    tasks: int
    skipped: int
    finished: int = 0
    revalidated: int = 0
    wall_s: float = 0.0
    startup_s: float = 0.0
    workers: int = 0
    rows: list = field(default_factory=list)
    unreadable: list = field(default_factory=list)
    warnings: int = 0
    interrupted: bool = False

    @property
    def per_grasp(self) -> list[dict]:
        """Per grasp type over the whole table: see `synergrasp.batch.store.grasp_summary`."""
        return grasp_summary(self.rows)

    def __str__(self) -> str:
        lines = []
        if self.finished and self.wall_s > 0:
            lines.append(f"{self.finished} tasks finished in {self.wall_s:.1f} s on {self.workers} workers: "
                         f"{self.finished / self.wall_s:.2f} plans/s (cluster start {self.startup_s:.1f} s)")
        lines.append(f"{self.tasks} tasks: {self.skipped} done before this run, {self.finished} now"
                     + (f" ({self.revalidated} of them planned before and validated now)" if self.revalidated else "")
                     + (", interrupted: rerun the same command to plan the rest" if self.interrupted else ""))
        lines.append(f"{'grasp':10s} {'tasks':>6s} {'grasps':>7s} {'success':>8s} {'failed':>7s} {'timeout':>8s} "
                     f"{'median s':>9s} {'p90 s':>7s} {'plans/s/worker':>15s} {'held/validated':>15s}")
        for s in self.per_grasp:
            held = f"{s['held']}/{s['validated']}" if s["validated"] else "-"
            lines.append(f"{s['grasp']:10s} {s['tasks']:6d} {s['success']:7d} {100 * s['rate']:7.1f}% {s['failed']:7d} "
                         f"{s['timeouts']:8d} {s['median_s']:9.2f} {s['p90_s']:7.2f} {s['plans_per_s']:15.2f} {held:>15s}")
        lines.append(f"summary table: {self.out / 'summary.csv'}")
        if self.warnings:
            lines.append(f"{self.warnings} warnings: {self.out / 'warnings.log'}")
        if self.unreadable:
            lines.append(f"{len(self.unreadable)} unreadable result files moved aside (their tasks planned, or a "
                         "validation's plan validated with --validate, again): "
                         + ", ".join(str(p) for p in self.unreadable))
        return "\n".join(lines)


def _importing_main_again() -> bool:
    """Whether the caller is the main script's module code, run again by a spawned process (``__mp_main__``)."""
    frame = inspect.currentframe()
    while frame is not None:
        if frame.f_code.co_name == "<module>" and frame.f_globals.get("__name__") == "__mp_main__":
            return True
        frame = frame.f_back
    return False


def run(objects, grasps=("precision",), out="batch-out", *, workers=None, scheduler=None, backend="native",
        options=None, time_limit=None, scale=1.0, validate=None, retry_failed=False, progress=True,
        connect_timeout=10.0):
    """Plan every object with every grasp type on a Dask cluster, writing each result as it finishes.

    Parameters
    ----------
    objects : str or os.PathLike, or a sequence of them
        Built-in names, mesh or point-cloud files, or folders of them (see
        `synergrasp.batch.tasks`).
    grasps : sequence of str
        Grasp types: ``"precision"``, ``"power"``.
    out : str or Path
        Output folder (layout in `synergrasp.batch.store`); created if needed.
    workers : int, optional
        Worker processes of the local cluster (one thread each), at most one
        per task; default the number of CPUs. Not with ``scheduler``.
    scheduler : str, optional
        Address of a running Dask scheduler (``tcp://host:8786``); its workers
        plan the tasks. Default: a ``LocalCluster`` on this machine's loopback.
    backend : str
        LP backend name.
    options : dict, optional
        Keyword arguments of ``synergrasp.plan`` for every task (planner options,
        ``max_iter``...); checked before any task runs: the values by the
        method's options class, the rest by a one-step plan of an ellipsoid.
    time_limit : float, optional
        Seconds per plan (checked after every planner iteration), in place of
        the planner's own ``time_limit`` unless ``options`` set it; a plan
        that exceeds it is recorded as ``"timeout"``. None: the planner's own
        limit (10 s by default), after which a plan ends without a grasp.
    scale : float
        Factor applied to the coordinates of object files (1000 for files in metres).
    validate : str, optional
        Test every successful plan in MuJoCo with this preset of
        ``synergrasp.validate`` (``"synergrasp"``, ``"dexgraspbench"``); the
        verdict goes to the ``held`` and ``physics`` columns. A rerun with it
        validates the successful plans of earlier runs without planning them
        again. Needs the ``sim`` extra. None: no validation.
    retry_failed : bool
        Plan again the tasks recorded as failed (load or plan error, timeout,
        worker lost); by default a rerun plans only the tasks without any record.
    progress : bool
        Show a progress bar (tasks done, rate, time left) on stderr.
    connect_timeout : float
        Seconds to wait for ``scheduler`` to answer and to have a worker (at
        most `MAX_CONNECT_TIMEOUT`).

    Returns
    -------
    BatchReport
        Counts, times and the summary table; ``print(report)`` gives the
        per-grasp summary.

    Raises
    ------
    ValueError
        Bad objects or grasps (see `synergrasp.batch.tasks.expand`), an unknown
        backend or validation preset, planner options the planner rejects, a
        bad ``time_limit``, ``scale`` or ``workers``; an ``out`` that cannot
        be created or written, or that another run is writing to; objects
        whose plans in ``out`` were made at another ``scale`` (all before
        anything is planned).
    ImportError
        With ``validate``, if MuJoCo is not installed.
    ConnectionError
        If ``scheduler`` does not answer, or has no worker, within ``connect_timeout``.
    RuntimeError
        If called from a script without the ``if __name__ == "__main__":``
        guard, as the local cluster's workers import it again.
    BatchInterrupted
        On Ctrl-C (a ``KeyboardInterrupt``), after the results that arrived were
        written and the summary table rebuilt; its ``report`` says what was done.

    Examples
    --------
    >>> import tempfile
    >>> report = run(["ellipsoid", "cup"], ["precision"], tempfile.mkdtemp(), workers=1, progress=False)
    >>> report.finished, [(r["object"], r["grasp"], r["success"]) for r in report.rows]
    (2, [('cup', 'precision', True), ('ellipsoid', 'precision', True)])
    >>> run(["ellipsoid", "cup"], ["precision"], report.out, workers=1, progress=False).finished   # all done
    0
    """
    if _importing_main_again():
        raise RuntimeError("synergrasp.batch.run was called while a worker process imported your script again (Dask "
                           "starts its workers with Python's spawn method): put the call under "
                           "`if __name__ == \"__main__\":`, see the batch how-to")
    tasks = expand(objects, grasps)
    store = ResultStore(out)
    _check_settings(tasks, backend, options, time_limit, scale, workers, scheduler, validate, connect_timeout)
    store.check_writable()  # (after the settings: a refused run leaves no folders behind)
    with store.lock():
        rows, unreadable = store.scan()
        for path in unreadable:
            os.replace(path, path.with_name(path.name + ".unreadable"))
        _check_same_objects(store, rows, tasks, scale, (options or {}).get("hand"))
        done = {(r["object"], r["grasp"]): r for r in rows if r["status"] == "planned" or not retry_failed}
        wanted = None
        if validate is not None:
            from ..physics import protocol

            wanted = json.loads(json.dumps(asdict(protocol(validate))))  # as a validation file holds it
        todo, to_validate = [], {}
        for task in tasks:
            row = done.get((task.key, task.grasp))
            if row is None:
                todo.append(task)
            elif wanted is not None and row["success"] and (
                    row["held"] == "" or store.validation_protocol(task.key, task.grasp) != wanted):
                todo.append(task)  # not validated yet, or with another protocol: validated (again) with this one
                to_validate[task] = store.result_path(task.key, task.grasp)
        builtins = sorted({task.key for task in todo if task.source.lower() in BUILTINS})
        if scale != 1.0 and builtins:  # (they were planned in mm, and their records said scale)
            many = len(builtins) > 1
            raise ValueError(f"scale applies to object files; the built-in object{'s' * many} "
                             f"{', '.join(map(repr, builtins))} {'are' if many else 'is'} in millimetres already: "
                             f"plan {'them' if many else 'it'} in a run of {'their' if many else 'its'} own, at "
                             "scale 1")
        report = BatchReport(Path(out), len(tasks), len(tasks) - len(todo), unreadable=unreadable)
        try:
            if todo:
                _plan_all(todo, to_validate, store, report, workers, scheduler, backend, options, time_limit, scale,
                          validate, progress, connect_timeout)
        finally:
            report.rows, _ = store.scan()
            store.write_summary(report.rows)
    return report


def _check_settings(tasks, backend, options, time_limit, scale, workers, scheduler, validate, connect_timeout):
    get_backend(backend)
    positive_scalar(connect_timeout, "connect_timeout (seconds)", MAX_CONNECT_TIMEOUT)
    if scheduler is not None and not isinstance(scheduler, str):
        raise TypeError(f"scheduler must be a Dask scheduler's address such as 'tcp://host:8786', "
                        f"got {type(scheduler).__name__}")
    if validate is not None:
        from ..physics import PRESETS

        if not isinstance(validate, str):
            raise TypeError(f"validate must be a preset's name ({', '.join(sorted(PRESETS))}) or None, got "
                            f"{type(validate).__name__} {validate!r}")
        from ..physics.simulate import mujoco_module

        if validate not in PRESETS:
            raise ValueError(f"validate must be a preset of synergrasp.validate ({', '.join(sorted(PRESETS))}) "
                             f"or None, got {validate!r}")
        mujoco_module()
    if time_limit is not None:
        positive_scalar(time_limit, "time_limit")
    positive_scalar(scale, "scale")
    if workers is not None:
        if scheduler is not None:
            raise ValueError("workers sets the size of the local cluster; a scheduler's workers are started "
                             "with `dask worker ADDRESS` (pass workers=None with scheduler=)")
        if not isinstance(workers, (int, np.integer)) or isinstance(workers, bool) or workers < 1:
            raise ValueError(f"workers must be a whole number >= 1, got {workers!r}")
    if options is not None and not isinstance(options, dict):
        raise TypeError(f"options must be a dict of synergrasp.plan keyword arguments, got {type(options).__name__}")
    options = options or {}
    own = sorted(set(options) & {"obj", "grasp", "backend", "progress"})
    if own:
        raise ValueError(f"options {own} are set by the batch itself: give the objects and grasp types as its "
                         "arguments and the backend as backend=...; a batch reports its own progress")
    method = options.get("method", "gradient")
    cap = "steps" if method == "annealing" else "max_iter"  # the option that makes the probe plan one step
    probe = ellipsoid()
    try:
        if cap in options and method in METHODS:  # the user's own value, which the probe replaces
            METHODS[method](**{cap: options[cap]})
        for grasp in dict.fromkeys(t.grasp for t in tasks):
            plan(probe, grasp, backend=backend, **{**options, cap: 1})
    except (ValueError, TypeError) as exc:
        raise ValueError(f"the planner rejects the options {options!r}: {exc}") from None


def _check_same_objects(store, rows, tasks, scale, hand=None):
    """Refuse a run whose objects already have plans in ``store`` made of another file, at another scale or with
    another hand (``hand``; None: the paper's).

    Their plans would be taken for this run's (or kept beside new ones at this
    scale, or of this hand), and ``object.json`` (which `synergrasp report`
    loads the object by) would name only one of them. A recorded file that no
    longer exists (a folder moved since) is not compared. The built-ins take
    no scale.
    """
    from ..hand import SynergyHand

    hand = SynergyHand.default() if hand is None else hand
    for row in rows:
        made_with = row["hand"]
        if row["status"] == "planned" and not hand.made(made_with):
            raise ValueError(
                f"the plans of '{row['object']}' in '{store.out}' were made with hand {made_with!r}, and this run plans "
                f"with {hand.identity!r}: pass that hand (--hand FILE) to go on with them, or write to another output "
                "folder")
    planned = {r["object"] for r in rows if r["status"] == "planned"}
    for task in tasks:
        key = task.key
        recorded = store.object_source(key) if key in planned and task.source.lower() not in BUILTINS else None
        if recorded is None:
            continue
        source, recorded_scale = recorded
        if source != task.source and Path(source).exists():
            raise ValueError(
                f"the plans of '{key}' in '{store.out}' were made of {source}, and this run's '{key}' is "
                f"{task.source}: write to another output folder (or delete '{store.results / key}' to plan it again)")
        if not math.isclose(recorded_scale, scale, rel_tol=1e-9):
            raise ValueError(
                f"the plans of '{key}' in '{store.out}' were made at scale {recorded_scale:g}, and this run's scale is "
                f"{scale:g}: pass the same scale (--scale {recorded_scale:g}) to go on with them, or write to another "
                f"output folder (or delete '{store.results / key}' to plan it again)")


def local_cluster(workers=None):
    """The Dask cluster `run` starts without a scheduler address: one-thread worker processes on loopback.

    Parameters
    ----------
    workers : int, optional
        Worker processes; default the number of CPUs.

    Returns
    -------
    distributed.LocalCluster
        Listening on 127.0.0.1 only, without the dashboard (its HTTP server on
        a free port), logging errors only, but for a worker's failed heartbeat
        to its scheduler (`synergrasp.batch.cluster_logs`). Close it when
        done (or use it in a ``with`` block).

    Notes
    -----
    The workers start without the ``MALLOC_TRIM_THRESHOLD_`` that Dask's nannies
    set by default (``distributed.nanny.pre-spawn-environ``): it makes the C
    library return freed memory at once, and a plan's many short-lived arrays
    then cost page faults afresh (``benchmarks/bench_batch.py`` measures the
    CPU time and page faults with and without it). Nor do they run Dask's
    statistical profiler (``distributed.worker.profile``), which samples
    every worker's stack every 10 ms for a dashboard that is not served (a
    worker its nanny restarts after a crash runs it again: Dask starts it
    with its default configuration).
    """
    import dask
    from distributed import LocalCluster

    from .cluster_logs import QuietHeartbeat

    with dask.config.set({"distributed.nanny.pre-spawn-environ.MALLOC_TRIM_THRESHOLD_": None,
                          "distributed.worker.profile.enabled": False}):
        try:
            return LocalCluster(n_workers=workers or os.cpu_count() or 1, threads_per_worker=1, processes=True,
                                host="127.0.0.1", dashboard_address=None,
                                scheduler_kwargs={"dashboard_address": "127.0.0.1:0"}, silence_logs=logging.ERROR,
                                plugins=[QuietHeartbeat()])
        except RuntimeError as exc:  # "Nanny failed to start": the workers' own errors are printed above it
            raise RuntimeError(f"the local Dask cluster's workers did not start ({exc}). A script that calls "
                               "synergrasp.batch.run needs it under `if __name__ == \"__main__\":` (the workers "
                               "import the script again); otherwise see the workers' errors printed above") from exc


def _connect(workers, scheduler, connect_timeout):
    """(client, cluster or None, worker threads)."""
    from distributed import Client

    if scheduler is None:
        cluster = local_cluster(workers)
        client = Client(cluster)
    else:
        cluster = None
        try:
            client = Client(scheduler, timeout=f"{connect_timeout}s")
        except (OSError, TimeoutError, ValueError) as exc:
            raise ConnectionError(
                f"no Dask scheduler answered at {scheduler!r} within {connect_timeout:g} s ({exc}); "
                "start one with `dask scheduler` and check the address"
            ) from None
        try:
            client.wait_for_workers(1, timeout=connect_timeout)
        except (OSError, TimeoutError) as exc:
            client.close()
            raise ConnectionError(f"the Dask scheduler at {scheduler!r} has no worker after {connect_timeout:g} s "
                                  f"({exc}); start some with `dask worker {scheduler}`") from None
    threads = sum(w["nthreads"] for w in client.scheduler_info()["workers"].values())
    return client, cluster, threads


def _note_interrupts():
    """Have Ctrl-C set a flag, which the batch checks after every result, and raise only while armed.

    Python raises a ``KeyboardInterrupt`` wherever the main thread is when it
    handles the signal, and one raised inside a finalizer or another
    library's callback is lost; the flag is not. While the batch is armed
    (its tasks submitted and collected), the handler in place before
    (Python's, or a caller's) then runs and the interrupt is raised; while
    the cluster starts or closes, Ctrl-C is only noted (an interrupted start
    or close left Dask's clusters half made, and a second Ctrl-C escaped
    the run as if nothing had been planned). Nothing changes outside the
    main thread or where Ctrl-C is ignored.

    Returns
    -------
    requested : threading.Event
        Set by Ctrl-C.
    arm : callable
        ``arm(True)`` raises on Ctrl-C from then on, ``arm(False)`` only notes it.
    restore : callable
        Puts the previous handler back.
    """
    requested, armed = threading.Event(), threading.Event()
    previous = signal.getsignal(signal.SIGINT)
    if threading.current_thread() is not threading.main_thread() or previous is signal.SIG_IGN:
        return requested, lambda on: None, lambda: None

    def note(signum, frame):
        requested.set()
        if armed.is_set():
            if callable(previous):
                previous(signum, frame)
            raise KeyboardInterrupt

    signal.signal(signal.SIGINT, note)
    return (requested, lambda on: armed.set() if on else armed.clear(),
            lambda: signal.signal(signal.SIGINT, previous if previous is not None else signal.SIG_DFL))


def _plan_all(todo, to_validate, store, report, workers, scheduler, backend, options, time_limit, scale, validate,
              progress, connect_timeout):
    from distributed import as_completed
    from tqdm import tqdm

    if scheduler is None:  # no more local workers than tasks: each one costs a process start
        workers = min(workers or os.cpu_count() or 1, len(todo))
    futures, token, client, cluster, bar = {}, uuid.uuid4().hex[:8], None, None, None
    counts = dict.fromkeys(("grasps", "no grasp", "failed"), 0)
    interrupted, arm, restore = _note_interrupts()  # a Ctrl-C while a local cluster starts stops the run once it is up
    client_log = logging.getLogger("distributed.client")
    level = client_log.level
    client_log.setLevel(logging.CRITICAL)  # a lost scheduler: said once (`_outcome`), not as distributed's tracebacks
    try:
        start = time.perf_counter()
        arm(scheduler is not None)  # (waiting for a remote scheduler's workers stops at once: it makes no cluster)
        try:
            client, cluster, report.workers = _connect(workers, scheduler, connect_timeout)
        except RuntimeError:  # Ctrl-C reached the local workers as they started: they did not, and that is why
            if interrupted.is_set():
                raise KeyboardInterrupt from None
            raise
        report.startup_s = time.perf_counter() - start
        bar = tqdm(total=len(todo), unit="plan", desc="batch", disable=not progress, dynamic_ncols=True)
        arm(True)
        if interrupted.is_set():
            raise KeyboardInterrupt
        start = time.perf_counter()
        by_object = {}
        for task in todo:
            by_object.setdefault((task.key, task.source), []).append(task)
        for (key, source), its_tasks in by_object.items():
            store.write_object(key, source, scale)
            prepared = client.submit(prepare_object, source, scale, key=f"load-{token}-{key}", pure=False)
            for task in its_tasks:
                earlier = PlanResult.load(to_validate[task]) if task in to_validate else None
                future = client.submit(plan_task, source, task.grasp, backend, options, time_limit, scale, prepared,
                                       validate, earlier, key=f"plan-{token}-{task.grasp}-{key}", pure=False)
                futures[future] = task
        for future in as_completed(list(futures)):
            task = futures.pop(future)
            outcome, messages, validation = _outcome(future)
            if task not in to_validate:
                store.write_result(task.key, task.grasp, outcome, validation)
            elif validation is not None:  # an earlier plan, validated now
                store.write_validation(task.key, task.grasp, validation)
                report.revalidated += 1
            store.log_warnings(task.key, task.grasp, messages)
            report.finished += 1
            report.warnings += len(messages)
            counts["failed" if isinstance(outcome, TaskFailure) else "grasps" if outcome.success else "no grasp"] += 1
            report.wall_s = time.perf_counter() - start
            bar.update(1)
            bar.set_postfix(counts, refresh=False)
            if interrupted.is_set():  # Ctrl-C whose KeyboardInterrupt was lost on the way
                raise KeyboardInterrupt
    except KeyboardInterrupt:
        report.interrupted = True
    finally:
        arm(False)  # a further Ctrl-C while the cluster closes is noted, not raised: the close completes
        try:
            if bar is not None:
                bar.close()
            if futures:
                client.cancel(list(futures))
            if client is not None:
                client.close()
            if cluster is not None:
                cluster.close()
        finally:
            restore()
            client_log.setLevel(level)
    if report.interrupted:
        raise BatchInterrupted(report)  # run() rebuilds the summary table on the way out


def _outcome(future):
    """(PlanResult or TaskFailure, warnings, Validation or None) of a finished future."""
    from distributed import KilledWorker

    if future.status == "finished":
        return future.result()
    if future.status == "cancelled":
        raise ConnectionError("the Dask cluster cancelled a task (scheduler lost?); the results written so far "
                              "are kept: rerun the same command to plan the rest")
    exc = future.exception()
    if isinstance(exc, KilledWorker):
        return TaskFailure("worker lost", f"the workers running it died repeatedly ({exc})"), [], None
    return TaskFailure("plan error", f"{type(exc).__name__}: {exc}"), [], None
