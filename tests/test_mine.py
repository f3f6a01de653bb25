"""``oacc mine``: many recordings segmented and matched on Dask; errors as rows; resumable."""

from __future__ import annotations

import json
import socket
import sqlite3
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from oacdsl.cli import main
from oacdsl.errors import UsageError
from oacdsl.mining.inputs import expand_recordings
from oacdsl.mining.table import MineTable
from oacdsl.mining.task import JobSpec, analyse
from oacdsl.segmentation.readers import read_recording, write_c3d
from oacdsl.segmentation.recording import Recording

ROOT = Path(__file__).resolve().parents[1]
DOUGH = ROOT / "data" / "dough.c3d"
LIBRARY = ROOT / "library"
STEPS = ["grasp", "pour", "place", "grasp", "pour", "place", "grasp", "mix"]


def _variant(rec: Recording, k: int) -> Recording:
    """Take ``k`` of the bundled demonstration: moved k·7 cm along x and turned k·30° about z."""
    a = np.deg2rad(30.0 * k)
    rot = np.array([[np.cos(a), -np.sin(a), 0.0], [np.sin(a), np.cos(a), 0.0], [0.0, 0.0, 1.0]])
    pos = rec.positions_m @ rot.T + [0.07 * k, 0.0, 0.0]
    return Recording(f"take{k}", rec.rate_hz, rec.times_s, rec.marker_names, pos, dict(rec.groups))


