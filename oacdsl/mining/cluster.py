"""The Dask client of ``oacc mine`` and ``oacc run --seeds``: an embedded cluster, or a running one.

The embedded cluster is a scheduler in this process and ``n`` worker processes, one thread
each, started directly (``python -m distributed.cli.dask_spec`` with the plain
``distributed.Worker``), not through nannies: a nanny adds a process start per worker, a
monitor in the client, and seconds of graceful shutdown at the end of every job; a job here
is short and a worker that dies is an error row, not a restart. The workers' numerical
libraries run one thread each (``OMP/MKL/OPENBLAS_NUM_THREADS=1``, as Dask's nannies set
them): ``n`` single-threaded workers on ``n`` cores, not ``n × n`` threads.
"""

from __future__ import annotations

import asyncio
import json
import logging
import os
import sys
from typing import Any

from oacdsl.errors import UsageError

__all__ = ["WORKER_ENV", "client_for", "worker_count"]

#: Environment of the embedded cluster's worker processes (on top of this process's).
WORKER_ENV = {
    "OMP_NUM_THREADS": "1",
    "MKL_NUM_THREADS": "1",
    "OPENBLAS_NUM_THREADS": "1",
    "MALLOC_TRIM_THRESHOLD_": "65536",
    "DASK_LOGGING__DISTRIBUTED": "error",  # a worker's start and stop lines are not the user's business
}


def _local(n: int, dashboard: bool) -> Any:
    from distributed import Scheduler, SpecCluster
    from distributed.deploy.subprocess import SubprocessWorker

    class WorkerProcess(SubprocessWorker):  # type: ignore[misc]
        """A ``distributed.Worker`` in a process of its own, with :data:`WORKER_ENV`."""

        async def _start(self) -> None:
            spec = {"cls": "distributed.Worker", "opts": self.worker_kwargs}
            self.process = await asyncio.create_subprocess_exec(
                sys.executable, "-m", "distributed.cli.dask_spec", self.scheduler, "--spec", json.dumps(spec),
                env={**os.environ, **WORKER_ENV},
            )

    worker = {"cls": WorkerProcess, "options": {"worker_kwargs": {"nthreads": 1}}}
    # the scheduler's HTTP server (health routes; the dashboard when asked) on a free port, never 8787
    scheduler = {"cls": Scheduler, "options": {"host": "127.0.0.1", "dashboard_address": ":0",
                                               "dashboard": dashboard}}
    return SpecCluster(workers={i: worker for i in range(n)}, scheduler=scheduler,
                       silence_logs=logging.ERROR)


def client_for(workers: int | None, scheduler: str | None, dashboard: bool) -> tuple[Any, Any]:
    """``(client, cluster)``: a client of the running scheduler at ``scheduler`` (cluster None), or
    of an embedded cluster of ``workers`` processes (default: one per core)."""
    try:
        from dask.distributed import Client
    except ImportError as error:
        raise UsageError(f"mining needs the 'scale' extra (pip install -e '.[scale]'): {error}") from None
    if scheduler is not None:
        try:
            return Client(scheduler, timeout="30s"), None
        except (OSError, TimeoutError) as error:
            raise UsageError(f"--scheduler {scheduler}: cannot reach the Dask scheduler ({error})") from None
    n = workers if workers is not None else max(1, os.cpu_count() or 1)
    cluster = _local(n, dashboard)
    try:
        return Client(cluster), cluster
    except BaseException:
        cluster.close()
        raise


def worker_count(client: Any, workers: int | None, scheduler: str | None) -> int:
    """The workers' threads a job can count on: the embedded cluster's processes, or the running
    cluster's threads (at least 1)."""
    if scheduler is None:
        return workers if workers is not None else max(1, os.cpu_count() or 1)
    try:
        return max(1, sum(client.nthreads().values()))
    except (OSError, TimeoutError):
        return 1
