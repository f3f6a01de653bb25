"""Before a long run: can its outcome be recorded in the run store at all?"""

from __future__ import annotations

import os
import sqlite3
import stat
import tempfile
from pathlib import Path

from oacdsl.errors import StoreError
from oacdsl.stats.schema import SCHEMA_VERSION
from oacdsl.stats.store import RunStore

__all__ = ["check_store_path", "ensure_writable", "read_only"]


def check_store_path(db: Path, what: str = "no run database here") -> None:
    """Refuse, as a :class:`StoreError`, a path that cannot be a run database: an existing entry
    that is not a regular file (a folder, a FIFO, a device), or one under something not a folder
    (``what`` begins that message)."""
    try:
        info = os.stat(db)
    except FileNotFoundError:
        return
    except NotADirectoryError:
        raise StoreError(f"{what}: a parent of this path is not a folder", location=str(db)) from None
    except OSError as error:
        raise StoreError(f"cannot read: {error.strerror or error}", location=str(db)) from None
    if stat.S_ISDIR(info.st_mode):
        raise StoreError("is a directory, not a run database (give a file path with --db)", location=str(db))
    if not stat.S_ISREG(info.st_mode):
        raise StoreError("is not a regular file, not a run database (give a file path with --db)",
                         location=str(db))


def read_only(db: Path) -> None:
    """Refuse a store file whose mode has no write permission (``0444``), also for root:
    the mode says its owner wants it left alone."""
    mode = stat.S_IMODE(os.stat(db).st_mode)
    if not mode & 0o222 or not os.access(db, os.W_OK):
        why = f"read-only (mode {mode:04o})" if not mode & 0o222 else "not writable"
        raise StoreError(f"{why}: cannot record runs here; give another --db or --no-record",
                         location=str(db))


def ensure_writable(path: str | os.PathLike[str]) -> Path:
    """Check, before any long work, that a run can be recorded at ``path``; return the path.

    An existing file must be an oacdsl run store that this process can lock for writing; a
    new one needs a folder where files can be created (the folder is created, as the first
    write would). The check writes a probe file and removes it: permission bits alone do not
    tell (root ignores them, a read-only mount does not show in them). Raises
    :class:`~oacdsl.errors.StoreError` (exit status 2) with the reason on one line.
    """
    db = Path(path)
    if RunStore.exists(db):
        read_only(db)
        store = RunStore(db, create=False)  # refuses a foreign, newer or incomplete file
        try:
            if (damage := store.integrity()) != "ok":
                raise StoreError(f"damaged run database: {damage[:200]}; move it aside", location=str(db))
            store.rows()  # what the report reads at the end: every row decodes (StoreError if not)
            store.adaptations()
            store._conn.execute("BEGIN IMMEDIATE")
            try:  # a real write (rolled back): a read-only mount or an immutable file fails here
                store._conn.execute(f"PRAGMA user_version = {SCHEMA_VERSION}")
            finally:
                store._conn.execute("ROLLBACK")
        except sqlite3.DatabaseError as error:
            raise StoreError(f"cannot record runs here: {error}", location=str(db)) from None
        finally:
            store.close()
    else:
        check_store_path(db, "cannot record runs here")
    try:
        db.parent.mkdir(parents=True, exist_ok=True)
    except (FileExistsError, NotADirectoryError):
        raise StoreError(f"cannot record runs here: {db.parent} is not a folder", location=str(db)) from None
    except OSError as error:
        why = error.strerror or str(error)
        raise StoreError(f"cannot record runs here: {why} ({db.parent})", location=str(db)) from None
    try:
        fd, probe = tempfile.mkstemp(prefix=f".{db.name}.", suffix=".probe", dir=db.parent)
        os.close(fd)
        os.unlink(probe)
    except OSError as error:
        why = error.strerror or str(error)
        raise StoreError(f"cannot record runs here: {why} ({db.parent})", location=str(db)) from None
    return db
