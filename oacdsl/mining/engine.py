"""Mining many recordings on Dask distributed: the client side of ``oacc mine``.

:func:`mine` expands the recordings, checks the library once in the client, skips the
recordings the job's table already holds (a killed job run again resumes), and sends one
task per remaining recording (:func:`oacdsl.mining.task.analyse`) to the cluster: an embedded
``LocalCluster`` of ``workers`` worker processes (one thread each) by default, or the cluster
of a running ``dask scheduler`` at ``scheduler``. Results are written by the client alone, as
they arrive, one transaction per recording (:mod:`oacdsl.mining.table`); a task that dies with its
worker becomes an error row too. At the end the summary page is written
(:mod:`oacdsl.mining.summary`).
"""

from __future__ import annotations

import logging
import os
import sys
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import IO, Any

from oacdsl.errors import InputError, UsageError
from oacdsl.mining.inputs import RecordingFile, expand_recordings
from oacdsl.mining.table import TABLE_NAME, MineTable
from oacdsl.mining.task import JobSpec, analyse

__all__ = ["MineResult", "mine"]


@dataclass
class MineResult:
    """What a job did: the recordings found, analysed now, skipped (done before), failed now;
    the table and summary paths; the Dask dashboard's address (None when not asked)."""

    found: int
    analysed: int
    skipped: int
    errors: int
    table: Path
    summary: Path
    dashboard: str | None = None
    wall_s: float = 0.0
    rows: list[dict[str, Any]] = field(default_factory=list, repr=False)


def _params_dict(params: Any) -> dict[str, Any]:
    from dataclasses import asdict

    from oacdsl.segmentation.params import AasParams

    return asdict(params if params is not None else AasParams())


class _Ticker:
    """done/total, rate and ETA on ``stream``: in place on a terminal, a line per 10 % elsewhere."""

    def __init__(
        self, total: int, stream: IO[str] | None, what: str = "mined", unit: str = "recordings"
    ) -> None:
        self.total, self.stream, self.done, self.errors = total, stream, 0, 0
        self.what, self.unit = what, unit
        self.start = time.perf_counter()
        self.tty = bool(stream is not None and getattr(stream, "isatty", lambda: False)())
        self._shown = -1

    def tick(self, failed: bool) -> None:
        self.done += 1
        self.errors += failed
        if self.stream is None:
            return
        elapsed = time.perf_counter() - self.start
        rate = self.done / elapsed if elapsed > 0 else 0.0
        eta = (self.total - self.done) / rate if rate > 0 else 0.0
        text = (
            f"{self.what} {self.done}/{self.total} ({self.errors} failed), {rate:.2f} {self.unit}/s,"
            f" ETA {eta:.0f} s"
        )
        decile = self.done * 10 // max(self.total, 1)
        if self.tty:
            self.stream.write("\r\x1b[K" + text + ("\n" if self.done == self.total else ""))
            self.stream.flush()
        elif decile != self._shown or self.done == self.total:
            self._shown = decile
            print(text, file=self.stream)


def _client(workers: int | None, scheduler: str | None, dashboard: bool) -> tuple[Any, Any]:
    try:
        from dask.distributed import Client, LocalCluster
    except ImportError as error:
        raise UsageError(f"mining needs the 'scale' extra (pip install -e '.[scale]'): {error}") from None
    if scheduler is not None:
        try:
            return Client(scheduler, timeout="30s"), None
        except (OSError, TimeoutError) as error:
            raise UsageError(f"--scheduler {scheduler}: cannot reach the Dask scheduler ({error})") from None
    n = workers if workers is not None else max(1, os.cpu_count() or 1)
    # the scheduler's HTTP server (health routes; the dashboard when asked) on a free port, never 8787
    cluster = LocalCluster(
        n_workers=n,
        threads_per_worker=1,
        processes=True,
        dashboard_address=":0" if dashboard else None,
        silence_logs=logging.ERROR,
        scheduler_kwargs={"dashboard_address": ":0"},
    )
    return Client(cluster), cluster


def _worker_error(rec: RecordingFile, error: BaseException) -> dict[str, Any]:
    first = (str(error).strip().splitlines() or [type(error).__name__])[0]
    return {
        "id": rec.id,
        "path": rec.path,
        "status": "error",
        "stage": "worker",
        "error": f"the task failed on its worker: {type(error).__name__}: {first}"[:500],
        "subs": [],
    }


def mine(
    recordings: Sequence[str],
    library: Sequence[str | Path],
    *,
    out: str | Path,
    scene: str | None = None,
    params: Any = None,
    compose: bool = False,
    workers: int | None = None,
    scheduler: str | None = None,
    dashboard: bool = False,
    progress: IO[str] | None = sys.stderr,
    note: Callable[[str], None] | None = None,
) -> MineResult:
    """Segment and match every recording against ``library`` (module doc); ``out`` is the job's
    folder (its table and summary page). ``workers``: processes of the embedded cluster (default:
    the machine's cores); ``scheduler``: the address of a running Dask scheduler instead."""
    from oacdsl.mining.summary import write_summary
    from oacdsl.pipeline.inputs import open_library

    if workers is not None and workers < 1:
        raise UsageError(f"--workers {workers}: at least 1")
    if workers is not None and scheduler is not None:
        raise UsageError("--workers starts a cluster of its own; --scheduler uses a running one: give one")
    t0 = time.perf_counter()
    files = expand_recordings(recordings)
    paths = [str(Path(p)) for p in library]
    open_library([Path(p) for p in paths])  # a library that does not compile fails here, once
    folder = Path(out)
    if folder.exists() and not folder.is_dir():
        raise InputError("not a folder: the job's output folder", location=str(folder))
    folder.mkdir(parents=True, exist_ok=True)
    spec = JobSpec(paths, scene, _params_dict(params), compose)
    with MineTable(folder / TABLE_NAME) as table:
        done = table.done_ids()
        todo = [r for r in files if r.id not in done]
        ticker = _Ticker(len(todo), progress)
        address = None
        rows: list[dict[str, Any]] = []
        if todo:
            client, cluster = _client(workers, scheduler, dashboard)
            try:
                if dashboard:
                    address = client.dashboard_link
                    if note is not None:
                        note(f"Dask dashboard: {address}")
                from dask.distributed import as_completed

                spec_future = client.scatter(spec, broadcast=True)
                futures = {
                    client.submit(analyse, r.path, r.id, spec_future, pure=False, key=f"mine-{r.id}"): r
                    for r in todo
                }
                for future in as_completed(futures):
                    rec = futures[future]
                    try:
                        row = future.result()
                    except Exception as error:  # the worker died (KilledWorker) or could not import
                        row = _worker_error(rec, error)
                    table.add(row)
                    rows.append(row)
                    ticker.tick(row["status"] != "ok")
            finally:
                client.close()
                if cluster is not None:
                    cluster.close()
        summary = write_summary(table, folder, library=paths)
    errors = sum(1 for r in rows if r["status"] != "ok")
    return MineResult(
        len(files),
        len(rows),
        len(files) - len(todo),
        errors,
        folder / TABLE_NAME,
        summary,
        address,
        time.perf_counter() - t0,
        rows,
    )
