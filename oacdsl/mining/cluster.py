"""The Dask client of ``oacc mine`` and ``oacc run --seeds``: an embedded cluster, or a running one.

The embedded cluster is a scheduler in this process and ``n`` worker processes with one
thread each, plain ``distributed.Worker``s without nannies: a nanny adds a process start per
worker, a monitor in the client, and seconds of graceful shutdown at the end of every job; a
job here is short and a worker that dies is an error row, not a restart. The workers are
forked from this process before the scheduler starts (:mod:`oacdsl.mining.forked`: they
start with the job's modules imported); where there is no ``fork`` (Windows) each is a new
process (``python -m distributed.cli.dask_spec``).

New processes run their numerical libraries with one thread (``OMP/MKL/OPENBLAS_NUM_THREADS=1``,
as Dask's nannies set them): ``n`` single-threaded workers on ``n`` cores, not ``n × n``
threads. Forked ones keep the client's libraries as loaded (``oacc mine`` of 40 recordings on
2 workers took the same CPU time with one BLAS thread as with the default). The workers run
without Dask's statistical profiler and poll their health less often (:data:`WORKER_CONFIG`),
the scheduler too (:data:`SCHEDULER_CONFIG`).

:func:`close` ends a job in order: the client first (the scheduler forgets the job's data),
then each worker closes gracefully, then the scheduler, so that no side reads a connection
the other has already dropped.

A running scheduler may have no worker yet (a batch queue still starting them) or never get one
(a worker that cannot reach it): :func:`client_for` waits at most ``worker_wait_s`` for the first
worker to join, saying so on the progress stream every :data:`WAIT_NOTE_S`, then stops the job
with a one-line :class:`~oacdsl.errors.UsageError` instead of waiting forever.
"""

from __future__ import annotations

import asyncio
import json
import logging
import os
import sys
import time
import uuid
from collections.abc import Sequence
from typing import IO, Any

from oacdsl.errors import UsageError

__all__ = [
    "SCHEDULER_CONFIG",
    "WAIT_NOTE_S",
    "WORKER_CONFIG",
    "WORKER_ENV",
    "WORKER_WAIT_S",
    "client_for",
    "close",
    "share",
    "wait_for_worker",
    "worker_count",
]

#: How long a job given a running scheduler waits for its first worker (``--worker-wait``).
WORKER_WAIT_S = 120.0
#: While waiting, a line on the progress stream this often.
WAIT_NOTE_S = 10.0

#: Dask settings of the embedded cluster's workers: no statistical profiler (it samples every
#: thread's stack 100 times a second: ~3 % of a core while idle, more while a task runs) and
#: health polls once a second, not every 20 to 500 ms.
WORKER_CONFIG: dict[str, Any] = {
    "distributed.worker.profile.enabled": False,
    "distributed.admin.tick.interval": "1s",
    "distributed.admin.system-monitor.interval": "2s",
    "distributed.worker.memory.monitor-interval": "1s",
}
#: The embedded scheduler's health polls, as the workers'.
SCHEDULER_CONFIG = {k: v for k, v in WORKER_CONFIG.items() if k.startswith("distributed.admin.")}


def _env_name(key: str) -> str:
    return "DASK_" + key.upper().replace(".", "__").replace("-", "_")


#: Environment of the embedded cluster's worker processes (on top of this process's).
WORKER_ENV = {
    "OMP_NUM_THREADS": "1",
    "MKL_NUM_THREADS": "1",
    "OPENBLAS_NUM_THREADS": "1",
    # as a forked worker (oacdsl.mining.forked._steady_malloc)
    "MALLOC_ARENA_MAX": "1",
    "MALLOC_MMAP_THRESHOLD_": str(32 << 20),
    "MALLOC_TRIM_THRESHOLD_": str(64 << 20),
    "DASK_LOGGING__DISTRIBUTED": "error",  # a worker's start and stop lines are not the user's business
    **{_env_name(k): str(v) for k, v in WORKER_CONFIG.items()},  # for a new process (not forked)
}


def _local(n: int, dashboard: bool, preload: Sequence[str]) -> Any:
    import dask
    from distributed import Scheduler, SpecCluster
    from distributed.deploy.spec import ProcessInterface
    from distributed.deploy.subprocess import SubprocessWorker

    from oacdsl.mining.forked import can_fork, fork_workers

    class ForkedWorker(ProcessInterface):  # type: ignore[misc]
        """A worker forked before the cluster started (:mod:`oacdsl.mining.forked`)."""

        def __init__(self, scheduler: str, child: Any, name: Any = None):
            super().__init__(scheduler, name)
            self.scheduler, self.child, self.name = scheduler, child, name

        async def start(self) -> None:
            self.child.send(self.scheduler, self.name)
            await super().start()

        async def close(self) -> None:
            await self.child.stop()
            await super().close()

    class WorkerProcess(SubprocessWorker):  # type: ignore[misc]
        """A ``distributed.Worker`` in a process of its own, with :data:`WORKER_ENV`."""

        async def _start(self) -> None:
            spec = {"cls": "distributed.Worker", "opts": self.worker_kwargs}
            self.process = await asyncio.create_subprocess_exec(
                sys.executable, "-m", "distributed.cli.dask_spec", self.scheduler, "--spec", json.dumps(spec),
                env={**os.environ, **WORKER_ENV},
            )

    if can_fork():  # before the cluster's event loop thread exists
        options = {"nthreads": 1, "host": "127.0.0.1"}
        children = fork_workers(n, options, WORKER_ENV, WORKER_CONFIG, preload)
        workers = {i: {"cls": ForkedWorker, "options": {"child": c}} for i, c in enumerate(children)}
    else:
        children = []
        worker = {"cls": WorkerProcess, "options": {"worker_kwargs": {"nthreads": 1}}}
        workers = {i: worker for i in range(n)}
    # the scheduler's HTTP server (health routes; the dashboard when asked) on a free port, never 8787
    scheduler = {"cls": Scheduler, "options": {"host": "127.0.0.1", "dashboard_address": ":0",
                                               "dashboard": dashboard}}
    try:
        with dask.config.set(SCHEDULER_CONFIG):
            return SpecCluster(workers=workers, scheduler=scheduler, silence_logs=logging.ERROR)
    except BaseException:
        for child in children:
            child.send(None)
        raise


