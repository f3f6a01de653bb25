"""``oacc stats``: reliability per OAC from the run store."""

import json
import sqlite3

import pytest

from oacdsl.cli import main
from oacdsl.stats import Outcome, RunStore, wilson_interval


@pytest.fixture
def db(tmp_path):
    path = tmp_path / "runs.sqlite3"
    with RunStore(path) as store:
        for i in range(5):
            failed = i in (1, 3)
            store.record(
                Outcome("dough", {}, not failed, 10.0 + i, f"pour failed in run {i}" if failed else None),
                [Outcome("grasp", {"h": "left_hand", "o": "red_cup"}, True, 2.0),
                 Outcome("pour", {"h": "left_hand"}, not failed, 3.0 + i,
                         f"pour failed in run {i}" if failed else None)],
                seed=i,
            )
    return path


def test_table_shows_rates_intervals_medians_and_last_failure(db, capsys):
    assert main(["stats", "--db", str(db)]) == 0
    out = capsys.readouterr().out
    assert out.startswith(f"5 runs recorded in {db}")
    lines = {ln.split()[0]: ln for ln in out.splitlines()[2:]}
    assert set(lines) == {"OAC", "dough", "grasp", "pour"}
    lo, hi = wilson_interval(3, 5)
    assert f"{100 * lo:.0f} % – {100 * hi:.0f} %" in lines["pour"]
    assert "60 %" in lines["pour"] and "pour failed in run 3" in lines["pour"]
    assert "5.00 s" in lines["pour"]  # median of 3..7 s
    assert "100 %" in lines["grasp"] and lines["grasp"].rstrip().endswith("—")


def test_json_and_oac_filter(db, capsys):
    assert main(["stats", "--db", str(db), "--json", "--oac", "pour"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["db"] == str(db) and doc["runs"] == 5
    (pour,) = doc["oacs"]
    assert (pour["oac"], pour["runs"], pour["successes"]) == ("pour", 5, 3)
    assert pour["last_failure"] == "pour failed in run 3"
    assert (pour["ci_low"], pour["ci_high"]) == pytest.approx(wilson_interval(3, 5))


def test_unknown_oac_names_the_close_one(db, capsys):
    assert main(["stats", "--db", str(db), "--oac", "pur"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("oacc: error:") and "did you mean 'pour'" in err and len(err.splitlines()) == 1


def test_empty_or_missing_database_is_friendly_and_not_created(tmp_path, capsys):
    missing = tmp_path / "none.sqlite3"
    assert main(["stats", "--db", str(missing)]) == 0
    assert "No runs recorded yet" in capsys.readouterr().out
    assert not missing.exists()
    empty = tmp_path / "empty.sqlite3"
    RunStore(empty).close()
    assert main(["stats", "--db", str(empty), "--json"]) == 0
    assert json.loads(capsys.readouterr().out) == {"db": str(empty), "runs": 0, "oacs": [], "adaptations": []}


def test_env_var_chooses_the_database(db, monkeypatch, capsys):
    monkeypatch.setenv("OACDSL_DB", str(db))
    assert main(["stats", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["runs"] == 5


def test_foreign_file_is_a_one_line_error(tmp_path, capsys):
    other = tmp_path / "other.sqlite3"
    conn = sqlite3.connect(other)
    conn.execute("CREATE TABLE t (x)")
    conn.commit()
    conn.close()
    assert main(["stats", "--db", str(other)]) == 2
    err = capsys.readouterr().err
    assert "not an oacdsl run database" in err and len(err.splitlines()) == 1


def test_adaptations_are_counted_and_the_latest_listed(tmp_path, capsys):
    path = tmp_path / "runs.sqlite3"
    doc = {
        "oac": "dough", "success": True, "steps": [], "metrics": {"sim_time_s": 30.0},
        "adaptations": [
            {"kind": "skipped", "step": 0, "text": "skipped pour(left_hand, red_cup, liquid_one, bowl)"},
            {"kind": "replanned", "step": 2,
             "text": "replanned after step 2 grasp(right_hand, green_cup) failed",
             "plan": ["grasp(left_hand, green_cup)"]},
        ],
    }
    with RunStore(path) as store:
        store.record_run_json(doc)
        store.record_run_json({**doc, "adaptations": doc["adaptations"][:1]})
    assert main(["stats", "--db", str(path)]) == 0
    out = capsys.readouterr().out
    assert "Adaptations of adaptive runs (3 in 2 runs): 1 replanned, 2 skipped" in out
    line = "dough  replanned after step 2 grasp(right_hand, green_cup) failed → grasp(left_hand, green_cup)"
    assert line in out
    assert main(["stats", "--db", str(path), "--json"]) == 0
    adapted = json.loads(capsys.readouterr().out)["adaptations"]
    assert [a["kind"] for a in adapted] == ["skipped", "replanned", "skipped"]
    assert adapted[1]["plan"] == ["grasp(left_hand, green_cup)"]
