"""Before a long run: can its outcome be recorded in the run store at all?"""

from __future__ import annotations

import os
import sqlite3
import tempfile
from pathlib import Path

from oacdsl.errors import StoreError
from oacdsl.stats.store import RunStore

__all__ = ["ensure_writable"]


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
        store = RunStore(db, create=False)  # refuses a foreign or newer file
        try:
            store._conn.execute("BEGIN IMMEDIATE")
            store._conn.execute("ROLLBACK")
        except sqlite3.DatabaseError as error:
            raise StoreError(f"cannot record runs here: {error}", location=str(db)) from None
        finally:
            store.close()
    elif db.is_dir():
        raise StoreError("is a directory, not a run database (give a file path with --db)", location=str(db))
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
