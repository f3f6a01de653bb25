"""References for ``benchmarks/mining.py``: what two processes reach on this machine without Dask.

:func:`plain_processes` runs the mining task function in processes forked from the benchmark,
a share of the recordings each, with the workers' malloc settings and no Dask, no table: the
most any job of that many processes can reach here. :func:`cores_alone_and_together` times a
pure-Python loop alone and in two processes at once: on cores that slow each other down (a
virtual machine's two CPUs on one physical core, a shared boost budget) every parallel job
pays that factor, whatever it does.
"""

from __future__ import annotations

import os
import pickle
import statistics
import time
from typing import Any

from oacdsl.mining.task import JobSpec, analyse

__all__ = ["cores_alone_and_together", "plain_processes"]


def plain_processes(files: list[Any], spec: JobSpec, k: int = 2) -> list[dict[str, Any]]:
    """The task function in ``k`` processes forked from this one (every k-th recording each,
    the workers' malloc settings), rows back through a pipe: no Dask, no table. What any job of
    ``k`` processes can reach here: on a machine whose cores slow each other down, less than k×."""
    from oacdsl.mining.forked import _steady_malloc

    children = []
    for i in range(k):
        reader, writer = os.pipe()
        pid = os.fork()
        if pid == 0:  # the child: analyse its share, send the rows' figures, exit without cleanup
            code = 1
            try:
                os.close(reader)
                _steady_malloc()
                rows = [analyse(f.path, f.id, spec) for f in files[i::k]]
                keep = ("status", "error", "cpu_s", "stage_cpu_s")
                with os.fdopen(writer, "wb") as out:
                    out.write(pickle.dumps([{key: row.get(key) for key in keep} for row in rows]))
                code = 0
            finally:
                os._exit(code)
        os.close(writer)
        children.append((pid, reader))
    rows = []
    for pid, reader in children:
        with os.fdopen(reader, "rb") as inp:
            data = inp.read()
        os.waitpid(pid, 0)
        if not data:
            raise SystemExit("a plain process failed")
        rows += pickle.loads(data)
    return rows


def _spin(n: int = 400_000) -> float:
    """CPU seconds of a pure-Python loop (no memory traffic to speak of)."""
    c0, s = time.process_time(), 0
    for i in range(n):
        s += i * i % 7
    return time.process_time() - c0


def cores_alone_and_together(rounds: int = 5) -> str:
    """The machine itself: a pure-Python loop's CPU alone, and in each of two processes at once."""
    alone, together = [], []
    for _ in range(rounds):
        alone.append(_spin())
        reader, writer = os.pipe()
        pids = []
        for _ in range(2):
            pid = os.fork()
            if pid == 0:
                os.write(writer, f"{_spin()!r}\n".encode())
                os._exit(0)
            pids.append(pid)
        for pid in pids:
            os.waitpid(pid, 0)
        os.close(writer)
        with os.fdopen(reader) as inp:
            together += [float(x) for x in inp.read().split()]
    a, t = statistics.median(alone), statistics.median(together)
    return (f"a pure-Python loop: {1000 * a:.0f} ms CPU alone, {1000 * t:.0f} ms in each of two processes at"
            f" once ({t / a:.2f}x)")
