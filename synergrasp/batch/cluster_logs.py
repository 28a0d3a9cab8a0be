"""What a local cluster's workers log as the cluster closes: the plugin that quiets the heartbeat race.

When a local cluster closes, its scheduler (in the client's process) can close the
connection while a worker's heartbeat is in flight; the worker then logs "Failed to
communicate with scheduler during heartbeat." with two tracebacks, after the batch has
already written its results and its summary. `QuietHeartbeat` drops that one record in every
worker of `synergrasp.batch.local_cluster` (a worker the nanny restarts gets it again): the
local scheduler lives in the client's process, so losing it is the batch's to report, once.
Every other record is printed as before. Workers of a scheduler given by its address are not
touched: their logs are their owner's. Dask is imported here, so this module is imported
only when a batch runs.
"""

from __future__ import annotations

import logging

from distributed import WorkerPlugin

#: The worker's log record (its format string) dropped by `QuietHeartbeat`.
HEARTBEAT_FAILED = "Failed to communicate with scheduler during heartbeat."


class _DropHeartbeatFailure(logging.Filter):
    def filter(self, record: logging.LogRecord) -> bool:
        return record.msg != HEARTBEAT_FAILED


class QuietHeartbeat(WorkerPlugin):
    """Drops `HEARTBEAT_FAILED` from the ``distributed.worker`` logger of the worker it is set up in."""

    name = "synergrasp-quiet-heartbeat"

    def setup(self, worker) -> None:
        log = logging.getLogger("distributed.worker")
        if not any(isinstance(f, _DropHeartbeatFailure) for f in log.filters):
            log.addFilter(_DropHeartbeatFailure())
