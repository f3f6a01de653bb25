"""The run store: schema, paths, refusal of foreign files, concurrency and crash safety."""

import json
import os
import signal
import sqlite3
import subprocess
import sys
import time
from pathlib import Path

import pytest

from oacdsl.errors import StoreError
from oacdsl.stats import (
    APPLICATION_ID,
    SCHEMA_VERSION,
    Outcome,
    RunStore,
    default_db_path,
    resolve_db_path,
    summarise,
    wilson_interval,
)

ROOT = Path(__file__).resolve().parents[1]

# A child process that records runs of `steps` outcomes each, printing each run id once committed.
WRITER = """
import sys
from oacdsl.stats import Outcome, RunStore
path, tag, count, steps = sys.argv[1], sys.argv[2], int(sys.argv[3]), int(sys.argv[4])
with RunStore(path) as store:
    i = 0
    while count < 0 or i < count:
        run = Outcome("dough", {}, i % 3 != 0, 1.5, None if i % 3 else "pour: balls spilled")
        rows = [Outcome("grasp", {"h": "left_hand", "o": f"cup{k}"}, True, 0.5) for k in range(steps)]
        rid = store.record(run, rows, recording="dough.c3d", seed=i, run_id=f"{tag}-{i}")
        print(rid, flush=True)
        i += 1
"""


def _writer(path, tag, count, steps):
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    return subprocess.Popen(
        [sys.executable, "-c", WRITER, str(path), tag, str(count), str(steps)],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env, cwd=ROOT,
    )


def test_record_and_read_back(tmp_path):
    db = tmp_path / "sub" / "runs.sqlite3"
    with RunStore(db) as store:
        rid = store.record(
            Outcome("dough", {"h": "left_hand"}, True, 12.5),
            [Outcome("grasp", {"h": "left_hand", "o": "red_cup"}, True, 2.0),
             Outcome("pour", {"h": "left_hand"}, False, 3.0, "only 40 % of the balls in the bowl")],
            recording="dough.c3d", seed=7, fidelity=0.75, edit_distance=1, command="reproduce",
        )
        rows = store.rows()
        assert [r["oac"] for r in rows] == ["dough", "grasp", "pour"]
        assert all(r["run_id"] == rid and r["seed"] == 7 and r["recording"] == "dough.c3d" for r in rows)
        assert rows[1]["binding"] == {"h": "left_hand", "o": "red_cup"}
        assert rows[2]["success"] is False and rows[2]["error"].startswith("only 40")
        assert rows[0]["fidelity"] == 0.75 and rows[0]["edit_distance"] == 1
        assert store.oac_names() == ["dough", "grasp", "pour"]
        assert store.rows("pour")[0]["duration_s"] == 3.0
    conn = sqlite3.connect(db)
    assert conn.execute("PRAGMA application_id").fetchone()[0] == APPLICATION_ID
    assert conn.execute("PRAGMA user_version").fetchone()[0] == SCHEMA_VERSION
    assert conn.execute("PRAGMA journal_mode").fetchone()[0] == "wal"
    conn.close()


def test_fidelity_out_of_range_is_refused(tmp_path):
    with RunStore(tmp_path / "r.db") as store, pytest.raises(ValueError, match="fidelity"):
        store.record(Outcome("grasp", success=True), fidelity=1.5)


def test_record_run_json_stores_steps_and_deduplicates_primitive_runs(tmp_path):
    composed = {
        "oac": "dough", "success": False,
        "steps": [
            {"oac": "grasp", "binding": {"h": "left_hand", "o": "red_cup"}, "success": True,
             "duration_s": 2.0, "predicted": [], "observed": [], "error": None},
            {"oac": "pour", "binding": {"h": "left_hand"}, "success": False, "duration_s": 4.0,
             "predicted": [], "observed": [], "error": "balls spilled"},
        ],
        "metrics": {"balls_total": 10, "balls_in_bowl": 3, "sim_time_s": 6.5, "wall_time_s": 1.0},
    }
    primitive = {"oac": "grasp", "success": True,
                 "steps": [{"oac": "grasp", "binding": {"h": "right_hand", "o": "mixer"}, "success": True,
                            "duration_s": 1.25, "error": None}],
                 "metrics": {"sim_time_s": 1.5}}
    with RunStore(tmp_path / "r.db") as store:
        store.record_run_json(composed, seed=3)
        store.record_run_json(primitive)
        rows = store.rows()
    expected = [("dough", 0), ("grasp", 1), ("pour", 2), ("grasp", 0)]
    assert [(r["oac"], r["position"]) for r in rows] == expected
    assert rows[0]["duration_s"] == 6.5 and rows[0]["error"] == "balls spilled" and rows[0]["seed"] == 3
    assert rows[3]["binding"] == {"h": "right_hand", "o": "mixer"} and rows[3]["duration_s"] == 1.25


