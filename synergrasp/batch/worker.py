"""What runs on the Dask workers: load an object once per worker, plan one task, pin BLAS.

A batch submits one `prepare_object` task per object and one `plan_task` per (object, grasp)
that depends on it. `prepare_object` loads the object on some worker (a mesh's convex
decomposition then lands in the disk cache) and keeps it in that worker process; the plan
tasks run after it, where Dask prefers the worker that holds its (tiny) result, and take the
object from their process's memory, loading it there (from the disk cache) only if another
worker prepared it. Objects stay in the workers: they hold fcl geometry that cannot be pickled.

Every plan starts its LPs cold (`synergrasp.plan` drops the warm starts kept from earlier
solves), so a plan depends only on its task, not on the tasks the worker ran before: a batch
gives bit-identical results whatever the number of workers and the order of the tasks, and the
same as ``sg.plan`` in a new process. A plan and a validation each get a new `GraspObject` over
the loaded object's convex pieces and a new instance of the LP backend (nothing shared between
tasks), the validation with the pseudo-distance's memory of regimes cleared
(``synergrasp.pseudo_distance.reset_regime_memory``).

Both task functions catch every exception of the work they do and return it as a
`TaskFailure`, so a bad object or a plan that raises is recorded and never stops the batch.
`plan_task` also limits BLAS to one thread in its process (once) before it plans, and
tests a successful plan in MuJoCo when the batch asks for it (``synergrasp.validate``).
"""

from __future__ import annotations

import os
import time
import warnings
from collections import OrderedDict

from .. import objects
from ..lp import get_backend
from ..planner import plan
from ..pseudo_distance import reset_regime_memory
from .store import TaskFailure

#: Loaded objects a worker process keeps (the most recently used).
KEPT_OBJECTS = 8

_pinned = False
_kept: OrderedDict = OrderedDict()


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
    """Load one object of a batch.

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

    Examples
    --------
    >>> load_object("cup")[0]
    GraspObject('cup', 6 pieces, 75 x 75 x 80 mm, L=51.5)
    >>> load_object("teapot")[0].reason
    "ValueError: unknown object 'teapot': not a built-in (ellipsoid, cup, bell, goblet) and no such file"
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


def _kept_object(source: str, scale: float):
    """`load_object` through this process's memory of the last `KEPT_OBJECTS` objects (a file edited since, by its
    modification time and size, is loaded again: a long-lived worker of a cluster served a fixed file's old failure)."""
    try:
        stamp = os.stat(source)
        key = (source, float(scale), stamp.st_mtime_ns, stamp.st_size)
    except OSError:  # a built-in, or no such file
        key = (source, float(scale))
    if key in _kept:
        _kept.move_to_end(key)
    else:
        _kept[key] = load_object(source, scale)
        while len(_kept) > KEPT_OBJECTS:
            _kept.popitem(last=False)
    return _kept[key]


def prepare_object(source: str, scale: float = 1.0):
    """Load an object into this worker process (the task the plans of one object depend on).

    Parameters
    ----------
    source : str
        A built-in name or a file path.
    scale : float
        Factor applied to a file's coordinates.

    Returns
    -------
    failure : TaskFailure or None
        The ``"load error"``, or None when the object loaded.
    warnings : list of str
        Warnings raised while loading.
    """
    obj, messages = _kept_object(source, scale)
    return (obj if isinstance(obj, TaskFailure) else None), messages


class _TimeLimit(Exception):
    """Raised from the planner's progress callback when a task runs out of time."""


