"""Where the run store lives: ``--db``, ``$OACDSL_DB``, or the user's XDG data directory."""

from __future__ import annotations

import os
import tempfile
from collections.abc import Mapping
from pathlib import Path

from oacdsl.errors import StoreError

__all__ = ["ENV_VAR", "default_db_path", "ensure_writable", "resolve_db_path"]

#: Environment variable that overrides the default database path.
ENV_VAR = "OACDSL_DB"


def default_db_path(environ: Mapping[str, str] | None = None) -> Path:
    """``$OACDSL_DB``, else ``$XDG_DATA_HOME/oacdsl/runs.sqlite3``, else ``~/.local/share/…``.

    A relative ``XDG_DATA_HOME`` is ignored, as the XDG base-directory spec says.
    """
    env = os.environ if environ is None else environ
    if env.get(ENV_VAR):
        return Path(env[ENV_VAR]).expanduser()
    xdg = env.get("XDG_DATA_HOME", "")
    root = Path(xdg) if xdg and os.path.isabs(xdg) else Path.home() / ".local" / "share"
    return root / "oacdsl" / "runs.sqlite3"


def resolve_db_path(arg: str | os.PathLike[str] | None, environ: Mapping[str, str] | None = None) -> Path:
    """The ``--db`` argument if given, else :func:`default_db_path`."""
    return Path(arg).expanduser() if arg else default_db_path(environ)


def ensure_writable(path: str | os.PathLike[str]) -> Path:
    """Check, before any long work, that a run can be recorded at ``path``; return the path.

    An existing file must be an oacdsl run store that this process can lock for writing; a
    new one needs a folder where files can be created (the folder is created, as the first
    write would). The check writes a probe file and removes it: permission bits alone do not
    tell (root ignores them, a read-only mount does not show in them). Raises
    :class:`~oacdsl.errors.StoreError` (exit status 2) with the reason on one line.
    """
    import sqlite3

    from oacdsl.stats.store import RunStore

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
