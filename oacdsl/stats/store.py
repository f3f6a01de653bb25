"""The run store: an embedded SQLite database of the outcome of every OAC execution.

Krüger's OAC is a triple (execution, prediction, success measure); the store
keeps the measurements behind the third element. One *run* (an ``oacc run`` or
``oacc reproduce``) executes one OAC; a composed OAC's steps are OACs too, and
every one of them gets an *outcome* row: success, duration, error, binding.

Safety: WAL journal, ``busy_timeout``, and each run written in one short
``BEGIN IMMEDIATE`` transaction, so concurrent writers wait for each other
instead of failing, and a process killed mid-write leaves either the whole run
or none of it. The file is marked with ``PRAGMA application_id`` and versioned
with ``PRAGMA user_version``; a foreign or newer file is refused with a clear
message instead of being touched.
"""

from __future__ import annotations

import json
import os
import sqlite3
import uuid
from collections.abc import Iterator, Mapping, Sequence
from contextlib import contextmanager
from pathlib import Path
from typing import Any
from urllib.parse import quote

from oacdsl.errors import StoreError
from oacdsl.stats.adapted import decoded, rows_of
from oacdsl.stats.paths import ENV_VAR
from oacdsl.stats.schema import (
    APPLICATION_ID,
    BUSY_TIMEOUT_MS,
    MIGRATIONS,
    REQUIRED,
    SCHEMA_V1,
    SCHEMA_VERSION,
    SQLITE_MAGIC,
    Fetched,
    Outcome,
    execute_script,
    now_utc,
)

__all__ = [
    "APPLICATION_ID",
    "SCHEMA_VERSION",
    "Outcome",
    "RunStore",
]