@pytest.fixture(scope="module")
def folder(tmp_path_factory) -> Path:
    """50 takes of the dough demonstration and 3 broken files."""
    out = tmp_path_factory.mktemp("recordings")
    rec = read_recording(DOUGH)
    for k in range(50):
        write_c3d(_variant(rec, k), out / f"take_{k:02d}.c3d")
    (out / "garbage.c3d").write_bytes(b"not a c3d file at all")
    (out / "empty.tsv").write_text("", encoding="utf-8")
    data = (out / "take_00.c3d").read_bytes()
    (out / "truncated.c3d").write_bytes(data[: len(data) // 3])
    return out


def _rows(db: Path) -> list[tuple]:
    with sqlite3.connect(db) as con:
        recs = con.execute(
            "SELECT path, status, stage, error, keyframes, sub_actions, explained FROM recordings"
            " ORDER BY path"
        ).fetchall()
        subs = con.execute(
            "SELECT r.path, s.idx, s.change, s.oac, s.binding FROM sub_actions s JOIN recordings r"
            " ON r.id = s.recording_id ORDER BY r.path, s.idx"
        ).fetchall()
    return recs + subs


def test_expand_recordings(tmp_path):
    (tmp_path / "a.c3d").write_bytes(b"x")
    (tmp_path / "sub").mkdir()
    (tmp_path / "sub" / "b.TSV").write_text("x", encoding="utf-8")
    (tmp_path / "sub" / "c.labels.csv").write_text("x", encoding="utf-8")  # KIT side files: not recordings
    (tmp_path / "notes.txt").write_text("x", encoding="utf-8")
    found = expand_recordings([str(tmp_path), str(tmp_path / "a.c3d"), str(tmp_path / "*.c3d")])
    assert [Path(f.path).name for f in found] == ["a.c3d", "b.TSV"]
    assert len({f.id for f in found}) == 2
    with pytest.raises(UsageError, match="nowhere: no such file or folder"):
        expand_recordings(["nowhere"])
    with pytest.raises(UsageError, match=r"\*.mp4: no file matches"):
        expand_recordings([str(tmp_path / "*.mp4")])


def test_a_task_never_raises_and_a_table_takes_a_recording_once(tmp_path):
    spec = JobSpec([str(LIBRARY)], None, {}, compose=True)
    bad = tmp_path / "bad.c3d"
    bad.write_bytes(b"nope")
    row = analyse(str(bad), "bad", spec)
    assert (row["status"], row["stage"]) == ("error", "read") and "bad.c3d" in row["error"]
    good = analyse(str(DOUGH), "dough", spec)
    assert good["status"] == "ok", good["error"]
    assert [s["oac"] for s in good["subs"]] == STEPS
    assert "oac dough(" in good["composed"]
    # each stage's wall and thread CPU seconds (the CPU for benchmarks: not in the table)
    assert list(good["stage_cpu_s"]) == list(good["times_s"]) == ["read", "segment", "match", "compose"]
    assert 0 < sum(good["stage_cpu_s"].values()) <= good["cpu_s"] + 0.01
    with MineTable(tmp_path / "t.sqlite3") as table:
        assert table.add(good) and table.add(row)
        assert not table.add(good)  # the same recording again: nothing is counted twice
        assert table.done_ids() == {"bad", "dough"}
        assert len(list(table.sub_actions())) == 8


def test_unexplained_sub_actions_get_a_drafted_oac(tmp_path):
    from oacdsl.mining.summary import summarise

    lib = tmp_path / "lib"
    lib.mkdir()
    text = (LIBRARY / "actions.oac").read_text(encoding="utf-8")
    start = text.index("oac mix(")  # the library without its mix OAC
    (lib / "actions.oac").write_text(text[:start] + text[text.index("\n}\n", start) + 3 :], encoding="utf-8")
    for f in ("classes.oac", "kitchen.oac", "wiping.oac"):
        (lib / f).write_text((LIBRARY / f).read_text(encoding="utf-8"), encoding="utf-8")
    row = analyse(str(DOUGH), "dough", JobSpec([str(lib)], None, {}, compose=False))
    assert row["status"] == "ok", row["error"]
    with MineTable(tmp_path / "t.sqlite3") as table:
        table.add(row)
        doc = summarise(table)
    (group,) = doc["unexplained"]
    assert group["count"] == 1 and group["change"] == "+ Bowl <-> Mixer"
    assert "effect  mixer <-> bowl" in group["draft"] and "execute TODO" in group["draft"]
    assert {o["oac"]: o["sub_actions"] for o in doc["oacs"]} == {"grasp": 3, "pour": 2, "place": 2}


def test_a_recording_mined_and_composed_gives_the_same_matches_and_oac(tmp_path, capsys):
    """Mining matches as oacc compose does, with the demonstration's motion: the synthetic Peel
    against the KIT library's generic OACs (no peel OAC) ties touch(left_hand, cucumber, peeler)
    with touch(right_hand, peeler, cucumber); the world states cannot tell which hand moved, the
    motion can (the right one). Without the motion mining chose the left hand."""
    sys.path.insert(0, str(ROOT / "tests"))
    import _task_demos as demos

    text = (LIBRARY / "examples" / "peel.oac").read_text(encoding="utf-8")
    scene = tmp_path / "peeling.oac"  # its classes and scene, without its peel OACs
    scene.write_text(text[: text.index("# Peel the cucumber")], encoding="utf-8")
    libraries = [str(LIBRARY / "kit"), str(scene)]
    clip = demos.write("Peel", tmp_path)
    row = analyse(str(clip), "peel", JobSpec(libraries, None, {}, compose=True))
    assert row["status"] == "ok", row["error"]
    mined = [(s["oac"], s["binding"]) for s in row["subs"]]
    out = tmp_path / "composed.oac"
    argv = ["compose", str(clip), "--name", "synthetic_peel", "-o", str(out), "--json"]
    assert main([*argv, *(a for lib in libraries for a in ("--library", lib))]) == 0
    composed = [(s["oac"], s["binding"]) for s in json.loads(capsys.readouterr().out)["steps"]]
    assert mined == composed
    assert mined[-1] == ("touch", {"h": "right_hand", "o": "peeler", "t": "cucumber"})
    written = out.read_text(encoding="utf-8")
    assert row["composed"] == written[written.index("oac synthetic_peel("):]  # the same OAC, its tilt too


@pytest.mark.slow
def test_a_local_cluster_mines_50_recordings_and_3_broken_files(folder, tmp_path, capsys):
    out = tmp_path / "mined"
    assert main(["mine", str(folder), "--library", str(LIBRARY), "--out", str(out), "--workers", "2"]) == 0
    stdout = capsys.readouterr().out
    assert "53 recordings: 53 analysed now (3 could not be), 0 done before" in stdout
    with MineTable(out / "mine.sqlite3") as table:
        recs = table.recordings()
        workers = {r["worker"] for r in recs}
    assert len(workers) == 2  # two worker processes did the work
    ok = [r for r in recs if r["status"] == "ok"]
    assert len(ok) == 50 and all(r["explained"] == r["sub_actions"] == 8 for r in ok)
    assert sorted(Path(r["path"]).name for r in recs if r["status"] == "error") == [
        "empty.tsv",
        "garbage.c3d",
        "truncated.c3d",
    ]
    page = (out / "summary.html").read_text(encoding="utf-8")
    assert "Mining 53 recordings" in page and "garbage.c3d" in page and "<td>grasp<td class=n>150" in page
    # run again: everything is done, nothing is redone
    assert main(["mine", str(folder), "--library", str(LIBRARY), "--out", str(out), "--workers", "2"]) == 0
    assert "53 recordings: 0 analysed now (0 could not be), 53 done before" in capsys.readouterr().out
    test_a_local_cluster_mines_50_recordings_and_3_broken_files.rows = _rows(out / "mine.sqlite3")


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


@pytest.mark.slow
def test_a_running_scheduler_and_two_workers_give_the_same_table(folder, tmp_path):
    port = _free_port()
    address = f"tcp://127.0.0.1:{port}"
    bindir = Path(sys.executable).parent
    procs = [
        subprocess.Popen(
            [str(bindir / "dask"), "scheduler", "--host", "127.0.0.1", "--port", str(port), "--no-dashboard"],
            stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL,
        )
    ]
    try:
        deadline = time.monotonic() + 120  # the scheduler listens (slow on a busy machine)
        while time.monotonic() < deadline:
            with socket.socket() as s:
                if s.connect_ex(("127.0.0.1", port)) == 0:
                    break
            time.sleep(0.2)
        procs += [
            subprocess.Popen(
                [str(bindir / "dask"), "worker", address, "--nthreads", "1", "--no-dashboard"],
                stdout=subprocess.DEVNULL,
                stderr=subprocess.DEVNULL,
            )
            for _ in range(2)
        ]
        out = tmp_path / "mined"
        code = main(
            ["mine", str(folder), "--library", str(LIBRARY), "--out", str(out), "--scheduler", address]
        )
        assert code == 0
        local = tmp_path / "local"
        assert (
            main(["mine", str(folder), "--library", str(LIBRARY), "--out", str(local), "--workers", "2"]) == 0
        )
        assert _rows(out / "mine.sqlite3") == _rows(local / "mine.sqlite3")
        assert len(_rows(out / "mine.sqlite3")) == 53 + 50 * 8
    finally:
        for p in procs:
            p.terminate()
        for p in procs:
            p.wait(timeout=30)


@pytest.mark.slow
def test_a_job_killed_half_way_resumes_without_duplicates(folder, tmp_path):
    out = tmp_path / "mined"
    cmd = [
        sys.executable,
        "-m",
        "oacdsl",
        "mine",
        str(folder),
        "--library",
        str(LIBRARY),
        "--out",
        str(out),
        "--workers",
        "2",
    ]
    proc = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, start_new_session=True)
    db = out / "mine.sqlite3"
    deadline = time.monotonic() + 240
    done = 0
    while time.monotonic() < deadline and proc.poll() is None:
        if db.exists():
            try:
                with sqlite3.connect(db) as con:
                    done = con.execute("SELECT count(*) FROM recordings").fetchone()[0]
            except sqlite3.OperationalError:
                done = 0
            if done >= 10:
                break
        time.sleep(0.2)
    import os
    import signal

    os.killpg(proc.pid, signal.SIGKILL)  # the client and its cluster, at once
    proc.wait(timeout=30)
    assert 10 <= done < 53
    result = subprocess.run(cmd, capture_output=True, text=True, timeout=600)
    assert result.returncode == 0, result.stderr
    with sqlite3.connect(db) as con:
        ids = [r[0] for r in con.execute("SELECT id FROM recordings")]
        subs = con.execute(
            "SELECT count(*), count(DISTINCT recording_id || '/' || idx) FROM sub_actions"
        ).fetchone()
    assert len(ids) == len(set(ids)) == 53
    assert subs[0] == subs[1] == 50 * 8
    assert "done before" in result.stdout and "53 recordings" in result.stdout


@pytest.mark.slow
def test_many_runs_on_two_workers_equal_sequential_runs_and_reach_the_store(tmp_path, capsys):
    pytest.importorskip("mujoco", reason="the robot runtime needs the 'robot' extra (mujoco)")
    from oacdsl.mining.runs import RunSpec, run_one

    db = tmp_path / "runs.sqlite3"
    argv = [
        "run",
        "grasp",
        "--library",
        str(LIBRARY),
        "--bind",
        "h=right_hand",
        "--bind",
        "o=green_cup",
        "--seeds",
        "0:2",
        "--place-samples",
        "2",
        "--workers",
        "2",
        "--db",
        str(db),
        "--json",
    ]
    assert main(argv) == 0
    import json

    docs = json.loads(capsys.readouterr().out)
    assert [(d["seed"], d["sample"]) for d in docs] == [(0, 0), (0, 1), (1, 0), (1, 1)]
    assert docs[0]["places"] == {} and set(docs[1]["places"]) >= {"green_cup"}
    spec = RunSpec([str(LIBRARY)], "grasp", {"h": "right_hand", "o": "green_cup"}, None)

    def outcome(d):
        return [(s["oac"], s["success"], s["observed"]) for s in d["steps"]], d["success"]

    for d in docs:  # the same run in this process, one after the other
        assert outcome(run_one(spec, d["seed"], d["sample"])) == outcome(d)
    assert main(["stats", "--db", str(db), "--json"]) == 0
    stats = json.loads(capsys.readouterr().out)
    assert stats["runs"] == 4 and stats["oacs"][0]["runs"] == 4


def test_many_runs_options_are_checked(capsys):
    from oacdsl.cli import main as oacc

    assert oacc(["run", "grasp", "--library", str(LIBRARY), "--workers", "2"]) == 2
    err = capsys.readouterr().err
    assert "--workers, --scheduler, --worker-wait and --place-samples go with --seeds A:B" in err
    with pytest.raises(SystemExit):
        oacc(["run", "grasp", "--seeds", "5:5"])
    assert "expected A:B, whole numbers with 0 <= A < B" in capsys.readouterr().err
    assert oacc(["run", "grasp", "--library", str(LIBRARY), "--seeds", "0:2", "--seed", "3"]) == 2
    assert "--seed and --seeds: give one" in capsys.readouterr().err


def test_an_out_folder_that_cannot_be_made_stops_the_job_before_it_starts(tmp_path, capsys):
    (tmp_path / "a.c3d").write_bytes(b"not a c3d file")
    (tmp_path / "afile").write_text("a file, not a folder", encoding="utf-8")
    out = tmp_path / "afile" / "sub" / "mined"
    assert main(["mine", str(tmp_path / "a.c3d"), "--library", str(LIBRARY), "--out", str(out)]) == 2
    err = capsys.readouterr().err
    why = f"cannot make the job's folder: {tmp_path / 'afile'} is not a folder"
    assert err.splitlines() == [f"oacc: error: {out}: {why}"]
