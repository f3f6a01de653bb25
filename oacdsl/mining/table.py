"""The mining table: one SQLite file, a row per recording and a row per sub-action.

Why SQLite and not Parquet: the job is resumable and written by one process (the client) as
results arrive. A recording's rows go in with one transaction, keyed by the recording's id, so a
job killed at any moment leaves each recording either wholly in the table or not at all, and a
second run skips what is there — nothing is counted twice, which appending Parquet files would
have to reconcile afterwards. SQLite is in the standard library; ``pandas.read_sql`` or the
``sqlite3`` shell read it as it is.

Tables: ``recordings(id PRIMARY KEY, path, status, stage, error, scene, rate_hz, frames,
duration_s, keyframes, sub_actions, explained, composed, worker, read_s, segment_s, match_s,
compose_s, finished_utc)`` and ``sub_actions(recording_id, idx, from_frame, to_frame, change,
class_change, oac, binding, draft, PRIMARY KEY (recording_id, idx))``.
"""

from __future__ import annotations

import json
import sqlite3
from collections.abc import Iterator
from datetime import datetime, timezone
from pathlib import Path
from typing import Any

from oacdsl.errors import InputError

__all__ = ["MineTable", "TABLE_NAME"]

#: The file name of the table in the job's output folder.
TABLE_NAME = "mine.sqlite3"

_SCHEMA = """
CREATE TABLE IF NOT EXISTS recordings (
    id TEXT PRIMARY KEY, path TEXT NOT NULL, status TEXT NOT NULL, stage TEXT, error TEXT,
    scene TEXT, rate_hz REAL, frames INTEGER, duration_s REAL, keyframes INTEGER,
    sub_actions INTEGER, explained INTEGER, composed TEXT, worker TEXT,
    read_s REAL, segment_s REAL, match_s REAL, compose_s REAL, finished_utc TEXT
);
CREATE TABLE IF NOT EXISTS sub_actions (
    recording_id TEXT NOT NULL REFERENCES recordings(id), idx INTEGER NOT NULL,
    from_frame INTEGER, to_frame INTEGER, change TEXT, class_change TEXT, oac TEXT, binding TEXT,
    draft TEXT, PRIMARY KEY (recording_id, idx)
);
"""

_COLUMNS = (
    "id",
    "path",
    "status",
    "stage",
    "error",
    "scene",
    "rate_hz",
    "frames",
    "duration_s",
    "keyframes",
    "sub_actions",
    "explained",
    "composed",
    "worker",
    "read_s",
    "segment_s",
    "match_s",
    "compose_s",
    "finished_utc",
)


class MineTable:
    """The table of one job (module doc); a context manager closing the connection."""

    def __init__(self, path: Path) -> None:
        self.path = path
        if path.exists() and not path.is_file():
            raise InputError("not a regular file: cannot hold the mining table", location=str(path))
        try:
            self._db = sqlite3.connect(path)
            self._db.executescript(_SCHEMA)
        except sqlite3.DatabaseError as error:
            raise InputError(f"not a mining table ({error})", location=str(path)) from None

    def __enter__(self) -> MineTable:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def close(self) -> None:
        self._db.close()

    def done_ids(self) -> set[str]:
        """The ids of the recordings already in the table."""
        return {r[0] for r in self._db.execute("SELECT id FROM recordings")}

    def add(self, row: dict[str, Any]) -> bool:
        """Insert one recording's rows (from :func:`oacdsl.mining.task.analyse`) in one transaction;
        False when the recording is there already (nothing written)."""
        return self.add_many([row]) == 1

    def add_many(self, rows: list[dict[str, Any]]) -> int:
        """Insert several recordings' rows in one transaction (one commit, not one per recording:
        each waits for the disk); a recording already there is left as it is. Returns how many
        recordings were added."""
        with self._db:
            return sum(self._insert(row) for row in rows)

    def _insert(self, row: dict[str, Any]) -> bool:
        subs = row.get("subs", [])
        times = row.get("times_s", {})
        values = {
            **{k: row.get(k) for k in _COLUMNS},
            "sub_actions": len(subs) if row["status"] == "ok" else None,
            "explained": sum(1 for s in subs if s["oac"] is not None) if row["status"] == "ok" else None,
            "read_s": times.get("read"),
            "segment_s": times.get("segment"),
            "match_s": times.get("match"),
            "compose_s": times.get("compose"),
            "finished_utc": datetime.now(timezone.utc).isoformat(timespec="seconds"),
        }
        cur = self._db.execute(
            f"INSERT OR IGNORE INTO recordings ({', '.join(_COLUMNS)})"
            f" VALUES ({', '.join('?' for _ in _COLUMNS)})",
            [values[k] for k in _COLUMNS],
        )
        if cur.rowcount == 0:
            return False
        self._db.executemany(
            "INSERT INTO sub_actions VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?)",
            [
                (
                    row["id"],
                    s["index"],
                    s["from_frame"],
                    s["to_frame"],
                    s["change"],
                    s["class_change"],
                    s["oac"],
                    json.dumps(s["binding"], sort_keys=True) if s["binding"] is not None else None,
                    s["draft"],
                )
                for s in subs
            ],
        )
        return True

    def recordings(self) -> list[dict[str, Any]]:
        """Every recording row, sorted by path."""
        cur = self._db.execute(f"SELECT {', '.join(_COLUMNS)} FROM recordings ORDER BY path, id")
        return [dict(zip(_COLUMNS, r, strict=True)) for r in cur]

    def sub_actions(self) -> Iterator[dict[str, Any]]:
        """Every sub-action row with its recording's path, sorted by path and index."""
        cur = self._db.execute(
            "SELECT r.path, s.idx, s.from_frame, s.to_frame, s.change, s.class_change, s.oac, s.binding,"
            " s.draft FROM sub_actions s JOIN recordings r ON r.id = s.recording_id ORDER BY r.path, s.idx"
        )
        names = (
            "path",
            "index",
            "from_frame",
            "to_frame",
            "change",
            "class_change",
            "oac",
            "binding",
            "draft",
        )
        for r in cur:
            yield dict(zip(names, r, strict=True))
