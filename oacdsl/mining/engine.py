"""Mining many recordings on Dask distributed: the client side of ``oacc mine``.

:func:`mine` expands the recordings, skips those the job's table already holds (a killed job
run again resumes), starts the cluster, parses the library once in the client while the
workers come up (a library that does not compile stops the job there, before anything is
written; the parsed library goes to the workers with the job's spec), and sends the
remaining recordings in batches (:func:`batches`; a task each,
:func:`oacdsl.mining.task.analyse_batch`) to the cluster: an embedded cluster of ``workers``
worker processes (one thread each, :mod:`oacdsl.mining.cluster`) by default, or the cluster of
a running ``dask scheduler`` at ``scheduler``. Results are written by the client alone, as
they arrive, one transaction per batch, so every recording's rows are in the table wholly or
not at all (:mod:`oacdsl.mining.table`); a task that dies with its worker makes an error row of
each of its recordings. At the end the summary page is written (:mod:`oacdsl.mining.summary`).
"""

from __future__ import annotations

import os
import sys
import time
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import IO, Any

from oacdsl.errors import InputError, UsageError
from oacdsl.mining.cluster import WORKER_WAIT_S, client_for, close, share, worker_count
from oacdsl.mining.inputs import RecordingFile, expand_recordings
from oacdsl.mining.table import TABLE_NAME, MineTable
from oacdsl.mining.task import PRELOAD, JobSpec, analyse_batch

__all__ = ["MAX_BATCH", "MineResult", "batches", "mine", "Ticker"]

#: Most recordings in one task (a killed job redoes at most this many per worker).
MAX_BATCH = 8
#: A task takes about 1/GUIDE of the recordings left per worker (guided self-scheduling).
GUIDE = 2


def batches(items: Sequence[Any], workers: int) -> list[list[Any]]:
    """``items`` cut into tasks, in order: each about the recordings still left over
    :data:`GUIDE` × ``workers``, from :data:`MAX_BATCH` down to 1. Large batches while much
    is left keep the scheduler's round trips few (each costs ~5 ms of CPU in the client and
    as much in a worker, against ~0.1 s per recording); single recordings at the end let the
    workers finish together instead of one waiting for the other's last large batch."""
    out, i = [], 0
    while i < len(items):
        size = min(MAX_BATCH, -(-(len(items) - i) // (GUIDE * max(1, workers))))
        out.append(list(items[i : i + size]))
        i += size
    return out


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


class Ticker:
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


def _not_done(files: list[RecordingFile], path: Path) -> list[RecordingFile]:
    """The recordings the table at ``path`` (if any) does not hold yet."""
    if not path.exists():
        return list(files)
    with MineTable(path) as table:
        done = table.done_ids()
    return [r for r in files if r.id not in done]


def _results(client: Any, spec: JobSpec, work: list[list[RecordingFile]]) -> Iterator[list[dict[str, Any]]]:
    """Each task's rows as it finishes (a task that died with its worker: an error row each)."""
    from dask.distributed import as_completed

    shared = share(client, spec, "mine-spec")
    futures = {
        client.submit(analyse_batch, [(r.path, r.id) for r in b], shared, pure=False,
                      key=f"mine-{b[0].id}-{len(b)}"): b
        for b in work
    }
    for future in as_completed(futures):
        try:
            yield future.result()
        except Exception as error:  # the worker died (KilledWorker) or could not import
            yield [_worker_error(rec, error) for rec in futures[future]]


def _check_makeable(folder: Path) -> None:
    """:class:`InputError` (exit 2) when ``folder`` cannot be made: the nearest existing path above
    it is a file, or a folder this process may not write in."""
    above = folder
    while not above.exists() and above.parent != above:
        above = above.parent
    if above == folder:
        return
    if not above.is_dir():
        raise InputError(f"cannot make the job's folder: {above} is not a folder", location=str(folder))
    if not os.access(above, os.W_OK | os.X_OK):
        raise InputError(f"cannot make the job's folder: {above} is not writable", location=str(folder))


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
    worker_wait_s: float = WORKER_WAIT_S,
    dashboard: bool = False,
    progress: IO[str] | None = sys.stderr,
    note: Callable[[str], None] | None = None,
) -> MineResult:
    """Segment and match every recording against ``library`` (module doc); ``out`` is the job's
    folder (its table and summary page). ``workers``: processes of the embedded cluster (default:
    the machine's cores); ``scheduler``: the address of a running Dask scheduler instead, whose
    first worker is awaited at most ``worker_wait_s`` seconds (a line on ``progress`` while
    waiting; :class:`UsageError` when none joins)."""
    from oacdsl.mining.summary import write_summary
    from oacdsl.pipeline.inputs import open_library

    if workers is not None and workers < 1:
        raise UsageError(f"--workers {workers}: at least 1")
    if workers is not None and scheduler is not None:
        raise UsageError("--workers starts a cluster of its own; --scheduler uses a running one: give one")
    t0 = time.perf_counter()
    files = expand_recordings(recordings)
    paths = [str(Path(p)) for p in library]
    folder = Path(out)
    if folder.exists() and not folder.is_dir():
        raise InputError("not a folder: the job's output folder", location=str(folder))
    _check_makeable(folder)  # before the cluster starts: a bad --out costs nothing
    todo = _not_done(files, folder / TABLE_NAME)
    ticker = Ticker(len(todo), progress)
    address = None
    rows: list[dict[str, Any]] = []
    # the cluster starts first: its workers come up while this process parses the library
    client, cluster = (
        client_for(workers, scheduler, dashboard, PRELOAD, worker_wait_s=worker_wait_s, progress=progress)
        if todo
        else (None, None)
    )
    try:
        parsed = open_library([Path(p) for p in paths])  # a library that does not compile fails here, once
        try:
            folder.mkdir(parents=True, exist_ok=True)
        except OSError as error:
            why = error.strerror or error
            raise InputError(f"cannot make the job's folder: {why}", location=str(folder)) from None
        spec = JobSpec(paths, scene, _params_dict(params), compose, parsed)
        with MineTable(folder / TABLE_NAME) as table:
            if client is not None:
                if dashboard:
                    address = client.dashboard_link
                    if note is not None:
                        note(f"Dask dashboard: {address}")
                size = worker_count(client, workers, scheduler)
                for done_rows in _results(client, spec, batches(todo, size)):
                    table.add_many(done_rows)
                    for row in done_rows:
                        rows.append(row)
                        ticker.tick(row["status"] != "ok")
                close(client, cluster)
                client = None
            summary = write_summary(table, folder, library=paths)
    finally:
        if client is not None:
            close(client, cluster)
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