def test_default_path_follows_env_and_xdg(tmp_path, monkeypatch):
    assert default_db_path({"OACDSL_DB": "~/x.db"}) == Path.home() / "x.db"
    assert default_db_path({"XDG_DATA_HOME": "/data"}) == Path("/data/oacdsl/runs.sqlite3")
    assert default_db_path({"XDG_DATA_HOME": "relative"}) == Path.home() / ".local/share/oacdsl/runs.sqlite3"
    assert default_db_path({}) == Path.home() / ".local/share/oacdsl/runs.sqlite3"
    assert resolve_db_path("a.db", {"OACDSL_DB": "b.db"}) == Path("a.db")
    monkeypatch.setenv("OACDSL_DB", str(tmp_path / "env.db"))
    assert resolve_db_path(None) == tmp_path / "env.db"


def test_foreign_files_are_refused_untouched(tmp_path):
    text = tmp_path / "notes.txt"
    text.write_text("hello, not a database\n")
    with pytest.raises(StoreError, match="not an oacdsl run database"):
        RunStore(text)
    assert text.read_text() == "hello, not a database\n"

    other = tmp_path / "other.sqlite"
    conn = sqlite3.connect(other)
    conn.execute("CREATE TABLE t (x)")
    conn.commit()
    conn.close()
    with pytest.raises(StoreError, match="SQLite database but not an oacdsl"):
        RunStore(other)

    with pytest.raises(StoreError, match="is a directory"):
        RunStore(tmp_path)


def test_newer_schema_is_refused(tmp_path):
    db = tmp_path / "r.db"
    RunStore(db).close()
    conn = sqlite3.connect(db)
    conn.execute(f"PRAGMA user_version = {SCHEMA_VERSION + 1}")
    conn.commit()
    conn.close()
    with pytest.raises(StoreError, match=rf"newer oacdsl \(schema version {SCHEMA_VERSION + 1}"):
        RunStore(db)


def test_missing_file_is_not_created_when_reading(tmp_path):
    with pytest.raises(StoreError, match="no run database"):
        RunStore(tmp_path / "absent.db", create=False)
    assert not (tmp_path / "absent.db").exists()


def test_empty_file_is_initialised(tmp_path):
    db = tmp_path / "empty.db"
    db.touch()
    with RunStore(db) as store:
        assert store.run_count() == 0 and store.integrity() == "ok"


def test_concurrent_writers_lose_nothing(tmp_path):
    db = tmp_path / "runs.db"
    procs = [_writer(db, f"w{k}", 25, 8) for k in range(3)]
    for p in procs:
        out, err = p.communicate(timeout=120)
        assert p.returncode == 0, err
        assert len(out.split()) == 25
    with RunStore(db) as store:
        assert store.integrity() == "ok"
        assert store.run_count() == 75
        rows = store.rows()
    assert len(rows) == 75 * 9
    assert {r["run_id"] for r in rows} == {f"w{k}-{i}" for k in range(3) for i in range(25)}


@pytest.mark.parametrize("after_runs", [2, 5, 11])
def test_killed_writer_leaves_a_sound_store_with_every_committed_run(tmp_path, after_runs):
    db = tmp_path / "runs.db"
    proc = _writer(db, "k", -1, 3000)  # large runs: the kill most likely lands inside a transaction
    committed = []
    assert proc.stdout is not None
    while len(committed) < after_runs:
        line = proc.stdout.readline()
        assert line, proc.stderr.read() if proc.stderr else "writer died"
        committed.append(line.strip())
    time.sleep(0.013 * after_runs)
    proc.send_signal(signal.SIGKILL)
    proc.wait(timeout=30)
    committed += [ln.strip() for ln in proc.stdout.read().split()]
    with RunStore(db) as store:
        assert store.integrity() == "ok"
        rows = store.rows()
        per_run: dict[str, int] = {}
        for r in rows:
            per_run[r["run_id"]] = per_run.get(r["run_id"], 0) + 1
        assert set(committed) <= set(per_run)
        assert all(n == 3001 for n in per_run.values())  # no half-written run
        store.record(Outcome("grasp", success=True))  # and it is still writable
        assert store.run_count() == len(per_run) + 1