def plan_task(source: str, grasp: str, backend: str = "native", options=None, time_limit=None, scale: float = 1.0,
              prepared=None, validate=None, result=None):
    """Plan one task of a batch (on a worker), and test its grasp in MuJoCo if asked.

    Parameters
    ----------
    source : str
        The object: a built-in name or a file path.
    grasp : str
        ``"precision"`` or ``"power"``.
    backend : str
        LP backend name; the plan uses a new instance of it.
    options : dict, optional
        Keyword arguments of ``synergrasp.plan`` (planner options, ``max_iter``...).
    time_limit : float, optional
        Seconds; checked after every planner iteration (an LP solve in
        progress is not interrupted), in place of the planner's own
        ``time_limit`` (unless ``options`` set it). None: the planner's own.
    scale : float
        Factor applied to a file's coordinates.
    prepared : tuple, optional
        What `prepare_object` returned for the object: its load failure is
        returned as this task's outcome, its warnings with it.
    validate : str, optional
        A preset of ``synergrasp.validate`` (``"synergrasp"``, ``"dexgraspbench"``):
        a successful plan is tested in MuJoCo with it. None: no validation.
    result : PlanResult, optional
        A plan made before: only validate it (the task's plan is not made again).

    Returns
    -------
    outcome : PlanResult or TaskFailure
        The plan (successful or not), or a ``"load error"``, ``"plan error"``
        or ``"timeout"`` failure.
    warnings : list of str
        Warnings raised while loading the object, planning and validating; a
        validation that raised is reported here.
    validation : Validation or None
        The physics validation of a successful plan, with ``validate``.

    Examples
    --------
    >>> result, _, _ = plan_task("ellipsoid", "precision")
    >>> result.success, result.contact_labels[0]
    (True, 'T0')
    >>> plan_task("ellipsoid", "precision", time_limit=1e-6)[0].status
    'timeout'
    """
    pin_blas()
    failure, messages = prepared if prepared is not None else (None, None)
    if failure is not None:
        return failure, messages, None
    loaded, load_messages = _kept_object(source, scale)
    messages = list(load_messages if messages is None else messages)
    if isinstance(loaded, TaskFailure):
        return loaded, messages, None
    if result is None:
        outcome = _plan(_fresh(loaded), grasp, backend, options, time_limit, messages)
    else:
        outcome = result
    validation = None
    if validate is not None and not isinstance(outcome, TaskFailure) and outcome.success:
        from ..physics import validate as physics_validate

        reset_regime_memory()
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            try:
                validation = physics_validate(outcome, _fresh(loaded), preset=validate, hand=(options or {}).get("hand"),
                                              backend=type(get_backend(backend))())
            except Exception as exc:  # noqa: BLE001 - the plan is kept; the next run tries again
                messages.append(f"validation failed: {_describe(exc)}")
        messages += [str(w.message) for w in caught]
    if isinstance(outcome, TaskFailure):
        outcome.warnings = messages
    return outcome, messages, validation


def _fresh(loaded):
    """A new GraspObject over a loaded object's convex pieces: the same object, without the warm starts of earlier queries."""
    return objects.GraspObject(list(loaded.convex), center=loaded.center, torque_scale=loaded.torque_scale,
                               name=loaded.name, mesh=loaded.mesh, points=loaded.points, info=loaded.info)


def _plan(obj, grasp, backend, options, time_limit, messages):
    """``synergrasp.plan`` on a new backend instance, its failure as a TaskFailure; appends its warnings to ``messages``."""
    start = time.perf_counter()

    def progress(check, status):
        if time.perf_counter() - start > time_limit:
            raise _TimeLimit

    options = dict(options or {})
    if time_limit is not None and not {"time_limit", "options"} & set(options):
        options["time_limit"] = None  # the batch's limit, not the planner's own (10 s), ends a plan
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            outcome = plan(obj, grasp, backend=type(get_backend(backend))(),
                           progress=progress if time_limit is not None else None, **options)
        except _TimeLimit:
            elapsed = time.perf_counter() - start
            outcome = TaskFailure("timeout", f"no result within the time limit of {time_limit:g} s", elapsed)
        except Exception as exc:  # noqa: BLE001 - a plan that raises is recorded, the batch goes on
            outcome = TaskFailure("plan error", _describe(exc), time.perf_counter() - start)
    messages += [str(w.message) for w in caught]
    return outcome


def _describe(exc: BaseException) -> str:
    return f"{type(exc).__name__}: {exc}"
