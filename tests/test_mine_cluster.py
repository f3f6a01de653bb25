"""The embedded Dask cluster of ``oacc mine`` / ``oacc run --seeds``: forked warm workers, their
settings, an orderly close, and the batches recordings go out in."""

from __future__ import annotations

import os
import sys
from pathlib import Path

import pytest

from oacdsl.mining.engine import MAX_BATCH, batches


def test_batches_shrink_from_the_largest_to_single_recordings():
    items = list(range(200))
    sizes = [len(b) for b in batches(items, 2)]
    assert [x for b in batches(items, 2) for x in b] == items  # all, once, in order
    assert sizes[0] == MAX_BATCH and sizes[-1] == 1
    assert sizes == sorted(sizes, reverse=True)
    assert len(sizes) < len(items) // 4  # few round trips
    assert [len(b) for b in batches(items[:5], 2)] == [2, 1, 1, 1]
    assert batches([], 2) == []
    assert [len(b) for b in batches(items[:3], 1)] == [2, 1]


def _prober():
    def probe(_: int) -> tuple[int, bool, bool, bool]:
        """In a worker: its parent's pid, whether ``wave`` (the preloaded module) is imported,
        whether Dask's profiler is on, whether arrays of a recording's size are made and freed
        again and again without page faults (the heap reused, not mapped afresh each time)."""
        import os
        import resource
        import sys

        import dask
        import numpy as np

        profile = bool(dask.config.get("distributed.worker.profile.enabled"))
        faults = 0
        for round_ in range(5):  # 6 arrays of 3 MiB each (~770 pages each when mapped afresh)
            before = resource.getrusage(resource.RUSAGE_THREAD).ru_minflt
            arrays = [np.ones((3 << 20) // 8) for _ in range(6)]
            del arrays
            if round_ > 0:  # the first round may grow the heap
                faults += resource.getrusage(resource.RUSAGE_THREAD).ru_minflt - before
        return os.getppid(), "wave" in sys.modules, profile, faults < 1000

    return probe  # a closure: shipped by value, so that a new process need not import this file


def _gone(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return True
    return False


@pytest.mark.slow
def test_workers_are_forked_warm_without_the_profiler_and_close_quietly(capfd):
    pytest.importorskip("distributed")
    from oacdsl.mining.cluster import client_for, close

    assert "wave" not in sys.modules  # imported by client_for, before the fork
    client, cluster = client_for(2, None, False, preload=("wave",))
    try:
        client.wait_for_workers(2, timeout=120)
        pids = {p: w for w, p in client.run(os.getpid).items()}
        results = client.gather([client.submit(_prober(), i, pure=False) for i in range(4)])
    finally:
        close(client, cluster)
    assert len(pids) == 2
    assert set(results) == {(os.getpid(), True, False, True)}  # children of this process, warm, no profiler
    assert all(_gone(pid) for pid in pids)  # closed and reaped
    out, err = capfd.readouterr()
    assert "Traceback" not in err + out and "CommClosedError" not in err + out and "Error" not in err


@pytest.mark.slow
def test_without_fork_the_workers_are_new_processes_with_the_same_settings(monkeypatch, capfd):
    pytest.importorskip("distributed")
    import oacdsl.mining.forked
    from oacdsl.mining.cluster import client_for, close

    monkeypatch.setattr(oacdsl.mining.forked, "can_fork", lambda: False)
    client, cluster = client_for(1, None, False, preload=("wave",))
    try:
        client.wait_for_workers(1, timeout=120)
        (result,) = client.gather([client.submit(_prober(), 0, pure=False)])
    finally:
        close(client, cluster)
    # a new process: nothing preloaded; its Dask settings from the environment
    assert result == (os.getpid(), False, False, True)
    _, err = capfd.readouterr()
    assert "Traceback" not in err


@pytest.mark.slow
def test_a_library_that_does_not_compile_stops_the_started_job_before_anything_is_written(tmp_path, capfd):
    pytest.importorskip("distributed")
    import multiprocessing

    from oacdsl.cli import main

    recordings = tmp_path / "recordings"
    recordings.mkdir()
    dough = Path(__file__).resolve().parents[1] / "data" / "dough.c3d"
    (recordings / "dough.c3d").write_bytes(dough.read_bytes())
    (tmp_path / "lib").mkdir()
    (tmp_path / "lib" / "x.oac").write_text("oac broken(\n", encoding="utf-8")
    out = tmp_path / "mined"
    argv = ["mine", str(recordings), "--library", str(tmp_path / "lib"), "--out", str(out), "--workers", "2"]
    assert main(argv) == 1
    _, err = capfd.readouterr()
    assert err.count("\n") == 1 and "x.oac:1:" in err and "error" in err
    assert not out.exists()
    assert multiprocessing.active_children() == []  # the workers that had started are gone
