"""What runs on the Dask workers: load an object, plan one task, pin BLAS to one thread.

Both functions catch every exception of the work they do and return it as a
`TaskFailure`, so a bad object or a plan that raises is recorded and never stops the batch.

Each plan starts from fresh state: a copy of the loaded object and a new instance of the LP
backend. The planner's warm starts (the LP bases an object and a backend remember) then
depend only on the task itself, not on the tasks the worker ran before, so a batch gives
bit-identical results whatever the number of workers and the order of the tasks.
`plan_task` also limits BLAS to one thread in its process (once) before it plans.
"""

from __future__ import annotations

import copy
import time
import warnings

from .. import objects
from ..lp import get_backend
from ..planner import plan
from .store import TaskFailure

_pinned = False


def pin_blas() -> None:
    """Limit the BLAS and OpenMP thread pools of this process to one thread (threadpoolctl), once.

    Workers run one plan each at a time; the plans' arrays are small, and a
    BLAS that spreads them over every core makes the workers fight for cores.
    """
    global _pinned
    if not _pinned:
        from threadpoolctl import threadpool_limits

        threadpool_limits(limits=1)
        _pinned = True


def load_object(source: str, scale: float = 1.0):
    """Load one object of a batch (on a worker).

    Parameters
    ----------
    source : str
        A built-in name or a file path (`synergrasp.objects.get`).
    scale : float
        Factor applied to a file's coordinates (1000 for a file in metres);
        ignored for built-ins.

    Returns
    -------
    obj : GraspObject or TaskFailure
        The object, or a ``"load error"`` failure with the reason.
    warnings : list of str
        Warnings raised while loading.
    """
    start = time.perf_counter()
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            kwargs = {} if source.lower() in objects.BUILTINS else {"scale": scale}
            obj = objects.get(source, **kwargs)
        except Exception as exc:  # noqa: BLE001 - any failure to load is recorded, the batch goes on
            obj = TaskFailure("load error", _describe(exc), time.perf_counter() - start)
    messages = [str(w.message) for w in caught]
    if isinstance(obj, TaskFailure):
        obj.warnings = messages
    return obj, messages


class _TimeLimit(Exception):
    """Raised from the planner's progress callback when a task runs out of time."""


def plan_task(loaded, grasp: str, backend: str = "highs", options=None, time_limit=None):
    """Plan one task of a batch (on a worker).

    Parameters
    ----------
    loaded : tuple
        What `load_object` returned for the task's object.
    grasp : str
        ``"precision"`` or ``"power"``.
    backend : str
        LP backend name; the plan uses a new instance of it.
    options : dict, optional
        Keyword arguments of ``synergrasp.plan`` (planner options, ``max_iter``...).
    time_limit : float, optional
        Seconds; checked after every planner iteration (an LP solve in
        progress is not interrupted). None: no limit.

    Returns
    -------
    outcome : PlanResult or TaskFailure
        The plan (successful or not), or a ``"load error"``, ``"plan error"``
        or ``"timeout"`` failure.
    warnings : list of str
        Warnings raised while loading the object and planning.
    """
    pin_blas()
    obj, messages = loaded
    if isinstance(obj, TaskFailure):
        return obj, messages
    obj = copy.deepcopy(obj)
    start = time.perf_counter()

    def progress(check, status):
        if time.perf_counter() - start > time_limit:
            raise _TimeLimit

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            outcome = plan(obj, grasp, backend=type(get_backend(backend))(),
                           progress=progress if time_limit is not None else None, **(options or {}))
        except _TimeLimit:
            elapsed = time.perf_counter() - start
            outcome = TaskFailure("timeout", f"no result within the time limit of {time_limit:g} s", elapsed)
        except Exception as exc:  # noqa: BLE001 - a plan that raises is recorded, the batch goes on
            outcome = TaskFailure("plan error", _describe(exc), time.perf_counter() - start)
    messages = messages + [str(w.message) for w in caught]
    if isinstance(outcome, TaskFailure):
        outcome.warnings = messages
    return outcome, messages


def _describe(exc: BaseException) -> str:
    return f"{type(exc).__name__}: {exc}"