class RunStore:
    """An open run store. Use as a context manager, or call :meth:`close`.

    ``create=False`` opens an existing file only (``oacc stats`` never creates one);
    a missing file then raises :class:`~oacdsl.errors.StoreError`. Check
    :meth:`exists` first for a friendly message.
    """

    def __init__(self, path: str | os.PathLike[str], *, create: bool = True) -> None:
        self.path = Path(path)
        self._conn = self._open(create)

    @staticmethod
    def exists(path: str | os.PathLike[str]) -> bool:
        """True when ``path`` is a file (it may still be empty or foreign)."""
        return Path(path).is_file()

    # -- opening -----------------------------------------------------------------------------------
    def _fail(self, message: str) -> StoreError:
        return StoreError(message, location=str(self.path))

    def _open(self, create: bool) -> sqlite3.Connection:
        if self.path.is_dir():
            raise self._fail("is a directory, not a run database (give a file path with --db)")
        if self.path.exists():
            try:
                with open(self.path, "rb") as f:
                    head = f.read(len(SQLITE_MAGIC))
            except OSError as e:
                raise self._fail(f"cannot read: {e.strerror or e}") from None
            if head and head != SQLITE_MAGIC:
                raise self._fail("is not an oacdsl run database (not an SQLite file)")
        elif not create:
            raise self._fail("no run database here yet")
        else:
            try:
                self.path.parent.mkdir(parents=True, exist_ok=True)
            except OSError as e:
                raise self._fail(f"cannot create its folder: {e.strerror or e}") from None
        uri = "file:" + quote(str(self.path.resolve())) + ("?mode=rwc" if create else "?mode=rw")
        try:
            conn = sqlite3.connect(uri, uri=True, isolation_level=None, timeout=BUSY_TIMEOUT_MS / 1000)
            conn.execute(f"PRAGMA busy_timeout = {BUSY_TIMEOUT_MS}")
            conn.execute("PRAGMA foreign_keys = ON")
            self._check_and_init(conn)
            conn.execute("PRAGMA synchronous = FULL")
            missing = REQUIRED - {r[0] for r in conn.execute("SELECT name FROM sqlite_master")}
        except sqlite3.DatabaseError as e:
            raise self._fail(f"unusable run database: {e}") from None
        if missing:
            conn.close()
            raise self._fail(f"damaged run database: no {', '.join(sorted(missing))}; move it aside")
        return conn

    def _check_and_init(self, conn: sqlite3.Connection) -> None:
        app_id, version = self._header(conn)
        if app_id == APPLICATION_ID and version == SCHEMA_VERSION:
            return
        self._refuse_foreign(conn, app_id, version)
        # Fresh or older: initialise / migrate under the write lock, then re-check,
        # since another process may have done it while we waited.
        if conn.execute("PRAGMA journal_mode").fetchone()[0] != "wal":
            conn.execute("PRAGMA journal_mode = WAL")
        with self._transaction(conn):
            app_id, version = self._header(conn)
            self._refuse_foreign(conn, app_id, version)
            if app_id == 0:
                execute_script(conn, SCHEMA_V1)
                conn.execute(f"PRAGMA application_id = {APPLICATION_ID}")
                version = 1
            while version < SCHEMA_VERSION:
                execute_script(conn, MIGRATIONS[version])
                version += 1
            conn.execute(f"PRAGMA user_version = {SCHEMA_VERSION}")

    @staticmethod
    def _header(conn: sqlite3.Connection) -> tuple[int, int]:
        app_id = int(conn.execute("PRAGMA application_id").fetchone()[0])
        version = int(conn.execute("PRAGMA user_version").fetchone()[0])
        return app_id, version

    def _refuse_foreign(self, conn: sqlite3.Connection, app_id: int, version: int) -> None:
        if app_id == APPLICATION_ID:
            if version > SCHEMA_VERSION:
                raise self._fail(
                    f"written by a newer oacdsl (schema version {version}, this one reads up to"
                    f" {SCHEMA_VERSION}); upgrade oacdsl or choose another file with --db"
                )
            return
        tables = conn.execute("SELECT count(*) FROM sqlite_master").fetchone()[0]
        if app_id != 0 or tables:
            raise self._fail(
                "is an SQLite database but not an oacdsl run database; choose another file with --db"
                f" or ${ENV_VAR}"
            )

    @staticmethod
    @contextmanager
    def _transaction(conn: sqlite3.Connection) -> Iterator[None]:
        conn.execute("BEGIN IMMEDIATE")
        try:
            yield
        except BaseException:
            conn.execute("ROLLBACK")
            raise
        conn.execute("COMMIT")

    # -- writing -----------------------------------------------------------------------------------
    def record(
        self,
        run: Outcome,
        steps: Sequence[Outcome] = (),
        *,
        recording: str | None = None,
        seed: int | None = None,
        fidelity: float | None = None,
        edit_distance: int | None = None,
        command: str | None = None,
        run_id: str | None = None,
        time_utc: str | None = None,
        adaptations: Sequence[Mapping[str, Any]] = (),
    ) -> str:
        """Store one run (its own OAC's outcome and its steps') in one transaction; return its id.

        ``fidelity`` is the closed-loop fidelity in [0, 1] (1 = the robot's sequence of
        world-state changes equals the demonstration's), ``edit_distance`` the distance behind it;
        ``adaptations`` what an adaptive run changed (``kind``, ``step``, ``text``, ``plan``).
        """
        if fidelity is not None and not 0.0 <= fidelity <= 1.0:
            raise ValueError(f"fidelity must be within [0, 1], got {fidelity}")
        rid = run_id or uuid.uuid4().hex
        rows = [
            (
                rid,
                i,
                o.oac,
                json.dumps(dict(o.binding), sort_keys=True),
                int(bool(o.success)),
                None if o.duration_s is None else float(o.duration_s),
                o.error,
            )
            for i, o in enumerate([run, *steps])
        ]
        try:
            with self._transaction(self._conn):
                self._conn.execute(
                    "INSERT INTO runs (run_id, time_utc, oac, success, recording, seed, fidelity,"
                    " edit_distance, command) VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?)",
                    (
                        rid,
                        time_utc or now_utc(),
                        run.oac,
                        int(bool(run.success)),
                        recording,
                        seed,
                        fidelity,
                        edit_distance,
                        command,
                    ),
                )
                self._conn.executemany("INSERT INTO outcomes VALUES (?, ?, ?, ?, ?, ?, ?)", rows)
                self._conn.executemany(
                    "INSERT INTO adaptations VALUES (?, ?, ?, ?, ?, ?)", rows_of(rid, adaptations)
                )
        except sqlite3.DatabaseError as e:
            raise self._fail(f"cannot record the run: {e}") from None
        return rid

    def record_run_json(self, doc: Mapping[str, Any], **meta: Any) -> str:
        """Store an ``oacc run --json`` document; ``meta`` as for :meth:`record`.

        The run's own outcome is the document's ``oac`` and ``success``, its duration the
        simulated time (``metrics.sim_time_s``, else the sum of the steps'), its error the first
        failed step's. A primitive OAC run whose only step is that same OAC is stored once.
        """
        steps = [
            Outcome(
                s["oac"], s.get("binding") or {}, bool(s.get("success")), s.get("duration_s"), s.get("error")
            )
            for s in doc.get("steps", [])
        ]
        metrics = doc.get("metrics") or {}
        durations = [s.duration_s for s in steps if s.duration_s is not None]
        duration = metrics.get("sim_time_s", sum(durations) if durations else None)
        error = doc.get("error") or next((s.error for s in steps if s.error), None)
        run = Outcome(doc["oac"], doc.get("binding") or {}, bool(doc.get("success")), duration, error)
        if len(steps) == 1 and steps[0].oac == run.oac:
            run, steps = (
                Outcome(run.oac, steps[0].binding or run.binding, run.success, steps[0].duration_s, error),
                [],
            )
        adapted = [a for a in doc.get("adaptations") or [] if isinstance(a, Mapping)]
        return self.record(run, steps, adaptations=adapted, **meta)

    # -- reading -----------------------------------------------------------------------------------
    def _query(self, sql: str, args: tuple[Any, ...] = ()) -> sqlite3.Cursor:
        """``sql`` executed and fetched; a damaged file is a :class:`StoreError`, not a traceback."""
        try:
            cur = self._conn.execute(sql, args)
            return Fetched(cur.description, cur.fetchall())  # type: ignore[return-value]
        except sqlite3.DatabaseError as e:
            raise self._fail(f"damaged run database: {e}; move it aside") from None

    def rows(self, oac: str | None = None) -> list[dict[str, Any]]:
        """Every outcome row (joined with its run), oldest first; ``binding`` decoded."""
        sql = "SELECT * FROM outcome_rows"
        args: tuple[Any, ...] = ()
        if oac is not None:
            sql, args = sql + " WHERE oac = ?", (oac,)
        cur = self._query(sql + " ORDER BY run_seq, position", args)
        names = [d[0] for d in cur.description]
        out = []
        for values in cur.fetchall():
            row = dict(zip(names, values, strict=True))
            try:
                row["binding"] = json.loads(row["binding"])
            except (TypeError, ValueError, RecursionError):
                row["binding"] = None
            if not isinstance(row["binding"], dict):
                where = f"run {row['run_id']} step {row['position']}"
                raise self._fail(f"damaged run database: {where}: its binding is not a JSON object")
            row["success"] = bool(row["success"])
            out.append(row)
        return out

    def adaptations(self, oac: str | None = None) -> list[dict[str, Any]]:
        """Every adaptation of an adaptive run (joined with its run: ``time_utc``, the run's
        ``oac``), oldest first; ``plan`` decoded (a list, or None); ``oac``: runs of that OAC."""
        sql = (
            "SELECT a.run_id, r.time_utc, r.oac, a.position, a.kind, a.step, a.text, a.plan"
            " FROM adaptations AS a JOIN runs AS r USING (run_id)"
        )
        args: tuple[Any, ...] = ()
        if oac is not None:
            sql, args = sql + " WHERE r.oac = ?", (oac,)
        cur = self._query(sql + " ORDER BY r.rowid, a.position", args)
        return decoded(cur.description, cur.fetchall(), self._fail)

    def oac_names(self) -> list[str]:
        """The OACs with at least one recorded outcome, sorted."""
        return [r[0] for r in self._query("SELECT DISTINCT oac FROM outcomes ORDER BY oac").fetchall()]

    def run_count(self) -> int:
        return int(self._query("SELECT count(*) FROM runs").fetchall()[0][0])

    def integrity(self) -> str:
        """``PRAGMA integrity_check``: ``"ok"`` when the file is sound."""
        return "; ".join(str(r[0]) for r in self._query("PRAGMA integrity_check").fetchall())

    def close(self) -> None:
        self._conn.close()

    def __enter__(self) -> RunStore:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()