def wait_for_worker(
    client: Any, scheduler: str, wait_s: float = WORKER_WAIT_S, progress: IO[str] | None = None
) -> int:
    """The number of workers of the running cluster once at least one has joined; waits at most
    ``wait_s`` seconds for the first, writing a line to ``progress`` at the start and every
    :data:`WAIT_NOTE_S` seconds; :class:`UsageError` (exit 2) when none joined in time."""
    t0 = time.monotonic()
    deadline = t0 + wait_s
    next_note, told = t0, False
    while True:
        try:
            n = len(client.nthreads())
        except (OSError, TimeoutError) as error:
            raise UsageError(f"--scheduler {scheduler}: lost the Dask scheduler ({error})") from None
        if n:
            if told and progress is not None:
                waited_s = time.monotonic() - t0
                print(f"oacc: {n} worker(s) joined {scheduler} after {waited_s:.0f} s", file=progress)
            return n
        now = time.monotonic()
        if now >= deadline:
            raise UsageError(
                f"--scheduler {scheduler}: no Dask worker joined in {wait_s:g} s"
                f" (start one with 'dask worker {scheduler}', or wait longer with --worker-wait SECONDS)"
            )
        if progress is not None and now >= next_note:
            print(
                f"oacc: waiting for a Dask worker to join {scheduler}: {now - t0:.0f} s of {wait_s:g} s",
                file=progress,
                flush=True,
            )
            next_note, told = now + WAIT_NOTE_S, True
        time.sleep(min(0.5, max(0.0, deadline - now)))


def client_for(
    workers: int | None,
    scheduler: str | None,
    dashboard: bool,
    preload: Sequence[str] = (),
    *,
    worker_wait_s: float = WORKER_WAIT_S,
    progress: IO[str] | None = None,
) -> tuple[Any, Any]:
    """``(client, cluster)``: a client of the running scheduler at ``scheduler`` (cluster None)
    once a worker has joined it (:func:`wait_for_worker`, at most ``worker_wait_s`` seconds), or
    of an embedded cluster of ``workers`` processes (default: one per core) forked after this
    process imported the modules ``preload`` (the job's tasks' own imports)."""
    try:
        from dask.distributed import Client
    except ImportError as error:
        raise UsageError(f"mining needs the 'scale' extra (pip install -e '.[scale]'): {error}") from None
    if scheduler is not None:
        if not worker_wait_s > 0:
            raise UsageError(f"--worker-wait {worker_wait_s:g}: more than 0 seconds")
        try:
            client = Client(scheduler, timeout="30s")
        except (OSError, TimeoutError) as error:
            raise UsageError(f"--scheduler {scheduler}: cannot reach the Dask scheduler ({error})") from None
        try:
            wait_for_worker(client, scheduler, worker_wait_s, progress)
        except BaseException:
            client.close()
            raise
        return client, None
    n = workers if workers is not None else max(1, os.cpu_count() or 1)
    cluster = _local(n, dashboard, preload)
    try:
        return Client(cluster), cluster
    except BaseException:
        cluster.close()
        raise


def _itself(obj: Any) -> Any:
    return obj


def share(client: Any, obj: Any, name: str) -> Any:
    """``obj`` on the cluster, as a future the job's tasks take as an argument: held by the first
    worker that comes up and copied to another when one of its tasks needs it. (``scatter``
    would first wait, polling every 0.1 s, for a worker to exist.)"""
    return client.submit(_itself, obj, pure=False, key=f"{name}-{uuid.uuid4().hex}")


async def _stop_forked(cluster: Any) -> None:
    await asyncio.gather(*(w.child.stop() for w in list(cluster.workers.values()) if hasattr(w, "child")))


def close(client: Any, cluster: Any) -> None:
    """End a job in order (module doc): the client, then the embedded cluster if any: its forked
    workers close themselves while the scheduler still knows them (a worker the scheduler
    retired first may hear from its next heartbeat that it is unknown, and log an error)."""
    try:
        client.close()
    finally:
        if cluster is not None:
            try:
                cluster.sync(_stop_forked, cluster)
            finally:
                cluster.close()


def worker_count(client: Any, workers: int | None, scheduler: str | None) -> int:
    """The workers' threads a job can count on: the embedded cluster's processes, or the running
    cluster's threads (at least 1)."""
    if scheduler is None:
        return workers if workers is not None else max(1, os.cpu_count() or 1)
    try:
        return max(1, sum(client.nthreads().values()))
    except (OSError, TimeoutError):
        return 1
