"""The run store's file format: its marks, schema and migrations, and the row types.

:class:`~oacdsl.stats.store.RunStore` opens, checks and writes the file; this module
says what a sound one holds.
"""

from __future__ import annotations

import sqlite3
from collections.abc import Mapping
from dataclasses import dataclass, field
from datetime import datetime, timezone
from typing import Any

__all__ = [
    "APPLICATION_ID",
    "BUSY_TIMEOUT_MS",
    "REQUIRED",
    "SCHEMA_VERSION",
    "Outcome",
    "Fetched",
    "MIGRATIONS",
    "SCHEMA_V1",
    "SQLITE_MAGIC",
    "execute_script",
    "now_utc",
]

#: ``PRAGMA application_id`` of an oacdsl run store: the bytes "OACD".
APPLICATION_ID = 0x4F414344
#: ``PRAGMA user_version`` this code writes; older files are migrated, newer refused.
SCHEMA_VERSION = 2
#: How long a writer waits for another one's lock before giving up, milliseconds.
BUSY_TIMEOUT_MS = 30_000

#: The first bytes of every SQLite file.
SQLITE_MAGIC = b"SQLite format 3\x00"

#: The tables of a version-1 store (a new file is made so, then migrated).
SCHEMA_V1 = """
CREATE TABLE runs (
    run_id        TEXT PRIMARY KEY,
    time_utc      TEXT NOT NULL,
    oac           TEXT NOT NULL,
    success       INTEGER NOT NULL CHECK (success IN (0, 1)),
    recording     TEXT,
    seed          INTEGER,
    fidelity      REAL CHECK (fidelity IS NULL OR (fidelity >= 0 AND fidelity <= 1)),
    edit_distance INTEGER,
    command       TEXT
);
CREATE TABLE outcomes (
    run_id     TEXT NOT NULL REFERENCES runs(run_id) ON DELETE CASCADE,
    position   INTEGER NOT NULL,
    oac        TEXT NOT NULL,
    binding    TEXT NOT NULL,
    success    INTEGER NOT NULL CHECK (success IN (0, 1)),
    duration_s REAL,
    error      TEXT,
    PRIMARY KEY (run_id, position)
);
CREATE INDEX outcomes_by_oac ON outcomes(oac);
CREATE VIEW outcome_rows AS
    SELECT o.run_id, r.time_utc, o.position, o.oac, o.binding, o.success, o.duration_s, o.error,
           r.recording, r.seed, r.fidelity, r.edit_distance, r.command, r.rowid AS run_seq
    FROM outcomes AS o JOIN runs AS r USING (run_id);
"""

#: Version 2: what an adaptive run changed (issue 22), one row per adaptation, in order:
#: ``kind`` (skipped, replanned, followed, exchanged, failed), ``step`` (how many steps had run), ``text``,
#: ``plan`` (the repair's steps as a JSON list of labels, or NULL).
_ADAPTATIONS_V2 = """
CREATE TABLE adaptations (
    run_id   TEXT NOT NULL REFERENCES runs(run_id) ON DELETE CASCADE,
    position INTEGER NOT NULL,
    kind     TEXT NOT NULL,
    step     INTEGER,
    text     TEXT NOT NULL,
    plan     TEXT,
    PRIMARY KEY (run_id, position)
);
"""

#: The tables and views a run store has.
REQUIRED = frozenset({"runs", "outcomes", "outcome_rows", "adaptations"})

#: Migrations from version N to N+1 (a new file is made at version 1 and migrated).
MIGRATIONS: dict[int, str] = {1: _ADAPTATIONS_V2}


@dataclass(frozen=True)
class Outcome:
    """The outcome of executing one OAC with one binding (``duration_s`` in seconds)."""

    oac: str
    binding: Mapping[str, str] = field(default_factory=dict)
    success: bool = False
    duration_s: float | None = None
    error: str | None = None


@dataclass(frozen=True)
class Fetched:
    """A query's column description and rows, fetched while errors could still be caught."""

    description: Any
    rows: list[Any]

    def fetchall(self) -> list[Any]:
        return self.rows


def execute_script(conn: sqlite3.Connection, script: str) -> None:
    """Run ``;``-separated DDL inside the current transaction (``executescript`` would commit)."""
    for statement in script.split(";"):
        if statement.strip():
            conn.execute(statement)


def now_utc() -> str:
    """The time now, UTC, ISO 8601 to the millisecond with a Z."""
    return datetime.now(timezone.utc).isoformat(timespec="milliseconds").replace("+00:00", "Z")