def test_wilson_interval_known_values():
    assert wilson_interval(0, 0) == (0.0, 1.0)
    lo, hi = wilson_interval(5, 10)
    assert lo == pytest.approx(0.2366, abs=1e-4) and hi == pytest.approx(0.7634, abs=1e-4)
    lo, hi = wilson_interval(10, 10)
    assert lo == pytest.approx(0.7225, abs=1e-4) and hi == 1.0
    lo, hi = wilson_interval(0, 10)
    assert lo == 0.0 and hi == pytest.approx(0.2775, abs=1e-4)
    with pytest.raises(ValueError):
        wilson_interval(3, 2)


def test_summarise_counts_rates_medians_and_last_failure():
    rows = [
        {"oac": "pour", "success": True, "duration_s": 3.0, "error": None, "time_utc": "t1"},
        {"oac": "pour", "success": False, "duration_s": 5.0, "error": "spilled", "time_utc": "t2"},
        {"oac": "grasp", "success": True, "duration_s": None, "error": None, "time_utc": "t3"},
        {"oac": "pour", "success": False, "duration_s": 4.0, "error": None, "time_utc": "t4"},
        {"oac": "pour", "success": True, "duration_s": 1.0, "error": None, "time_utc": "t5"},
    ]
    grasp, pour = summarise(rows)
    assert (grasp.oac, grasp.runs, grasp.successes, grasp.median_duration_s) == ("grasp", 1, 1, None)
    assert grasp.last_failure is None
    assert (pour.runs, pour.successes, pour.rate) == (4, 2, 0.5)
    assert pour.median_duration_s == 3.5
    assert (pour.last_failure_utc, pour.last_failure) == ("t4", "failed (no reason recorded)")
    assert pour.last_run_utc == "t5"
    assert (pour.ci_low, pour.ci_high) == wilson_interval(2, 4)
    assert json.loads(json.dumps(pour.to_json()))["oac"] == "pour"


ADAPTED = {
    "oac": "dough",
    "success": True,
    "steps": [
        {"oac": "grasp", "binding": {"h": "right_hand", "o": "red_cup"}, "success": True, "duration_s": 2.0}
    ],
    "metrics": {"sim_time_s": 30.0},
    "adaptations": [
        {"kind": "skipped", "step": 0, "text": "skipped pour(left_hand, red_cup, liquid_one, orange_bowl)"},
        {"kind": "replanned", "step": 1,
         "text": "grasp(left_hand, red_cup): red_cup is out of left_hand's reach",
         "plan": ["grasp(right_hand, red_cup)", "pour(right_hand, red_cup, liquid_one, orange_bowl)"]},
    ],
}


def test_an_adaptive_runs_adaptations_are_stored_in_order(tmp_path):
    with RunStore(tmp_path / "runs.sqlite3") as store:
        rid = store.record_run_json(ADAPTED, seed=3, command="run")
        store.record_run_json({**ADAPTED, "oac": "other", "adaptations": []})
        rows = store.adaptations()
        assert [(r["run_id"], r["oac"], r["position"], r["kind"], r["step"]) for r in rows] == [
            (rid, "dough", 0, "skipped", 0), (rid, "dough", 1, "replanned", 1)]
        assert rows[0]["plan"] is None and rows[1]["plan"] == ADAPTED["adaptations"][1]["plan"]
        assert rows[1]["text"].endswith("out of left_hand's reach") and rows[1]["time_utc"]
        assert store.adaptations("other") == [] and len(store.adaptations("dough")) == 2


def test_a_version_1_store_gets_the_adaptations_table_and_keeps_its_runs(tmp_path):
    from oacdsl.stats.schema import SCHEMA_V1

    path = tmp_path / "old.sqlite3"
    conn = sqlite3.connect(path)
    conn.executescript(SCHEMA_V1)
    conn.execute(f"PRAGMA application_id = {APPLICATION_ID}")
    conn.execute("PRAGMA user_version = 1")
    conn.execute(
        "INSERT INTO runs (run_id, time_utc, oac, success) VALUES ('old', '2026-01-01T00:00:00Z', 'dough', 1)"
    )
    conn.commit()
    conn.close()
    with RunStore(path, create=False) as store:
        assert store.run_count() == 1 and store.adaptations() == []
        store.record_run_json(ADAPTED)
        assert len(store.adaptations()) == 2
    conn = sqlite3.connect(path)
    assert conn.execute("PRAGMA user_version").fetchone()[0] == SCHEMA_VERSION == 2
    conn.close()
