"""Batch planning on Dask: many objects and grasp types, resumable, one result file per plan.

``sg.batch.run(objects, grasps, out)`` plans every object with every grasp type on a Dask
cluster (a local one by default, any scheduler by its address) and writes each plan's
`PlanResult` to ``out`` as it finishes; a rerun plans only what is missing, and
``summary.csv`` is rebuilt from the result files. ``write_report(out)`` makes a page with the
table and a gallery of the final grasps. The command line has the same as
``synergrasp batch`` and ``synergrasp report``. Dask and threadpoolctl come with the
``batch`` extra (``pip install "synergrasp[batch]"``); they are imported when a batch runs.
"""

from .report import write_report
from .runner import BatchInterrupted, BatchReport, local_cluster, run
from .store import COLUMNS, STATUSES, ResultStore, TaskFailure, grasp_summary
from .tasks import Task, expand
from .worker import load_object, pin_blas, plan_task, prepare_object

__all__ = [
    "BatchInterrupted",
    "BatchReport",
    "COLUMNS",
    "ResultStore",
    "STATUSES",
    "Task",
    "TaskFailure",
    "expand",
    "grasp_summary",
    "load_object",
    "local_cluster",
    "pin_blas",
    "plan_task",
    "prepare_object",
    "run",
    "write_report",
]
