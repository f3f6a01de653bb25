"""A running Dask scheduler that no worker joins: ``oacc mine`` / ``oacc run --seeds`` wait a
bounded time (``--worker-wait``), say so on stderr, then stop with one line and exit 2."""

from __future__ import annotations

import io
import threading
from pathlib import Path

import pytest

from oacdsl.cli import main
from oacdsl.errors import UsageError

distributed = pytest.importorskip("distributed", reason="mining needs the 'scale' extra")

ROOT = Path(__file__).resolve().parents[1]
LIBRARY = ROOT / "library"


@pytest.fixture
def empty_cluster():
    """A scheduler on 127.0.0.1 in this process, with no worker (none is ever started)."""
    cluster = distributed.LocalCluster(
        n_workers=0,
        processes=False,
        protocol="tcp",
        host="127.0.0.1",
        dashboard_address=None,
        silence_logs=50,
    )
    try:
        yield cluster
    finally:
        cluster.close()


@pytest.fixture
def recording(tmp_path) -> Path:
    folder = tmp_path / "recordings"
    folder.mkdir()
    (folder / "garbage.c3d").write_bytes(b"not a c3d file")
    return folder


def test_mine_stops_when_no_worker_joins_the_scheduler(empty_cluster, recording, tmp_path, capsys):
    out = tmp_path / "mined"
    address = empty_cluster.scheduler_address
    argv = ["mine", str(recording), "--library", str(LIBRARY), "--out", str(out), "--scheduler", address]
    assert main([*argv, "--worker-wait", "1.5"]) == 2
    err = capsys.readouterr().err
    assert f"oacc: waiting for a Dask worker to join {address}: 0 s of 1.5 s" in err
    assert f"oacc: error: --scheduler {address}: no Dask worker joined in 1.5 s" in err.splitlines()[-1]
    assert "Traceback" not in err
    assert not out.exists()  # nothing written


def test_run_seeds_stops_when_no_worker_joins_the_scheduler(empty_cluster, capsys):
    pytest.importorskip("mujoco", reason="the robot runtime needs the 'robot' extra (mujoco)")
    address = empty_cluster.scheduler_address
    argv = ["run", "grasp", "--library", str(LIBRARY), "--bind", "h=right_hand", "--bind", "o=green_cup"]
    assert main([*argv, "--seeds", "0:2", "--scheduler", address, "--worker-wait", "1", "--no-record"]) == 2
    err = capsys.readouterr().err
    assert "waiting for a Dask worker to join" in err
    assert err.splitlines()[-1].startswith(
        f"oacc: error: --scheduler {address}: no Dask worker joined in 1 s"
    )


def test_the_wait_ends_when_a_worker_joins(empty_cluster):
    from oacdsl.mining.cluster import client_for, close

    timer = threading.Timer(1.0, empty_cluster.scale, args=(1,))
    timer.start()
    progress = io.StringIO()
    try:
        client, cluster = client_for(
            None, empty_cluster.scheduler_address, False, worker_wait_s=60, progress=progress
        )
    finally:
        timer.join()
    try:
        assert cluster is None and len(client.nthreads()) == 1
        assert client.submit(sum, [1, 2, 3]).result(timeout=30) == 6
    finally:
        close(client, cluster)
    text = progress.getvalue()
    assert "waiting for a Dask worker to join" in text and "1 worker(s) joined" in text


def test_worker_wait_is_checked(empty_cluster, recording, tmp_path, capsys):
    from oacdsl.mining.cluster import client_for

    with pytest.raises(UsageError, match="--worker-wait 0: more than 0 seconds"):
        client_for(None, empty_cluster.scheduler_address, False, worker_wait_s=0)
    argv = [
        "mine",
        str(recording),
        "--library",
        str(LIBRARY),
        "--out",
        str(tmp_path / "m"),
        "--worker-wait",
        "5",
    ]
    assert main(argv) == 2
    assert "--worker-wait goes with --scheduler" in capsys.readouterr().err
