"""Where the run store lives: ``--db``, ``$OACDSL_DB``, or the user's XDG data directory."""

from __future__ import annotations

import os
from collections.abc import Mapping
from pathlib import Path

__all__ = ["ENV_VAR", "default_db_path", "resolve_db_path"]

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
