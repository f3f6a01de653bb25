"""Worker processes forked from the client: the embedded cluster's workers start warm.

A worker started as a new Python process imports Dask and oacdsl before its first task (about
1 s of CPU for mining, 2 s with the simulator), once per worker, on the same cores as the job.
A worker forked from the client shares the modules the client has already imported
(:func:`fork_workers` imports the job's ``preload`` modules first) and starts in milliseconds.

The forks happen in the calling thread, before the cluster's scheduler and its event loop
thread exist, so that no Dask thread is copied half-way through anything (a fork keeps only
the calling thread; Dask's serialization thread, left by an earlier job in the same process,
is replaced in the child). Each child waits on a pipe for the scheduler's address, then runs
one ``distributed.Worker`` with one thread in an event loop of its own until the scheduler
closes it or the cluster stops it (:meth:`ForkedChild.stop`: SIGTERM, a graceful
``Worker.close``, then a kill after :data:`CLOSE_TIMEOUT_S`). ^C reaches the client alone.
"""

from __future__ import annotations

import asyncio
import importlib
import logging
import multiprocessing
import os
import signal
import time
from collections.abc import Mapping, Sequence
from typing import Any

__all__ = ["CLOSE_TIMEOUT_S", "MALLOC_OPTIONS", "ForkedChild", "can_fork", "fork_workers"]

#: Seconds a worker gets to close gracefully before it is killed.
CLOSE_TIMEOUT_S = 5.0


def can_fork() -> bool:
    """Whether worker processes can be forked here (POSIX; not Windows)."""
    return "fork" in multiprocessing.get_all_start_methods()


class ForkedChild:
    """One forked worker process, waiting for the scheduler's address (:meth:`send`)."""

    def __init__(self, process: Any, conn: Any):
        self.process, self.conn = process, conn

    def send(self, address: str | None, name: Any = None) -> None:
        """The scheduler's address and the worker's name (address None: exit, no worker)."""
        try:
            self.conn.send((address, name))
        except OSError:  # the child is gone already: its tasks go to the others
            pass
        self.conn.close()

    async def stop(self, timeout_s: float = CLOSE_TIMEOUT_S) -> None:
        """Ask the worker to close (SIGTERM), wait up to ``timeout_s``, then kill it; reaped."""
        started = self.conn.closed
        if not started:
            self.send(None)  # it never became a worker: it exits by itself
        deadline = time.monotonic() + timeout_s
        if started and self.process.exitcode is None:
            try:
                os.kill(self.process.pid, signal.SIGTERM)
            except ProcessLookupError:
                pass
        while self.process.exitcode is None and time.monotonic() < deadline:
            await asyncio.sleep(0.02)
        if self.process.exitcode is None:
            self.process.kill()
        self.process.join()


def fork_workers(
    n: int,
    options: Mapping[str, Any],
    env: Mapping[str, str],
    config: Mapping[str, Any],
    preload: Sequence[str] = (),
) -> list[ForkedChild]:
    """``n`` worker processes forked from this one, after importing ``preload`` here; each
    waits for :meth:`ForkedChild.send`. ``options`` are ``distributed.Worker``'s keywords,
    ``env`` is added to each child's environment, ``config`` to its Dask settings."""
    import distributed  # noqa: F401  # what every worker needs: imported once, here

    for name in preload:
        importlib.import_module(name)
    ctx = multiprocessing.get_context("fork")
    children = []
    for _ in range(n):
        reader, writer = ctx.Pipe(duplex=False)
        args = (reader, os.getpid(), dict(options), dict(env), dict(config))
        process = ctx.Process(target=_child_main, args=args, daemon=True)
        process.start()
        reader.close()
        children.append(ForkedChild(process, writer))
    return children


def _die_with(parent: int) -> None:
    """Linux: the kernel kills this process when the client's thread that forked it ends, so that a
    client killed outright leaves no worker behind (to print that its scheduler is gone)."""
    try:
        import ctypes

        ctypes.CDLL(None, use_errno=True).prctl(1, signal.SIGKILL)  # PR_SET_PDEATHSIG
    except (OSError, AttributeError):  # not Linux: the worker closes when its scheduler is gone
        pass
    if os.getppid() != parent:  # the client died before the line above
        os._exit(0)


#: glibc's ``mallopt`` settings of a worker (:func:`_steady_malloc`): option number → value.
MALLOC_OPTIONS = {
    -8: 1,  # M_ARENA_MAX: every thread allocates from the main arena
    -3: 32 << 20,  # M_MMAP_THRESHOLD, bytes: a block under 32 MiB comes from the heap, not a fresh mapping
    -1: 64 << 20,  # M_TRIM_THRESHOLD, bytes: the heap keeps up to 64 MiB free at its top
}


def _steady_malloc() -> None:
    """glibc: a worker reuses its heap from one recording to the next. Every thread allocates
    from the main arena, as a loop in the main thread does (a task runs in a worker's thread,
    and a thread's own arena gives memory back and takes it again: 7 times the page faults);
    and blocks of a recording's size (a few MiB) come from the heap and stay there. glibc's
    own thresholds start at 128 KiB and rise only as large blocks are freed, so that a process
    forked early maps, faults in and unmaps each array again: 1,870 page faults per recording
    against 280, ~4 % of its CPU."""
    try:
        import ctypes

        libc = ctypes.CDLL(None)
        for option, value in MALLOC_OPTIONS.items():
            libc.mallopt(option, value)
    except (OSError, AttributeError):  # not glibc
        pass


def _child_main(
    conn: Any, parent: int, options: dict[str, Any], env: dict[str, str], config: dict[str, Any]
) -> None:
    """A forked child: wait for the scheduler's address, then be a worker until closed."""
    _die_with(parent)
    _steady_malloc()
    os.environ.update(env)
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # ^C in the terminal is the client's to handle
    signal.signal(signal.SIGTERM, signal.SIG_DFL)  # not the client's handler: until the worker runs, just end
    try:
        address, name = conn.recv()
    except (EOFError, OSError):  # the client went away before its cluster started
        return
    finally:
        conn.close()
    if address is None:
        return
    import concurrent.futures

    import dask
    import distributed.utils

    # the client's offload thread, if it had one, was not copied by the fork: a fresh executor
    distributed.utils._offload_executor = concurrent.futures.ThreadPoolExecutor(
        max_workers=1, thread_name_prefix="Dask-Offload"
    )
    logging.getLogger("distributed").setLevel(logging.ERROR)
    with dask.config.set(config):
        asyncio.run(_serve(address, {**options, "name": name}))


async def _serve(address: str, options: dict[str, Any]) -> None:
    from distributed import Worker

    worker = await Worker(address, **options)
    loop = asyncio.get_running_loop()
    closing: list[Any] = []

    def close() -> None:
        if not closing:
            # a task still running (the job was interrupted) is not waited for: its results are lost anyway
            closing.append(asyncio.ensure_future(worker.close(reason="the job is done", executor_wait=False)))

    loop.add_signal_handler(signal.SIGTERM, close)
    await worker.finished()
